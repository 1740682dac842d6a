mod connect;
mod reverse_tcp;
pub(crate) mod tcp;
pub(crate) use connect::Connector;
pub(crate) use reverse_tcp::ReverseTcpConnector;

/// A byte stream the server speaks opc.tcp over: a TCP connection, or any
/// other stream handed to it (a relay inside the process, for example).
pub trait Connection: tokio::io::AsyncRead + tokio::io::AsyncWrite + Send + Sync + Unpin {}

impl<T: tokio::io::AsyncRead + tokio::io::AsyncWrite + Send + Sync + Unpin> Connection for T {}

/// A connection of any kind, boxed.
pub type Stream = Box<dyn Connection>;
