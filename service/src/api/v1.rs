//! The versioned JSON API under `/api/v1`: state, position, motions, jobs,
//! stop, home, reset, tool/base frames and speeds.

use std::time::Duration;

use axum::extract::{Path, State};
use axum::http::{HeaderValue, header};
use axum::response::Response;
use kuka_protocol::MAX_REAL;
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::auth::Who;
use super::problem::{JsonBody, PROBLEM_JSON, Problem, ProblemDetails, QueryParams, json_response};
use super::{AppState, ok_json};
use crate::engine::{
    AxisAngles, CartesianFrame, Job, JobId, JobState, Operation, Position, RobotState,
};
use crate::error::{BridgeError, ErrorCode};
use crate::motion::{Configuration, MotionRequest, SpeedSettings};

/// A motion request: one motion or a continuous batch.
#[derive(Debug, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({
    "motions": [
        {"type": "ptp", "target": {"x": 200, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0}},
        {"type": "lin", "target": {"z": 70}, "velocity_m_s": 0.1},
        {"type": "circ", "aux": {"x": 250, "y": 50}, "target": {"x": 200, "y": 100}, "approx_mm": 2},
        {"type": "lin", "target": {"z": 100}}
    ],
    "wait": true
}))]
pub struct MotionBatch {
    /// The motions, executed in order as one continuous batch (approximated
    /// between motions unless `approx_mm` is 0).
    pub motions: Vec<MotionRequest>,
    /// Wait for completion (default true). With false the answer is 202
    /// with the queued job; poll `/api/v1/jobs/{id}` or listen to events.
    pub wait: Option<bool>,
    /// Fail the job (and stop the robot) if it has not finished after this many ms.
    pub timeout_ms: Option<u64>,
    /// How the PTPs without `s` (and without their own `config`) get their
    /// arm configuration: `auto` (the bridge chooses) or `keep` (KUKA's
    /// rule). Default: the site's `motion.configuration` (`auto`).
    pub config: Option<Configuration>,
}

/// Position with axis angles.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({
    "position": {"x": 355.0, "y": 0.0, "z": 625.0, "a": 0.0, "b": 90.0, "c": 0.0, "s": 2, "t": 2},
    "axes": {"a1": 0.0, "a2": -90.0, "a3": 90.0, "a4": 0.0, "a5": 0.0, "a6": 0.0},
    "source": "controller", "age_ms": 0
}))]
pub struct PositionReport {
    /// TCP in the base frame with Status/Turn.
    pub position: Position,
    /// Axis angles.
    pub axes: Option<AxisAngles>,
    /// Where it comes from: `controller` (a GETPOS round trip through the
    /// controller program, while the robot stands) or `live` (while a job
    /// runs: the controller's newest state file, answered at once instead
    /// of waiting behind the motion).
    pub source: PositionSource,
    /// For `live`: milliseconds since the service read the state file that
    /// carried the position (the controller writes it every heartbeat,
    /// 100 ms in the shipped KRL program). 0 for `controller`.
    pub age_ms: u64,
}

/// Where a reported position comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum PositionSource {
    /// Read through the controller program (GETPOS).
    Controller,
    /// The controller's live state while a job runs.
    Live,
}

/// Partial update of the speed settings; omitted fields keep their value.
#[derive(Debug, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"override_pct": 50}))]
pub struct SpeedUpdate {
    /// Program override in %.
    pub override_pct: Option<f64>,
    /// Default PTP velocity in %.
    pub ptp_velocity_pct: Option<f64>,
    /// Default PTP acceleration in %.
    pub ptp_acceleration_pct: Option<f64>,
    /// Default LIN/CIRC velocity in m/s.
    pub cp_velocity_m_s: Option<f64>,
    /// Default LIN/CIRC acceleration in %.
    pub cp_acceleration_pct: Option<f64>,
}

/// Job list filter.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct JobsQuery {
    /// Most jobs returned, newest first (default 100, at most 1000).
    limit: Option<usize>,
}

/// Stop confirmation.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({"stopped": true}))]
pub struct Stopped {
    /// True once the controller confirmed the stop.
    pub stopped: bool,
}

