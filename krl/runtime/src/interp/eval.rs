//! Expressions: literals, variables and their components, calls of
//! built-in functions and `DEFFCT`s, structure values and operators, each
//! node counted against the evaluation and nesting limits.

use kuka_krl::{BinOp, Expr, RoutineKind, UnOp};

use super::operators::{BUILTINS, binary, builtin, unary};
use super::values::{PathElem, Value, step_into};
use super::{Interp, RunError, describe};

impl<'a> Interp<'a> {
    /// Evaluates an expression. Counts one evaluation and one level of
    /// nesting; the work per kind of node is in functions of its own, so
    /// that the frames on the recursion stay small in a debug build.
    pub(super) fn eval(&mut self, e: &Expr) -> Result<Value, RunError> {
        self.enter()?;
        let r = match self.charge(1) {
            Ok(()) => self.eval_node(e),
            Err(x) => Err(x),
        };
        self.nesting -= 1;
        r
    }

    fn eval_node(&mut self, e: &Expr) -> Result<Value, RunError> {
        match e {
            Expr::Int(i) => Ok(Value::Int(*i)),
            Expr::Real(r) => Ok(Value::Real(*r)),
            Expr::Bool(b) => Ok(Value::Bool(*b)),
            Expr::Str(s) => Ok(Value::Str(s.clone())),
            Expr::Enum(s) => Ok(Value::Enum(s.to_ascii_uppercase())),
            Expr::Var(_) | Expr::Index(..) | Expr::Field(..) => {
                if self.hosted.is_some() && reads_actual_position(e) {
                    self.host_advance_stop()?;
                }
                self.eval_place(e)
            }
            Expr::Call(name, args) => self.eval_call(name, args),
            Expr::Struct { ty, fields } => self.eval_struct(ty.as_deref(), fields),
            Expr::Unary(op, x) => self.eval_unary(*op, x),
            Expr::Binary(op, a, b) => self.eval_binary(*op, a, b),
            Expr::Omitted => Err(self.err("a left-out argument or index has no value")),
        }
    }

    /// A variable, element or component.
    fn eval_place(&mut self, e: &Expr) -> Result<Value, RunError> {
        if let Some(p) = self.place_of(e)? {
            return self.read_place(&p);
        }
        // A component or element of a computed value, e.g. f().X.
        let (base, elem) = match e {
            Expr::Field(b, f) => (b, PathElem::Field(f.to_ascii_uppercase())),
            Expr::Index(b, idx) => {
                let mut ii = Vec::new();
                for i in idx {
                    let v = self.eval(i)?;
                    ii.push(v.int().map_err(|m| self.err(format!("index: {m}")))?);
                }
                (b, PathElem::Index(ii))
            }
            _ => return Err(self.err("internal: not a place")),
        };
        let v = self.eval(base)?;
        match step_into(&v, &elem) {
            Ok(Value::Unset(_)) => Err(self.err(format!("{} has no value", describe(e)))),
            Ok(x) => Ok(x.clone()),
            Err(m) => Err(self.err(m)),
        }
    }

    fn eval_call(&mut self, name: &str, args: &[Expr]) -> Result<Value, RunError> {
        let up = name.to_ascii_uppercase();
        if BUILTINS.contains(&up.as_str()) {
            let mut vals = Vec::with_capacity(args.len());
            for a in args {
                vals.push(self.eval(a)?);
            }
            return builtin(&up, &vals).map_err(|m| self.err(m));
        }
        if self.harness.is_some()
            && let Some(v) = self.kinematic_function(&up, args)?
        {
            return Ok(v);
        }
        let routine = self.routine(name)?;
        if routine.kind == RoutineKind::Def {
            return Err(self.err(format!("{name} is a procedure (DEF) and has no value")));
        }
        self.call_routine(routine, args)?
            .ok_or_else(|| self.err(format!("{name} returned no value")))
    }

    fn eval_struct(
        &mut self,
        ty: Option<&str>,
        fields: &[(String, Expr)],
    ) -> Result<Value, RunError> {
        let mut out = Vec::with_capacity(fields.len());
        for (n, v) in fields {
            out.push((n.to_ascii_uppercase(), self.eval(v)?));
        }
        let ty = ty.unwrap_or("").to_ascii_uppercase();
        Ok(Value::Struct(ty, out))
    }

    fn eval_unary(&mut self, op: UnOp, x: &Expr) -> Result<Value, RunError> {
        let v = self.eval(x)?;
        unary(op, v).map_err(|m| self.err(m))
    }

    fn eval_binary(&mut self, op: BinOp, a: &Expr, b: &Expr) -> Result<Value, RunError> {
        let l = self.eval(a)?;
        let r = self.eval(b)?;
        binary(op, l, r).map_err(|m| self.err(m))
    }

    pub(super) fn eval_num(&mut self, e: &Expr) -> Result<f64, RunError> {
        let v = self.eval(e)?;
        v.num().map_err(|m| self.err(m))
    }

    pub(super) fn eval_int(&mut self, e: &Expr) -> Result<i64, RunError> {
        let v = self.eval(e)?;
        v.int().map_err(|m| self.err(m))
    }

    pub(super) fn eval_bool(&mut self, e: &Expr) -> Result<bool, RunError> {
        let v = self.eval(e)?;
        v.bool().map_err(|m| self.err(m))
    }
}

/// Whether `e` reads `$POS_ACT` or `$AXIS_ACT` (or a part of them): an
/// advance-run stop on a KRC.
fn reads_actual_position(e: &Expr) -> bool {
    match e {
        Expr::Var(n) => n.eq_ignore_ascii_case("$POS_ACT") || n.eq_ignore_ascii_case("$AXIS_ACT"),
        Expr::Index(b, _) | Expr::Field(b, _) => reads_actual_position(b),
        _ => false,
    }
}
