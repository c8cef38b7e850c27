//! `/api/v1/programs`: upload, list, read, delete and run KRL programs.
//!
//! An upload is checked by the KRL front end (and, with the simulator, its
//! KRL subset) before anything is stored; a run writes a fresh module into
//! the controller's program folder and sends one RUN command, so every run
//! executes the newest code.

use std::time::Duration;

use axum::extract::{Path, State};
use axum::http::{HeaderValue, header};
use axum::response::Response;
use serde::Deserialize;
use utoipa::ToSchema;
use utoipa_axum::{router::OpenApiRouter, routes};

use super::auth::Who;
use super::problem::{JsonBody, PROBLEM_JSON, Problem, ProblemDetails, json_response};
use super::{AppState, ok_json};
use crate::engine::{Job, Operation};
use crate::error::BridgeError;
use crate::programs::{ProgramInfo, ProgramUpload, StoredProgram};

/// Options of a run.
#[derive(Debug, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RunRequest {
    /// Wait for the program to end (default true); false answers 202 with the job.
    #[serde(default)]
    pub wait: Option<bool>,
    /// Job timeout in ms (default `programs.run_timeout_ms`, one hour).
    #[serde(default)]
    pub timeout_ms: Option<u64>,
}

/// Uploads (or replaces) a KRL program.
///
/// The `.src` (and optional `.dat`) are parsed and checked before anything is stored or
/// reaches the controller: syntax, names of at most 24 characters, the entry point (no
/// parameters) and, when the service runs the simulated controller, its KRL subset.
/// Errors are `invalid_program` / `program_unsupported` with `file` and `line`.
#[utoipa::path(post, path = "/api/v1/programs", tag = "programs", request_body = ProgramUpload,
    responses((status = 201, body = ProgramInfo, description = "Stored (new)"), (status = 200, body = ProgramInfo, description = "Stored (replaced)"),
        (status = 422, body = ProblemDetails, content_type = PROBLEM_JSON), (status = 413, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn upload(
    State(app): State<AppState>,
    JsonBody(u): JsonBody<ProgramUpload>,
) -> Result<Response, Problem> {
    let (stored, created) = app.programs.put(u)?;
    let mut r = json_response(
        if created { 201 } else { 200 },
        "application/json",
        &stored.info,
    );
    if let Ok(v) = HeaderValue::from_str(&format!("/api/v1/programs/{}", stored.info.name)) {
        r.headers_mut().insert(header::LOCATION, v);
    }
    Ok(r)
}

/// Lists the stored programs.
#[utoipa::path(get, path = "/api/v1/programs", tag = "programs", responses((status = 200, body = [ProgramInfo])))]
async fn list(State(app): State<AppState>) -> Response {
    ok_json(&app.programs.list())
}

/// One program with its source text.
#[utoipa::path(get, path = "/api/v1/programs/{name}", tag = "programs", params(("name" = String, Path, description = "Program name")),
    responses((status = 200, body = StoredProgram), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_one(
    State(app): State<AppState>,
    Path(name): Path<String>,
) -> Result<Response, Problem> {
    Ok(ok_json(app.programs.get(&name)?.as_ref()))
}

/// Deletes a program.
#[utoipa::path(delete, path = "/api/v1/programs/{name}", tag = "programs", params(("name" = String, Path, description = "Program name")),
    responses((status = 204, description = "Deleted"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn delete_one(
    State(app): State<AppState>,
    Path(name): Path<String>,
) -> Result<Response, Problem> {
    app.programs.remove(&name)?;
    Ok(json_response(204, "application/json", &()))
}

/// Runs a stored program on the controller.
///
/// Writes the module `kbu<cid>` (a new name every time) into the controller's program
/// folder and sends one RUN command; queued like any motion. Waits for the end by default.
/// A failure names the program line (`line`): `program_failed`, `program_unsupported`,
/// or a motion error such as `unreachable`.
#[utoipa::path(post, path = "/api/v1/programs/{name}/run", tag = "programs", params(("name" = String, Path, description = "Program name")),
    request_body(content = Option<RunRequest>, description = "Optional"),
    responses((status = 200, body = Job, description = "Finished"), (status = 202, body = Job, description = "Queued (wait = false)"),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn run(
    State(app): State<AppState>,
    who: Who,
    Path(name): Path<String>,
    body: axum::body::Bytes,
) -> Result<Response, Problem> {
    let req: RunRequest = if body.iter().all(u8::is_ascii_whitespace) {
        RunRequest::default()
    } else {
        serde_json::from_slice(&body)
            .map_err(|e| BridgeError::invalid(format!("run options: {e}")))?
    };
    let program = app.programs.get(&name)?;
    let timeout = req.timeout_ms.map(Duration::from_millis);
    if timeout.is_some_and(|t| t.is_zero()) {
        return Err(BridgeError::invalid("timeout_ms must be positive").into());
    }
    let timeout = Some(timeout.unwrap_or(app.programs.run_timeout()));
    let job = app
        .engine
        .submit(Operation::RunProgram(program), timeout, who.caller())
        .await?;
    if req.wait == Some(false) {
        let mut r = json_response(202, "application/json", &job);
        if let Ok(v) = HeaderValue::from_str(&format!("/api/v1/jobs/{}", job.id)) {
            r.headers_mut().insert(header::LOCATION, v);
        }
        return Ok(r);
    }
    let job = app.engine.wait(job.id, app.wait_budget(timeout)).await?;
    super::v1::job_outcome(job)
}

/// The routes of this module.
pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(upload, list))
        .routes(routes!(get_one, delete_one))
        .routes(routes!(run))
}
