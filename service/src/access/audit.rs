//! The audit trail: one JSON line per mutating request (who, role, what,
//! parameters, job ids, result, duration) in `audit.<date>.jsonl` files in
//! `<log dir>/audit` (private to the service account and administrators),
//! rolled daily and kept as long as the other logs. Each line is appended
//! (one `write` to the file, no user-space buffer) by the request's own task
//! before its answer leaves, so an answered request is always on record;
//! a hand-off to a writer thread cost two thread wake-ups (≈100 µs on the
//! 2-vCPU machine) for a write of a few microseconds. Token secrets never
//! reach it: query parameters named `access_token` are removed.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};
use tracing_appender::rolling::RollingFileAppender;
use utoipa::{IntoParams, ToSchema};

use crate::clock::JobId;

/// One audited request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
#[schema(example = json!({
    "time_ms": 1763856000123_u64, "who": "line-3-pc", "role": "operator", "client": "10.0.3.17",
    "method": "POST", "path": "/api/v1/motions", "route": "/api/v1/motions",
    "params": {"body": {"motions": [{"type": "ptp", "target": {"x": 200, "y": 0, "z": 100}}]}},
    "jobs": [42], "status": 200, "duration_ms": 812.4
}))]
pub struct AuditRecord {
    /// When the request arrived (Unix ms).
    pub time_ms: u64,
    /// Token name (`anonymous` when auth is off).
    pub who: String,
    /// Its role.
    pub role: super::Role,
    /// Client address.
    pub client: String,
    /// HTTP method.
    pub method: String,
    /// Request path (no query string).
    pub path: String,
    /// The route it matched.
    pub route: String,
    /// Query parameters and JSON body (bodies of other types by size only).
    pub params: serde_json::Value,
    /// Jobs the request created.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub jobs: Vec<JobId>,
    /// HTTP status of the answer.
    pub status: u16,
    /// Problem code when it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub code: Option<String>,
    /// Time to the answer (ms).
    pub duration_ms: f64,
}

/// Filters of `GET /api/v1/audit`.
#[derive(Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct AuditQuery {
    /// Only this token name.
    pub who: Option<String>,
    /// Only paths containing this text (e.g. `motions`, `/krl/`).
    pub path: Option<String>,
    /// Only this HTTP method.
    pub method: Option<String>,
    /// Only failures (status ≥ 400) when true, only successes when false.
    pub failed: Option<bool>,
    /// Only this problem code.
    pub code: Option<String>,
    /// Only records at or after this time (Unix ms).
    pub since_ms: Option<u64>,
    /// Only records before this time (Unix ms).
    pub until_ms: Option<u64>,
    /// Most records returned, newest first (default 100, at most 1000).
    pub limit: Option<usize>,
}

impl AuditQuery {
    fn matches(&self, r: &AuditRecord) -> bool {
        self.who.as_ref().is_none_or(|w| *w == r.who)
            && self
                .path
                .as_ref()
                .is_none_or(|p| r.path.contains(p.as_str()))
            && self
                .method
                .as_ref()
                .is_none_or(|m| m.eq_ignore_ascii_case(&r.method))
            && self.failed.is_none_or(|f| f == (r.status >= 400))
            && self
                .code
                .as_ref()
                .is_none_or(|c| r.code.as_deref() == Some(c))
            && self.since_ms.is_none_or(|t| r.time_ms >= t)
            && self.until_ms.is_none_or(|t| r.time_ms < t)
    }
}

/// The audit writer and reader.
pub struct AuditLog {
    dir: PathBuf,
    file: Mutex<RollingFileAppender>,
}

const PREFIX: &str = "audit";
const SUFFIX: &str = "jsonl";

impl AuditLog {
    /// Opens the trail in `dir`, keeping `keep_days` files.
    pub fn open(dir: &Path, keep_days: usize) -> std::io::Result<AuditLog> {
        std::fs::create_dir_all(dir)?;
        let appender = RollingFileAppender::builder()
            .rotation(tracing_appender::rolling::Rotation::DAILY)
            .filename_prefix(PREFIX)
            .filename_suffix(SUFFIX)
            .max_log_files(keep_days.max(1))
            .build(dir)
            .map_err(std::io::Error::other)?;
        Ok(AuditLog {
            dir: dir.to_path_buf(),
            file: Mutex::new(appender),
        })
    }

