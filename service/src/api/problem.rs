//! RFC 9457 problem details: every error the API returns is
//! `application/problem+json` with a stable `code` and a human `detail`.
//! Also the JSON/query extractors whose rejections become problems.

use axum::extract::rejection::{JsonRejection, QueryRejection};
use axum::extract::{FromRequest, FromRequestParts, Request};
use axum::http::{HeaderValue, StatusCode, header, request::Parts};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use serde::de::DeserializeOwned;
use utoipa::ToSchema;

use crate::engine::JobId;
use crate::error::{BridgeError, ErrorCode};

/// The media type of problem responses.
pub const PROBLEM_JSON: &str = "application/problem+json";

/// Where the service serves its error catalogue (`api::errors`): every
/// problem's `type` is this page with the code as its fragment.
pub const ERROR_PAGE: &str = "/errors";

/// The `type` of a problem with this code: `/errors#<code>`, a relative
/// URI reference (RFC 9457 §3.1.1) resolved against the request's URL, so
/// that it leads to the catalogue of the service that answered, also on a
/// plant network without internet.
pub fn type_uri(code: ErrorCode) -> String {
    format!("{ERROR_PAGE}#{}", code.as_str())
}

/// A problem details body (RFC 9457) with kuka-bridge extensions.
#[derive(Debug, Clone, Serialize, ToSchema)]
#[schema(example = json!({
    "type": "/errors#software_limit",
    "title": "Software limit switch",
    "status": 422,
    "detail": "axis A5 would be at 128.000° outside its software limits [-120.0°, 120.0°]",
    "code": "software_limit",
    "axis": 5,
    "motion": 0
}))]
pub struct ProblemDetails {
    /// The problem type: `/errors#<code>`, a URI reference relative to the
    /// request's URL; the service's error catalogue (`GET /errors`)
    /// explains the code there.
    #[serde(rename = "type")]
    pub type_uri: String,
    /// Short summary of the problem type.
    pub title: String,
    /// HTTP status.
    pub status: u16,
    /// Human explanation of this occurrence.
    pub detail: String,
    /// Stable machine-readable code.
    pub code: ErrorCode,
    /// Axis (1..6) for software-limit errors.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis: Option<u8>,
    /// Index of the failing motion in the batch.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motion: Option<usize>,
    /// For KRL program errors: the uploaded file (`src` or `dat`) of `line`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// For KRL program errors: the 1-based line in the uploaded file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<u32>,
    /// Job the error belongs to.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub job_id: Option<JobId>,
    /// The request's id (also the `x-request-id` header): the service log
    /// has the request's internal details (paths, operating system errors)
    /// under it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub request_id: Option<String>,
    /// On a plugin route: the plugin that answered or whose request was refused.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plugin: Option<String>,
    /// For `invalid_input` against a plugin's request schema: each violation
    /// (at most 10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub errors: Option<Vec<SchemaViolation>>,
}

/// One place where a request does not match a JSON schema.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct SchemaViolation {
    /// JSON Pointer to the offending value (`/x`; empty for the whole body).
    pub pointer: String,
    /// The schema keyword that failed (`type`, `additionalProperties`, …).
    pub keyword: String,
    /// What is wrong, as a sentence.
    pub message: String,
}

impl ProblemDetails {
    /// Builds the body for an error.
    pub fn from_error(e: &BridgeError) -> Self {
        ProblemDetails {
            type_uri: type_uri(e.code),
            title: e.code.title().into(),
            status: e.code.http_status(),
            detail: e.detail.clone(),
            code: e.code,
            axis: e.axis,
            motion: e.motion,
            file: e.file.clone(),
            line: e.line,
            job_id: None,
            request_id: None,
            plugin: None,
            errors: None,
        }
    }
}

/// An error response.
#[derive(Debug)]
pub struct Problem {
    /// The error.
    pub error: BridgeError,
    /// The job it belongs to.
    pub job_id: Option<JobId>,
}

impl From<BridgeError> for Problem {
    fn from(error: BridgeError) -> Self {
        Problem {
            error,
            job_id: None,
        }
    }
}