/// The robot model the service checks motions against: enough to draw the
/// arm (a stick model from the OPW lengths and the axis angles of
/// `/api/v1/state`) and to show each axis against its software limits.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({
    "name": "kr3_r540",
    "opw_mm": {"a1": 20.0, "a2": -20.0, "b": 0.0, "c1": 345.0, "c2": 260.0, "c3": 260.0, "c4": 75.0},
    "limits_deg": [[-170.0, 170.0], [-170.0, 50.0], [-110.0, 155.0], [-175.0, 175.0], [-120.0, 120.0], [-350.0, 350.0]],
    "max_speed_deg_s": [530.0, 529.0, 538.0, 600.0, 600.0, 800.0],
    "max_acc_deg_s2": [300.0, 300.0, 300.0, 300.0, 300.0, 300.0],
    "home": [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]
}))]
pub struct ModelInfo {
    /// Model id (`kr3_r540`, ... or the custom model's name).
    pub name: String,
    /// OPW lengths in mm. Chain from the robot root (Z up): A1 turns about
    /// −Z; A2 sits at (a1, b, c1) in the A1 frame and turns about Y with the
    /// upper arm (c2) along Z at A2 = −90°; A3 turns about Y at the elbow;
    /// the forearm goes a2 along X then c3 along Z to the wrist; A4 turns
    /// about −Z, A5 about Y, A6 about −Z; the flange is c4 further along Z.
    pub opw_mm: OpwLengths,
    /// Software limit switches per axis A1..A6: `[negative, positive]` degrees.
    pub limits_deg: Vec<[f64; 2]>,
    /// Maximum axis speeds A1..A6 in deg/s.
    pub max_speed_deg_s: Vec<f64>,
    /// Axis accelerations A1..A6 at 100 % in deg/s² (what the dry run and
    /// the simulators plan with; an assumption unless the site set them).
    pub max_acc_deg_s2: Vec<f64>,
    /// Home position A1..A6 in degrees.
    pub home: Vec<f64>,
}

/// OPW lengths in mm (rs-opw-kinematics' names).
#[derive(Debug, Serialize, ToSchema)]
pub struct OpwLengths {
    /// A1 axis to A2 axis, horizontally.
    pub a1: f64,
    /// Elbow offset (A3 to forearm), negative on KUKA arms.
    pub a2: f64,
    /// Lateral offset.
    pub b: f64,
    /// Floor to A2 axis.
    pub c1: f64,
    /// Upper arm (A2 to A3).
    pub c2: f64,
    /// Forearm (A3 to wrist point).
    pub c3: f64,
    /// Wrist point to flange.
    pub c4: f64,
}

impl From<&kuka_kinematics::RobotModel> for ModelInfo {
    fn from(m: &kuka_kinematics::RobotModel) -> Self {
        let [a1, a2, b, c1, c2, c3, c4] = m.opw_mm;
        ModelInfo {
            name: m.name.clone(),
            opw_mm: OpwLengths {
                a1,
                a2,
                b,
                c1,
                c2,
                c3,
                c4,
            },
            limits_deg: m.limits_deg.iter().map(|&(lo, hi)| [lo, hi]).collect(),
            max_speed_deg_s: m.max_speed_deg_s.to_vec(),
            max_acc_deg_s2: m.max_acc_deg_s2.to_vec(),
            home: m.home.to_vec(),
        }
    }
}

/// Checks a frame's numbers.
pub(crate) fn check_frame(f: &CartesianFrame) -> Result<(), BridgeError> {
    for (name, v) in [
        ("x", f.x),
        ("y", f.y),
        ("z", f.z),
        ("a", f.a),
        ("b", f.b),
        ("c", f.c),
    ] {
        if !v.is_finite() || v.abs() > MAX_REAL {
            return Err(BridgeError::invalid(format!(
                "{name} = {} is not a finite number within ±{MAX_REAL}",
                crate::error::shown(v)
            )));
        }
    }
    Ok(())
}

async fn execute(app: &AppState, who: &Who, op: Operation) -> Result<Job, Problem> {
    Ok(app
        .engine
        .execute(op, None, app.request_timeout, who.caller())
        .await?)
}

