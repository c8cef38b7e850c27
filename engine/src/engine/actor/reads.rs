//! Reading the controller: state and result files, each result handled
//! once by its command id, lost commands, restarts, junk files, and the
//! folders' health.

use super::*;
use crate::io::{AnalogChange, IoChange, IoKind};
use kuka_protocol::IoState;

impl Actor {
    /// Reads the state and result files and reacts to what changed.
    pub(super) fn refresh(&mut self, changed: Changed) {
        let now = Instant::now();
        let state = if changed.state {
            self.channel.read_state()
        } else {
            ReadOutcome::Missing
        };
        match state {
            ReadOutcome::Record(s) => {
                self.oversize(kuka_protocol::STATE_FILE, None);
                self.faults.version = None;
                let old_seq = self.ctl.state.as_ref().map(|old| old.seq);
                if old_seq != Some(s.seq) {
                    // The first heartbeat seen may be a stale file: only a change proves life.
                    if let Some(old) = old_seq {
                        self.ctl.seq_changed_at = Some(now);
                        // seq only grows (wrapping at the top): a smaller one
                        // means a controller program that started afresh.
                        if s.seq < old && old < i32::MAX - 1_000_000 {
                            self.on_restart(old, s.seq, now);
                        }
                    }
                    self.on_state(s, now);
                }
            }
            ReadOutcome::Invalid(kuka_protocol::DecodeError::Version(v)) => {
                if self.faults.version.is_none() {
                    let detail = format!(
                        "the controller program speaks protocol version {v}; this service speaks version {}: install the KRL program of this release (krl/KRC, docs/CONTROLLER.md)",
                        kuka_protocol::PROTOCOL_VERSION
                    );
                    tracing::error!(version = v, "controller speaks another protocol version");
                    self.faults.version = Some(detail);
                }
            }
            ReadOutcome::Invalid(e) => {
                tracing::trace!(error = %e, "state file not complete; reading again later")
            }
            ReadOutcome::TooLarge(len) => self.oversize(kuka_protocol::STATE_FILE, Some(len)),
            ReadOutcome::Failed(e) => tracing::debug!(error = %e, "state file unreadable"),
            ReadOutcome::Missing | ReadOutcome::Locked | ReadOutcome::Unchanged => {}
        }
        let results = if changed.results {
            // A poll (or an event the watcher could not attribute) reads
            // whatever the stamp says.
            self.channel.read_results(changed == Changed::BOTH)
        } else {
            ReadOutcome::Missing
        };
        match results {
            ReadOutcome::Record(r) => {
                self.oversize(kuka_protocol::RESULT_FILE, None);
                for rec in r.results {
                    if !self.ledger.is_seen(rec.cid) {
                        self.ledger.see(rec.cid);
                        self.on_result(rec);
                    }
                }
                // Read without the running command's result: lost if the
                // controller has been idle with it long enough.
                self.check_lost(now);
            }
            ReadOutcome::Invalid(e) => {
                tracing::debug!(error = %e, "result file not complete; reading again later")
            }
            ReadOutcome::TooLarge(len) => self.oversize(kuka_protocol::RESULT_FILE, Some(len)),
            ReadOutcome::Failed(e) => tracing::debug!(error = %e, "result file unreadable"),
            ReadOutcome::Missing | ReadOutcome::Locked | ReadOutcome::Unchanged => {}
        }
        let online = self
            .ctl
            .seq_changed_at
            .is_some_and(|t| now.duration_since(t) < self.cfg.offline_after);
        if online != self.ctl.online {
            self.ctl.online = online;
            if online {
                tracing::info!(event_id = events::CONTROLLER_ONLINE, "controller online");
            } else {
                tracing::warn!(
                    event_id = events::CONTROLLER_OFFLINE,
                    after_ms = self.cfg.offline_after.as_millis(),
                    "controller offline: heartbeat stopped"
                );
                self.on_offline();
            }
        }
    }

