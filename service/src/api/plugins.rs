//! Plugin management (`PUT/GET/DELETE /api/v1/plugins/{name}`,
//! `GET /api/v1/plugins`), the catch-all route that serves every plugin's
//! own routes under `/api/v1/plugins/{name}/...`, and the plugin part of
//! `/openapi.json` (added per request from the live registry, so routes
//! appear when a plugin is installed and disappear when it is removed).

use std::sync::Arc;

use axum::body::Body;
use axum::extract::{Path, RawQuery, State};
use axum::http::{Method, StatusCode};
use axum::response::{IntoResponse, Response};
use kuka_plugin_host::{LoadedPlugin, Refusal, Request};
use serde_json::{Value, json};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::auth::Who;
use super::problem::{PROBLEM_JSON, Problem, ProblemDetails, json_response};
use super::{AppState, ok_json};
use crate::error::{BridgeError, ErrorCode};
use crate::plugins::{Installed, PluginInfo, PluginRegistry, plugin_error};

fn registry(app: &AppState) -> Result<&Arc<PluginRegistry>, Problem> {
    app.plugins.as_ref().ok_or_else(|| {
        BridgeError::new(
            ErrorCode::PluginsUnavailable,
            "plugins are switched off (plugins.enabled = false in the configuration)",
        )
        .into()
    })
}

async fn read_body(body: Body, limit: usize, what: &str) -> Result<axum::body::Bytes, Problem> {
    axum::body::to_bytes(body, limit).await.map_err(|e| {
        let too_large = std::error::Error::source(&e)
            .is_some_and(|s| s.is::<http_body_util::LengthLimitError>());
        if too_large {
            BridgeError::new(
                ErrorCode::PayloadTooLarge,
                format!("the {what} is larger than {limit} bytes"),
            )
        } else {
            BridgeError::invalid(format!("cannot read the {what}: {e}"))
        }
        .into()
    })
}

