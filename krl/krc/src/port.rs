//! The interpreters' side of the scheduler: each interpreter thread holds
//! a [`Port`], the [`Host`] its interpreter hands control to. A turn moves
//! the shared globals to the scheduler and blocks until the scheduler
//! hands them back: only one interpreter runs at a time.

use std::collections::BTreeMap;
use std::sync::mpsc::{Receiver, Sender};
use std::sync::{Arc, Mutex};

use kuka_krl_runtime::interp::{Cancelled, Globals, Host, RunError, Step, TriggerAt, Turn, Wait};

/// Which interpreter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Who {
    /// The robot interpreter (`kb_main`, `kbu<n>`).
    Robot,
    /// The Submit interpreter (`sps.sub`).
    Submit,
}

/// What an interpreter thread tells the scheduler.
pub(crate) enum Msg {
    /// The interpreter gives control back: its globals and what it waits
    /// for (`None`: its statement budget for this cycle is used up).
    Yield {
        vars: Globals,
        wait: Option<Wait>,
        /// The turn's generation (a thread of a cancelled program is
        /// ignored).
        generation: u64,
    },
    /// A motion for the robot.
    Motion {
        step: Step,
        triggers: Vec<TriggerAt>,
    },
    /// `RESUME`: drop what was planned ahead.
    Discard,
    /// `CWRITE($CMD, …)`.
    Command(String),
    /// `PULSE`: set `signal[index]` to `restore` at `until_ms`.
    Pulse {
        signal: String,
        index: i64,
        restore: bool,
        until_ms: i64,
    },
    /// The interpreter's routine ended (or failed, or was cancelled).
    Ended {
        who: Who,
        result: Result<(), RunError>,
        /// The globals as the program left them (not when cancelled).
        vars: Option<Globals>,
        generation: u64,
    },
}

/// The scheduler's answer to a [`Msg::Yield`].
pub(crate) struct Resume {
    pub(crate) vars: Globals,
    pub(crate) ready: bool,
    pub(crate) new_cycle: bool,
    pub(crate) fired: Vec<u64>,
    /// End the run (`CANCEL`, shutdown).
    pub(crate) cancel: bool,
}

/// How many passes [`PassStats::recent`] keeps for the percentiles: a
/// controller that runs for days must not grow with every pass.
pub(crate) const RECENT_PASSES: usize = 100_000;

/// Statistics of the Submit loop's passes.
#[derive(Debug, Default, Clone)]
pub(crate) struct PassStats {
    /// Statements of the last [`RECENT_PASSES`] completed passes of
    /// `kb_submit_cycle`.
    pub(crate) recent: std::collections::VecDeque<u64>,
    /// Completed passes.
    pub(crate) count: u64,
    /// Statements of the longest pass.
    pub(crate) max: u64,
    /// Passes over the budget.
    pub(crate) over: u64,
    /// One cycle's Submit budget (statements).
    pub(crate) budget: u64,
    current_statements: u64,
    started: bool,
}

impl PassStats {
    /// Statistics against a Submit budget of `budget` statements per cycle.
    pub(crate) fn new(budget: u64) -> Self {
        PassStats {
            budget,
            ..PassStats::default()
        }
    }

    fn pass_starts(&mut self) {
        if self.started {
            let n = self.current_statements;
            if self.recent.len() == RECENT_PASSES {
                self.recent.pop_front();
            }
            self.recent.push_back(n);
            self.count += 1;
            self.max = self.max.max(n);
            if n > self.budget {
                self.over += 1;
                // The 1st, 10th, 100th … overrun: visible in the log
                // without a line per pass.
                if self
                    .over
                    .checked_ilog10()
                    .is_some_and(|e| 10u64.pow(e) == self.over)
                {
                    tracing::warn!(
                        statements = n,
                        budget = self.budget,
                        overruns = self.over,
                        passes = self.count,
                        "a Submit pass needed more statements than one cycle's budget (it continued in the next cycle)"
                    );
                }
            }
        }
        self.started = true;
        self.current_statements = 0;
    }
}

