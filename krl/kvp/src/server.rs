//! A KUKAVARPROXY server over a [`VarStore`]: what the simulated
//! controllers run so that the service's variable access is tested here
//! against the same protocol a KRC's proxy speaks. A thread accepts
//! connections and a thread serves each (a proxy serves a handful of
//! clients); requests are answered in order.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::codec::{self, Answer, Function, Request};

/// The variables a server reads and writes, as KRL text.
pub trait VarStore: Send + Sync + 'static {
    /// The value of `name`, or `None` when there is no such variable.
    fn read(&self, name: &str) -> Option<String>;
    /// Sets `name` to `value` (KRL text); its value afterwards, or `None`
    /// when the variable does not exist, is read-only or the value does
    /// not fit it.
    fn write(&self, name: &str, value: &str) -> Option<String>;
}

/// A running server; it stops when dropped.
pub struct KvpServer {
    addr: SocketAddr,
    stop: Arc<AtomicBool>,
}

impl KvpServer {
    /// Listens on `addr` (e.g. `127.0.0.1:0` for a free port) and serves
    /// `store`.
    pub fn start(addr: &str, store: Arc<dyn VarStore>) -> std::io::Result<Self> {
        let listener = TcpListener::bind(addr)?;
        let addr = listener.local_addr()?;
        listener.set_nonblocking(true)?;
        let stop = Arc::new(AtomicBool::new(false));
        let stopping = stop.clone();
        std::thread::Builder::new()
            .name("kvp-accept".into())
            .spawn(move || accept(listener, store, stopping))?;
        Ok(KvpServer { addr, stop })
    }

    /// Where it listens.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }
}

impl Drop for KvpServer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
    }
}

fn accept(listener: TcpListener, store: Arc<dyn VarStore>, stop: Arc<AtomicBool>) {
    while !stop.load(Ordering::SeqCst) {
        match listener.accept() {
            Ok((stream, peer)) => {
                let store = store.clone();
                let stop = stop.clone();
                let spawned = std::thread::Builder::new()
                    .name("kvp-conn".into())
                    .spawn(move || serve(stream, &*store, &stop));
                if let Err(e) = spawned {
                    tracing::warn!(%peer, error = %e, "KUKAVARPROXY stand-in: no thread for a connection");
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(20));
            }
            Err(e) => {
                tracing::warn!(error = %e, "KUKAVARPROXY stand-in: accept failed");
                std::thread::sleep(Duration::from_millis(100));
            }
        }
    }
}

fn serve(mut stream: TcpStream, store: &dyn VarStore, stop: &AtomicBool) {
    let _ = stream.set_nonblocking(false);
    let _ = stream.set_read_timeout(Some(Duration::from_millis(200)));
    let _ = stream.set_nodelay(true);
    loop {
        let mut head = [0u8; 4];
        match stream.read_exact(&mut head) {
            Ok(()) => {}
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                if stop.load(Ordering::SeqCst) {
                    return;
                }
                continue;
            }
            Err(_) => return,
        }
        let (id, len) = codec::header(head);
        let mut body = vec![0u8; len];
        if stream.read_exact(&mut body).is_err() {
            return;
        }
        let answer = match Request::decode(id, &body) {
            Ok(r) => {
                let result = match (&r.function, &r.value) {
                    (Function::Write, Some(v)) => store.write(&r.name, v),
                    _ => store.read(&r.name),
                };
                Answer {
                    id,
                    function: r.function,
                    ok: result.is_some(),
                    value: result.unwrap_or_default(),
                }
            }
            // A message it cannot read: answered as refused, as a proxy
            // answers a variable it does not know.
            Err(_) => Answer {
                id,
                function: Function::Read,
                value: String::new(),
                ok: false,
            },
        };
        let Ok(bytes) = answer.encode() else {
            return;
        };
        if stream.write_all(&bytes).is_err() {
            return;
        }
    }
}
