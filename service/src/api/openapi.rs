//! The last pass over the OpenAPI document before it is served: what
//! utoipa's derive cannot say, so that standard validators
//! (openapi-spec-validator, Redocly) accept the document and client
//! generators (openapi-python-client, openapi-typescript) produce usable
//! code from it.
//!
//! - every response has a `description` (required by OpenAPI);
//! - operation ids are verb-first camelCase and unique (`getState`,
//!   `createMotions`), from [`OPERATION_IDS`] or the handler's name;
//! - primitive component schemas utoipa makes of type aliases (`u64` for a
//!   job id, `i32` for a command id) are inlined;
//! - the motion kinds are named schemas (`PtpMotion`, `AxisMotion`,
//!   `LinMotion`, `CircMotion`, `SlinMotion`, `ScircMotion`, `SptpMotion`,
//!   `SplMotion`, and the actions `SetOutputAction`, `WaitInputAction`,
//!   `DwellAction`) under a `oneOf` with a `type` discriminator,
//!   and so are the variants of other tagged unions (`JobEvent`, …);
//! - a problem's `code` is an open string: the bridge's codes are listed,
//!   and plugins may answer their own;
//! - raw byte bodies are binary strings (`format: binary`);
//! - a token is optional in the document (`security` lists `{}` too): it
//!   is needed only beyond loopback or with `--require-auth`;
//! - `info.license` has its SPDX identifier, and `servers` the service itself.
//!
//! Every step is idempotent: the plugin routes are added to an already
//! finished document and the pass runs again.

use serde_json::{Map, Value, json};

/// Operation ids by method and path; operations not listed get their
/// handler's name in camelCase (name new handlers verb-first).
pub(crate) const OPERATION_IDS: &[(&str, &str, &str)] = &[
    ("get", "/health", "getHealth"),
    ("post", "/krl/ptp", "movePtpThesis"),
    ("post", "/krl/linmov", "moveLinThesis"),
    ("post", "/krl/circ", "moveCircThesis"),
    ("post", "/krl/getpos", "getPositionThesis"),
    ("post", "/krl/base", "moveHomeThesis"),
    ("post", "/krl/tcp", "setToolThesis"),
    ("post", "/krl/gettcp", "getToolThesis"),
    ("post", "/krl/uploadfile", "uploadFileThesis"),
    ("get", "/api/v1/state", "getState"),
    ("get", "/api/v1/model", "getModel"),
    ("get", "/api/v1/workspace", "getWorkspace"),
    ("get", "/api/v1/position", "getPosition"),
    ("post", "/api/v1/motions", "createMotions"),
    ("get", "/api/v1/jobs", "listJobs"),
    ("get", "/api/v1/jobs/{id}", "getJob"),
    ("delete", "/api/v1/jobs/{id}", "cancelJob"),
    ("post", "/api/v1/paths", "createPath"),
    ("get", "/api/v1/paths/{id}", "getPath"),
    ("post", "/api/v1/paths/{id}/motions", "appendToPath"),
    ("delete", "/api/v1/paths/{id}", "endPath"),
    ("post", "/api/v1/stop", "stopMotion"),
    ("post", "/api/v1/home", "moveHome"),
    ("post", "/api/v1/reset", "resetController"),
    ("get", "/api/v1/tool", "getTool"),
    ("put", "/api/v1/tool", "setTool"),
    ("get", "/api/v1/base", "getBase"),
    ("put", "/api/v1/base", "setBase"),
    ("get", "/api/v1/speed", "getSpeed"),
    ("put", "/api/v1/speed", "setSpeed"),
    ("get", "/api/v1/programs", "listPrograms"),
    ("post", "/api/v1/programs", "uploadProgram"),
    ("get", "/api/v1/programs/{name}", "getProgram"),
    ("delete", "/api/v1/programs/{name}", "deleteProgram"),
    ("post", "/api/v1/programs/{name}/run", "runProgram"),
    ("get", "/api/v1/plugins", "listPlugins"),
    ("get", "/api/v1/plugins/{name}", "getPlugin"),
    ("put", "/api/v1/plugins/{name}", "installPlugin"),
    ("delete", "/api/v1/plugins/{name}", "removePlugin"),
    ("get", "/api/v1/control", "getControl"),
    ("post", "/api/v1/control", "takeControl"),
    ("delete", "/api/v1/control", "releaseControl"),
    ("get", "/api/v1/tokens", "listTokens"),
    ("post", "/api/v1/tokens", "createToken"),
    ("delete", "/api/v1/tokens/{name}", "revokeToken"),
    ("get", "/api/v1/audit", "listAuditRecords"),
    ("get", "/api/v1/events", "streamEvents"),
    ("get", "/api/v1/sim", "getSimulator"),
    ("get", "/api/v1/sim/trace", "getSimTrace"),
    ("delete", "/api/v1/sim/trace", "clearSimTrace"),
    ("post", "/api/v1/sim/acknowledge", "acknowledgeSimStop"),
    ("put", "/api/v1/sim/inputs/{index}", "setSimInput"),
    ("put", "/api/v1/sim/safety", "setSimSafety"),
    ("get", "/api/v1/io", "getIo"),
    ("get", "/api/v1/io/config", "getIoConfig"),
    ("put", "/api/v1/io/config", "setIoConfig"),
    ("delete", "/api/v1/io/config", "resetIoConfig"),
    ("get", "/api/v1/io/inputs/{signal}", "getInput"),
    ("get", "/api/v1/io/outputs/{signal}", "getOutput"),
    ("put", "/api/v1/io/outputs/{signal}", "setOutput"),
    ("put", "/api/v1/variables/{name}", "setVariable"),
    (
        "put",
        "/api/v1/io/analog-outputs/{signal}",
        "setAnalogOutput",
    ),
    (
        "put",
        "/api/v1/sim/analog-inputs/{index}",
        "setSimAnalogInput",
    ),
];

