//! `pick-and-place`: a kuka-bridge plugin that picks a part and places it,
//! working a gripper and waiting for a part-present sensor, as ONE batch.
//!
//! `POST /api/v1/plugins/pick-and-place/cycle` with
//! `{"pick": {"x": 300, "y": -60, "z": 100}, "place": {"x": 300, "y": 60, "z": 100}}`
//! (mm, the TCP at the part; optional orientation `a`, `b`, `c`, else the
//! robot's current one) runs, through the `steps` interface's `run-steps`:
//!
//! 1. PTP above the pick point (`approach_mm` higher);
//! 2. `set-output` gripper open, switched as the descent starts;
//! 3. LIN down at `approach_speed_m_s`, exact stop;
//! 4. `set-output` gripper closed, at the bottom;
//! 5. `wait-input` part present, at most `part_timeout_ms`;
//! 6. LIN up, blended into the LIN above the place point, blended into
//! 7. the LIN down;
//! 8. `set-output` gripper open, at the bottom, and a `dwell` of
//!    `release_ms` while it opens;
//! 9. LIN up.
//!
//! With `"spline": true` the straight motions are SLINs (the spline
//! family, `C_SPL` in the transfer). With `"release_before_mm": d` the
//! gripper opens `d` mm before the place point, while the robot descends
//! (KRL `TRIGGER WHEN PATH = -d`), instead of at the bottom.
//!
//! The gripper signal (`gripper`, default `gripper_close`: true = closed)
//! and the sensor (`part_present`) are names from the site's `[io]`
//! configuration (or numbers); the gripper must be on the site's list of
//! writable outputs. When the part never comes the bridge stops the robot
//! at the pick point and the answer is 422 `input_timeout` with the step.
//! Every motion and action goes through the bridge's own checks, exactly
//! as a `POST /api/v1/motions` would.
//!
//! Build: `cargo build --release --target wasm32-wasip2` (or `../build.sh OUT`).

wit_bindgen::generate!({
    path: "../../wit",
    world: "bridge-plugin",
    additional_type_attributes: {
        "kuka-bridge:plugin/types@0.1.0/motion-params": [#[derive(Default)]],
    },
});

use exports::kuka_bridge::plugin::plugin::{Description, Guest, Request, Response, Route};
use kuka_bridge::plugin::host::{self, LogLevel};
use kuka_bridge::plugin::io::WaitInput;
use kuka_bridge::plugin::splines::{AnyMotion, SlinMotion};
use kuka_bridge::plugin::steps::{self, Step, SwitchOutput};
use kuka_bridge::plugin::types::{
    HostError, LinMotion, Motion, MotionParams, Pose, Position, PtpMotion,
};
use serde::Deserialize;
use serde_json::json;

/// Blending between the lift, the transfer and the descent (mm).
const TRANSFER_APPROX_MM: f64 = 20.0;

/// A point of the cell: the TCP at the part (mm, current base), with an
/// optional orientation (degrees; else the robot's current one).
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct Spot {
    x: f64,
    y: f64,
    z: f64,
    a: Option<f64>,
    b: Option<f64>,
    c: Option<f64>,
}

/// The request body of `POST /cycle`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct CycleRequest {
    pick: Spot,
    place: Spot,
    #[serde(default = "default_approach")]
    approach_mm: f64,
    #[serde(default = "default_gripper")]
    gripper: String,
    #[serde(default = "default_sensor")]
    part_present: String,
    #[serde(default = "default_timeout")]
    part_timeout_ms: u32,
    #[serde(default = "default_release")]
    release_ms: u32,
    #[serde(default = "default_speed")]
    speed_m_s: f64,
    #[serde(default = "default_approach_speed")]
    approach_speed_m_s: f64,
    #[serde(default)]
    spline: bool,
    #[serde(default)]
    release_before_mm: f64,
}