    pub(super) fn on_state(&mut self, mut s: StateFile, now: Instant) {
        // A state file written before a reset the controller took (it had
        // not accepted the RESET yet) shows the error the reset cleared.
        if let Some(rc) = self.ctl.reset_cid {
            if written_after(&s, rc) {
                self.ctl.reset_cid = None;
            } else {
                forget_error(&mut s);
            }
        }
        // last_cid is the command's id or newer: the controller accepted it.
        let accepted = |cid: Cid| s.last_cid > 0 && !kuka_protocol::cid_is_newer(cid, s.last_cid);
        let running = |cid: Cid| s.status == ControllerStatus::Busy && s.busy_cid == cid;
        // A state file written before the newest result (the controller had
        // not accepted that command yet, or was still running it) holds an
        // older position than the result: read right after the result, it
        // would set the start of the next motion back (a LIN planned from
        // where the robot was before the PTP that just ended). That holds
        // for `last_cid` 0 too: a file from before the controller accepted
        // its first command (a controller recovers `last_cid` from its
        // result file when it starts, so 0 never follows a result; a
        // restart clears `result_cid`).
        let stale = self
            .ctl
            .result_cid
            .is_some_and(|r| s.last_cid <= 0 || !accepted(r) || running(r));
        if !stale {
            self.ctl.pose = Some((s.position, s.s, s.t));
            self.ctl.axes = Some(s.axes);
            self.ctl.pose_at = Some(now);
            self.ctl.tool = Some(s.tool);
            self.ctl.base = Some(s.base);
        }
        // The result file's stamp only when the command has just gone idle
        // (a stat, not on every heartbeat of a running job).
        let stamp = match &self.inflight {
            Some(f) if f.idle_since.is_none() && accepted(f.cid) && !running(f.cid) => {
                self.channel.results_stamp()
            }
            _ => None,
        };
        // While it runs, a stat per state file: the stamp a restart changes.
        let busy_stamp = match &self.inflight {
            Some(f) if running(f.cid) => self.channel.results_stamp(),
            _ => None,
        };
        if let Some(f) = &mut self.inflight {
            if (accepted(f.cid) || s.busy_cid == f.cid) && !f.acked {
                f.acked = true;
            }
            if running(f.cid) {
                f.busy_stamp = busy_stamp;
            }
            if accepted(f.cid) && !running(f.cid) {
                if f.idle_since.is_none() {
                    f.idle_since = Some(now);
                    // Compared with the file as it was while the command
                    // ran, if a state showed that: a result file rewritten
                    // since then without its result means a restart.
                    f.idle_stamp = f.busy_stamp.or(stamp);
                }
            } else {
                f.idle_since = None;
                f.idle_stamp = None;
            }
            if s.status == ControllerStatus::Busy && s.busy_cid == f.cid {
                let id = f.id;
                let index = s.busy_index as usize;
                self.progress_to(id, index);
            }
        }
        self.path_state(&s);
        self.io_changes(&s);
        self.analog_changes(&s);
        // The override changed on the controller (a variable write of
        // $OV_PRO, the pendant): the speeds follow it. (Only a change
        // between two state files: a state written before a SETSPEED ran
        // must not take back the value it set.)
        if let Some(prev) = self.ctl.state.as_ref()
            && (s.override_pct - prev.override_pct).abs() > 1e-9
            && (0.0..=100.0).contains(&s.override_pct)
        {
            self.speeds.override_pct = s.override_pct;
        }
        self.ctl.state = Some(s);
        // A RESET's result held for a state written after it: decided now
        // (or held on, if this one is older too).
        if let Some((r, _)) = self.ctl.reset_held {
            self.on_result(r);
        }
    }

