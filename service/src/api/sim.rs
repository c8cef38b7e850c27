//! Simulator endpoints (only in `--simulate` mode): the executed TCP trace
//! and the simulated clock, for tests, benchmarks and the dashboard.

use axum::extract::State;
use axum::response::Response;
use kuka_protocol::AcknowledgeRefused;
use serde::Deserialize;
use utoipa::{IntoParams, ToSchema};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::problem::{JsonBody, PROBLEM_JSON, Problem, ProblemDetails, QueryParams};
use super::{AppState, ok_json};
use crate::error::{BridgeError, ErrorCode};

/// Trace filter.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct TraceQuery {
    /// Only samples with simulated time `t` greater than this (seconds).
    /// A motion to where the robot already is adds a sample with the same
    /// `t` as the one before: to poll without missing one, pass a little
    /// less than the last `t` you have and drop repeats.
    since: Option<f64>,
}

/// The simulated controller the service embeds, whichever kind.
enum Simulated<'a> {
    /// `--simulate native`.
    Native(&'a kuka_sim::SimController),
    /// `--simulate krc`: the shipped KRL program in the KRC-like runtime.
    Krc(&'a kuka_krc::KrcController),
}

fn sim(app: &AppState) -> Result<Simulated<'_>, Problem> {
    if let Some(sim) = app.sim.as_deref() {
        return Ok(Simulated::Native(sim));
    }
    if let Some(krc) = app.krc.as_deref() {
        return Ok(Simulated::Krc(krc));
    }
    Err(BridgeError::new(
        ErrorCode::NotFound,
        "the service is not running the simulated controller (start it with `run --simulate`)",
    )
    .into())
}

/// The KRC-like runtime's trace in the simulator endpoints' form. Its
/// clock is the controller's (standstill counts), its motion index the
/// KRL program's `kb_busy_idx`.
fn krc_sample(s: &kuka_krc::KrcTraceSample) -> kuka_sim::TraceSample {
    kuka_sim::TraceSample {
        t: s.t,
        cid: i32::try_from(s.cid).unwrap_or(0),
        motion: s.motion,
        pose: s.pose,
        axes: s.axes,
        stop: s.stop,
    }
}

