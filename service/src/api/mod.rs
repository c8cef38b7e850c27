//! The HTTP API: thesis-compatible `/krl/*` endpoints, the versioned JSON
//! API under `/api/v1`, plugin management and plugin routes, access
//! (control, tokens, audit), Server-Sent Events, `/health`,
//! `/openapi.json` and Swagger UI at `/docs` (served from the binary, no
//! internet needed). Every route passes the access middleware (`auth`)
//! and the edge layers (`edge`).

mod access;
mod auth;
mod dashboard;
mod edge;
mod errors;
mod events;
mod io;
mod openapi;
mod paths;
mod plugins;
pub mod problem;
mod programs;
mod sim;
mod thesis;
mod v1;
mod variables;

use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use axum::extract::State;
use axum::http::Uri;
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use utoipa::OpenApi;
use utoipa::ToSchema;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;
use utoipa_swagger_ui::SwaggerUi;

use crate::engine::{Connection, Engine};
use crate::error::{BridgeError, ErrorCode};
use problem::Problem;

/// Shared state of all handlers.
#[derive(Clone)]
pub struct AppState {
    /// The engine.
    pub engine: Engine,
    /// The embedded simulator, in `--simulate` mode.
    pub sim: Option<Arc<kuka_sim::SimController>>,
    /// The embedded KRC-like runtime, in `--simulate krc` mode.
    pub krc: Option<Arc<kuka_krc::KrcController>>,
    /// Longest a synchronous request waits beyond its job's own timeout.
    pub request_timeout: Duration,
    /// The OpenAPI document of the built-in routes (plugin routes are added
    /// per request by `/openapi.json`).
    pub openapi: Arc<serde_json::Value>,
    /// Becomes true when the service shuts down (ends event streams).
    pub closing: tokio::sync::watch::Receiver<bool>,
    /// Uploaded KRL programs.
    pub programs: Arc<crate::programs::ProgramStore>,
    /// Installed WASM plugins (`None` when switched off).
    pub plugins: Option<Arc<crate::plugins::PluginRegistry>>,
    /// Tokens, control lease, audit trail.
    pub access: Arc<crate::access::Access>,
    /// The `[server]` settings (edge limits).
    pub server: Arc<crate::config::ServerConfig>,
    /// `motion.thesis_blend_ms`: thesis motion calls this close together
    /// blend into one path (zero: off).
    pub thesis_blend: Duration,
    /// The open path of each thesis client that blends.
    pub thesis_paths: Arc<thesis::BlendPaths>,
    /// KRL variables through KUKAVARPROXY.
    pub variables: Arc<crate::variables::Variables>,
    /// The I/O configuration an admin edits (`/api/v1/io/config`).
    pub io_store: Arc<crate::io_store::IoStore>,
}

impl AppState {
    /// How long to wait for a job with this timeout.
    pub(crate) fn wait_budget(&self, job_timeout: Option<Duration>) -> Duration {
        job_timeout.map_or(self.request_timeout, |t| t + Duration::from_secs(5))
    }
}

#[derive(OpenApi)]
#[openapi(
    info(
        title = "kuka-bridge",
        description = "A REST API for KUKA robots (KRC, KSS 8.x) over a file protocol.\n\n\
            The `/krl/*` endpoints keep the 2023 thesis bridge's interface (POST with query parameters, \
            answer `{\"statuscode\": 1, \"position\": [x, y, z, a, b, c]}`). The `/api/v1` endpoints are \
            the versioned JSON API: robot state, motions (single or continuous batches), jobs, stop, \
            frames, speeds and live events.\n\n\
            Errors are `application/problem+json` with a stable `code` (see the ProblemDetails schema). \
            Error codes: [/errors](/errors), served by this service (each problem's `type` links to its \
            code's section there). \
            Units: mm, degrees; PTP speeds in % of the maximum axis speed, LIN/CIRC speeds in m/s.\n\n\
            **Access.** When the service listens beyond loopback (or runs with `--require-auth`) every \
            endpoint except `/health` and the documentation needs a bearer token (*Authorize* above). \
            Each operation names the role it needs (`x-required-role`: viewer < operator < admin) and \
            whether it is refused with 409 `control_held` while another client holds control \
            (`x-needs-control`). See docs/SECURITY.md.",
        license(name = "MIT OR Apache-2.0")
    ),
    tags(
        (name = "thesis", description = "Compatible with the thesis bridge's clients."),
        (name = "robot", description = "State, position, frames and speeds."),
        (name = "io", description = "Digital inputs and outputs: read live, write the outputs the site allows."),
        (name = "motion", description = "Motions, jobs and stop."),
        (name = "programs", description = "Upload and run KRL programs."),
        (name = "plugins", description = "Install, list and remove WASM plugins; each plugin's own routes follow under `plugin: <name>`."),
        (name = "access", description = "Control of the robot (one writer at a time), tokens and the audit trail."),
        (name = "events", description = "Server-Sent Events."),
        (name = "simulator", description = "Only in `--simulate` mode."),
        (name = "service", description = "Health and documentation.")
    ),
    components(schemas(crate::engine::Event, crate::engine::JobPlan, crate::engine::PlannedMotion))
)]
struct ApiDoc;

/// Service health.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({"status": "ok", "version": "0.1.0", "connection": "online", "simulated": true, "degraded": []}))]
pub struct Health {
    /// `ok` when commands can be sent; `degraded` when something stops
    /// them (the reasons are in `degraded`).
    pub status: &'static str,
    /// Service version.
    pub version: &'static str,
    /// Connection to the controller.
    pub connection: Connection,
    /// True when running on the embedded simulator.
    pub simulated: bool,
    /// Why commands cannot be sent now, each with a stable `code` and a
    /// sentence (empty when `status` is `ok`); the same list as
    /// `degraded` in `/api/v1/state`.
    pub degraded: Vec<crate::error::BridgeError>,
}

