//! A plugin's request schemas are a contract the bridge enforces: each
//! route's JSON Schema is compiled once when the plugin loads (with the
//! `jsonschema` crate), and every request is checked against it before
//! the plugin runs. A POST body must be JSON that the schema accepts; a GET
//! query becomes a JSON object (one property per parameter, typed as the
//! schema declares it) that the schema must accept.
//!
//! Compilation never reaches outside the service: the crate is built
//! without its HTTP and file resolvers (a `$ref` to a URL does not compile),
//! and `pattern`s use the linear-time `regex` engine (no look-around or
//! back-references; no catastrophic backtracking on a client's input).

use std::sync::Arc;

use serde_json::{Map, Value};

/// Most violations listed in a refusal.
pub const MAX_VIOLATIONS: usize = 10;

/// Longest message of one violation (a value printed in it is cut).
const MAX_MESSAGE_CHARS: usize = 200;

/// Longest printed value before it is masked in a message.
const MAX_VALUE_CHARS: usize = 80;

/// Size limit of one compiled `pattern` (the `regex` crate's size limit).
const PATTERN_SIZE_LIMIT: usize = 1 << 20;

/// A request schema, compiled.
#[derive(Clone)]
pub struct CompiledSchema(Arc<jsonschema::Validator>);

impl std::fmt::Debug for CompiledSchema {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("CompiledSchema")
    }
}

/// Compiles a schema; the error is a sentence (the crate's reason).
pub(crate) fn compile(schema: &Value) -> Result<CompiledSchema, String> {
    jsonschema::options()
        .with_pattern_options(jsonschema::PatternOptions::regex().size_limit(PATTERN_SIZE_LIMIT))
        .build(schema)
        .map(|v| CompiledSchema(Arc::new(v)))
        .map_err(|e| {
            let at = e.instance_path().as_str();
            let msg = crate::error::one_line(&e.to_string());
            if at.is_empty() {
                msg
            } else {
                format!("{msg} (at {at} in the schema)")
            }
        })
}

/// One way a request breaks its route's schema.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Violation {
    /// JSON Pointer (RFC 6901) of the offending value in the body, or in
    /// the query object for a GET (`/radius`); `""` is the whole body.
    pub pointer: String,
    /// The schema keyword that refused it (`type`, `required`,
    /// `additionalProperties`, `maximum`, ...).
    pub keyword: String,
    /// What is wrong (`"220" is not of type "number"`).
    pub message: String,
}

impl Violation {
    /// `pointer: message`, with `root` naming the pointer `""`.
    fn sentence(&self, root: &str) -> String {
        let at = if self.pointer.is_empty() {
            root
        } else {
            &self.pointer
        };
        format!("{at}: {}", self.message)
    }
}

/// Why a request was refused before the plugin ran.
#[derive(Debug, Clone)]
pub struct Refusal {
    /// One sentence for the client: what was checked and the first
    /// violations (`/x: "220" is not of type "number"`).
    pub detail: String,
    /// The violations (at most [`MAX_VIOLATIONS`]); empty when the body is
    /// not JSON at all.
    pub violations: Vec<Violation>,
}

impl CompiledSchema {
    /// Checks a POST body (JSON text).
    pub fn check_body(&self, route: &str, body: &str) -> Result<(), Refusal> {
        if body.trim().is_empty() {
            return Err(Refusal {
                detail: format!(
                    "{route} takes a JSON body (see its request schema); the request has none"
                ),
                violations: Vec::new(),
            });
        }
        let value: Value = serde_json::from_str(body).map_err(|e| Refusal {
            detail: format!("the request body of {route} is not JSON: {e}"),
            violations: Vec::new(),
        })?;
        self.check(
            &value,
            &format!("the request body of {route}"),
            "(the body)",
        )
    }

    /// Checks a GET query: the parameters as a JSON object, each value
    /// typed as the schema's property says (see [`query_object`]).
    pub fn check_query(
        &self,
        route: &str,
        schema: &Value,
        query: &[(String, String)],
    ) -> Result<(), Refusal> {
        let value = query_object(schema, query);
        self.check(&value, &format!("the query of {route}"), "(the query)")
    }

    fn check(&self, value: &Value, what: &str, root: &str) -> Result<(), Refusal> {
        if self.0.is_valid(value) {
            return Ok(());
        }
        let mut violations = Vec::new();
        for e in self.0.iter_errors(value) {
            violations.extend(describe(&e));
            if violations.len() >= MAX_VIOLATIONS {
                break;
            }
        }
        violations.truncate(MAX_VIOLATIONS);
        let shown: Vec<String> = violations
            .iter()
            .take(3)
            .map(|v| v.sentence(root))
            .collect();
        let more = violations.len().saturating_sub(3);
        let mut detail = format!(
            "{what} does not match the plugin's request schema: {}",
            shown.join("; ")
        );
        if more > 0 {
            detail.push_str(&format!(" (and {more} more, listed in `errors`)"));
        }
        Err(Refusal { detail, violations })
    }
}

