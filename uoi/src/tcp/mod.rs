//! UOI over TCP: a tokio server that many host programs share, and a
//! client (async, plus a blocking wrapper). Frames as in [`crate::wire`].

mod access;
mod arrivals;
mod client;
mod config;
mod connection;
mod core_handle;
mod floods;
mod gate;
mod halves;
mod handler;
mod idle;
mod places;
mod server;
mod shared;
mod slices;

pub use access::{
    is_hello_payload, is_loopback_peer, AccessPolicy, AccessToken, BadToken, MAX_TOKEN_LEN,
    MIN_TOKEN_LEN,
};
pub use arrivals::AcceptRate;
pub use client::{answer_error, BlockingClient, Client, ClientError, ClientOptions, Waited};
pub use config::{Refused, ServerConfig};
pub use core_handle::CoreHandle;
pub use handler::{Handler, Session, Slice, Wait};
pub use places::{Full as NoPlace, Limits as PlaceLimits, Places, Seat};
pub use server::Server;
