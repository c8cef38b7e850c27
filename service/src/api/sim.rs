//! Simulator endpoints (only in `--simulate` mode): the executed TCP trace
//! and the simulated clock, for tests, benchmarks and the dashboard.

use axum::extract::State;
use axum::response::Response;
use serde::Deserialize;
use utoipa::IntoParams;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::problem::{PROBLEM_JSON, Problem, ProblemDetails, QueryParams};
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

fn sim(app: &AppState) -> Result<&kuka_sim::SimController, Problem> {
    app.sim.as_deref().ok_or_else(|| {
        let detail = if app.krc.is_some() {
            "the KRC-like runtime (`--simulate krc`) keeps no trace yet: the simulator endpoints serve the native simulator (`--simulate native`)"
        } else {
            "the service is not running the simulated controller (start it with `run --simulate`)"
        };
        BridgeError::new(ErrorCode::NotFound, detail).into()
    })
}

/// The simulated controller: model, simulated clock, axes, last command id.
#[utoipa::path(get, path = "/api/v1/sim", tag = "simulator",
    responses((status = 200, description = "Simulator snapshot (`sim_time_s` is simulated seconds spent moving)", body = kuka_sim::SimSnapshot), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn snapshot(State(app): State<AppState>) -> Result<Response, Problem> {
    Ok(ok_json(&sim(&app)?.snapshot()))
}

/// The executed TCP trace: `{t, cid, motion, pose: [x,y,z,a,b,c], axes}` per IPO sample (12 ms).
#[utoipa::path(get, path = "/api/v1/sim/trace", tag = "simulator", params(TraceQuery),
    responses((status = 200, description = "Trace samples, oldest first", body = [kuka_sim::TraceSample]), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn trace(
    State(app): State<AppState>,
    QueryParams(q): QueryParams<TraceQuery>,
) -> Result<Response, Problem> {
    let since = q.since.unwrap_or(f64::NEG_INFINITY);
    let samples = sim(&app)?.trace_since(since);
    Ok(ok_json(&samples))
}

/// Clear the trace.
#[utoipa::path(delete, path = "/api/v1/sim/trace", tag = "simulator",
    responses((status = 204, description = "Cleared"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn clear_trace(State(app): State<AppState>) -> Result<axum::http::StatusCode, Problem> {
    sim(&app)?.clear_trace();
    Ok(axum::http::StatusCode::NO_CONTENT)
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(snapshot))
        .routes(routes!(trace, clear_trace))
}