/// The violations of one validation error: `additionalProperties` names
/// each unexpected property by its own pointer.
fn describe(e: &jsonschema::ValidationError<'_>) -> Vec<Violation> {
    use jsonschema::error::ValidationErrorKind;
    let base = e.instance_path().as_str().to_string();
    let keyword = e.kind().keyword().to_string();
    match e.kind() {
        ValidationErrorKind::AdditionalProperties { unexpected }
        | ValidationErrorKind::UnevaluatedProperties { unexpected } => unexpected
            .iter()
            .map(|name| Violation {
                pointer: format!("{base}/{}", escape(name)),
                keyword: keyword.clone(),
                message: format!("the property {name:?} is not allowed ({keyword} is false)"),
            })
            .collect(),
        _ => {
            let printed = e.instance().to_string();
            let message = if printed.chars().count() > MAX_VALUE_CHARS {
                e.masked_with("the value").to_string()
            } else {
                e.to_string()
            };
            vec![Violation {
                pointer: base,
                keyword,
                message: cut(&crate::error::one_line(&message), MAX_MESSAGE_CHARS),
            }]
        }
    }
}

/// A JSON Pointer segment (RFC 6901: `~` → `~0`, `/` → `~1`).
fn escape(segment: &str) -> String {
    segment.replace('~', "~0").replace('/', "~1")
}

