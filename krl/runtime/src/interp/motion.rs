//! Single motions (`PTP`, `LIN`, `CIRC` and their `_REL` forms): their
//! targets resolved against the programmed pose, emitted as
//! [`Step::Move`]s, and the programmed pose, axes, Status and Turn after
//! them.

use kuka_kinematics::{Motion, MotionKind as MoveKind, Pose, RobotModel};
use kuka_krl::{Expr, MotionKind as KrlMotion};

use super::sysvars::Speeds;
use super::values::{AXIS_FIELDS, EXT_FIELDS, FRAME_FIELDS, Value, num_field};
use super::{Interp, RunError, Step};

impl<'a> Interp<'a> {
    pub(super) fn motion(
        &mut self,
        kind: KrlMotion,
        aux: Option<&Expr>,
        target: &Expr,
        approx_mm: f64,
        sp: Speeds,
    ) -> Result<(), RunError> {
        self.enter()?;
        let r = self.motion_body(kind, aux, target, approx_mm, sp);
        self.nesting -= 1;
        r
    }

    pub(super) fn target_fields(&mut self, e: &Expr) -> Result<Vec<(String, Value)>, RunError> {
        match self.eval(e)? {
            Value::Struct(_, f) => Ok(f),
            v => Err(self.err(format!(
                "a motion target must be a position (FRAME, POS, E6POS, AXIS, E6AXIS), found {}",
                v.type_name()
            ))),
        }
    }

    pub(super) fn is_axis_target(&self, fields: &[(String, Value)]) -> Result<bool, RunError> {
        let has = |names: &[&str]| fields.iter().any(|(n, _)| names.contains(&n.as_str()));
        let axis = has(&AXIS_FIELDS);
        if axis && has(&FRAME_FIELDS) {
            return Err(self.err("a motion target mixes axis (A1..A6) and Cartesian components"));
        }
        for (n, _) in fields {
            let ok = EXT_FIELDS.contains(&n.as_str())
                || if axis {
                    AXIS_FIELDS.contains(&n.as_str())
                } else {
                    FRAME_FIELDS.contains(&n.as_str()) || n == "S" || n == "T"
                };
            if !ok {
                return Err(self.err(format!("{n} is not a component of a position")));
            }
        }
        Ok(axis)
    }

    /// A Cartesian target: missing components from the programmed pose, or
    /// (relative) added to it.
    pub(super) fn cart_target(
        &self,
        fields: &[(String, Value)],
        rel: bool,
    ) -> Result<Pose, RunError> {
        let mut v = [None; 6];
        for (slot, n) in v.iter_mut().zip(FRAME_FIELDS) {
            *slot = num_field(fields, n).map_err(|m| self.err(m))?;
        }
        let cur = self.pos;
        let p = if rel {
            let d = Pose::new(
                v[0].unwrap_or(0.0),
                v[1].unwrap_or(0.0),
                v[2].unwrap_or(0.0),
                v[3].unwrap_or(0.0),
                v[4].unwrap_or(0.0),
                v[5].unwrap_or(0.0),
            );
            let mut p = if d.a == 0.0 && d.b == 0.0 && d.c == 0.0 {
                cur
            } else {
                Pose::from_parts(cur.position(), d.rotation() * cur.rotation())
            };
            p.x = cur.x + d.x;
            p.y = cur.y + d.y;
            p.z = cur.z + d.z;
            p
        } else {
            let c = cur.to_array();
            let g = |i: usize| v[i].unwrap_or(c[i]);
            Pose::new(g(0), g(1), g(2), g(3), g(4), g(5))
        };
        if !p.is_finite() {
            return Err(self.err("the target is not a finite position"));
        }
        Ok(p)
    }

    fn st_field(&self, fields: &[(String, Value)], n: &str) -> Result<Option<u8>, RunError> {
        match num_field(fields, n).map_err(|m| self.err(m))? {
            None => Ok(None),
            Some(v) if (0.0..=255.0).contains(&v) && v.fract() == 0.0 => Ok(Some(v as u8)),
            Some(v) => Err(self.err(format!("{n} = {v} is not a valid Status/Turn"))),
        }
    }

