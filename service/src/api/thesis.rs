//! Endpoints compatible with the 2023 thesis bridge: POST with query
//! parameters `x y z a b c s t` (omitted coordinates keep their current
//! value), answering `{"statuscode": 1, "position": [x, y, z, a, b, c]}`.
//! Failures answer an HTTP error whose JSON still carries `statuscode`
//! (never 1) and `position`, plus the problem details.

use std::time::Duration;

use axum::extract::FromRequestParts;
use axum::extract::State;
use axum::http::request::Parts;
use axum::response::Response;
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::AppState;
use super::auth::Who;
use super::problem::{PROBLEM_JSON, ProblemDetails, json_response, query_rejection};
use crate::engine::{CartesianFrame, Job, JobState, Operation};
use crate::error::{BridgeError, ErrorCode};
use crate::motion::{AuxPoint, Configuration, MotionRequest, TargetSpec};

/// Target coordinates; omitted ones keep their current value. Upper-case
/// names (KUKA's own spelling) are accepted too; unknown parameters are
/// refused rather than ignored, so a typo never moves the robot elsewhere.
#[derive(Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct PointQuery {
    /// X in mm.
    #[serde(alias = "X")]
    x: Option<f64>,
    /// Y in mm.
    #[serde(alias = "Y")]
    y: Option<f64>,
    /// Z in mm.
    #[serde(alias = "Z")]
    z: Option<f64>,
    /// A (about Z) in degrees.
    #[serde(alias = "A")]
    a: Option<f64>,
    /// B (about Y) in degrees.
    #[serde(alias = "B")]
    b: Option<f64>,
    /// C (about X) in degrees.
    #[serde(alias = "C")]
    c: Option<f64>,
    /// Status (0..7); PTP only.
    #[serde(alias = "S")]
    s: Option<i64>,
    /// Turn (0..63); PTP only.
    #[serde(alias = "T")]
    t: Option<i64>,
}

impl PointQuery {
    fn target(&self) -> TargetSpec {
        TargetSpec {
            x: self.x,
            y: self.y,
            z: self.z,
            a: self.a,
            b: self.b,
            c: self.c,
            s: self.s,
            t: self.t,
        }
    }
}

/// CIRC: end point `x y z a b c` and auxiliary point `ax ay az`.
#[derive(Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct CircQuery {
    /// End X in mm.
    #[serde(alias = "X")]
    x: Option<f64>,
    /// End Y in mm.
    #[serde(alias = "Y")]
    y: Option<f64>,
    /// End Z in mm.
    #[serde(alias = "Z")]
    z: Option<f64>,
    /// End A in degrees.
    #[serde(alias = "A")]
    a: Option<f64>,
    /// End B in degrees.
    #[serde(alias = "B")]
    b: Option<f64>,
    /// End C in degrees.
    #[serde(alias = "C")]
    c: Option<f64>,
    /// Auxiliary point X in mm.
    #[serde(alias = "AX")]
    ax: Option<f64>,
    /// Auxiliary point Y in mm.
    #[serde(alias = "AY")]
    ay: Option<f64>,
    /// Auxiliary point Z in mm.
    #[serde(alias = "AZ")]
    az: Option<f64>,
}

/// A tool frame; omitted values keep the current tool's.
#[derive(Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct FrameQuery {
    /// X in mm.
    #[serde(alias = "X")]
    x: Option<f64>,
    /// Y in mm.
    #[serde(alias = "Y")]
    y: Option<f64>,
    /// Z in mm.
    #[serde(alias = "Z")]
    z: Option<f64>,
    /// A (about Z) in degrees.
    #[serde(alias = "A")]
    a: Option<f64>,
    /// B (about Y) in degrees.
    #[serde(alias = "B")]
    b: Option<f64>,
    /// C (about X) in degrees.
    #[serde(alias = "C")]
    c: Option<f64>,
}

