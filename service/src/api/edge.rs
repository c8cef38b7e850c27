//! The HTTP edge: the layers every request passes besides the access
//! layer. Outside it: request tracing without query strings, CORS when
//! configured, load shedding (a concurrency limit that answers 503 +
//! `Retry-After` instead of queueing, never for Stop or `/health`) and the
//! layer that turns bare error answers into problem documents. Inside it,
//! so that the audit trail records the outcome: the per-request time limit,
//! the body size limit (tower-http) and the check that refuses query
//! parameters an operation does not declare.

use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use axum::extract::{MatchedPath, Request, State};
use axum::http::{HeaderValue, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::Response;
use tokio::sync::Semaphore;
use tower_http::cors::{AllowOrigin, CorsLayer};
use tower_http::limit::RequestBodyLimitLayer;
use tower_http::timeout::TimeoutLayer;
use tower_http::trace::TraceLayer;

use super::AppState;
use super::problem::PROBLEM_JSON;
use crate::config::ServerConfig;
use crate::error::{BridgeError, ErrorCode};

/// The query-parameter check, the time and body limits (applied inside
/// the access layer).
pub fn inner_layers(router: Router<AppState>, state: &AppState) -> Router<AppState> {
    let server = &state.server;
    router
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            known_query_parameters,
        ))
        .layer(TimeoutLayer::with_status_code(
            StatusCode::GATEWAY_TIMEOUT,
            Duration::from_millis(server.max_request_ms),
        ))
        .layer(RequestBodyLimitLayer::new(server.max_body_bytes))
}

/// Load shedding, CORS, problem bodies and tracing (outside the access layer).
pub fn outer_layers(router: Router<AppState>, server: &ServerConfig) -> Router<AppState> {
    let slots = Arc::new(Semaphore::new(server.max_concurrent_requests));
    let router = router.layer(axum::middleware::from_fn_with_state(slots, shed_load));
    let router = match cors(&server.cors_origins) {
        Some(c) => router.layer(c),
        None => router,
    };
    router
        .layer(axum::middleware::from_fn(problem_for_bare_errors))
        // Failed requests are logged where they fail, with their code; the
        // HTTP layer only traces. The span names the request id and the
        // path, never the query string (it may carry `access_token`); every
        // event logged while the request is served carries them.
        .layer(
            TraceLayer::new_for_http()
                .make_span_with(|req: &axum::http::Request<_>| {
                    let id = req
                        .extensions()
                        .get::<RequestId>()
                        .map_or("", |r| r.0.as_str());
                    tracing::info_span!("request", id = %id, method = %req.method(), path = %req.uri().path())
                })
                .on_request(())
                .on_response(())
                .on_body_chunk(())
                .on_eos(())
                .on_failure(
                    tower_http::trace::DefaultOnFailure::new().level(tracing::Level::DEBUG),
                ),
        )
        .layer(axum::middleware::from_fn(request_id))
}

/// A request's id: unique in this run and across restarts (the start
/// time, then a counter), in the `x-request-id` answer header and in the
/// `request_id` of every error body, and on every log line written while
/// the request is served.
#[derive(Debug, Clone)]
pub struct RequestId(pub String);

/// Largest error body the request id is added to (all of ours are far smaller).
const MAX_PROBLEM_BODY: usize = 64 * 1024;

/// Gives the request its id and puts it into the answer.
async fn request_id(mut req: Request, next: Next) -> Response {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(1);
    static STARTED: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    let started = *STARTED.get_or_init(|| crate::clock::now_ms() / 1000);
    let id = format!("{started:x}-{}", NEXT.fetch_add(1, Ordering::Relaxed));
    req.extensions_mut().insert(RequestId(id.clone()));
    let resp = next.run(req).await;
    let (mut parts, body) = resp.into_parts();
    if let Ok(v) = HeaderValue::from_str(&id) {
        parts.headers.insert("x-request-id", v);
    }
    let json_error = (parts.status.is_client_error() || parts.status.is_server_error())
        && parts
            .headers
            .get(header::CONTENT_TYPE)
            .and_then(|v| v.to_str().ok())
            .is_some_and(|v| v.contains("json"));
    if !json_error {
        return Response::from_parts(parts, body);
    }
    let Ok(bytes) = axum::body::to_bytes(body, MAX_PROBLEM_BODY).await else {
        return Response::from_parts(parts, axum::body::Body::empty());
    };
    let with_id = match serde_json::from_slice::<serde_json::Value>(&bytes) {
        Ok(serde_json::Value::Object(mut map)) => {
            map.insert("request_id".into(), serde_json::Value::String(id));
            serde_json::to_vec(&map).ok()
        }
        _ => None,
    };
    match with_id {
        Some(out) => {
            parts.headers.remove(header::CONTENT_LENGTH);
            Response::from_parts(parts, axum::body::Body::from(out))
        }
        None => Response::from_parts(parts, axum::body::Body::from(bytes)),
    }
}