    /// `analog` events for the watched analog channels that moved by their
    /// deadband since they last published one (the first report of a
    /// channel is its baseline: nothing changed yet). A state file without
    /// the `ANS` line (PROTOCOL.md §7: not every one has it) changes nothing.
    fn analog_changes(&mut self, s: &StateFile) {
        let Some(new) = s.analog.as_ref() else {
            return;
        };
        let io = self.shared.io();
        for (k, (kind, values, configs)) in [
            (IoKind::Input, &new.inputs, &io.analog_inputs),
            (IoKind::Output, &new.outputs, &io.analog_outputs),
        ]
        .into_iter()
        .enumerate()
        {
            for (i, &value) in values.iter().enumerate() {
                let seen = &mut self.ctl.analog_published[k][i];
                let Some(last) = *seen else {
                    *seen = Some(value);
                    continue;
                };
                let Some(c) = configs
                    .iter()
                    .find(|c| c.watch && usize::from(c.index) == i + 1)
                else {
                    *seen = Some(value);
                    continue;
                };
                // (1e-9: the values are thousandths; a change of exactly
                // the deadband counts.)
                if (value - last).abs() + 1e-9 >= c.deadband {
                    *seen = Some(value);
                    self.shared.publish(Event::Analog(AnalogChange {
                        kind,
                        index: c.index,
                        name: c.name.clone(),
                        value,
                    }));
                }
            }
        }
    }

    /// `io` events for the watched signals that changed since the last
    /// state file (none for the first one: nothing changed yet).
    fn io_changes(&self, s: &StateFile) {
        let (Some(new), Some(old)) = (
            s.io.as_ref(),
            self.ctl.state.as_ref().and_then(|p| p.io.as_ref()),
        ) else {
            return;
        };
        if new.base != old.base {
            return;
        }
        let io = self.shared.io();
        for (kind, a, b) in [
            (IoKind::Input, old.inputs, new.inputs),
            (IoKind::Output, old.outputs, new.outputs),
        ] {
            let changed = a ^ b;
            for k in 0..IoState::WIDTH {
                let index = new.base + k;
                if changed & (1 << k) != 0 && io.watched(kind, index) {
                    self.shared.publish(Event::Io(IoChange {
                        kind,
                        index,
                        name: io.name_of(kind, index).map(str::to_string),
                        value: b & (1 << k) != 0,
                    }));
                }
            }
        }
    }

    /// The job is executing with `index` motions completed: a job event
    /// for each motion completed since the last one it published (a
    /// heartbeat may report several at once: short motions of a path).
    fn progress_to(&mut self, id: JobId, index: usize) {
        let Ok(j) = self.shared_job(id) else { return };
        if j.state == JobState::Executing && j.completed == index {
            return;
        }
        let from = match j.state {
            JobState::Executing if j.completed < index => j.completed + 1,
            // Not reported executing yet: from its first motion on.
            JobState::Queued | JobState::Sent => 0,
            _ => index,
        };
        for k in from..=index {
            self.shared.update(id, |j| {
                j.state = JobState::Executing;
                j.completed = k;
            });
        }
    }

    /// Whether the RESET result `r` waits for the controller's next state
    /// file (held in `ctl.reset_held`; `on_state` hands it back): the
    /// newest state file was written before the controller took the RESET
    /// and shows the safety circuit open. The operator may have closed it
    /// and acknowledged since (a client that acknowledges and resets at
    /// once), so that file cannot tell whether the reset helped; the next
    /// one can. Held at most [`RESET_STATE_WAIT`]; then decided on what
    /// is known.
    fn hold_reset(&mut self, r: &ResultRecord) -> bool {
        let is_reset = self
            .inflight
            .as_ref()
            .is_some_and(|f| f.cid == r.cid && matches!(f.op, Operation::Reset));
        let Some(s) = self.ctl.state.as_ref() else {
            return false;
        };
        let open = s.safety.as_ref().is_some_and(circuit_open);
        if !is_reset || r.code != ResultCode::Ok || !open || written_after(s, r.cid) {
            self.ctl.reset_held = None;
            return false;
        }
        let since = match self.ctl.reset_held {
            Some((held, since)) if held.cid == r.cid => since,
            _ => Instant::now(),
        };
        if since.elapsed() >= RESET_STATE_WAIT {
            self.ctl.reset_held = None;
            return false;
        }
        self.ctl.reset_held = Some((*r, since));
        true
    }

