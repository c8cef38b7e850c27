//! Digital I/O (`/api/v1/io`): `$IN`/`$OUT` as the controller's state file
//! reports them (live, no round trip), and writes of the outputs the site
//! allows (`[io] outputs`), by number or by name.

use axum::extract::{Path, State};
use axum::response::Response;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::auth::Who;
use super::problem::{JsonBody, PROBLEM_JSON, Problem, ProblemDetails};
use super::{AppState, ok_json};
use crate::engine::{Connection, Operation};
use crate::error::{BridgeError, ErrorCode};
use crate::io::{AnalogOutputRequest, IoKind, IoWindow, OutputRequest};

/// One digital signal and its value.
#[derive(Debug, Clone, Serialize, ToSchema)]
#[schema(example = json!({"kind": "output", "index": 1, "name": "gripper_close", "value": true, "writable": true}))]
pub struct Signal {
    /// Input or output.
    pub kind: IoKind,
    /// `$IN`/`$OUT` index.
    #[schema(minimum = 1, maximum = 4096)]
    pub index: u16,
    /// Its name in the site's `[io]` configuration.
    pub name: Option<String>,
    /// Its value: as the controller last reported it (a read), or as
    /// written (the answer to a write; the next state file, within a
    /// heartbeat, reports it).
    pub value: bool,
    /// Clients may write it (an output on the site's list).
    pub writable: bool,
}

/// The digital I/O the controller reports.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct IoView {
    /// Index of the first signal reported (the KRL program's `kb_io_base`).
    pub base: u16,
    /// Milliseconds since the service read the state file they come from.
    pub age_ms: Option<u64>,
    /// `$IN[base..base+30]`.
    pub inputs: Vec<Signal>,
    /// `$OUT[base..base+30]`.
    pub outputs: Vec<Signal>,
}

/// The body of an output write.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields, expecting = "an object such as {\"value\": true}")]
#[schema(example = json!({"value": true}))]
pub struct OutputWrite {
    /// The value to set.
    pub value: bool,
    /// Return to the other value after this many ms (0..=60000); default:
    /// the output's `pulse_ms` in the configuration (0: it stays).
    #[schema(maximum = 60000)]
    pub pulse_ms: Option<u32>,
}

/// The I/O window of the controller's last state file.
fn window(app: &AppState) -> Result<(IoWindow, Option<u64>), BridgeError> {
    let state = app.engine.state();
    if state.connection == Connection::Offline {
        return Err(BridgeError::new(
            ErrorCode::ControllerOffline,
            "the controller is offline (no heartbeat): its I/O is not known",
        ));
    }
    let age = state
        .position_read_at
        .map(|t| t.elapsed().as_millis() as u64);
    state.io.map(|w| (w, age)).ok_or_else(|| {
        BridgeError::new(
            ErrorCode::SignalNotReported,
            "the controller program reports no I/O (its state file has no IOS line: update the KRL program)",
        )
    })
}

fn signal(app: &AppState, w: &IoWindow, kind: IoKind, index: u16) -> Option<Signal> {
    let io = app.engine.io_config();
    Some(Signal {
        kind,
        index,
        name: io.name_of(kind, index).map(str::to_string),
        value: w.get(kind, index)?,
        writable: kind == IoKind::Output && io.writable(index).is_ok(),
    })
}