/// The motion kinds: the `type` tag and the schema name of each.
const MOTION_KINDS: &[(&str, &str)] = &[
    ("ptp", "PtpMotion"),
    ("ptp_axes", "AxisMotion"),
    ("lin", "LinMotion"),
    ("circ", "CircMotion"),
    ("slin", "SlinMotion"),
    ("scirc", "ScircMotion"),
    ("sptp", "SptpMotion"),
    ("sptp_axes", "SptpAxisMotion"),
    ("spl", "SplMotion"),
    ("set_output", "SetOutputAction"),
    ("wait_input", "WaitInputAction"),
    ("dwell", "DwellAction"),
];

const METHODS: &[&str] = &[
    "get", "put", "post", "delete", "options", "head", "patch", "trace",
];

/// Applies every step of the module doc to `doc`.
pub(crate) fn finish(doc: &mut Value) {
    info_and_servers(doc);
    inline_primitives(doc);
    name_tagged_variants(doc);
    open_error_code(doc);
    for_each_operation(doc, |method, path, op| {
        describe_responses(op);
        name_operation(method, path, op);
        binary_bodies(op);
        optional_auth(op);
    });
    unique_operation_ids(doc);
}

/// A token is needed only when the service listens beyond loopback or
/// runs with `--require-auth`: each secured operation also lists the empty
/// requirement (`{}`), so generated clients work with and without one.
fn optional_auth(op: &mut Map<String, Value>) {
    add_empty_requirement(op.get_mut("security"));
}

/// Appends `{}` to a non-empty list of security requirements that lacks it.
fn add_empty_requirement(security: Option<&mut Value>) {
    if let Some(list) = security.and_then(Value::as_array_mut)
        && !list.is_empty()
        && !list
            .iter()
            .any(|r| r.as_object().is_some_and(Map::is_empty))
    {
        list.push(json!({}));
    }
}

fn info_and_servers(doc: &mut Value) {
    add_empty_requirement(doc.get_mut("security"));
    if let Some(license) = doc
        .pointer_mut("/info/license")
        .and_then(Value::as_object_mut)
        && let Some(name) = license.get("name").and_then(Value::as_str)
    {
        let id = name.to_string();
        license.entry("identifier").or_insert(json!(id));
    }
    if let Some(map) = doc.as_object_mut() {
        map.entry("servers").or_insert_with(
            || json!([{"url": "/", "description": "This service (the document is served by it)"}]),
        );
    }
}

/// Rust primitive names utoipa uses for the schemas of type aliases.
fn is_primitive(name: &str) -> bool {
    matches!(
        name,
        "i8" | "i16"
            | "i32"
            | "i64"
            | "u8"
            | "u16"
            | "u32"
            | "u64"
            | "usize"
            | "isize"
            | "f32"
            | "f64"
            | "bool"
            | "String"
    )
}

fn inline_primitives(doc: &mut Value) {
    let Some(schemas) = doc
        .pointer_mut("/components/schemas")
        .and_then(Value::as_object_mut)
    else {
        return;
    };
    let primitives: Map<String, Value> = schemas
        .iter()
        .filter(|(k, _)| is_primitive(k))
        .map(|(k, v)| (format!("#/components/schemas/{k}"), v.clone()))
        .collect();
    schemas.retain(|k, _| !is_primitive(k));
    if !primitives.is_empty() {
        replace_refs(doc, &primitives);
    }
}

