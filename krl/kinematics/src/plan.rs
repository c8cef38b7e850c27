//! Motion planning and timing for PTP, axis PTP, LIN, CIRC and spline points with
//! approximation: the trajectory the simulated controller executes and the
//! service's safety module dry-runs before sending anything.
//!
//! # Model (a simplified KRC)
//!
//! * **PTP / axis PTP**: synchronous axis motion. Every axis follows the same
//!   normalised trapezoid; its speed and acceleration are the largest for
//!   which no axis exceeds `velocity % × override % × max_speed_deg_s[i]` or
//!   `acceleration_pct % × max_acc_axis_deg_s2[i]` (for a one-axis move this
//!   is the textbook trapezoid `T = Δ/v + v/a`, or `2·√(Δ/a)` without
//!   cruise). Cartesian PTP targets go through [`RobotModel::inverse`] (the
//!   Status/Turn rules documented in [`crate::model`]). PTP motions always
//!   stop exactly at their end, even with `approx_mm > 0` (no PTP blending).
//! * **LIN / CIRC**: the TCP position follows the line or the arc (circle
//!   through start, auxiliary and end point), the orientation is slerped from
//!   start to target. Path speed is `velocity` m/s × override, acceleration
//!   `max_acc_cp × acceleration_pct %`. The orientation speed is bounded by
//!   [`ORI_SPEED_DEG_S`] ($VEL.ORI1): a segment's path parameter is its
//!   "effective length" `max(length, angle × v / ORI_SPEED_DEG_S)`, so pure
//!   re-orientations take time too; its acceleration is also bounded so
//!   that the orientation accelerates at most [`ORI_ACC_DEG_S2`]
//!   ($ACC.ORI1).
//! * **SPL** (a point of a spline block): the TCP follows the centripetal
//!   Catmull-Rom curve through the block's points ([`catmull_rom`], arc
//!   length from a table of 64 steps), planned like a LIN otherwise (speed,
//!   orientation slerp, blending). SLIN/SCIRC/SPTP are planned as LIN/CIRC/
//!   PTP; that the spline and the conventional family never blend into
//!   each other is the caller's rule (their `approx_mm` is 0 there).
//! * **Approximation** (C_DIS): a LIN/CIRC with `approx_mm > 0` followed by
//!   another LIN/CIRC does not stop at the corner. Like a CNC junction-speed
//!   planner, each corner gets a speed limit `√(a · r)` with
//!   `r = d / tan(θ/2)`, `θ` the deflection between the path tangents and
//!   `d = min(approx_mm, half of either segment)` (KUKA also caps the
//!   approximation at half a segment); `θ ≈ 0` gives no extra limit. A
//!   backward and a forward pass then keep every segment within the
//!   acceleration limit, so a fine polyline approximating a smooth curve runs
//!   at constant speed apart from the first acceleration and the last
//!   deceleration. **The samples stay on the programmed polyline**: the
//!   rounded corner the real controller drives is not drawn (the deviation is
//!   at most the approximation distance). The last motion of a batch always
//!   stops exactly.
//! * **Sampling**: every `sample_period_s` from `t = 0` (the start) plus the
//!   exact end point. For LIN/CIRC every sample's axes come from
//!   [`RobotModel::inverse_continuing`] from the previous sample. The
//!   trajectory stops at the last good sample when a sample is unreachable
//!   ([`IkError::Unreachable`]), violates a software limit
//!   ([`IkError::SoftwareLimit`]), or when an axis would have to move more
//!   than [`SINGULARITY_SPEED_FACTOR`] × its maximum speed between two
//!   samples ([`MotionError::Singularity`]: `"wrist"` if A5 is near or crosses
//!   0, `"overhead"` if the wrist point is near the A1 axis, `"elbow"` if A3
//!   is near the stretched angle φ, else `"axis speed limit"`).
//! * **Look-ahead checks**: before a LIN/CIRC block starts, every target is
//!   checked for reachability within the limits and every CIRC for its
//!   geometry; a failing motion ends the block before it (exact stop), like
//!   the KRC's advance run. A failing point of a spline block stops the
//!   robot before the block's first point: a KRC plans a SPLINE block as a
//!   whole.
//! * **Errors**: parameters are validated for the whole batch first; the
//!   motions before the first invalid one are still planned. On an error
//!   `samples` ends where the robot stops, `end_axes` are the axes there,
//!   and all earlier motions count as executed.

use serde::{Deserialize, Serialize};

use rs_opw_kinematics::glam::{DQuat, DVec3};

use crate::model::{Axes, IkError, RobotModel};
use crate::pose::Pose;

/// The geometric part of one motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum MotionKind {
    /// Cartesian PTP: synchronous axis motion to a TCP target.
    Ptp {
        /// TCP target in the base frame.
        target: Pose,
        /// Status, if the caller set it.
        s: Option<u8>,
        /// Turn, if the caller set it.
        t: Option<u8>,
    },
    /// Axis-specific PTP to axis angles (degrees).
    PtpAxes {
        /// Target axes.
        axes: Axes,
    },
    /// Straight line of the TCP with orientation interpolation.
    Lin {
        /// TCP target in the base frame.
        target: Pose,
    },
    /// Circular arc from the start through `aux` to `target`.
    Circ {
        /// Auxiliary point (only its position is used, as in KRL).
        aux: Pose,
        /// End point (position and orientation).
        target: Pose,
    },
    /// One segment of a spline block (KRL `SPL`): the centripetal
    /// Catmull-Rom curve ([`catmull_rom`]) from the start to `target`.
    /// Its end tangents come from the block's neighbouring points: the
    /// start of the previous segment (none when `first`: `prev` if given,
    /// else the previous segment's start as planned) and `next` (none at
    /// the block's end); a missing neighbour is the mirror image of the
    /// segment's other end, so a block of one point is a straight line.
    /// With `prev` a segment can be planned again from its own start (a
    /// path that grows while the robot runs it) along the same curve.
    /// The orientation is slerped as in a LIN. Segments of one block are
    /// tangent-continuous: planned with `approx_mm > 0` they run through
    /// their points without slowing down.
    Spl {
        /// The point (TCP pose in the base frame).
        target: Pose,
        /// The first point of its block.
        first: bool,
        /// The start of the previous segment (the point before this
        /// segment's start), when the caller knows it.
        prev: Option<Pose>,
        /// The block's next point, if this is not its last.
        next: Option<Pose>,
    },
    /// A standstill of `seconds` where the motion before it ended (KRL
    /// `WAIT SEC`, or `WAIT FOR` with a timer played for its whole
    /// timeout): the motion before it stops exactly. Its samples carry its
    /// index, so a caller can cut it short and shift what follows (the
    /// robot starts from a standstill after it, so the rest of the plan is
    /// the same, only earlier).
    Hold {
        /// Length of the standstill in seconds (≥ 0).
        seconds: f64,
    },
    /// A point of the sequence that does not move the robot and does not
    /// stop it (an I/O action switched by the next motion's trigger): the
    /// planner skips it, and the motions on either side blend as if it
    /// were not there. No sample carries its index: a caller sees the
    /// robot pass it when the index after it is reached.
    Mark,
}

