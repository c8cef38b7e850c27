//! The system variables: the speeds, `$APO`, `$TOOL` and `$BASE` the
//! motions read, their range checks on assignment, the re-expression of
//! the programmed pose when the frames change, the read-only `$POS_ACT`,
//! `$AXIS_ACT`, `$NULLFRAME` and `$OV_PRO`, and `BAS(#INITMOV)`.

use kuka_kinematics::Pose;
use kuka_kinematics::plan::MAX_CP_VELOCITY;
use kuka_krl::Expr;

use super::values::{
    EXT_FIELDS, FRAME_FIELDS, Scalar, Value, axis_value, frame_value, num_field, pose_of,
};
use super::{ACC_CP_MAX, Interp, RunError, Step, Unsupported};

/// Speeds in effect for one motion.
#[derive(Debug, Clone, Copy)]
pub(super) struct Speeds {
    pub(super) cp: f64,
    pub(super) cp_acc_pct: f64,
    pub(super) ptp: f64,
    pub(super) ptp_acc_pct: f64,
}

impl<'a> Interp<'a> {
    fn sys_field(&self, root: &str, field: &str) -> Result<f64, RunError> {
        let v = self
            .globals
            .get(root)
            .ok_or_else(|| self.err(format!("{root} is missing")))?;
        let Value::Struct(_, f) = v else {
            return Err(self.err(format!("{root} is not a structure")));
        };
        num_field(f, field)
            .map_err(|m| self.err(format!("{root}: {m}")))?
            .ok_or_else(|| self.err(format!("{root}.{field} has no value")))
    }

    fn sys_array(&self, root: &str) -> Result<Vec<f64>, RunError> {
        match self.globals.get(root) {
            Some(Value::Array(_, e)) => e
                .iter()
                .map(|v| v.num().map_err(|m| self.err(format!("{root}: {m}"))))
                .collect(),
            _ => Err(self.err(format!("{root} is not an array"))),
        }
    }

    fn sys_frame(&self, root: &str) -> Result<Pose, RunError> {
        let v = self
            .globals
            .get(root)
            .ok_or_else(|| self.err(format!("{root} is missing")))?;
        pose_of(v).map_err(|m| self.err(format!("{root}: {m}")))
    }

    pub(super) fn tool(&self) -> Result<Pose, RunError> {
        self.sys_frame("$TOOL")
    }

    pub(super) fn base(&self) -> Result<Pose, RunError> {
        self.sys_frame("$BASE")
    }

    pub(super) fn cdis(&self) -> Result<f64, RunError> {
        self.sys_field("$APO", "CDIS")
    }

    pub(super) fn speeds(&self) -> Result<Speeds, RunError> {
        let min = |v: Vec<f64>| v.into_iter().fold(f64::INFINITY, f64::min);
        Ok(Speeds {
            cp: self.sys_field("$VEL", "CP")?,
            cp_acc_pct: (self.sys_field("$ACC", "CP")? / ACC_CP_MAX * 100.0).clamp(1.0, 100.0),
            ptp: min(self.sys_array("$VEL_AXIS")?),
            ptp_acc_pct: min(self.sys_array("$ACC_AXIS")?),
        })
    }

