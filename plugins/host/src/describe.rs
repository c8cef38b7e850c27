//! Checks a plugin's self-description before it is activated: its name,
//! version and routes (methods, paths, duplicates), that its JSON schemas
//! parse and that each request schema compiles (it is enforced on every
//! request, see [`crate::schema`]). Every problem is listed, not just the
//! first.

use crate::bindings::Description;
use crate::schema::{CompiledSchema, Refusal};

/// HTTP methods a plugin route may use.
pub const METHODS: [&str; 2] = ["GET", "POST"];

/// Most routes one plugin may declare.
pub const MAX_ROUTES: usize = 64;

/// One route of a plugin, checked and with parsed schemas.
#[derive(Debug, Clone)]
pub struct RouteSpec {
    /// `GET` or `POST`.
    pub method: String,
    /// Path below the plugin's prefix, starting with `/`.
    pub path: String,
    /// One line for the documentation.
    pub summary: String,
    /// JSON Schema of the request body (POST) or the query (GET).
    pub request_schema: serde_json::Value,
    /// JSON Schema of the 200 response body (documentation: not checked).
    pub response_schema: serde_json::Value,
    /// `request_schema`, compiled when the plugin loaded.
    request_validator: CompiledSchema,
}

impl RouteSpec {
    /// Checks a request against the route's request schema before the
    /// plugin runs: a POST's `body` must be JSON the schema accepts; a GET's
    /// `query` is checked as a JSON object (see [`crate::schema::query_object`]).
    pub fn check_request(&self, body: &str, query: &[(String, String)]) -> Result<(), Refusal> {
        let label = format!("{} {}", self.method, self.path);
        if self.method == "GET" {
            self.request_validator
                .check_query(&label, &self.request_schema, query)
        } else {
            self.request_validator.check_body(&label, body)
        }
    }
}

/// Is this a valid plugin name (also its URL prefix and file name)?
/// Lower-case ASCII letters, digits and `-`, 1 to 64 characters, starting
/// with a letter and not ending with `-`.
pub fn check_name(name: &str) -> Result<(), String> {
    let ok = (1..=64).contains(&name.len())
        && name.starts_with(|c: char| c.is_ascii_lowercase())
        && !name.ends_with('-')
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
        && !is_windows_device(name);
    if ok {
        Ok(())
    } else {
        Err(format!(
            "plugin name {name:?} must be 1 to 64 lower-case letters, digits or '-', starting with a letter (not a Windows device name such as con or com1)"
        ))
    }
}

/// `con.wasm` and friends cannot be files on Windows.
fn is_windows_device(name: &str) -> bool {
    matches!(name, "con" | "prn" | "aux" | "nul")
        || ["com", "lpt"].iter().any(|p| {
            name.strip_prefix(p)
                .is_some_and(|n| n.len() == 1 && n.as_bytes()[0].is_ascii_digit())
        })
}

fn check_path(path: &str) -> Result<(), String> {
    if !path.starts_with('/') || path.len() < 2 || path.len() > 200 {
        return Err(format!(
            "route path {path:?} must start with '/' and name something (2 to 200 characters)"
        ));
    }
    let segments_ok = path[1..].split('/').all(|seg| {
        !seg.is_empty()
            && seg != "."
            && seg != ".."
            && seg
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_.~".contains(c))
    });
    if segments_ok {
        Ok(())
    } else {
        Err(format!(
            "route path {path:?} may only hold non-empty segments of letters, digits and -_.~ (no parameters)"
        ))
    }
}

fn parse_schema(route: &str, which: &str, text: &str) -> Result<serde_json::Value, String> {
    match serde_json::from_str::<serde_json::Value>(text) {
        Ok(v @ (serde_json::Value::Object(_) | serde_json::Value::Bool(_))) => Ok(v),
        Ok(_) => Err(format!(
            "{route}: the {which} schema must be a JSON object (a JSON Schema)"
        )),
        Err(e) => Err(format!("{route}: the {which} schema is not JSON: {e}")),
    }
}