/// Serialises `body` as JSON with the given status and media type.
pub fn json_response(status: u16, content_type: &'static str, body: &impl Serialize) -> Response {
    let status = StatusCode::from_u16(status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    match serde_json::to_vec(body) {
        Ok(bytes) => (
            status,
            [(header::CONTENT_TYPE, HeaderValue::from_static(content_type))],
            bytes,
        )
            .into_response(),
        Err(e) => {
            tracing::error!(error = %e, "cannot serialise response");
            StatusCode::INTERNAL_SERVER_ERROR.into_response()
        }
    }
}

impl IntoResponse for Problem {
    fn into_response(self) -> Response {
        let mut body = ProblemDetails::from_error(&self.error);
        body.job_id = self.job_id;
        if body.code == ErrorCode::Internal {
            tracing::error!(detail = %self.error.detail, "internal error");
        }
        let busy = matches!(body.code, ErrorCode::QueueFull | ErrorCode::PathFull);
        let mut resp = json_response(body.status, PROBLEM_JSON, &body);
        if busy {
            // Full now, free again as soon as something running ends (or
            // the robot has run some of the path's motions).
            resp.headers_mut().insert(
                axum::http::header::RETRY_AFTER,
                axum::http::HeaderValue::from_static("1"),
            );
        }
        resp
    }
}

/// A JSON body whose rejection is a problem (`invalid_input`).
pub struct JsonBody<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for JsonBody<T> {
    type Rejection = Problem;

    async fn from_request(req: Request, state: &S) -> Result<Self, Self::Rejection> {
        match axum::Json::<T>::from_request(req, state).await {
            Ok(axum::Json(v)) => Ok(JsonBody(v)),
            Err(e) => Err(json_rejection(&e).into()),
        }
    }
}

/// The body of a request that takes none: empty, or an empty JSON object
/// (what some clients send by default). Anything else is refused with
/// `invalid_input` rather than ignored, so that a client that thinks the
/// request takes options learns that it does not.
pub struct NoBody;

impl<S: Send + Sync> FromRequest<S> for NoBody {
    type Rejection = Problem;

    async fn from_request(req: Request, state: &S) -> Result<Self, Self::Rejection> {
        let bytes = axum::body::Bytes::from_request(req, state)
            .await
            .map_err(|_| BridgeError::invalid("request body: it could not be read"))?;
        let empty = match std::str::from_utf8(&bytes).map(str::trim) {
            Ok("") => true,
            Ok(text) => serde_json::from_str::<serde_json::Map<String, serde_json::Value>>(text)
                .is_ok_and(|m| m.is_empty()),
            Err(_) => false,
        };
        if empty {
            Ok(NoBody)
        } else {
            Err(
                BridgeError::invalid("request body: this request takes none (send no body, or {})")
                    .into(),
            )
        }
    }
}

fn json_rejection(e: &JsonRejection) -> BridgeError {
    let code = match e.status().as_u16() {
        413 => ErrorCode::PayloadTooLarge,
        415 => ErrorCode::UnsupportedMediaType,
        _ => ErrorCode::InvalidInput,
    };
    BridgeError::new(code, format!("request body: {}", e.body_text()))
}

/// Query parameters whose rejection is a problem (`invalid_input`).
pub struct QueryParams<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequestParts<S> for QueryParams<T> {
    type Rejection = Problem;

    async fn from_request_parts(parts: &mut Parts, state: &S) -> Result<Self, Self::Rejection> {
        match axum::extract::Query::<T>::from_request_parts(parts, state).await {
            Ok(axum::extract::Query(v)) => Ok(QueryParams(v)),
            Err(e) => Err(query_rejection(&e).into()),
        }
    }
}

/// The sentence for a rejected query string.
pub fn query_rejection(e: &QueryRejection) -> BridgeError {
    let text = e.body_text();
    // axum's own wording first, then serde's (`limit: invalid digit found in string`).
    let text = text
        .strip_prefix("Failed to deserialize query string: ")
        .unwrap_or(&text);
    BridgeError::invalid(format!("query string: {text}"))
}
