//! Robot models (OPW geometry, software limit switches, axis speeds, home),
//! forward and inverse kinematics in KUKA conventions, Status and Turn.
//!
//! # Conventions implemented
//!
//! * **Frames.** The robot root frame ($ROBROOT) has Z = 0 at the floor
//!   mounting plane. The flange frame is the OPW end frame of
//!   rs-opw-kinematics (ROS-Industrial `tool0` rotated +90° about Y): its Z
//!   axis leaves the flange face, so at home {A1 0, A2 −90, A3 90, A4 0,
//!   A5 0, A6 0} the flange reads A 0, B 90, C 0 (a KR 6 R700 sixx at
//!   X 470, Y 0, Z 750). Positive A1 turns clockwise seen from above.
//!   [`RobotModel::forward`] = inv(base) · flange · tool.
//! * **Status** ([`RobotModel::status`]):
//!   bit 0 (1) = the wrist point (intersection of A4/A5/A6) lies at negative
//!   X of the A1 frame (overhead area);
//!   bit 1 (2) = A3 ≥ φ with φ = atan(A3–A4 offset / A3-to-wrist), the A3
//!   angle at which the arm is stretched (≈ 4.40° KR 3 R540, 5.48°
//!   R700 sixx, 4.76° R900 sixx, 3.89° R1100 sixx); the usual home has S = 2;
//!   bit 2 (4) = A5 < 0.
//! * **Turn** ([`RobotModel::turn`]): bit n set when axis n+1 < 0.
//! * For Status bit 2 and Turn, angles within [`ZERO_TOL_DEG`] of 0 count as
//!   0 (not negative): IK returns values like −1e−12 at A5 = 0.
//! * **Inverse without S/T** ([`RobotModel::inverse`]): KUKA-like, the
//!   current Status (`status(current)`) is kept and among the solutions with
//!   that Status the one with the shortest (speed-weighted) axis motion from
//!   `current` is taken; A4/A6 (and any axis whose limits allow it) may take
//!   ±360° variants, which is how T is chosen. If no solution within the
//!   software limits has the current Status, the result is
//!   [`IkError::NoMatchingConfiguration`] (with the current S and T): like a
//!   KRC, the planner never changes the configuration silently. Callers that
//!   want any configuration can use [`RobotModel::solutions`] and pass S/T.
//!   Exception: a Status bit that is undefined at `current` because the
//!   robot stands exactly on that singularity ([`RobotModel::singular_status_bits`],
//!   e.g. bit 2 at A5 = 0, the usual home) is free, so the first move away
//!   from home may choose either wrist configuration.
//!   With only `t` given, the current Status is kept as well; with only `s`
//!   given, the Turn is free (shortest motion).

use rs_opw_kinematics::kinematic_traits::{Joints, Kinematics};
use rs_opw_kinematics::kinematics_impl::OPWKinematics;
use rs_opw_kinematics::parameters::opw_kinematics::Parameters;
use serde::{Deserialize, Serialize};

use crate::pose::Pose;

/// Axis angles A1..A6 in degrees (pendant angles).
pub type Axes = [f64; 6];

/// Angles closer to 0 than this (degrees) count as 0 for Status bit 2 and Turn.
pub const ZERO_TOL_DEG: f64 = 1e-6;

/// When a requested Status is matched, a bit whose axis lies closer than
/// this (degrees) to the bit's boundary (φ for bit 1, 0° for bit 2)
/// matches either value. A pose reported with 3 decimals solves back to
/// e.g. −0.0002° for an A5 that was at exactly 0°, which would flip its
/// bit; the two solutions are then both at the wrist singularity and the
/// one with the least axis motion is taken (docs/CONFIGURATION.md).
pub const ST_MATCH_TOL_DEG: f64 = 0.05;

/// The same for the Turn bits (0° for each axis). Turn only tells the
/// 360° variants of an axis apart, so a wider band costs nothing; near a
/// singularity a 3-decimal pose pins an axis only to some 0.01–0.1°.
pub const TURN_MATCH_TOL_DEG: f64 = 0.5;