    pub(super) fn on_result(&mut self, r: ResultRecord) {
        if self.on_append_result(&r) {
            return;
        }
        let is_frame_op = |op: &Operation| {
            matches!(
                op,
                Operation::SetTool(_)
                    | Operation::GetTool
                    | Operation::SetBase(_)
                    | Operation::GetBase
            )
        };
        if let Some(stop) = &self.stop
            && stop.cid == r.cid
        {
            if let Some(stop) = self.stop.take() {
                for w in stop.waiters {
                    let _ = w.send(Ok(()));
                }
            }
            self.ctl.pose = Some((r.position, r.s, r.t));
            self.ctl.axes = Some(r.axes);
            self.ctl.pose_at = Some(Instant::now());
            self.ctl.result_cid = Some(r.cid);
            // Results come in command-id order: a command older than the STOP
            // without a result of its own was superseded before the controller
            // read it, so it never ran — unless the controller had picked it
            // up (then it lost the command, e.g. in a restart).
            if let Some(f) = self
                .inflight
                .take_if(|f| kuka_protocol::cid_is_newer(r.cid, f.cid))
            {
                let why = if f.acked {
                    let done = self.shared_job(f.id).map_or(0, |j| j.completed);
                    tracing::warn!(
                        job = f.id,
                        cid = f.cid,
                        completed = done,
                        "stopped; the controller gave no result for the command it had picked up"
                    );
                    BridgeError::new(
                        ErrorCode::Cancelled,
                        format!(
                            "stopped; the controller had picked up command {} but gave no result for it (was it restarted?); {done} motion(s) had completed by its last report",
                            f.cid
                        ),
                    )
                } else {
                    tracing::info!(
                        job = f.id,
                        cid = f.cid,
                        "command superseded by stop before it ran"
                    );
                    BridgeError::new(
                        ErrorCode::Cancelled,
                        "stopped before the controller started it; nothing moved",
                    )
                };
                let (state, why) = self.stopped_path(f.id, why);
                self.shared.finish(f.id, state, why);
            }
            return;
        }
        if self.hold_reset(&r) {
            return;
        }
        let Some(f) = self.inflight.take_if(|f| f.cid == r.cid) else {
            self.on_other_result(r);
            return;
        };
        self.answered_at = Some(Instant::now());
        self.ctl.axes = Some(r.axes);
        self.ctl.pose_at = self.answered_at;
        self.ctl.result_cid = Some(r.cid);
        match &f.op {
            Operation::SetTool(_) | Operation::GetTool if r.code == ResultCode::Ok => {
                self.ctl.tool = Some(r.position)
            }
            Operation::SetBase(_) | Operation::GetBase if r.code == ResultCode::Ok => {
                self.ctl.base = Some(r.position)
            }
            Operation::SetSpeed(s) if r.code == ResultCode::Ok => self.speeds = *s,
            op if !is_frame_op(op) => self.ctl.pose = Some((r.position, r.s, r.t)),
            _ => {}
        }
        let safety = self.ctl.state.as_ref().and_then(|s| s.safety.as_ref());
        let simulated = self.ctl.state.as_ref().is_some_and(|s| s.simulated);
        let mut error = result_error(&r).map(|e| explain_safety(e, safety, simulated));
        if error.is_none()
            && let Some(refused) = self
                .path
                .as_ref()
                .filter(|p| p.cid == r.cid)
                .and_then(|p| p.refused.clone())
        {
            // The path ran what was accepted; it ends with the refusal.
            error = Some(refused);
        }
        if r.code == ResultCode::Cancelled
            && let Some(stop) = error.take()
        {
            // Also when a stop cut the accepted motions short afterwards.
            error = Some(self.stopped_path(f.id, stop).1);
        }
        if matches!(f.op, Operation::Reset)
            && error.is_none()
            && let Some(s) = safety.filter(|s| circuit_open(s))
        {
            // The controller took the RESET, but an open safety circuit
            // keeps it stopped (the KRL program stays NOT_READY): say so
            // rather than answer "done".
            error = Some(explain_safety(
                BridgeError::new(
                    ErrorCode::ControllerError,
                    "the reset cannot clear the controller's error yet",
                ),
                Some(s),
                simulated,
            ));
        }
        let cleared = matches!(f.op, Operation::Reset)
            && error.is_none()
            && r.code == ResultCode::Ok
            && safety
                .is_none_or(|s| s.alarm_stop && s.user_safety && s.drives_ready && !s.stop_message);
        if cleared {
            // A reset the controller took with its safety circuit closed
            // clears its error state: the state the clients see says so
            // at once, not only once the next state file is read (a client
            // that resets and then opens a path must not be refused on the
            // state file from before the reset). A state file written
            // before the reset no longer sets the error back (`on_state`).
            self.ctl.reset_cid = Some(r.cid);
            if let Some(s) = self.ctl.state.as_mut() {
                forget_error(s);
            }
        }
        if !matches!(f.op, Operation::Move(_) | Operation::Path(_))
            && let Some(e) = &mut error
        {
            e.motion = None;
        }
        if let Operation::RunProgram(p) = &f.op {
            error = error.map(|e| program_result_error(e, &r, &p.info.name));
        }
        let elapsed_ms = f.sent_at.elapsed().as_secs_f64() * 1000.0;
        match &error {
            None => tracing::debug!(job = f.id, cid = r.cid, elapsed_ms, "job done"),
            Some(e) if e.code == ErrorCode::Cancelled => {
                tracing::info!(job = f.id, cid = r.cid, detail = %e.detail, "job cancelled")
            }
            Some(e) => {
                tracing::warn!(event_id = events::JOB_FAILED, job = f.id, cid = r.cid, code = e.code.as_str(), detail = %e.detail, "job failed")
            }
        }
        let frame_op = is_frame_op(&f.op);
        if matches!(f.op, Operation::Move(_) | Operation::Path(_)) && r.completed > 0 {
            // The motions finished since the last heartbeat, each with its
            // event, before the one that ends the job.
            self.progress_to(f.id, r.completed as usize - 1);
        }
        // Publish what the result changed (pose, frames, speeds) before the
        // job completes, so a client woken by the job reads the new state.
        self.publish_state();
        self.shared.update(f.id, |j| {
            j.finished_ms = Some(now_ms());
            j.completed = if matches!(f.op, Operation::Move(_) | Operation::Path(_)) {
                r.completed as usize
            } else if matches!(f.op, Operation::RunProgram(_)) && r.code == ResultCode::Ok {
                // A program that ended ran all its motions: the KRL program
                // on a KRC answers 0 (it cannot count another program's
                // statements), the native simulator the count.
                (r.completed as usize).max(j.motions)
            } else {
                0
            };
            j.axes = Some(r.axes.into());
            if frame_op {
                j.frame = Some(r.position.into());
            } else {
                j.position = Some(Position::new(&r.position, r.s, r.t));
            }
            j.state = match r.code {
                // A path that ran what was accepted of it but refused a motion.
                ResultCode::Ok if error.is_some() => JobState::Failed,
                ResultCode::Ok => JobState::Done,
                // A stop after a refusal: the refusal is how it ended.
                ResultCode::Cancelled
                    if error
                        .as_ref()
                        .is_some_and(|e| e.code != ErrorCode::Cancelled) =>
                {
                    JobState::Failed
                }
                ResultCode::Cancelled => JobState::Cancelled,
                _ => JobState::Failed,
            };
            j.error = error;
        });
    }

