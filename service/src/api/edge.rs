//! The HTTP edge: the layers every request passes besides the access
//! layer. Outside it: request tracing without query strings, CORS when
//! configured, load shedding (a concurrency limit that answers 503 +
//! `Retry-After` instead of queueing, never for Stop or `/health`) and the
//! layer that turns bare error answers into problem documents. Inside it,
//! so that the audit trail records the outcome: the per-request time limit
//! and the body size limit (tower-http).

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

/// The time and body limits (applied inside the access layer).
pub fn inner_layers(router: Router<AppState>, server: &ServerConfig) -> Router<AppState> {
    router
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
        // HTTP layer only traces. The span names the path, never the query
        // string (it may carry `access_token`).
        .layer(
            TraceLayer::new_for_http()
                .make_span_with(|req: &axum::http::Request<_>| {
                    tracing::debug_span!("request", method = %req.method(), path = %req.uri().path())
                })
                .on_failure(
                    tower_http::trace::DefaultOnFailure::new().level(tracing::Level::DEBUG),
                ),
        )
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
        _ => (ErrorCode::InvalidInput, "the request was refused"),
    };
    let error = BridgeError::new(code, detail);
    let mut out = if thesis {
        super::thesis::fail_at(&error, [0.0; 6])
    } else {
        let body = super::problem::ProblemDetails::from_error(&error);
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