/// Replaces `{"$ref": r, ...rest}` by the referenced schema merged with `rest`.
fn replace_refs(v: &mut Value, by: &Map<String, Value>) {
    match v {
        Value::Object(map) => {
            if let Some(target) = map
                .get("$ref")
                .and_then(Value::as_str)
                .and_then(|r| by.get(r))
                .and_then(Value::as_object)
            {
                let target = target.clone();
                map.remove("$ref");
                for (k, t) in target {
                    map.entry(k).or_insert(t);
                }
            }
            map.values_mut().for_each(|x| replace_refs(x, by));
        }
        Value::Array(items) => items.iter_mut().for_each(|x| replace_refs(x, by)),
        _ => {}
    }
}

/// Names the inline variants of every tagged `oneOf` (a `type` property
/// with one value each): [`MOTION_KINDS`] for motions, `<Tag><Parent>`
/// otherwise (`JobEvent` for the `job` variant of `Event`), and adds the
/// discriminator, so generators make one type per variant.
fn name_tagged_variants(doc: &mut Value) {
    let Some(schemas) = doc
        .pointer_mut("/components/schemas")
        .and_then(Value::as_object_mut)
    else {
        return;
    };
    let parents: Vec<String> = schemas
        .iter()
        .filter(|(_, v)| {
            v.get("oneOf").and_then(Value::as_array).is_some_and(|vs| {
                !vs.is_empty()
                    && vs
                        .iter()
                        .all(|x| x.pointer("/properties/type/enum/0").is_some())
            })
        })
        .map(|(k, _)| k.clone())
        .collect();
    for parent in parents {
        let Some(variants) = schemas
            .get(&parent)
            .and_then(|m| m.get("oneOf"))
            .and_then(Value::as_array)
            .cloned()
        else {
            continue;
        };
        let mut refs = Vec::new();
        let mut mapping = Map::new();
        for variant in variants {
            let tag = variant
                .pointer("/properties/type/enum/0")
                .and_then(Value::as_str)
                .unwrap_or_default()
                .to_string();
            let name = match MOTION_KINDS.iter().find(|(t, _)| *t == tag) {
                Some((_, name)) if parent == "MotionRequest" => (*name).to_string(),
                _ => format!("{}{parent}", pascal(&tag)),
            };
            let r = format!("#/components/schemas/{name}");
            schemas.insert(name, variant);
            mapping.insert(tag, json!(r));
            refs.push(json!({"$ref": r}));
        }
        if let Some(m) = schemas.get_mut(&parent).and_then(Value::as_object_mut) {
            m.insert("oneOf".into(), Value::Array(refs));
            m.insert(
                "discriminator".into(),
                json!({"propertyName": "type", "mapping": mapping}),
            );
        }
    }
}

fn open_error_code(doc: &mut Value) {
    let Some(code) = doc.pointer_mut("/components/schemas/ErrorCode") else {
        return;
    };
    let Some(known) = code.get("enum").and_then(Value::as_array).cloned() else {
        return; // done before
    };
    let names: Vec<&str> = known.iter().filter_map(Value::as_str).collect();
    *code = json!({
        "type": "string",
        "description": format!(
            "A stable, machine-readable error code (never renamed; see /errors). \
             The bridge's codes: {}. A plugin's answer may carry a code of its own.",
            names.join(", ")
        ),
        "examples": known,
    });
}

fn for_each_operation(doc: &mut Value, mut f: impl FnMut(&str, &str, &mut Map<String, Value>)) {
    let Some(paths) = doc.get_mut("paths").and_then(Value::as_object_mut) else {
        return;
    };
    for (path, item) in paths.iter_mut() {
        let Some(item) = item.as_object_mut() else {
            continue;
        };
        for (method, op) in item.iter_mut() {
            if let (true, Some(op)) = (METHODS.contains(&method.as_str()), op.as_object_mut()) {
                f(method, path, op);
            }
        }
    }
}

/// The standard sentence for a status without a description.
fn default_description(status: &str) -> &'static str {
    match status {
        "200" => "Success",
        "201" => "Created",
        "202" => "Accepted: the job is queued",
        "204" => "Done; no content",
        s if s.starts_with('4') => "Rejected: problem+json with a stable code and a sentence",
        s if s.starts_with('5') => {
            "The controller or the service failed: problem+json with a stable code and a sentence"
        }
        _ => "Answer",
    }
}

