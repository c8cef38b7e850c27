//! The error catalogue, served by the service itself: every problem's
//! `type` is `/errors#<code>`, and a plant network often has no internet
//! to follow a link to the repository. `GET /errors` answers
//! docs/errors.md (embedded at build time) as one self-contained HTML
//! page, each code a section with `id="<code>"`; asked for JSON
//! (`Accept: application/json`) it answers each code's title, HTTP status,
//! thesis `statuscode` and sentence, built from [`ErrorCode`] itself so
//! that it cannot go stale.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use utoipa::ToSchema;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::AppState;
use super::problem::{json_response, type_uri};
use super::thesis::statuscode;
use crate::error::ErrorCode;

/// docs/errors.md, as it was when the binary was built.
const MARKDOWN: &str = include_str!("../../../docs/errors.md");

/// Every code, in the order of the enum (a test compares this list with
/// the codes utoipa derives from the enum, so a new code cannot be missed).
pub(crate) const ALL: [ErrorCode; 48] = [
    ErrorCode::InvalidInput,
    ErrorCode::WorkspaceViolation,
    ErrorCode::SpeedLimit,
    ErrorCode::Unreachable,
    ErrorCode::SoftwareLimit,
    ErrorCode::Singularity,
    ErrorCode::ControllerOffline,
    ErrorCode::ChannelLocked,
    ErrorCode::Timeout,
    ErrorCode::ControllerError,
    ErrorCode::ControllerBusy,
    ErrorCode::Cancelled,
    ErrorCode::NotFound,
    ErrorCode::MethodNotAllowed,
    ErrorCode::PayloadTooLarge,
    ErrorCode::UnsupportedMediaType,
    ErrorCode::QueueFull,
    ErrorCode::InvalidProgram,
    ErrorCode::ProgramUnsupported,
    ErrorCode::ProgramFailed,
    ErrorCode::ProgramsUnavailable,
    ErrorCode::PluginInvalid,
    ErrorCode::PluginTimeout,
    ErrorCode::PluginMemory,
    ErrorCode::PluginTrap,
    ErrorCode::PluginBadResponse,
    ErrorCode::PluginsUnavailable,
    ErrorCode::Unauthenticated,
    ErrorCode::Forbidden,
    ErrorCode::ControlHeld,
    ErrorCode::TooManyAttempts,
    ErrorCode::Overloaded,
    ErrorCode::RequestTimeout,
    ErrorCode::ProtocolError,
    ErrorCode::Internal,
    ErrorCode::StorageUnavailable,
    ErrorCode::CommandLost,
    ErrorCode::Gone,
    ErrorCode::ShuttingDown,
    ErrorCode::PathClosed,
    ErrorCode::PathFull,
    ErrorCode::OutputNotAllowed,
    ErrorCode::UnknownSignal,
    ErrorCode::SignalNotReported,
    ErrorCode::InputTimeout,
    ErrorCode::VariableNotAllowed,
    ErrorCode::UnknownVariable,
    ErrorCode::VariablesUnavailable,
];

/// One code of the catalogue.
#[derive(Debug, Clone, Serialize, ToSchema)]
#[schema(example = json!({
    "title": "Software limit switch", "status": 422, "thesis_statuscode": 21,
    "summary": "an axis would pass its software limit switch", "type": "/errors#software_limit"
}))]
pub struct ErrorCodeInfo {
    /// The problem's `title` for this code.
    pub title: &'static str,
    /// The HTTP status a problem with this code has.
    pub status: u16,
    /// The `statuscode` the thesis endpoints (`/krl/*`) answer for it.
    pub thesis_statuscode: i32,
    /// What it means, in a sentence (the catalogue's summary table).
    pub summary: String,
    /// The problem's `type` for this code: its section of the HTML page.
    #[serde(rename = "type")]
    pub type_uri: String,
}