    pub(super) fn emit(
        &mut self,
        kind: MoveKind,
        velocity: f64,
        acc: f64,
        approx_mm: f64,
    ) -> Result<(), RunError> {
        let step = Step::Move {
            tool: self.tool()?,
            base: self.base()?,
            motion: Motion {
                kind,
                velocity,
                acceleration_pct: acc,
                approx_mm,
            },
            line: self.line,
        };
        self.push(step)
    }

    pub(super) fn moved_to_pose(&mut self, p: Pose) {
        self.pos = p;
        self.axes = None;
        self.cart_line = self.line;
    }

    fn motion_body(
        &mut self,
        kind: KrlMotion,
        aux: Option<&Expr>,
        target: &Expr,
        approx_mm: f64,
        sp: Speeds,
    ) -> Result<(), RunError> {
        let rel = matches!(
            kind,
            KrlMotion::PtpRel | KrlMotion::LinRel | KrlMotion::CircRel
        );
        let fields = self.target_fields(target)?;
        let axis = self.is_axis_target(&fields)?;
        match kind {
            KrlMotion::Ptp | KrlMotion::PtpRel if axis => {
                let mut axes = [0.0; 6];
                for (i, n) in AXIS_FIELDS.iter().enumerate() {
                    let v = num_field(&fields, n).map_err(|m| self.err(m))?;
                    axes[i] = match (v, self.axes) {
                        (Some(v), Some(cur)) if rel => cur[i] + v,
                        (Some(v), _) if !rel => v,
                        (None, Some(cur)) => cur[i],
                        _ => {
                            return Err(self.err(format!(
                                "{} needs the programmed axes, which are not known after the Cartesian motion on line {}",
                                if rel { "PTP_REL with axis values" } else { "an axis PTP with missing axes" },
                                self.cart_line
                            )));
                        }
                    };
                }
                if !axes.iter().all(|a| a.is_finite()) {
                    return Err(self.err("the axis target is not finite"));
                }
                self.emit(
                    MoveKind::PtpAxes { axes },
                    sp.ptp,
                    sp.ptp_acc_pct,
                    approx_mm,
                )?;
                self.pos = self.model.forward(&axes, &self.tool()?, &self.base()?);
                self.axes = Some(axes);
                self.status = Some(self.model.status(&axes));
                self.turn = Some(RobotModel::turn(&axes));
            }
            KrlMotion::Ptp | KrlMotion::PtpRel => {
                let target = self.cart_target(&fields, rel)?;
                let (s, t) = if rel {
                    (None, None)
                } else {
                    (self.st_field(&fields, "S")?, self.st_field(&fields, "T")?)
                };
                self.emit(
                    MoveKind::Ptp { target, s, t },
                    sp.ptp,
                    sp.ptp_acc_pct,
                    approx_mm,
                )?;
                self.moved_to_pose(target);
                self.status = s.or(self.status);
                self.turn = t;
            }
            _ if axis => {
                return Err(self.err("LIN and CIRC need a Cartesian target, not axis values"));
            }
            KrlMotion::Lin | KrlMotion::LinRel => {
                let target = self.cart_target(&fields, rel)?;
                self.emit(MoveKind::Lin { target }, sp.cp, sp.cp_acc_pct, approx_mm)?;
                self.moved_to_pose(target);
                self.turn = None;
            }
            KrlMotion::Circ | KrlMotion::CircRel => {
                let Some(aux) = aux else {
                    return Err(self.err("CIRC without an auxiliary point"));
                };
                let af = self.target_fields(aux)?;
                if self.is_axis_target(&af)? {
                    return Err(self.err("the CIRC auxiliary point must be Cartesian"));
                }
                let aux = self.cart_target(&af, rel)?;
                let target = self.cart_target(&fields, rel)?;
                self.emit(
                    MoveKind::Circ { aux, target },
                    sp.cp,
                    sp.cp_acc_pct,
                    approx_mm,
                )?;
                self.moved_to_pose(target);
                self.turn = None;
            }
        }
        Ok(())
    }
}
