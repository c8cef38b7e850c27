//! `draw-smiley`: a kuka-bridge plugin that draws the thesis's smiley.
//!
//! `POST /api/v1/plugins/draw-smiley/smiley` with `{"x": 220, "y": 0, "z": 70}`
//! (the face centre and the paper height, mm; optional `"size"` = face radius,
//! `"lift_mm"`, `"speed_m_s"`) draws a face circle, two eyes and a smiling
//! mouth as ONE continuous batch: between two shapes the pen goes up by
//! `lift_mm` (LIN), over (LIN) and down again (LIN). Circles are two CIRCs,
//! the mouth is one CIRC. The orientation of the tool is kept from the
//! current position, so put the pen down first (for example A 0, B 180, C 0).
//!
//! On the drawing "up" is +X of the base and "left" is +Y; angles are measured
//! in the XY plane from +X towards +Y. The response lists the shapes drawn, so
//! a test can check the simulator's trace against them.

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
use kuka_bridge::plugin::types::{
    CircMotion, HostError, LinMotion, Motion, MotionParams, Point, Pose, Position, PtpMotion,
};
use serde::Deserialize;
use serde_json::{Value, json};

/// Blending between consecutive motions (mm); the last motion stops exactly.
const APPROX_MM: f64 = 1.0;

/// The request body of `POST /smiley`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SmileyRequest {
    /// Face centre X (mm, current base); +X is "up" on the drawing.
    x: f64,
    /// Face centre Y (mm); +Y is "left" on the drawing.
    y: f64,
    /// Paper height (mm): where the pen touches.
    z: f64,
    /// Face radius (mm), 10..=200.
    #[serde(default = "default_size")]
    size: f64,
    /// How far the pen is lifted between shapes (mm), in (0, 100].
    #[serde(default = "default_lift")]
    lift_mm: f64,
    /// Path speed of every LIN and CIRC (m/s).
    #[serde(default = "default_speed")]
    speed_m_s: f64,
}

fn default_size() -> f64 {
    40.0
}

fn default_lift() -> f64 {
    10.0
}

fn default_speed() -> f64 {
    0.1
}

/// One shape of the drawing: an arc of a circle in the paper plane.
#[derive(Clone, Copy, Debug)]
struct Arc {
    /// Centre (x, y), mm.
    center: (f64, f64),
    /// Radius, mm.
    radius: f64,
    /// Start angle, degrees from +X towards +Y.
    from_deg: f64,
    /// End angle (from_deg + 360 for a full circle).
    to_deg: f64,
}

impl Arc {
    /// A full circle, drawn from 0° to 360°.
    fn circle(center: (f64, f64), radius: f64) -> Self {
        Arc {
            center,
            radius,
            from_deg: 0.0,
            to_deg: 360.0,
        }
    }

    /// The point at `deg` degrees.
    fn at(&self, deg: f64) -> (f64, f64) {
        let rad = deg.to_radians();
        (
            self.center.0 + self.radius * rad.cos(),
            self.center.1 + self.radius * rad.sin(),
        )
    }

    /// The shape as the response lists it.
    fn to_json(self) -> Value {
        let center = [self.center.0, self.center.1];
        if self.to_deg - self.from_deg >= 360.0 {
            json!({"kind": "circle", "center": center, "radius": self.radius})
        } else {
            json!({"kind": "arc", "center": center, "radius": self.radius,
                   "from_deg": self.from_deg, "to_deg": self.to_deg})
        }
    }
}

/// The face: a circle of radius `size`, two eyes and a mouth, scaled from
/// the thesis's drawing (face radius 55 mm).
fn smiley_shapes(s: &SmileyRequest) -> Vec<Arc> {
    let (x, y, r) = (s.x, s.y, s.size);
    vec![
        Arc::circle((x, y), r),
        // Left eye (+Y), right eye (-Y): above the centre.
        Arc::circle((x + 0.4 * r, y + 0.35 * r), 0.12 * r),
        Arc::circle((x + 0.4 * r, y - 0.35 * r), 0.12 * r),
        // The mouth: the lower part of a circle around the face centre,
        // from lower left (120°) through the bottom (180°) to lower right.
        Arc {
            center: (x, y),
            radius: 0.6 * r,
            from_deg: 120.0,
            to_deg: 240.0,
        },
    ]
}

