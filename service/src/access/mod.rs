//! Access control: who may move the robot. Tokens with roles
//! ([`tokens`], [`policy`]), one writer at a time ([`control`]), the audit
//! trail ([`audit`]), the failed-attempt limiter and the first admin token.
//! The HTTP side (the middleware that applies all this to each request)
//! lives in `api::auth`; this module has no HTTP types.
//!
//! The identity of the request being served is kept in a task-local
//! [`RequestContext`], so code that runs on its behalf (the engine creating
//! jobs, a plugin asking for motions) acts under the caller's identity and
//! control lease without passing it through every signature.

pub mod audit;
pub mod control;
pub mod policy;
pub mod tokens;

use std::collections::HashMap;
use std::net::IpAddr;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

pub use control::{Control, Lease};
pub use policy::{Role, Rule};
pub use tokens::{TokenError, TokenInfo, TokenStore};

use crate::clock::JobId;

/// The query parameter old clients may use instead of the header (weaker:
/// URLs end up in proxies' and browsers' histories).
pub const QUERY_TOKEN: &str = "access_token";

/// Who is making a request.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, utoipa::ToSchema)]
pub struct Principal {
    /// Token name (`anonymous` when auth is off).
    pub name: String,
    /// Its role (admin when auth is off).
    pub role: Role,
}

impl Principal {
    /// The identity of every request when auth is off (loopback only).
    pub fn anonymous() -> Principal {
        Principal {
            name: "anonymous".into(),
            role: Role::Admin,
        }
    }
}

/// The request being served: its caller and the jobs it created.
#[derive(Debug)]
pub struct RequestContext {
    /// The caller.
    pub principal: Principal,
    jobs: Mutex<Vec<JobId>>,
}

impl RequestContext {
    /// A context for `principal`.
    pub fn new(principal: Principal) -> Arc<RequestContext> {
        Arc::new(RequestContext {
            principal,
            jobs: Mutex::new(Vec::new()),
        })
    }

    /// The jobs created so far.
    pub fn jobs(&self) -> Vec<JobId> {
        self.jobs
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone()
    }

    /// Records that this request created job `id` (for the audit).
    pub fn note_job(&self, id: JobId) {
        self.jobs
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(id);
    }

    /// The engine's [`crate::engine::Caller`] for this request: the
    /// principal's name, and [`RequestContext::note_job`] to record the
    /// jobs it creates.
    pub fn caller(self: &Arc<Self>) -> crate::engine::Caller {
        let ctx = self.clone();
        crate::engine::Caller {
            name: Some(self.principal.name.clone()),
            on_job: Some(Arc::new(move |id| ctx.note_job(id))),
        }
    }
}

/// Counts failed authentication attempts per client address and refuses
/// further attempts from an address once it failed too often in a window.
pub struct AttemptLimiter {
    max: u32,
    window: Duration,
    seen: Mutex<HashMap<IpAddr, (u32, Instant)>>,
}

impl AttemptLimiter {
    /// At most `max` failures per `window` and address.
    pub fn new(max: u32, window: Duration) -> AttemptLimiter {
        AttemptLimiter {
            max,
            window,
            seen: Mutex::new(HashMap::new()),
        }
    }

    fn map(&self) -> std::sync::MutexGuard<'_, HashMap<IpAddr, (u32, Instant)>> {
        self.seen
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// `Err(seconds to wait)` if `ip` may not try now.
    pub fn check(&self, ip: IpAddr) -> Result<(), u64> {
        let map = self.map();
        match map.get(&ip) {
            Some((n, start)) if *n >= self.max && start.elapsed() < self.window => {
                Err((self.window - start.elapsed()).as_secs().max(1))
            }
            _ => Ok(()),
        }
    }

    /// Counts a failure of `ip`.
    pub fn fail(&self, ip: IpAddr) {
        let mut map = self.map();
        let window = self.window;
        if map.len() > 10_000 {
            map.retain(|_, (_, start)| start.elapsed() < window);
        }
        let e = map.entry(ip).or_insert((0, Instant::now()));
        if e.1.elapsed() >= window {
            *e = (0, Instant::now());
        }
        e.0 += 1;
    }
}

/// Everything access control needs at run time.
pub struct Access {
    /// Tokens are required (listening beyond loopback, or asked for).
    pub enabled: bool,
    /// The token file.
    pub tokens: Arc<TokenStore>,
    /// The control lease.
    pub control: Arc<Control>,
    /// The audit trail.
    pub audit: audit::AuditLog,
    /// Failed attempts per address.
    pub limiter: AttemptLimiter,
    /// Accept `?access_token=` where old clients need it.
    pub query_token: bool,
}

impl Access {
    /// Ends the control lease of a token that was revoked (with auth off
    /// the holder is `anonymous`, which has no token).
    pub fn forget_revoked(&self) {
        if self.enabled {
            self.control.release_unless(|name| self.tokens.exists(name));
        }
    }
}

/// The file the first admin token is written to.
pub fn initial_token_path(data_dir: &Path) -> PathBuf {
    data_dir.join("initial-admin-token.txt")
}

/// When auth is on and no admin token exists: creates one named `admin`
/// (or `admin-2`, …) and writes its secret to [`initial_token_path`],
/// readable only by the service account and administrators. Returns the
/// file's path when it did.
pub fn ensure_admin(tokens: &TokenStore, data_dir: &Path) -> Result<Option<PathBuf>, TokenError> {
    if tokens.has_admin() {
        return Ok(None);
    }
    let taken: Vec<String> = tokens.list().into_iter().map(|t| t.name).collect();
    let name = std::iter::once("admin".to_string())
        .chain((2..).map(|i| format!("admin-{i}")))
        .find(|n| !taken.contains(n))
        .unwrap_or_else(|| "admin".into());
    let (info, secret) = tokens.create(&name, Role::Admin)?;
    let path = initial_token_path(data_dir);
    let text = format!(
        "# kuka-bridge: the first admin token (name `{}`), created because access control is on\n\
         # and no admin token existed. Send it as `Authorization: Bearer <token>`.\n\
         # Store it somewhere safe, then delete this file. Revoke it with\n\
         # `kuka-bridge token revoke {}` once you have created your own tokens.\n{}\n",
        info.name, info.name, secret
    );
    crate::platform::private_file::write(&path, text.as_bytes()).map_err(|source| {
        TokenError::Io {
            path: path.display().to_string(),
            source,
        }
    })?;
    Ok(Some(path))
}

/// Re-reads the token file every `period` so that tokens created or revoked
/// by the CLI take effect on the running service (a revoked holder of
/// control loses it).
pub async fn watch_tokens(
    access: Arc<Access>,
    period: Duration,
    mut closing: tokio::sync::watch::Receiver<bool>,
) {
    let tokens = access.tokens.clone();
    let mut reported = false;
    loop {
        tokio::select! {
            () = tokio::time::sleep(period) => {}
            _ = closing.changed() => return,
        }
        let store = tokens.clone();
        match tokio::task::spawn_blocking(move || store.reload()).await {
            Ok(Ok(true)) => {
                reported = false;
                tracing::info!(tokens = tokens.list().len(), "token file changed; reloaded");
                access.forget_revoked();
            }
            Ok(Ok(false)) => reported = false,
            Ok(Err(e)) if !reported => {
                reported = true;
                tracing::warn!(error = %e, "cannot reload the token file; the previous tokens stay in force");
            }
            _ => {}
        }
    }
}