/// The catalogue as JSON: code → its title, status and sentence.
pub fn catalogue() -> BTreeMap<&'static str, ErrorCodeInfo> {
    let summaries = summaries(MARKDOWN);
    ALL.iter()
        .map(|&code| {
            let info = ErrorCodeInfo {
                title: code.title(),
                status: code.http_status(),
                thesis_statuscode: statuscode(code),
                summary: summaries
                    .get(code.as_str())
                    .cloned()
                    .unwrap_or_else(|| code.title().to_lowercase()),
                type_uri: type_uri(code),
            };
            (code.as_str(), info)
        })
        .collect()
}

/// The error catalogue: what each problem `code` means and what a client
/// should do about it.
///
/// Every problem's `type` is `/errors#<code>`, a link into this page,
/// served by the service itself (no internet needed). Browsers get the
/// page as HTML; a request with `Accept: application/json` gets the codes
/// as JSON (code → title, HTTP status, thesis `statuscode`, sentence).
#[utoipa::path(get, path = "/errors", tag = "service", operation_id = "getErrorCatalogue",
    responses((status = 200,
        description = "The catalogue: an HTML page with a section per code (`id` = the code), or with `Accept: application/json` an object of the codes",
        content(
            (String = "text/html"),
            (BTreeMap<String, ErrorCodeInfo> = "application/json")
        ))))]
async fn get_error_catalogue(headers: HeaderMap) -> Response {
    let mut resp = if wants_json(&headers) {
        json_response(200, "application/json", &catalogue())
    } else {
        let mut r = (StatusCode::OK, page()).into_response();
        let h = r.headers_mut();
        h.insert(
            header::CONTENT_TYPE,
            HeaderValue::from_static("text/html; charset=utf-8"),
        );
        // No script at all; the page's own style block only.
        h.insert(
            header::CONTENT_SECURITY_POLICY,
            HeaderValue::from_static(CSP),
        );
        h.insert(
            header::X_CONTENT_TYPE_OPTIONS,
            HeaderValue::from_static("nosniff"),
        );
        r
    };
    resp.headers_mut()
        .insert(header::VARY, HeaderValue::from_static("accept"));
    resp
}

const CSP: &str = "default-src 'none'; style-src 'unsafe-inline'; base-uri 'none'; \
    form-action 'none'; frame-ancestors 'none'";

/// The router of the catalogue.
pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new().routes(routes!(get_error_catalogue))
}

/// JSON only when the client asks for it more than for HTML (`*/*`, a
/// browser's list or no `Accept` at all get the page).
fn wants_json(headers: &HeaderMap) -> bool {
    let mut json = 0.0_f32;
    let mut html = 0.0_f32;
    for value in headers.get_all(header::ACCEPT) {
        let Ok(value) = value.to_str() else { continue };
        for range in value.split(',') {
            let mut parts = range.split(';');
            let media = parts.next().unwrap_or_default().trim().to_ascii_lowercase();
            let q = parts
                .filter_map(|p| p.trim().strip_prefix("q="))
                .find_map(|q| q.trim().parse::<f32>().ok())
                .unwrap_or(1.0);
            match media.as_str() {
                "application/json" | "application/problem+json" => json = json.max(q),
                "text/html" | "application/xhtml+xml" => html = html.max(q),
                _ => {}
            }
        }
    }
    json > 0.0 && json > html
}

/// The page, rendered once.
fn page() -> &'static str {
    static PAGE: OnceLock<String> = OnceLock::new();
    PAGE.get_or_init(|| {
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <title>kuka-bridge error codes</title>\n<style>{STYLE}</style>\n</head>\n<body>\n\
             <p class=\"note\">kuka-bridge {version}: the error codes of this service \
             (<a href=\"/docs/\">API documentation</a>). As JSON: <code>GET /errors</code> \
             with <code>Accept: application/json</code>.</p>\n{body}</body>\n</html>\n",
            version = env!("CARGO_PKG_VERSION"),
            body = render_markdown(MARKDOWN),
        )
    })
}

const STYLE: &str = "body{font:15px/1.5 system-ui,sans-serif;max-width:60em;margin:2em auto;padding:0 1em;color:#222}\
    code,pre{font-family:ui-monospace,Consolas,monospace;background:#f3f3f3;border-radius:3px}\
    code{padding:0 .2em}pre{padding:.6em;overflow-x:auto}\
    table{border-collapse:collapse;margin:.6em 0}th,td{border:1px solid #ccc;padding:.2em .5em;text-align:left;vertical-align:top}\
    h2{border-top:1px solid #ddd;padding-top:.6em}:target{background:#fff6cc}.note{color:#555}";

