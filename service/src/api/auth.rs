//! The access middleware: for each request, find the route's rule
//! (`access::policy`), identify the caller from its bearer token, check its
//! role and the control lease, run the request under its identity and write
//! the audit record. Failures answer 401 (with `WWW-Authenticate`), 403,
//! 409 `control_held` or 429 as problem+json (thesis format on `/krl/*`).

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::extract::{ConnectInfo, MatchedPath, Request, State};
use axum::http::{HeaderValue, header};
use axum::middleware::Next;
use axum::response::Response;
use http_body_util::BodyExt;

use super::AppState;
use crate::access::{self, Principal, QUERY_TOKEN, RequestContext, Role, audit};
use crate::error::{BridgeError, ErrorCode};

/// The caller of the request being served, as this middleware put it in
/// the request's extensions: handlers pass it with every submission (its
/// [`RequestContext::caller`]), and the audit record reads the jobs it
/// created from the same context, also when the client went away first.
#[derive(Clone)]
pub(super) struct Who(pub Arc<RequestContext>);

impl Who {
    /// The engine's caller for this request.
    pub(super) fn caller(&self) -> crate::engine::Caller {
        self.0.caller()
    }

    /// The principal.
    pub(super) fn principal(&self) -> &Principal {
        &self.0.principal
    }
}

impl<S: Send + Sync> axum::extract::FromRequestParts<S> for Who {
    type Rejection = super::problem::Problem;

    async fn from_request_parts(
        parts: &mut axum::http::request::Parts,
        _: &S,
    ) -> Result<Self, Self::Rejection> {
        parts
            .extensions
            .get::<Arc<RequestContext>>()
            .cloned()
            .map(Who)
            .ok_or_else(|| {
                tracing::error!(path = %parts.uri.path(), "request without an identity: the access layer did not run");
                BridgeError::new(ErrorCode::Internal, "the request has no identity").into()
            })
    }
}

/// Largest JSON body read for the audit record (bigger ones are refused
/// here as they would be by the handler).
const MAX_AUDITED_JSON: usize = 2 << 20;

/// One request as the audit trail describes it.
struct Call {
    method: String,
    uri: axum::http::Uri,
    template: String,
    client: Option<std::net::IpAddr>,
    time_ms: u64,
    started: Instant,
}

impl Call {
    fn record(
        &self,
        who: &Principal,
        params: serde_json::Value,
        jobs: Vec<crate::engine::JobId>,
        status: u16,
        code: Option<String>,
    ) -> audit::AuditRecord {
        audit::AuditRecord {
            time_ms: self.time_ms,
            who: who.name.clone(),
            role: who.role,
            client: self
                .client
                .map_or_else(|| "unknown".into(), |c| c.to_string()),
            method: self.method.clone(),
            path: self.uri.path().to_string(),
            route: self.template.clone(),
            params,
            jobs,
            status,
            code,
            duration_ms: self.started.elapsed().as_secs_f64() * 1000.0,
        }
    }
}