/// A point of the centripetal Catmull-Rom curve (Barry–Goldman, α = ½)
/// through the four control points `c`, between `c[1]` (`t = 0`) and
/// `c[2]` (`t = 1`). The spline blocks of the simulated controllers
/// follow this curve; a KRC's own spline is not published and may differ
/// between the points (it passes through them too).
pub fn catmull_rom(c: &[[f64; 3]; 4], t: f64) -> [f64; 3] {
    let dist = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    let knot = |a: [f64; 3], b: [f64; 3]| dist(a, b).sqrt().max(1e-9);
    let t0 = 0.0;
    let t1 = t0 + knot(c[0], c[1]);
    let t2 = t1 + knot(c[1], c[2]);
    let t3 = t2 + knot(c[2], c[3]);
    let u = t1 + (t2 - t1) * t;
    let lerp = |p: [f64; 3], q: [f64; 3], ta: f64, tb: f64| {
        let w = (u - ta) / (tb - ta);
        [
            p[0] + (q[0] - p[0]) * w,
            p[1] + (q[1] - p[1]) * w,
            p[2] + (q[2] - p[2]) * w,
        ]
    };
    let a1 = lerp(c[0], c[1], t0, t1);
    let a2 = lerp(c[1], c[2], t1, t2);
    let a3 = lerp(c[2], c[3], t2, t3);
    let b1 = lerp(a1, a2, t0, t2);
    let b2 = lerp(a2, a3, t1, t3);
    lerp(b1, b2, t1, t2)
}

/// One motion with its speed, acceleration and approximation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    /// What to do.
    pub kind: MotionKind,
    /// PTP: % of maximum axis speed (1..=100); LIN/CIRC: TCP speed in m/s.
    pub velocity: f64,
    /// % of maximum acceleration (1..=100).
    pub acceleration_pct: f64,
    /// Approximation distance in mm (C_DIS); 0 = exact stop at the end.
    pub approx_mm: f64,
}

/// Machine-wide planner settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanSettings {
    /// Program override $OV_PRO in % (scales all speeds).
    pub override_pct: f64,
    /// Maximum Cartesian acceleration at 100 % in m/s² ($ACC.CP).
    pub max_acc_cp: f64,
    /// Maximum axis acceleration at 100 % in deg/s² (one value per axis).
    pub max_acc_axis_deg_s2: [f64; 6],
    /// Sample period of the returned trajectory in seconds (KRC IPO: 0.012).
    pub sample_period_s: f64,
}

impl PlanSettings {
    /// The defaults with the model's axis accelerations: what the dry run,
    /// configuration planning and both simulated controllers plan with.
    pub fn for_model(model: &RobotModel) -> Self {
        PlanSettings {
            max_acc_axis_deg_s2: model.max_acc_deg_s2,
            ..PlanSettings::default()
        }
    }
}

impl Default for PlanSettings {
    /// Override 100 %, $ACC.CP 2.3 m/s² (`DEF_ACC_CP` of real
    /// `$config.dat` files, what `kb_main` commands at 100 %), 300 deg/s² on
    /// every axis ([`crate::model::DEFAULT_AXIS_ACC_DEG_S2`]; use
    /// [`PlanSettings::for_model`] for a model's own table), IPO cycle 12 ms.
    fn default() -> Self {
        PlanSettings {
            override_pct: 100.0,
            max_acc_cp: 2.3,
            max_acc_axis_deg_s2: [crate::model::DEFAULT_AXIS_ACC_DEG_S2; 6],
            sample_period_s: 0.012,
        }
    }
}

/// One point of an executed trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time since the start of the batch in seconds.
    pub t: f64,
    /// Index of the motion in the batch this sample belongs to.
    pub motion: usize,
    /// Axis angles.
    pub axes: Axes,
    /// TCP pose in the base frame.
    pub pose: Pose,
}