/// The "in short" column of the summary table, by code: rows such as
/// ``| [`invalid_input`](#invalid_input) | 422 | 10 | malformed request … |``.
fn summaries(markdown: &str) -> BTreeMap<String, String> {
    summary_rows(markdown)
        .into_iter()
        .map(|cells| {
            let sentence = cells.last().cloned().unwrap_or_default().replace('`', "");
            (cells[0].clone(), sentence)
        })
        .collect()
}

/// The summary table's rows: the code (first cell without its link), then
/// the other cells as written.
fn summary_rows(markdown: &str) -> Vec<Vec<String>> {
    markdown
        .lines()
        .filter(|l| l.starts_with("| [`"))
        .filter_map(|l| {
            let mut cells = table_cells(l);
            let first = cells.first()?;
            let code = first.strip_prefix("[`")?.split('`').next()?.to_string();
            cells[0] = code;
            (cells.len() >= 4).then_some(cells)
        })
        .collect()
}

// ---------------------------------------------------------------------------
// Markdown → HTML. A minimal conversion of the subset docs/errors.md uses
// (headings, paragraphs, `-` lists, pipe tables, fenced code, `---`, inline
// code, **bold**, links) rather than a Markdown crate: none is in the
// dependency tree yet, and a test renders the real file and checks the
// anchors, so a construct the conversion lacks shows up as plain text, not
// as a broken page.
// ---------------------------------------------------------------------------

/// The HTML of a Markdown document (the subset above).
pub(crate) fn render_markdown(md: &str) -> String {
    let mut out = String::new();
    let lines: Vec<&str> = md.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let trimmed = line.trim();
        if trimmed.is_empty() {
            i += 1;
        } else if let Some(lang) = trimmed.strip_prefix("```") {
            let mut code = String::new();
            i += 1;
            while i < lines.len() && !lines[i].trim_start().starts_with("```") {
                code.push_str(lines[i]);
                code.push('\n');
                i += 1;
            }
            i += 1; // the closing fence
            let class = if lang.is_empty() {
                String::new()
            } else {
                format!(" class=\"language-{}\"", escape(lang))
            };
            out.push_str(&format!(
                "<pre><code{class}>{}</code></pre>\n",
                escape(&code)
            ));
        } else if let Some((level, text)) = heading(trimmed) {
            out.push_str(&format!(
                "<h{level} id=\"{}\">{}</h{level}>\n",
                escape(&slug(text)),
                inline(text)
            ));
            i += 1;
        } else if trimmed.chars().all(|c| c == '-') && trimmed.len() >= 3 {
            out.push_str("<hr>\n");
            i += 1;
        } else if trimmed.starts_with('|') {
            let start = i;
            while i < lines.len() && lines[i].trim_start().starts_with('|') {
                i += 1;
            }
            out.push_str(&table(&lines[start..i]));
        } else if trimmed.starts_with("- ") {
            out.push_str("<ul>\n");
            while i < lines.len() && lines[i].trim_start().starts_with("- ") {
                let mut item = lines[i].trim_start()[2..].trim().to_string();
                i += 1;
                // Continuation lines: indented, not a new item or block.
                while i < lines.len()
                    && lines[i].starts_with(' ')
                    && !lines[i].trim().is_empty()
                    && !lines[i].trim_start().starts_with("- ")
                {
                    item.push(' ');
                    item.push_str(lines[i].trim());
                    i += 1;
                }
                out.push_str(&format!("<li>{}</li>\n", inline(&item)));
            }
            out.push_str("</ul>\n");
        } else {
            let mut para = Vec::new();
            while i < lines.len() && !ends_paragraph(lines[i]) {
                para.push(lines[i].trim());
                i += 1;
            }
            out.push_str(&format!("<p>{}</p>\n", inline(&para.join("\n"))));
        }
    }
    out
}

