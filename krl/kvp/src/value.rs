//! KRL values as KUKAVARPROXY shows them (text in KRL's own syntax) and
//! as typed values: `100` (INT), `1.5` (REAL), `TRUE` (BOOL), `"abc"`
//! (CHAR array), `#T1` (ENUM), `{E6POS: X 1.0, Y 2.0, ...}` (a structure,
//! with or without its type name). Written by hand rather than with the
//! KRL front end (`kuka_krl`): this is the small literal syntax of one
//! value, and the service must not depend on the program parser.
//!
//! Also the check of variable names: a client names a variable, never
//! sends KRL. [`check_name`] admits an identifier (optionally `$`), array
//! indices of digits and `.FIELD` selectors, and nothing else.

use serde_json::{Map, Value, json};

/// A KRL value.
#[derive(Debug, Clone, PartialEq)]
pub enum KrlValue {
    /// INT.
    Int(i64),
    /// REAL.
    Real(f64),
    /// BOOL.
    Bool(bool),
    /// A CHAR array (or a CHAR).
    Text(String),
    /// An ENUM value, without its `#`.
    Enum(String),
    /// A structure: its type name if the text gave it, and its fields in
    /// order.
    Struct(Option<String>, Vec<(String, KrlValue)>),
}

/// Longest name [`check_name`] admits.
pub const MAX_NAME: usize = 100;

/// Longest KRL identifier (KSS 8: 24 characters).
const MAX_IDENT: usize = 24;

fn ident(s: &str) -> bool {
    let mut c = s.chars();
    matches!(c.next(), Some(f) if f.is_ascii_alphabetic() || f == '_')
        && c.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && s.len() <= MAX_IDENT
}

/// Why `name` is not a variable name, if it is not one: `[$]IDENT`, then
/// any of `[i]`, `[i,j]`, `[i,j,k]` (decimal indices) and `.IDENT`. No
/// spaces, operators, quotes, `;` or line breaks: nothing a proxy could
/// take for a statement.
pub fn check_name(name: &str) -> Result<(), String> {
    if name.is_empty() || name.len() > MAX_NAME {
        return Err(format!("a variable name has 1 to {MAX_NAME} characters"));
    }
    let bad = || {
        format!(
            "{:?} is not a variable name: a KRL identifier (optionally with $), array indices like [3] or [1,2] and .FIELD selectors only",
            name.chars().take(40).collect::<String>()
        )
    };
    let body = name.strip_prefix('$').unwrap_or(name);
    let end = body.find(['[', '.']).unwrap_or(body.len());
    if !ident(&body[..end]) {
        return Err(bad());
    }
    let mut rest = &body[end..];
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix('[') {
            let close = r.find(']').ok_or_else(bad)?;
            let idx = &r[..close];
            let parts: Vec<&str> = idx.split(',').collect();
            // A trailing empty index selects a row of a CHAR array
            // (`TOOL_NAME[3,]`, KRL's partial index); no other is empty.
            let last = parts.len() - 1;
            if parts.len() > 3
                || parts.iter().enumerate().any(|(k, p)| {
                    if p.is_empty() {
                        k == 0 || k != last
                    } else {
                        p.len() > 5 || !p.bytes().all(|b| b.is_ascii_digit())
                    }
                })
            {
                return Err(bad());
            }
            rest = &r[close + 1..];
        } else if let Some(r) = rest.strip_prefix('.') {
            let end = r.find(['[', '.']).unwrap_or(r.len());
            if !ident(&r[..end]) {
                return Err(bad());
            }
            rest = &r[end..];
        } else {
            return Err(bad());
        }
    }
    Ok(())
}

struct Parser<'a> {
    s: &'a str,
    at: usize,
}

impl<'a> Parser<'a> {
    fn ws(&mut self) {
        while self.s[self.at..].starts_with([' ', '\t', '\r', '\n']) {
            self.at += 1;
        }
    }

    fn word(&mut self) -> &'a str {
        let r = &self.s[self.at..];
        let n = r
            .find(|c: char| !(c.is_ascii_alphanumeric() || "_$.+-".contains(c)))
            .unwrap_or(r.len());
        self.at += n;
        &r[..n]
    }

    fn value(&mut self, depth: usize) -> Option<KrlValue> {
        if depth > 8 {
            return None;
        }
        self.ws();
        let r = &self.s[self.at..];
        if let Some(q) = r.strip_prefix('"') {
            let end = q.find('"')?;
            self.at += end + 2;
            return Some(KrlValue::Text(q[..end].to_string()));
        }
        if let Some(q) = r.strip_prefix('\'') {
            let end = q.find('\'')?;
            self.at += end + 2;
            return Some(KrlValue::Text(q[..end].to_string()));
        }
        if r.starts_with('#') {
            self.at += 1;
            let w = self.word();
            return ident(w).then(|| KrlValue::Enum(w.to_string()));
        }
        if r.starts_with('{') {
            self.at += 1;
            return self.structure(depth);
        }
        let w = self.word();
        match w.to_ascii_uppercase().as_str() {
            "TRUE" => return Some(KrlValue::Bool(true)),
            "FALSE" => return Some(KrlValue::Bool(false)),
            _ => {}
        }
        if let Ok(i) = w.parse::<i64>() {
            return Some(KrlValue::Int(i));
        }
        w.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .map(KrlValue::Real)
    }

    fn structure(&mut self, depth: usize) -> Option<KrlValue> {
        self.ws();
        // `{E6POS: X 1, ...}`: the type name before a colon.
        let mark = self.at;
        let w = self.word();
        self.ws();
        let type_name = if !w.is_empty() && self.s[self.at..].starts_with(':') {
            self.at += 1;
            Some(w.to_string())
        } else {
            self.at = mark;
            None
        };
        let mut fields = Vec::new();
        loop {
            self.ws();
            if self.s[self.at..].starts_with('}') {
                self.at += 1;
                return Some(KrlValue::Struct(type_name, fields));
            }
            let name = self.word();
            if !ident(name) {
                return None;
            }
            let v = self.value(depth + 1)?;
            fields.push((name.to_ascii_uppercase(), v));
            self.ws();
            if self.s[self.at..].starts_with(',') {
                self.at += 1;
            } else if !self.s[self.at..].starts_with('}') {
                return None;
            }
        }
    }
}