/// Why a motion could not be (fully) executed; KRC-like.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// Target or a path point cannot be reached.
    #[error(transparent)]
    Ik(#[from] IkError),
    /// The path passes through (or too close to) a singularity.
    #[error("path passes a singularity ({0})")]
    Singularity(&'static str),
    /// Geometry is degenerate (e.g. CIRC points collinear or coincident).
    #[error("invalid motion geometry: {0}")]
    Geometry(&'static str),
    /// A parameter is out of range (speed, acceleration, ...).
    #[error("invalid parameter: {0}")]
    Parameter(&'static str),
}

/// The outcome of planning a batch: what would actually be executed.
#[derive(Debug, Clone, PartialEq)]
pub struct Execution {
    /// Sampled trajectory, from the start pose to the end (or the error point).
    pub samples: Vec<Sample>,
    /// Axis angles at the end (or where the error stopped the robot).
    pub end_axes: Axes,
    /// Total time of the trajectory in seconds.
    pub duration_s: f64,
    /// The first failing motion (index) and why; motions before it are executed.
    pub error: Option<(usize, MotionError)>,
    /// Where each motion starts (in order; a motion that does not move has
    /// none): the points a path that grows while it is played re-plans
    /// from ([`plan_from`]).
    pub junctions: Vec<Junction>,
}

/// Where a motion starts in a planned execution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Junction {
    /// Index of the motion that starts here.
    pub motion: usize,
    /// Time (s) at which it starts.
    pub t: f64,
    /// Axes there.
    pub axes: Axes,
    /// Path speed (mm/s of the path parameter, orientation included) with
    /// which it is entered: 0 from a standstill, more where the motion
    /// before blends into it.
    pub speed: f64,
}

/// Plans a batch of motions from `start`, blending consecutive motions that
/// have `approx_mm > 0`.
pub fn plan(
    model: &RobotModel,
    start: &Axes,
    tool: &Pose,
    base: &Pose,
    motions: &[Motion],
    settings: &PlanSettings,
) -> Execution {
    Planner::new(model, start, tool, base, settings).run(motions)
}

/// Plans `motions` as the continuation of an execution from one of its
/// junctions: the first motion starts at `from.t` with `from.axes` and,
/// when it is a LIN/CIRC, with the path speed `from.speed` (the motion
/// before it blends into it and keeps the profile already played). Samples
/// stay on the same time grid; motion and junction indices count from 0 at
/// `motions[0]`.
///
/// This is how a path that grows while it is played (a motion stream) is
/// planned: when motions are appended, the part not yet played is planned
/// again from the next junction, and what the robot already does never
/// changes. The result equals [`plan`] of the whole path wherever the
/// appended motions do not change the speeds before that junction (they
/// can only raise them: a KRC with a bounded advance run plans the same way).
pub fn plan_from(
    model: &RobotModel,
    tool: &Pose,
    base: &Pose,
    motions: &[Motion],
    settings: &PlanSettings,
    from: &Junction,
) -> Execution {
    let mut p = Planner::new(model, &from.axes, tool, base, settings);
    p.t = from.t;
    p.entry_speed = from.speed;
    let dt = settings.sample_period_s;
    if dt > 0.0 && from.t.is_finite() && from.t > 0.0 {
        p.next_k = (from.t / dt).floor() as u64 + 1;
    }
    p.run(motions)
}

/// Highest LIN/CIRC speed accepted (m/s).
pub const MAX_CP_VELOCITY: f64 = 2.0;

/// Orientation speed (deg/s, like $VEL.ORI1) at 100 % override that bounds
/// re-orientation during LIN/CIRC.
pub const ORI_SPEED_DEG_S: f64 = 200.0;

/// Orientation acceleration (deg/s², like $ACC.ORI1/ORI2) at 100 %:
/// `DEF_ACC_ORI1/2` of real `$config.dat` files, which `kb_main` commands
/// (`$ACC.ORI1 = DEF_ACC_ORI1 × pct / 100`). A segment that re-orients
/// accelerates its path parameter no faster than keeps the orientation
/// within it.
pub const ORI_ACC_DEG_S2: f64 = 100.0;

/// An axis moving faster than this multiple of its maximum speed between two
/// LIN/CIRC samples is reported as a singularity.
pub const SINGULARITY_SPEED_FACTOR: f64 = 3.0;

/// Shortest accepted sample period (s); bounds the number of samples.
pub const MIN_SAMPLE_PERIOD_S: f64 = 0.001;

/// Below this (mm, rad) a length or angle counts as zero.
const EPS: f64 = 1e-9;

fn validate_settings(s: &PlanSettings) -> Result<(), MotionError> {
    if !(s.override_pct.is_finite() && s.override_pct > 0.0 && s.override_pct <= 100.0) {
        return Err(MotionError::Parameter("override must be in (0, 100] %"));
    }
    if !(s.max_acc_cp.is_finite() && s.max_acc_cp > 0.0) {
        return Err(MotionError::Parameter("max_acc_cp must be > 0"));
    }
    if !s
        .max_acc_axis_deg_s2
        .iter()
        .all(|a| a.is_finite() && *a > 0.0)
    {
        return Err(MotionError::Parameter("axis accelerations must be > 0"));
    }
    if !(s.sample_period_s.is_finite() && s.sample_period_s >= MIN_SAMPLE_PERIOD_S) {
        return Err(MotionError::Parameter("sample period must be >= 1 ms"));
    }
    Ok(())
}

fn validate_motion(m: &Motion) -> Result<(), MotionError> {
    match &m.kind {
        MotionKind::Mark => return Ok(()),
        MotionKind::Hold { seconds } => {
            return if seconds.is_finite() && *seconds >= 0.0 {
                Ok(())
            } else {
                Err(MotionError::Parameter("a standstill must be >= 0 s"))
            };
        }
        _ => {}
    }
    if !(m.velocity.is_finite() && m.velocity > 0.0) {
        return Err(MotionError::Parameter("velocity must be > 0"));
    }
    if !(m.acceleration_pct.is_finite() && (1.0..=100.0).contains(&m.acceleration_pct)) {
        return Err(MotionError::Parameter("acceleration must be 1..100 %"));
    }
    if !(m.approx_mm.is_finite() && m.approx_mm >= 0.0) {
        return Err(MotionError::Parameter(
            "approximation distance must be >= 0 mm",
        ));
    }
    match &m.kind {
        MotionKind::Ptp { target, s, t } => {
            if m.velocity > 100.0 {
                return Err(MotionError::Parameter("PTP velocity must be 1..100 %"));
            }
            if !target.is_finite() {
                return Err(MotionError::Parameter("target must be finite"));
            }
            if s.is_some_and(|s| s > 7) || t.is_some_and(|t| t > 63) {
                return Err(MotionError::Parameter("Status must be 0..7, Turn 0..63"));
            }
        }
        MotionKind::PtpAxes { axes } => {
            if m.velocity > 100.0 {
                return Err(MotionError::Parameter("PTP velocity must be 1..100 %"));
            }
            if !axes.iter().all(|a| a.is_finite()) {
                return Err(MotionError::Parameter("axis angles must be finite"));
            }
        }
        MotionKind::Lin { target } => {
            if m.velocity > MAX_CP_VELOCITY {
                return Err(MotionError::Parameter("LIN velocity must be <= 2 m/s"));
            }
            if !target.is_finite() {
                return Err(MotionError::Parameter("target must be finite"));
            }
        }
        MotionKind::Spl {
            target, prev, next, ..
        } => {
            if m.velocity > MAX_CP_VELOCITY {
                return Err(MotionError::Parameter("SPL velocity must be <= 2 m/s"));
            }
            if !target.is_finite()
                || next.is_some_and(|p| !p.is_finite())
                || prev.is_some_and(|p| !p.is_finite())
            {
                return Err(MotionError::Parameter("spline points must be finite"));
            }
        }
        MotionKind::Circ { aux, target } => {
            if m.velocity > MAX_CP_VELOCITY {
                return Err(MotionError::Parameter("CIRC velocity must be <= 2 m/s"));
            }
            if !target.is_finite() || !aux.is_finite() {
                return Err(MotionError::Parameter(
                    "target and auxiliary point must be finite",
                ));
            }
        }
        MotionKind::Hold { .. } | MotionKind::Mark => {}
    }
    Ok(())
}

fn is_cartesian(m: &Motion) -> bool {
    matches!(
        m.kind,
        MotionKind::Lin { .. } | MotionKind::Circ { .. } | MotionKind::Spl { .. }
    )
}

/// A trapezoidal (or triangular) speed profile over a distance.
#[derive(Debug, Clone, Copy, Default)]
struct Trapezoid {
    v0: f64,
    vp: f64,
    a: f64,
    t_acc: f64,
    t_cruise: f64,
    t_dec: f64,
    d_acc: f64,
    d_cruise: f64,
    len: f64,
}

impl Trapezoid {
    /// From entry speed `v0` to exit speed `v1` over `len` with peak at most
    /// `vmax` and acceleration `a`. The speeds must be reachable (the
    /// planner's passes ensure that); small inconsistencies are absorbed.
    fn new(len: f64, v0: f64, v1: f64, vmax: f64, a: f64) -> Self {
        if len <= EPS || a <= 0.0 {
            return Trapezoid::default();
        }
        let vp = vmax
            .min((a * len + 0.5 * (v0 * v0 + v1 * v1)).sqrt())
            .max(v0)
            .max(v1);
        if vp <= EPS {
            return Trapezoid::default();
        }
        let d_acc = (vp * vp - v0 * v0) / (2.0 * a);
        let d_dec = (vp * vp - v1 * v1) / (2.0 * a);
        let d_cruise = (len - d_acc - d_dec).max(0.0);
        Trapezoid {
            v0,
            vp,
            a,
            t_acc: (vp - v0) / a,
            t_cruise: d_cruise / vp,
            t_dec: (vp - v1) / a,
            d_acc,
            d_cruise,
            len,
        }
    }

    fn duration(&self) -> f64 {
        self.t_acc + self.t_cruise + self.t_dec
    }

    /// Distance travelled after `t` seconds.
    fn pos(&self, t: f64) -> f64 {
        let d = if t <= 0.0 {
            0.0
        } else if t < self.t_acc {
            self.v0 * t + 0.5 * self.a * t * t
        } else if t < self.t_acc + self.t_cruise {
            self.d_acc + self.vp * (t - self.t_acc)
        } else if t < self.duration() {
            let td = t - self.t_acc - self.t_cruise;
            self.d_acc + self.d_cruise + self.vp * td - 0.5 * self.a * td * td
        } else {
            self.len
        };
        d.clamp(0.0, self.len)
    }
}

/// Path geometry of one Cartesian segment (positions in mm).
#[derive(Debug, Clone, Copy)]
#[expect(
    clippy::large_enum_variant,
    reason = "segments live only while one blended block is planned; a spline's arc-length table inline keeps Segment Copy and needs no allocation per segment"
)]
enum Geom {
    Line {
        p0: DVec3,
        p1: DVec3,
    },
    Arc {
        center: DVec3,
        /// Start point relative to the centre.
        r0: DVec3,
        /// Unit normal (rotation axis, right-handed).
        normal: DVec3,
        /// Swept angle in radians (0, 2π).
        angle: f64,
    },
    /// A Catmull-Rom segment, reparametrised by arc length.
    Curve {
        /// Control points.
        c: [[f64; 3]; 4],
        /// Arc length at `t = k / CURVE_STEPS`, `k = 0..=CURVE_STEPS`.
        table: [f64; CURVE_STEPS + 1],
    },
}