/// An interpreter's [`Host`].
pub(crate) struct Port {
    pub(crate) who: Who,
    pub(crate) generation: u64,
    pub(crate) tx: Sender<Msg>,
    pub(crate) rx: Receiver<Resume>,
    pub(crate) budget: u64,
    pub(crate) left: u64,
    /// The Submit loop's pass statistics (Submit port only).
    pub(crate) passes: Option<Arc<Mutex<PassStats>>>,
    /// File functions called, by name (lower case).
    pub(crate) file_calls: Arc<Mutex<BTreeMap<String, u64>>>,
    /// Most passes of the Submit loop begun in one cycle (0 = no limit).
    pub(crate) max_passes: u32,
    /// Passes begun in this cycle.
    pub(crate) passes_this_cycle: u32,
    /// A pass was held back to the next cycle by `max_passes`.
    pub(crate) deferred: bool,
}

impl Port {
    fn turn(&mut self, vars: &mut Globals, wait: Option<Wait>) -> Result<Turn, Cancelled> {
        let sent = self.tx.send(Msg::Yield {
            vars: std::mem::take(vars),
            wait,
            generation: self.generation,
        });
        if sent.is_err() {
            return Err(Cancelled);
        }
        let r = self.rx.recv().map_err(|_| Cancelled)?;
        if r.cancel {
            return Err(Cancelled);
        }
        *vars = r.vars;
        if r.new_cycle {
            self.left = self.budget;
            self.passes_this_cycle = u32::from(self.deferred);
            self.deferred = false;
        }
        Ok(Turn {
            ready: r.ready,
            new_cycle: r.new_cycle,
            fired: r.fired,
        })
    }
}

impl Host for Port {
    fn statement(&mut self, vars: &mut Globals) -> Result<Turn, Cancelled> {
        if let Some(p) = &self.passes {
            let mut p = p.lock().unwrap_or_else(|e| e.into_inner());
            p.current_statements += 1;
        }
        if self.left > 0 {
            self.left -= 1;
            return Ok(Turn {
                ready: true,
                ..Turn::default()
            });
        }
        let mut t = self.turn(vars, None)?;
        t.ready = true;
        Ok(t)
    }

    fn wait(&mut self, vars: &mut Globals, what: Wait) -> Result<Turn, Cancelled> {
        // The Submit interpreter has no advance run and moves nothing.
        if self.who == Who::Submit && matches!(what, Wait::Advance | Wait::Standstill | Wait::Brake)
        {
            return Ok(Turn {
                ready: true,
                ..Turn::default()
            });
        }
        self.turn(vars, Some(what))
    }

    fn queue_motion(&mut self, step: Step, triggers: Vec<TriggerAt>) {
        let _ = self.tx.send(Msg::Motion { step, triggers });
    }

    fn discard_motions(&mut self) {
        let _ = self.tx.send(Msg::Discard);
    }

    fn command(&mut self, _vars: &mut Globals, text: &str) -> bool {
        self.tx.send(Msg::Command(text.to_string())).is_ok()
    }

    fn called(&mut self, routine: &str) {
        if let Some(p) = &self.passes
            && routine.eq_ignore_ascii_case("kb_submit_cycle")
        {
            p.lock().unwrap_or_else(|e| e.into_inner()).pass_starts();
            if self.max_passes > 0 && self.passes_this_cycle >= self.max_passes {
                // This pass begins in the next cycle.
                self.left = 0;
                self.deferred = true;
            } else {
                self.passes_this_cycle += 1;
            }
        }
    }

    fn pulse(&mut self, signal: &str, index: i64, restore: bool, until_ms: i64) {
        let _ = self.tx.send(Msg::Pulse {
            signal: signal.to_string(),
            index,
            restore,
            until_ms,
        });
    }

    fn file_call(&mut self, function: &str) {
        let mut calls = self.file_calls.lock().unwrap_or_else(|e| e.into_inner());
        *calls.entry(function.to_ascii_lowercase()).or_insert(0) += 1;
    }
}