fn cut(s: &str, n: usize) -> String {
    match s.char_indices().nth(n) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// A GET query as the JSON object its schema checks: one property per
/// parameter, its value typed as the schema's `properties.<name>.type`
/// allows (`integer`, `number`, `boolean`, `null`; a string otherwise, so
/// `?x=abc` for a number is refused as a string). A parameter whose type is
/// `array` collects every occurrence (each item typed as `items.type`); any
/// other parameter given twice becomes an array, which its schema refuses.
pub fn query_object(schema: &Value, query: &[(String, String)]) -> Value {
    let props = schema.get("properties").and_then(Value::as_object);
    let mut out = Map::new();
    for (name, text) in query {
        let prop = props.and_then(|p| p.get(name));
        let types = declared_types(prop);
        if types.contains(&"array") {
            let items = declared_types(prop.and_then(|p| p.get("items")));
            let item = typed(text, &items);
            match out.get_mut(name) {
                Some(Value::Array(list)) => list.push(item),
                _ => {
                    out.insert(name.clone(), Value::Array(vec![item]));
                }
            }
            continue;
        }
        let value = typed(text, &types);
        match out.get_mut(name) {
            None => {
                out.insert(name.clone(), value);
            }
            Some(Value::Array(list)) => list.push(value),
            Some(first) => {
                let first = first.take();
                out.insert(name.clone(), Value::Array(vec![first, value]));
            }
        }
    }
    Value::Object(out)
}

/// The `type`s a (sub)schema declares: one name or a list.
fn declared_types(schema: Option<&Value>) -> Vec<&str> {
    match schema.and_then(|s| s.get("type")) {
        Some(Value::String(t)) => vec![t.as_str()],
        Some(Value::Array(ts)) => ts.iter().filter_map(Value::as_str).collect(),
        _ => Vec::new(),
    }
}

/// A query value as the first declared type it parses as, else a string.
fn typed(text: &str, types: &[&str]) -> Value {
    for t in types {
        let v = match *t {
            "integer" | "number" => text
                .parse::<i64>()
                .ok()
                .map(Value::from)
                .or_else(|| text.parse::<u64>().ok().map(Value::from))
                .or_else(|| {
                    let f = text.parse::<f64>().ok().filter(|f| f.is_finite())?;
                    // "1.5" for an integer stays a number, which `integer` refuses.
                    serde_json::Number::from_f64(f).map(Value::Number)
                }),
            "boolean" => match text {
                "true" => Some(Value::Bool(true)),
                "false" => Some(Value::Bool(false)),
                _ => None,
            },
            "null" if text.is_empty() || text == "null" => Some(Value::Null),
            _ => None,
        };
        if let Some(v) = v {
            return v;
        }
    }
    Value::String(text.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn circle() -> CompiledSchema {
        compile(&json!({
            "$schema": "https://json-schema.org/draft/2020-12/schema",
            "type": "object",
            "required": ["x", "radius"],
            "additionalProperties": false,
            "properties": {
                "x": {"type": "number"},
                "radius": {"type": "number", "exclusiveMinimum": 0, "maximum": 500},
                "mode": {"enum": ["circ", "lin"]},
                "a/b": {"type": "string"}
            }
        }))
        .expect("compiles")
    }

    #[test]
    fn a_valid_body_passes() {
        let s = circle();
        assert!(s.check_body("POST /c", r#"{"x": 1, "radius": 2}"#).is_ok());
        assert!(
            s.check_body("POST /c", r#"{"x": 1.5, "radius": 2, "mode": "lin"}"#)
                .is_ok()
        );
    }

    #[test]
    fn violations_name_the_pointer_and_the_rule() {
        let s = circle();
        let r = s
            .check_body(
                "POST /c",
                r#"{"x": "220", "radius": 600, "extra": 1, "a/b": 2}"#,
            )
            .expect_err("refused");
        let has = |pointer: &str, keyword: &str, needle: &str| {
            assert!(
                r.violations.iter().any(|v| v.pointer == pointer
                    && v.keyword == keyword
                    && v.message.contains(needle)),
                "no {pointer} {keyword} {needle:?} in {:?}",
                r.violations
            );
        };
        has("/x", "type", r#""220" is not of type "number""#);
        has("/radius", "maximum", "600");
        has("/extra", "additionalProperties", "\"extra\" is not allowed");
        has("/a~1b", "type", "is not of type \"string\"");
        assert!(
            r.detail
                .starts_with("the request body of POST /c does not match")
        );
        assert!(
            r.detail.contains("/x: \"220\" is not of type \"number\""),
            "{}",
            r.detail
        );
        let r = s.check_body("POST /c", r#"{"x": 1}"#).expect_err("refused");
        assert_eq!(r.violations[0].pointer, "");
        assert_eq!(r.violations[0].keyword, "required");
        assert!(
            r.detail
                .contains("(the body): \"radius\" is a required property"),
            "{}",
            r.detail
        );
    }

    #[test]
    fn a_body_that_is_not_json_is_refused() {
        let s = compile(&json!({})).expect("compiles");
        assert!(s.check_body("POST /c", "{}").is_ok());
        let r = s.check_body("POST /c", "x=1").expect_err("not JSON");
        assert!(r.detail.contains("is not JSON"), "{}", r.detail);
        let r = s.check_body("POST /c", "").expect_err("empty");
        assert!(r.detail.contains("takes a JSON body"), "{}", r.detail);
    }

    #[test]
    fn long_values_are_masked() {
        let s = compile(&json!({"type": "object", "properties": {"t": {"type": "number"}}}))
            .expect("compiles");
        let body = json!({"t": "y".repeat(5000)}).to_string();
        let r = s.check_body("POST /c", &body).expect_err("refused");
        assert!(r.violations[0].message.len() < 300, "{:?}", r.violations);
        assert!(r.violations[0].message.contains("the value is not of type"));
    }

    #[test]
    fn schemas_that_do_not_compile_are_named() {
        for (schema, needle) in [
            (json!({"type": "nmber"}), "nmber"),
            (
                json!({"$ref": "https://example.com/s.json"}),
                "https://example.com/s.json",
            ),
            (json!({"type": "string", "pattern": "(?<=a)b"}), "(?<=a)b"),
        ] {
            let e = compile(&schema).expect_err("does not compile");
            assert!(e.contains(needle), "{needle:?} not in {e:?}");
        }
    }

    #[test]
    fn a_query_is_typed_by_its_schema() {
        let schema = json!({
            "type": "object",
            "additionalProperties": false,
            "properties": {
                "n": {"type": "integer"},
                "x": {"type": ["number", "null"]},
                "on": {"type": "boolean"},
                "tags": {"type": "array", "items": {"type": "integer"}},
                "name": {"type": "string"}
            }
        });
        let q = |pairs: &[(&str, &str)]| -> Vec<(String, String)> {
            pairs
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect()
        };
        let v = query_object(
            &schema,
            &q(&[
                ("n", "3"),
                ("x", "1.5"),
                ("on", "true"),
                ("tags", "1"),
                ("tags", "2"),
                ("name", "42"),
            ]),
        );
        assert_eq!(
            v,
            json!({"n": 3, "x": 1.5, "on": true, "tags": [1, 2], "name": "42"})
        );
        let s = compile(&schema).expect("compiles");
        assert!(s.check_query("GET /q", &schema, &q(&[("n", "3")])).is_ok());
        let r = s
            .check_query(
                "GET /q",
                &schema,
                &q(&[("n", "abc"), ("zz", "1"), ("on", "1")]),
            )
            .expect_err("refused");
        let pointers: Vec<&str> = r.violations.iter().map(|v| v.pointer.as_str()).collect();
        for p in ["/n", "/zz", "/on"] {
            assert!(pointers.contains(&p), "{p} not in {pointers:?}");
        }
        assert!(r.detail.starts_with("the query of GET /q"), "{}", r.detail);
        // A scalar given twice is an array, which the schema refuses.
        let r = s
            .check_query("GET /q", &schema, &q(&[("n", "1"), ("n", "2")]))
            .expect_err("refused");
        assert_eq!(r.violations[0].pointer, "/n");
    }
}