/// Intervals of a spline segment's arc-length table.
const CURVE_STEPS: usize = 64;

/// A planned motion that may only be planned again from the start of its
/// spline block, not from its own start: a spline segment inside a block
/// whose previous point is not known to it ([`MotionKind::Spl`]'s `prev`).
pub fn needs_block_start(m: &Motion) -> bool {
    matches!(
        m.kind,
        MotionKind::Spl {
            first: false,
            prev: None,
            ..
        }
    )
}

impl Geom {
    fn at(&self, u: f64) -> DVec3 {
        match *self {
            Geom::Line { p0, p1 } => p0.lerp(p1, u),
            Geom::Arc {
                center,
                r0,
                normal,
                angle,
            } => center + DQuat::from_axis_angle(normal, angle * u) * r0,
            Geom::Curve { c, table } => {
                let len = table[CURVE_STEPS];
                let s = u.clamp(0.0, 1.0) * len;
                let j = table.partition_point(|l| *l < s).clamp(1, CURVE_STEPS);
                let (l0, l1) = (table[j - 1], table[j]);
                let w = if l1 > l0 { (s - l0) / (l1 - l0) } else { 1.0 };
                let t = (j as f64 - 1.0 + w) / CURVE_STEPS as f64;
                DVec3::from_array(catmull_rom(&c, t))
            }
        }
    }
}

/// The spline segment from `p1` to `p2` with neighbours `before` and
/// `after`: geometry, length and unit end tangents.
fn curve(
    p1: DVec3,
    p2: DVec3,
    before: Option<DVec3>,
    after: Option<DVec3>,
) -> (Geom, f64, DVec3, DVec3) {
    const SAME: f64 = 1e-6;
    let p0 = before
        .filter(|p| p.distance(p1) >= SAME)
        .unwrap_or(2.0 * p1 - p2);
    let p3 = after
        .filter(|p| p.distance(p2) >= SAME)
        .unwrap_or(2.0 * p2 - p1);
    let c = [p0.to_array(), p1.to_array(), p2.to_array(), p3.to_array()];
    let mut table = [0.0; CURVE_STEPS + 1];
    let (mut prev, mut total) = (p1, 0.0);
    for (k, slot) in table.iter_mut().enumerate().skip(1) {
        let x = DVec3::from_array(catmull_rom(&c, k as f64 / CURVE_STEPS as f64));
        total += prev.distance(x);
        *slot = total;
        prev = x;
    }
    let len = table[CURVE_STEPS];
    let h = 1e-4;
    let at = |t: f64| DVec3::from_array(catmull_rom(&c, t));
    let dir_in = (at(h) - p1).normalize_or_zero();
    let dir_out = (p2 - at(1.0 - h)).normalize_or_zero();
    (Geom::Curve { c, table }, len, dir_in, dir_out)
}