/// Builds the batch: the motions so far and where the pen is.
struct Pen {
    motions: Vec<Motion>,
    /// Where the pen touches the paper now (`None` before the first shape).
    at: Option<(f64, f64)>,
    /// The orientation kept from the current position (its x, y, z are unused).
    orientation: Pose,
    paper_z: f64,
    up_z: f64,
    /// Speed and blending of every LIN and CIRC.
    params: MotionParams,
}

impl Pen {
    fn pose(&self, (x, y): (f64, f64), z: f64) -> Pose {
        Pose {
            x,
            y,
            z,
            ..self.orientation
        }
    }

    fn lin(&mut self, xy: (f64, f64), z: f64) {
        let target = self.pose(xy, z);
        self.motions.push(Motion::Lin(LinMotion {
            target,
            params: self.params,
        }));
    }

    /// Lifts the pen, moves it over `xy` and puts it down there. The first
    /// move is a PTP (exact stop) from wherever the robot is to above `xy`.
    fn move_to(&mut self, xy: (f64, f64)) {
        match self.at {
            None => {
                let target = self.pose(xy, self.up_z);
                let params = MotionParams {
                    approx_mm: Some(0.0),
                    ..Default::default()
                };
                self.motions.push(Motion::Ptp(PtpMotion {
                    target,
                    s: None,
                    t: None,
                    params,
                }));
            }
            Some(here) => {
                self.lin(here, self.up_z);
                self.lin(xy, self.up_z);
            }
        }
        self.lin(xy, self.paper_z);
        self.at = Some(xy);
    }

    /// Draws `arc` from its start (where the pen must be): one CIRC per half
    /// circle at most, each through the point in the middle of its span.
    fn draw(&mut self, arc: &Arc) {
        let span = arc.to_deg - arc.from_deg;
        let pieces = (span / 180.0).ceil().max(1.0) as u32;
        let step = span / f64::from(pieces);
        for i in 0..pieces {
            let a0 = arc.from_deg + step * f64::from(i);
            let (ax, ay) = arc.at(a0 + step / 2.0);
            let end = arc.at(a0 + step);
            let aux = Point {
                x: ax,
                y: ay,
                z: self.paper_z,
            };
            let target = self.pose(end, self.paper_z);
            self.motions.push(Motion::Circ(CircMotion {
                aux,
                target,
                params: self.params,
            }));
            self.at = Some(end);
        }
    }

    /// Lifts the pen and stops there exactly: the batch is complete.
    fn finish(mut self) -> Vec<Motion> {
        if let Some(here) = self.at {
            let target = self.pose(here, self.up_z);
            let params = MotionParams {
                approx_mm: Some(0.0),
                ..self.params
            };
            self.motions.push(Motion::Lin(LinMotion { target, params }));
        }
        self.motions
    }
}

/// The plugin; its trait implementation is exported with `export!` below.
struct DrawSmiley;

impl Guest for DrawSmiley {
    fn describe() -> Description {
        Description {
            name: "draw-smiley".into(),
            version: "0.1.0".into(),
            routes: vec![Route {
                method: "POST".into(),
                path: "/smiley".into(),
                summary: "Draw a smiley (face, two eyes, a mouth) as one continuous batch with \
                          pen lifts, keeping the current orientation"
                    .into(),
                request_schema: request_schema().to_string(),
                response_schema: response_schema().to_string(),
            }],
        }
    }

    fn handle(req: Request) -> Response {
        if (req.method.as_str(), req.path.as_str()) != ("POST", "/smiley") {
            let detail = format!("draw-smiley has no route {} {}", req.method, req.path);
            return error(404, "not_found", &detail);
        }
        let smiley = match parse(&req.body) {
            Ok(s) => s,
            Err(detail) => return error(400, "bad_request", &detail),
        };
        let here = match host::get_position() {
            Ok(p) => p,
            Err(e) => return host_error(&e),
        };
        let shapes = smiley_shapes(&smiley);
        let mut pen = Pen {
            motions: Vec::new(),
            at: None,
            orientation: here.pose,
            paper_z: smiley.z,
            up_z: smiley.z + smiley.lift_mm,
            params: MotionParams {
                velocity: Some(smiley.speed_m_s),
                approx_mm: Some(APPROX_MM),
                ..Default::default()
            },
        };
        for shape in &shapes {
            pen.move_to(shape.at(shape.from_deg));
            pen.draw(shape);
        }
        let motions = pen.finish();
        host::log(
            LogLevel::Info,
            &format!(
                "smiley of radius {} mm at ({}, {}, {}): {} motions",
                smiley.size,
                smiley.x,
                smiley.y,
                smiley.z,
                motions.len()
            ),
        );
        match host::run_motions(&motions) {
            Ok(done) => Response {
                status: 200,
                body: json!({
                    "completed": done.completed,
                    "motions": motions.len(),
                    "shapes": shapes.iter().map(|s| s.to_json()).collect::<Vec<_>>(),
                    "position": position_json(&done.position),
                })
                .to_string(),
            },
            Err(e) => host_error(&e),
        }
    }
}

