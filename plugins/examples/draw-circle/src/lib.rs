//! `draw-circle`: a kuka-bridge plugin that draws a horizontal circle.
//!
//! `POST /api/v1/plugins/draw-circle/circle` with
//! `{"x": 200, "y": 0, "z": 70, "radius": 40}` (mm, the centre and the height;
//! optional `"speed_m_s"`, `"mode": "circ" | "lin" | "spl"` and `"segments"`)
//! reads the robot's position, keeps its orientation (A, B, C) and runs ONE
//! blended batch: a PTP to the start point (x + radius, y, z), then the circle
//! — two CIRC half circles, `segments` LINs in `lin` mode, or `segments` SPL
//! points in `spl` mode (spline blocks of 8 points, through the `splines`
//! interface) — back to the start point.
//!
//! With `"turns": n` (lin or spl mode, 2..=1000) it draws the circle n times as
//! ONE path that never stops: it opens a path (the `paths` interface) and
//! appends one turn at a time (in spl mode with `splines.append-spline-motions`),
//! so it never holds more than one turn in memory, however many turns are asked
//! for.
//!
//! Every motion goes through the bridge's own checks (reachability, limits,
//! singularities, speed caps), exactly as a `POST /api/v1/motions` would.
//!
//! Build: `cargo build --release --target wasm32-wasip2` (or `../build.sh OUT`).

wit_bindgen::generate!({
    path: "../../wit",
    world: "bridge-plugin",
    // `MotionParams { approx_mm: .., ..Default::default() }`: all three fields are options.
    additional_type_attributes: {
        "kuka-bridge:plugin/types@0.1.0/motion-params": [#[derive(Default)]],
    },
});

use exports::kuka_bridge::plugin::plugin::{Description, Guest, Request, Response, Route};
use kuka_bridge::plugin::host::{self, LogLevel};
use kuka_bridge::plugin::paths;
use kuka_bridge::plugin::splines::{self, AnyMotion, SplPoint};
use kuka_bridge::plugin::types::{
    CircMotion, HostError, LinMotion, Motion, MotionParams, Point, Pose, Position, PtpMotion,
};
use serde::Deserialize;
use serde_json::json;

/// The version this plugin describes (`0.2.0` with the `next-version` feature).
const VERSION: &str = if cfg!(feature = "next-version") {
    "0.2.0"
} else {
    "0.1.0"
};

/// Blending between the segments of the circle (mm).
const APPROX_MM: f64 = 1.0;

/// How the circle is drawn.
#[derive(Deserialize, Clone, Copy, Default, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
enum Mode {
    /// Two CIRC motions (half circles).
    #[default]
    Circ,
    /// `segments` LIN motions (a regular polygon).
    Lin,
    /// `segments` SPL points (spline blocks: a smooth curve through them).
    Spl,
}

/// The request body of `POST /circle`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct CircleRequest {
    /// Centre X (mm, current base).
    x: f64,
    /// Centre Y (mm).
    y: f64,
    /// Height of the circle (mm).
    z: f64,
    /// Radius (mm), in (0, 500].
    radius: f64,
    /// Path speed of the circle (m/s).
    #[serde(default = "default_speed")]
    speed_m_s: f64,
    /// `circ` (default), `lin` or `spl`.
    #[serde(default)]
    mode: Mode,
    /// Number of LINs (`lin` mode) or SPL points (`spl` mode), 8..=720.
    #[serde(default = "default_segments")]
    segments: u32,
    /// Times round, 1..=1000 (more than 1: `lin` or `spl` mode, streamed as
    /// a path).
    #[serde(default = "default_turns")]
    turns: u32,
}

fn default_turns() -> u32 {
    1
}

fn default_speed() -> f64 {
    0.1
}

fn default_segments() -> u32 {
    36
}

/// The plugin; its trait implementation is exported with `export!` below.
struct DrawCircle;