/// One LIN/CIRC motion in a blended block.
#[derive(Debug, Clone, Copy)]
struct Segment {
    motion: usize,
    geom: Geom,
    q0: DQuat,
    q1: DQuat,
    /// Geometric length (mm).
    len: f64,
    /// Effective length (mm): path parameter including re-orientation.
    le: f64,
    /// Unit tangents at start and end (zero if the position does not move).
    dir_in: DVec3,
    dir_out: DVec3,
    vmax: f64,
    acc: f64,
    approx: f64,
    profile: Trapezoid,
    t_start: f64,
}

impl Segment {
    /// `before`: the start of the previous segment of the same spline
    /// block (only used by an `Spl` that is not its block's first point).
    fn build(
        motion: usize,
        m: &Motion,
        start: &Pose,
        before: Option<DVec3>,
        settings: &PlanSettings,
    ) -> Result<Segment, MotionError> {
        let p0 = start.position();
        let q0 = start.rotation();
        let (geom, len, dir_in, dir_out, q1) = match &m.kind {
            MotionKind::Lin { target } => {
                let p1 = target.position();
                let d = p1 - p0;
                let len = d.length();
                let dir = if len > EPS { d / len } else { DVec3::ZERO };
                (Geom::Line { p0, p1 }, len, dir, dir, target.rotation())
            }
            MotionKind::Circ { aux, target } => {
                let (geom, len, din, dout) = circle(p0, aux.position(), target.position())?;
                (geom, len, din, dout, target.rotation())
            }
            MotionKind::Spl {
                target,
                first,
                prev,
                next,
            } => {
                let p1 = target.position();
                if p0.distance(p1) <= EPS {
                    // Only the orientation changes: as a LIN.
                    (
                        Geom::Line { p0, p1 },
                        0.0,
                        DVec3::ZERO,
                        DVec3::ZERO,
                        target.rotation(),
                    )
                } else {
                    let before = if *first {
                        None
                    } else {
                        prev.as_ref().map(Pose::position).or(before)
                    };
                    let (geom, len, din, dout) =
                        curve(p0, p1, before, next.as_ref().map(Pose::position));
                    (geom, len, din, dout, target.rotation())
                }
            }
            MotionKind::Ptp { .. }
            | MotionKind::PtpAxes { .. }
            | MotionKind::Hold { .. }
            | MotionKind::Mark => {
                return Err(MotionError::Geometry("not a Cartesian motion"));
            }
        };
        let angle_deg = crate::pose::quat_angle(q0, q1).to_degrees();
        let v_prog = m.velocity * 1000.0;
        let le = len.max(angle_deg * v_prog / ORI_SPEED_DEG_S);
        Ok(Segment {
            motion,
            geom,
            q0,
            q1,
            len,
            le,
            dir_in,
            dir_out,
            vmax: v_prog * settings.override_pct / 100.0,
            acc: {
                let path = settings.max_acc_cp * 1000.0 * m.acceleration_pct / 100.0;
                // The orientation turns angle_deg over the path parameter's
                // le mm: its angular acceleration is angle_deg / le × acc.
                if angle_deg > 1e-6 && le > EPS {
                    path.min(ORI_ACC_DEG_S2 * m.acceleration_pct / 100.0 * le / angle_deg)
                } else {
                    path
                }
            },
            approx: m.approx_mm,
            profile: Trapezoid::default(),
            t_start: 0.0,
        })
    }

    fn pose_at(&self, t: f64) -> Pose {
        let s = self.profile.pos(t - self.t_start);
        let u = if self.le > EPS {
            (s / self.le).clamp(0.0, 1.0)
        } else {
            1.0
        };
        Pose::from_parts(self.geom.at(u), self.q0.slerp(self.q1, u))
    }

    fn t_end(&self) -> f64 {
        self.t_start + self.profile.duration()
    }
}

/// The circle from `p0` through `p1` to `p2`: geometry, arc length and the
/// unit tangents at start and end.
fn circle(p0: DVec3, p1: DVec3, p2: DVec3) -> Result<(Geom, f64, DVec3, DVec3), MotionError> {
    let a = p1 - p0;
    let b = p2 - p0;
    let scale = a.length().max(b.length()).max((p2 - p1).length());
    // Positions are in mm and travel with 3 decimals: closer than 0.01 mm
    // counts as the same point (a full circle needs two CIRCs, as in KRL).
    const SAME_POINT_MM: f64 = 0.01;
    if a.length() < SAME_POINT_MM {
        return Err(MotionError::Geometry(
            "CIRC auxiliary point coincides with the start",
        ));
    }
    if b.length() < SAME_POINT_MM {
        return Err(MotionError::Geometry(
            "CIRC end point coincides with the start (a full circle needs two CIRCs)",
        ));
    }
    if (p2 - p1).length() < SAME_POINT_MM {
        return Err(MotionError::Geometry(
            "CIRC auxiliary point coincides with the end point",
        ));
    }
    let n = a.cross(b);
    // |a × b| = |a||b| sin(angle): reject nearly collinear points.
    if n.length() < 1e-6 * scale * scale {
        return Err(MotionError::Geometry("CIRC points are collinear"));
    }
    // Circumcentre of the triangle p0, p1, p2.
    let center = p0
        + (b.length_squared() * n.cross(a) + a.length_squared() * b.cross(n))
            / (2.0 * n.length_squared());
    let normal = n.normalize();
    let r0 = p0 - center;
    let r2 = p2 - center;
    // Counter-clockwise angle about `normal` from r0 to r2; p1 lies on the
    // way because p0, p1, p2 are counter-clockwise about `normal`.
    let mut angle = normal.dot(r0.cross(r2)).atan2(r0.dot(r2));
    if angle <= 0.0 {
        angle += std::f64::consts::TAU;
    }
    let radius = r0.length();
    let dir_in = normal.cross(r0).normalize_or_zero();
    let dir_out = normal.cross(r2).normalize_or_zero();
    Ok((
        Geom::Arc {
            center,
            r0,
            normal,
            angle,
        },
        radius * angle,
        dir_in,
        dir_out,
    ))
}