    /// A result that is neither the running command's nor the STOP's: the
    /// late answer of a command whose job has already ended (it then
    /// takes the controller's outcome), or a foreign line (reported).
    pub(super) fn on_other_result(&mut self, r: ResultRecord) {
        match self.ledger.job_of(r.cid) {
            Some(Some(id)) => {
                let Ok(job) = self.shared_job(id) else { return };
                let state = match r.code {
                    ResultCode::Ok => JobState::Done,
                    ResultCode::Cancelled => JobState::Cancelled,
                    _ => JobState::Failed,
                };
                let ctl_state = self.ctl.state.as_ref();
                let mut error = result_error(&r).map(|e| {
                    explain_safety(
                        e,
                        ctl_state.and_then(|s| s.safety.as_ref()),
                        ctl_state.is_some_and(|s| s.simulated),
                    )
                });
                if job.operation != "move"
                    && job.operation != "path"
                    && let Some(e) = &mut error
                {
                    e.motion = None;
                }
                tracing::warn!(
                    job = id,
                    cid = r.cid,
                    code = r.code.code(),
                    was = job.state.as_str(),
                    "late result: the job takes the controller's outcome"
                );
                self.shared.update(id, |j| {
                    j.state = state;
                    j.error = error;
                    j.late_result = true;
                    j.finished_ms = Some(now_ms());
                    if j.operation == "move" || j.operation == "path" || r.code == ResultCode::Ok {
                        j.completed = r.completed as usize;
                    }
                    j.axes = Some(r.axes.into());
                    if j.frame.is_none() {
                        j.position = Some(Position::new(&r.position, r.s, r.t));
                    }
                });
            }
            Some(None) => {
                tracing::debug!(cid = r.cid, "late result of a stop");
            }
            None => {
                tracing::warn!(
                    event_id = events::FOREIGN_RESULT,
                    cid = r.cid,
                    code = r.code.code(),
                    "result for a command this service did not send; ignored"
                );
                self.shared.publish(Event::Alarm(BridgeError::new(
                    ErrorCode::ProtocolError,
                    format!(
                        "the result file holds a result for command {}, which this run of the service did not send (an earlier run's command, or another writer); it is ignored",
                        r.cid
                    ),
                )));
            }
        }
    }

