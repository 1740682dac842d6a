//! UOI over TCP: a tokio server that many host programs share, and a
//! client (async, plus a blocking wrapper). Frames as in [`crate::wire`].

mod access;
mod client;
mod connection;
mod core_handle;
mod gate;
mod halves;
mod idle;
mod places;
mod server;
mod shared;

pub use access::{
    is_loopback_peer, AccessPolicy, AccessToken, BadToken, MAX_TOKEN_LEN, MIN_TOKEN_LEN,
};
pub use client::{answer_error, BlockingClient, Client, ClientError, ClientOptions, Waited};
pub use core_handle::CoreHandle;
pub use places::{Full as NoPlace, Limits as PlaceLimits, Places, Seat};
pub use server::{Core, Handler, Served, Server, ServerConfig, Session, Slice, Wait};
