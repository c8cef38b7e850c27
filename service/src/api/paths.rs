//! Paths: motion streams that stay open while motions are appended
//! (`/api/v1/paths`), for paths that are sent piece by piece or are too
//! long for one batch. Motions appended while the robot moves blend into
//! what it is doing; the controller's buffer is filled as it has room
//! (protocol version 2, krl/PROTOCOL.md §5.5).

use std::time::Duration;

use axum::extract::{FromRequest, Path, Request, State};
use axum::http::{HeaderValue, header};
use axum::response::Response;
use futures_util::StreamExt;
use serde::Deserialize;
use utoipa::{IntoParams, ToSchema};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::auth::Who;
use super::problem::{JsonBody, PROBLEM_JSON, Problem, ProblemDetails, QueryParams, json_response};
use super::{AppState, ok_json};
use crate::engine::{AppendOutcome, Job, JobId, Operation, PathOptions};
use crate::error::{BridgeError, ErrorCode};
use crate::motion::{Configuration, MotionRequest};

/// How long an append waits for room by default (JSON body).
const DEFAULT_WAIT_MS: u64 = 30_000;
/// Motions of a JSON-lines stream appended together at most.
const STREAM_BATCH: usize = 200;
/// The longest line of a JSON-lines stream.
const MAX_LINE: usize = 64 * 1024;

/// Opening a path.
#[derive(Debug, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"config": "auto"}))]
pub struct PathCreate {
    /// How the PTPs without `s` get their arm configuration: `auto` (the
    /// bridge chooses) or `keep` (KUKA's rule). Default: the site's
    /// `motion.configuration`.
    pub config: Option<Configuration>,
}

/// Motions to append.
#[derive(Debug, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({
    "motions": [
        {"type": "lin", "target": {"x": 200, "y": 10}, "velocity_m_s": 0.2},
        {"type": "lin", "target": {"x": 210, "y": 20}, "velocity_m_s": 0.2}
    ],
    "close": false
}))]
pub struct AppendBody {
    /// The motions, in order; they are approximated into each other and
    /// into what follows (`approx_mm` default of the site) unless they set
    /// `approx_mm`. May be empty (with `close`).
    #[serde(default)]
    pub motions: Vec<MotionRequest>,
    /// Close the path after these motions: it ends when they have run.
    #[serde(default)]
    pub close: bool,
    /// How long to wait for room while the path's buffer is full (ms,
    /// default 30000); then `path_full` with `Retry-After`.
    pub wait_ms: Option<u64>,
}

/// Query of a JSON-lines append.
#[derive(Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct AppendQuery {
    /// JSON lines only: close the path when the stream ends (default
    /// true). A stream that breaks off (the client disconnects) always
    /// closes it at the last motion appended.
    pub close: Option<bool>,
}

/// Query of `DELETE /api/v1/paths/{id}`.
#[derive(Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct EndQuery {
    /// Stop the robot now (the path is cancelled) instead of letting it
    /// finish the motions already appended.
    pub cancel: Option<bool>,
}