    /// The running command was accepted by the controller, which has been
    /// idle since without a result for it: it lost the command (a restart
    /// of the controller program). The job ends now with what is known.
    pub(super) fn check_lost(&mut self, now: Instant) {
        let Some(f) = &self.inflight else { return };
        let Some(since) = f.idle_since else { return };
        let restarted = self.ctl.restarted_at.is_some_and(|t| t >= f.sent_at);
        if !restarted
            && (now.duration_since(since) < LOST_GRACE
                || self.channel.results_stamp() == f.idle_stamp)
        {
            return;
        }
        let Some(f) = self.inflight.take() else {
            return;
        };
        let job = self.shared_job(f.id).ok();
        let done = job.as_ref().map_or(0, |j| j.completed);
        let of = job
            .as_ref()
            .filter(|j| j.motions > 0)
            .map_or(String::new(), |j| format!(" of {}", j.motions));
        let why = if restarted {
            "the controller program restarted"
        } else {
            "the controller is idle"
        };
        let e = BridgeError::new(
            ErrorCode::CommandLost,
            format!(
                "the controller accepted command {} but {why} without a result for it; {done}{of} motion(s) had completed by its last report, the rest did not run",
                f.cid
            ),
        );
        tracing::warn!(
            event_id = events::JOB_FAILED,
            job = f.id,
            cid = f.cid,
            completed = done,
            "command lost by the controller"
        );
        self.shared.finish(f.id, JobState::Failed, e);
        self.answered_at = Some(now);
    }

    /// The heartbeat number went backwards.
    pub(super) fn on_restart(&mut self, old: i32, new: i32, now: Instant) {
        tracing::warn!(
            event_id = events::CONTROLLER_RESTARTED,
            old_seq = old,
            new_seq = new,
            "controller restarted (heartbeat number went back)"
        );
        self.ctl.restarted_at = Some(now);
        // The restarted program's state files are its own: none of them is
        // older than a result of the program before.
        self.ctl.result_cid = None;
        self.shared.publish(Event::Alarm(BridgeError::new(
            ErrorCode::ControllerOffline,
            "the controller program restarted (its heartbeat number started again)",
        )));
    }

    /// A result or state file over [`kuka_protocol::MAX_CONTROLLER_FILE_LEN`]
    /// (`Some(size)`), or one of normal size again (`None`).
    pub(super) fn oversize(&mut self, file: &'static str, len: Option<u64>) {
        match len {
            Some(len) => {
                if self.faults.oversize.is_none() {
                    tracing::error!(
                        file,
                        len,
                        max = kuka_protocol::MAX_CONTROLLER_FILE_LEN,
                        "controller file too large; not read"
                    );
                    let detail = format!(
                        "{file} is {len} bytes, more than the {} a protocol file can be; it is not read until it is rewritten",
                        kuka_protocol::MAX_CONTROLLER_FILE_LEN
                    );
                    self.shared.publish(Event::Alarm(BridgeError::new(
                        ErrorCode::ProtocolError,
                        detail.clone(),
                    )));
                    self.faults.oversize = Some((file, detail));
                }
            }
            None => {
                if self
                    .faults
                    .oversize
                    .as_ref()
                    .is_some_and(|(f, _)| *f == file)
                {
                    self.faults.oversize = None;
                }
            }
        }
    }