/// The middleware (installed on every route by `api::app`).
pub async fn guard(State(app): State<AppState>, req: Request, next: Next) -> Response {
    let Some(template) = req
        .extensions()
        .get::<MatchedPath>()
        .map(|m| m.as_str().to_string())
    else {
        // No route: the 404/405 fallbacks answer without identifying anyone.
        return next.run(req).await;
    };
    let mut req = req;
    let query_secret = if query_token_allowed(&app, &template) {
        take_query_token(&mut req)
    } else {
        QuerySecret::Absent
    };
    let rule = access::policy::rule(req.method().as_str(), &template);
    let Some(needed) = rule.role else {
        return next.run(req).await;
    };
    let call = Call {
        method: req.method().as_str().to_string(),
        uri: req.uri().clone(),
        template,
        client: req
            .extensions()
            .get::<ConnectInfo<SocketAddr>>()
            .map(|c| c.0.ip()),
        time_ms: crate::engine::now_ms(),
        started: Instant::now(),
    };
    if !app.access.enabled
        && let Some(why) = cross_site(&req, &app.server.cors_origins)
    {
        let e = BridgeError::new(ErrorCode::Forbidden, why);
        return refused(&app, &call, rule.audited, &Principal::anonymous(), e).await;
    }
    let principal = match identify(&app, &req, query_secret, call.client, rule.safety) {
        Ok(p) => p,
        Err(resp) => return *resp,
    };
    if principal.role < needed {
        let e = BridgeError::new(
            ErrorCode::Forbidden,
            format!(
                "{} {} needs the {needed} role; token {:?} is {}",
                call.method,
                call.uri.path(),
                principal.name,
                article(principal.role)
            ),
        );
        return refused(&app, &call, rule.audited, &principal, e).await;
    }
    // Held while the call runs: a long motion of the holder keeps its lease.
    let _in_use = if rule.control {
        match app.access.control.check(&principal) {
            Ok(guard) => guard,
            Err(e) => return refused(&app, &call, rule.audited, &principal, e).await,
        }
    } else {
        None
    };
    let ctx = RequestContext::new(principal);
    req.extensions_mut().insert(ctx.clone());
    if !rule.audited {
        return next.run(req).await;
    }
    let body_time = Duration::from_millis(app.server.header_timeout_ms);
    let (req, params) = match audit_params(req, body_time).await {
        Ok(v) => v,
        Err(e) => {
            // Refused while reading the body: on record too.
            let code = e.code.as_str().to_string();
            let resp = super::routing_error(&app, &call.uri, e);
            let params = audit::params(call.uri.query(), None, &[], None);
            let record = call.record(
                &ctx.principal,
                params,
                Vec::new(),
                resp.status().as_u16(),
                Some(code),
            );
            app.access.audit.record(&record);
            return resp;
        }
    };
    let mut unanswered = Unanswered {
        app: app.clone(),
        call,
        ctx: ctx.clone(),
        params: Some(params),
    };
    let response = next.run(req).await;
    let (response, code) = problem_code(response).await;
    unanswered.write(response.status().as_u16(), code);
    response
}

/// HTTP status recorded for a request whose client went away before the
/// answer (nginx's "client closed request").
const CLIENT_CLOSED: u16 = 499;

/// The audit record of a request being served. When the client goes away
/// first, the server drops the request's future and this with it: the
/// record is then written on drop, with status 499, code
/// `client_disconnected` and the jobs started so far (they run on), so a
/// motion is on record even if nobody waited for its answer.
struct Unanswered {
    app: AppState,
    call: Call,
    ctx: Arc<RequestContext>,
    params: Option<serde_json::Value>,
}

impl Unanswered {
    /// Writes the record (once).
    fn write(&mut self, status: u16, code: Option<String>) {
        if let Some(params) = self.params.take() {
            let record =
                self.call
                    .record(&self.ctx.principal, params, self.ctx.jobs(), status, code);
            self.app.access.audit.record(&record);
        }
    }
}

impl Drop for Unanswered {
    fn drop(&mut self) {
        if self.params.is_some() {
            tracing::warn!(who = %self.ctx.principal.name, path = %self.call.uri.path(), jobs = ?self.ctx.jobs(), "client went away before the answer");
            self.write(CLIENT_CLOSED, Some("client_disconnected".into()));
        }
    }
}

fn article(role: Role) -> &'static str {
    match role {
        Role::Viewer => "a viewer",
        Role::Operator => "an operator",
        Role::Admin => "an admin",
    }
}

/// May this route take the token from the query string?
fn query_token_allowed(app: &AppState, template: &str) -> bool {
    app.access.query_token && (template.starts_with("/krl/") || template == "/api/v1/events")
}

/// The `access_token` query parameter(s) of a request.
enum QuerySecret {
    /// None given.
    Absent,
    /// Exactly one.
    One(String),
    /// More than one: refused like several `Authorization` headers (which
    /// one a proxy or client library keeps is anybody's guess).
    Several,
}