/// Open a path: a motion stream that stays open while motions are appended.
///
/// The answer is the path's job (`operation: path`), 201 with a `Location`. The path
/// takes the controller like any job (it waits behind queued jobs), then runs motions
/// as they are appended with `POST /api/v1/paths/{id}/motions`: motions appended while
/// the robot moves are approximated into it, so a path sent motion by motion does not
/// stop between motions as long as they come faster than the robot runs them. End it
/// with `DELETE /api/v1/paths/{id}` (the robot finishes what was appended), or stop.
#[utoipa::path(post, path = "/api/v1/paths", tag = "motion",
    request_body(content = Option<PathCreate>, description = "Optional: no body opens a path with the defaults"),
    responses(
        (status = 201, description = "The path's job", body = Job),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn create_path(
    State(app): State<AppState>,
    who: Who,
    headers: axum::http::HeaderMap,
    body: axum::body::Bytes,
) -> Result<Response, Problem> {
    // The body is optional: no body opens a path with the defaults.
    let create: PathCreate = if body.iter().all(u8::is_ascii_whitespace) {
        PathCreate::default()
    } else {
        if !is_json(&headers) {
            return Err(BridgeError::new(
                ErrorCode::UnsupportedMediaType,
                "send the path's options as application/json, or no body for the defaults",
            )
            .into());
        }
        let v: serde_json::Value = serde_json::from_slice(&body)
            .map_err(|e| BridgeError::invalid(format!("request body: {e}")))?;
        if !v.is_object() {
            return Err(BridgeError::invalid(
                "the request body is a JSON object of options, e.g. {} or {\"config\": \"auto\"}",
            )
            .into());
        }
        serde_json::from_value(v).map_err(|e| BridgeError::invalid(format!("request body: {e}")))?
    };
    // A controller in its error state runs no path: say so now, rather
    // than open one whose first append is refused as closed.
    if let Some(e) = app.engine.state().controller.error {
        return Err(BridgeError::new(ErrorCode::ControllerError, e.detail).into());
    }
    let job = app
        .engine
        .submit(
            Operation::Path(PathOptions {
                config: create.config,
            }),
            None,
            who.caller(),
        )
        .await?;
    let mut r = json_response(201, "application/json", &job);
    if let Ok(v) = HeaderValue::from_str(&format!("/api/v1/paths/{}", job.id)) {
        r.headers_mut().insert(header::LOCATION, v);
    }
    Ok(r)
}

/// Append motions to an open path.
///
/// Either a JSON object (`AppendBody`: the motions, `close`, `wait_ms`), appended all or
/// none, or a stream of JSON lines (`Content-Type: application/x-ndjson`, one motion
/// object per line) for a path of any length: the lines are appended as they arrive and
/// the connection's flow control holds the client back while the path is full. Each
/// motion is checked (reachability, limits, configuration, the swept path against the
/// workspace rules) against the end of what the path already holds before anything is
/// sent; a refused motion closes the path at the last accepted motion (the answer names
/// it and says why; a JSON object is appended all or none, a JSON-lines stream keeps the
/// lines before the refused one). Omitted coordinates keep
/// the previous motion's value, across appends. While the path holds 2000 motions not
/// yet on the controller an append waits for room, up to `wait_ms`,
/// then answers `path_full` with `Retry-After`.
#[utoipa::path(post, path = "/api/v1/paths/{id}/motions", tag = "motion",
    params(("id" = u64, Path, description = "The path's job id"), AppendQuery),
    request_body(content(
        (AppendBody = "application/json"),
        (String = "application/x-ndjson"),
        (String = "application/jsonl")
    )),
    responses(
        (status = 200, description = "Appended", body = AppendOutcome),
        (status = 404, description = "`not_found`: no job with this id, or the job is not a path", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 409, description = "`path_closed`: the path is not open (closed, refused a motion, ended, stopped)", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 415, description = "`unsupported_media_type`: the body is neither JSON nor JSON lines", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "A refused motion (`motion` = its index in the path): the path is closed at the last accepted motion; nothing of a JSON object was appended, a JSON-lines stream kept the lines before it", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 503, description = "`path_full`: no room within `wait_ms`; nothing appended", body = ProblemDetails, content_type = PROBLEM_JSON,
            headers(("Retry-After" = u64, description = "Seconds to wait before appending again (1)"))),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn append(
    State(app): State<AppState>,
    Path(id): Path<String>,
    QueryParams(q): QueryParams<AppendQuery>,
    req: Request,
) -> Result<Response, Problem> {
    let id = parse_id(&id)?;
    let lines = req
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| {
            let v = v.trim_start().to_ascii_lowercase();
            v.starts_with("application/x-ndjson") || v.starts_with("application/jsonl")
        });
    if lines {
        return append_lines(&app, id, q.close.unwrap_or(true), req).await;
    }
    if q.close.is_some() {
        return Err(BridgeError::invalid(
            "the query parameter close is for JSON-lines streams; a JSON body says \"close\"",
        )
        .into());
    }
    if !is_json(req.headers()) {
        return Err(BridgeError::new(
            ErrorCode::UnsupportedMediaType,
            "send the motions as application/json (an object with \"motions\") or as JSON lines (application/x-ndjson, one motion per line)",
        )
        .into());
    }
    let JsonBody(body) = JsonBody::<AppendBody>::from_request(req, &app).await?;
    let wait = Duration::from_millis(body.wait_ms.unwrap_or(DEFAULT_WAIT_MS));
    let outcome = app
        .engine
        .append(id, body.motions, body.close, wait)
        .await
        .map_err(full_retry)?;
    Ok(ok_json(&outcome))
}

/// How long a JSON-lines stream may pause before the service tells the
/// controller that its path is still in use (well within the KRL
/// program's `kb_path_idle_ms`, 5 s).
const STREAM_KEEPALIVE: Duration = Duration::from_secs(2);

/// What a JSON-lines stream has appended so far.
#[derive(Default)]
struct Streamed {
    /// Path-wide index of its first motion.
    first: Option<usize>,
    appended: usize,
    total: usize,
    end: Option<crate::engine::CartesianFrame>,
    /// Parsed motions not yet appended.
    batch: Vec<MotionRequest>,
}

impl Streamed {
    /// Appends up to [`STREAM_BATCH`] of the parsed motions; unless `last`,
    /// not the `spl` points of a spline block the next lines may continue
    /// (a block never depends on where the bytes broke). The number
    /// appended (0: only such points are parsed).
    async fn flush(
        &mut self,
        engine: &crate::engine::Engine,
        id: JobId,
        wait: Duration,
        last: bool,
    ) -> Result<usize, BridgeError> {
        let mut take = self.batch.len().min(STREAM_BATCH);
        if !last {
            take -= crate::motion::open_spline_tail(&self.batch[..take]);
        }
        if take == 0 {
            return Ok(0);
        }
        let motions: Vec<MotionRequest> = self.batch.drain(..take).collect();
        let o = engine.append_with(id, motions, false, wait, true).await?;
        self.first.get_or_insert(o.first);
        self.appended += o.appended;
        self.total = o.total;
        self.end = Some(o.end);
        Ok(take)
    }
}

/// A JSON-lines stream: motions appended in batches as the lines arrive.
/// A bad line, a refused motion or a broken-off stream closes the path at
/// the last motion appended.
async fn append_lines(
    app: &AppState,
    id: JobId,
    close_at_end: bool,
    req: Request,
) -> Result<Response, Problem> {
    let engine = &app.engine;
    // Waiting for room is the stream's back-pressure: as long as the request may take.
    let wait = Duration::from_millis(app.server.max_request_ms);
    let mut body = req.into_body().into_data_stream();
    let mut buf: Vec<u8> = Vec::new();
    let mut done = Streamed::default();
    let mut line_no = 0usize;
    let close = || async {
        let _ = engine
            .append(id, Vec::new(), true, Duration::from_secs(10))
            .await;
    };
    loop {
        // A pause in the stream is not a client that is gone: while the
        // connection is open the path is kept alive (the controller ends a
        // path nobody appends to after `kb_path_idle_ms`, 5 s).
        let next = loop {
            match tokio::time::timeout(STREAM_KEEPALIVE, body.next()).await {
                Ok(next) => break next,
                Err(_) => {
                    // The stream pauses: a spline block held back for more
                    // points goes as it is (the robot would otherwise stop
                    // before points it was sent).
                    while !done.batch.is_empty() {
                        if let Err(e) = done.flush(engine, id, wait, true).await {
                            if e.code != ErrorCode::PathClosed {
                                close().await;
                            }
                            return Err(e.into());
                        }
                    }
                    if let Err(e) = engine.keep_path_alive(id).await {
                        tracing::debug!(
                            path = id,
                            code = e.code.as_str(),
                            "keep-alive of a paused stream"
                        );
                    }
                }
            }
        };
        let ended = match next {
            None => true,
            Some(Ok(bytes)) => {
                buf.extend_from_slice(&bytes);
                false
            }
            Some(Err(e)) => {
                // The client went away: the path ends at the last motion
                // received whole (a held-back spline block goes too).
                while !done.batch.is_empty() {
                    if done.flush(engine, id, wait, true).await.is_err() {
                        break;
                    }
                }
                tracing::info!(path = id, appended = done.appended, error = %e, "path stream broke off; closing the path");
                close().await;
                return Err(BridgeError::invalid(format!(
                    "the stream broke off after {} motions; the path was closed there",
                    done.appended
                ))
                .into());
            }
        };
        // Every complete line; at the end also what is left.
        let mut start = 0;
        let mut bad = None;
        while let Some(nl) = buf[start..].iter().position(|&b| b == b'\n') {
            let line = &buf[start..start + nl];
            start += nl + 1;
            line_no += 1;
            if let Err(e) = parse_line(line, line_no, &mut done.batch) {
                bad = Some(e);
                break;
            }
        }
        buf.drain(..start);
        if bad.is_none() && ended && !buf.is_empty() {
            line_no += 1;
            let rest = std::mem::take(&mut buf);
            bad = parse_line(&rest, line_no, &mut done.batch).err();
        }
        if bad.is_none() && buf.len() > MAX_LINE {
            bad = Some(BridgeError::invalid(format!(
                "line {} is longer than {MAX_LINE} bytes",
                line_no + 1
            )));
        }
        if let Some(mut e) = bad {
            // The lines before the bad one run; then the path ends, failed
            // with the reason (`motion`: the bad line's index in the path).
            let mut flushed = true;
            while !done.batch.is_empty() {
                if done.flush(engine, id, wait, true).await.is_err() {
                    flushed = false;
                    break;
                }
            }
            if flushed {
                // Motions in the path so far (this request may have
                // appended none: then the job says).
                let total = if done.first.is_some() {
                    done.total
                } else {
                    engine.job(id).map_or(0, |j| j.motions)
                };
                e.motion = Some(total);
                if let Err(why) = engine.refuse_path(id, e.clone()).await
                    && why.code != ErrorCode::PathClosed
                {
                    tracing::warn!(
                        path = id,
                        code = why.code.as_str(),
                        "could not close the path after a bad line"
                    );
                }
            } else {
                close().await;
            }
            return Err(e.into());
        }
        while done.batch.len() >= STREAM_BATCH
            || (!done.batch.is_empty() && (ended || buf.is_empty()))
        {
            match done.flush(engine, id, wait, ended).await {
                // Only an open spline block: its next lines decide.
                Ok(0) => break,
                Ok(_) => {}
                Err(e) => {
                    if e.code != ErrorCode::PathClosed {
                        close().await;
                    }
                    return Err(e.into());
                }
            }
        }
        if ended {
            break;
        }
    }
    let mut closed = false;
    if close_at_end {
        let o = engine
            .append(id, Vec::new(), true, Duration::from_secs(10))
            .await
            .map_err(full_retry)?;
        closed = o.closed;
        done.total = o.total;
        done.end = Some(o.end);
    }
    Ok(ok_json(&AppendOutcome {
        path: id,
        first: done.first.unwrap_or(done.total),
        appended: done.appended,
        total: done.total,
        closed,
        end: done.end.unwrap_or_default(),
    }))
}

/// One line of a JSON-lines stream into `batch` (blank lines are skipped).
fn parse_line(
    line: &[u8],
    line_no: usize,
    batch: &mut Vec<MotionRequest>,
) -> Result<(), BridgeError> {
    if line.len() > MAX_LINE {
        return Err(BridgeError::invalid(format!(
            "line {line_no} is longer than {MAX_LINE} bytes"
        )));
    }
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    if line.iter().all(u8::is_ascii_whitespace) {
        return Ok(());
    }
    let m: MotionRequest = serde_json::from_slice(line)
        .map_err(|e| BridgeError::invalid(format!("line {line_no}: {e}")))?;
    batch.push(m);
    Ok(())
}

/// The error as a problem (`path_full` gets its `Retry-After` there).
fn full_retry(e: BridgeError) -> Problem {
    e.into()
}

/// One path: its job record (`operation: path`) with `path.appended`, `path.sent`,
/// `path.closed`; `completed` counts the motions the robot has finished.
#[utoipa::path(get, path = "/api/v1/paths/{id}", tag = "motion", params(("id" = u64, Path, description = "The path's job id")),
    responses((status = 200, body = Job), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_path(
    State(app): State<AppState>,
    Path(id): Path<String>,
) -> Result<Response, Problem> {
    let job = app.engine.job(parse_id(&id)?)?;
    if job.operation != "path" {
        return Err(
            BridgeError::new(ErrorCode::NotFound, format!("job {} is not a path", job.id)).into(),
        );
    }
    Ok(ok_json(&job))
}

/// End a path: it is closed and the robot finishes the motions already appended (the
/// job becomes `done` when the last has run); with `cancel=true` the robot stops now
/// and the path is cancelled. A path still queued behind other jobs (it has no motions
/// yet) is cancelled at once. A path that has ended already is returned unchanged.
#[utoipa::path(delete, path = "/api/v1/paths/{id}", tag = "motion",
    params(("id" = u64, Path, description = "The path's job id"), EndQuery),
    responses((status = 200, body = Job), (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn end_path(
    State(app): State<AppState>,
    Path(id): Path<String>,
    QueryParams(q): QueryParams<EndQuery>,
) -> Result<Response, Problem> {
    let id = parse_id(&id)?;
    let job = app.engine.job(id)?;
    if job.operation != "path" {
        return Err(
            BridgeError::new(ErrorCode::NotFound, format!("job {id} is not a path")).into(),
        );
    }
    if q.cancel == Some(true) {
        app.engine.cancel(id).await?;
        // The controller confirms the stop within moments: answer with the
        // path's final record when it has (or as it is after 5 s).
        return Ok(ok_json(&app.engine.wait(id, Duration::from_secs(5)).await?));
    }
    if job.state == crate::engine::JobState::Queued && app.engine.cancel_if_queued(id).await? {
        // Still behind other jobs: it has no motions yet (appends wait for
        // it to start), so closing it ends it now, without waiting for the
        // jobs ahead. (One step of the engine: a path that started in the
        // meantime is closed below instead, and finishes its motions.)
        return Ok(ok_json(&app.engine.job(id)?));
    }
    if !job.state.is_terminal() {
        match app
            .engine
            .append(id, Vec::new(), true, Duration::from_secs(10))
            .await
        {
            Ok(_) => {}
            // Ended meanwhile: the job says how.
            Err(e) if e.code == ErrorCode::PathClosed => {}
            Err(e) => return Err(e.into()),
        }
    }
    Ok(ok_json(&app.engine.job(id)?))
}

/// The request says its body is JSON (`application/json` or a `+json` type).
fn is_json(headers: &axum::http::HeaderMap) -> bool {
    headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.split(';').next())
        .is_some_and(|v| {
            let v = v.trim().to_ascii_lowercase();
            v == "application/json" || (v.starts_with("application/") && v.ends_with("+json"))
        })
}

fn parse_id(id: &str) -> Result<JobId, BridgeError> {
    id.parse()
        .map_err(|_| BridgeError::invalid(format!("path id {id:?} is not a number")))
}

/// The path endpoints.
pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(create_path))
        .routes(routes!(append))
        .routes(routes!(get_path, end_path))
}
