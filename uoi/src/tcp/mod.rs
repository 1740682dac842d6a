//! UOI over TCP: a tokio server that many host programs share, and a
//! client (async, plus a blocking wrapper). Frames as in [`crate::wire`].

mod client;
mod connection;
mod halves;
mod idle;
mod server;

pub use client::{answer_error, BlockingClient, Client, ClientError};
pub use server::{Core, Handler, Server, ServerConfig, Slice};