/// Removes `access_token` from the query string (handlers never see it)
/// and returns it.
fn take_query_token(req: &mut Request) -> QuerySecret {
    take_query_tokens(req).unwrap_or(QuerySecret::Absent)
}

fn take_query_tokens(req: &mut Request) -> Option<QuerySecret> {
    let query = req.uri().query()?;
    let pairs: Vec<(String, String)> = serde_urlencoded::from_str(query).ok()?;
    let (token, rest): (Vec<_>, Vec<_>) = pairs.into_iter().partition(|(k, _)| k == QUERY_TOKEN);
    let secret = match token.len() {
        0 => return None,
        1 => QuerySecret::One(token.into_iter().next()?.1),
        _ => QuerySecret::Several,
    };
    let rest = serde_urlencoded::to_string(&rest).ok()?;
    let path = req.uri().path();
    let path_and_query = if rest.is_empty() {
        path.to_string()
    } else {
        format!("{path}?{rest}")
    };
    let mut parts = req.uri().clone().into_parts();
    parts.path_and_query = path_and_query.parse().ok();
    *req.uri_mut() = axum::http::Uri::from_parts(parts).ok()?;
    Some(secret)
}

/// Without tokens (loopback only) any web page the operator's browser
/// opens could otherwise drive the robot: a cross-site form or `fetch`
/// needs no CORS to *send* a request, and DNS rebinding turns a foreign
/// name into 127.0.0.1. So a request must name this machine by a loopback
/// name or address (`Host`), and a browser's state-changing request must
/// come from this service's own pages (`Origin` = this host) or from a
/// configured `server.cors_origins` entry. Clients that send no `Origin`
/// (curl, scripts, the thesis's clients) are not affected.
fn cross_site(req: &Request, cors_origins: &[String]) -> Option<String> {
    let host = req
        .headers()
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .map(str::to_string)
        .or_else(|| req.uri().authority().map(|a| a.as_str().to_string()));
    if let Some(host) = &host
        && !is_loopback_host(host)
    {
        return Some(format!(
            "without access tokens the service answers only to loopback names (localhost, 127.0.0.1, [::1]), not {host:?}; use one of those or turn tokens on"
        ));
    }
    let reads = matches!(req.method().as_str(), "GET" | "HEAD" | "OPTIONS");
    let origin = req
        .headers()
        .get(header::ORIGIN)?
        .to_str()
        .unwrap_or("null");
    if reads || cors_origins.iter().any(|o| o == origin) {
        return None;
    }
    let same = host.is_some_and(|h| {
        origin
            .split_once("://")
            .is_some_and(|(_, rest)| rest.eq_ignore_ascii_case(&h))
    });
    (!same).then(|| {
        format!(
            "a page from {origin} may not change the robot (cross-site request); only this service's own pages and server.cors_origins may"
        )
    })
}

/// `localhost`, a loopback IP literal, with or without a port.
fn is_loopback_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        Some(v6) => v6.split(']').next().unwrap_or_default(),
        None => host.rsplit_once(':').map_or(host, |(n, _)| n),
    };
    name.eq_ignore_ascii_case("localhost")
        || name
            .parse::<std::net::IpAddr>()
            .is_ok_and(|ip| ip.is_loopback())
}