    /// Appends a record as one line, written to the file when this returns
    /// (a failure is logged: the request it describes has already run).
    pub fn record(&self, record: &AuditRecord) {
        let mut line = match serde_json::to_vec(record) {
            Ok(line) => line,
            Err(e) => {
                tracing::error!(error = %e, "cannot encode an audit record");
                return;
            }
        };
        line.push(b'\n');
        // A panic while writing poisons the lock but leaves a usable file.
        let mut file = self.file.lock().unwrap_or_else(|p| p.into_inner());
        if let Err(e) = file.write_all(&line).and_then(|()| file.flush()) {
            tracing::error!(error = %e, "cannot write the audit trail");
        }
    }

    /// Records matching `q`, newest first.
    pub async fn query(&self, q: AuditQuery) -> std::io::Result<Vec<AuditRecord>> {
        let dir = self.dir.clone();
        tokio::task::spawn_blocking(move || read(&dir, &q))
            .await
            .map_err(std::io::Error::other)?
    }
}

fn read(dir: &Path, q: &AuditQuery) -> std::io::Result<Vec<AuditRecord>> {
    let limit = q.limit.unwrap_or(100).clamp(1, 1000);
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("audit.") && n.ends_with(".jsonl"))
        })
        .collect();
    // Dates in the names sort in time order.
    files.sort();
    let mut out = Vec::new();
    for f in files.iter().rev() {
        let text = std::fs::read_to_string(f)?;
        for line in text.lines().rev() {
            // A line being written or damaged is skipped, never fatal.
            let Ok(r) = serde_json::from_str::<AuditRecord>(line) else {
                continue;
            };
            if q.matches(&r) {
                out.push(r);
                if out.len() >= limit {
                    return Ok(out);
                }
            }
        }
    }
    Ok(out)
}

/// Largest body recorded with its content (bigger ones by size only).
pub const MAX_RECORDED_BODY: usize = 16 * 1024;

/// A media type without its parameters, in lower case.
fn essence(content_type: &str) -> String {
    content_type
        .split(';')
        .next()
        .unwrap_or_default()
        .trim()
        .to_ascii_lowercase()
}

/// True for `application/json` and `application/<anything>+json`, in any
/// letter case and with parameters (what axum's JSON extractor accepts).
pub fn is_json(content_type: &str) -> bool {
    let essence = essence(content_type);
    essence == "application/json"
        || (essence.starts_with("application/") && essence.ends_with("+json"))
}

/// Bodies of this media type are recorded as text when they are not JSON:
/// forms (what `curl -d` sends without a content type) and `text/*`.
pub fn is_text(content_type: &str) -> bool {
    let essence = essence(content_type);
    essence == "application/x-www-form-urlencoded" || essence.starts_with("text/")
}

/// Parameters for the record: the query string without secrets, and the
/// body if it is small (read by the caller): as `body` when it is JSON
/// (whatever its content type says), as `body_text` when it is a form,
/// text or broken JSON, else by size and type (`body_bytes`).
pub fn params(
    query: Option<&str>,
    content_type: Option<&str>,
    body: &[u8],
    size: Option<u64>,
) -> serde_json::Value {
    let mut out = serde_json::Map::new();
    if let Some(q) = query.filter(|q| !q.is_empty()) {
        let pairs: Vec<(String, String)> = serde_urlencoded::from_str(q).unwrap_or_default();
        let map: serde_json::Map<String, serde_json::Value> = pairs
            .into_iter()
            .filter(|(k, _)| k != super::QUERY_TOKEN)
            .map(|(k, v)| (k, serde_json::Value::String(v)))
            .collect();
        if !map.is_empty() {
            out.insert("query".into(), map.into());
        }
    }
    if !body.is_empty() {
        let small = body.len() <= MAX_RECORDED_BODY;
        let parsed = small
            .then(|| serde_json::from_slice::<serde_json::Value>(body).ok())
            .flatten();
        // Text-like types, and JSON that does not parse (kept for the record).
        let texty = content_type.is_none_or(|c| is_text(c) || is_json(c));
        let text = (small && texty)
            .then(|| std::str::from_utf8(body).ok())
            .flatten();
        match (parsed, text) {
            (Some(v), _) => {
                out.insert("body".into(), v);
            }
            (None, Some(t)) => {
                out.insert("body_text".into(), t.into());
            }
            (None, None) => {
                out.insert(
                    "body_bytes".into(),
                    serde_json::json!({"bytes": body.len(), "content_type": content_type}),
                );
            }
        }
    } else if let Some(n) = size.filter(|n| *n > 0) {
        out.insert(
            "body_bytes".into(),
            serde_json::json!({"bytes": n, "content_type": content_type}),
        );
    }
    out.into()
}