impl KrlValue {
    /// Parses a value's text as KUKAVARPROXY shows it.
    pub fn parse(text: &str) -> Option<KrlValue> {
        let mut p = Parser { s: text, at: 0 };
        let v = p.value(0)?;
        p.ws();
        (p.at == text.len()).then_some(v)
    }

    /// The KRL type name: `INT`, `REAL`, `BOOL`, `CHAR`, `ENUM`, or the
    /// structure's type (`STRUC` when the text did not name it).
    pub fn type_name(&self) -> String {
        match self {
            KrlValue::Int(_) => "INT".into(),
            KrlValue::Real(_) => "REAL".into(),
            KrlValue::Bool(_) => "BOOL".into(),
            KrlValue::Text(_) => "CHAR".into(),
            KrlValue::Enum(_) => "ENUM".into(),
            KrlValue::Struct(t, _) => t.clone().unwrap_or_else(|| "STRUC".into()),
        }
    }

    /// As JSON: numbers, booleans, strings, `{"enum": "T1"}`, and objects
    /// for structures (fields upper-case, as KRL writes them).
    pub fn to_json(&self) -> Value {
        match self {
            KrlValue::Int(i) => json!(i),
            KrlValue::Real(r) => json!(r),
            KrlValue::Bool(b) => json!(b),
            KrlValue::Text(t) => json!(t),
            KrlValue::Enum(e) => json!({ "enum": e }),
            KrlValue::Struct(_, fields) => Value::Object(
                fields
                    .iter()
                    .map(|(k, v)| (k.clone(), v.to_json()))
                    .collect::<Map<String, Value>>(),
            ),
        }
    }

    /// The value a client sent as JSON, checked: integers, finite numbers,
    /// booleans, strings of printable ASCII without `"` (at most 128),
    /// `{"enum": "NAME"}`, and objects of fields (KRL identifiers) with
    /// such values, at most 4 levels deep. Arrays and `null` are refused.
    pub fn from_json(v: &Value) -> Result<KrlValue, String> {
        Self::from_json_at(v, 0)
    }

    fn from_json_at(v: &Value, depth: usize) -> Result<KrlValue, String> {
        if depth > 4 {
            return Err("structures nest at most 4 levels".into());
        }
        match v {
            Value::Bool(b) => Ok(KrlValue::Bool(*b)),
            Value::Number(n) => match (n.as_i64(), n.as_f64()) {
                (Some(i), _) if i32::try_from(i).is_ok() => Ok(KrlValue::Int(i)),
                (Some(i), _) => Err(format!("{i} is outside KRL's INT range")),
                (None, Some(f)) if f.is_finite() && f.abs() < 1e30 => Ok(KrlValue::Real(f)),
                _ => Err(format!("{n} is not a KRL number")),
            },
            Value::String(s) => {
                if s.len() > 128 || !s.bytes().all(|b| (0x20..0x7f).contains(&b) && b != b'"') {
                    Err("a text value has at most 128 printable ASCII characters and no \"".into())
                } else {
                    Ok(KrlValue::Text(s.clone()))
                }
            }
            Value::Object(o) => {
                if let (1, Some(Value::String(e))) = (o.len(), o.get("enum")) {
                    return if ident(e) {
                        Ok(KrlValue::Enum(e.clone()))
                    } else {
                        Err(format!(
                            "{:?} is not an ENUM value name",
                            e.chars().take(30).collect::<String>()
                        ))
                    };
                }
                if o.is_empty() || o.len() > 32 {
                    return Err("a structure has 1 to 32 fields".into());
                }
                let mut fields = Vec::with_capacity(o.len());
                for (k, v) in o {
                    if !ident(k) {
                        return Err(format!(
                            "{:?} is not a field name",
                            k.chars().take(30).collect::<String>()
                        ));
                    }
                    fields.push((k.to_ascii_uppercase(), Self::from_json_at(v, depth + 1)?));
                }
                Ok(KrlValue::Struct(None, fields))
            }
            Value::Array(_) => {
                Err("arrays are written element by element (name[1], name[2], ...)".into())
            }
            Value::Null => Err("null is not a KRL value".into()),
        }
    }

    /// The value as KRL text (what KUKAVARPROXY writes into the variable).
    pub fn to_krl(&self) -> String {
        match self {
            KrlValue::Int(i) => i.to_string(),
            KrlValue::Real(r) => {
                let s = format!("{r}");
                if s.contains(['.', 'e', 'E']) {
                    s
                } else {
                    format!("{s}.0")
                }
            }
            KrlValue::Bool(b) => if *b { "TRUE" } else { "FALSE" }.into(),
            KrlValue::Text(t) => format!("\"{t}\""),
            KrlValue::Enum(e) => format!("#{e}"),
            KrlValue::Struct(t, fields) => {
                let inner: Vec<String> = fields
                    .iter()
                    .map(|(k, v)| format!("{k} {}", v.to_krl()))
                    .collect();
                match t {
                    Some(t) => format!("{{{t}: {}}}", inner.join(", ")),
                    None => format!("{{{}}}", inner.join(", ")),
                }
            }
        }
    }
}