/// Speed limit (mm/s) at the corner between two blended segments.
fn junction_speed(a: &Segment, b: &Segment) -> f64 {
    let vmax = a.vmax.min(b.vmax);
    if a.dir_out == DVec3::ZERO || b.dir_in == DVec3::ZERO {
        return 0.0;
    }
    let theta = a.dir_out.dot(b.dir_in).clamp(-1.0, 1.0).acos();
    if theta < 1e-6 {
        return vmax;
    }
    let d = a.approx.min(0.5 * a.len).min(0.5 * b.len);
    let r = d / (0.5 * theta).tan();
    (a.acc.min(b.acc) * r).max(0.0).sqrt().min(vmax)
}

/// Sets entry/exit speeds, profiles and start times of a blended block.
fn time_block(segs: &mut [Segment], t0: f64, v0: f64) {
    let n = segs.len();
    if n == 0 {
        return;
    }
    // v[i] = speed at the start of segment i; v[n] = 0 at the end. v[0] is
    // the entry speed: 0 from a standstill, or a continuation's (already
    // played, so the backward pass leaves it alone).
    let mut v = vec![0.0; n + 1];
    v[0] = v0.min(segs[0].vmax).max(0.0);
    for i in 1..n {
        v[i] = junction_speed(&segs[i - 1], &segs[i]);
    }
    // Backward pass: able to brake to the next limit.
    for i in (1..n).rev() {
        let s = &segs[i];
        v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * s.acc * s.le).sqrt());
    }
    // Forward pass: able to accelerate from the previous speed.
    for i in 0..n {
        let s = &segs[i];
        v[i + 1] = v[i + 1].min((v[i] * v[i] + 2.0 * s.acc * s.le).sqrt());
    }
    let mut t = t0;
    for (i, s) in segs.iter_mut().enumerate() {
        s.profile = Trapezoid::new(s.le, v[i], v[i + 1], s.vmax, s.acc);
        s.t_start = t;
        t += s.profile.duration();
    }
}

/// Planner state while walking through a batch.
struct Planner<'a> {
    model: &'a RobotModel,
    tool: &'a Pose,
    base: &'a Pose,
    settings: &'a PlanSettings,
    /// Current axes (end of what has been planned so far).
    axes: Axes,
    /// Current time.
    t: f64,
    /// Motion the robot executes (or executed last).
    motion: usize,
    /// Next grid time to sample.
    next_k: u64,
    samples: Vec<Sample>,
    /// Path speed into the first motion (a continuation's; else 0).
    entry_speed: f64,
    junctions: Vec<Junction>,
}

/// Result of one block: `Err` stops the batch.
type BlockResult = Result<(), (usize, MotionError)>;

impl<'a> Planner<'a> {
    fn new(
        model: &'a RobotModel,
        start: &Axes,
        tool: &'a Pose,
        base: &'a Pose,
        settings: &'a PlanSettings,
    ) -> Self {
        Planner {
            model,
            tool,
            base,
            settings,
            axes: *start,
            t: 0.0,
            motion: 0,
            next_k: 1,
            samples: Vec::new(),
            entry_speed: 0.0,
            junctions: Vec::new(),
        }
    }

    fn pose(&self, axes: &Axes) -> Pose {
        self.model.forward(axes, self.tool, self.base)
    }

    fn run(mut self, motions: &[Motion]) -> Execution {
        let start_pose = self.pose(&self.axes);
        self.samples.push(Sample {
            t: self.t,
            motion: 0,
            axes: self.axes,
            pose: start_pose,
        });
        if let Err(e) = validate_settings(self.settings) {
            return self.finish(Some((0, e)));
        }
        // Parameters first: the motions before the first bad one still run.
        let (runnable, pending) = match motions
            .iter()
            .enumerate()
            .find_map(|(i, m)| validate_motion(m).err().map(|e| (i, e)))
        {
            Some((i, e)) => (&motions[..i], Some((i, e))),
            None => (motions, None),
        };
        // Marks are not planned: the motions on either side are planned as
        // neighbours, and the indices are mapped back below.
        let index: Vec<usize> = (0..runnable.len())
            .filter(|&k| !matches!(runnable[k].kind, MotionKind::Mark))
            .collect();
        if index.len() < runnable.len() {
            let kept: Vec<Motion> = index.iter().map(|&k| runnable[k].clone()).collect();
            // (the start sample too: it carries the first planned index)
            let first_sample = self.samples.len().saturating_sub(1);
            let first_junction = self.junctions.len();
            let mut e = self.run_planned(&kept, pending);
            let map = |k: usize| index.get(k).copied().unwrap_or(runnable.len());
            for s in &mut e.samples[first_sample..] {
                s.motion = map(s.motion);
            }
            for j in &mut e.junctions[first_junction..] {
                j.motion = map(j.motion);
            }
            if let Some((k, _)) = &mut e.error
                && *k < kept.len()
            {
                *k = map(*k);
            }
            return e;
        }
        self.run_planned(runnable, pending)
    }

    /// Plans `runnable` (no marks), then reports `pending` (a bad motion
    /// after them) unless planning fails first.
    fn run_planned(
        mut self,
        runnable: &[Motion],
        mut pending: Option<(usize, MotionError)>,
    ) -> Execution {
        let mut i = 0;
        while i < runnable.len() {
            let m = &runnable[i];
            let result = if is_cartesian(m) {
                let mut j = i + 1;
                while j < runnable.len()
                    && runnable[j - 1].approx_mm > 0.0
                    && is_cartesian(&runnable[j])
                {
                    j += 1;
                }
                let r = self.cartesian_block(runnable, i, j);
                i = j;
                r
            } else if let MotionKind::Hold { seconds } = m.kind {
                self.hold(i, seconds);
                i += 1;
                Ok(())
            } else {
                let r = self.ptp(i, m);
                i += 1;
                r
            };
            if let Err(e) = result {
                pending = Some(e);
                break;
            }
        }
        self.finish(pending)
    }

    fn finish(mut self, error: Option<(usize, MotionError)>) -> Execution {
        let needs_end = self.samples.last().is_none_or(|s| s.t < self.t - 1e-9);
        if needs_end {
            let pose = self.pose(&self.axes);
            self.samples.push(Sample {
                t: self.t,
                motion: self.motion,
                axes: self.axes,
                pose,
            });
        }
        Execution {
            end_axes: self.axes,
            duration_s: self.t,
            samples: self.samples,
            error,
            junctions: self.junctions,
        }
    }