/// Checks a description; returns the routes or every problem found.
pub(crate) fn check(expected_name: &str, d: &Description) -> Result<Vec<RouteSpec>, Vec<String>> {
    let mut problems = Vec::new();
    if let Err(e) = check_name(&d.name) {
        problems.push(e);
    } else if d.name != expected_name {
        problems.push(format!(
            "the plugin calls itself {:?} but is installed as {expected_name:?}; install it under its own name",
            d.name
        ));
    }
    if d.version.trim().is_empty() || d.version.len() > 64 {
        problems.push(format!(
            "version {:?} must be 1 to 64 characters",
            d.version
        ));
    }
    if d.routes.is_empty() {
        problems.push("the plugin declares no routes".into());
    }
    if d.routes.len() > MAX_ROUTES {
        problems.push(format!("{} routes; at most {MAX_ROUTES}", d.routes.len()));
    }
    let mut routes: Vec<RouteSpec> = Vec::new();
    for r in d.routes.iter().take(MAX_ROUTES) {
        let label = format!("{} {}", r.method, r.path);
        let mut ok = true;
        if !METHODS.contains(&r.method.as_str()) {
            problems.push(format!("{label}: method must be GET or POST"));
            ok = false;
        }
        if let Err(e) = check_path(&r.path) {
            problems.push(e);
            ok = false;
        }
        if r.summary.len() > 300 {
            problems.push(format!("{label}: summary longer than 300 bytes"));
            ok = false;
        }
        let request_schema = parse_schema(&label, "request", &r.request_schema)
            .map_err(|e| problems.push(e))
            .ok()
            .and_then(|schema| match crate::schema::compile(&schema) {
                Ok(validator) => Some((schema, validator)),
                Err(e) => {
                    problems.push(format!(
                        "{label}: the request schema does not compile as a JSON Schema: {e}"
                    ));
                    None
                }
            });
        let response_schema = parse_schema(&label, "response", &r.response_schema)
            .map_err(|e| problems.push(e))
            .ok();
        if routes
            .iter()
            .any(|x| x.method == r.method && x.path == r.path)
        {
            problems.push(format!("{label}: declared twice"));
            ok = false;
        }
        if let (true, Some((request_schema, request_validator)), Some(response_schema)) =
            (ok, request_schema, response_schema)
        {
            routes.push(RouteSpec {
                method: r.method.clone(),
                path: r.path.clone(),
                summary: r.summary.clone(),
                request_schema,
                response_schema,
                request_validator,
            });
        }
    }
    if problems.is_empty() {
        Ok(routes)
    } else {
        Err(problems)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bindings::exports::kuka_bridge::plugin::plugin::Route;

    fn route(method: &str, path: &str, schema: &str) -> Route {
        Route {
            method: method.into(),
            path: path.into(),
            summary: "s".into(),
            request_schema: schema.into(),
            response_schema: "{}".into(),
        }
    }

    fn desc(name: &str, routes: Vec<Route>) -> Description {
        Description {
            name: name.into(),
            version: "0.1.0".into(),
            routes,
        }
    }

    #[test]
    fn a_good_description_passes() {
        let d = desc(
            "draw-circle",
            vec![route("POST", "/circle", r#"{"type":"object"}"#)],
        );
        let routes = check("draw-circle", &d).expect("valid");
        assert_eq!(routes.len(), 1);
        assert_eq!(routes[0].request_schema["type"], "object");
    }

    #[test]
    fn every_problem_is_listed() {
        let d = desc(
            "Other",
            vec![
                route("POST", "/a", "{}"),
                route("POST", "/a", "{}"),
                route("DELETE", "/b", "{}"),
                route("GET", "c", "{}"),
                route("GET", "/d/{id}", "{}"),
                route("GET", "/e", "not json"),
                route("GET", "/f", "[1]"),
                route("POST", "/g", r#"{"type": "nmber"}"#),
            ],
        );
        let problems = check("other", &d).expect_err("invalid");
        let all = problems.join("\n");
        for needle in [
            "\"Other\" must be",
            "/a: declared twice",
            "DELETE /b: method must be GET or POST",
            "\"c\" must start with '/'",
            "\"/d/{id}\" may only hold",
            "GET /e: the request schema is not JSON",
            "GET /f: the request schema must be a JSON object",
            "POST /g: the request schema does not compile as a JSON Schema",
        ] {
            assert!(all.contains(needle), "missing {needle:?} in:\n{all}");
        }
    }

    #[test]
    fn names_are_checked() {
        for good in ["a", "draw-circle", "py-square2", "console", "com10"] {
            assert!(check_name(good).is_ok(), "{good}");
        }
        for bad in [
            "",
            "-a",
            "a-",
            "A",
            "a_b",
            "1a",
            "a.b",
            &"a".repeat(65),
            "con/x",
            "con",
            "com1",
            "lpt9",
        ] {
            assert!(check_name(bad).is_err(), "{bad}");
        }
        let d = desc("draw-circle", vec![route("GET", "/x", "{}")]);
        let problems = check("circle", &d).expect_err("name mismatch");
        assert!(
            problems[0].contains("installed as \"circle\""),
            "{problems:?}"
        );
    }
}
