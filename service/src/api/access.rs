//! Access endpoints: the control lease (`/api/v1/control`), token
//! management (`/api/v1/tokens`) and the audit trail (`/api/v1/audit`).
//! Who may call them is in `access::policy` like everything else.

use axum::extract::{Path, State};
use axum::response::Response;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::auth::Who;
use super::problem::{JsonBody, PROBLEM_JSON, Problem, ProblemDetails, QueryParams, json_response};
use super::{AppState, ok_json};
use crate::access::audit::{AuditQuery, AuditRecord};
use crate::access::{Lease, Principal, Role, TokenError, TokenInfo};
use crate::error::{BridgeError, ErrorCode};

/// Who holds control.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({"lease": null, "auth": true, "you": {"name": "line-3-pc", "role": "operator"}}))]
pub struct ControlState {
    /// The live lease, or null when no one holds control (then any
    /// operator may write).
    pub lease: Option<Lease>,
    /// Whether tokens are required (without them everyone is `anonymous`
    /// and control changes nothing).
    pub auth: bool,
    /// The caller: its token name and role (what it may do: see
    /// `x-required-role` on each operation).
    pub you: Principal,
}

/// Taking control.
#[derive(Debug, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"take_over": false}))]
pub struct ControlRequest {
    /// Admins only: take control even if another client holds it.
    #[serde(default)]
    pub take_over: bool,
}

/// A new token.
#[derive(Debug, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"name": "line-3-pc", "role": "operator"}))]
pub struct NewToken {
    /// Unique name: 1–64 letters, digits, `.`, `_`, `-`, `@`.
    pub name: String,
    /// Its role.
    pub role: Role,
}

/// A token just created: its secret is shown this once.
#[derive(Debug, Serialize, ToSchema)]
pub struct CreatedToken {
    /// The token.
    #[serde(flatten)]
    pub info: TokenInfo,
    /// The secret to send as `Authorization: Bearer <secret>`; not stored
    /// by the service (only its hash), so it cannot be shown again.
    pub secret: String,
}

fn control_state(app: &AppState, who: &Who) -> ControlState {
    ControlState {
        lease: app.access.control.current(),
        auth: app.access.enabled,
        you: who.principal().clone(),
    }
}

/// Who holds control of the robot, and who you are (token name and role).
#[utoipa::path(get, path = "/api/v1/control", tag = "access", responses((status = 200, body = ControlState)))]
async fn get_control(State(app): State<AppState>, who: Who) -> Response {
    ok_json(&control_state(&app, &who))
}

/// Take (or renew) control of the robot.
///
/// While you hold control, other clients' motions and settings are refused with 409
/// `control_held`; reads and stop are never refused. Every mutating call of yours renews
/// the lease; it lapses after `lease_ms` without one. An admin may `take_over`.
#[utoipa::path(post, path = "/api/v1/control", tag = "access", request_body(content = Option<ControlRequest>),
    responses((status = 200, body = ControlState),
        (status = 409, description = "Another client holds control", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn take_control(
    State(app): State<AppState>,
    who: Who,
    body: axum::body::Bytes,
) -> Result<Response, Problem> {
    let req: ControlRequest = if body.iter().all(u8::is_ascii_whitespace) {
        ControlRequest::default()
    } else {
        serde_json::from_slice(&body)
            .map_err(|e| BridgeError::invalid(format!("request body: {e}")))?
    };
    app.access.control.acquire(who.principal(), req.take_over)?;
    Ok(ok_json(&control_state(&app, &who)))
}

/// Release control (your own; an admin may release anyone's).
#[utoipa::path(delete, path = "/api/v1/control", tag = "access",
    responses((status = 200, body = ControlState),
        (status = 409, description = "Another client holds control", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn release_control(State(app): State<AppState>, who: Who) -> Result<Response, Problem> {
    app.access.control.release(who.principal())?;
    Ok(ok_json(&control_state(&app, &who)))
}

/// The client gets the sentence of a refusal; a storage failure (its path
/// and OS error) goes to the log only.
fn token_problem(e: TokenError) -> Problem {
    let code = match &e {
        TokenError::Exists(_) | TokenError::BadName(_) => ErrorCode::InvalidInput,
        TokenError::NotFound(_) => ErrorCode::NotFound,
        _ => {
            tracing::error!(error = %crate::error::chain(&e), "token store failed");
            return BridgeError::new(
                ErrorCode::Internal,
                "the token store could not be read or written; the service log has the cause",
            )
            .into();
        }
    };
    BridgeError::new(code, e.to_string()).into()
}

/// Tokens (names and roles, never secrets).
#[utoipa::path(get, path = "/api/v1/tokens", tag = "access", responses((status = 200, body = [TokenInfo])))]
async fn list_tokens(State(app): State<AppState>) -> Response {
    ok_json(&app.access.tokens.list())
}

/// Create a token; the answer holds its secret, shown only this once.
#[utoipa::path(post, path = "/api/v1/tokens", tag = "access", request_body = NewToken,
    responses((status = 201, body = CreatedToken),
        (status = "4XX", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn create_token(
    State(app): State<AppState>,
    who: Who,
    JsonBody(req): JsonBody<NewToken>,
) -> Result<Response, Problem> {
    let tokens = app.access.tokens.clone();
    let (info, secret) = tokio::task::spawn_blocking(move || tokens.create(&req.name, req.role))
        .await
        .map_err(|e| BridgeError::new(ErrorCode::Internal, e.to_string()))?
        .map_err(token_problem)?;
    tracing::info!(name = %info.name, role = %info.role, by = %who.principal().name, "token created");
    Ok(json_response(
        201,
        "application/json",
        &CreatedToken { info, secret },
    ))
}

/// Revoke a token; it is refused from the next request on.
#[utoipa::path(delete, path = "/api/v1/tokens/{name}", tag = "access",
    params(("name" = String, Path, description = "Token name")),
    responses((status = 200, body = TokenInfo),
        (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn revoke_token(
    State(app): State<AppState>,
    who: Who,
    Path(name): Path<String>,
) -> Result<Response, Problem> {
    let tokens = app.access.tokens.clone();
    let info = tokio::task::spawn_blocking(move || tokens.revoke(&name))
        .await
        .map_err(|e| BridgeError::new(ErrorCode::Internal, e.to_string()))?
        .map_err(token_problem)?;
    app.access.forget_revoked();
    tracing::info!(name = %info.name, by = %who.principal().name, "token revoked");
    Ok(ok_json(&info))
}

/// The audit trail: every mutating request, newest first.
#[utoipa::path(get, path = "/api/v1/audit", tag = "access", params(AuditQuery),
    responses((status = 200, body = [AuditRecord])))]
async fn get_audit(
    State(app): State<AppState>,
    QueryParams(q): QueryParams<AuditQuery>,
) -> Result<Response, Problem> {
    let records = app
        .access
        .audit
        .query(q)
        .await
        .map_err(|e| {
            tracing::error!(error = %e, "audit trail not read");
            BridgeError::new(
                ErrorCode::StorageUnavailable,
                "the service cannot read its audit trail; the service log (under this request's id) says why",
            )
        })?;
    Ok(ok_json(&records))
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(get_control, take_control, release_control))
        .routes(routes!(list_tokens, create_token))
        .routes(routes!(revoke_token))
        .routes(routes!(get_audit))
}
