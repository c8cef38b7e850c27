//! The HTTP edge: the tower layers every request passes before any handler
//! (request tracing without query strings, CORS when configured, a
//! concurrency limit that sheds load with 503 + `Retry-After`, a
//! per-request time limit and a body size limit), and the last layer that
//! turns the bare error answers of those layers into problem+json.

use std::time::Duration;

use axum::Router;
use axum::error_handling::HandleErrorLayer;
use axum::http::{HeaderValue, Method, StatusCode, header};
use axum::response::{IntoResponse, Response};
use tower::ServiceBuilder;
use tower_http::cors::{AllowOrigin, CorsLayer};
use tower_http::limit::RequestBodyLimitLayer;
use tower_http::timeout::TimeoutLayer;
use tower_http::trace::TraceLayer;

use super::problem::{PROBLEM_JSON, Problem};
use crate::config::ServerConfig;
use crate::error::{BridgeError, ErrorCode};

/// Wraps the application in the edge layers configured in `[server]`.
pub fn layers(router: Router, server: &ServerConfig) -> Router {
    let max_request = Duration::from_millis(server.max_request_ms);
    let router = router.layer(
        ServiceBuilder::new()
            .layer(HandleErrorLayer::new(overloaded))
            .load_shed()
            // One limit for the whole service (`Router::layer` wraps each
            // route on its own; a per-route limit would not be one).
            .layer(tower::limit::GlobalConcurrencyLimitLayer::new(
                server.max_concurrent_requests,
            ))
            .layer(TimeoutLayer::with_status_code(
                StatusCode::GATEWAY_TIMEOUT,
                max_request,
            ))
            .layer(RequestBodyLimitLayer::new(server.max_body_bytes)),
    );
    let router = match cors(&server.cors_origins) {
        Some(c) => router.layer(c),
        None => router,
    };
    router
        .layer(axum::middleware::map_response(problem_for_bare_errors))
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

async fn overloaded(_: tower::BoxError) -> Response {
    let mut r = Problem::from(BridgeError::new(
        ErrorCode::Overloaded,
        "too many requests are in progress; retry after the Retry-After delay",
    ))
    .into_response();
    r.headers_mut()
        .insert(header::RETRY_AFTER, HeaderValue::from_static("1"));
    r
}

/// The layers above answer errors with an empty or plain-text body: give
/// them the problem+json body every other error has.
async fn problem_for_bare_errors(resp: Response) -> Response {
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
    let mut body = super::problem::ProblemDetails::from_error(&BridgeError::new(code, detail));
    body.status = status.as_u16();
    let mut out = super::problem::json_response(status.as_u16(), PROBLEM_JSON, &body);
    for h in [header::RETRY_AFTER, header::WWW_AUTHENTICATE, header::ALLOW] {
        if let Some(v) = resp.headers().get(&h) {
            out.headers_mut().insert(h, v.clone());
        }
    }
    // CORS headers set by the layer below stay.
    for (name, v) in resp.headers() {
        if name.as_str().starts_with("access-control-") {
            out.headers_mut().insert(name.clone(), v.clone());
        }
    }
    out
}
