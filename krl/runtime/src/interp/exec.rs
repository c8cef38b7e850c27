//! Statements: calls of routines with their parameters and results,
//! blocks, control flow (`IF`, the loops, `SWITCH`), waits, and the
//! dispatch of declarations, motions and splines.

use std::collections::HashMap;

use kuka_krl::{Expr, MotionKind as KrlMotion, Routine, RoutineKind, SplinePoint, Stmt, StmtKind};

use super::harness::err_value;
use super::operators::{int_result, values_equal};
use super::values::{Scalar, Value, assign_into, cells};
use super::vars::{Place, Root, Slot};
use super::{Interp, MAX_CALL_DEPTH, RunError, Step, Unsupported, describe};

/// How a statement or block ended.
pub(super) enum Flow {
    Next,
    Exit,
    Return(Option<Value>),
}

impl<'a> Interp<'a> {
    pub(super) fn routine(&self, name: &str) -> Result<&'a Routine, RunError> {
        self.routines
            .get(&name.to_ascii_uppercase())
            .copied()
            .ok_or_else(|| self.err(format!("the routine {name} is not defined")))
    }

    pub(super) fn call_routine(
        &mut self,
        r: &'a Routine,
        args: &[Expr],
    ) -> Result<Option<Value>, RunError> {
        self.enter()?;
        let result = self.call_routine_body(r, args);
        self.nesting -= 1;
        result
    }

    fn call_routine_body(
        &mut self,
        r: &'a Routine,
        args: &[Expr],
    ) -> Result<Option<Value>, RunError> {
        let call_line = self.line;
        if let Some(h) = self.hosted.as_mut() {
            h.host.called(&r.name);
        }
        // Separate functions: their frames are gone while the body runs.
        // Binding evaluates the arguments: a level of its own.
        self.enter()?;
        let bound = self.bind_params(r, args);
        self.nesting -= 1;
        let (frame, held) = bound?;
        self.frames.push(frame);
        self.frame_cells.push(0);
        let flow = match self.hold(held) {
            Ok(()) => self.exec_block(&r.body),
            Err(e) => Err(e),
        };
        self.frames.pop();
        let released = self.frame_cells.pop().unwrap_or(0);
        self.cells = self.cells.saturating_sub(released);
        let flow = flow?;
        let result = self.routine_result(r, flow)?;
        self.line = call_line;
        Ok(result)
    }

    /// The new frame of a call of `r`: its `IN` parameters' values and its
    /// `OUT` parameters' places; and the values the frame holds.
    fn bind_params(
        &mut self,
        r: &'a Routine,
        args: &[Expr],
    ) -> Result<(HashMap<String, Slot>, usize), RunError> {
        if r.params.len() != args.len() {
            return Err(self.err(format!(
                "{} takes {} argument(s), got {}",
                r.name,
                r.params.len(),
                args.len()
            )));
        }
        if self.frames.len() >= MAX_CALL_DEPTH {
            return Err(self.limit(format!(
                "calls nested deeper than {MAX_CALL_DEPTH} levels (limit MAX_CALL_DEPTH; endless recursion?)"
            )));
        }
        let mut frame = HashMap::new();
        let mut held = 0usize;
        for (p, a) in r.params.iter().zip(args) {
            let slot = if p.out {
                match self.place_of(a)? {
                    Some(pl) if matches!(pl.root, Root::Global(ref n) if n.starts_with('$')) => {
                        return Err(self.err(format!(
                            "the system variable {} cannot be an OUT argument",
                            describe(a)
                        )));
                    }
                    Some(pl) if !matches!(pl.root, Root::Computed(_)) => Slot::Ref(pl),
                    _ => {
                        return Err(self.err(format!(
                            "the OUT parameter {} of {} needs a variable",
                            p.name, r.name
                        )));
                    }
                }
            } else {
                let v = self.eval(a)?;
                held = held.saturating_add(cells(&v));
                Slot::Val(v)
            };
            frame.insert(p.name.to_ascii_uppercase(), slot);
        }
        Ok((frame, held))
    }

    /// The value a call of `r` returns, after its body ended with `flow`.
    fn routine_result(&mut self, r: &'a Routine, flow: Flow) -> Result<Option<Value>, RunError> {
        self.line = r.end_line;
        let result = match (&r.kind, flow) {
            (RoutineKind::Def, Flow::Next | Flow::Return(None)) => None,
            (RoutineKind::Def, Flow::Return(Some(_))) => {
                return Err(self.err(format!("the procedure {} cannot RETURN a value", r.name)));
            }
            (RoutineKind::DefFct(ty), Flow::Return(Some(v))) => {
                let mut slot = self
                    .type_template(ty)
                    .ok_or_else(|| self.err(format!("functions returning {ty}")))?;
                assign_into(&mut slot, v)
                    .map_err(|m| self.err(format!("return value of {}: {m}", r.name)))?;
                Some(slot)
            }
            (RoutineKind::DefFct(_), Flow::Next | Flow::Return(None)) => {
                return Err(self.err(format!(
                    "the function {} ended without RETURN of a value",
                    r.name
                )));
            }
            (_, Flow::Exit) => return Err(self.err("EXIT outside a loop")),
        };
        Ok(result)
    }

    fn exec_block(&mut self, body: &'a [Stmt]) -> Result<Flow, RunError> {
        for s in body {
            match self.exec(s)? {
                Flow::Next => {}
                f => return Ok(f),
            }
        }
        Ok(Flow::Next)
    }

    /// Runs a loop body; `Some(flow)` when the loop must end with `flow`.
    fn loop_body(&mut self, body: &'a [Stmt], line: u32) -> Result<Option<Flow>, RunError> {
        // A loop's frames count as a level of their own.
        self.enter()?;
        let r = self.loop_iteration(body, line);
        self.nesting -= 1;
        r
    }

    fn loop_iteration(&mut self, body: &'a [Stmt], line: u32) -> Result<Option<Flow>, RunError> {
        self.line = line;
        self.tick()?;
        let f = match self.exec_block(body)? {
            Flow::Next => None,
            Flow::Exit => Some(Flow::Next),
            r @ Flow::Return(_) => Some(r),
        };
        self.line = line;
        Ok(f)
    }

    pub(super) fn exec(&mut self, s: &'a Stmt) -> Result<Flow, RunError> {
        self.enter()?;
        let guarded = std::mem::take(&mut self.error_proceed);
        let r = match self.exec_stmt(s) {
            // ON_ERROR_PROCEED (harness only): note the error in $ERR and
            // go on after the statement. The statement limit still ends
            // the run.
            Err(RunError::Runtime { line, .. })
                if guarded && self.statements <= self.max_statements =>
            {
                self.globals.insert("$ERR".into(), err_value(1, line));
                Ok(Flow::Next)
            }
            // RESUME unwinds to the statement of the routine that declared
            // the interrupt; that routine goes on after it.
            Err(RunError::Resumed { depth }) if self.frames.len() <= depth => Ok(Flow::Next),
            r => r,
        };
        self.nesting -= 1;
        r
    }

    /// Dispatches on the statement. Every statement with more than a few
    /// locals has a function of its own: a debug build gives a function one
    /// stack slot per local of every `match` arm, and this function is on
    /// every recursion (blocks, calls).
    fn exec_stmt(&mut self, s: &'a Stmt) -> Result<Flow, RunError> {
        self.line = s.line;
        self.tick()?;
        self.continue_active = std::mem::take(&mut self.continue_pending);
        let l = s.line;
        match &s.kind {
            StmtKind::Decl { ty, vars, .. } => self.exec_decl(ty, vars),
            StmtKind::InterruptDecl { prio, when, action } if self.hosted.is_some() => {
                self.declare_interrupt(prio, when, action)?;
                Ok(Flow::Next)
            }
            StmtKind::InterruptSwitch { action, prio } if self.hosted.is_some() => {
                self.switch_interrupt(action, prio.as_ref())?;
                Ok(Flow::Next)
            }
            // Only the standard stop-message interrupt passes check_subset.
            StmtKind::Ext { .. }
            | StmtKind::InterruptDecl { .. }
            | StmtKind::InterruptSwitch { .. } => Ok(Flow::Next),
            StmtKind::Assign { target, value } => self.exec_assign(target, value),
            StmtKind::Call { name, args } => self.exec_call(name, args),
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => self.exec_if(cond, then_body, else_body),
            StmtKind::While { cond, body } => self.exec_while(cond, body, l),
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => self.exec_for(var, [from, to], step.as_ref(), body, l),
            StmtKind::Loop { body } => self.exec_loop(body, l),
            StmtKind::Repeat { body, until } => self.exec_repeat(body, until, l),
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => self.exec_switch(selector, cases, default.as_deref()),
            StmtKind::Return(e) => self.exec_return(e.as_ref()),
            StmtKind::Exit => Ok(Flow::Exit),
            StmtKind::Continue => {
                self.continue_pending = true;
                Ok(Flow::Next)
            }
            StmtKind::WaitSec(e) => self.exec_wait_sec(e, l),
            StmtKind::WaitFor(e) => self.exec_wait_for(e),
            StmtKind::Motion {
                kind,
                aux,
                target,
                approx,
                ..
            } => self.exec_motion(*kind, aux.as_ref(), target, approx.is_some()),
            StmtKind::Spline {
                points,
                triggers,
                approx,
                ..
            } => self.exec_spline(points, triggers, approx.is_some()),
            // A single SPTP/SLIN/SCIRC plays as a spline block of one point
            // (check_subset refuses the _REL forms).
            StmtKind::SplineMotion { point, .. } => {
                self.exec_spline(std::slice::from_ref(point), &[], point.approx.is_some())
            }
            _ => self.exec_other(s),
        }
    }

    /// Statements of the harness and those outside the subset.
    fn exec_other(&mut self, s: &'a Stmt) -> Result<Flow, RunError> {
        match &s.kind {
            StmtKind::Struc { name, fields } => self.define_struc(name, fields)?,
            StmtKind::Enum { name, .. } => {
                self.types
                    .insert(name.to_ascii_uppercase(), Value::Unset(Scalar::Enum));
            }
            StmtKind::OnErrorProceed if self.harness.is_some() => self.error_proceed = true,
            StmtKind::Trigger {
                path,
                at,
                onstart,
                delay,
                action,
            } if self.hosted.is_some() => self.trigger(*path, *onstart, at, delay, action)?,
            StmtKind::Brake if self.hosted.is_some() => self.host_wait(super::Wait::Brake)?,
            StmtKind::Resume if self.hosted.is_some() => self.resume()?,
            _ => {
                return Err(Unsupported {
                    line: s.line,
                    what: "this statement".into(),
                }
                .into());
            }
        }
        Ok(Flow::Next)
    }

    fn exec_spline(
        &mut self,
        points: &'a [SplinePoint],
        triggers: &'a [Stmt],
        c_spl: bool,
    ) -> Result<Flow, RunError> {
        // The spline's and the motion's frames are large (in a debug
        // build): each counts as a level of its own.
        self.enter()?;
        let r = self
            .planner_boundary(true)
            .and_then(|()| self.spline(points, triggers, c_spl));
        self.nesting -= 1;
        r.map(|()| Flow::Next)
    }

    fn exec_decl(&mut self, ty: &str, vars: &[kuka_krl::Declarator]) -> Result<Flow, RunError> {
        for d in vars {
            self.declare(ty, d)?;
        }
        Ok(Flow::Next)
    }

    fn exec_assign(&mut self, target: &Expr, value: &Expr) -> Result<Flow, RunError> {
        let v = self.eval(value)?;
        let Some(p) = self.place_of(target)? else {
            return Err(self.err(format!("cannot assign to {}", describe(target))));
        };
        self.write_place(&p, v)?;
        Ok(Flow::Next)
    }

    fn exec_call(&mut self, name: &str, args: &[Expr]) -> Result<Flow, RunError> {
        if name.eq_ignore_ascii_case("BAS") {
            self.bas(args)?;
        } else if self.harness.is_some() && name.eq_ignore_ascii_case("CWRITE") {
            self.cwrite(args)?;
        } else if self.harness.is_some() && name.eq_ignore_ascii_case("SWRITE") {
            self.swrite(args)?;
        } else if self.harness.is_some() && name.eq_ignore_ascii_case("SREAD") {
            self.sread(args)?;
        } else if self.hosted.is_some() && name.eq_ignore_ascii_case("PULSE") {
            self.pulse(args)?;
        } else if self.harness.is_some() && name.eq_ignore_ascii_case("ERR_CLEAR") {
            match args {
                [Expr::Var(v)] if v.eq_ignore_ascii_case("$ERR") => {
                    self.globals.insert("$ERR".into(), err_value(0, 0));
                }
                _ => return Err(self.err("ERR_CLEAR takes $ERR")),
            }
        } else {
            let r = self.routine(name)?;
            self.call_routine(r, args)?;
        }
        Ok(Flow::Next)
    }

    fn exec_if(
        &mut self,
        cond: &Expr,
        then_body: &'a [Stmt],
        else_body: &'a [Stmt],
    ) -> Result<Flow, RunError> {
        let body = if self.eval_bool(cond)? {
            then_body
        } else {
            else_body
        };
        self.exec_block(body)
    }

    fn exec_while(&mut self, cond: &Expr, body: &'a [Stmt], l: u32) -> Result<Flow, RunError> {
        while self.eval_bool(cond)? {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
        }
        Ok(Flow::Next)
    }

    fn exec_for(
        &mut self,
        var: &str,
        bounds: [&Expr; 2],
        step: Option<&Expr>,
        body: &'a [Stmt],
        l: u32,
    ) -> Result<Flow, RunError> {
        // Two calls in a row: the frame that evaluates the bounds is gone
        // before the loop recurses into the body.
        let (counter, to, step) = self.for_start(var, bounds, step)?;
        self.for_loop(&counter, to, step, body, l)
    }

    /// Evaluates a FOR's bounds and step and sets the counter to `from`.
    fn for_start(
        &mut self,
        var: &str,
        [from, to]: [&Expr; 2],
        step: Option<&Expr>,
    ) -> Result<(Place, i64, i64), RunError> {
        let from = self.eval_int(from)?;
        let to = self.eval_int(to)?;
        let step = match step {
            Some(e) => self.eval_int(e)?,
            None => 1,
        };
        if step == 0 {
            return Err(self.err("FOR with STEP 0 never ends"));
        }
        let counter = self.place_of(&Expr::Var(var.to_string()))?;
        let Some(counter) = counter else {
            return Err(self.err(format!("{var} is not a variable")));
        };
        self.write_place(&counter, Value::Int(from))?;
        Ok((counter, to, step))
    }

    fn for_loop(
        &mut self,
        counter: &Place,
        to: i64,
        step: i64,
        body: &'a [Stmt],
        l: u32,
    ) -> Result<Flow, RunError> {
        while self.for_continues(counter, to, step)? {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
            self.for_next(counter, step)?;
        }
        Ok(Flow::Next)
    }

    fn for_continues(&mut self, counter: &Place, to: i64, step: i64) -> Result<bool, RunError> {
        let i = self.read_place(counter)?.int().map_err(|m| self.err(m))?;
        Ok(!((step > 0 && i > to) || (step < 0 && i < to)))
    }

    fn for_next(&mut self, counter: &Place, step: i64) -> Result<(), RunError> {
        let i = self.read_place(counter)?.int().map_err(|m| self.err(m))?;
        let next = int_result(i.checked_add(step)).map_err(|m| self.err(m))?;
        self.write_place(counter, next)
    }

    fn exec_loop(&mut self, body: &'a [Stmt], l: u32) -> Result<Flow, RunError> {
        loop {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
        }
    }

    fn exec_repeat(&mut self, body: &'a [Stmt], until: &Expr, l: u32) -> Result<Flow, RunError> {
        loop {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
            if self.eval_bool(until)? {
                return Ok(Flow::Next);
            }
        }
    }

    fn exec_switch(
        &mut self,
        selector: &Expr,
        cases: &'a [(Vec<Expr>, Vec<Stmt>)],
        default: Option<&'a [Stmt]>,
    ) -> Result<Flow, RunError> {
        match self.switch_body(selector, cases, default)? {
            Some(body) => self.exec_block(body),
            None => Ok(Flow::Next),
        }
    }

    /// The body a SWITCH runs, if any.
    fn switch_body(
        &mut self,
        selector: &Expr,
        cases: &'a [(Vec<Expr>, Vec<Stmt>)],
        default: Option<&'a [Stmt]>,
    ) -> Result<Option<&'a [Stmt]>, RunError> {
        let sel = self.eval(selector)?;
        for (vals, body) in cases {
            for v in vals {
                let v = self.eval(v)?;
                if values_equal(&sel, &v).map_err(|m| self.err(m))? {
                    return Ok(Some(body));
                }
            }
        }
        Ok(default)
    }

    fn exec_return(&mut self, e: Option<&Expr>) -> Result<Flow, RunError> {
        let v = match e {
            Some(e) => Some(self.eval(e)?),
            None => None,
        };
        Ok(Flow::Return(v))
    }

    fn exec_wait_sec(&mut self, e: &Expr, l: u32) -> Result<Flow, RunError> {
        let t = self.eval_num(e)?;
        if !(t >= 0.0 && t.is_finite()) {
            return Err(self.err(format!("WAIT SEC {t}: the time must not be negative")));
        }
        self.push(Step::Dwell {
            seconds: t,
            line: l,
        })?;
        Ok(Flow::Next)
    }

    fn exec_wait_for(&mut self, e: &Expr) -> Result<Flow, RunError> {
        if self.hosted.is_some() {
            // An advance-run stop (unless after CONTINUE), then the
            // condition is checked every cycle.
            self.host_advance_stop()?;
            while !self.eval_bool(e)? {
                self.host_wait(super::Wait::Cycle)?;
            }
            return Ok(Flow::Next);
        }
        if !self.eval_bool(e)? {
            return Err(self.err(
                "WAIT FOR: the condition is FALSE and nothing in the simulator can change it (the program would wait forever)",
            ));
        }
        Ok(Flow::Next)
    }

    fn exec_motion(
        &mut self,
        kind: KrlMotion,
        aux: Option<&Expr>,
        target: &Expr,
        approx: bool,
    ) -> Result<Flow, RunError> {
        let approx_mm = if approx { self.cdis()? } else { 0.0 };
        let speeds = self.speeds()?;
        self.planner_boundary(false)?;
        self.motion(kind, aux, target, approx_mm, speeds)?;
        Ok(Flow::Next)
    }
}