    /// Grid times within (self.t, t_end], advancing the grid counter.
    fn grid_until(&mut self, t_end: f64) -> Vec<f64> {
        let dt = self.settings.sample_period_s;
        let mut out = Vec::new();
        loop {
            let t = self.next_k as f64 * dt;
            if t > t_end + 1e-12 {
                break;
            }
            if t > self.t {
                out.push(t);
            }
            self.next_k += 1;
        }
        out
    }

    fn ptp(&mut self, index: usize, m: &Motion) -> BlockResult {
        let target = match &m.kind {
            MotionKind::Ptp { target, s, t } => self
                .model
                .inverse(target, self.tool, self.base, *s, *t, &self.axes)
                .map_err(|e| (index, e.into()))?,
            MotionKind::PtpAxes { axes } => {
                self.model
                    .check_limits(axes)
                    .map_err(|e| (index, e.into()))?;
                *axes
            }
            MotionKind::Lin { .. }
            | MotionKind::Circ { .. }
            | MotionKind::Spl { .. }
            | MotionKind::Hold { .. }
            | MotionKind::Mark => {
                return Err((index, MotionError::Geometry("not a PTP motion")));
            }
        };
        let start = self.axes;
        self.junctions.push(Junction {
            motion: index,
            t: self.t,
            axes: start,
            speed: 0.0,
        });
        self.entry_speed = 0.0;
        let profile = ptp_profile(self.model, self.settings, m, &start, &target);
        let t0 = self.t;
        let t_end = t0 + profile.duration();
        for t in self.grid_until(t_end) {
            let sigma = profile.pos(t - t0);
            let mut axes = start;
            for (a, (s, e)) in axes.iter_mut().zip(start.iter().zip(target.iter())) {
                *a = s + (e - s) * sigma;
            }
            let pose = self.pose(&axes);
            self.samples.push(Sample {
                t,
                motion: index,
                axes,
                pose,
            });
        }
        self.axes = target;
        self.t = t_end;
        self.motion = index;
        Ok(())
    }

    /// A standstill of `seconds` at the current axes.
    fn hold(&mut self, index: usize, seconds: f64) {
        self.junctions.push(Junction {
            motion: index,
            t: self.t,
            axes: self.axes,
            speed: 0.0,
        });
        self.entry_speed = 0.0;
        let t_end = self.t + seconds;
        let pose = self.pose(&self.axes);
        // Two samples, whatever its length (a wait of ten minutes is not
        // 50,000 grid points): where it starts, so that a caller sees the
        // robot reach it, and where it ends, so that a caller cutting it
        // short finds its end.
        let mut times = vec![self.t];
        if seconds > 0.0 {
            times.push(t_end);
        }
        for t in times {
            self.samples.push(Sample {
                t,
                motion: index,
                axes: self.axes,
                pose,
            });
        }
        // The grid goes on after the standstill.
        let dt = self.settings.sample_period_s;
        self.next_k = self.next_k.max((t_end / dt).floor() as u64 + 1);
        self.t = t_end;
        self.motion = index;
    }

    /// Plans motions `from..to` (all LIN/CIRC, blended) as one block.
    fn cartesian_block(&mut self, motions: &[Motion], from: usize, to: usize) -> BlockResult {
        let mut segs: Vec<Segment> = Vec::with_capacity(to - from);
        let mut pending = None;
        let mut start = self.pose(&self.axes);
        // The previous segment's start: a spline point's tangent.
        let mut before: Option<DVec3> = None;
        for (k, m) in motions.iter().enumerate().take(to).skip(from) {
            let target = match &m.kind {
                MotionKind::Lin { target }
                | MotionKind::Circ { target, .. }
                | MotionKind::Spl { target, .. } => *target,
                MotionKind::Ptp { .. }
                | MotionKind::PtpAxes { .. }
                | MotionKind::Hold { .. }
                | MotionKind::Mark => break,
            };
            let seg = Segment::build(k, m, &start, before, self.settings).and_then(|seg| {
                self.model
                    .check_reachable(&target, self.tool, self.base)
                    .map(|()| seg)
                    .map_err(MotionError::from)
            });
            match seg {
                Ok(seg) => {
                    // A motion that does not move at all needs no samples.
                    if seg.le > EPS {
                        segs.push(seg);
                    }
                }
                Err(e) => {
                    pending = Some((k, e));
                    break;
                }
            }
            before = Some(start.position());
            start = target;
        }
        // A spline block is planned as a whole (a KRC's SPLINE statement):
        // when one of its points fails, none of it runs; the robot stops
        // where the block would start.
        if let Some((k, _)) = pending
            && matches!(motions[k].kind, MotionKind::Spl { first: false, .. })
        {
            let block = (from..k)
                .rev()
                .find(|&i| !matches!(motions[i].kind, MotionKind::Spl { first: false, .. }))
                .unwrap_or(from);
            segs.retain(|seg| seg.motion < block);
        }
        // Only the first block of a continuation enters at speed.
        let v0 = std::mem::take(&mut self.entry_speed);
        time_block(&mut segs, self.t, v0);
        let Some(last) = segs.last() else {
            return pending.map_or(Ok(()), Err);
        };
        if let Some(first) = segs.first() {
            self.junctions.push(Junction {
                motion: first.motion,
                t: first.t_start,
                axes: self.axes,
                speed: first.profile.v0,
            });
        }
        let t_end = last.t_end();
        let grid = self.grid_until(t_end);
        let mut seg_i = 0;
        let mut prev_t = self.t;
        // The grid samples, then the exact block end (kept as a sample only
        // at the batch end, where `finish` adds it).
        let points = grid
            .into_iter()
            .map(|t| (t, true))
            .chain(std::iter::once((t_end, false)));
        for (t, on_grid) in points {
            if t <= prev_t + 1e-12 {
                continue;
            }
            while seg_i + 1 < segs.len() && t > segs[seg_i].t_end() {
                seg_i += 1;
                // A junction passed since the last sample: its axes continue
                // from that sample's.
                let next = &segs[seg_i];
                let at = next.pose_at(next.t_start);
                let axes = self
                    .model
                    .inverse_continuing(&at, self.tool, self.base, &self.axes)
                    .unwrap_or(self.axes);
                self.junctions.push(Junction {
                    motion: next.motion,
                    t: next.t_start,
                    axes,
                    speed: next.profile.v0,
                });
            }
            let seg = &segs[seg_i];
            let pose = seg.pose_at(t);
            let step = self.follow(&pose, t - prev_t);
            match step {
                Ok(axes) => {
                    self.axes = axes;
                    self.t = t;
                    self.motion = seg.motion;
                    prev_t = t;
                    if on_grid {
                        self.samples.push(Sample {
                            t,
                            motion: seg.motion,
                            axes,
                            pose,
                        });
                    }
                }
                Err(e) => return Err((seg.motion, e)),
            }
        }
        pending.map_or(Ok(()), Err)
    }