/// Install or replace a plugin.
///
/// The body is the plugin's `.wasm` (a WebAssembly component of the world
/// `kuka-bridge:plugin/bridge-plugin@0.1.0`, see docs/PLUGINS.md). It is
/// compiled, linked and described before it is activated: a component of
/// another world, a description with invalid routes or schemas, or a name
/// other than `{name}` is refused and changes nothing. A new version replaces
/// the old one atomically; requests in flight finish on the old one. The
/// file is kept in the plugins folder and loads again at the next start.
#[utoipa::path(put, path = "/api/v1/plugins/{name}", tag = "plugins", operation_id = "install_plugin",
    params(("name" = String, Path, description = "The plugin's name (as it describes itself)")),
    request_body(description = "The component (any media type is accepted; `application/wasm` is the right one)",
        content((Vec<u8> = "application/wasm"), (Vec<u8> = "application/octet-stream"))),
    responses(
        (status = 201, description = "Installed", body = PluginInfo),
        (status = 200, description = "Replaced an installed version", body = PluginInfo),
        (status = 413, body = ProblemDetails, content_type = PROBLEM_JSON),
        (status = 422, description = "Not a valid plugin (`plugin_invalid`)", body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn install(
    State(app): State<AppState>,
    Path(name): Path<String>,
    body: Body,
) -> Result<Response, Problem> {
    let registry = registry(&app)?;
    let wasm = read_body(body, registry.max_wasm_bytes(), "plugin").await?;
    let (status, info) = match registry.install(&name, wasm.to_vec()).await? {
        Installed::Created(info) => (201, info),
        Installed::Replaced(info) => (200, info),
    };
    Ok(json_response(status, "application/json", &info))
}

/// Installed plugins with their versions, routes and status.
#[utoipa::path(get, path = "/api/v1/plugins", tag = "plugins", operation_id = "list_plugins",
    responses((status = 200, body = [PluginInfo]), (status = 503, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn list(State(app): State<AppState>) -> Result<Response, Problem> {
    Ok(ok_json(&registry(&app)?.list()))
}

fn not_installed(name: &str) -> BridgeError {
    BridgeError::new(
        ErrorCode::NotFound,
        format!("no plugin named {name:?} is installed; see GET /api/v1/plugins"),
    )
}

/// One installed plugin.
#[utoipa::path(get, path = "/api/v1/plugins/{name}", tag = "plugins", operation_id = "get_plugin",
    params(("name" = String, Path, description = "Plugin name")),
    responses((status = 200, body = PluginInfo), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn get_one(
    State(app): State<AppState>,
    Path(name): Path<String>,
) -> Result<Response, Problem> {
    let info = registry(&app)?
        .info(&name)
        .ok_or_else(|| not_installed(&name))?;
    Ok(ok_json(&info))
}

/// Remove a plugin: its routes disappear at once (requests in flight finish)
/// and its file is deleted from the plugins folder.
#[utoipa::path(delete, path = "/api/v1/plugins/{name}", tag = "plugins", operation_id = "remove_plugin",
    params(("name" = String, Path, description = "Plugin name")),
    responses((status = 204, description = "Removed"), (status = 404, body = ProblemDetails, content_type = PROBLEM_JSON)))]
async fn remove(
    State(app): State<AppState>,
    Path(name): Path<String>,
) -> Result<StatusCode, Problem> {
    registry(&app)?.remove(&name).await?;
    Ok(StatusCode::NO_CONTENT)
}

/// Serves `/api/v1/plugins/{name}/{*path}`: finds the plugin and its route,
/// and runs the request in the plugin's sandbox.
pub(super) async fn call(
    State(app): State<AppState>,
    who: Who,
    Path((name, path)): Path<(String, String)>,
    method: Method,
    RawQuery(query): RawQuery,
    headers: axum::http::HeaderMap,
    body: Body,
) -> Result<Response, Problem> {
    let registry = registry(&app)?;
    let plugin = registry.get(&name).ok_or_else(|| not_installed(&name))?;
    let path = format!("/{path}");
    // HEAD is GET without the body (hyper leaves the body out).
    let method = if method == Method::HEAD {
        Method::GET
    } else {
        method
    };
    let Some(route) = plugin.route(method.as_str(), &path) else {
        let routes: Vec<String> = plugin
            .routes
            .iter()
            .map(|r| format!("{} /api/v1/plugins/{name}{}", r.method, r.path))
            .collect();
        let allowed: Vec<&str> = plugin
            .routes
            .iter()
            .filter(|r| r.path == path)
            .map(|r| r.method.as_str())
            .collect();
        let code = if allowed.is_empty() {
            ErrorCode::NotFound
        } else {
            ErrorCode::MethodNotAllowed
        };
        let mut resp = Problem::from(BridgeError::new(
            code,
            format!(
                "plugin {name} has no route {method} {path}; its routes: {}",
                routes.join(", ")
            ),
        ))
        .into_response();
        if !allowed.is_empty() {
            let mut allow = allowed.join(",");
            if allowed.contains(&"GET") {
                allow.push_str(",HEAD");
            }
            if let Ok(v) = axum::http::HeaderValue::from_str(&allow) {
                resp.headers_mut().insert(axum::http::header::ALLOW, v);
            }
        }
        return Ok(resp);
    };
    let body = read_body(body, registry.max_body_bytes(), "request body").await?;
    let body = String::from_utf8(body.to_vec())
        .map_err(|_| BridgeError::invalid("the request body is not UTF-8 text (JSON expected)"))?;
    let query: Vec<(String, String)> =
        serde_urlencoded::from_str(query.as_deref().unwrap_or(""))
            .map_err(|e| BridgeError::invalid(format!("query string: {e}")))?;
    // A POST body is JSON, as on every other endpoint (no header: taken as JSON).
    if method == Method::POST
        && let Some(ct) = headers.get(axum::http::header::CONTENT_TYPE)
    {
        let media = ct
            .to_str()
            .unwrap_or("")
            .split(';')
            .next()
            .unwrap_or("")
            .trim()
            .to_ascii_lowercase();
        if media != "application/json" && !media.ends_with("+json") {
            return Err(BridgeError::new(
                ErrorCode::UnsupportedMediaType,
                format!(
                    "POST {path} of plugin {name} takes a JSON body (Content-Type: application/json), not {media:?}"
                ),
            )
            .into());
        }
    }
    // A POST route's input is its JSON body: a query parameter there is
    // refused like an undeclared one on every other endpoint.
    if method == Method::POST && !query.is_empty() {
        let names: Vec<&str> = query.iter().map(|(k, _)| k.as_str()).collect();
        return Err(BridgeError::invalid(format!(
            "POST {path} of plugin {name} takes no query parameters (its input is the JSON body); got: {}",
            names.join(", ")
        ))
        .into());
    }
    // The plugin's request schema is a contract: a request it refuses
    // never reaches the plugin (nothing runs, nothing moves).
    if let Err(refusal) = route.check_request(&body, &query) {
        return Ok(schema_refusal(&name, &refusal));
    }
    let request = Request {
        method: method.as_str().to_string(),
        path,
        query,
        body,
    };
    let response = registry
        .host()
        .call(&plugin, request, Some(who.0))
        .await
        .map_err(|e| plugin_error(&e))?;
    Ok(plugin_response(&name, response.status, response.body))
}

/// A request its route's schema refuses: 422 `invalid_input`, the first
/// violations in `detail` and all of them (up to ten) in `errors`, each
/// with the JSON Pointer of the offending value, the schema keyword and a
/// message; `plugin` names the plugin whose schema it is.
fn schema_refusal(plugin: &str, refusal: &Refusal) -> Response {
    let problem = ProblemDetails::from_error(&BridgeError::invalid(refusal.detail.clone()));
    let mut body = serde_json::to_value(&problem).unwrap_or_else(|_| json!({}));
    let errors: Vec<Value> = refusal
        .violations
        .iter()
        .map(|v| json!({"pointer": v.pointer, "keyword": v.keyword, "message": v.message}))
        .collect();
    if let Value::Object(map) = &mut body {
        map.insert("errors".into(), Value::Array(errors));
        map.insert("plugin".into(), json!(plugin));
    }
    json_response(problem.status, PROBLEM_JSON, &body)
}

/// The plugin's answer as an HTTP response. Error answers (4xx/5xx) become
/// `application/problem+json` like every other error of the API: the
/// plugin's JSON object gets the real `status`, `type: about:blank`, its
/// `plugin` name and a `title` when it has none; anything but an object
/// becomes the `detail` of a `plugin_error`.
fn plugin_response(plugin: &str, status: u16, body: String) -> Response {
    let http = StatusCode::from_u16(status).unwrap_or(StatusCode::BAD_GATEWAY);
    // Only registered statuses: clients map them to types (Python's
    // HTTPStatus has no 599).
    if http.canonical_reason().is_none() {
        let e = BridgeError::new(
            ErrorCode::PluginBadResponse,
            format!(
                "plugin {plugin} answered status {status}, which is not a registered HTTP status"
            ),
        );
        return Problem::from(e).into_response();
    }
    if status < 400 {
        let mut out = Response::new(Body::from(body));
        *out.status_mut() = http;
        out.headers_mut().insert(
            axum::http::header::CONTENT_TYPE,
            axum::http::HeaderValue::from_static("application/json"),
        );
        return out;
    }
    let mut problem = match serde_json::from_str::<Value>(&body) {
        Ok(Value::Object(map)) => map,
        other => {
            let detail = match other {
                Ok(Value::String(s)) => s,
                _ => body,
            };
            let mut map = serde_json::Map::new();
            map.insert("code".into(), json!("plugin_error"));
            map.insert("detail".into(), json!(detail));
            map
        }
    };
    // The HTTP status, the type and the plugin's name are the bridge's to
    // say: a plugin cannot make its problem contradict the response.
    // A bridge code the plugin relays (e.g. `unreachable` from a batch)
    // links to its section of the catalogue; a plugin's own code cannot.
    let known = problem
        .get("code")
        .and_then(Value::as_str)
        .and_then(|c| super::errors::ALL.iter().find(|k| k.as_str() == c).copied());
    let type_uri = known.map_or_else(|| "about:blank".to_string(), super::problem::type_uri);
    problem.insert("type".into(), json!(type_uri));
    // The title a bridge code has everywhere else; a plugin's own code
    // gets the status's reason.
    problem.entry("title").or_insert_with(|| {
        json!(known.map_or_else(
            || http.canonical_reason().unwrap_or("Plugin error"),
            |k| k.title()
        ))
    });
    problem.insert("status".into(), json!(status));
    problem.insert("plugin".into(), json!(plugin));
    json_response(status, PROBLEM_JSON, &Value::Object(problem))
}

/// Adds the routes of the active plugins to an OpenAPI document (as JSON):
/// each route becomes an operation under `/api/v1/plugins/{name}{path}`
/// with the plugin's JSON schemas (OpenAPI 3.1 schemas are JSON Schema).
pub(super) fn add_plugin_paths(doc: &mut Value, plugins: &[Arc<LoadedPlugin>]) {
    for plugin in plugins {
        let tag = format!("plugin: {}", plugin.name);
        if let Some(tags) = doc.get_mut("tags").and_then(Value::as_array_mut) {
            tags.push(json!({
                "name": tag,
                "description": format!("WASM plugin {} {} (installed at runtime)", plugin.name, plain(&plugin.version)),
            }));
        }
        for (index, route) in plugin.routes.iter().enumerate() {
            let url = format!("/api/v1/plugins/{}{}", plugin.name, route.path);
            let mut op = json!({
                "tags": [tag],
                "summary": route.summary,
                // Unique: the route's index (paths may differ only in `/` vs `_`).
                "operationId": format!("plugin_{}_{index}_{}", plugin.name, route.method.to_lowercase()),
                "responses": {
                    "200": {"description": "The plugin's answer", "content": {"application/json": {"schema": route.response_schema}}},
                    "default": {"description": "An error: 422 invalid_input (with `errors`: pointer, keyword, message) when the request does not match the route's schema, before the plugin runs; the plugin's own codes (passed through unchanged); or the bridge's (plugin_timeout, plugin_trap, ...)",
                        "content": {PROBLEM_JSON: {"schema": {"$ref": "#/components/schemas/ProblemDetails"}}}}
                }
            });
            if route.method == "POST" {
                op["requestBody"] = json!({
                    "required": true,
                    "content": {"application/json": {"schema": route.request_schema}}
                });
            } else {
                op["parameters"] = Value::Array(query_parameters(&route.request_schema));
            }
            plain_descriptions(&mut op);
            let Some(paths) = doc.get_mut("paths").and_then(Value::as_object_mut) else {
                return;
            };
            let entry = paths.entry(url).or_insert_with(|| json!({}));
            entry[route.method.to_lowercase()] = op;
        }
    }
}

/// A plugin's text as plain text for documentation viewers that render
/// Markdown and HTML (Swagger UI): markup characters escaped, so a plugin
/// cannot put elements or links on the documentation page.
fn plain(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// [`plain`] applied to every `description`, `title` and `summary` string
/// inside a plugin's operation (its schemas included).
fn plain_descriptions(v: &mut Value) {
    match v {
        Value::Object(map) => {
            for (k, item) in map.iter_mut() {
                match item {
                    Value::String(text)
                        if matches!(k.as_str(), "description" | "title" | "summary") =>
                    {
                        *text = plain(text);
                    }
                    _ => plain_descriptions(item),
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(plain_descriptions),
        _ => {}
    }
}

/// A GET route's request schema (an object) as query parameters.
fn query_parameters(schema: &Value) -> Vec<Value> {
    let required: Vec<&str> = schema
        .get("required")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    schema
        .get("properties")
        .and_then(Value::as_object)
        .map(|props| {
            props
                .iter()
                .map(|(name, s)| {
                    json!({"name": name, "in": "query", "required": required.contains(&name.as_str()), "schema": s})
                })
                .collect()
        })
        .unwrap_or_default()
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(list))
        .routes(routes!(install, get_one, remove))
}