/// Endpoints without parameters refuse any (a typo must not go unnoticed).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct NoParams {}

/// The thesis's response.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({"statuscode": 1, "position": [200.0, 0.0, 70.0, 0.0, 180.0, 0.0]}))]
pub struct ThesisResponse {
    /// 1 on success; see docs/errors.md for the other values.
    pub statuscode: i32,
    /// `[x, y, z, a, b, c]`: the robot position (for `tcp`/`gettcp`: the tool frame).
    pub position: [f64; 6],
    /// `getpos` while a motion runs: the position comes from the
    /// controller's live state, read this many ms ago (absent otherwise:
    /// read through the controller program when the robot stands).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub age_ms: Option<u64>,
}

/// A thesis failure: the problem details plus `statuscode` and `position`.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({
    "statuscode": 20, "position": [355.0, 0.0, 625.0, 0.0, 90.0, 0.0],
    "type": "/errors#unreachable",
    "title": "Target unreachable", "status": 422, "detail": "target is out of reach of the robot",
    "code": "unreachable", "motion": 0
}))]
pub struct ThesisProblem {
    /// Never 1.
    pub statuscode: i32,
    /// Last known position `[x, y, z, a, b, c]` (zeros when unknown).
    pub position: [f64; 6],
    /// The problem details.
    #[serde(flatten)]
    pub problem: ProblemDetails,
}

/// The thesis `statuscode` for an error (1 is success). Motion errors use
/// the numbers of the matching controller result codes; see docs/errors.md.
pub fn statuscode(code: ErrorCode) -> i32 {
    match code {
        ErrorCode::Cancelled => 2,
        ErrorCode::ControllerBusy => 3,
        ErrorCode::InvalidInput => 10,
        ErrorCode::ProtocolError => 11,
        ErrorCode::Unreachable => 20,
        ErrorCode::SoftwareLimit => 21,
        ErrorCode::Singularity => 22,
        ErrorCode::WorkspaceViolation => 25,
        ErrorCode::SpeedLimit => 26,
        ErrorCode::ControllerError => 30,
        ErrorCode::ControllerOffline => 50,
        ErrorCode::ChannelLocked => 51,
        ErrorCode::Timeout => 52,
        ErrorCode::QueueFull => 53,
        ErrorCode::NotFound => 54,
        ErrorCode::MethodNotAllowed => 55,
        ErrorCode::PayloadTooLarge => 56,
        ErrorCode::UnsupportedMediaType => 57,
        ErrorCode::InvalidProgram => 12,
        ErrorCode::ProgramUnsupported => 13,
        ErrorCode::ProgramFailed => 40,
        ErrorCode::ProgramsUnavailable => 58,
        ErrorCode::PluginsUnavailable => 59,
        ErrorCode::PluginInvalid => 60,
        ErrorCode::PluginTimeout => 61,
        ErrorCode::PluginMemory => 62,
        ErrorCode::PluginTrap => 63,
        ErrorCode::PluginBadResponse => 64,
        ErrorCode::Unauthenticated => 70,
        ErrorCode::Forbidden => 71,
        ErrorCode::ControlHeld => 72,
        ErrorCode::TooManyAttempts => 73,
        ErrorCode::Overloaded => 74,
        ErrorCode::RequestTimeout => 75,
        ErrorCode::StorageUnavailable => 76,
        ErrorCode::CommandLost => 41,
        ErrorCode::Gone => 77,
        ErrorCode::ShuttingDown => 78,
        ErrorCode::PathClosed => 79,
        ErrorCode::PathFull => 80,
        ErrorCode::OutputNotAllowed => 81,
        ErrorCode::UnknownSignal => 82,
        ErrorCode::SignalNotReported => 83,
        ErrorCode::InputTimeout => 84,
        ErrorCode::VariableNotAllowed => 85,
        ErrorCode::UnknownVariable => 86,
        ErrorCode::VariablesUnavailable => 87,
        ErrorCode::Internal => 99,
    }
}