/// The caller, or the 401/429 answer. `safety` (Stop) is never refused by
/// the failed-attempt limiter: a valid token stops the robot even from an
/// address that guessed wrong (a shared HMI PC, a NAT).
fn identify(
    app: &AppState,
    req: &Request,
    query_secret: QuerySecret,
    client: Option<std::net::IpAddr>,
    safety: bool,
) -> Result<Principal, Box<Response>> {
    if !app.access.enabled {
        return Ok(Principal::anonymous());
    }
    let uri = req.uri();
    let query_secret = match query_secret {
        QuerySecret::Absent => None,
        QuerySecret::One(s) => Some(s),
        QuerySecret::Several => {
            return Err(Box::new(unauthenticated(
                uri,
                "send one access_token parameter, not several",
                Challenge::InvalidRequest,
            )));
        }
    };
    let mut headers = req.headers().get_all(header::AUTHORIZATION).iter();
    let from_header = headers.next().map(|v| v.to_str().unwrap_or_default());
    if headers.next().is_some() {
        return Err(Box::new(unauthenticated(
            uri,
            "send one Authorization header, not several",
            Challenge::InvalidRequest,
        )));
    }
    if from_header.is_some() && query_secret.is_some() {
        return Err(Box::new(unauthenticated(
            uri,
            "send the token once: in the Authorization header or as access_token, not both",
            Challenge::InvalidRequest,
        )));
    }
    let secret = match from_header {
        Some(h) => {
            let mut parts = h.splitn(2, ' ');
            let scheme = parts.next().unwrap_or_default();
            let value = parts.next().unwrap_or_default().trim();
            if !scheme.eq_ignore_ascii_case("bearer") || value.is_empty() {
                return Err(Box::new(unauthenticated(
                    uri,
                    "the Authorization header must be `Bearer <token>`",
                    Challenge::InvalidRequest,
                )));
            }
            Some(value.to_string())
        }
        None => query_secret,
    };
    let Some(secret) = secret else {
        return Err(Box::new(unauthenticated(
            uri,
            "this endpoint needs a token: send `Authorization: Bearer <token>` (see /docs, Authorize)",
            Challenge::Missing,
        )));
    };
    let client_text = client.map_or_else(|| "unknown".to_string(), |c| c.to_string());
    let locked_out = client.and_then(|ip| app.access.limiter.check(ip).err());
    if let Some(wait) = locked_out.filter(|_| !safety) {
        return Err(Box::new(too_many_attempts(uri, &client_text, wait)));
    }
    match app.access.tokens.verify(&secret) {
        Some(t) => Ok(Principal {
            name: t.name,
            role: t.role,
        }),
        // Stop from a locked-out address with a wrong token: refused like
        // everything else from there (no extra guesses, no log line).
        None if let Some(wait) = locked_out => {
            Err(Box::new(too_many_attempts(uri, &client_text, wait)))
        }
        None => {
            if let Some(ip) = client {
                app.access.limiter.fail(ip);
            }
            tracing::warn!(client = %client_text, path = %uri.path(), "request with an unknown or revoked token");
            Err(Box::new(unauthenticated(
                uri,
                "the token is unknown or was revoked",
                Challenge::InvalidToken,
            )))
        }
    }
}

/// 429 for an address locked out by the failed-attempt limiter.
fn too_many_attempts(uri: &axum::http::Uri, client: &str, wait: u64) -> Response {
    let e = BridgeError::new(
        ErrorCode::TooManyAttempts,
        format!("too many failed token attempts from {client}; try again in {wait} s"),
    );
    let mut resp = super::routing_error_blind(uri, e);
    if let Ok(v) = HeaderValue::from_str(&wait.to_string()) {
        resp.headers_mut().insert(header::RETRY_AFTER, v);
    }
    resp
}

/// What the `WWW-Authenticate` challenge says (RFC 6750 §3.1).
enum Challenge {
    /// No credentials: just the scheme.
    Missing,
    /// A malformed header.
    InvalidRequest,
    /// A token that is not (or no longer) valid.
    InvalidToken,
}

/// 401, without the robot's position in a thesis answer (the caller is
/// nobody yet).
fn unauthenticated(uri: &axum::http::Uri, detail: &str, challenge: Challenge) -> Response {
    let e = BridgeError::new(ErrorCode::Unauthenticated, detail);
    let mut resp = super::routing_error_blind(uri, e);
    let challenge = match challenge {
        Challenge::Missing => r#"Bearer realm="kuka-bridge""#,
        Challenge::InvalidRequest => r#"Bearer realm="kuka-bridge", error="invalid_request""#,
        Challenge::InvalidToken => r#"Bearer realm="kuka-bridge", error="invalid_token""#,
    };
    resp.headers_mut().insert(
        header::WWW_AUTHENTICATE,
        HeaderValue::from_static(challenge),
    );
    resp
}