    /// Checks now and then that the channel and data folders can be
    /// written, so `degraded` shows before a command fails.
    pub(super) fn probe_folders(&mut self, now: Instant) {
        if self
            .probed_at
            .is_some_and(|t| now.duration_since(t) < PROBE_INTERVAL)
        {
            return;
        }
        self.probed_at = Some(now);
        // A lock shows before a command meets it: when two probes in a row
        // (a second apart) find it; one may meet the controller reading.
        let held = self.pending.is_none() && self.channel.command_locked();
        self.ctl.lock_probes = if held { self.ctl.lock_probes + 1 } else { 0 };
        if !self.ctl.locked && self.ctl.lock_probes >= 2 {
            tracing::warn!(event_id = events::CHANNEL_LOCKED, dir = %self.channel.dir().display(), "command file locked by another process");
            self.ctl.locked = true;
            self.shared.publish(Event::Alarm(BridgeError::new(
                ErrorCode::ChannelLocked,
                "the command file is locked by another process",
            )));
        }
        match self.channel.probe_writable() {
            Ok(()) => self.faults.channel = None,
            Err(e) => {
                if self.faults.channel.is_none() {
                    tracing::error!(error = %crate::error::chain(&e), "channel folder not writable");
                }
                self.faults.channel = Some("the service cannot write into the channel folder: commands, stop included, cannot be sent. Check the disk and the folder's permissions".into());
            }
        }
        self.probes += 1;
        if self.probes < DATA_PROBE_EVERY && self.faults.data.is_none() {
            return;
        }
        self.probes = 0;
        match self.cids.probe_writable() {
            Ok(()) => self.faults.data = None,
            Err(e) => {
                if self.faults.data.is_none() {
                    tracing::error!(error = %crate::error::chain(&e), "data folder not writable");
                }
                self.faults.data = Some("the service cannot write its data folder (command id and job id counters): commands will fail once the ids reserved on disk are used (stop excepted). Check the disk and the folder's permissions".into());
            }
        }
    }

    pub(super) fn on_offline(&mut self) {
        let secs = self.cfg.offline_after.as_secs_f64();
        if let Some(f) = &self.inflight {
            let e = BridgeError::new(
                ErrorCode::Timeout,
                format!(
                    "no heartbeat from the controller for {secs:.1} s while command {} was running; its outcome is unknown. A stop was left on the channel, so the controller brakes first if it comes back",
                    f.cid
                ),
            );
            self.fail_inflight(e);
            // A controller that comes back reads the newest command first:
            // the motion its client was told had failed must not run on.
            self.request_stop(None);
        }
        let e = BridgeError::new(
            ErrorCode::ControllerOffline,
            format!("the controller went offline (no heartbeat for {secs:.1} s)"),
        );
        self.fail_queue(&e);
        self.drop_pending_job(JobState::Failed, e.clone());
        if let Some(stop) = &mut self.stop {
            for w in stop.waiters.drain(..) {
                let _ = w.send(Err(e.clone()));
            }
        }
        self.shared.publish(Event::Alarm(e));
    }
}

/// A state file's error state cleared (by a reset the controller took):
/// idle, no error.
fn forget_error(s: &mut StateFile) {
    if s.status == ControllerStatus::Error {
        s.status = ControllerStatus::Idle;
        s.error = None;
        s.error_axis = 0;
    }
}

/// The state file was written after the controller took command `cid`
/// (its `last_cid` has reached it) and is not still running it.
fn written_after(s: &StateFile, cid: Cid) -> bool {
    s.last_cid > 0
        && !kuka_protocol::cid_is_newer(cid, s.last_cid)
        && !(s.status == ControllerStatus::Busy && s.busy_cid == cid)
}