impl Guest for DrawCircle {
    fn describe() -> Description {
        Description {
            name: "draw-circle".into(),
            version: VERSION.into(),
            routes: vec![Route {
                method: "POST".into(),
                path: "/circle".into(),
                summary: "Draw a horizontal circle (PTP to its start, then 2 CIRCs, n LINs \
                          or n SPL points), keeping the current orientation"
                    .into(),
                request_schema: request_schema().to_string(),
                response_schema: response_schema().to_string(),
            }],
        }
    }

    fn handle(req: Request) -> Response {
        if (req.method.as_str(), req.path.as_str()) != ("POST", "/circle") {
            let detail = format!("draw-circle has no route {} {}", req.method, req.path);
            return error(404, "not_found", &detail);
        }
        let circle = match parse(&req.body) {
            Ok(c) => c,
            Err(detail) => return error(400, "bad_request", &detail),
        };
        // Keep the tool's current orientation: the pen stays as it is held now.
        let here = match host::get_position() {
            Ok(p) => p,
            Err(e) => return host_error(&e),
        };
        if circle.turns > 1 {
            return stream_turns(&circle, &here.pose);
        }
        if circle.mode == Mode::Spl {
            return run_spline_circle(&circle, &here.pose);
        }
        let motions = circle_motions(&circle, &here.pose);
        host::log(
            LogLevel::Info,
            &format!(
                "circle r={} mm at ({}, {}, {}), {:?} mode, {} motions",
                circle.radius,
                circle.x,
                circle.y,
                circle.z,
                circle.mode,
                motions.len()
            ),
        );
        match host::run_motions(&motions) {
            Ok(done) => Response {
                status: 200,
                body: json!({
                    "completed": done.completed,
                    "motions": motions.len(),
                    "position": position_json(&done.position),
                })
                .to_string(),
            },
            Err(e) => host_error(&e),
        }
    }
}

/// Parses and checks the request body; the error is a sentence for the client.
fn parse(body: &str) -> Result<CircleRequest, String> {
    let c: CircleRequest = serde_json::from_str(body)
        .map_err(|e| format!("The request body is not a valid circle: {e}."))?;
    if !(c.radius > 0.0 && c.radius <= 500.0) {
        return Err(format!(
            "radius must be more than 0 and at most 500 mm, not {}.",
            c.radius
        ));
    }
    if c.speed_m_s <= 0.0 {
        return Err(format!(
            "speed_m_s must be more than 0, not {}.",
            c.speed_m_s
        ));
    }
    if !(1..=1000).contains(&c.turns) {
        return Err(format!(
            "turns must be between 1 and 1000, not {}.",
            c.turns
        ));
    }
    if c.turns > 1 && c.mode == Mode::Circ {
        return Err("turns above 1 need \"mode\": \"lin\" or \"spl\".".into());
    }
    if c.mode != Mode::Circ && !(8..=720).contains(&c.segments) {
        return Err(format!(
            "segments must be between 8 and 720, not {}.",
            c.segments
        ));
    }
    Ok(c)
}

/// The point of the circle at `deg` degrees (from +X towards +Y), with the
/// kept orientation.
fn circle_point(c: &CircleRequest, orientation: &Pose, deg: f64) -> Pose {
    let rad = deg.to_radians();
    Pose {
        x: c.x + c.radius * rad.cos(),
        y: c.y + c.radius * rad.sin(),
        z: c.z,
        ..*orientation
    }
}

