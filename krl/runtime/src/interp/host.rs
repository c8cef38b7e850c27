//! Running on a host: a KRC-like runtime ([`run_hosted`]) drives the
//! interpreter in simulated time instead of letting it run ahead.
//!
//! The interpreter hands control to its [`Host`] before every statement
//! and whenever it must wait: for the next cycle (`WAIT FOR` with a FALSE
//! condition), for room in the advance run after it queued a motion, for
//! the robot to stand still (an advance-run stop: `WAIT SEC`, reading
//! `$POS_ACT`/`$AXIS_ACT`), for a time, or for `BRAKE` to stop the robot.
//! The host answers with a [`Turn`]: whether the wait is over, whether a
//! cycle boundary passed (then the interpreter checks its interrupt
//! conditions, as a KRC does every interpreter cycle) and which path
//! triggers of queued motions fired (the interpreter runs their actions).
//!
//! The variables travel with the turn: the host gets the interpreter's
//! globals ([`Globals`]) while it has control, so that two interpreters
//! (robot and Submit) on two threads share one set of globals with a
//! deterministic interleaving, and the host can update the system
//! variables (`$ROB_TIMER`, `$POS_ACT`, `$AXIS_ACT`, `$PRO_STATE1`, …).
//!
//! What the interpreter does itself in hosted mode: `INTERRUPT DECL`/`ON`/
//! `OFF`/`ENABLE`/`DISABLE` (a handler runs when its condition turns TRUE,
//! handlers of lower priority wait), `RESUME` (ends every routine above the
//! one that declared the running interrupt; the motions planned ahead are
//! discarded), `TRIGGER WHEN DISTANCE|PATH` (attached to the next motion),
//! `PULSE(signal, level, seconds)` (the signal is set now; the host sets it
//! back to the other level when the time is over: [`Host::pulse`]),
//! and everything of the test harness ([`run_with_files`](super::run_with_files)):
//! `CWRITE($FCT_CALL, …)` on the host's folder, `ON_ERROR_PROCEED`, `$ERR`.

use kuka_krl::{Expr, Stmt};

use super::harness::Globals;
use super::values::{Value, axis_value, pose_of};
use super::{Interp, RunError, Step, describe};

/// Why the interpreter waits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wait {
    /// `WAIT FOR` found its condition FALSE: one cycle passes.
    Cycle,
    /// A motion was queued: until the advance run has room (no more than
    /// `$ADVANCE` motions planned ahead of the one executing).
    Advance,
    /// An advance-run stop: until every queued motion is done.
    Standstill,
    /// Until the host's clock (`$ROB_TIMER`, ms) reaches this value.
    Until(i64),
    /// `BRAKE`: until the robot stands (the queued motions stay).
    Brake,
}

/// The host's answer when it gives control back.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Turn {
    /// The wait is over (always after a statement).
    pub ready: bool,
    /// A cycle boundary passed since the last turn: the interpreter
    /// checks its interrupt conditions.
    pub new_cycle: bool,
    /// Path triggers (ids given with [`Host::queue_motion`]) that fired.
    pub fired: Vec<u64>,
}

/// A path trigger of a queued motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriggerAt {
    /// Its id (reported back in [`Turn::fired`]).
    pub id: u64,
    /// `PATH = mm` (distance along the path from the end point, negative
    /// before it; from the start point with `onstart`) rather than
    /// `DISTANCE = 0|1` (start or end point).
    pub path: bool,
    /// The `DISTANCE`/`PATH` value.
    pub at: f64,
    /// `PATH … ONSTART`: `at` is measured from the motion's start point
    /// (after it for `at` > 0) instead of its end point.
    pub onstart: bool,
    /// `DELAY` in ms.
    pub delay_ms: f64,
}

/// The host ended the run (the program was cancelled, or the runtime
/// shuts down).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the program was cancelled")]
pub struct Cancelled;

