//! Spline blocks: `SLIN`/`SCIRC`/`SPTP` points as single motions, and runs
//! of `SPL` points as the planner's spline segments (a centripetal
//! Catmull-Rom curve through them).

use kuka_kinematics::{MotionKind as MoveKind, Pose};
use kuka_krl::{Expr, MotionKind as KrlMotion, SplinePoint, SplinePointKind, Stmt, StmtKind};

use super::sysvars::Speeds;
use super::values::Value;
use super::{Interp, RunError, Step, describe};

/// Approximation between two points of a spline run: the curve is
/// tangent-continuous there, any distance above 0 only tells the planner
/// not to stop (as `kuka_krl_runtime::to_motions` does for SPL records).
const SPL_INNER_APPROX_MM: f64 = 1.0;

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
    /// segment starts.
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

    /// A run of `SPL` points as spline segments of the planner (the
    /// centripetal Catmull-Rom curve from `start` through them,
    /// [`kuka_kinematics::catmull_rom`], the curve the native simulator and
    /// the service's checks follow too), one step per point. Inner points
    /// blend; `end_approx`: the run ends the block, its last point is
    /// approximated by this (else it blends into the block's next point).
    fn flush_spl(
        &mut self,
        start: Pose,
        run: &mut Vec<SplRun<'a>>,
        end_approx: Option<f64>,
    ) -> Result<(), RunError> {
        let pts = std::mem::take(run);
        let count = pts.len();
        let nexts: Vec<Option<Pose>> = (0..count).map(|i| pts.get(i + 1).map(|p| p.pose)).collect();
        // The point before each segment's start: the run's start for the
        // second point (where the robot is programmed to be when the run
        // begins), then the points of the run.
        let prevs: Vec<Option<Pose>> = (0..count)
            .map(|i| match i {
                0 => None,
                1 => Some(start),
                _ => Some(pts[i - 2].pose),
            })
            .collect();
        for (i, point) in pts.into_iter().enumerate() {
            let SplRun {
                pose,
                speeds: sp,
                line,
                triggers,
            } = point;
            self.line = line;
            let approx = match end_approx {
                Some(e) if i + 1 == count => e,
                _ => SPL_INNER_APPROX_MM,
            };
            // The point's triggers: PATH is measured from it (with ONSTART
            // from the point before, the segment's start).
            for t in triggers {
                self.trigger_at(true, t.onstart, t.at, t.delay_ms, t.action);
            }
            self.emit(
                MoveKind::Spl {
                    target: pose,
                    first: i == 0,
                    prev: prevs[i],
                    next: nexts[i],
                },
                sp.cp,
                sp.cp_acc_pct,
                approx,
            )?;
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
