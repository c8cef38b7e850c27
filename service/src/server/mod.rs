//! The HTTP(S) server: accepts TCP connections (limited in total and per
//! client address), optionally wraps them in TLS (rustls, certificate and
//! key from `[server.tls]`), and serves the axum application over HTTP/1.1
//! or HTTP/2 with limits on the request head (size and time to arrive), the
//! client's address for the access layer, idle connections closed, and a
//! graceful shutdown. In the spirit of axum's own `serve`, with the knobs a
//! plant-network service needs.

mod connections;

use std::net::SocketAddr;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::Router;
use axum::extract::ConnectInfo;
use hyper_util::rt::{TokioExecutor, TokioIo, TokioTimer};
use hyper_util::server::conn::auto;
use tokio::io::{AsyncRead, AsyncWrite};
use tokio::net::TcpListener;
use tokio_rustls::TlsAcceptor;
use tower::ServiceExt;

use crate::config::{ServerConfig, TlsConfig};
use connections::{Activity, Connections, InFlight, Tracked, Watched};

/// Why TLS could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum TlsError {
    /// A PEM file cannot be read or holds nothing usable.
    #[error("{path}: {message}")]
    Pem {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// rustls refused the certificate or key.
    #[error("TLS configuration: {0}")]
    Rustls(#[from] rustls::Error),
}

/// Builds the TLS acceptor from PEM files.
pub fn tls_acceptor(tls: &TlsConfig) -> Result<TlsAcceptor, TlsError> {
    use rustls_pki_types::pem::PemObject;
    use rustls_pki_types::{CertificateDer, PrivateKeyDer};
    let pem_error = |path: &Path, message: String| TlsError::Pem {
        path: path.display().to_string(),
        message,
    };
    let certs: Vec<CertificateDer<'static>> = CertificateDer::pem_file_iter(&tls.cert)
        .map_err(|e| pem_error(&tls.cert, e.to_string()))?
        .collect::<Result<_, _>>()
        .map_err(|e| pem_error(&tls.cert, e.to_string()))?;
    if certs.is_empty() {
        return Err(pem_error(&tls.cert, "no CERTIFICATE block".into()));
    }
    let key = PrivateKeyDer::from_pem_file(&tls.key)
        .map_err(|e| pem_error(&tls.key, format!("no usable private key: {e}")))?;
    let provider = Arc::new(rustls::crypto::ring::default_provider());
    let mut config = rustls::ServerConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()?
        .with_no_client_auth()
        .with_single_cert(certs, key)?;
    config.alpn_protocols = vec![b"h2".to_vec(), b"http/1.1".to_vec()];
    Ok(TlsAcceptor::from(Arc::new(config)))
}

/// Serves `router` on `listener` until `stop` resolves, then waits for open
/// connections to finish (event streams end on the service's closing
/// signal). Connections are limited in number (in total and per client
/// address) and closed when idle for `server.header_timeout_ms`, so clients
/// that connect and send nothing cannot use up the service's sockets.
pub async fn serve(
    listener: TcpListener,
    router: Router,
    server: &ServerConfig,
    tls: Option<TlsAcceptor>,
    stop: impl Future<Output = ()>,
) -> std::io::Result<()> {
    let mut builder = auto::Builder::new(TokioExecutor::new());
    let head_timeout = Duration::from_millis(server.header_timeout_ms);
    builder
        .http1()
        .timer(TokioTimer::new())
        .header_read_timeout(head_timeout)
        .max_buf_size(server.max_header_bytes)
        .max_headers(100);
    builder
        .http2()
        .timer(TokioTimer::new())
        .max_header_list_size(u32::try_from(server.max_header_bytes).unwrap_or(u32::MAX));
    let builder = Arc::new(builder);
    let connections = Arc::new(Connections::new(
        server.max_connections,
        server.max_connections_per_client,
    ));
    let (closing, closing_rx) = tokio::sync::watch::channel(false);
    let mut refused_logged: Option<Instant> = None;
    tokio::pin!(stop);
    loop {
        let (tcp, remote) = tokio::select! {
            () = &mut stop => break,
            accepted = listener.accept() => match accepted {
                Ok(a) => a,
                Err(e) => {
                    // Out of file descriptors and the like: wait, go on.
                    tracing::warn!(error = %e, "cannot accept a connection");
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
        };
        let Some(admitted) = connections.admit(remote.ip()) else {
            if refused_logged.is_none_or(|t| t.elapsed() > Duration::from_secs(10)) {
                refused_logged = Some(Instant::now());
                tracing::warn!(client = %remote.ip(), "connection refused: too many open connections (server.max_connections, max_connections_per_client)");
            }
            drop(tcp);
            continue;
        };
        // Small request/response pairs: send at once instead of waiting
        // for delayed ACKs (Nagle), which costs milliseconds per round trip.
        if let Err(e) = tcp.set_nodelay(true) {
            tracing::debug!(error = %e, "cannot set TCP_NODELAY");
        }
        let (router, builder, closing) = (router.clone(), builder.clone(), closing_rx.clone());
        let tls = tls.clone();
        tokio::spawn(async move {
            let activity = admitted.activity.clone();
            let _admitted = admitted;
            let watched = |io| Watched {
                io,
                activity: activity.clone(),
            };
            match tls {
                None => {
                    let io = watched(tcp);
                    drive(
                        &builder,
                        io,
                        remote,
                        router,
                        head_timeout,
                        closing,
                        activity,
                    )
                    .await;
                }
                Some(acceptor) => {
                    match tokio::time::timeout(head_timeout, acceptor.accept(watched(tcp))).await {
                        Ok(Ok(stream)) => {
                            drive(
                                &builder,
                                stream,
                                remote,
                                router,
                                head_timeout,
                                closing,
                                activity.clone(),
                            )
                            .await;
                        }
                        Ok(Err(e)) => {
                            tracing::debug!(client = %remote, error = %e, "TLS handshake failed");
                        }
                        Err(_) => tracing::debug!(client = %remote, "TLS handshake timed out"),
                    }
                }
            }
        });
    }
    drop(listener);
    let _ = closing.send(true);
    // Each connection closes gracefully (or is dropped `header_timeout`
    // after it was asked to); the last one to go wakes this.
    connections.all_closed().await;
    Ok(())
}

/// Serves one HTTP connection until it ends, is idle for `idle`, its
/// writes are stuck for `idle` (a client that does not read), it is closed
/// to make room, or the server closes; each request carries the client's
/// address. A connection asked to close gracefully is dropped if it has
/// not ended `idle` later (an HTTP/2 client that never answers).
async fn drive<IO>(
    builder: &auto::Builder<TokioExecutor>,
    io: IO,
    remote: SocketAddr,
    router: Router,
    idle: Duration,
    mut closing: tokio::sync::watch::Receiver<bool>,
    activity: Arc<Activity>,
) where
    IO: AsyncRead + AsyncWrite + Unpin + Send + 'static,
{
    let counted = activity.clone();
    let service = hyper::service::service_fn(move |req: hyper::Request<hyper::body::Incoming>| {
        let in_flight = InFlight::new(&counted);
        let mut req = req.map(axum::body::Body::new);
        req.extensions_mut().insert(ConnectInfo(remote));
        let answer = router.clone().oneshot(req);
        async move {
            let resp = answer.await?;
            Ok::<_, std::convert::Infallible>(
                resp.map(|inner| axum::body::Body::new(Tracked::new(inner, in_flight))),
            )
        }
    });
    let conn = builder.serve_connection_with_upgrades(TokioIo::new(io), service);
    tokio::pin!(conn);
    let mut closing_since: Option<Instant> = None;
    let check = (idle / 4).max(Duration::from_millis(25));
    loop {
        tokio::select! {
            result = conn.as_mut() => {
                if let Err(e) = result {
                    tracing::debug!(client = %remote, error = %e, "connection ended with an error");
                }
                return;
            }
            () = activity.evict.notified() => {
                tracing::debug!(client = %remote, "idle connection closed to make room");
                return;
            }
            () = tokio::time::sleep(check) => {
                if closing_since.is_some_and(|t| t.elapsed() >= idle) {
                    tracing::debug!(client = %remote, "connection did not close in time; dropped");
                    return;
                }
                if activity.write_stuck_for().is_some_and(|d| d >= idle) {
                    tracing::debug!(client = %remote, "client does not read its answers; dropped");
                    return;
                }
                if closing_since.is_none() && activity.idle_for().is_some_and(|d| d >= idle) {
                    closing_since = Some(Instant::now());
                    conn.as_mut().graceful_shutdown();
                }
            }
            changed = closing.changed(), if closing_since.is_none() => {
                if changed.is_err() || *closing.borrow() {
                    closing_since = Some(Instant::now());
                    conn.as_mut().graceful_shutdown();
                }
            }
        }
    }
}