/// A line that ends a paragraph: blank, or the start of another block.
fn ends_paragraph(line: &str) -> bool {
    let t = line.trim();
    t.is_empty()
        || t.starts_with("```")
        || t.starts_with('|')
        || t.starts_with("- ")
        || heading(t).is_some()
        || (t.len() >= 3 && t.chars().all(|c| c == '-'))
}

/// `## Text` → (2, "Text").
fn heading(line: &str) -> Option<(usize, &str)> {
    let level = line.chars().take_while(|&c| c == '#').count();
    if !(1..=6).contains(&level) {
        return None;
    }
    line[level..]
        .strip_prefix(' ')
        .map(|text| (level, text.trim()))
}

/// A heading's anchor as GitHub makes it: lower case, spaces to `-`, only
/// letters, digits, `-` and `_` kept (`## invalid_input` → `invalid_input`,
/// `## Thesis statuscode` → `thesis-statuscode`).
fn slug(text: &str) -> String {
    text.to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// A pipe table (header, separator, rows).
fn table(lines: &[&str]) -> String {
    let mut out = String::from("<table>\n");
    let separator = |l: &str| {
        table_cells(l)
            .iter()
            .all(|c| !c.is_empty() && c.chars().all(|ch| matches!(ch, '-' | ':' | ' ')))
    };
    let has_head = lines.len() >= 2 && separator(lines[1]);
    for (n, line) in lines.iter().enumerate() {
        if has_head && n == 1 {
            continue;
        }
        let tag = if has_head && n == 0 { "th" } else { "td" };
        out.push_str("<tr>");
        for cell in table_cells(line) {
            out.push_str(&format!("<{tag}>{}</{tag}>", inline(&cell)));
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</table>\n");
    out
}

/// The cells of a table row; a `|` inside a code span or escaped as `\|`
/// is text.
fn table_cells(line: &str) -> Vec<String> {
    let line = line.trim();
    let line = line.strip_prefix('|').unwrap_or(line);
    let line = line.strip_suffix('|').unwrap_or(line);
    let mut cells = Vec::new();
    let mut cell = String::new();
    let mut in_code = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '`' => {
                in_code = !in_code;
                cell.push(c);
            }
            '\\' if chars.peek() == Some(&'|') => {
                cell.push('|');
                chars.next();
            }
            '|' if !in_code => cells.push(std::mem::take(&mut cell).trim().to_string()),
            _ => cell.push(c),
        }
    }
    cells.push(cell.trim().to_string());
    cells
}

/// Inline Markdown: `code`, **bold**, [links](target); everything else is
/// escaped text.
fn inline(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    let mut bold = false;
    while let Some(c) = rest.chars().next() {
        if c == '`'
            && let Some(end) = rest[1..].find('`')
        {
            out.push_str(&format!("<code>{}</code>", escape(&rest[1..=end])));
            rest = &rest[end + 2..];
        } else if rest.starts_with("**") {
            out.push_str(if bold { "</strong>" } else { "<strong>" });
            bold = !bold;
            rest = &rest[2..];
        } else if c == '['
            && let Some((label, target, len)) = link(rest)
        {
            // Links within the page and to the web work offline or not at
            // all anyway; other documents are not served: their name only.
            if target.starts_with('#')
                || target.starts_with("http://")
                || target.starts_with("https://")
            {
                out.push_str(&format!(
                    "<a href=\"{}\">{}</a>",
                    escape(target),
                    inline(label)
                ));
            } else {
                out.push_str(&inline(label));
            }
            rest = &rest[len..];
        } else {
            out.push_str(&escape(&rest[..c.len_utf8()]));
            rest = &rest[c.len_utf8()..];
        }
    }
    if bold {
        out.push_str("</strong>");
    }
    out
}

/// `[label](target)` at the start of `s`: label, target, length in bytes.
fn link(s: &str) -> Option<(&str, &str, usize)> {
    let close = s.find("](")?;
    let label = &s[1..close];
    if label.contains('[') || label.contains(']') {
        return None;
    }
    let after = &s[close + 2..];
    let end = after.find(')')?;
    let target = &after[..end];
    if target.contains(char::is_whitespace) {
        return None;
    }
    Some((label, target, close + 2 + end + 1))
}

/// HTML-escapes text (also for attribute values).
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`ALL`] is every code of the enum, in its order: the list utoipa
    /// derives from the enum itself is the reference.
    #[test]
    fn all_is_every_error_code() {
        let schema =
            serde_json::to_value(<ErrorCode as utoipa::PartialSchema>::schema()).expect("schema");
        let derived: Vec<&str> = schema["enum"]
            .as_array()
            .expect("an enum of strings")
            .iter()
            .filter_map(serde_json::Value::as_str)
            .collect();
        let listed: Vec<&str> = ALL.iter().map(|c| c.as_str()).collect();
        assert_eq!(listed, derived, "add the new code to api::errors::ALL");
    }

    /// docs/errors.md has a section (an anchor of the page) and a row of
    /// the summary table for every code, and the table's HTTP status and
    /// thesis statuscode are the ones the service answers.
    #[test]
    fn every_code_has_a_section_and_a_true_summary_row() {
        let html = page();
        let rows = summary_rows(MARKDOWN);
        for code in ALL {
            let name = code.as_str();
            assert!(
                html.contains(&format!("id=\"{name}\"")),
                "docs/errors.md has no `## {name}` section"
            );
            let row = rows
                .iter()
                .find(|r| r[0] == name)
                .unwrap_or_else(|| panic!("docs/errors.md's table has no row for {name}"));
            assert_eq!(
                row[1],
                code.http_status().to_string(),
                "HTTP status of {name}"
            );
            assert_eq!(
                row[2],
                statuscode(code).to_string(),
                "thesis statuscode of {name}"
            );
        }
        assert_eq!(rows.len(), ALL.len(), "one row per code");
        let c = catalogue();
        assert_eq!(c.len(), ALL.len());
        assert_eq!(
            c["software_limit"].summary,
            "an axis would pass its software limit switch"
        );
        assert_eq!(c["software_limit"].type_uri, "/errors#software_limit");
    }

    #[test]
    fn markdown_subset() {
        let html = render_markdown(
            "# Title\n\nSome `a<b>` and **bold** text,\nover two lines; [x](#invalid_input), [doc](PLUGINS.md#5).\n\n\
             | code | in short |\n|---|---|\n| [`gone`](#gone) | `a|b` \\| c |\n\n- one\n  more\n- two\n\n---\n\n```json\n{\"a\": \"<\"}\n```\n\
             ### Audit-only code: `client_disconnected` (499)\n",
        );
        assert!(html.contains("<h1 id=\"title\">Title</h1>"), "{html}");
        assert!(
            html.contains("<p>Some <code>a&lt;b&gt;</code> and <strong>bold</strong> text,\nover two lines; <a href=\"#invalid_input\">x</a>, doc.</p>"),
            "{html}"
        );
        assert!(
            html.contains("<tr><th>code</th><th>in short</th></tr>"),
            "{html}"
        );
        assert!(
            html.contains("<tr><td><a href=\"#gone\"><code>gone</code></a></td><td><code>a|b</code> | c</td></tr>"),
            "{html}"
        );
        assert!(html.contains("<li>one more</li>\n<li>two</li>"), "{html}");
        assert!(html.contains("<hr>"), "{html}");
        assert!(
            html.contains("<pre><code class=\"language-json\">{&quot;a&quot;: &quot;&lt;&quot;}\n</code></pre>"),
            "{html}"
        );
        assert!(
            html.contains("id=\"audit-only-code-client_disconnected-499\""),
            "{html}"
        );
    }

    #[test]
    fn json_only_when_asked_for() {
        let with = |accept: &str| {
            let mut h = HeaderMap::new();
            h.insert(
                header::ACCEPT,
                HeaderValue::from_str(accept).expect("value"),
            );
            wants_json(&h)
        };
        assert!(!wants_json(&HeaderMap::new()));
        assert!(!with("*/*"));
        assert!(!with(
            "text/html,application/xhtml+xml,application/xml;q=0.9,*/*;q=0.8"
        ));
        assert!(with("application/json"));
        assert!(with("application/json, text/html;q=0.5"));
        assert!(!with("application/json;q=0.5, text/html"));
    }
}