/// Parses and checks the request body; the error is a sentence for the client.
fn parse(body: &str) -> Result<SmileyRequest, String> {
    let s: SmileyRequest = serde_json::from_str(body)
        .map_err(|e| format!("The request body is not a valid smiley: {e}."))?;
    if !(10.0..=200.0).contains(&s.size) {
        return Err(format!(
            "size (the face radius) must be between 10 and 200 mm, not {}.",
            s.size
        ));
    }
    if !(s.lift_mm > 0.0 && s.lift_mm <= 100.0) {
        return Err(format!(
            "lift_mm must be more than 0 and at most 100 mm, not {}.",
            s.lift_mm
        ));
    }
    if s.speed_m_s <= 0.0 {
        return Err(format!(
            "speed_m_s must be more than 0, not {}.",
            s.speed_m_s
        ));
    }
    Ok(s)
}

/// `{"x","y","z","a","b","c","s","t"}` of a position.
fn position_json(p: &Position) -> Value {
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
/// timed out (try again later), 422 for everything else (the motion is wrong).
fn host_error(e: &HostError) -> Response {
    let status = match e.code.as_str() {
        "controller_offline" | "timeout" => 503,
        _ => 422,
    };
    Response {
        status,
        body: json!({"code": e.code, "detail": e.detail, "motion": e.motion}).to_string(),
    }
}

/// JSON Schema of the request body.
fn request_schema() -> Value {
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "Smiley",
        "type": "object",
        "required": ["x", "y", "z"],
        "additionalProperties": false,
        "properties": {
            "x": {"type": "number", "description": "face centre X (mm); +X is up on the drawing"},
            "y": {"type": "number", "description": "face centre Y (mm); +Y is left on the drawing"},
            "z": {"type": "number", "description": "paper height (mm)"},
            "size": {"type": "number", "minimum": 10, "maximum": 200, "default": 40,
                     "description": "face radius (mm)"},
            "lift_mm": {"type": "number", "exclusiveMinimum": 0, "maximum": 100, "default": 10,
                        "description": "pen lift between shapes (mm)"},
            "speed_m_s": {"type": "number", "exclusiveMinimum": 0, "default": 0.1,
                          "description": "path speed (m/s)"}
        },
        "examples": [{"x": 220, "y": 0, "z": 70, "size": 40}]
    })
}

/// JSON Schema of the 200 response body.
fn response_schema() -> Value {
    let number = json!({"type": "number"});
    let xy = json!({"type": "array", "items": number, "minItems": 2, "maxItems": 2});
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "SmileyDone",
        "type": "object",
        "required": ["completed", "motions", "shapes", "position"],
        "properties": {
            "completed": {"type": "integer", "description": "motions the bridge completed"},
            "motions": {"type": "integer", "description": "motions in the batch"},
            "shapes": {
                "type": "array",
                "description": "what was drawn, in order; angles in degrees from +X towards +Y",
                "items": {
                    "type": "object",
                    "required": ["kind", "center", "radius"],
                    "properties": {
                        "kind": {"enum": ["circle", "arc"]},
                        "center": xy,
                        "radius": number,
                        "from_deg": number,
                        "to_deg": number
                    }
                }
            },
            "position": {
                "type": "object",
                "description": "where the robot stopped (mm, degrees, Status, Turn)",
                "required": ["x", "y", "z", "a", "b", "c", "s", "t"],
                "properties": {
                    "x": number, "y": number, "z": number, "a": number, "b": number, "c": number,
                    "s": {"type": "integer"}, "t": {"type": "integer"}
                }
            }
        }
    })
}

export!(DrawSmiley);