/// A thesis-format failure (for the `/krl/*` fallbacks too).
pub(super) fn fail(app: &AppState, e: &BridgeError) -> Response {
    fail_at(
        e,
        app.engine.state().position.map_or([0.0; 6], |p| p.xyzabc()),
    )
}

/// A thesis-format failure reporting `position`.
pub(super) fn fail_at(e: &BridgeError, position: [f64; 6]) -> Response {
    let problem = ProblemDetails::from_error(e);
    let body = ThesisProblem {
        statuscode: statuscode(e.code),
        position,
        problem,
    };
    json_response(body.problem.status, PROBLEM_JSON, &body)
}

fn done(position: [f64; 6]) -> Response {
    answer(position, None)
}

/// A success with the age of a live position, if it is one.
fn answer(position: [f64; 6], age_ms: Option<u64>) -> Response {
    json_response(
        200,
        "application/json",
        &ThesisResponse {
            statuscode: 1,
            position,
            age_ms,
        },
    )
}

async fn run(app: &AppState, who: &Who, op: Operation, frame_result: bool) -> Response {
    run_with(app, who, op, frame_result, None).await
}

/// [`run`] with a job timeout of its own (and a wait to match).
async fn run_with(
    app: &AppState,
    who: &Who,
    op: Operation,
    frame_result: bool,
    timeout: Option<std::time::Duration>,
) -> Response {
    if !app.thesis_blend.is_zero() {
        // Another kind of call: the client's blending path ends first (the
        // call runs after its last motion), without waiting for the window.
        let key = who.caller().name.unwrap_or_else(|| "anonymous".into());
        let open = app.thesis_paths.lock().remove(&key);
        if let Some((id, _)) = open {
            let _ = app
                .engine
                .append(id, Vec::new(), true, Duration::from_secs(10))
                .await;
            app.thesis_paths.closed().insert(key.clone(), id);
        }
        if matches!(op, Operation::Move(_))
            && let Some(e) = unreported_end(app, &key)
        {
            return fail(app, &e);
        }
    }
    match app
        .engine
        .execute(op, timeout, app.wait_budget(timeout), who.caller())
        .await
    {
        Ok(job) => done(job_position(&job, frame_result)),
        Err(e) => fail(app, &e),
    }
}

fn job_position(job: &Job, frame_result: bool) -> [f64; 6] {
    if frame_result {
        job.frame
            .map_or([0.0; 6], |f| [f.x, f.y, f.z, f.a, f.b, f.c])
    } else {
        job.position.map_or([0.0; 6], |p| p.xyzabc())
    }
}

/// Query parameters whose rejection is a thesis-format failure.
pub(super) struct ThesisQuery<T>(T);

impl<T: serde::de::DeserializeOwned> FromRequestParts<AppState> for ThesisQuery<T> {
    type Rejection = Response;

    async fn from_request_parts(
        parts: &mut Parts,
        app: &AppState,
    ) -> Result<Self, Self::Rejection> {
        match axum::extract::Query::<T>::from_request_parts(parts, app).await {
            Ok(axum::extract::Query(v)) => Ok(ThesisQuery(v)),
            Err(e) => Err(fail(app, &query_rejection(&e))),
        }
    }
}