/// Answers a refused request (403, 409) and records it when the route is
/// audited: refusals of identified callers are part of the trail.
async fn refused(
    app: &AppState,
    call: &Call,
    audited: bool,
    principal: &Principal,
    e: BridgeError,
) -> Response {
    let code = e.code.as_str().to_string();
    let resp = super::routing_error(app, &call.uri, e);
    if audited {
        let params = audit::params(call.uri.query(), None, &[], None);
        let record = call.record(
            principal,
            params,
            Vec::new(),
            resp.status().as_u16(),
            Some(code),
        );
        app.access.audit.record(&record);
    }
    resp
}

/// Reads a JSON body, or a small form or text one, to record it and puts
/// it back; other bodies are passed on untouched and recorded by size.
async fn audit_params(
    req: Request,
    body_time: Duration,
) -> Result<(Request, serde_json::Value), BridgeError> {
    let content_type = req
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .map(str::to_string);
    let size = req
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.parse::<u64>().ok());
    let query = req.uri().query().map(str::to_string);
    let json = content_type.as_deref().is_some_and(audit::is_json);
    // `curl -d` without a content type sends a form: a plugin reads it as
    // its JSON text anyway, so small ones are recorded too.
    let small_text = content_type.as_deref().is_none_or(audit::is_text)
        && size.is_some_and(|n| n > 0 && n <= audit::MAX_RECORDED_BODY as u64);
    if !json && !small_text {
        let params = audit::params(query.as_deref(), content_type.as_deref(), &[], size);
        return Ok((req, params));
    }
    let (parts, body) = req.into_parts();
    let read = http_body_util::Limited::new(body, MAX_AUDITED_JSON).collect();
    let bytes = tokio::time::timeout(body_time, read)
        .await
        .map_err(|_| {
            BridgeError::new(
                ErrorCode::RequestTimeout,
                format!(
                    "the JSON body did not arrive within {} s (server.header_timeout_ms)",
                    body_time.as_secs_f64()
                ),
            )
        })?
        .map_err(|e| {
            BridgeError::new(
                ErrorCode::PayloadTooLarge,
                format!("request body: {e} (at most {MAX_AUDITED_JSON} bytes of JSON)"),
            )
        })?
        .to_bytes();
    let params = audit::params(query.as_deref(), content_type.as_deref(), &bytes, None);
    Ok((
        Request::from_parts(parts, axum::body::Body::from(bytes)),
        params,
    ))
}

/// The problem code of an error answer (reads and restores its body).
async fn problem_code(resp: Response) -> (Response, Option<String>) {
    let is_problem = resp.headers().get(header::CONTENT_TYPE).is_some_and(|v| {
        v.as_bytes()
            .starts_with(super::problem::PROBLEM_JSON.as_bytes())
    });
    if resp.status().as_u16() < 400 {
        return (resp, None);
    }
    if !is_problem {
        // Bare answers of the body and time limits (made problems later).
        let code = match resp.status().as_u16() {
            413 => Some(ErrorCode::PayloadTooLarge),
            504 | 408 => Some(ErrorCode::RequestTimeout),
            _ => None,
        };
        return (resp, code.map(|c| c.as_str().to_string()));
    }
    let (parts, body) = resp.into_parts();
    let Ok(collected) = http_body_util::Limited::new(body, 1 << 20).collect().await else {
        return (Response::from_parts(parts, axum::body::Body::empty()), None);
    };
    let bytes = collected.to_bytes();
    let code = serde_json::from_slice::<serde_json::Value>(&bytes)
        .ok()
        .and_then(|v| v.get("code").and_then(|c| c.as_str()).map(str::to_string));
    (
        Response::from_parts(parts, axum::body::Body::from(bytes)),
        code,
    )
}

