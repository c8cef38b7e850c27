//! The service's KUKAVARPROXY client: one TCP connection, one request at
//! a time (the proxy answers in order), connected on first use and again
//! after an error, every step bounded by a timeout.

use std::time::Duration;

use thiserror::Error;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::sync::Mutex;

use crate::codec::{self, Answer, CodecError, Function, Request};

/// Why a variable could not be read or written.
#[derive(Debug, Error)]
pub enum KvpError {
    /// No connection to the proxy (refused, unreachable, closed, timed out).
    #[error("KUKAVARPROXY at {addr} is not reachable: {why}")]
    Unreachable {
        /// Its address.
        addr: String,
        /// What happened.
        why: String,
    },
    /// The proxy answered that it could not access the variable (it does
    /// not exist, or the value does not fit it).
    #[error("the controller refused the access to {0}")]
    Refused(String),
    /// The answer did not follow the protocol.
    #[error("KUKAVARPROXY answered something unexpected: {0}")]
    Protocol(String),
}

/// A KUKAVARPROXY client.
#[derive(Debug)]
pub struct KvpClient {
    addr: String,
    timeout: Duration,
    conn: Mutex<(Option<TcpStream>, u16)>,
}

impl KvpClient {
    /// A client of the proxy at `addr` (`host:port`); nothing is connected
    /// before the first request. Each connect, send and answer waits at
    /// most `timeout`.
    pub fn new(addr: impl Into<String>, timeout: Duration) -> Self {
        KvpClient {
            addr: addr.into(),
            timeout,
            conn: Mutex::new((None, 1)),
        }
    }

    /// The proxy's address.
    pub fn addr(&self) -> &str {
        &self.addr
    }

    /// Reads a variable: its value as KRL text.
    pub async fn read(&self, name: &str) -> Result<String, KvpError> {
        self.call(Function::Read, name, None).await
    }

    /// Writes a variable (`value` in KRL syntax); its value afterwards.
    pub async fn write(&self, name: &str, value: &str) -> Result<String, KvpError> {
        self.call(Function::Write, name, Some(value)).await
    }

    fn unreachable(&self, why: impl std::fmt::Display) -> KvpError {
        KvpError::Unreachable {
            addr: self.addr.clone(),
            why: why.to_string(),
        }
    }

    async fn call(
        &self,
        function: Function,
        name: &str,
        value: Option<&str>,
    ) -> Result<String, KvpError> {
        let mut guard = self.conn.lock().await;
        let (conn, next_id) = &mut *guard;
        let id = *next_id;
        *next_id = next_id.wrapping_add(1).max(1);
        let request = Request {
            id,
            function,
            name: name.to_string(),
            value: value.map(str::to_string),
        }
        .encode()
        .map_err(|e: CodecError| KvpError::Protocol(e.to_string()))?;
        if conn.is_none() {
            let stream = tokio::time::timeout(self.timeout, TcpStream::connect(&self.addr))
                .await
                .map_err(|_| self.unreachable("connecting timed out"))?
                .map_err(|e| self.unreachable(e))?;
            let _ = stream.set_nodelay(true);
            *conn = Some(stream);
        }
        let Some(stream) = conn.as_mut() else {
            return Err(self.unreachable("no connection"));
        };
        let answer = tokio::time::timeout(self.timeout, exchange(stream, &request)).await;
        let answer = match answer {
            Ok(Ok(a)) => a,
            Ok(Err(e)) => {
                // A broken connection is opened again by the next request.
                *conn = None;
                return Err(e.into_error(self));
            }
            Err(_) => {
                *conn = None;
                return Err(self.unreachable("no answer in time"));
            }
        };
        if answer.id != id {
            *conn = None;
            return Err(KvpError::Protocol(format!(
                "an answer to message {} where {id} was asked",
                answer.id
            )));
        }
        if !answer.ok {
            return Err(KvpError::Refused(name.to_string()));
        }
        Ok(answer.value)
    }
}

enum Exchange {
    Io(std::io::Error),
    Codec(CodecError),
}

impl Exchange {
    fn into_error(self, c: &KvpClient) -> KvpError {
        match self {
            Exchange::Io(e) => c.unreachable(e),
            Exchange::Codec(e) => KvpError::Protocol(e.to_string()),
        }
    }
}

async fn exchange(stream: &mut TcpStream, request: &[u8]) -> Result<Answer, Exchange> {
    stream.write_all(request).await.map_err(Exchange::Io)?;
    let mut head = [0u8; 4];
    stream.read_exact(&mut head).await.map_err(Exchange::Io)?;
    let (id, len) = codec::header(head);
    let mut body = vec![0u8; len];
    stream.read_exact(&mut body).await.map_err(Exchange::Io)?;
    Answer::decode(id, &body).map_err(Exchange::Codec)
}