/// The controller an interpreter runs on (see the [module docs](self)).
pub trait Host {
    /// Before a statement: the host may take the turn (the statement
    /// budget of a cycle is used up) and give it back later.
    fn statement(&mut self, vars: &mut Globals) -> Result<Turn, Cancelled>;
    /// Waits for `what`; returns after at most one cycle.
    fn wait(&mut self, vars: &mut Globals, what: Wait) -> Result<Turn, Cancelled>;
    /// Queues a motion for the robot, with its path triggers.
    fn queue_motion(&mut self, step: Step, triggers: Vec<TriggerAt>);
    /// `RESUME`: the motions planned ahead and not started are dropped.
    fn discard_motions(&mut self);
    /// `CWRITE($CMD, …, text)`: program control (`RUN`, `STOP`, `CANCEL`,
    /// `RESET`); whether the command was taken.
    fn command(&mut self, vars: &mut Globals, text: &str) -> bool;
    /// A routine is called (for the host's statistics, e.g. statements
    /// per pass of a Submit loop).
    fn called(&mut self, _routine: &str) {}
    /// A file function runs through `CWRITE($FCT_CALL, …)` (`krl_fopen`,
    /// `krl_fgets` …, as written in the program), for the host's
    /// statistics (file operations per motion).
    fn file_call(&mut self, _function: &str) {}
    /// `PULSE(signal[index], level, t)`: the program has set the element
    /// `index` of the BOOL array `signal` (`$OUT`) to `level`; the host
    /// sets it to `restore` (the other level) once its clock
    /// (`$ROB_TIMER`, ms) reaches `until_ms`, whatever the program does
    /// meanwhile. A host without a clock leaves the signal as it is.
    fn pulse(&mut self, _signal: &str, _index: i64, _restore: bool, _until_ms: i64) {}
}

/// A declared interrupt.
pub(super) struct Interrupt<'a> {
    when: &'a Expr,
    action: &'a Stmt,
    /// Frames active where it was declared (RESUME returns there).
    depth: usize,
    on: bool,
    enabled: bool,
    /// The condition at the last check (interrupts fire on an edge).
    last: bool,
}

/// The hosted-mode state of an interpreter.
pub(super) struct Hosted<'a> {
    pub(super) host: Box<dyn Host + Send + 'a>,
    /// Declared interrupts by priority (1 is the highest).
    interrupts: std::collections::BTreeMap<i64, Interrupt<'a>>,
    /// Priorities of the handlers running, innermost last.
    running: Vec<i64>,
    /// `TRIGGER`s waiting for the next motion.
    pending: Vec<(TriggerAt, &'a Stmt)>,
    /// Actions of the triggers queued with motions, by id.
    actions: std::collections::HashMap<u64, &'a Stmt>,
    next_trigger: u64,
}

impl<'a> Hosted<'a> {
    pub(super) fn new(host: Box<dyn Host + Send + 'a>) -> Self {
        Hosted {
            host,
            interrupts: Default::default(),
            running: Vec::new(),
            pending: Vec::new(),
            actions: Default::default(),
            next_trigger: 1,
        }
    }
}

impl<'a> Interp<'a> {
    /// Hands the globals to the host for one call.
    fn with_host(
        &mut self,
        f: impl FnOnce(&mut dyn Host, &mut Globals) -> Result<Turn, Cancelled>,
    ) -> Result<Turn, RunError> {
        let Some(h) = self.hosted.as_mut() else {
            return Ok(Turn {
                ready: true,
                ..Turn::default()
            });
        };
        let mut g = Globals {
            vars: std::mem::take(&mut self.globals),
            open_files: Vec::new(),
        };
        let r = f(h.host.as_mut(), &mut g);
        self.globals = g.vars;
        r.map_err(|_| RunError::Cancelled)
    }

    /// Before every statement in hosted mode.
    pub(super) fn host_statement(&mut self) -> Result<(), RunError> {
        let turn = self.with_host(|h, g| h.statement(g))?;
        self.after_turn(turn)
    }

    /// Waits for `what`, handling interrupts and triggers meanwhile.
    pub(super) fn host_wait(&mut self, what: Wait) -> Result<(), RunError> {
        loop {
            let turn = self.with_host(|h, g| h.wait(g, what))?;
            let ready = turn.ready;
            self.after_turn(turn)?;
            if ready {
                return Ok(());
            }
        }
    }

    fn after_turn(&mut self, turn: Turn) -> Result<(), RunError> {
        for id in turn.fired {
            let action = self.hosted.as_mut().and_then(|h| h.actions.remove(&id));
            if let Some(a) = action {
                self.exec(a)?;
            }
        }
        if turn.new_cycle {
            self.check_interrupts()?;
        }
        Ok(())
    }