/// The batch: a PTP to the start point (angle 0°, that is +X of the centre),
/// then the circle counter-clockwise seen from above (from +X towards +Y).
/// In spl mode only the PTP: the circle's points are [`spline_points`].
fn circle_motions(c: &CircleRequest, orientation: &Pose) -> Vec<Motion> {
    let at = |deg: f64| circle_point(c, orientation, deg);
    let aux = |deg: f64| {
        let p = at(deg);
        Point {
            x: p.x,
            y: p.y,
            z: p.z,
        }
    };
    let start = at(0.0);
    let blend = MotionParams {
        velocity: Some(c.speed_m_s),
        approx_mm: Some(APPROX_MM),
        ..Default::default()
    };
    let exact = MotionParams {
        approx_mm: Some(0.0),
        ..blend
    };

    // The PTP stops exactly on the start point (bridge's default PTP speed,
    // Status and Turn kept), so the circle begins where it should.
    let mut motions = vec![Motion::Ptp(PtpMotion {
        target: start,
        s: None,
        t: None,
        params: MotionParams {
            approx_mm: Some(0.0),
            ..Default::default()
        },
    })];
    match c.mode {
        Mode::Circ => {
            motions.push(Motion::Circ(CircMotion {
                aux: aux(90.0),
                target: at(180.0),
                params: blend,
            }));
            motions.push(Motion::Circ(CircMotion {
                aux: aux(270.0),
                target: start,
                params: exact,
            }));
        }
        // Not drawn with conventional motions: see `spline_motions`.
        Mode::Spl => {}
        Mode::Lin => {
            let n = c.segments;
            for i in 1..n {
                let target = at(360.0 * f64::from(i) / f64::from(n));
                motions.push(Motion::Lin(LinMotion {
                    target,
                    params: blend,
                }));
            }
            // Close the circle exactly on the start point, and stop there.
            motions.push(Motion::Lin(LinMotion {
                target: start,
                params: exact,
            }));
        }
    }
    motions
}

/// One turn of the circle as `segments` SPL points after the start point,
/// back to it; every point blends (`approx_mm` 1) unless `stop_at_end`,
/// which ends the last block there with an exact stop. The bridge forms
/// the spline blocks (8 points at most), as for `POST /api/v1/motions`.
fn spline_points(c: &CircleRequest, orientation: &Pose, stop_at_end: bool) -> Vec<AnyMotion> {
    let n = c.segments;
    (1..=n)
        .map(|i| {
            let last = i == n;
            AnyMotion::Spl(SplPoint {
                // The last point is the start point exactly (no rounding of 360°).
                target: circle_point(c, orientation, 360.0 * f64::from(i % n) / f64::from(n)),
                params: MotionParams {
                    velocity: Some(c.speed_m_s),
                    approx_mm: Some(if last && stop_at_end { 0.0 } else { APPROX_MM }),
                    ..Default::default()
                },
            })
        })
        .collect()
}

/// Spl mode, one turn: the PTP to the start and the SPL points in ONE
/// `run-spline-motions` batch.
fn run_spline_circle(c: &CircleRequest, orientation: &Pose) -> Response {
    let mut motions: Vec<AnyMotion> = circle_motions(c, orientation)
        .into_iter()
        .map(AnyMotion::Motion)
        .collect();
    motions.extend(spline_points(c, orientation, true));
    host::log(
        LogLevel::Info,
        &format!(
            "circle r={} mm at ({}, {}, {}) through {} spline points",
            c.radius, c.x, c.y, c.z, c.segments
        ),
    );
    match splines::run_spline_motions(&motions) {
        Ok(done) => Response {
            status: 200,
            body: json!({
                "completed": done.completed,
                "motions": motions.len(),
                "position": position_json(&done.position),
            })
            .to_string(),
        },
        Err(e) => host_error(&e),
    }
}

/// `turns` times round as one path: the PTP to the start, then one turn of
/// LINs (or, in spl mode, of SPL points) per append, blended into each
/// other, closed at the start point.
fn stream_turns(c: &CircleRequest, orientation: &Pose) -> Response {
    let one = circle_motions(c, orientation);
    let (ptp, turn) = one.split_at(1);
    // Within the path every LIN blends, the last one of each turn too.
    let blended: Vec<Motion> = turn
        .iter()
        .map(|m| match m {
            Motion::Lin(l) => Motion::Lin(LinMotion {
                target: l.target,
                params: MotionParams {
                    approx_mm: Some(APPROX_MM),
                    ..l.params
                },
            }),
            other => *other,
        })
        .collect();
    let path = match paths::open_path() {
        Ok(p) => p,
        Err(e) => return host_error(&e),
    };
    host::log(
        LogLevel::Info,
        &format!("{} turns ({:?} mode) as path {path}", c.turns, c.mode),
    );
    if let Err(e) = paths::append(path, ptp) {
        let _ = paths::cancel(path);
        return host_error(&e);
    }
    let spline_turn = spline_points(c, orientation, false);
    for _ in 0..c.turns {
        let appended = if c.mode == Mode::Spl {
            splines::append_spline_motions(path, &spline_turn)
        } else {
            paths::append(path, &blended)
        };
        if let Err(e) = appended {
            let _ = paths::cancel(path);
            return host_error(&e);
        }
    }
    let per_turn = if c.mode == Mode::Spl {
        spline_turn.len()
    } else {
        turn.len()
    };
    match paths::finish(path) {
        Ok(done) => Response {
            status: 200,
            body: json!({
                "completed": done.completed,
                "motions": 1 + per_turn * c.turns as usize,
                "path": path,
                "position": position_json(&done.position),
            })
            .to_string(),
        },
        Err(e) => host_error(&e),
    }
}