/// Writes the access rules into an OpenAPI document: the bearer scheme
/// (Swagger UI's Authorize button), and per operation its `security`, its
/// role (`x-required-role`), whether it needs control (`x-needs-control`),
/// a sentence in its description and the 401/403/409/429 answers it may
/// give. Idempotent (operations already marked are left alone).
pub(super) fn document(doc: &mut serde_json::Value) {
    use serde_json::{Value, json};
    let problem = json!({"content": {super::problem::PROBLEM_JSON: {"schema": {"$ref": "#/components/schemas/ProblemDetails"}}}});
    let answer = |description: &str| {
        let mut a = problem.clone();
        a["description"] = Value::String(description.into());
        a
    };
    doc["components"]["securitySchemes"]["bearer"] = json!({
        "type": "http",
        "scheme": "bearer",
        "description": "A token from `kuka-bridge token create --name NAME --role viewer|operator|admin` \
            (or POST /api/v1/tokens). Needed when the service listens beyond loopback or runs with \
            --require-auth."
    });
    doc["security"] = json!([{"bearer": []}]);
    let Some(paths) = doc.get_mut("paths").and_then(Value::as_object_mut) else {
        return;
    };
    for (path, item) in paths.iter_mut() {
        let Some(item) = item.as_object_mut() else {
            continue;
        };
        for (method, op) in item.iter_mut() {
            if op.get("x-required-role").is_some() {
                continue;
            }
            let Some(rule) = access::policy::documented_rule(method, path) else {
                continue;
            };
            // Any operation may be refused at the edge (malformed input,
            // body too large, overloaded, time limit): say so.
            let responses = &mut op["responses"];
            if responses.get("4XX").is_none() {
                responses["4XX"] = answer(
                    "Refused: invalid input (`invalid_input`), body too large, wrong media type, not found, …",
                );
            }
            if responses.get("5XX").is_none() {
                responses["5XX"] = answer(
                    "Failed or not started: `overloaded` (with Retry-After), `request_timeout`, controller errors, …",
                );
            }
            let Some(role) = rule.role else {
                op["security"] = json!([]);
                op["x-required-role"] = Value::String("none".into());
                continue;
            };
            op["security"] = json!([{"bearer": []}]);
            if path.starts_with("/krl/") || path == "/api/v1/events" {
                let param = json!({
                    "name": QUERY_TOKEN, "in": "query", "required": false,
                    "schema": {"type": "string"},
                    "description": "The token, for clients that cannot set headers (weaker than \
                        the header: URLs are logged by proxies and kept in histories; see docs/SECURITY.md)"
                });
                match op.get_mut("parameters").and_then(Value::as_array_mut) {
                    Some(list) => list.push(param),
                    None => op["parameters"] = json!([param]),
                }
            }
            op["x-required-role"] = Value::String(role.as_str().into());
            op["x-needs-control"] = Value::Bool(rule.control);
            let mut note = format!("\n\n**Access:** role `{role}` or higher");
            if rule.control {
                note.push_str(
                    "; refused with 409 `control_held` while another client holds control",
                );
            }
            note.push('.');
            let text = op
                .get("description")
                .and_then(Value::as_str)
                .unwrap_or_default()
                .to_string();
            op["description"] = Value::String(format!("{text}{note}"));
            let responses = &mut op["responses"];
            responses["401"] = answer("No token, or an unknown or revoked one (`unauthenticated`)");
            responses["403"] = answer("The token's role is too low (`forbidden`)");
            responses["429"] =
                answer("Too many failed token attempts from this address (`too_many_attempts`)");
            if rule.control && responses.get("409").is_none() {
                responses["409"] = answer(
                    "Another client holds control (`control_held`), or the controller refused",
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::is_loopback_host;

    #[test]
    fn loopback_hosts() {
        for h in [
            "localhost",
            "LOCALHOST:8080",
            "127.0.0.1",
            "127.0.0.1:80",
            "[::1]:8080",
            "[::1]",
            "127.3.4.5:9",
        ] {
            assert!(is_loopback_host(h), "{h}");
        }
        for h in [
            "evil.example",
            "evil.example:8080",
            "10.0.0.1:8080",
            "localhost.evil.example",
            "[::2]:80",
            "",
        ] {
            assert!(!is_loopback_host(h), "{h}");
        }
    }
}
