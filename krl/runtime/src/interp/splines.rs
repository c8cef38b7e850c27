//! Spline blocks: `SLIN`/`SCIRC`/`SPTP` points as single motions, and runs
//! of `SPL` points sampled from a centripetal Catmull-Rom curve into short
//! blended LINs.

use kuka_kinematics::{MotionKind as MoveKind, Pose};
use kuka_krl::{Expr, MotionKind as KrlMotion, SplinePoint, SplinePointKind};

use super::sysvars::Speeds;
use super::values::Value;
use super::{Interp, RunError, Step, describe};

/// Longest LIN an `SPL` curve is sampled into (mm); a little below 5 mm
/// so the chords stay under 5 mm despite the arc-length table's error.
const SPL_SAMPLE_MM: f64 = 4.9;

impl<'a> Interp<'a> {
    /// Applies a spline point's `WITH` assignments, reads the speeds and
    /// restores `$VEL`/`$ACC`.
    fn point_speeds(&mut self, with: &[(Expr, Expr)]) -> Result<Speeds, RunError> {
        let saved: Vec<(String, Option<Value>)> = ["$VEL", "$ACC"]
            .iter()
            .map(|n| (n.to_string(), self.globals.get(*n).cloned()))
            .collect();
        let mut r = Ok(());
        for (t, v) in with {
            r = self.eval(v).and_then(|v| match self.place_of(t)? {
                Some(p) => self.write_place(&p, v),
                None => Err(self.err(format!("cannot assign to {}", describe(t)))),
            });
            if r.is_err() {
                break;
            }
        }
        let sp = r.and_then(|_| self.speeds());
        for (n, v) in saved {
            if let Some(v) = v {
                self.globals.insert(n, v);
            }
        }
        sp
    }

    pub(super) fn spline(
        &mut self,
        points: &'a [SplinePoint],
        c_spl: bool,
    ) -> Result<(), RunError> {
        let first = self.steps.len();
        let cdis = self.cdis()?;
        let mut run: Vec<(Pose, Speeds, u32)> = Vec::new();
        let mut run_start = self.pos;
        for p in points {
            self.line = p.line;
            self.tick()?;
            let sp = self.point_speeds(&p.with)?;
            match p.kind {
                SplinePointKind::Spl => {
                    let fields = self.target_fields(&p.target)?;
                    if self.is_axis_target(&fields)? {
                        return Err(self.err("SPL needs a Cartesian target, not axis values"));
                    }
                    let pose = self.cart_target(&fields, false)?;
                    if run.is_empty() {
                        run_start = self.pos;
                    }
                    run.push((pose, sp, p.line));
                    self.moved_to_pose(pose);
                    self.turn = None;
                }
                kind => {
                    self.flush_spl(run_start, &mut run)?;
                    self.line = p.line;
                    let (k, approx) = match kind {
                        SplinePointKind::Slin => (KrlMotion::Lin, cdis),
                        SplinePointKind::Scirc => (KrlMotion::Circ, cdis),
                        _ => (KrlMotion::Ptp, 0.0),
                    };
                    self.motion(k, p.aux.as_ref(), &p.target, approx, sp)?;
                }
            }
        }
        self.flush_spl(run_start, &mut run)?;
        if self.steps.len() > first
            && let Some(Step::Move { motion, .. }) = self.steps.last_mut()
        {
            motion.approx_mm = if c_spl { cdis } else { 0.0 };
        }
        Ok(())
    }

    /// Samples a run of `SPL` points (a centripetal Catmull-Rom curve from
    /// `start` through them) into short, blended LINs.
    fn flush_spl(
        &mut self,
        start: Pose,
        run: &mut Vec<(Pose, Speeds, u32)>,
    ) -> Result<(), RunError> {
        if run.is_empty() {
            return Ok(());
        }
        let pts = std::mem::take(run);
        let mut q: Vec<Pose> = Vec::with_capacity(pts.len() + 1);
        q.push(start);
        q.extend(pts.iter().map(|p| p.0));
        for (i, (b, sp, line)) in pts.iter().enumerate() {
            self.line = *line;
            let a = q[i];
            let (pa, pb) = (p3(&a), p3(b));
            if dist(pa, pb) < 1e-6 {
                if a.angle_deg(b) > 1e-9 {
                    self.emit(MoveKind::Lin { target: *b }, sp.cp, sp.cp_acc_pct, 0.0)?;
                }
                continue;
            }
            let reflect = |x: [f64; 3], y: [f64; 3]| {
                [2.0 * x[0] - y[0], 2.0 * x[1] - y[1], 2.0 * x[2] - y[2]]
            };
            let p0 = match i.checked_sub(1).and_then(|k| q.get(k)) {
                Some(p) if dist(p3(p), pa) >= 1e-6 => p3(p),
                _ => reflect(pa, pb),
            };
            let p3_ = match q.get(i + 2) {
                Some(p) if dist(p3(p), pb) >= 1e-6 => p3(p),
                _ => reflect(pb, pa),
            };
            let ctrl = [p0, pa, pb, p3_];
            // Arc-length table.
            let m = ((dist(pa, pb) / 0.25).ceil() as usize).clamp(64, 4000);
            let mut table = Vec::with_capacity(m + 1);
            let mut prev = pa;
            let mut len = 0.0;
            table.push((0.0, 0.0));
            for k in 1..=m {
                let t = k as f64 / m as f64;
                let x = catmull_rom(&ctrl, t);
                len += dist(prev, x);
                table.push((t, len));
                prev = x;
            }
            let n = ((len / SPL_SAMPLE_MM).ceil() as usize).max(1);
            let (qa, qb) = (a.rotation(), b.rotation());
            let mut last = pa;
            for k in 1..=n {
                let target = if k == n {
                    *b
                } else {
                    let s = len * k as f64 / n as f64;
                    let j = table.partition_point(|(_, l)| *l < s).clamp(1, m);
                    let (t0, l0) = table[j - 1];
                    let (t1, l1) = table[j];
                    let t = if l1 > l0 {
                        t0 + (t1 - t0) * (s - l0) / (l1 - l0)
                    } else {
                        t1
                    };
                    let x = catmull_rom(&ctrl, t);
                    let mut p = Pose::from_parts(a.position(), qa.slerp(qb, s / len));
                    p.x = x[0];
                    p.y = x[1];
                    p.z = x[2];
                    p
                };
                let chord = dist(last, p3(&target));
                last = p3(&target);
                self.emit(MoveKind::Lin { target }, sp.cp, sp.cp_acc_pct, chord / 2.0)?;
            }
        }
        Ok(())
    }
}

fn p3(p: &Pose) -> [f64; 3] {
    [p.x, p.y, p.z]
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Centripetal Catmull-Rom (Barry–Goldman) between `c[1]` (t = 0) and
/// `c[2]` (t = 1).
fn catmull_rom(c: &[[f64; 3]; 4], t: f64) -> [f64; 3] {
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