/// Is the service up, and can it send commands?
///
/// 200 while the service runs. `status` is `ok` when commands can be sent,
/// `degraded` with the reasons when they cannot (controller offline,
/// channel locked or not writable, data folder not writable, controller in
/// its error state, a junk controller file, shutting down).
#[utoipa::path(get, path = "/health", tag = "service", responses((status = 200, description = "The service runs; `status` says whether commands can be sent.", body = Health)))]
async fn health(State(app): State<AppState>) -> axum::Json<Health> {
    let state = app.engine.state();
    axum::Json(Health {
        status: if state.degraded.is_empty() {
            "ok"
        } else {
            "degraded"
        },
        version: env!("CARGO_PKG_VERSION"),
        connection: state.connection,
        simulated: app.sim.is_some() || app.krc.is_some(),
        degraded: state.degraded,
    })
}

async fn openapi_json(State(app): State<AppState>) -> Response {
    match &app.plugins {
        Some(registry) => {
            let mut doc = app.openapi.as_ref().clone();
            plugins::add_plugin_paths(&mut doc, &registry.active());
            auth::document(&mut doc);
            openapi::finish(&mut doc);
            problem::json_response(200, "application/json", &doc)
        }
        None => problem::json_response(200, "application/json", app.openapi.as_ref()),
    }
}

/// Thesis clients read `statuscode`: answer `/krl/*` errors in their format.
fn routing_error(app: &AppState, uri: &Uri, e: BridgeError) -> Response {
    if uri.path().starts_with("/krl/") {
        thesis::fail(app, &e)
    } else {
        Problem::from(e).into_response()
    }
}

/// [`routing_error`] for callers not identified yet: a thesis answer
/// carries zeros, not the robot's position.
pub(crate) fn routing_error_blind(uri: &Uri, e: BridgeError) -> Response {
    if uri.path().starts_with("/krl/") {
        thesis::fail_at(&e, [0.0; 6])
    } else {
        Problem::from(e).into_response()
    }
}

async fn not_found(uri: Uri) -> Response {
    let e = BridgeError::new(
        ErrorCode::NotFound,
        format!("no endpoint at {}; see /docs", uri.path()),
    );
    // Nobody was identified: no position in a thesis answer.
    routing_error_blind(&uri, e)
}

async fn method_not_allowed(uri: Uri) -> Response {
    let e = BridgeError::new(
        ErrorCode::MethodNotAllowed,
        format!("{} does not accept this HTTP method; see /docs", uri.path()),
    );
    routing_error_blind(&uri, e)
}

/// The documented routes and their OpenAPI description.
fn documented() -> OpenApiRouter<AppState> {
    OpenApiRouter::with_openapi(ApiDoc::openapi())
        .routes(routes!(health))
        .merge(errors::router())
        .merge(thesis::router())
        .merge(v1::router())
        .merge(paths::router())
        .merge(io::router())
        .merge(variables::router())
        .merge(programs::router())
        .merge(plugins::router())
        .merge(access::router())
        .merge(events::router())
        .merge(sim::router())
}

/// The OpenAPI document with each operation's access rule.
pub fn openapi() -> serde_json::Value {
    let mut doc = serde_json::to_value(documented().into_openapi()).unwrap_or_default();
    auth::document(&mut doc);
    openapi::finish(&mut doc);
    doc
}

/// Builds the whole HTTP application; `state.openapi` is replaced by the
/// document of the routes built here.
pub fn app(mut state: AppState) -> Router {
    let (router, doc) = documented().split_for_parts();
    let mut doc = serde_json::to_value(&doc).unwrap_or_default();
    auth::document(&mut doc);
    openapi::finish(&mut doc);
    state.openapi = Arc::new(doc);
    let server = state.server.clone();
    let router = router
        .route("/openapi.json", axum::routing::get(openapi_json))
        .route(
            "/api/v1/plugins/{name}/{*path}",
            axum::routing::any(plugins::call),
        )
        // Swagger UI forgets the token when the page is closed (no
        // persisted authorization: HMI PCs are shared).
        .merge(SwaggerUi::new("/docs").config(utoipa_swagger_ui::Config::from("/openapi.json")))
        // The dashboard (its page asks for a token when access control is on).
        .route("/", axum::routing::get(dashboard::page))
        .route("/ui/{*path}", axum::routing::get(dashboard::file))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed);
    // Inside the access layer: what it must see (and audit) as the
    // request's outcome; outside it: what refuses a request before anyone
    // is identified.
    let router = edge::inner_layers(router, &state).layer(axum::middleware::from_fn_with_state(
        state.clone(),
        auth::guard,
    ));
    edge::outer_layers(router, &server).with_state(state)
}

/// Converts anything into a 200 JSON response.
pub(crate) fn ok_json(body: &impl Serialize) -> Response {
    problem::json_response(200, "application/json", body)
}

#[cfg(test)]
mod tests {
    /// Every documented operation has its own line in the access table
    /// (`access::policy`): a new endpoint cannot be added without deciding
    /// who may call it.
    #[test]
    fn every_documented_operation_has_a_rule() {
        let doc = super::openapi();
        let paths = doc["paths"].as_object().expect("paths");
        let mut missing = Vec::new();
        for (path, item) in paths {
            for method in item.as_object().expect("path item").keys() {
                if crate::access::policy::documented_rule(method, path).is_none() {
                    missing.push(format!("{} {path}", method.to_uppercase()));
                }
            }
        }
        assert!(missing.is_empty(), "no access rule for: {missing:?}");
    }
}