    /// Axes for the next path pose, checked against limits and axis speeds.
    fn follow(&self, pose: &Pose, dt: f64) -> Result<Axes, MotionError> {
        let axes = self
            .model
            .inverse_continuing(pose, self.tool, self.base, &self.axes)
            .ok_or(MotionError::Ik(IkError::Unreachable))?;
        self.model.check_limits(&axes)?;
        let prev = &self.axes;
        let too_fast = (0..6).any(|i| {
            (axes[i] - prev[i]).abs()
                > SINGULARITY_SPEED_FACTOR * self.model.max_speed_deg_s[i] * dt + 1e-3
        });
        if too_fast {
            return Err(MotionError::Singularity(classify_singularity(
                self.model, prev, &axes,
            )));
        }
        // A Cartesian path cannot change Status: crossing the A1 axis with
        // the wrist point, stretching the elbow or passing A5 = 0 means
        // passing through a singularity (a KRC stops there). Bits that are
        // undefined at either sample (e.g. leaving A5 = 0 at home) are free.
        let free = self.model.singular_status_bits(prev) | self.model.singular_status_bits(&axes);
        let changed = (self.model.status(prev) ^ self.model.status(&axes)) & !free;
        if changed != 0 {
            let which = if changed & 1 != 0 {
                "overhead"
            } else if changed & 2 != 0 {
                "elbow"
            } else {
                "wrist"
            };
            return Err(MotionError::Singularity(which));
        }
        Ok(axes)
    }
}

/// Best guess which singularity made the axes jump from `a` to `b`.
fn classify_singularity(model: &RobotModel, a: &Axes, b: &Axes) -> &'static str {
    const NEAR_DEG: f64 = 10.0;
    const NEAR_MM: f64 = 50.0;
    let crosses = |x: f64, y: f64, near: f64| x.abs() < near || y.abs() < near || x * y < 0.0;
    if crosses(a[4], b[4], NEAR_DEG) {
        return "wrist";
    }
    let (wa, _) = model.wrist_in_a1_frame(a);
    let (wb, _) = model.wrist_in_a1_frame(b);
    if crosses(wa, wb, NEAR_MM) {
        return "overhead";
    }
    let phi = model.elbow_angle_deg();
    if crosses(a[2] - phi, b[2] - phi, NEAR_DEG) {
        return "elbow";
    }
    "axis speed limit"
}

/// The normalised (0..1) synchronous PTP profile from `start` to `target`.
fn ptp_profile(
    model: &RobotModel,
    settings: &PlanSettings,
    m: &Motion,
    start: &Axes,
    target: &Axes,
) -> Trapezoid {
    let mut v_norm = f64::INFINITY;
    let mut a_norm = f64::INFINITY;
    for i in 0..6 {
        let d = (target[i] - start[i]).abs();
        if d <= EPS {
            continue;
        }
        let v = m.velocity / 100.0 * settings.override_pct / 100.0 * model.max_speed_deg_s[i];
        let a = m.acceleration_pct / 100.0 * settings.max_acc_axis_deg_s2[i];
        v_norm = v_norm.min(v / d);
        a_norm = a_norm.min(a / d);
    }
    if !v_norm.is_finite() || !a_norm.is_finite() {
        return Trapezoid::default();
    }
    Trapezoid::new(1.0, 0.0, 0.0, v_norm, a_norm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_profiles() {
        // Cruise: 0 → 100 at a = 100 needs 50 per ramp; 300 long.
        let p = Trapezoid::new(300.0, 0.0, 0.0, 100.0, 100.0);
        assert!((p.duration() - (300.0 / 100.0 + 1.0)).abs() < 1e-12);
        assert!((p.pos(0.5) - 12.5).abs() < 1e-12);
        assert!((p.pos(p.duration()) - 300.0).abs() < 1e-12);
        // Triangle.
        let p = Trapezoid::new(25.0, 0.0, 0.0, 100.0, 100.0);
        assert!((p.duration() - 1.0).abs() < 1e-12);
        assert!((p.pos(0.5) - 12.5).abs() < 1e-12);
        // Entry and exit speeds.
        let p = Trapezoid::new(100.0, 50.0, 50.0, 50.0, 100.0);
        assert!((p.duration() - 2.0).abs() < 1e-12);
        let p = Trapezoid::new(0.0, 0.0, 0.0, 50.0, 100.0);
        assert_eq!(p.duration(), 0.0);
        assert_eq!(p.pos(1.0), 0.0);
    }

    #[test]
    fn circle_through_three_points() {
        let (g, len, din, dout) = circle(
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
        )
        .expect("circle");
        assert!((len - std::f64::consts::PI).abs() < 1e-12);
        assert!((din - DVec3::Y).length() < 1e-12);
        assert!((dout - DVec3::NEG_Y).length() < 1e-12);
        assert!((g.at(0.5) - DVec3::Y).length() < 1e-12);
        // Three quarters of a circle: the auxiliary point decides the way.
        let (g, len, _, _) = circle(
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
        )
        .expect("circle");
        assert!((len - 1.5 * std::f64::consts::PI).abs() < 1e-12);
        assert!((g.at(1.0 / 1.5) - DVec3::NEG_X).length() < 1e-12);
        assert!(matches!(
            circle(DVec3::ZERO, DVec3::X, DVec3::X * 2.0),
            Err(MotionError::Geometry(_))
        ));
        assert!(matches!(
            circle(DVec3::ZERO, DVec3::ZERO, DVec3::X),
            Err(MotionError::Geometry(_))
        ));
    }
}