/// The digital inputs and outputs the controller reports.
///
/// Live from the controller's state file (its heartbeat, every 100 ms on the
/// shipped KRL program): 31 inputs and 31 outputs from `base` (the KRL
/// program's `kb_io_base`), with the names of the site's `[io]` configuration
/// and which outputs clients may write.
#[utoipa::path(get, path = "/api/v1/io", tag = "io",
    responses((status = 200, body = IoView),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_io(State(app): State<AppState>) -> Result<Response, Problem> {
    let (w, age_ms) = window(&app)?;
    let list = |kind| -> Vec<Signal> {
        (0..w.inputs.len() as u16)
            .filter_map(|k| signal(&app, &w, kind, w.base + k))
            .collect()
    };
    Ok(ok_json(&IoView {
        base: w.base,
        age_ms,
        inputs: list(IoKind::Input),
        outputs: list(IoKind::Output),
    }))
}

/// One signal, by number or configured name.
fn one(app: &AppState, kind: IoKind, name: &str) -> Result<Response, Problem> {
    let (index, _) = app.engine.io_config().resolve(kind, name)?;
    let (w, _) = window(app)?;
    let s = signal(app, &w, kind, index).ok_or_else(|| {
        BridgeError::new(
            ErrorCode::SignalNotReported,
            format!(
                "the controller reports {io}[{}..{}] only, not {io}[{index}] (the KRL program's kb_io_base)",
                w.base,
                w.base + w.inputs.len() as u16 - 1,
                io = kind.krl()
            ),
        )
    })?;
    Ok(ok_json(&s))
}

/// One digital input, by number or configured name.
///
/// `signal` is a number (1..=4096) or a name from the site's `[io]
/// inputs`. A signal outside what the controller reports (31 from its
/// `base`) is `signal_not_reported`.
#[utoipa::path(get, path = "/api/v1/io/inputs/{signal}", tag = "io",
    params(("signal" = String, Path, description = "A number (1..=4096) or a configured name")),
    responses((status = 200, body = Signal),
        (status = 404, description = "`unknown_signal`: no input has that name", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "`signal_not_reported`, or a number out of range", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_input(
    State(app): State<AppState>,
    Path(name): Path<String>,
) -> Result<Response, Problem> {
    one(&app, IoKind::Input, &name)
}

/// One digital output, by number or configured name.
///
/// As for inputs; `writable` says whether clients may set it.
#[utoipa::path(get, path = "/api/v1/io/outputs/{signal}", tag = "io",
    params(("signal" = String, Path, description = "A number (1..=4096) or a configured name")),
    responses((status = 200, body = Signal),
        (status = 404, description = "`unknown_signal`: no output has that name", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "`signal_not_reported`, or a number out of range", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_output(
    State(app): State<AppState>,
    Path(name): Path<String>,
) -> Result<Response, Problem> {
    one(&app, IoKind::Output, &name)
}

/// Set a digital output the site allows clients to write.
///
/// Only outputs listed in the site's `[io] outputs` may be written (by number
/// or name); any other is refused with 403 `output_not_allowed` and nothing
/// reaches the controller. Queued like every command: it runs after the
/// motions sent before it. `pulse_ms` returns the output to the other value
/// after that time. Answers the signal as set.
#[utoipa::path(put, path = "/api/v1/io/outputs/{signal}", tag = "io",
    params(("signal" = String, Path, description = "A number (1..=4096) or a configured name")),
    request_body = OutputWrite,
    responses((status = 200, body = Signal),
        (status = 403, description = "`output_not_allowed`: not on the site's list", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 404, description = "`unknown_signal`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "`invalid_input`: a number or value out of range, or a body of the wrong shape", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_output(
    State(app): State<AppState>,
    who: Who,
    Path(name): Path<String>,
    JsonBody(body): JsonBody<OutputWrite>,
) -> Result<Response, Problem> {
    let io = app.engine.io_config();
    let (index, _) = io.resolve(IoKind::Output, &name)?;
    let entry = io.writable(index)?;
    let pulse_ms = body.pulse_ms.unwrap_or(entry.pulse_ms);
    let op = Operation::SetOutput(OutputRequest {
        index,
        value: body.value,
        pulse_ms,
    });
    app.engine
        .execute(op, None, app.request_timeout, who.caller())
        .await?;
    Ok(ok_json(&Signal {
        kind: IoKind::Output,
        index,
        name: Some(entry.name.clone()),
        value: body.value,
        writable: true,
    }))
}

/// One analog channel and its value.
#[derive(Debug, Clone, Serialize, ToSchema)]
#[schema(example = json!({"index": 1, "name": "spindle_speed", "value": 0.5, "writable": true}))]
pub struct AnalogSignal {
    /// `$ANIN`/`$ANOUT` index.
    #[schema(minimum = 1, maximum = 32)]
    pub index: u8,
    /// Its name in the site's `[io]` configuration.
    pub name: Option<String>,
    /// Normalised value, −1..1 (±1 = the channel's full scale, ±10 V on
    /// the usual cards), 3 decimals: as last reported, or as written.
    pub value: f64,
    /// Clients may write it (an analog output on the site's list).
    pub writable: bool,
}

/// The analog I/O the controller reports.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct AnalogView {
    /// `$ANIN[1..8]`.
    pub inputs: Vec<AnalogSignal>,
    /// `$ANOUT[1..8]`.
    pub outputs: Vec<AnalogSignal>,
}

/// The body of an analog output write.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields, expecting = "an object such as {\"value\": 0.5}")]
#[schema(example = json!({"value": 0.5}))]
pub struct AnalogWrite {
    /// Normalised value, −1..=1; the protocol carries 3 decimals.
    #[schema(minimum = -1.0, maximum = 1.0)]
    pub value: f64,
}

fn analog_window(app: &AppState) -> Result<crate::io::AnalogWindow, BridgeError> {
    let state = app.engine.state();
    if state.connection == Connection::Offline {
        return Err(BridgeError::new(
            ErrorCode::ControllerOffline,
            "the controller is offline (no heartbeat): its I/O is not known",
        ));
    }
    state.analog.ok_or_else(|| {
        BridgeError::new(
            ErrorCode::SignalNotReported,
            "the controller program reports no analog I/O (its state file has no ANS line: update the KRL program)",
        )
    })
}

/// The analog inputs and outputs the controller reports.
///
/// `$ANIN[1..8]` and `$ANOUT[1..8]` from the controller's state file
/// (live, no round trip), normalised −1..1, with the names of the site's
/// `[io] analog_inputs`/`analog_outputs` and which outputs clients may
/// write.
#[utoipa::path(get, path = "/api/v1/io/analog", tag = "io",
    responses((status = 200, body = AnalogView),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_analog(State(app): State<AppState>) -> Result<Response, Problem> {
    let w = analog_window(&app)?;
    let io = app.engine.io_config();
    let list = |output: bool, values: &[f64]| -> Vec<AnalogSignal> {
        values
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let index = k as u8 + 1;
                let named = if output {
                    &io.analog_outputs
                } else {
                    &io.analog_inputs
                };
                AnalogSignal {
                    index,
                    name: named
                        .iter()
                        .find(|a| a.index == index)
                        .map(|a| a.name.clone()),
                    value: *v,
                    writable: output && io.analog_writable(index).is_ok(),
                }
            })
            .collect()
    };
    Ok(ok_json(&AnalogView {
        inputs: list(false, &w.inputs),
        outputs: list(true, &w.outputs),
    }))
}

/// One analog channel, by number or name, as the controller last reported
/// it (`output`: `$ANOUT`, else `$ANIN`).
fn analog_signal(app: &AppState, output: bool, signal: &str) -> Result<AnalogSignal, BridgeError> {
    let io = app.engine.io_config();
    let (index, name) = io.resolve_analog(output, signal)?;
    let w = analog_window(app)?;
    let values = if output { &w.outputs } else { &w.inputs };
    let kind = if output { "$ANOUT" } else { "$ANIN" };
    let value = *values.get(usize::from(index) - 1).ok_or_else(|| {
        BridgeError::new(
            ErrorCode::SignalNotReported,
            format!(
                "{kind}[{index}] is not reported: the controller reports channels 1..={} (read it as a variable: GET /api/v1/variables/{kind}%5B{index}%5D)",
                values.len()
            ),
        )
    })?;
    Ok(AnalogSignal {
        index,
        name: name.map(str::to_string),
        value,
        writable: output && io.analog_writable(index).is_ok(),
    })
}

/// One analog input, by number (1..=32) or configured name.
///
/// As the controller last reported it (channels 1..8; others:
/// `signal_not_reported`, read them with `GET /api/v1/variables/$ANIN[n]`).
#[utoipa::path(get, path = "/api/v1/io/analog-inputs/{signal}", tag = "io",
    params(("signal" = String, Path, description = "A number (1..=32) or a configured name")),
    responses((status = 200, body = AnalogSignal),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_analog_input(
    State(app): State<AppState>,
    Path(signal): Path<String>,
) -> Result<Response, Problem> {
    Ok(ok_json(&analog_signal(&app, false, &signal)?))
}

/// One analog output, by number (1..=32) or configured name.
#[utoipa::path(get, path = "/api/v1/io/analog-outputs/{signal}", tag = "io",
    params(("signal" = String, Path, description = "A number (1..=32) or a configured name")),
    responses((status = 200, body = AnalogSignal),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_analog_output(
    State(app): State<AppState>,
    Path(signal): Path<String>,
) -> Result<Response, Problem> {
    Ok(ok_json(&analog_signal(&app, true, &signal)?))
}

/// Set an analog output the site allows.
///
/// Only the analog outputs in `[io] analog_outputs` (by number 1..32 or
/// name); any other is refused with 403 `output_not_allowed` and nothing
/// reaches the controller. Queued like every command. The value is
/// normalised −1..1 and sent with 3 decimals.
#[utoipa::path(put, path = "/api/v1/io/analog-outputs/{signal}", tag = "io",
    params(("signal" = String, Path, description = "A number (1..=32) or a configured name")),
    request_body = AnalogWrite,
    responses((status = 200, body = AnalogSignal),
        (status = 403, description = "`output_not_allowed`: not on the site's list", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 404, description = "`unknown_signal`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "`invalid_input`: a number or value out of range, or a body of the wrong shape", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_analog_output(
    State(app): State<AppState>,
    who: Who,
    Path(name): Path<String>,
    JsonBody(body): JsonBody<AnalogWrite>,
) -> Result<Response, Problem> {
    let io = app.engine.io_config();
    let (index, _) = io.resolve_analog(true, &name)?;
    let entry = io.analog_writable(index)?;
    // (+ 0.0: no "-0.0" for a small negative value)
    let value = (body.value * 1000.0).round() / 1000.0 + 0.0;
    app.engine
        .execute(
            Operation::SetAnalogOutput(AnalogOutputRequest {
                index,
                value: body.value,
            }),
            None,
            app.request_timeout,
            who.caller(),
        )
        .await?;
    Ok(ok_json(&AnalogSignal {
        index,
        name: Some(entry.name.clone()),
        value,
        writable: true,
    }))
}

/// The site's I/O configuration now: named inputs, the outputs clients
/// may write (the allow-list), named analog channels, and which of them
/// publish events.
///
/// From the configuration file's `[io]`, or, once an admin has edited it
/// (`PUT`), from the copy the service keeps in its data folder
/// (`io.json`), which then replaces the file's until `DELETE`.
#[utoipa::path(get, path = "/api/v1/io/config", tag = "io",
    responses((status = 200, body = crate::io::IoConfig)))]
async fn get_io_config(State(app): State<AppState>) -> Response {
    ok_json(&*app.engine.io_config())
}

/// Replace the site's I/O configuration (admin): names, the outputs
/// clients may write, analog channels, watched signals.
///
/// Checked as at start (names, ranges, duplicates; 422 `invalid_input`
/// with the reason, nothing changed), then used at once for every request
/// that arrives afterwards (a job already queued keeps the signals it
/// resolved), and kept in the data folder (`io.json`, private) so that it
/// survives a restart; it replaces the configuration file's `[io]` until
/// `DELETE /api/v1/io/config`. The change is in the audit trail.
#[utoipa::path(put, path = "/api/v1/io/config", tag = "io",
    request_body = crate::io::IoConfig,
    responses((status = 200, description = "The configuration now in force", body = crate::io::IoConfig),
        (status = 422, body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 503, description = "It could not be stored (`storage_unavailable`); nothing changed", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_io_config(
    State(app): State<AppState>,
    JsonBody(io): JsonBody<crate::io::IoConfig>,
) -> Result<Response, Problem> {
    io.validate().map_err(BridgeError::invalid)?;
    // Stored first: a configuration that would not survive a restart is
    // not put in force.
    app.io_store.save(&io).map_err(|e| {
        tracing::error!(error = %e, "cannot store the I/O configuration");
        BridgeError::new(
            ErrorCode::StorageUnavailable,
            "the I/O configuration could not be stored in the data folder; nothing changed",
        )
    })?;
    app.engine.set_io_config(io).map_err(BridgeError::invalid)?;
    tracing::warn!("the I/O configuration was replaced over HTTP");
    Ok(ok_json(&*app.engine.io_config()))
}

/// Go back to the configuration file's `[io]` (admin): the stored copy is
/// removed and the file's configuration is in force at once.
#[utoipa::path(delete, path = "/api/v1/io/config", tag = "io",
    responses((status = 200, description = "The configuration file's `[io]`, now in force", body = crate::io::IoConfig),
        (status = 503, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn delete_io_config(State(app): State<AppState>) -> Result<Response, Problem> {
    let io = app.io_store.reset().map_err(|e| {
        tracing::error!(error = %e, "cannot remove the stored I/O configuration");
        BridgeError::new(
            ErrorCode::StorageUnavailable,
            "the stored I/O configuration could not be removed; nothing changed",
        )
    })?;
    app.engine.set_io_config(io).map_err(BridgeError::invalid)?;
    tracing::warn!("the I/O configuration is the configuration file's again");
    Ok(ok_json(&*app.engine.io_config()))
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(get_io_config, put_io_config, delete_io_config))
        .routes(routes!(get_analog))
        .routes(routes!(get_analog_output, put_analog_output))
        .routes(routes!(get_analog_input))
        .routes(routes!(get_io))
        .routes(routes!(get_input))
        .routes(routes!(get_output, put_output))
}