/// PTP to a Cartesian target (thesis method 1).
///
/// Moves point-to-point; omitted coordinates keep their current value
/// (`/krl/ptp?x=30` moves only X). Waits until the motion is done.
#[utoipa::path(post, path = "/krl/ptp", tag = "thesis", params(PointQuery),
    responses((status = 200, body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn ptp(
    State(app): State<AppState>,
    who: Who,
    ThesisQuery(q): ThesisQuery<PointQuery>,
) -> Response {
    let m = MotionRequest::Ptp {
        target: q.target(),
        relative: false,
        velocity_pct: None,
        acceleration_pct: None,
        approx_mm: None,
        // Thesis clients never send S/T: the bridge chooses the arm
        // configuration (docs/CONFIGURATION.md).
        config: Some(Configuration::Auto),
    };
    run(&app, &who, Operation::Move(vec![m]), false).await
}

/// Straight line to a Cartesian target (thesis method 2).
#[utoipa::path(post, path = "/krl/linmov", tag = "thesis", params(PointQuery),
    responses((status = 200, body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn linmov(
    State(app): State<AppState>,
    who: Who,
    ThesisQuery(q): ThesisQuery<PointQuery>,
) -> Response {
    let m = MotionRequest::Lin {
        target: q.target(),
        relative: false,
        velocity_m_s: None,
        acceleration_pct: None,
        approx_mm: None,
    };
    if !app.thesis_blend.is_zero() {
        return blended(&app, &who, m).await;
    }
    run(&app, &who, Operation::Move(vec![m]), false).await
}

/// The open path of each thesis client whose motion calls blend
/// (`motion.thesis_blend_ms`): its job id and how many calls went to it;
/// and the last path closed for each client whose outcome the client has
/// not heard yet (a Stop or a failure after its calls were answered is
/// told by its next motion call, however late that comes).
#[derive(Default)]
pub struct BlendPaths {
    open: std::sync::Mutex<std::collections::HashMap<String, (crate::engine::JobId, u64)>>,
    closed: std::sync::Mutex<std::collections::HashMap<String, crate::engine::JobId>>,
}

impl BlendPaths {
    fn lock(
        &self,
    ) -> std::sync::MutexGuard<'_, std::collections::HashMap<String, (crate::engine::JobId, u64)>>
    {
        self.open.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn closed(
        &self,
    ) -> std::sync::MutexGuard<'_, std::collections::HashMap<String, crate::engine::JobId>> {
        self.closed.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// The outcome of the client's last closed blending path, once: the error
/// its next motion call answers with (and runs nothing) if the path was
/// stopped or failed. A path still running stays to be looked at by the
/// call after.
fn unreported_end(app: &AppState, key: &str) -> Option<BridgeError> {
    let id = app.thesis_paths.closed().get(key).copied()?;
    let job = app.engine.job(id).ok();
    let state = job.as_ref().map(|j| j.state);
    match state {
        Some(JobState::Failed | JobState::Cancelled) => {
            app.thesis_paths.closed().remove(key);
            job.map(|j| unran(&j))
        }
        Some(JobState::Done) | None => {
            app.thesis_paths.closed().remove(key);
            None
        }
        Some(_) => None,
    }
}

/// The answer for calls that were answered 1 but did not all run: the
/// path `ended` was stopped (`cancelled`) or failed (`controller_error`).
fn unran(ended: &Job) -> BridgeError {
    let why = ended.error.as_ref().map_or_else(
        || "stopped".to_string(),
        |e| format!("{} ({})", e.detail, e.code.as_str()),
    );
    let code = if ended.state == JobState::Cancelled {
        ErrorCode::Cancelled
    } else {
        ErrorCode::ControllerError
    };
    BridgeError::new(
        code,
        format!(
            "the blended calls before this one did not all run: {why}; this call ran nothing (the next call starts anew)"
        ),
    )
}

/// A thesis motion call that blends: appended to the client's open path
/// (opened on the first call), answered as soon as it is checked and
/// queued, with the position the robot will reach. The path is closed
/// when no call follows within `motion.thesis_blend_ms`: the robot then
/// stops at the last motion.
async fn blended(app: &AppState, who: &Who, m: MotionRequest) -> Response {
    let caller = who.caller();
    let key = caller.name.clone().unwrap_or_else(|| "anonymous".into());
    let wait = app.wait_budget(None);
    // A controller in its error state runs nothing: the call says so, as
    // an unblended one would, instead of being queued (and answered 1).
    if let Some(e) = app.engine.state().controller.error {
        app.thesis_paths.lock().remove(&key);
        app.thesis_paths.closed().remove(&key);
        return fail(app, &BridgeError::new(ErrorCode::ControllerError, e.detail));
    }
    if let Some(e) = unreported_end(app, &key) {
        return fail(app, &e);
    }
    for attempt in 0..2 {
        let open = app.thesis_paths.lock().get(&key).map(|(id, _)| *id);
        let id = match open {
            Some(id) => id,
            None => {
                let job = match app
                    .engine
                    .submit(
                        Operation::Path(crate::engine::PathOptions::default()),
                        None,
                        who.caller(),
                    )
                    .await
                {
                    Ok(job) => job,
                    Err(e) => return fail(app, &e),
                };
                app.thesis_paths.lock().insert(key.clone(), (job.id, 0));
                job.id
            }
        };
        match app.engine.append(id, vec![m.clone()], false, wait).await {
            Ok(o) => {
                let seq = {
                    let mut open = app.thesis_paths.lock();
                    let entry = open.entry(key.clone()).or_insert((id, 0));
                    entry.1 += 1;
                    entry.1
                };
                // Closed when no call follows within the window.
                let (engine, paths, window, key) = (
                    app.engine.clone(),
                    app.thesis_paths.clone(),
                    app.thesis_blend,
                    key.clone(),
                );
                tokio::spawn(async move {
                    tokio::time::sleep(window).await;
                    let last = paths.lock().remove_if_unchanged(&key, id, seq);
                    if last {
                        paths.closed().insert(key, id);
                        let _ = engine
                            .append(id, Vec::new(), true, Duration::from_secs(10))
                            .await;
                    }
                });
                let e = o.end;
                return done([e.x, e.y, e.z, e.a, e.b, e.c]);
            }
            // The path ended meanwhile. Ended as planned (the controller
            // closed it): a new one, once. Stopped or failed: the calls
            // answered before did not all run, and this call is how the
            // client learns it (README: "through its next call"); it runs
            // nothing, the next call starts a new path.
            Err(e) if e.code == ErrorCode::PathClosed && attempt == 0 => {
                app.thesis_paths.lock().remove(&key);
                if let Some(ended) = app
                    .engine
                    .job(id)
                    .ok()
                    .filter(|j| matches!(j.state, JobState::Failed | JobState::Cancelled))
                {
                    return fail(app, &unran(&ended));
                }
            }
            Err(e) => {
                // The path ends here: the robot stops at the last call that
                // was accepted (a path this call opened has none and ends at
                // once; left open it would hold the robot until the
                // controller's idle end, and every client behind it).
                app.thesis_paths.lock().remove(&key);
                if let Err(close) = app
                    .engine
                    .append(id, Vec::new(), true, Duration::from_secs(2))
                    .await
                    && close.code != ErrorCode::PathClosed
                {
                    tracing::warn!(
                        path = id,
                        code = close.code.as_str(),
                        "could not close the thesis client's path after a refused call"
                    );
                }
                // A thesis client sent one motion and knows of no path: the
                // sentence is about its call.
                let mut e = e;
                if let Some(cut) = e.detail.rfind(" (motion ") {
                    e.detail.truncate(cut);
                }
                if let Some(rest) = e.detail.strip_prefix("motion 0: ") {
                    e.detail = rest.to_string();
                }
                e.motion = None;
                return fail(app, &e);
            }
        }
    }
    fail(
        app,
        &BridgeError::new(ErrorCode::PathClosed, "the path closed twice in a row"),
    )
}

/// Removing a client's path only if no call came since.
trait RemoveIfUnchanged {
    fn remove_if_unchanged(&mut self, key: &str, id: crate::engine::JobId, seq: u64) -> bool;
}

impl RemoveIfUnchanged for std::collections::HashMap<String, (crate::engine::JobId, u64)> {
    fn remove_if_unchanged(&mut self, key: &str, id: crate::engine::JobId, seq: u64) -> bool {
        if self.get(key) == Some(&(id, seq)) {
            self.remove(key);
            true
        } else {
            false
        }
    }
}

/// Circular motion through `ax ay az` to `x y z a b c` (thesis method 7).
#[utoipa::path(post, path = "/krl/circ", tag = "thesis", params(CircQuery),
    responses((status = 200, body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn circ(
    State(app): State<AppState>,
    who: Who,
    ThesisQuery(q): ThesisQuery<CircQuery>,
) -> Response {
    let m = MotionRequest::Circ {
        aux: AuxPoint {
            x: q.ax,
            y: q.ay,
            z: q.az,
        },
        target: TargetSpec {
            x: q.x,
            y: q.y,
            z: q.z,
            a: q.a,
            b: q.b,
            c: q.c,
            s: None,
            t: None,
        },
        relative: false,
        velocity_m_s: None,
        acceleration_pct: None,
        approx_mm: None,
    };
    if !app.thesis_blend.is_zero() {
        return blended(&app, &who, m).await;
    }
    run(&app, &who, Operation::Move(vec![m]), false).await
}

/// Current position (thesis method 3): read through the controller program while
/// the robot stands; while a motion runs, at once from the controller's live state
/// (as `GET /api/v1/position` with `source: live`), with `age_ms`, the age of that sample.
#[utoipa::path(post, path = "/krl/getpos", tag = "thesis",
    responses((status = 200, body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn getpos(State(app): State<AppState>, who: Who, _: ThesisQuery<NoParams>) -> Response {
    if let Some(live) = app
        .engine
        .live_position_within(kuka_engine::engine::LIVE_POSITION_WAIT)
        .await
    {
        let age = u64::try_from(live.age.as_millis()).unwrap_or(u64::MAX);
        return answer(live.position.xyzabc(), Some(age));
    }
    run(&app, &who, Operation::GetPosition, false).await
}

/// Move to the home position (thesis method 6, "base").
#[utoipa::path(post, path = "/krl/base", tag = "thesis",
    responses((status = 200, body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn base(State(app): State<AppState>, who: Who, _: ThesisQuery<NoParams>) -> Response {
    run(&app, &who, Operation::Home, false).await
}

/// Set the tool (TCP) frame (thesis method 8); omitted values keep the current tool's.
#[utoipa::path(post, path = "/krl/tcp", tag = "thesis", params(FrameQuery),
    responses((status = 200, description = "`position` is the new tool frame", body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn tcp(
    State(app): State<AppState>,
    who: Who,
    ThesisQuery(q): ThesisQuery<FrameQuery>,
) -> Response {
    let cur = app.engine.state().tool.unwrap_or_default();
    let frame = CartesianFrame {
        x: q.x.unwrap_or(cur.x),
        y: q.y.unwrap_or(cur.y),
        z: q.z.unwrap_or(cur.z),
        a: q.a.unwrap_or(cur.a),
        b: q.b.unwrap_or(cur.b),
        c: q.c.unwrap_or(cur.c),
    };
    if let Err(e) = super::v1::check_frame(&frame) {
        return fail(&app, &e);
    }
    run(&app, &who, Operation::SetTool(frame), true).await
}

/// Current tool (TCP) frame (thesis method 9).
#[utoipa::path(post, path = "/krl/gettcp", tag = "thesis",
    responses((status = 200, description = "`position` is the tool frame", body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn gettcp(State(app): State<AppState>, who: Who, _: ThesisQuery<NoParams>) -> Response {
    run(&app, &who, Operation::GetTool, true).await
}

/// The form a thesis client posts to `/krl/uploadfile`.
#[derive(utoipa::ToSchema)]
#[allow(dead_code)] // documents the form; the handler reads the parts itself
pub struct UploadForm {
    /// The `.src` file.
    #[schema(value_type = String, format = Binary)]
    file: Vec<u8>,
}

/// Name under which `/krl/uploadfile` stores its upload.
const THESIS_PROGRAM: &str = "uploaded";

/// Uploads a KRL file and runs it (thesis method 10).
///
/// The body is the `.src` text, either as a `multipart/form-data` file part (the thesis
/// client's form upload: the part named `file`, else the first part with a file name) or as
/// the raw request body. The file
/// must define `DEFFCT INT fuploaded()` (the thesis convention) or its first routine is
/// run. It is checked before anything reaches the controller, stored as program
/// `uploaded`, written as a new module and run — every upload runs its own code, not the
/// first one. Answers when the program has ended.
#[utoipa::path(post, path = "/krl/uploadfile", tag = "thesis",
    request_body(description = "The .src text, raw or as a form's file part",
        content((String = "text/plain"), (UploadForm = "multipart/form-data"))),
    responses((status = 200, body = ThesisResponse), (status = "4XX", body = ThesisProblem, content_type = PROBLEM_JSON), (status = "5XX", body = ThesisProblem, content_type = PROBLEM_JSON)))]
async fn uploadfile(
    State(app): State<AppState>,
    who: Who,
    _: ThesisQuery<NoParams>,
    req: axum::extract::Request,
) -> Response {
    let src = match upload_text(&app, req).await {
        Ok(s) => s,
        Err(e) => return fail(&app, &e),
    };
    let upload = crate::programs::ProgramUpload {
        name: THESIS_PROGRAM.into(),
        src,
        dat: None,
        entry: None,
    };
    let program = match app.programs.put(upload) {
        Ok((p, _)) => p,
        Err(e) => return fail(&app, &e),
    };
    // Programs run longer than single motions: their own timeout.
    let timeout = app.programs.run_timeout();
    run_with(
        &app,
        &who,
        Operation::RunProgram(program),
        false,
        Some(timeout),
    )
    .await
}

/// The uploaded text from a multipart form (first field) or the raw body.
async fn upload_text(app: &AppState, req: axum::extract::Request) -> Result<String, BridgeError> {
    use axum::extract::FromRequest;
    let multipart = req
        .headers()
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.starts_with("multipart/form-data"));
    let bytes = if multipart {
        let form_error = |e: axum::extract::multipart::MultipartError| {
            if e.status() == axum::http::StatusCode::PAYLOAD_TOO_LARGE {
                BridgeError::new(ErrorCode::PayloadTooLarge, format!("multipart upload: {e}"))
            } else {
                BridgeError::invalid(format!("multipart upload: {e}"))
            }
        };
        let mut form = axum::extract::Multipart::from_request(req, app)
            .await
            .map_err(|e| BridgeError::invalid(format!("multipart upload: {e}")))?;
        // The file: the part named `file` (FastAPI's UploadFile parameter)
        // or else the first part that carries a file name; other form
        // fields are skipped.
        let mut found = None;
        while let Some(field) = form.next_field().await.map_err(form_error)? {
            if field.name() == Some("file") || field.file_name().is_some() {
                found = Some(field.bytes().await.map_err(form_error)?);
                break;
            }
        }
        found.ok_or_else(|| {
            BridgeError::invalid(
                "the form has no file part (send the .src as a field named `file`)",
            )
        })?
    } else {
        axum::body::to_bytes(req.into_body(), 4 * 1024 * 1024)
            .await
            .map_err(|e| BridgeError::new(ErrorCode::PayloadTooLarge, format!("upload: {e}")))?
    };
    if bytes.is_empty() {
        return Err(BridgeError::invalid(
            "the upload is empty: send the .src text",
        ));
    }
    Ok(crate::programs::decode_text(&bytes))
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(ptp))
        .routes(routes!(linmov))
        .routes(routes!(circ))
        .routes(routes!(getpos))
        .routes(routes!(base))
        .routes(routes!(tcp))
        .routes(routes!(gettcp))
        .routes(routes!(uploadfile))
}