fn describe_responses(op: &mut Map<String, Value>) {
    let Some(responses) = op.get_mut("responses").and_then(Value::as_object_mut) else {
        return;
    };
    for (status, r) in responses.iter_mut() {
        if let Some(r) = r.as_object_mut() {
            let empty = r
                .get("description")
                .and_then(Value::as_str)
                .is_none_or(str::is_empty);
            if empty {
                r.insert("description".into(), json!(default_description(status)));
            }
        }
    }
}

/// Bodies of raw bytes (a plugin's `.wasm`) as binary strings: generators
/// then send bytes, not an array of integers.
fn binary_bodies(op: &mut Map<String, Value>) {
    let Some(content) = op
        .get_mut("requestBody")
        .and_then(|b| b.get_mut("content"))
        .and_then(Value::as_object_mut)
    else {
        return;
    };
    for (media, body) in content.iter_mut() {
        if media == "application/octet-stream" || media == "application/wasm" {
            body["schema"] =
                json!({"type": "string", "format": "binary", "contentMediaType": media});
        }
    }
    // One media type for a body of bytes: with two, generators make a
    // union of two identical file types (openapi-python-client cannot).
    if content.contains_key("application/wasm") {
        content.remove("application/octet-stream");
    }
}

/// `snake_case` → `camelCase`.
fn camel(name: &str) -> String {
    let mut out = String::new();
    let mut upper = false;
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            if upper && !out.is_empty() {
                out.push(c.to_ascii_uppercase());
            } else {
                out.push(c);
            }
            upper = false;
        } else {
            upper = true;
        }
    }
    out
}

/// `snake_case` → `PascalCase`.
fn pascal(name: &str) -> String {
    let camel = camel(name);
    let mut chars = camel.chars();
    chars
        .next()
        .map(|c| c.to_ascii_uppercase().to_string() + chars.as_str())
        .unwrap_or_default()
}

fn name_operation(method: &str, path: &str, op: &mut Map<String, Value>) {
    let plugin_route = path
        .strip_prefix("/api/v1/plugins/")
        .and_then(|rest| rest.split_once('/'))
        .filter(|(name, _)| !name.starts_with('{'));
    let id = match OPERATION_IDS
        .iter()
        .find(|(m, p, _)| *m == method && *p == path)
    {
        Some((_, _, id)) => (*id).to_string(),
        None if plugin_route.is_some() => {
            let (plugin, route) = plugin_route.unwrap_or_default();
            plugin_operation_id(plugin, method, &format!("/{route}"))
        }
        None => match op.get("operationId").and_then(Value::as_str) {
            Some(id) => camel(id),
            None => camel(&format!("{method}_{path}")),
        },
    };
    op.insert("operationId".into(), json!(id));
}

/// A second operation with an id gets `2`, `3`, … appended (in path order).
fn unique_operation_ids(doc: &mut Value) {
    let mut seen = std::collections::HashSet::new();
    for_each_operation(doc, |_, _, op| {
        let Some(id) = op.get("operationId").and_then(Value::as_str) else {
            return;
        };
        let mut unique = id.to_string();
        let mut n = 2;
        while !seen.insert(unique.clone()) {
            unique = format!("{id}{n}");
            n += 1;
        }
        op.insert("operationId".into(), json!(unique));
    });
}

/// A plugin route's operation id: `get`/`run` + the plugin's name + the
/// route's path, camel-cased (`runDrawSquareSquare` for `POST /square` of
/// `draw-square`); stable whatever the order of the plugin's routes.
pub(crate) fn plugin_operation_id(plugin: &str, method: &str, path: &str) -> String {
    let verb = if method.eq_ignore_ascii_case("GET") {
        "get"
    } else {
        "run"
    };
    let mut id = camel(&format!("{verb}_{plugin}_{path}"));
    if !path.chars().any(|c| c.is_ascii_alphanumeric()) {
        id.push_str("Root");
    }
    id
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_camel_case() {
        assert_eq!(pascal("ptp_axes"), "PtpAxes");
        assert_eq!(camel("list_jobs"), "listJobs");
        assert_eq!(
            plugin_operation_id("draw-square", "POST", "/square"),
            "runDrawSquareSquare"
        );
        assert_eq!(
            plugin_operation_id("draw-square", "GET", "/a_b/c"),
            "getDrawSquareABC"
        );
        assert_eq!(plugin_operation_id("p", "GET", "/"), "getPRoot");
    }

    #[test]
    fn finishing_twice_changes_nothing() {
        let mut doc = super::super::openapi();
        let once = doc.clone();
        finish(&mut doc);
        assert_eq!(doc, once);
    }
}