/// Robot and controller state.
///
/// Served from the service's latest knowledge (heartbeat and results): connection
/// (online/offline/locked), controller status and errors, position with S/T, axes,
/// tool, base, speeds, the running job and the queue length. Cheap; no round trip.
#[utoipa::path(get, path = "/api/v1/state", tag = "robot", responses((status = 200, body = RobotState)))]
async fn get_state(State(app): State<AppState>) -> Response {
    ok_json(&app.engine.state())
}

/// The configured robot model: OPW geometry, software limits, axis speeds, home.
///
/// 404 `not_found` when the service runs without a model (`robot.model = "none"`).
#[utoipa::path(get, path = "/api/v1/model", tag = "robot",
    responses((status = 200, body = ModelInfo), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_model(State(app): State<AppState>) -> Result<Response, Problem> {
    let model = app.engine.safety().model().ok_or_else(|| {
        BridgeError::new(
            ErrorCode::NotFound,
            "no robot model is configured (robot.model = \"none\")",
        )
    })?;
    Ok(ok_json(&ModelInfo::from(model)))
}

/// Where the TCP may go: the workspace box, the floor and the keep-out zones.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({
    "box": {"x": [0.0, 500.0], "y": [-400.0, 400.0], "z": [20.0, 700.0]},
    "floor_z": 0.0,
    "keep_out": [{"name": "fixture", "x": [300.0, 400.0], "y": [-50.0, 50.0], "z": [0.0, 120.0]}]
}))]
pub struct WorkspaceInfo {
    /// The box the whole TCP path stays in (`[workspace]`), if configured.
    #[serde(rename = "box")]
    pub workspace: Option<crate::config::WorkspaceBox>,
    /// The TCP stays at or above this Z (`zones.floor_z`), if configured.
    pub floor_z: Option<f64>,
    /// Boxes the TCP must not enter (`zones.keep_out`).
    pub keep_out: Vec<crate::config::KeepOut>,
}

/// The workspace box, floor and keep-out zones every motion's swept path is
/// checked against (docs/CONFIGURATION.md); the dashboard draws them.
#[utoipa::path(get, path = "/api/v1/workspace", tag = "robot",
    responses((status = 200, body = WorkspaceInfo)))]
async fn get_workspace(State(app): State<AppState>) -> Response {
    let safety = app.engine.safety();
    ok_json(&WorkspaceInfo {
        workspace: safety.workspace().copied(),
        floor_z: safety.zones().floor_z,
        keep_out: safety.zones().keep_out.clone(),
    })
}

