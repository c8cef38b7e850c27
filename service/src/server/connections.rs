//! Connection bookkeeping for the server: how many are open (in total and
//! per client address, with the idlest closed to make room), what each is
//! doing (requests in flight including their answer bodies, idle time,
//! writes that make no progress), and the socket and body wrappers that
//! feed it.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tokio::io::{AsyncRead, AsyncWrite};

/// Open connections, in total and per client address, within limits.
/// When the total is reached, the connection idle the longest is closed to
/// make room, so a flood of idle connections cannot lock out a client that
/// needs to send Stop.
pub(super) struct Connections {
    max: usize,
    per_client: usize,
    open: Mutex<HashMap<IpAddr, usize>>,
    total: AtomicUsize,
    live: Mutex<Vec<std::sync::Weak<Activity>>>,
    /// Woken when the last connection closes (shutdown waits on it).
    all_closed: tokio::sync::Notify,
}

/// One admitted connection; dropping it frees its place.
pub(super) struct Admitted {
    table: Arc<Connections>,
    ip: IpAddr,
    /// What the connection is doing.
    pub(super) activity: Arc<Activity>,
}

impl Connections {
    /// No connections yet; at most `max` in total and `per_client` per address.
    pub(super) fn new(max: usize, per_client: usize) -> Connections {
        Connections {
            max,
            per_client,
            open: Mutex::new(HashMap::new()),
            total: AtomicUsize::new(0),
            live: Mutex::new(Vec::new()),
            all_closed: tokio::sync::Notify::new(),
        }
    }

    /// Returns once no connection is open (at once if none is).
    pub(super) async fn all_closed(&self) {
        loop {
            let closed = self.all_closed.notified();
            if self.open_count() == 0 {
                return;
            }
            closed.await;
        }
    }

    /// Connections open now.
    pub(super) fn open_count(&self) -> usize {
        self.total.load(Ordering::SeqCst)
    }

    fn map(&self) -> std::sync::MutexGuard<'_, HashMap<IpAddr, usize>> {
        self.open
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Asks the connection idle the longest to close; false if none is idle.
    fn evict_idlest(&self) -> bool {
        let mut live = self
            .live
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        live.retain(|w| w.strong_count() > 0);
        let idlest = live
            .iter()
            .filter_map(std::sync::Weak::upgrade)
            .filter(|a| !a.evicted.load(Ordering::SeqCst))
            .filter_map(|a| a.idle_for().map(|d| (d, a)))
            .max_by_key(|(d, _)| *d);
        match idlest {
            Some((_, a)) => {
                a.evicted.store(true, Ordering::SeqCst);
                a.evict.notify_one();
                true
            }
            None => false,
        }
    }

    /// A place for a new connection from `ip`, if within the per-client
    /// limit and the total (making room by closing an idle connection).
    pub(super) fn admit(self: &Arc<Self>, ip: IpAddr) -> Option<Admitted> {
        let mut map = self.map();
        let n = map.entry(ip).or_insert(0);
        if *n >= self.per_client {
            return None;
        }
        if self.total.load(Ordering::SeqCst) >= self.max && !self.evict_idlest() {
            return None;
        }
        *n += 1;
        self.total.fetch_add(1, Ordering::SeqCst);
        let activity = Arc::new(Activity {
            in_flight: AtomicUsize::new(0),
            last: Mutex::new(Instant::now()),
            write_blocked: Mutex::new(None),
            evict: tokio::sync::Notify::new(),
            evicted: std::sync::atomic::AtomicBool::new(false),
        });
        let mut live = self
            .live
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        // Forget closed connections now and then (amortised; the list
        // would otherwise grow with every connection ever accepted).
        if live.len() > 2 * self.total.load(Ordering::SeqCst).max(64) {
            live.retain(|w| w.strong_count() > 0);
        }
        live.push(Arc::downgrade(&activity));
        drop(live);
        Some(Admitted {
            table: self.clone(),
            ip,
            activity,
        })
    }
}

impl Drop for Admitted {
    fn drop(&mut self) {
        let mut map = self.table.map();
        if let Some(n) = map.get_mut(&self.ip) {
            *n -= 1;
            if *n == 0 {
                map.remove(&self.ip);
            }
        }
        if self.table.total.fetch_sub(1, Ordering::SeqCst) == 1 {
            self.table.all_closed.notify_waiters();
        }
    }
}