fn default_approach() -> f64 {
    50.0
}
fn default_gripper() -> String {
    "gripper_close".into()
}
fn default_sensor() -> String {
    "part_present".into()
}
fn default_timeout() -> u32 {
    2000
}
fn default_release() -> u32 {
    200
}
fn default_speed() -> f64 {
    0.2
}
fn default_approach_speed() -> f64 {
    0.05
}

/// The plugin; its trait implementation is exported with `export!` below.
struct PickAndPlace;

impl Guest for PickAndPlace {
    fn describe() -> Description {
        Description {
            name: "pick-and-place".into(),
            version: "0.1.0".into(),
            routes: vec![Route {
                method: "POST".into(),
                path: "/cycle".into(),
                summary: "Pick a part and place it: approach, open, descend, close, wait for the \
                          part, lift, move, place, release, as one batch"
                    .into(),
                request_schema: request_schema().to_string(),
                response_schema: response_schema().to_string(),
            }],
        }
    }

    fn handle(req: Request) -> Response {
        if (req.method.as_str(), req.path.as_str()) != ("POST", "/cycle") {
            let detail = format!("pick-and-place has no route {} {}", req.method, req.path);
            return error(404, "not_found", &detail);
        }
        let cycle: CycleRequest = match serde_json::from_str(&req.body) {
            Ok(c) => c,
            Err(e) => return error(400, "bad_request", &format!("invalid request: {e}")),
        };
        let here = match host::get_position() {
            Ok(p) => p,
            Err(e) => return host_error(&e),
        };
        let steps = cycle_steps(&cycle, &here.pose);
        host::log(
            LogLevel::Info,
            &format!(
                "pick at ({}, {}, {}), place at ({}, {}, {}), {} steps",
                cycle.pick.x,
                cycle.pick.y,
                cycle.pick.z,
                cycle.place.x,
                cycle.place.y,
                cycle.place.z,
                steps.len()
            ),
        );
        match steps::run_steps(&steps) {
            Ok(done) => Response {
                status: 200,
                body: json!({
                    "completed": done.completed,
                    "steps": steps.len(),
                    "position": position_json(&done.position),
                })
                .to_string(),
            },
            Err(e) => host_error(&e),
        }
    }
}

/// The pose of a spot, `dz` above it, with the current orientation where
/// the spot gives none.
fn pose(s: &Spot, dz: f64, orientation: &Pose) -> Pose {
    Pose {
        x: s.x,
        y: s.y,
        z: s.z + dz,
        a: s.a.unwrap_or(orientation.a),
        b: s.b.unwrap_or(orientation.b),
        c: s.c.unwrap_or(orientation.c),
    }
}

/// A straight motion: a LIN, or with `spline` an SLIN.
fn lin(c: &CycleRequest, target: Pose, speed: f64, approx_mm: f64) -> Step {
    let params = MotionParams {
        velocity: Some(speed),
        approx_mm: Some(approx_mm),
        ..Default::default()
    };
    Step::Motion(if c.spline {
        AnyMotion::Slin(SlinMotion { target, params })
    } else {
        AnyMotion::Motion(Motion::Lin(LinMotion { target, params }))
    })
}

/// The gripper output, switched as the next motion starts, or `path_mm`
/// from the end point of the motion before it.
fn gripper(c: &CycleRequest, closed: bool, path_mm: Option<f64>) -> Step {
    Step::SetOutput(SwitchOutput {
        signal: c.gripper.clone(),
        value: closed,
        pulse_ms: Some(0),
        path_mm,
    })
}

