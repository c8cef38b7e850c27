//! Spline blocks: `SLIN`/`SCIRC`/`SPTP` points as single motions, and runs
//! of `SPL` points sampled from a centripetal Catmull-Rom curve into short
//! blended LINs.

use kuka_kinematics::{MotionKind as MoveKind, Pose};
use kuka_krl::{Expr, MotionKind as KrlMotion, SplinePoint, SplinePointKind, Stmt, StmtKind};

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

    /// A spline block (or a single spline motion: a block of one point).
    /// Inner `SLIN`/`SCIRC` points are approximated with `$APO.CDIS`, the
    /// block's end only with `C_SPL` (`c_spl`). A `TRIGGER WHEN PATH`
    /// inside the block belongs to the point after it: `PATH = 0` switches
    /// where the robot reaches that point, `PATH = 0 ONSTART` where its
    /// segment starts (an `SPL` point's trigger goes with the last, with
    /// `ONSTART` the first, of the LINs its segment is sampled into).
    pub(super) fn spline(
        &mut self,
        points: &'a [SplinePoint],
        triggers: &'a [Stmt],
        c_spl: bool,
    ) -> Result<(), RunError> {
        let first = self.steps.len();
        let cdis = self.cdis()?;
        let end_approx = if c_spl { cdis } else { 0.0 };
        let mut run: Vec<SplRun<'a>> = Vec::new();
        let mut run_start = self.pos;
        let mut next_trigger = 0;
        for (j, p) in points.iter().enumerate() {
            let last = j + 1 == points.len();
            // The triggers written before this point (and after the one
            // before it).
            let mut mine: Vec<PointTrigger<'a>> = Vec::new();
            while let Some(t) = triggers.get(next_trigger).filter(|t| t.line < p.line) {
                next_trigger += 1;
                self.line = t.line;
                mine.push(self.spline_trigger(t)?);
            }
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
                    run.push(SplRun {
                        pose,
                        speeds: sp,
                        line: p.line,
                        triggers: mine,
                    });
                    self.moved_to_pose(pose);
                    self.turn = None;
                }
                kind => {
                    self.flush_spl(run_start, &mut run, None)?;
                    self.line = p.line;
                    for t in mine {
                        self.trigger_at(true, t.onstart, t.at, t.delay_ms, t.action);
                    }
                    let (k, approx) = match kind {
                        SplinePointKind::Slin => (KrlMotion::Lin, cdis),
                        SplinePointKind::Scirc => (KrlMotion::Circ, cdis),
                        _ => (KrlMotion::Ptp, 0.0),
                    };
                    let approx = if last && kind != SplinePointKind::Sptp {
                        end_approx
                    } else {
                        approx
                    };
                    self.motion(k, p.aux.as_ref(), &p.target, approx, sp)?;
                }
            }
        }
        if let Some(t) = triggers.get(next_trigger) {
            self.line = t.line;
            return Err(self.err("a TRIGGER after the last point of a spline block"));
        }
        self.flush_spl(run_start, &mut run, Some(end_approx))?;
        if self.steps.len() > first
            && let Some(Step::Move { motion, .. }) = self.steps.last_mut()
        {
            motion.approx_mm = end_approx;
        }
        Ok(())
    }

    /// A `TRIGGER` inside a spline block, evaluated: KRL allows only
    /// `TRIGGER WHEN PATH` there.
    fn spline_trigger(&mut self, t: &'a Stmt) -> Result<PointTrigger<'a>, RunError> {
        match &t.kind {
            StmtKind::Trigger {
                path: true,
                at,
                onstart,
                delay,
                action,
            } => Ok(PointTrigger {
                onstart: *onstart,
                at: self.eval_num(at)?,
                delay_ms: self.eval_num(delay)?,
                action,
            }),
            StmtKind::Trigger { .. } => {
                Err(self.err("only TRIGGER WHEN PATH is allowed in a spline block"))
            }
            _ => Err(self.err("a spline block holds points and path triggers only")),
        }
    }

    /// Samples a run of `SPL` points (a centripetal Catmull-Rom curve from
    /// `start` through them) into short, blended LINs.
    /// `end_approx`: the run ends the block, its last LIN is approximated
    /// by this (else by half its length, as every other).
    fn flush_spl(
        &mut self,
        start: Pose,
        run: &mut Vec<SplRun<'a>>,
        end_approx: Option<f64>,
    ) -> Result<(), RunError> {
        if run.is_empty() {
            return Ok(());
        }
        let pts = std::mem::take(run);
        let mut q: Vec<Pose> = Vec::with_capacity(pts.len() + 1);
        q.push(start);
        q.extend(pts.iter().map(|p| p.pose));
        let count = pts.len();
        for (i, point) in pts.into_iter().enumerate() {
            let SplRun {
                pose: b,
                speeds: sp,
                line,
                triggers,
            } = point;
            let b = &b;
            let end = end_approx.filter(|_| i + 1 == count);
            self.line = line;
            let a = q[i];
            let (pa, pb) = (p3(&a), p3(b));
            if dist(pa, pb) < 1e-6 {
                for t in triggers {
                    self.trigger_at(true, t.onstart, t.at, t.delay_ms, t.action);
                }
                if a.angle_deg(b) > 1e-9 {
                    self.emit(
                        MoveKind::Lin { target: *b },
                        sp.cp,
                        sp.cp_acc_pct,
                        end.unwrap_or(0.0),
                    )?;
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
                let approx = match end {
                    Some(e) if k == n => e,
                    _ => chord / 2.0,
                };
                // The point's triggers: PATH is measured from it (with
                // ONSTART from the point before, the segment's start).
                for t in triggers
                    .iter()
                    .filter(|t| (t.onstart && k == 1) || (!t.onstart && k == n))
                {
                    self.trigger_at(true, t.onstart, t.at, t.delay_ms, t.action);
                }
                self.emit(MoveKind::Lin { target }, sp.cp, sp.cp_acc_pct, approx)?;
            }
        }
        Ok(())
    }
}

/// An `SPL` point waiting in a run: its pose, speeds, line and triggers.
struct SplRun<'a> {
    pose: Pose,
    speeds: Speeds,
    line: u32,
    triggers: Vec<PointTrigger<'a>>,
}

/// A spline block's `TRIGGER WHEN PATH`, evaluated, for the point after it.
struct PointTrigger<'a> {
    /// `ONSTART`: measured from the segment's start (the point before).
    onstart: bool,
    at: f64,
    delay_ms: f64,
    action: &'a Stmt,
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