/// The simulated controller: model, simulated clock, axes, last command id.
#[utoipa::path(get, path = "/api/v1/sim", tag = "simulator",
    responses((status = 200, description = "Simulator snapshot. `sim_time_s`: the native simulator counts seconds spent moving, the KRC-like runtime (`--simulate krc`) its controller clock (`$ROB_TIMER`, standstill included); either way it is the clock of the trace's `t`", body = kuka_sim::SimSnapshot), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn snapshot(State(app): State<AppState>) -> Result<Response, Problem> {
    match sim(&app)? {
        Simulated::Native(sim) => Ok(ok_json(&sim.snapshot())),
        Simulated::Krc(krc) => {
            let s = krc.snapshot();
            let int = |name: &str| {
                krc.int_variable(name)
                    .and_then(|v| i32::try_from(v).ok())
                    .unwrap_or(0)
            };
            let model = app
                .engine
                .safety()
                .model()
                .map_or_else(String::new, |m| m.name.clone());
            Ok(ok_json(&kuka_sim::SimSnapshot {
                model,
                sim_time_s: s.time_ms as f64 / 1000.0,
                axes: s.axes,
                pose: s.pose,
                last_cid: int("kb_last_cid"),
                busy: int("kb_run_cid") != 0,
                heartbeats: int("kb_seq"),
            }))
        }
    }
}

/// The executed TCP trace: `{t, cid, motion, pose: [x,y,z,a,b,c], axes, stop}` per sample (native: IPO step of 12 ms; krc: interpreter cycle, which may record one pose twice and then move two steps, so take speeds over several samples); `stop` marks where the robot stands still.
#[utoipa::path(get, path = "/api/v1/sim/trace", tag = "simulator", params(TraceQuery),
    responses((status = 200, description = "Trace samples, oldest first", body = [kuka_sim::TraceSample]), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn trace(
    State(app): State<AppState>,
    QueryParams(q): QueryParams<TraceQuery>,
) -> Result<Response, Problem> {
    let since = q.since.unwrap_or(f64::NEG_INFINITY);
    let samples = match sim(&app)? {
        Simulated::Native(sim) => sim.trace_since(since),
        Simulated::Krc(krc) => krc.trace_since(since).iter().map(krc_sample).collect(),
    };
    Ok(ok_json(&samples))
}

/// Clear the trace.
#[utoipa::path(delete, path = "/api/v1/sim/trace", tag = "simulator",
    responses((status = 204, description = "Cleared"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn clear_trace(State(app): State<AppState>) -> Result<axum::http::StatusCode, Problem> {
    match sim(&app)? {
        Simulated::Native(sim) => sim.clear_trace(),
        Simulated::Krc(krc) => krc.clear_trace(),
    }
    Ok(axum::http::StatusCode::NO_CONTENT)
}

/// The operator acknowledges the controller's stop message, switches the
/// drives on and (KRC-like runtime) starts the bridge's program again.
///
/// After a safety stop (`PUT /api/v1/sim/safety`) or an error stop (a
/// program that failed, a motion stopped on its path) a KRC waits for the
/// operator: the message is acknowledged on the teach pendant (or by the
/// PLC), the drives are switched on and `kb_main` selected and started
/// again. Until then the state reports `controller_error` ("not ready").
/// This does what the operator would, on the simulated controller. A job
/// the stop ended leaves the controller in its error state until
/// `POST /api/v1/reset`, as on a KRC. 409 `controller_error` while the
/// emergency stop is still pressed or the operator safety still open.
#[utoipa::path(post, path = "/api/v1/sim/acknowledge", tag = "simulator",
    responses((status = 204, description = "Acknowledged; drives on (and kb_main restarted on the KRC-like runtime)"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON), (status = 409, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn acknowledge(State(app): State<AppState>) -> Result<axum::http::StatusCode, Problem> {
    let acknowledged = match sim(&app)? {
        Simulated::Native(sim) => sim.acknowledge(),
        Simulated::Krc(krc) => krc.acknowledge(),
    };
    match acknowledged {
        Ok(()) => Ok(axum::http::StatusCode::NO_CONTENT),
        Err(AcknowledgeRefused::EmergencyStop) => Err(BridgeError::new(
            ErrorCode::ControllerError,
            "the emergency stop is still pressed: release it first (PUT /api/v1/sim/safety {\"emergency_stop\": false})",
        )
        .into()),
        Err(AcknowledgeRefused::UserSafety) => Err(BridgeError::new(
            ErrorCode::ControllerError,
            "the operator safety is still open: close it first (PUT /api/v1/sim/safety {\"user_safety\": true})",
        )
        .into()),
    }
}

/// A change of the simulated cell's safety circuit.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "an object such as {\"emergency_stop\": true}"
)]
#[schema(example = json!({"emergency_stop": true}))]
pub struct SafetyChange {
    /// Press (`true`) or release (`false`) the emergency stop
    /// (`$ALARM_STOP`); absent: unchanged.
    #[serde(default)]
    pub emergency_stop: Option<bool>,
    /// Close (`true`) or open (`false`) the operator safety: the fence
    /// door, the enabling device (`$USER_SAF`); absent: unchanged.
    #[serde(default)]
    pub user_safety: Option<bool>,
}

/// Press or release the simulated emergency stop, open or close the
/// operator safety (`--simulate` only; either simulator).
///
/// Opening the circuit does what a KRC does: the robot stops where it is
/// (here without a braking distance), the drives switch off, a stop
/// message appears, the running job fails with `controller_error` and
/// every motion is refused until the operator acknowledges
/// (`POST /api/v1/sim/acknowledge`) — which a KRC allows only once the
/// circuit is closed again — and, if a job was ended, `POST
/// /api/v1/reset`. `GET /api/v1/state` shows it in `controller.safety`.
#[utoipa::path(put, path = "/api/v1/sim/safety", tag = "simulator",
    request_body = SafetyChange,
    responses((status = 204, description = "Changed"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON), (status = 422, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_safety(
    State(app): State<AppState>,
    JsonBody(v): JsonBody<SafetyChange>,
) -> Result<axum::http::StatusCode, Problem> {
    if v.emergency_stop.is_none() && v.user_safety.is_none() {
        return Err(BridgeError::invalid(
            "nothing to change: give emergency_stop, user_safety or both",
        )
        .into());
    }
    match sim(&app)? {
        Simulated::Native(sim) => sim.set_safety(v.emergency_stop, v.user_safety),
        Simulated::Krc(krc) => krc.set_safety(v.emergency_stop, v.user_safety),
    }
    tracing::warn!(
        emergency_stop = ?v.emergency_stop,
        user_safety = ?v.user_safety,
        "simulated safety circuit changed"
    );
    Ok(axum::http::StatusCode::NO_CONTENT)
}

/// The value of a simulated digital input.
#[derive(Debug, Clone, serde::Deserialize, utoipa::ToSchema)]
#[serde(deny_unknown_fields, expecting = "an object such as {\"value\": true}")]
#[schema(example = json!({"value": true}))]
pub struct InputValue {
    /// `$IN[index]`.
    pub value: bool,
}

/// Set a digital input of the simulated controller (`$IN[index]`, 1..=4096,
/// or an input's name from the site's `[io]`), as the plant would: a part-present sensor, a button. The controller
/// reports it in its next state file (`GET /api/v1/io`).
#[utoipa::path(put, path = "/api/v1/sim/inputs/{index}", tag = "simulator",
    params(("index" = String, Path, description = "1..=4096, or an input's name from the site's [io] configuration")),
    request_body = InputValue,
    responses((status = 204, description = "Set"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON), (status = 422, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_input(
    State(app): State<AppState>,
    axum::extract::Path(index): axum::extract::Path<String>,
    JsonBody(v): JsonBody<InputValue>,
) -> Result<axum::http::StatusCode, Problem> {
    // A number, or an input name from the site's [io] configuration.
    let index: u16 = match index.parse::<u16>() {
        Ok(i) if (1..=kuka_protocol::MAX_IO_INDEX).contains(&i) => i,
        _ if index.starts_with(|c: char| c.is_ascii_lowercase()) => {
            app.engine
                .io_config()
                .resolve(crate::io::IoKind::Input, &index)?
                .0
        }
        _ => {
            return Err(BridgeError::invalid(format!(
                "$IN[{}] does not exist: a simulated input is given by its number, 1..={}, or its name",
                crate::io::clip(&index, 24),
                kuka_protocol::MAX_IO_INDEX
            ))
            .into());
        }
    };
    let set = match sim(&app)? {
        Simulated::Native(sim) => sim.set_input(index, v.value),
        Simulated::Krc(krc) => krc.set_bool_element("$IN", i64::from(index), v.value),
    };
    if set {
        Ok(axum::http::StatusCode::NO_CONTENT)
    } else {
        Err(BridgeError::new(
            ErrorCode::NotFound,
            format!("the simulated controller has no $IN[{index}]"),
        )
        .into())
    }
}

/// The body of a simulated analog input.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields, expecting = "an object such as {\"value\": 0.25}")]
#[schema(example = json!({"value": 0.25}))]
pub struct AnalogInputValue {
    /// `$ANIN[index]`, normalised −1..=1.
    #[schema(minimum = -1.0, maximum = 1.0)]
    pub value: f64,
}

/// Set an analog input of the simulated controller (`$ANIN[index]`,
/// 1..=32, or an analog input's name from the site's `[io]`), as a sensor
/// would; the next state file reports it (`GET /api/v1/io/analog`).
#[utoipa::path(put, path = "/api/v1/sim/analog-inputs/{index}", tag = "simulator",
    params(("index" = String, Path, description = "1..=32, or an analog input's name from the site's [io] configuration")),
    request_body = AnalogInputValue,
    responses((status = 204, description = "Set"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON), (status = 422, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_analog_input(
    State(app): State<AppState>,
    axum::extract::Path(index): axum::extract::Path<String>,
    JsonBody(v): JsonBody<AnalogInputValue>,
) -> Result<axum::http::StatusCode, Problem> {
    // A number, or an analog input's name from the site's [io].
    let (index, _) = app.engine.io_config().resolve_analog(false, &index)?;
    if !(v.value.is_finite() && (-1.0..=1.0).contains(&v.value)) {
        return Err(BridgeError::invalid(format!(
            "value = {} is not between -1 and 1 (the normalised analog range)",
            kuka_engine::error::shown(v.value)
        ))
        .into());
    }
    let set = match sim(&app)? {
        Simulated::Native(sim) => sim.set_analog_input(index, v.value),
        Simulated::Krc(krc) => krc
            .write_krl(&format!("$ANIN[{index}]"), &format!("{:.6}", v.value))
            .is_ok(),
    };
    if set {
        Ok(axum::http::StatusCode::NO_CONTENT)
    } else {
        Err(BridgeError::new(
            ErrorCode::NotFound,
            format!("the simulated controller has no $ANIN[{index}]"),
        )
        .into())
    }
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(snapshot))
        .routes(routes!(trace, clear_trace))
        .routes(routes!(acknowledge))
        .routes(routes!(put_safety))
        .routes(routes!(put_input))
        .routes(routes!(put_analog_input))
}