/// `{"x","y","z","a","b","c","s","t"}` of a position.
fn position_json(p: &Position) -> serde_json::Value {
    let q = &p.pose;
    json!({"x": q.x, "y": q.y, "z": q.z, "a": q.a, "b": q.b, "c": q.c, "s": p.s, "t": p.t})
}

/// An error response `{"code", "detail"}`.
fn error(status: u16, code: &str, detail: &str) -> Response {
    Response {
        status,
        body: json!({"code": code, "detail": detail}).to_string(),
    }
}

/// A failed host call as a response: 503 when the controller is offline or
/// timed out (try again later), 409 when it was stopped or is in a state
/// that refuses motions (a conflict with the controller, not a wrong
/// motion), 422 for everything else (the motion is wrong).
fn host_error(e: &HostError) -> Response {
    let status = match e.code.as_str() {
        "controller_offline" | "timeout" => 503,
        "cancelled" | "controller_busy" | "controller_error" | "path_closed" => 409,
        _ => 422,
    };
    Response {
        status,
        body: json!({"code": e.code, "detail": e.detail, "motion": e.motion}).to_string(),
    }
}

/// JSON Schema of the request body.
fn request_schema() -> serde_json::Value {
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "Circle",
        "type": "object",
        "required": ["x", "y", "z", "radius"],
        "additionalProperties": false,
        "properties": {
            "x": {"type": "number", "description": "centre X (mm, current base)"},
            "y": {"type": "number", "description": "centre Y (mm)"},
            "z": {"type": "number", "description": "height of the circle (mm)"},
            "radius": {"type": "number", "exclusiveMinimum": 0, "maximum": 500, "description": "mm"},
            "speed_m_s": {"type": "number", "exclusiveMinimum": 0, "default": 0.1,
                          "description": "path speed (m/s)"},
            "mode": {"enum": ["circ", "lin", "spl"], "default": "circ",
                     "description": "two CIRC half circles, `segments` LINs, or `segments` SPL points (spline blocks of 8)"},
            "segments": {"type": "integer", "minimum": 8, "maximum": 720, "default": 36,
                         "description": "number of LINs (lin mode) or SPL points (spl mode)"},
            "turns": {"type": "integer", "minimum": 1, "maximum": 1000, "default": 1,
                      "description": "times round; more than 1 needs lin or spl mode and runs as one path that never stops"}
        },
        "examples": [{"x": 200, "y": 0, "z": 70, "radius": 40}]
    })
}

/// JSON Schema of the 200 response body.
fn response_schema() -> serde_json::Value {
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "CircleDone",
        "type": "object",
        "required": ["completed", "motions", "position"],
        "properties": {
            "completed": {"type": "integer", "description": "motions the bridge completed"},
            "motions": {"type": "integer", "description": "motions in the batch (PTP included)"},
            "path": {"type": "integer", "description": "with turns: the path's id (GET /api/v1/paths/{id})"},
            "position": {
                "type": "object",
                "description": "where the robot stopped (mm, degrees, Status, Turn)",
                "required": ["x", "y", "z", "a", "b", "c", "s", "t"],
                "properties": {
                    "x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"},
                    "a": {"type": "number"}, "b": {"type": "number"}, "c": {"type": "number"},
                    "s": {"type": "integer"}, "t": {"type": "integer"}
                }
            }
        }
    })
}

export!(DrawCircle);