    /// Checks a system variable after an assignment (the KRC refuses
    /// out-of-range values too).
    pub(super) fn validate_sys(&self, name: &str) -> Result<(), String> {
        let msg = |e: RunError| match e {
            RunError::Runtime { message, .. }
            | RunError::TooLong { message, .. }
            | RunError::Limit { message, .. } => message,
            RunError::Unsupported(u) => u.what,
            other => other.to_string(),
        };
        match name {
            "$VEL" => {
                let cp = self.sys_field("$VEL", "CP").map_err(msg)?;
                if !(cp > 0.0 && cp <= MAX_CP_VELOCITY) {
                    return Err(format!(
                        "$VEL.CP = {cp} m/s is out of range (0 < CP <= {MAX_CP_VELOCITY})"
                    ));
                }
            }
            "$ACC" => {
                let cp = self.sys_field("$ACC", "CP").map_err(msg)?;
                if !(cp > 0.0 && cp.is_finite()) {
                    return Err(format!("$ACC.CP = {cp} m/s² must be positive"));
                }
            }
            "$VEL_AXIS" | "$ACC_AXIS" => {
                for (i, v) in self.sys_array(name).map_err(msg)?.iter().enumerate() {
                    if !(*v > 0.0 && *v <= 100.0) {
                        return Err(format!(
                            "{name}[{}] = {v} is out of range (0 < % <= 100)",
                            i + 1
                        ));
                    }
                }
            }
            "$APO" => {
                let d = self.sys_field("$APO", "CDIS").map_err(msg)?;
                if !(d >= 0.0 && d.is_finite()) {
                    return Err(format!("$APO.CDIS = {d} mm must not be negative"));
                }
            }
            "$TOOL" | "$BASE" => {
                let f = self.sys_frame(name).map_err(msg)?;
                if !f.is_finite() {
                    return Err(format!("{name} is not a finite frame"));
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// `$TOOL`/`$BASE` changed: re-express the programmed pose.
    pub(super) fn frames_changed(
        &mut self,
        old_tool: Pose,
        old_base: Pose,
    ) -> Result<(), RunError> {
        let (tool, base) = (self.tool()?, self.base()?);
        if tool == old_tool && base == old_base {
            return Ok(());
        }
        self.pos = match self.axes {
            Some(a) => self.model.forward(&a, &tool, &base),
            None => base
                .inverse()
                .compose(&old_base)
                .compose(&self.pos)
                .compose(&old_tool.inverse())
                .compose(&tool),
        };
        Ok(())
    }

    /// KRL stops the advance run here: the motion before ends exactly.
    fn advance_stop(&mut self) {
        if self.continue_active {
            return;
        }
        if let Some(Step::Move { motion, .. }) = self.steps.last_mut() {
            motion.approx_mm = 0.0;
        }
    }

    /// The programmed pose as an E6POS (`$POS_ACT`).
    pub(super) fn pos_act(&self) -> Value {
        let a = self.pos.to_array();
        let mut f: Vec<(String, Value)> = FRAME_FIELDS
            .iter()
            .zip(a)
            .map(|(n, v)| (n.to_string(), Value::Real(v)))
            .collect();
        let st = |v: Option<u8>| v.map_or(Value::Unset(Scalar::Int), |x| Value::Int(x.into()));
        f.push(("S".into(), st(self.status)));
        f.push(("T".into(), st(self.turn)));
        f.extend(EXT_FIELDS.iter().map(|n| (n.to_string(), Value::Real(0.0))));
        Value::Struct("E6POS".into(), f)
    }

    pub(super) fn computed(&mut self, name: &str) -> Result<Value, RunError> {
        Ok(match name {
            "$POS_ACT" => {
                self.advance_stop();
                self.pos_act()
            }
            "$AXIS_ACT" => {
                self.advance_stop();
                match self.axes {
                    Some(a) => axis_value(&a),
                    None => {
                        return Err(self.err(format!(
                            "$AXIS_ACT after the Cartesian motion on line {} is not known before the motion runs",
                            self.cart_line
                        )));
                    }
                }
            }
            "$NULLFRAME" => frame_value(&Pose::IDENTITY),
            _ => Value::Int(100), // $OV_PRO
        })
    }

    pub(super) fn bas(&mut self, args: &[Expr]) -> Result<(), RunError> {
        let cmd = match args.first() {
            Some(e) => self.eval(e)?,
            None => return Err(self.err("BAS needs a command")),
        };
        for a in args.iter().skip(1) {
            self.eval(a)?;
        }
        if cmd != Value::Enum("INITMOV".into()) {
            return Err(Unsupported {
                line: self.line,
                what: format!("BAS({})", cmd.type_name()),
            }
            .into());
        }
        let sp = self.speed;
        let arr = |v: f64| Value::Array(vec![6], vec![Value::Real(v); 6]);
        self.globals
            .insert("$VEL_AXIS".into(), arr(sp.ptp_velocity_pct));
        self.globals
            .insert("$ACC_AXIS".into(), arr(sp.ptp_acceleration_pct));
        for (root, v) in [
            ("$VEL", sp.cp_velocity),
            ("$ACC", sp.cp_acceleration_pct / 100.0 * ACC_CP_MAX),
        ] {
            if let Some(Value::Struct(_, f)) = self.globals.get_mut(root)
                && let Some((_, slot)) = f.iter_mut().find(|(n, _)| n == "CP")
            {
                *slot = Value::Real(v);
            }
        }
        Ok(())
    }
}