/// The same for Status bit 0: a wrist point closer than this (mm) to the
/// A1 axis matches either side.
pub const ST_MATCH_TOL_MM: f64 = 0.05;

/// A solution beyond a software limit by less than this (degrees) is
/// taken at the limit: a pose reported at a limit solves back to a hair
/// beyond it (up to a few thousandths of a degree from its 3 decimals).
pub const LIMIT_TOL_DEG: f64 = 0.05;

/// |A5| below this (degrees) counts as the wrist singularity, where only
/// A4 + A6 is defined: IK then also offers A5 = 0 with the splits that keep
/// A4 where the robot is, or at 0 (the solver's split is arbitrary). A pose
/// reported at A5 = 0 solves back to |A5| of a few 0.0001°; the
/// orientation error of snapping that to 0 is below the pose's own
/// rounding.
const WRIST_SINGULAR_DEG: f64 = 0.01;

/// OPW joint offsets of the KUKA models (radians): A2 is −90° at the OPW zero.
const KUKA_OFFSETS: [f64; 6] = [0.0, -std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0];
/// OPW sign corrections of the KUKA models (A1, A4, A6 turn about −Z/−X).
const KUKA_SIGNS: [i8; 6] = [-1, 1, 1, -1, 1, -1];

/// Why no axis solution was found for a Cartesian target.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IkError {
    /// No solution at all: the target is outside the workspace.
    #[error("target is out of reach of the robot")]
    Unreachable,
    /// Solutions exist but every one violates a software limit switch;
    /// `axis` is 1-based, `value` the angle of the closest candidate.
    #[error(
        "axis A{axis} would be at {value:.3}° outside its software limits [{min:.1}°, {max:.1}°]"
    )]
    SoftwareLimit {
        /// 1-based axis number.
        axis: u8,
        /// Angle the axis would have (degrees).
        value: f64,
        /// Negative limit (degrees).
        min: f64,
        /// Positive limit (degrees).
        max: f64,
    },
    /// No solution matches the requested Status/Turn.
    #[error("no solution with Status {s} and Turn {t}")]
    NoMatchingConfiguration {
        /// Requested Status.
        s: u8,
        /// Requested Turn.
        t: u8,
    },
}

/// Geometry and machine data of one robot type.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotModel {
    /// Model id, e.g. `kr3_r540`.
    pub name: String,
    /// OPW lengths in mm: a1, a2, b, c1, c2, c3, c4 (see rs-opw-kinematics).
    pub opw_mm: [f64; 7],
    /// Software limit switches per axis (degrees): ($SOFTN_END, $SOFTP_END).
    pub limits_deg: [(f64, f64); 6],
    /// Maximum axis speeds in deg/s.
    pub max_speed_deg_s: [f64; 6],
    /// Axis accelerations at 100 % in deg/s² (what `$ACC_AXIS[i] = 100`
    /// means on the controller). KUKA publishes no figure: every built-in
    /// model assumes [`DEFAULT_AXIS_ACC_DEG_S2`] on every axis, which is on
    /// the slow side for small robots; a site that knows its machine data
    /// sets its own (`robot.custom.max_acc_deg_s2`).
    #[serde(default = "default_axis_acc")]
    pub max_acc_deg_s2: [f64; 6],
    /// Home position (axis angles, degrees).
    pub home: Axes,
}

/// The axis acceleration every built-in model assumes (deg/s² at 100 %).
pub const DEFAULT_AXIS_ACC_DEG_S2: f64 = 300.0;

fn default_axis_acc() -> [f64; 6] {
    [DEFAULT_AXIS_ACC_DEG_S2; 6]
}

/// Limits shared by the KR 6 R700/R900 sixx and KR 10 R1100 sixx.
const SIXX_LIMITS: [(f64, f64); 6] = [
    (-170.0, 170.0),
    (-190.0, 45.0),
    (-120.0, 156.0),
    (-185.0, 185.0),
    (-120.0, 120.0),
    (-350.0, 350.0),
];
const KUKA_HOME: Axes = [0.0, -90.0, 90.0, 0.0, 0.0, 0.0];