/// At most `server.max_concurrent_requests` requests run at once; more are
/// refused at once with 503 `overloaded` + `Retry-After`. Stop and the
/// public routes (`/health`, documentation) are never refused: they are
/// cheap, and Stop must get through a full service. (A slot is held until
/// the answer's head is sent; an event stream does not hold one.)
async fn shed_load(State(slots): State<Arc<Semaphore>>, req: Request, next: Next) -> Response {
    let exempt = req.extensions().get::<MatchedPath>().is_none_or(|m| {
        let rule = crate::access::policy::rule(req.method().as_str(), m.as_str());
        rule.safety || rule.role.is_none()
    });
    if exempt {
        return next.run(req).await;
    }
    let Ok(_slot) = slots.try_acquire() else {
        let e = BridgeError::new(
            ErrorCode::Overloaded,
            "too many requests are in progress; retry after the Retry-After delay",
        );
        let mut r = super::routing_error_blind(req.uri(), e);
        r.headers_mut()
            .insert(header::RETRY_AFTER, HeaderValue::from_static("1"));
        return r;
    };
    next.run(req).await
}

/// Refuses a request with a query parameter its operation does not declare
/// in the OpenAPI document (`AppState::openapi`): 422 `invalid_input`
/// naming it and the ones the operation takes (in the thesis format on
/// `/krl/*`), before the handler runs. A typo (`?limt=5`, `?index=3` on an
/// endpoint without parameters) must not be ignored, on any endpoint.
///
/// `access_token` passes where the document declares it (`/krl/*` and
/// `/api/v1/events`, whose clients cannot always set headers; the access
/// layer has taken it out of the query already when it accepts it there).
/// The thesis endpoints also take their parameters in upper case (KUKA's
/// own spelling, `X=`). Plugin routes are checked against the plugin's own
/// schemas when they are called; routes outside the document (Swagger UI,
/// the dashboard's files, `/openapi.json`) are not checked.
async fn known_query_parameters(State(app): State<AppState>, req: Request, next: Next) -> Response {
    let Some(query) = req
        .uri()
        .query()
        .filter(|q| !q.is_empty())
        .map(str::to_string)
    else {
        return next.run(req).await;
    };
    let Some(template) = req
        .extensions()
        .get::<MatchedPath>()
        .map(|m| m.as_str().to_string())
    else {
        return next.run(req).await;
    };
    if template.starts_with("/api/v1/plugins/{name}/") {
        return next.run(req).await;
    }
    let method = match req.method().as_str() {
        "HEAD" => "get".to_string(),
        m => m.to_ascii_lowercase(),
    };
    let Some(operation) = app
        .openapi
        .get("paths")
        .and_then(|p| p.get(&template))
        .and_then(|item| item.get(&method))
    else {
        return next.run(req).await;
    };
    let declared: Vec<&str> = operation
        .get("parameters")
        .and_then(serde_json::Value::as_array)
        .into_iter()
        .flatten()
        .filter(|p| p["in"] == "query")
        .filter_map(|p| p["name"].as_str())
        .collect();
    let thesis = template.starts_with("/krl/");
    let pairs: Vec<(String, String)> = match serde_urlencoded::from_str(&query) {
        Ok(p) => p,
        Err(e) => {
            let e = BridgeError::invalid(format!("query string: {e}"));
            return super::routing_error(&app, req.uri(), e);
        }
    };
    let known = |name: &str| {
        declared.contains(&name)
            || (thesis
                && name.chars().all(|c| !c.is_ascii_lowercase())
                && declared.contains(&name.to_ascii_lowercase().as_str()))
    };
    let mut unknown: Vec<&str> = Vec::new();
    for (name, value) in &pairs {
        let blank = name.is_empty() && value.is_empty();
        if !blank && !known(name) && !unknown.contains(&name.as_str()) {
            unknown.push(name);
        }
    }
    if unknown.is_empty() {
        return next.run(req).await;
    }
    let e = BridgeError::invalid(unknown_parameters_sentence(
        req.method().as_str(),
        &template,
        &unknown,
        &declared,
        thesis,
    ));
    super::routing_error(&app, req.uri(), e)
}