    /// Runs the handler of every interrupt whose condition turned TRUE,
    /// highest priority first; a handler of a lower priority than one
    /// running waits.
    fn check_interrupts(&mut self) -> Result<(), RunError> {
        let Some(h) = self.hosted.as_ref() else {
            return Ok(());
        };
        let blocking = h.running.iter().copied().min().unwrap_or(i64::MAX);
        let candidates: Vec<(i64, &'a Expr, bool)> = h
            .interrupts
            .iter()
            .filter(|(p, i)| **p < blocking && i.on && i.enabled)
            .map(|(p, i)| (*p, i.when, i.last))
            .collect();
        for (prio, when, last) in candidates {
            let now = self.eval_bool(when)?;
            if let Some(i) = self
                .hosted
                .as_mut()
                .and_then(|h| h.interrupts.get_mut(&prio))
            {
                i.last = now;
            }
            if now && !last {
                self.run_handler(prio)?;
            }
        }
        Ok(())
    }

    fn run_handler(&mut self, prio: i64) -> Result<(), RunError> {
        let Some(action) = self
            .hosted
            .as_ref()
            .and_then(|h| h.interrupts.get(&prio))
            .map(|i| i.action)
        else {
            return Ok(());
        };
        if let Some(h) = self.hosted.as_mut() {
            h.running.push(prio);
        }
        let line = self.line;
        let r = self.exec(action);
        self.line = line;
        if let Some(h) = self.hosted.as_mut() {
            h.running.retain(|p| *p != prio);
        }
        r.map(|_| ())
    }

    /// `INTERRUPT DECL prio WHEN cond DO action` in hosted mode.
    pub(super) fn declare_interrupt(
        &mut self,
        prio: &Expr,
        when: &'a Expr,
        action: &'a Stmt,
    ) -> Result<(), RunError> {
        let p = self.eval_int(prio)?;
        if !(1..=128).contains(&p) {
            return Err(self.err(format!("INTERRUPT priority {p} is out of range (1..128)")));
        }
        let depth = self.frames.len();
        if let Some(h) = self.hosted.as_mut() {
            h.interrupts.insert(
                p,
                Interrupt {
                    when,
                    action,
                    depth,
                    on: false,
                    enabled: true,
                    last: false,
                },
            );
        }
        Ok(())
    }

    /// `INTERRUPT ON|OFF|ENABLE|DISABLE [prio]` in hosted mode.
    pub(super) fn switch_interrupt(
        &mut self,
        action: &str,
        prio: Option<&Expr>,
    ) -> Result<(), RunError> {
        let p = match prio {
            Some(e) => Some(self.eval_int(e)?),
            None => None,
        };
        let Some(h) = self.hosted.as_mut() else {
            return Ok(());
        };
        for (k, i) in h.interrupts.iter_mut() {
            if p.is_some_and(|p| p != *k) {
                continue;
            }
            match action {
                "ON" => {
                    i.on = true;
                    // An interrupt fires on the condition turning TRUE
                    // after it was switched on.
                    i.last = false;
                }
                "OFF" => i.on = false,
                "ENABLE" => i.enabled = true,
                _ => i.enabled = false,
            }
        }
        Ok(())
    }

    /// `RESUME`: drops the motions planned ahead and ends every routine
    /// above the one that declared the running interrupt.
    pub(super) fn resume(&mut self) -> Result<(), RunError> {
        let depth = self.hosted.as_ref().and_then(|h| {
            let prio = h.running.last()?;
            h.interrupts.get(prio).map(|i| i.depth)
        });
        let Some(depth) = depth else {
            return Err(self.err("RESUME outside an interrupt routine"));
        };
        if let Some(h) = self.hosted.as_mut() {
            h.host.discard_motions();
            h.pending.clear();
            h.running.clear();
        }
        Err(RunError::Resumed { depth })
    }

    /// `TRIGGER WHEN …`: attached to the next motion.
    pub(super) fn trigger(
        &mut self,
        path: bool,
        onstart: bool,
        at: &Expr,
        delay: &Expr,
        action: &'a Stmt,
    ) -> Result<(), RunError> {
        let at = self.eval_num(at)?;
        let delay_ms = self.eval_num(delay)?;
        self.trigger_at(path, onstart && path, at, delay_ms, action);
        Ok(())
    }

    /// A `TRIGGER` whose values are evaluated: attached to the next
    /// motion queued (a spline block's triggers are placed by
    /// [`Interp::spline`]).
    pub(super) fn trigger_at(
        &mut self,
        path: bool,
        onstart: bool,
        at: f64,
        delay_ms: f64,
        action: &'a Stmt,
    ) {
        if let Some(h) = self.hosted.as_mut() {
            let id = h.next_trigger;
            h.next_trigger += 1;
            h.pending.push((
                TriggerAt {
                    id,
                    path,
                    onstart,
                    at,
                    delay_ms,
                },
                action,
            ));
        }
    }

    /// A motion or a dwell in hosted mode: queue it and wait for room, or
    /// stop the advance run and wait.
    pub(super) fn host_step(&mut self, step: Step) -> Result<(), RunError> {
        match step {
            Step::Move { .. } => {
                if let Some(h) = self.hosted.as_mut() {
                    let triggers: Vec<TriggerAt> = h
                        .pending
                        .drain(..)
                        .map(|(t, action)| {
                            h.actions.insert(t.id, action);
                            t
                        })
                        .collect();
                    h.host.queue_motion(step, triggers);
                }
                self.host_wait(Wait::Advance)
            }
            Step::Dwell { seconds, .. } => {
                self.host_wait(Wait::Standstill)?;
                let now = self.globals.get("$ROB_TIMER").and_then(|v| v.int().ok());
                let until = now.unwrap_or(0) + (seconds * 1000.0).round() as i64;
                self.host_wait(Wait::Until(until))?;
                self.sync_position()
            }
        }
    }

    /// Reading `$POS_ACT`/`$AXIS_ACT` in hosted mode: an advance-run stop,
    /// then the programmed position is where the robot stands.
    pub(super) fn host_advance_stop(&mut self) -> Result<(), RunError> {
        if self.continue_active {
            return Ok(());
        }
        self.host_wait(Wait::Standstill)?;
        self.sync_position()
    }

    /// The programmed position from the host's `$AXIS_ACT`, and `$POS_ACT`
    /// from it in the current `$TOOL`/`$BASE`.
    fn sync_position(&mut self) -> Result<(), RunError> {
        let Some(v) = self.globals.get("$AXIS_ACT") else {
            return Ok(());
        };
        let Value::Struct(_, fields) = v else {
            return Ok(());
        };
        let mut axes = [0.0; 6];
        for (a, name) in axes.iter_mut().zip(super::values::AXIS_FIELDS) {
            if let Some((_, Value::Real(x))) = fields.iter().find(|(n, _)| n == name) {
                *a = *x;
            }
        }
        let (tool, base) = (self.tool()?, self.base()?);
        self.pos = self.model.forward(&axes, &tool, &base);
        self.axes = Some(axes);
        self.status = Some(self.model.status(&axes));
        self.turn = Some(kuka_kinematics::RobotModel::turn(&axes));
        let pos = self.pos_act();
        self.globals.insert("$POS_ACT".into(), pos);
        self.globals.insert("$AXIS_ACT".into(), axis_value(&axes));
        Ok(())
    }

    /// `PULSE(signal, level, seconds)` in hosted mode: an element of a
    /// BOOL system array (`$OUT[n]`) is set to `level` now, and the host
    /// sets it back after `seconds` ([`Host::pulse`]).
    pub(super) fn pulse(&mut self, args: &[Expr]) -> Result<(), RunError> {
        let [signal, level, time] = args else {
            return Err(self.err("PULSE takes a signal, a level and a time"));
        };
        let level = self.eval_bool(level)?;
        let seconds = self.eval_num(time)?;
        if !(seconds > 0.0 && seconds.is_finite()) {
            return Err(self.err(format!("PULSE: the time {seconds} s must be positive")));
        }
        let place = self.place_of(signal)?;
        let target = match &place {
            Some(super::vars::Place {
                root: super::vars::Root::Global(n),
                path,
                ..
            }) if n.starts_with('$') => match path.as_slice() {
                [super::values::PathElem::Index(ix)] if ix.len() == 1 => Some((n.clone(), ix[0])),
                _ => None,
            },
            _ => None,
        };
        let (Some(place), Some((name, index))) = (place, target) else {
            return Err(self.err(format!(
                "PULSE: {} is not a signal such as $OUT[n]",
                describe(signal)
            )));
        };
        self.write_place(&place, Value::Bool(level))?;
        let now = self
            .globals
            .get("$ROB_TIMER")
            .and_then(|v| v.int().ok())
            .unwrap_or(0);
        let until = now + (seconds * 1000.0).round() as i64;
        self.with_host(|h, _| {
            h.pulse(&name, index, !level, until);
            Ok(Turn::default())
        })?;
        Ok(())
    }

    /// `CWRITE($CMD, st, md, text)` in hosted mode.
    pub(super) fn host_command(&mut self, text: &str) -> Result<bool, RunError> {
        let text = text.to_string();
        let mut taken = false;
        self.with_host(|h, g| {
            taken = h.command(g, &text);
            Ok(Turn::default())
        })?;
        Ok(taken)
    }

    /// `INVERSE(target, start, err)` and `FORWARD(axes, err)` with the
    /// current `$TOOL` and `$BASE` (hosted and harness modes).
    pub(super) fn kinematic_function(
        &mut self,
        up: &str,
        args: &[Expr],
    ) -> Result<Option<Value>, RunError> {
        match (up, args) {
            ("INVERSE", [target, start, err]) => {
                let t = self.eval(target)?;
                let s = self.eval(start)?;
                let (tool, base) = (self.tool()?, self.base()?);
                let pose = pose_of(&t).map_err(|m| self.err(format!("INVERSE: {m}")))?;
                let start_axes = axes_of(&s)
                    .ok_or_else(|| self.err("INVERSE: the start must be an axis position"))?;
                let field = |name: &str| match &t {
                    Value::Struct(_, f) => f
                        .iter()
                        .find(|(n, _)| n == name)
                        .and_then(|(_, v)| v.int().ok()),
                    _ => None,
                };
                let (st, tu) = (field("S"), field("T"));
                let byte = |x: Option<i64>| x.and_then(|x| u8::try_from(x).ok());
                let sol = self
                    .model
                    .inverse(&pose, &tool, &base, byte(st), byte(tu), &start_axes);
                let (value, code) = match sol {
                    Ok(a) => (axis_value(&a), 0),
                    Err(_) => (axis_value(&start_axes), 1),
                };
                self.assign_out(err, Value::Int(code))?;
                Ok(Some(value))
            }
            ("FORWARD", [axes, err]) => {
                let a = self.eval(axes)?;
                let a = axes_of(&a)
                    .ok_or_else(|| self.err("FORWARD: the argument must be an axis position"))?;
                let (tool, base) = (self.tool()?, self.base()?);
                let p = self.model.forward(&a, &tool, &base);
                self.assign_out(err, Value::Int(0))?;
                let mut f: Vec<(String, Value)> = super::values::FRAME_FIELDS
                    .iter()
                    .zip(p.to_array())
                    .map(|(n, v)| (n.to_string(), Value::Real(v)))
                    .collect();
                f.push(("S".into(), Value::Int(self.model.status(&a).into())));
                f.push((
                    "T".into(),
                    Value::Int(kuka_kinematics::RobotModel::turn(&a).into()),
                ));
                Ok(Some(Value::Struct("E6POS".into(), f)))
            }
            ("INVERSE" | "FORWARD", _) => Err(self.err(format!("{up}: wrong number of arguments"))),
            _ => Ok(None),
        }
    }

    fn assign_out(&mut self, e: &Expr, v: Value) -> Result<(), RunError> {
        match self.place_of(e)? {
            Some(p) => self.write_place(&p, v),
            None => Err(self.err("the error argument must be a variable")),
        }
    }
}

/// The axes of an AXIS/E6AXIS value (missing axes are 0).
fn axes_of(v: &Value) -> Option<[f64; 6]> {
    let Value::Struct(_, fields) = v else {
        return None;
    };
    let mut axes = [0.0; 6];
    let mut any = false;
    for (a, name) in axes.iter_mut().zip(super::values::AXIS_FIELDS) {
        if let Some((_, x)) = fields.iter().find(|(n, _)| n == name) {
            *a = x.num().ok()?;
            any = true;
        }
    }
    any.then_some(axes)
}
