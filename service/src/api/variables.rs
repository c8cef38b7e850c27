//! KRL variables (`/api/v1/variables/{name}`): any variable the controller
//! has, read by name through KUKAVARPROXY as typed JSON; writes only to the
//! site's allow-list (`[variables] writable`). docs/VARIABLES.md.

use axum::extract::{Path, State};
use axum::response::Response;
use serde::Deserialize;
use utoipa::ToSchema;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::auth::Who;
use super::problem::{JsonBody, NoBody, PROBLEM_JSON, Problem, ProblemDetails};
use super::{AppState, ok_json};
use crate::engine::{CartesianFrame, Operation};
use crate::error::{BridgeError, ErrorCode};
use crate::variables::Variable;

/// The body of a variable write.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields, expecting = "an object such as {\"value\": 42}")]
#[schema(example = json!({"value": 50}))]
pub struct VariableWrite {
    /// The new value: a number, a boolean, a string (printable ASCII
    /// without `"`, at most 128), `{"enum": "NAME"}`, or an object of
    /// components (`{"X": 0, "Y": 0, "Z": 120}` sets those of a FRAME).
    #[schema(value_type = Value)]
    pub value: serde_json::Value,
}

/// Read a KRL variable by name.
///
/// Any variable the controller has: system variables (`$OV_PRO`,
/// `$POS_ACT`, `$MODE_OP`, `$OUT[3]`), a component (`$POS_ACT.X`), table
/// entries (`TOOL_DATA[3]`) and globals of loaded modules. Read through the
/// controller's KUKAVARPROXY server (`[variables] proxy`; with
/// `--simulate` the simulator's stand-in). The value comes as typed JSON
/// with its KRL type and text. Indices in the URL: percent-encode `[`
/// and `]` (`TOOL_DATA%5B3%5D`), or use `curl -g`.
#[utoipa::path(get, path = "/api/v1/variables/{name}", tag = "variables",
    params(("name" = String, Path, description = "A KRL variable name, e.g. $OV_PRO, $POS_ACT.X, TOOL_DATA[3]")),
    responses((status = 200, body = Variable),
        (status = 404, description = "`unknown_variable`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "`invalid_input`: not a variable name", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 503, description = "`variables_unavailable`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_variable(
    State(app): State<AppState>,
    Path(name): Path<String>,
) -> Result<Response, Problem> {
    Ok(ok_json(&app.variables.read(&name).await?))
}

/// Write a KRL variable on the site's allow-list.
///
/// Only names in `[variables] writable` (else 403 `variable_not_allowed`,
/// nothing sent). The value is typed JSON, turned into KRL text by the
/// service; an operator's token and the control lease are needed; every
/// write is audited. Answers the value the controller reports afterwards.
#[utoipa::path(put, path = "/api/v1/variables/{name}", tag = "variables",
    params(("name" = String, Path, description = "A KRL variable name on the allow-list")),
    request_body = VariableWrite,
    responses((status = 200, body = Variable),
        (status = 403, description = "`variable_not_allowed`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 404, description = "`unknown_variable`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "`invalid_input`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 503, description = "`variables_unavailable`", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn put_variable(
    State(app): State<AppState>,
    _who: Who,
    Path(name): Path<String>,
    JsonBody(body): JsonBody<VariableWrite>,
) -> Result<Response, Problem> {
    Ok(ok_json(&app.variables.write(&name, &body.value).await?))
}

/// An entry of the controller's tool or base table.
#[derive(Debug, Clone, serde::Serialize, ToSchema)]
#[schema(example = json!({"table": "TOOL_DATA", "number": 3, "name": "gripper", "frame": {"x": 0.0, "y": 0.0, "z": 120.0, "a": 0.0, "b": 0.0, "c": 0.0}}))]
pub struct TableEntry {
    /// `TOOL_DATA` or `BASE_DATA`.
    pub table: &'static str,
    /// The entry's number (tools 1..=16, bases 1..=32).
    pub number: u32,
    /// Its name as the teach pendant shows it (`TOOL_NAME[n,]`,
    /// `BASE_NAME[n,]`, trailing blanks removed); `null` when the
    /// controller has none to read or the entry is unnamed.
    pub name: Option<String>,
    /// The frame it holds.
    pub frame: CartesianFrame,
}

/// Which table: its KRL name, its names' array, and its size.
fn table(tool: bool) -> (&'static str, &'static str, u32) {
    if tool {
        ("TOOL_DATA", "TOOL_NAME", 16)
    } else {
        ("BASE_DATA", "BASE_NAME", 32)
    }
}

/// The name of table entry `number` (`TOOL_NAME[3,]`), if the controller
/// has one: a missing names array or an empty name is no name, never an
/// error (the frame is what a client needs).
async fn entry_name(app: &AppState, names: &str, number: u32) -> Option<String> {
    match app.variables.read(&format!("{names}[{number},]")).await {
        Ok(v) => v
            .value
            .as_str()
            .map(|s| s.trim_end().to_string())
            .filter(|s| !s.is_empty()),
        Err(e) => {
            tracing::debug!(names, number, error = %e, "no table entry name");
            None
        }
    }
}

/// Reads entry `number` of a table as a frame.
async fn entry(app: &AppState, tool: bool, number: &str) -> Result<TableEntry, BridgeError> {
    let (name, names, size) = table(tool);
    let number: u32 = number
        .parse()
        .ok()
        .filter(|n| (1..=size).contains(n))
        .ok_or_else(|| {
            BridgeError::invalid(format!(
                "{name} has the entries 1..={size}, not {:?}",
                crate::io::clip(number, 12)
            ))
        })?;
    let v = app.variables.read(&format!("{name}[{number}]")).await?;
    let f = |k: &str| v.value.get(k).and_then(serde_json::Value::as_f64);
    let frame = match (f("X"), f("Y"), f("Z"), f("A"), f("B"), f("C")) {
        (Some(x), Some(y), Some(z), Some(a), Some(b), Some(c)) => {
            CartesianFrame { x, y, z, a, b, c }
        }
        _ => {
            tracing::warn!(krl = %v.krl, "a table entry that is not a FRAME");
            return Err(BridgeError::new(
                ErrorCode::ProtocolError,
                format!("{name}[{number}] is not a FRAME on this controller"),
            ));
        }
    };
    Ok(TableEntry {
        table: name,
        number,
        name: entry_name(app, names, number).await,
        frame,
    })
}

/// Read an entry of the controller's tool table (`TOOL_DATA[1..16]`).
///
/// Read through KUKAVARPROXY like every variable (503
/// `variables_unavailable` without one). Write entries with
/// `PUT /api/v1/variables/TOOL_DATA[n]` where the site allows it.
#[utoipa::path(get, path = "/api/v1/tools/{number}", tag = "variables",
    params(("number" = u32, Path, minimum = 1, maximum = 16)),
    responses((status = 200, body = TableEntry),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_tool_entry(
    State(app): State<AppState>,
    Path(number): Path<String>,
) -> Result<Response, Problem> {
    Ok(ok_json(&entry(&app, true, &number).await?))
}

/// Make a tool table entry the active tool ($TOOL = TOOL_DATA[n]).
///
/// Reads the entry and sets it as the tool frame (as `PUT /api/v1/tool`
/// does, queued like every command): positions are reported for the new
/// TCP from then on. Answers the entry.
#[utoipa::path(post, path = "/api/v1/tools/{number}/select", tag = "variables",
    params(("number" = u32, Path, minimum = 1, maximum = 16)),
    responses((status = 200, body = TableEntry),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn select_tool(
    State(app): State<AppState>,
    who: Who,
    Path(number): Path<String>,
    _: NoBody,
) -> Result<Response, Problem> {
    select(&app, &who, true, &number).await
}

/// Read an entry of the controller's base table (`BASE_DATA[1..32]`).
#[utoipa::path(get, path = "/api/v1/bases/{number}", tag = "variables",
    params(("number" = u32, Path, minimum = 1, maximum = 32)),
    responses((status = 200, body = TableEntry),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_base_entry(
    State(app): State<AppState>,
    Path(number): Path<String>,
) -> Result<Response, Problem> {
    Ok(ok_json(&entry(&app, false, &number).await?))
}

/// Make a base table entry the active base ($BASE = BASE_DATA[n]).
#[utoipa::path(post, path = "/api/v1/bases/{number}/select", tag = "variables",
    params(("number" = u32, Path, minimum = 1, maximum = 32)),
    responses((status = 200, body = TableEntry),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = "5XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn select_base(
    State(app): State<AppState>,
    who: Who,
    Path(number): Path<String>,
    _: NoBody,
) -> Result<Response, Problem> {
    select(&app, &who, false, &number).await
}

async fn select(app: &AppState, who: &Who, tool: bool, number: &str) -> Result<Response, Problem> {
    let e = entry(app, tool, number).await?;
    super::v1::check_frame(&e.frame)?;
    let op = if tool {
        Operation::SetTool(e.frame)
    } else {
        Operation::SetBase(e.frame)
    };
    app.engine
        .execute(op, None, app.request_timeout, who.caller())
        .await?;
    Ok(ok_json(&e))
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(get_variable, put_variable))
        .routes(routes!(get_tool_entry))
        .routes(routes!(select_tool))
        .routes(routes!(get_base_entry))
        .routes(routes!(select_base))
}