/// `query parameter "index" is not known; GET /api/v1/tool takes no query
/// parameters`, or the ones it takes.
fn unknown_parameters_sentence(
    method: &str,
    template: &str,
    unknown: &[&str],
    declared: &[&str],
    thesis: bool,
) -> String {
    let names: Vec<String> = unknown.iter().map(|n| format!("{n:?}")).collect();
    let mut out = if names.len() == 1 {
        format!("query parameter {} is not known", names[0])
    } else {
        format!("query parameters {} are not known", names.join(", "))
    };
    if declared.is_empty() {
        out.push_str(&format!("; {method} {template} takes no query parameters"));
    } else {
        out.push_str(&format!(
            "; {method} {template} takes {}",
            declared.join(", ")
        ));
        if thesis && declared.iter().any(|d| *d != crate::access::QUERY_TOKEN) {
            out.push_str(" (coordinates also in upper case)");
        }
    }
    if unknown.contains(&crate::access::QUERY_TOKEN) {
        out.push_str(&format!(
            "; send the token in the Authorization header (`{}` is accepted only on /krl/* and /api/v1/events)",
            crate::access::QUERY_TOKEN
        ));
    }
    out
}

/// CORS for the configured origins; none configured: no CORS headers, so
/// browsers refuse cross-origin pages.
fn cors(origins: &[String]) -> Option<CorsLayer> {
    if origins.is_empty() {
        return None;
    }
    let list: Vec<HeaderValue> = origins
        .iter()
        .filter_map(|o| HeaderValue::from_str(o).ok())
        .collect();
    Some(
        CorsLayer::new()
            .allow_origin(AllowOrigin::list(list))
            .allow_methods([Method::GET, Method::POST, Method::PUT, Method::DELETE])
            .allow_headers([header::AUTHORIZATION, header::CONTENT_TYPE])
            .expose_headers([
                header::LOCATION,
                header::RETRY_AFTER,
                header::WWW_AUTHENTICATE,
            ]),
    )
}

/// The layers above (and hyper) answer some errors with an empty or
/// plain-text body: give them the problem body every other error has (in
/// the thesis format on `/krl/*`, with an unknown position).
async fn problem_for_bare_errors(req: Request, next: Next) -> Response {
    let thesis = req.uri().path().starts_with("/krl/");
    let resp = next.run(req).await;
    let status = resp.status();
    if !(status.is_client_error() || status.is_server_error()) {
        return resp;
    }
    let json = resp
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.contains("json"));
    if json {
        return resp;
    }
    let (code, detail) = match status {
        StatusCode::PAYLOAD_TOO_LARGE => (
            ErrorCode::PayloadTooLarge,
            "the request body is larger than the service accepts (server.max_body_bytes)",
        ),
        StatusCode::GATEWAY_TIMEOUT | StatusCode::REQUEST_TIMEOUT => (
            ErrorCode::RequestTimeout,
            "the request took longer than server.max_request_ms; a job it started goes on (see /api/v1/jobs)",
        ),
        StatusCode::SERVICE_UNAVAILABLE => (
            ErrorCode::Overloaded,
            "the service cannot take this request now; retry later",
        ),
        StatusCode::NOT_FOUND => (ErrorCode::NotFound, "no such resource; see /docs"),
        StatusCode::METHOD_NOT_ALLOWED => (
            ErrorCode::MethodNotAllowed,
            "this endpoint does not accept this HTTP method; see /docs",
        ),
        s if s.is_server_error() => (ErrorCode::Internal, "the service failed to answer"),
        StatusCode::BAD_REQUEST => (
            ErrorCode::InvalidInput,
            "the request is malformed (for example a path that is not valid UTF-8 after percent-decoding)",
        ),
        _ => (ErrorCode::InvalidInput, "the request was refused"),
    };
    let error = BridgeError::new(code, detail);
    let mut out = if thesis {
        super::thesis::fail_at(&error, [0.0; 6])
    } else {
        let mut body = super::problem::ProblemDetails::from_error(&error);
        // The body says the status the client gets (a bare 400 is not the code's 422).
        body.status = status.as_u16();
        super::problem::json_response(body.status, PROBLEM_JSON, &body)
    };
    *out.status_mut() = status;
    for (name, v) in resp.headers() {
        let keep = [header::RETRY_AFTER, header::WWW_AUTHENTICATE, header::ALLOW].contains(name)
            || name.as_str().starts_with("access-control-");
        if keep {
            out.headers_mut().insert(name.clone(), v.clone());
        }
    }
    out
}