/// What one connection is doing: requests still being answered (body
/// included), when the last one ended, whether its writes are stuck (a
/// client that does not read), and the request to close it.
pub(super) struct Activity {
    in_flight: AtomicUsize,
    last: Mutex<Instant>,
    write_blocked: Mutex<Option<Instant>>,
    /// Notified when the connection must close to make room.
    pub(super) evict: tokio::sync::Notify,
    evicted: std::sync::atomic::AtomicBool,
}

impl Activity {
    /// How long no request has been in progress (None while one is).
    pub(super) fn idle_for(&self) -> Option<Duration> {
        if self.in_flight.load(Ordering::SeqCst) > 0 {
            return None;
        }
        let last = *self
            .last
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        Some(last.elapsed())
    }

    /// How long writes have made no progress (None when they do).
    pub(super) fn write_stuck_for(&self) -> Option<Duration> {
        self.write_blocked
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .map(|t| t.elapsed())
    }

    fn wrote(&self, blocked: bool) {
        let mut w = self
            .write_blocked
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        match (blocked, w.is_some()) {
            (true, false) => *w = Some(Instant::now()),
            (false, true) => *w = None,
            _ => {}
        }
    }
}

/// The connection's socket, watched for writes that make no progress.
pub(super) struct Watched<IO> {
    /// The socket.
    pub(super) io: IO,
    /// Its connection's activity.
    pub(super) activity: Arc<Activity>,
}

impl<IO: AsyncRead + Unpin> AsyncRead for Watched<IO> {
    fn poll_read(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
        buf: &mut tokio::io::ReadBuf<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        std::pin::Pin::new(&mut self.io).poll_read(cx, buf)
    }
}

impl<IO: AsyncWrite + Unpin> AsyncWrite for Watched<IO> {
    fn poll_write(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
        buf: &[u8],
    ) -> std::task::Poll<std::io::Result<usize>> {
        let r = std::pin::Pin::new(&mut self.io).poll_write(cx, buf);
        self.activity.wrote(r.is_pending());
        r
    }

    fn poll_write_vectored(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
        bufs: &[std::io::IoSlice<'_>],
    ) -> std::task::Poll<std::io::Result<usize>> {
        let r = std::pin::Pin::new(&mut self.io).poll_write_vectored(cx, bufs);
        self.activity.wrote(r.is_pending());
        r
    }

    fn is_write_vectored(&self) -> bool {
        self.io.is_write_vectored()
    }

    fn poll_flush(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        let r = std::pin::Pin::new(&mut self.io).poll_flush(cx);
        self.activity.wrote(r.is_pending());
        r
    }

    fn poll_shutdown(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        std::pin::Pin::new(&mut self.io).poll_shutdown(cx)
    }
}

/// Marks a request in flight until its answer's body is done or dropped.
pub(super) struct InFlight(Arc<Activity>);

impl InFlight {
    /// Counts a request of this connection.
    pub(super) fn new(a: &Arc<Activity>) -> InFlight {
        a.in_flight.fetch_add(1, Ordering::SeqCst);
        InFlight(a.clone())
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        *self
            .0
            .last
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = Instant::now();
        self.0.in_flight.fetch_sub(1, Ordering::SeqCst);
    }
}

/// An answer body that keeps its request counted as in flight.
pub(super) struct Tracked {
    inner: axum::body::Body,
    /// Released when the body is done or dropped.
    _in_flight: InFlight,
}

impl Tracked {
    /// `inner`, counted as `in_flight` until it ends.
    pub(super) fn new(inner: axum::body::Body, in_flight: InFlight) -> Tracked {
        Tracked {
            inner,
            _in_flight: in_flight,
        }
    }
}

impl axum::body::HttpBody for Tracked {
    type Data = axum::body::Bytes;
    type Error = axum::Error;

    fn poll_frame(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<Option<Result<hyper::body::Frame<Self::Data>, Self::Error>>> {
        std::pin::Pin::new(&mut self.inner).poll_frame(cx)
    }

    fn is_end_stream(&self) -> bool {
        self.inner.is_end_stream()
    }

    fn size_hint(&self) -> hyper::body::SizeHint {
        self.inner.size_hint()
    }
}