/// The whole cycle as one batch of steps.
fn cycle_steps(c: &CycleRequest, orientation: &Pose) -> Vec<Step> {
    let up = c.approach_mm;
    let release = (c.release_before_mm > 0.0).then_some(-c.release_before_mm);
    vec![
        Step::Motion(AnyMotion::Motion(Motion::Ptp(PtpMotion {
            target: pose(&c.pick, up, orientation),
            s: None,
            t: None,
            params: MotionParams::default(),
        }))),
        gripper(c, false, None),
        lin(
            c,
            pose(&c.pick, 0.0, orientation),
            c.approach_speed_m_s,
            0.0,
        ),
        gripper(c, true, None),
        Step::WaitInput(WaitInput {
            signal: c.part_present.clone(),
            value: true,
            timeout_ms: c.part_timeout_ms,
        }),
        lin(
            c,
            pose(&c.pick, up, orientation),
            c.speed_m_s,
            TRANSFER_APPROX_MM,
        ),
        lin(
            c,
            pose(&c.place, up, orientation),
            c.speed_m_s,
            TRANSFER_APPROX_MM,
        ),
        lin(
            c,
            pose(&c.place, 0.0, orientation),
            c.approach_speed_m_s,
            0.0,
        ),
        gripper(c, false, release),
        Step::Dwell(c.release_ms),
        lin(c, pose(&c.place, up, orientation), c.speed_m_s, 0.0),
    ]
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

/// A failed host call as a response, with the bridge's code and the step:
/// 503 when the controller is offline or timed out, 403 for an output the
/// site does not allow, 404 for an unknown signal, 422 for the rest (the
/// part did not come, a pose is out of reach, ...).
fn host_error(e: &HostError) -> Response {
    let status = match e.code.as_str() {
        "controller_offline" | "timeout" => 503,
        "output_not_allowed" => 403,
        "unknown_signal" => 404,
        _ => 422,
    };
    Response {
        status,
        body: json!({"code": e.code, "detail": e.detail, "step": e.motion}).to_string(),
    }
}

/// JSON Schema of a spot.
fn spot_schema(what: &str) -> serde_json::Value {
    json!({
        "type": "object",
        "description": what,
        "required": ["x", "y", "z"],
        "additionalProperties": false,
        "properties": {
            "x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"},
            "a": {"type": "number", "description": "degrees; default: the current orientation"},
            "b": {"type": "number"}, "c": {"type": "number"}
        }
    })
}

/// JSON Schema of the request body.
fn request_schema() -> serde_json::Value {
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "PickAndPlace",
        "type": "object",
        "required": ["pick", "place"],
        "additionalProperties": false,
        "properties": {
            "pick": spot_schema("the TCP at the part to pick (mm, current base)"),
            "place": spot_schema("the TCP where the part is put down"),
            "approach_mm": {"type": "number", "minimum": 5, "maximum": 300, "default": 50,
                            "description": "height of the approach above pick and place"},
            "gripper": {"type": "string", "minLength": 1, "maxLength": 32, "default": "gripper_close",
                        "description": "the gripper's output (name or number; true = closed)"},
            "part_present": {"type": "string", "minLength": 1, "maxLength": 32, "default": "part_present",
                             "description": "the part-present input (name or number)"},
            "part_timeout_ms": {"type": "integer", "minimum": 1, "maximum": 600000, "default": 2000,
                                "description": "how long to wait for the part after closing"},
            "release_ms": {"type": "integer", "minimum": 0, "maximum": 10000, "default": 200,
                           "description": "standstill after opening at the place point"},
            "speed_m_s": {"type": "number", "exclusiveMinimum": 0, "maximum": 2, "default": 0.2},
            "approach_speed_m_s": {"type": "number", "exclusiveMinimum": 0, "maximum": 2, "default": 0.05},
            "spline": {"type": "boolean", "default": false,
                       "description": "straight motions as SLIN (spline family) instead of LIN"},
            "release_before_mm": {"type": "number", "minimum": 0, "maximum": 300, "default": 0,
                                  "description": "open the gripper this far before the place point, while descending (0: at the bottom; at most approach_mm)"}
        },
        "examples": [{"pick": {"x": 300, "y": -60, "z": 100}, "place": {"x": 300, "y": 60, "z": 100}}]
    })
}

/// JSON Schema of the 200 response body.
fn response_schema() -> serde_json::Value {
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "CycleDone",
        "type": "object",
        "required": ["completed", "steps", "position"],
        "properties": {
            "completed": {"type": "integer", "description": "steps the bridge completed"},
            "steps": {"type": "integer", "description": "motions and actions in the batch"},
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

export!(PickAndPlace);