impl RobotModel {
    /// Builds a KUKA-style model from the geometry columns of the table in
    /// the design brief (mm): base height A1→A2, A1–A2 offset, A2–A3,
    /// A3–A4 offset, A3 to wrist, wrist to flange.
    pub fn from_kuka_geometry(
        name: &str,
        geometry_mm: [f64; 6],
        limits_deg: [(f64, f64); 6],
        max_speed_deg_s: [f64; 6],
    ) -> Self {
        let [c1, a1, c2, a3a4, c3, c4] = geometry_mm;
        RobotModel {
            name: name.to_string(),
            opw_mm: [a1, -a3a4, 0.0, c1, c2, c3, c4],
            limits_deg,
            max_speed_deg_s,
            max_acc_deg_s2: default_axis_acc(),
            home: KUKA_HOME,
        }
    }

    /// KUKA KR 3 R540 (the default: closest public match to the OrangeApps ERS).
    pub fn kr3_r540() -> Self {
        Self::from_kuka_geometry(
            "kr3_r540",
            [345.0, 20.0, 260.0, 20.0, 260.0, 75.0],
            [
                (-170.0, 170.0),
                (-170.0, 50.0),
                (-110.0, 155.0),
                (-175.0, 175.0),
                (-120.0, 120.0),
                (-350.0, 350.0),
            ],
            [530.0, 529.0, 538.0, 600.0, 600.0, 800.0],
        )
    }
    /// KUKA KR 6 R700 sixx.
    pub fn kr6_r700_sixx() -> Self {
        Self::from_kuka_geometry(
            "kr6_r700_sixx",
            [400.0, 25.0, 315.0, 35.0, 365.0, 80.0],
            SIXX_LIMITS,
            [360.0, 300.0, 360.0, 381.0, 388.0, 615.0],
        )
    }
    /// KUKA KR 6 R900 sixx.
    pub fn kr6_r900_sixx() -> Self {
        Self::from_kuka_geometry(
            "kr6_r900_sixx",
            [400.0, 25.0, 455.0, 35.0, 420.0, 80.0],
            SIXX_LIMITS,
            [360.0, 300.0, 360.0, 381.0, 388.0, 615.0],
        )
    }
    /// KUKA KR 10 R1100 sixx.
    pub fn kr10_r1100_sixx() -> Self {
        Self::from_kuka_geometry(
            "kr10_r1100_sixx",
            [400.0, 25.0, 560.0, 35.0, 515.0, 80.0],
            SIXX_LIMITS,
            [300.0, 225.0, 225.0, 381.0, 311.0, 492.0],
        )
    }
    /// Looks a built-in model up by id (`kr3_r540`, `kr6_r700_sixx`, `kr6_r900_sixx`, `kr10_r1100_sixx`).
    pub fn by_name(name: &str) -> Option<Self> {
        match name {
            "kr3_r540" => Some(Self::kr3_r540()),
            "kr6_r700_sixx" => Some(Self::kr6_r700_sixx()),
            "kr6_r900_sixx" => Some(Self::kr6_r900_sixx()),
            "kr10_r1100_sixx" => Some(Self::kr10_r1100_sixx()),
            _ => None,
        }
    }
    /// Ids of all built-in models.
    pub fn builtin_names() -> &'static [&'static str] {
        &[
            "kr3_r540",
            "kr6_r700_sixx",
            "kr6_r900_sixx",
            "kr10_r1100_sixx",
        ]
    }

    /// The rs-opw-kinematics parameters of this model (meters, radians).
    pub fn opw_parameters(&self) -> Parameters {
        let [a1, a2, b, c1, c2, c3, c4] = self.opw_mm.map(|v| v / 1000.0);
        Parameters {
            a1,
            a2,
            b,
            c1,
            c2,
            c3,
            c4,
            offsets: KUKA_OFFSETS,
            sign_corrections: KUKA_SIGNS,
            dof: 6,
        }
    }

    fn solver(&self) -> OPWKinematics {
        OPWKinematics::new(self.opw_parameters())
    }

    /// φ: the A3 angle (degrees) at which the arm is stretched; Status bit 1
    /// is set when A3 ≥ φ.
    pub fn elbow_angle_deg(&self) -> f64 {
        let [_, a2, _, _, _, c3, _] = self.opw_mm;
        (-a2).atan2(c3).to_degrees()
    }

    /// Flange pose in the robot root frame ($ROBROOT) for these axes.
    /// Non-finite (or absurdly large) angles give a pose of NaNs.
    pub fn flange(&self, axes: &Axes) -> Pose {
        match self.solver().try_forward(&to_rad(axes)) {
            Ok(p) => Pose::from_opw(&p),
            // Only non-finite or absurdly large angles get here.
            Err(_) => Pose::new(f64::NAN, f64::NAN, f64::NAN, f64::NAN, f64::NAN, f64::NAN),
        }
    }

    /// TCP pose in the base frame: `inv(base) · flange(axes) · tool`.
    pub fn forward(&self, axes: &Axes, tool: &Pose, base: &Pose) -> Pose {
        base.inverse().compose(&self.flange(axes).compose(tool))
    }

    /// Wrist point (A4/A5/A6 intersection) in the A1 frame, mm: (x, z).
    /// x < 0 is the overhead area.
    pub fn wrist_in_a1_frame(&self, axes: &Axes) -> (f64, f64) {
        let [a1, a2, _, c1, c2, c3, _] = self.opw_mm;
        let q2 = axes[1].to_radians() - KUKA_OFFSETS[1];
        let q3 = axes[2].to_radians();
        let psi3 = a2.atan2(c3);
        let k = a2.hypot(c3);
        let x = c2 * q2.sin() + k * (q2 + q3 + psi3).sin() + a1;
        let z = c2 * q2.cos() + k * (q2 + q3 + psi3).cos() + c1;
        (x, z)
    }

    /// KUKA Status bits for these axes (bit 0 overhead, bit 1 elbow A3 ≥ φ, bit 2 A5 < 0).
    pub fn status(&self, axes: &Axes) -> u8 {
        let mut s = 0;
        if self.wrist_in_a1_frame(axes).0 < 0.0 {
            s |= 1;
        }
        if axes[2] >= self.elbow_angle_deg() {
            s |= 2;
        }
        if axes[4] < -ZERO_TOL_DEG {
            s |= 4;
        }
        s
    }

    /// Status bits that are undefined for these axes because they sit on a
    /// singularity: bit 0 if the wrist point is on the A1 axis, bit 1 if A3 = φ
    /// (stretched arm), bit 2 if A5 = 0 (e.g. the usual home). Within
    /// [`ZERO_TOL_DEG`] (or 1e-6 mm).
    pub fn singular_status_bits(&self, axes: &Axes) -> u8 {
        let mut bits = 0;
        if self.wrist_in_a1_frame(axes).0.abs() < 1e-6 {
            bits |= 1;
        }
        if (axes[2] - self.elbow_angle_deg()).abs() < ZERO_TOL_DEG {
            bits |= 2;
        }
        if axes[4].abs() < ZERO_TOL_DEG {
            bits |= 4;
        }
        bits
    }

    /// Status and Turn bits that a requested Status/Turn may contradict and
    /// still match these axes: each axis within [`ST_MATCH_TOL_DEG`]
    /// ([`TURN_MATCH_TOL_DEG`] for Turn; the wrist within
    /// [`ST_MATCH_TOL_MM`]) of its bit's boundary.
    pub fn loose_bits(&self, axes: &Axes) -> (u8, u8) {
        let mut s = 0;
        if self.wrist_in_a1_frame(axes).0.abs() < ST_MATCH_TOL_MM {
            s |= 1;
        }
        if (axes[2] - self.elbow_angle_deg()).abs() < ST_MATCH_TOL_DEG {
            s |= 2;
        }
        if axes[4].abs() < ST_MATCH_TOL_DEG {
            s |= 4;
        }
        let t = axes
            .iter()
            .enumerate()
            .filter(|(_, v)| v.abs() < TURN_MATCH_TOL_DEG)
            .fold(0, |t, (i, _)| t | (1 << i));
        (s, t)
    }

    /// Whether these axes have Status `s` (bits in `care`) and Turn `t`,
    /// within the tolerances of [`RobotModel::loose_bits`].
    pub fn matches(&self, axes: &Axes, s: u8, care: u8, t: Option<u8>) -> bool {
        let (loose_s, loose_t) = self.loose_bits(axes);
        (self.status(axes) ^ s) & care & !loose_s == 0
            && t.is_none_or(|t| (Self::turn(axes) ^ t) & 0b11_1111 & !loose_t == 0)
    }

    /// KUKA Turn bits for these axes (bit n set when axis n+1 < 0).
    pub fn turn(axes: &Axes) -> u8 {
        axes.iter()
            .enumerate()
            .filter(|(_, v)| **v < -ZERO_TOL_DEG)
            .fold(0, |t, (i, _)| t | (1 << i))
    }

    /// First axis (1-based) outside its software limits, as an `IkError::SoftwareLimit`.
    pub fn check_limits(&self, axes: &Axes) -> Result<(), IkError> {
        for (i, (&v, &(min, max))) in axes.iter().zip(self.limits_deg.iter()).enumerate() {
            // NaN fails the range check too.
            if !(min..=max).contains(&v) {
                return Err(IkError::SoftwareLimit {
                    axis: i as u8 + 1,
                    value: v,
                    min,
                    max,
                });
            }
        }
        Ok(())
    }

    /// Flange target in $ROBROOT for a TCP target in the base frame.
    fn flange_target(target: &Pose, tool: &Pose, base: &Pose) -> Pose {
        base.compose(target).compose(&tool.inverse())
    }

    /// All axis solutions (raw, not limit-filtered) for a TCP target,
    /// including ±360° variants of every axis whose range allows them;
    /// solutions near `reference` come first in rs-opw's order.
    /// With `clamp`, an angle beyond a limit by less than [`LIMIT_TOL_DEG`]
    /// is taken at the limit (then the solution is only that close).
    fn candidates(
        &self,
        target: &Pose,
        tool: &Pose,
        base: &Pose,
        reference: &Axes,
        clamp: bool,
    ) -> Vec<Axes> {
        let flange = Self::flange_target(target, tool, base);
        if !flange.is_finite() || !reference.iter().all(|v| v.is_finite()) {
            return Vec::new();
        }
        let pose = flange.to_opw();
        let solver = self.solver();
        let mut raw: Vec<Joints> = solver.inverse_continuing(&pose, &to_rad(reference));
        raw.extend(solver.inverse(&pose));
        let mut out: Vec<Axes> = Vec::with_capacity(raw.len() * 4);
        let mut raw_deg: Vec<Axes> = raw.iter().map(to_deg).collect();
        // At the wrist singularity only A4 + A6 is defined: also offer the
        // splits that keep A4 or A6 where the robot is or at 0 (the
        // solver's split is arbitrary and may be outside the limits).
        let singular: Vec<Axes> = raw_deg
            .iter()
            .filter(|a| a[4].abs() < WRIST_SINGULAR_DEG)
            .flat_map(|a| {
                let sum = a[3] + a[5];
                // Keep A4 (or A6) where the robot is, or at 0, or turn both
                // alike (with the ±360° variants below, every sign pair).
                [reference[3], 0.0, sum - reference[5], sum, 0.5 * sum].map(|a4| {
                    let mut b = *a;
                    b[4] = 0.0;
                    b[3] = a4;
                    b[5] = sum - a4;
                    b
                })
            })
            .collect();
        raw_deg.extend(singular);
        for base_axes in raw_deg {
            // Per axis: every 360° variant within the limits (or the angle
            // wrapped to (−180, 180] if none is, to report the limit error).
            let variants: Vec<Vec<f64>> = base_axes
                .iter()
                .zip(self.limits_deg.iter())
                .map(|(&v, &(min, max))| {
                    let w = wrap180(v);
                    let mut vs: Vec<f64> = (-2..=2)
                        .map(|k| w + 360.0 * f64::from(k))
                        .filter_map(|x| {
                            // A hair beyond a limit is at the limit.
                            let tol = if clamp { LIMIT_TOL_DEG } else { 0.0 };
                            if x >= min - tol && x <= max + tol {
                                Some(x.clamp(min, max))
                            } else {
                                None
                            }
                        })
                        .collect();
                    if vs.is_empty() {
                        vs.push(w);
                    }
                    vs
                })
                .collect();
            let total: usize = variants.iter().map(Vec::len).product();
            for mut n in 0..total {
                let mut axes = [0.0; 6];
                for (a, vs) in axes.iter_mut().zip(variants.iter()) {
                    *a = vs[n % vs.len()];
                    n /= vs.len();
                }
                if !out.iter().any(|o| max_abs_diff(o, &axes) < 1e-7) {
                    out.push(axes);
                }
            }
        }
        out
    }

    /// All solutions for a TCP target within the software limits, each with
    /// its Status and Turn, sorted by axis distance from `current` (closest
    /// first). Empty if the target is unreachable or only reachable outside
    /// the limits.
    pub fn solutions(
        &self,
        target: &Pose,
        tool: &Pose,
        base: &Pose,
        current: &Axes,
    ) -> Vec<(Axes, u8, u8)> {
        let mut c: Vec<Axes> = self
            .candidates(target, tool, base, current, false)
            .into_iter()
            .filter(|a| self.check_limits(a).is_ok())
            .collect();
        c.sort_by(|a, b| self.cost(current, a).total_cmp(&self.cost(current, b)));
        c.into_iter()
            .map(|a| {
                let s = self.status(&a);
                (a, s, Self::turn(&a))
            })
            .collect()
    }

    /// Axis travel from `from` to `to` as [`RobotModel::solutions`] and
    /// configuration planning weigh it: the PTP time at full speed (slowest
    /// axis) plus a tenth of the summed axis times, in seconds.
    pub fn travel_time(&self, from: &Axes, to: &Axes) -> f64 {
        self.cost(from, to)
    }

    /// Axis-motion cost from `from` to `to`: the PTP time at full speed
    /// (slowest axis) plus a small share of the summed axis times to break
    /// ties (e.g. the A4/A6 split at A5 = 0).
    fn cost(&self, from: &Axes, to: &Axes) -> f64 {
        let mut max: f64 = 0.0;
        let mut sum = 0.0;
        for i in 0..6 {
            let t = (to[i] - from[i]).abs() / self.max_speed_deg_s[i].max(1e-9);
            max = max.max(t);
            sum += t;
        }
        max + 0.1 * sum
    }

    /// Axis solution for a TCP target in the base frame, KUKA style: with
    /// `s`/`t` given, the solution with exactly that Status/Turn; without,
    /// keep the current Status and take the shortest axis path from
    /// `current`. Only solutions within software limits are returned.
    pub fn inverse(
        &self,
        target: &Pose,
        tool: &Pose,
        base: &Pose,
        s: Option<u8>,
        t: Option<u8>,
        current: &Axes,
    ) -> Result<Axes, IkError> {
        let candidates = self.candidates(target, tool, base, current, false);
        if candidates.is_empty() {
            return Err(IkError::Unreachable);
        }
        let want_s = s.unwrap_or_else(|| self.status(current));
        // Bits of the current Status that sit exactly on a singularity are
        // undefined there and do not constrain the choice (only when the
        // caller gave no Status).
        let care = if s.is_some() {
            0b111
        } else {
            !self.singular_status_bits(current)
        };
        // The fewest bits matched only within the tolerance (an axis a hair
        // on the other side of 0) first, then the least axis motion.
        let strict = |a: &Axes| {
            ((self.status(a) ^ want_s) & care).count_ones()
                + t.map_or(0, |t| (Self::turn(a) ^ t).count_ones())
        };
        let best = |list: &[Axes]| -> Option<Axes> {
            list.iter()
                .filter(|a| self.matches(a, want_s, care, t) && self.check_limits(a).is_ok())
                .min_by(|a, b| {
                    strict(a)
                        .cmp(&strict(b))
                        .then(self.cost(current, a).total_cmp(&self.cost(current, b)))
                })
                .copied()
        };
        if let Some(a) = best(&candidates) {
            return Ok(snap_zero(a));
        }
        // A solution a hair beyond a limit (a pose reported at the limit).
        if let Some(a) = best(&self.candidates(target, tool, base, current, true)) {
            return Ok(snap_zero(a));
        }
        let nearest_outside = candidates
            .iter()
            .filter(|a| self.matches(a, want_s, care, t))
            .min_by(|a, b| self.cost(current, a).total_cmp(&self.cost(current, b)));
        if let Some(a) = nearest_outside
            && let Err(e) = self.check_limits(a)
        {
            return Err(e);
        }
        Err(IkError::NoMatchingConfiguration {
            s: want_s,
            t: t.unwrap_or_else(|| Self::turn(current)),
        })
    }

    /// Checks that a TCP target has at least one axis solution within the
    /// software limits, in any configuration: [`IkError::Unreachable`] if
    /// there is no solution at all, else the limit violation of the first
    /// solution rs-opw returns. Cheaper than [`RobotModel::solutions`].
    pub fn check_reachable(&self, target: &Pose, tool: &Pose, base: &Pose) -> Result<(), IkError> {
        let flange = Self::flange_target(target, tool, base);
        if !flange.is_finite() {
            return Err(IkError::Unreachable);
        }
        let raw = self.solver().inverse(&flange.to_opw());
        let mut first_err = None;
        for sol in &raw {
            let mut axes = to_deg(sol);
            // Pick, per axis, the 360° variant closest to the limit centre.
            for (v, &(min, max)) in axes.iter_mut().zip(self.limits_deg.iter()) {
                let centre = 0.5 * (min + max);
                *v = centre + wrap180(*v - centre);
            }
            match self.check_limits(&axes) {
                Ok(()) => return Ok(()),
                Err(e) => {
                    first_err.get_or_insert(e);
                }
            }
        }
        Err(first_err.unwrap_or(IkError::Unreachable))
    }

    /// Solution closest to `previous` (continuous path following for
    /// LIN/CIRC sampling): no limit filtering, no S/T selection.
    pub fn inverse_continuing(
        &self,
        target: &Pose,
        tool: &Pose,
        base: &Pose,
        previous: &Axes,
    ) -> Option<Axes> {
        let flange = Self::flange_target(target, tool, base);
        if !flange.is_finite() || !previous.iter().all(|v| v.is_finite()) {
            return None;
        }
        self.solver()
            .inverse_continuing(&flange.to_opw(), &to_rad(previous))
            .first()
            .map(to_deg)
    }
}

fn to_rad(a: &Axes) -> Joints {
    a.map(f64::to_radians)
}

fn to_deg(j: &Joints) -> Axes {
    j.map(f64::to_degrees)
}

fn wrap180(v: f64) -> f64 {
    let w = (v + 180.0).rem_euclid(360.0) - 180.0;
    if w <= -180.0 { w + 360.0 } else { w }
}

fn max_abs_diff(a: &Axes, b: &Axes) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Sets angles within [`ZERO_TOL_DEG`] of 0 to exactly 0.
fn snap_zero(mut a: Axes) -> Axes {
    for v in a.iter_mut() {
        if v.abs() < ZERO_TOL_DEG {
            *v = 0.0;
        }
    }
    a
}
