//! Who may call what: the three roles and the one table that gives every
//! route the role it needs, whether it needs control of the robot and
//! whether it is audited. The auth layer and the OpenAPI document both
//! read this table, so the document always says what the service enforces.

use std::fmt;

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// A token's role; each includes the ones below it.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, ToSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// Reads state, position, jobs, events and documentation.
    Viewer,
    /// Moves the robot: motions, stop, home, tool/base/speed, programs and
    /// plugin routes.
    Operator,
    /// Installs and removes plugins and programs, manages tokens, reads
    /// the audit trail.
    Admin,
}

impl Role {
    /// The role as written in tokens and documents.
    pub fn as_str(self) -> &'static str {
        match self {
            Role::Viewer => "viewer",
            Role::Operator => "operator",
            Role::Admin => "admin",
        }
    }

    /// Parses `viewer`, `operator` or `admin`.
    pub fn parse(s: &str) -> Option<Role> {
        match s {
            "viewer" => Some(Role::Viewer),
            "operator" => Some(Role::Operator),
            "admin" => Some(Role::Admin),
            _ => None,
        }
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What a route requires.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rule {
    /// The least role; `None` means no token at all (health, documentation).
    pub role: Option<Role>,
    /// Refused with `control_held` while another client holds control.
    pub control: bool,
    /// Recorded in the audit trail.
    pub audited: bool,
    /// Stop: never shed under load, never refused by the failed-attempt
    /// limiter (a valid token always gets through), never needs control.
    pub safety: bool,
}

const fn rule_of(role: Option<Role>, control: bool, audited: bool) -> Rule {
    Rule {
        role,
        control,
        audited,
        safety: false,
    }
}

const PUBLIC: Rule = rule_of(None, false, false);
const READ: Rule = rule_of(Some(Role::Viewer), false, false);
/// Moves or changes the robot: needs control when someone holds it.
const OPERATE: Rule = rule_of(Some(Role::Operator), true, true);
/// Taking and releasing control: any operator.
const CONTROL: Rule = rule_of(Some(Role::Operator), false, true);
/// Stop: any operator, always (see [`Rule::safety`]).
const STOP: Rule = Rule {
    safety: true,
    ..CONTROL
};
const ADMIN: Rule = rule_of(Some(Role::Admin), false, true);
/// Installs code that then runs on the robot (thesis upload-and-run).
const ADMIN_OPERATE: Rule = rule_of(Some(Role::Admin), true, true);
const ADMIN_READ: Rule = rule_of(Some(Role::Admin), false, false);
/// A route missing from the table (fail closed).
const UNKNOWN: Rule = rule_of(Some(Role::Admin), true, true);

/// Every route: method, axum path template, rule. Plugin routes are the
/// catch-all `/api/v1/plugins/{name}/{*path}`.
const TABLE: &[(&str, &str, Rule)] = &[
    ("GET", "/health", PUBLIC),
    // Thesis endpoints (all POST; two of them only read).
    ("POST", "/krl/ptp", OPERATE),
    ("POST", "/krl/linmov", OPERATE),
    ("POST", "/krl/circ", OPERATE),
    ("POST", "/krl/base", OPERATE),
    ("POST", "/krl/tcp", OPERATE),
    ("POST", "/krl/getpos", READ),
    ("POST", "/krl/gettcp", READ),
    ("POST", "/krl/uploadfile", ADMIN_OPERATE),
    // Robot state and settings.
    ("GET", "/api/v1/state", READ),
    ("GET", "/api/v1/model", READ),
    ("GET", "/api/v1/workspace", READ),
    ("GET", "/api/v1/position", READ),
    ("GET", "/api/v1/tool", READ),
    ("PUT", "/api/v1/tool", OPERATE),
    ("GET", "/api/v1/base", READ),
    ("PUT", "/api/v1/base", OPERATE),
    ("GET", "/api/v1/io", READ),
    ("GET", "/api/v1/io/config", READ),
    ("PUT", "/api/v1/io/config", ADMIN),
    ("DELETE", "/api/v1/io/config", ADMIN),
    ("GET", "/api/v1/io/inputs/{signal}", READ),
    ("GET", "/api/v1/io/outputs/{signal}", READ),
    ("PUT", "/api/v1/io/outputs/{signal}", OPERATE),
    ("GET", "/api/v1/io/analog", READ),
    ("PUT", "/api/v1/io/analog-outputs/{signal}", OPERATE),
    ("GET", "/api/v1/io/analog-outputs/{signal}", READ),
    ("GET", "/api/v1/io/analog-inputs/{signal}", READ),
    ("GET", "/api/v1/variables/{name}", READ),
    ("PUT", "/api/v1/variables/{name}", OPERATE),
    ("GET", "/api/v1/tools/{number}", READ),
    ("POST", "/api/v1/tools/{number}/select", OPERATE),
    ("GET", "/api/v1/bases/{number}", READ),
    ("POST", "/api/v1/bases/{number}/select", OPERATE),
    ("GET", "/api/v1/speed", READ),
    ("PUT", "/api/v1/speed", OPERATE),
    ("POST", "/api/v1/reset", OPERATE),
    // Motion and jobs.
    ("POST", "/api/v1/motions", OPERATE),
    ("POST", "/api/v1/home", OPERATE),
    ("POST", "/api/v1/stop", STOP),
    ("GET", "/api/v1/jobs", READ),
    ("GET", "/api/v1/jobs/{id}", READ),
    ("DELETE", "/api/v1/jobs/{id}", OPERATE),
    ("POST", "/api/v1/paths", OPERATE),
    ("GET", "/api/v1/paths/{id}", READ),
    ("POST", "/api/v1/paths/{id}/motions", OPERATE),
    ("DELETE", "/api/v1/paths/{id}", OPERATE),
    ("GET", "/api/v1/events", READ),
    ("GET", "/api/v1/events/recent", READ),
    // Control of the robot.
    ("GET", "/api/v1/control", READ),
    ("POST", "/api/v1/control", CONTROL),
    ("DELETE", "/api/v1/control", CONTROL),
    // Programs.
    ("GET", "/api/v1/programs", READ),
    ("POST", "/api/v1/programs", ADMIN),
    ("GET", "/api/v1/programs/{name}", READ),
    ("DELETE", "/api/v1/programs/{name}", ADMIN),
    ("POST", "/api/v1/programs/{name}/run", OPERATE),
    // Plugins.
    ("GET", "/api/v1/plugins", READ),
    ("GET", "/api/v1/plugins/{name}", READ),
    ("PUT", "/api/v1/plugins/{name}", ADMIN),
    ("DELETE", "/api/v1/plugins/{name}", ADMIN),
    ("*", "/api/v1/plugins/{name}/{*path}", OPERATE),
    // Access administration.
    ("GET", "/api/v1/tokens", ADMIN_READ),
    ("POST", "/api/v1/tokens", ADMIN),
    ("DELETE", "/api/v1/tokens/{name}", ADMIN),
    ("GET", "/api/v1/audit", ADMIN_READ),
    // Simulator (only in --simulate mode).
    ("GET", "/api/v1/sim", READ),
    ("GET", "/api/v1/sim/trace", READ),
    ("DELETE", "/api/v1/sim/trace", OPERATE),
    ("POST", "/api/v1/sim/acknowledge", OPERATE),
    ("PUT", "/api/v1/sim/inputs/{index}", OPERATE),
    // The simulated emergency stop: never held back by the control lease.
    ("PUT", "/api/v1/sim/safety", STOP),
    ("PUT", "/api/v1/sim/analog-inputs/{index}", OPERATE),
    // Documentation.
    ("GET", "/openapi.json", PUBLIC),
    ("GET", "/errors", PUBLIC),
    ("GET", "/", PUBLIC),
    // The dashboard's files (the data it shows needs a token).
    ("GET", "/ui/{*path}", PUBLIC),
];

/// The rule for a request, by method and matched route template. HEAD is
/// GET without the body. Routes missing from the table need an admin (fail
/// closed); the documentation under `/docs` is public so that Swagger UI
/// loads before you authorize.
pub fn rule(method: &str, template: &str) -> Rule {
    if template == "/docs" || template.starts_with("/docs/") {
        return PUBLIC;
    }
    let method = if method == "HEAD" { "GET" } else { method };
    if let Some((_, _, r)) = TABLE
        .iter()
        .find(|(m, t, _)| (*m == "*" || *m == method) && *t == template)
    {
        return *r;
    }
    // Every method a route serves is in the table (a test checks the
    // documented ones): another method on a known route is answered 405
    // by the router, with nothing to protect or record.
    if TABLE.iter().any(|(_, t, _)| *t == template) {
        return PUBLIC;
    }
    UNKNOWN
}

/// The rule of a documented operation (OpenAPI path with `{param}`s);
/// `None` if the table does not know it.
pub fn documented_rule(method: &str, openapi_path: &str) -> Option<Rule> {
    TABLE
        .iter()
        .find(|(m, t, _)| (*m == "*" || m.eq_ignore_ascii_case(method)) && *t == openapi_path)
        .map(|(_, _, r)| *r)
        .or_else(|| {
            openapi_path
                .starts_with("/api/v1/plugins/")
                .then(|| rule("*", "/api/v1/plugins/{name}/{*path}"))
                .filter(|_| openapi_path.matches('/').count() > 4)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_routes_need_an_admin() {
        assert_eq!(rule("PATCH", "/api/v1/new").role, Some(Role::Admin));
        assert_eq!(rule("GET", "/docs/{*rest}").role, None);
        assert!(!rule("POST", "/api/v1/stop").control);
        assert!(rule("POST", "/api/v1/stop").safety);
        assert_eq!(rule("HEAD", "/health").role, None);
        assert_eq!(rule("PATCH", "/api/v1/state"), PUBLIC, "405, not 401");
        assert_eq!(rule("HEAD", "/api/v1/stop"), PUBLIC, "405");
        assert!(!rule("HEAD", "/api/v1/state").audited);
        assert!(rule("POST", "/api/v1/plugins/{name}/{*path}").control);
    }
}