/// Current position. While the robot stands it is read through the controller
/// program (a round trip); while a job runs it comes at once from the controller's
/// live state (`source: live`, with its age) instead of waiting behind the motion;
/// a sample older than 500 ms is not used: the read waits up to 2 s for the next.
#[utoipa::path(get, path = "/api/v1/position", tag = "robot",
    responses((status = 200, body = PositionReport), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_position(State(app): State<AppState>, who: Who) -> Result<Response, Problem> {
    if let Some(live) = app
        .engine
        .live_position_within(kuka_engine::engine::LIVE_POSITION_WAIT)
        .await
    {
        return Ok(ok_json(&PositionReport {
            position: live.position,
            axes: live.axes,
            source: PositionSource::Live,
            age_ms: live.age.as_millis() as u64,
        }));
    }
    let job = execute(&app, &who, Operation::GetPosition).await?;
    let position = job
        .position
        .ok_or_else(|| BridgeError::new(ErrorCode::ProtocolError, "no position in the result"))?;
    Ok(ok_json(&PositionReport {
        position,
        axes: job.axes,
        source: PositionSource::Controller,
        age_ms: 0,
    }))
}

/// Execute motions (PTP, axis PTP, LIN, CIRC), one or a continuous batch.
///
/// Each request is validated (numbers, Status/Turn, speed caps, workspace box, and with a
/// robot model a dry run for reachability, software limits and singularities) before
/// anything is written; a rejected request moves nothing. Omitted coordinates keep the
/// previous target's value; `relative: true` adds to it. Requests are executed in arrival
/// order. With `wait` (default) the answer is the finished job; otherwise 202 and the
/// queued job with a `Location` header.
#[utoipa::path(post, path = "/api/v1/motions", tag = "motion", request_body = MotionBatch,
    responses(
        (status = 200, description = "Done", body = Job),
        (status = 202, description = "Queued (wait = false)", body = Job),
        (status = "4XX", description = "Rejected or failed; nothing moved for 422 before execution", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", description = "Controller offline, channel locked or timeout", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn post_motions(
    State(app): State<AppState>,
    who: Who,
    JsonBody(batch): JsonBody<MotionBatch>,
) -> Result<Response, Problem> {
    let timeout = batch.timeout_ms.map(Duration::from_millis);
    if timeout.is_some_and(|t| t.is_zero()) {
        return Err(BridgeError::invalid("timeout_ms must be positive").into());
    }
    let mut motions = batch.motions;
    if let Some(c) = batch.config {
        motions.iter_mut().for_each(|m| m.default_config(c));
    }
    let job = app
        .engine
        .submit(Operation::Move(motions), timeout, who.caller())
        .await?;
    if batch.wait == Some(false) {
        let mut r = json_response(202, "application/json", &job);
        if let Ok(v) = HeaderValue::from_str(&format!("/api/v1/jobs/{}", job.id)) {
            r.headers_mut().insert(header::LOCATION, v);
        }
        return Ok(r);
    }
    let job = app.engine.wait(job.id, app.wait_budget(timeout)).await?;
    job_outcome(job)
}

pub(super) fn job_outcome(job: Job) -> Result<Response, Problem> {
    match (job.state, &job.error) {
        (JobState::Done, _) => Ok(ok_json(&job)),
        (_, Some(e)) => Err(Problem {
            error: e.clone(),
            job_id: Some(job.id),
        }),
        _ => Err(Problem {
            error: BridgeError::new(
                ErrorCode::Timeout,
                format!(
                    "job {} has not finished yet; poll /api/v1/jobs/{}",
                    job.id, job.id
                ),
            ),
            job_id: Some(job.id),
        }),
    }
}

/// Recent jobs, newest first.
#[utoipa::path(get, path = "/api/v1/jobs", tag = "motion", params(JobsQuery), responses((status = 200, body = [Job])))]
async fn list_jobs(
    State(app): State<AppState>,
    QueryParams(q): QueryParams<JobsQuery>,
) -> Response {
    ok_json(&app.engine.jobs(q.limit.unwrap_or(100).min(1000)))
}

/// One job.
#[utoipa::path(get, path = "/api/v1/jobs/{id}", tag = "motion", params(("id" = u64, Path, description = "Job id")),
    responses((status = 200, body = Job), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_job(State(app): State<AppState>, Path(id): Path<String>) -> Result<Response, Problem> {
    Ok(ok_json(&app.engine.job(parse_id(&id)?)?))
}

fn parse_id(id: &str) -> Result<JobId, BridgeError> {
    id.parse()
        .map_err(|_| BridgeError::invalid(format!("job id {id:?} is not a number")))
}

/// Cancel a job: a queued job is removed, a running one is stopped (its state
/// becomes `cancelled` when the controller confirms). Finished jobs are returned unchanged.
#[utoipa::path(delete, path = "/api/v1/jobs/{id}", tag = "motion", params(("id" = u64, Path, description = "Job id")),
    responses((status = 200, body = Job), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn cancel_job(
    State(app): State<AppState>,
    Path(id): Path<String>,
) -> Result<Response, Problem> {
    Ok(ok_json(&app.engine.cancel(parse_id(&id)?).await?))
}

/// Stop: brake now, cancel the running job and every queued job.
///
/// Always accepted, also while the queue is full or a job runs.
#[utoipa::path(post, path = "/api/v1/stop", tag = "motion",
    responses((status = 200, body = Stopped), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn stop(State(app): State<AppState>) -> Result<Response, Problem> {
    app.engine.stop().await?;
    Ok(ok_json(&Stopped { stopped: true }))
}

/// PTP to the home position (the BCO run), with the default PTP speed.
#[utoipa::path(post, path = "/api/v1/home", tag = "motion",
    responses((status = 200, body = Job), (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn home(State(app): State<AppState>, who: Who) -> Result<Response, Problem> {
    Ok(ok_json(&execute(&app, &who, Operation::Home).await?))
}

/// Acknowledge a controller error state.
#[utoipa::path(post, path = "/api/v1/reset", tag = "robot",
    responses((status = 200, body = Job), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn reset(State(app): State<AppState>, who: Who) -> Result<Response, Problem> {
    Ok(ok_json(&execute(&app, &who, Operation::Reset).await?))
}

fn frame_of(job: &Job) -> Result<CartesianFrame, Problem> {
    Ok(job
        .frame
        .ok_or_else(|| BridgeError::new(ErrorCode::ProtocolError, "no frame in the result"))?)
}

/// The tool frame ($TOOL), read from the controller.
#[utoipa::path(get, path = "/api/v1/tool", tag = "robot",
    responses((status = 200, body = CartesianFrame), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_tool(State(app): State<AppState>, who: Who) -> Result<Response, Problem> {
    Ok(ok_json(&frame_of(
        &execute(&app, &who, Operation::GetTool).await?,
    )?))
}

/// Set the tool frame ($TOOL): the TCP relative to the flange.
#[utoipa::path(put, path = "/api/v1/tool", tag = "robot", request_body = CartesianFrame,
    responses((status = 200, body = CartesianFrame), (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_tool(
    State(app): State<AppState>,
    who: Who,
    JsonBody(frame): JsonBody<CartesianFrame>,
) -> Result<Response, Problem> {
    check_frame(&frame)?;
    Ok(ok_json(&frame_of(
        &execute(&app, &who, Operation::SetTool(frame)).await?,
    )?))
}

/// The base frame ($BASE), read from the controller.
#[utoipa::path(get, path = "/api/v1/base", tag = "robot",
    responses((status = 200, body = CartesianFrame), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_base(State(app): State<AppState>, who: Who) -> Result<Response, Problem> {
    Ok(ok_json(&frame_of(
        &execute(&app, &who, Operation::GetBase).await?,
    )?))
}

/// Set the base frame ($BASE) relative to the robot root; positions are given in it.
#[utoipa::path(put, path = "/api/v1/base", tag = "robot", request_body = CartesianFrame,
    responses((status = 200, body = CartesianFrame), (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_base(
    State(app): State<AppState>,
    who: Who,
    JsonBody(frame): JsonBody<CartesianFrame>,
) -> Result<Response, Problem> {
    check_frame(&frame)?;
    Ok(ok_json(&frame_of(
        &execute(&app, &who, Operation::SetBase(frame)).await?,
    )?))
}

/// Override and default speeds.
#[utoipa::path(get, path = "/api/v1/speed", tag = "robot", responses((status = 200, body = SpeedSettings)))]
async fn get_speed(State(app): State<AppState>) -> Response {
    ok_json(&app.engine.state().speed)
}

/// Change override and default speeds (partial update); sent to the controller.
#[utoipa::path(put, path = "/api/v1/speed", tag = "robot", request_body = SpeedUpdate,
    responses((status = 200, body = SpeedSettings), (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON), (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_speed(
    State(app): State<AppState>,
    who: Who,
    JsonBody(u): JsonBody<SpeedUpdate>,
) -> Result<Response, Problem> {
    let cur = app.engine.state().speed;
    let next = SpeedSettings {
        override_pct: u.override_pct.unwrap_or(cur.override_pct),
        ptp_velocity_pct: u.ptp_velocity_pct.unwrap_or(cur.ptp_velocity_pct),
        ptp_acceleration_pct: u.ptp_acceleration_pct.unwrap_or(cur.ptp_acceleration_pct),
        cp_velocity_m_s: u.cp_velocity_m_s.unwrap_or(cur.cp_velocity_m_s),
        cp_acceleration_pct: u.cp_acceleration_pct.unwrap_or(cur.cp_acceleration_pct),
    };
    execute(&app, &who, Operation::SetSpeed(next)).await?;
    Ok(ok_json(&app.engine.state().speed))
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(get_state))
        .routes(routes!(get_model))
        .routes(routes!(get_workspace))
        .routes(routes!(get_position))
        .routes(routes!(post_motions))
        .routes(routes!(list_jobs))
        .routes(routes!(get_job, cancel_job))
        .routes(routes!(stop))
        .routes(routes!(home))
        .routes(routes!(reset))
        .routes(routes!(get_tool, put_tool))
        .routes(routes!(get_base, put_base))
        .routes(routes!(get_speed, put_speed))
}
