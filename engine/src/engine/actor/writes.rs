//! Writing commands: command ids, the atomic write of the command file,
//! retries while it is locked, and what a write that fails means.

use super::*;

/// How long a write must meet a locked command file before the channel
/// counts as locked (the alarm, `connection: locked`): a controller that
/// reads the file holds it for a Submit cycle or two, which is no fault.
pub(super) const LOCK_ALARM_AFTER: Duration = Duration::from_millis(100);

impl Actor {
    /// The id the controller last accepted, as its state file says. Only
    /// the state counts: result lines are not a floor for new ids (a
    /// foreign line could otherwise push the counter anywhere).
    pub(super) fn last_accepted(&self) -> Cid {
        self.ctl.state.as_ref().map_or(0, |s| s.last_cid)
    }

    pub(super) fn next_cid(&mut self) -> Result<Cid> {
        match self.cids.next(self.last_accepted()) {
            Ok(cid) => {
                self.faults.data = None;
                Ok(cid)
            }
            Err(e) => {
                tracing::error!(error = %crate::error::chain(&e), "command id counter not written");
                let e = self.data_fault();
                Err(e)
            }
        }
    }

    /// The data folder cannot be written: recorded for `degraded`, and the
    /// client's error (the path and OS error go to the log only).
    pub(super) fn data_fault(&mut self) -> BridgeError {
        let detail = "the service cannot write its data folder (command id counter); nothing was sent. Check the disk and the folder's permissions".to_string();
        self.faults.data = Some(detail.clone());
        BridgeError::new(ErrorCode::StorageUnavailable, detail)
    }

    /// Writes a command now, or keeps it pending while the file is locked.
    pub(super) fn write(&mut self, cmd: CommandFile, job: Option<(QueuedJob, Duration)>) {
        let now = Instant::now();
        self.pending = Some(PendingWrite {
            cmd,
            job,
            append: false,
            give_up_at: now + self.cfg.lock_timeout,
            next_try: now,
            backoff: Duration::from_micros(500),
        });
        self.retry_pending();
    }

    /// Writes an APPEND of the open path now, or keeps it pending while the
    /// file is locked.
    pub(super) fn write_append(&mut self, cmd: CommandFile) {
        let now = Instant::now();
        self.pending = Some(PendingWrite {
            cmd,
            job: None,
            append: true,
            give_up_at: now + self.cfg.lock_timeout,
            next_try: now,
            backoff: Duration::from_micros(500),
        });
        self.retry_pending();
    }

    /// One attempt at the pending write (when due). Never sleeps: while the
    /// file stays locked the actor keeps answering, and after `lock_timeout`
    /// the command fails with `channel_locked`.
    pub(super) fn retry_pending(&mut self) {
        let now = Instant::now();
        let Some(p) = self.pending.as_mut() else {
            return;
        };
        if now < p.next_try {
            return;
        }
        // The answer's file must differ from this one (see `next_msg`).
        self.spin_stamp = self.channel.results_stamp();
        match self.channel.write_command(&p.cmd) {
            Ok(()) => {
                self.faults.channel = None;
                self.on_channel = Some(p.cmd.cid);
                if self.ctl.locked {
                    tracing::warn!(event_id = events::CHANNEL_UNLOCKED, dir = %self.channel.dir().display(), "channel unlocked");
                    self.ctl.locked = false;
                }
                if let Some(p) = self.pending.take() {
                    if p.append {
                        self.ledger.sent(p.cmd.cid, None);
                        tracing::debug!(cid = p.cmd.cid, "append sent");
                    } else {
                        self.written(p.cmd, p.job, now);
                    }
                }
            }
            Err(ChannelError::Write(kuka_protocol::files::WriteError::Locked { path })) => {
                if now >= p.give_up_at {
                    let e = BridgeError::new(
                        ErrorCode::ChannelLocked,
                        format!(
                            "the command file stayed locked by another process for {} ms; nothing was sent. Close the program holding it (on a KRC: the KRL program's open file handle)",
                            self.cfg.lock_timeout.as_millis()
                        ),
                    );
                    self.write_failed(e);
                    return;
                }
                p.next_try = now + p.backoff;
                p.backoff = (p.backoff * 2).min(Duration::from_millis(50));
                // A controller reading the file holds it for a moment (the
                // shipped KRL program for a Submit pass or two): only a lock
                // that lasts is reported.
                let first_try = p.give_up_at - self.cfg.lock_timeout;
                if !self.ctl.locked && now.duration_since(first_try) >= LOCK_ALARM_AFTER {
                    tracing::warn!(event_id = events::CHANNEL_LOCKED, %path, "command file locked by another process; retrying");
                    self.ctl.locked = true;
                    self.shared.publish(Event::Alarm(BridgeError::new(
                        ErrorCode::ChannelLocked,
                        "the command file is locked by another process",
                    )));
                }
            }
            Err(ChannelError::Encode(e)) => {
                self.write_failed(BridgeError::invalid(crate::error::chain(&e)))
            }
            Err(e) => {
                tracing::error!(error = %crate::error::chain(&e), dir = %self.channel.dir().display(), "command file not written");
                let detail = "the service cannot write the command file into the channel folder; nothing was sent. Check the disk and the folder's permissions";
                self.faults.channel = Some(detail.into());
                self.write_failed(BridgeError::new(ErrorCode::StorageUnavailable, detail))
            }
        }
    }

    /// Removes the command file once the controller has read it, while a
    /// path runs: its state file's `last_cid` has reached the command, or
    /// its result came. (Outside paths nothing is removed: the polls of an
    /// idle controller cost no motion anything, and a single command stays
    /// on the channel until the next one; after a path there is none.) The
    /// controller reads a command whole in the Submit pass that accepts it
    /// and writes its state and result after closing the file (a MOVE the
    /// service sends is never longer than the program reads in one pass:
    /// longer batches go as paths), so a removal never cuts a read short.
    /// Locked: the controller is at it right now; the next turn of the loop
    /// tries again.
    pub(super) fn remove_read_command(&mut self) {
        let Some(cid) = self.on_channel else { return };
        if !self.cfg.remove_read_command {
            self.on_channel = None;
            return;
        }
        if self.pending.is_some() || self.path.is_none() {
            return;
        }
        let last = self.last_accepted();
        let read =
            (last > 0 && !kuka_protocol::cid_is_newer(cid, last)) || self.ledger.is_seen(cid);
        if !read {
            return;
        }
        match self.channel.remove_command() {
            Ok(()) => {
                self.on_channel = None;
                tracing::trace!(cid, "command read by the controller; file removed");
            }
            Err(ChannelError::Write(kuka_protocol::files::WriteError::Locked { .. })) => {}
            Err(e) => {
                self.on_channel = None;
                tracing::warn!(cid, error = %crate::error::chain(&e), "command file not removed (the controller reads it again at each poll)");
            }
        }
    }

    /// The pending command could not be written: its job fails (and, for a
    /// lock, so do the queued jobs: the lock would hold them too), or the
    /// STOP's waiters hear why.
    pub(super) fn write_failed(&mut self, e: BridgeError) {
        let Some(p) = self.pending.take() else { return };
        tracing::error!(cid = p.cmd.cid, code = e.code.as_str(), detail = %e.detail, "command not written");
        if p.append {
            self.fail_path(e);
            return;
        }
        match p.job {
            Some((job, _)) => {
                self.shared.finish(job.id, JobState::Failed, e.clone());
                if e.code == ErrorCode::ChannelLocked {
                    self.fail_queue(&e);
                }
            }
            None => {
                if let Some(stop) = self.stop.take() {
                    for w in stop.waiters {
                        let _ = w.send(Err(e.clone()));
                    }
                }
            }
        }
    }

    /// A command reached the channel.
    pub(super) fn written(
        &mut self,
        cmd: CommandFile,
        job: Option<(QueuedJob, Duration)>,
        now: Instant,
    ) {
        self.ledger.sent(cmd.cid, job.as_ref().map(|(j, _)| j.id));
        match job {
            Some((job, timeout)) => {
                tracing::debug!(
                    job = job.id,
                    cid = cmd.cid,
                    op = job.op.name(),
                    "command sent"
                );
                if let Command::Move(records) = &cmd.command {
                    self.shared.publish(Event::Plan(Box::new(JobPlan {
                        job: job.id,
                        cid: cmd.cid,
                        motions: records.iter().map(PlannedMotion::from).collect(),
                        first: 0,
                    })));
                }
                // A batch sent as a path: its whole plan at once, as a MOVE's.
                if let Some(motions) = self
                    .path
                    .as_ref()
                    .filter(|p| p.cid == cmd.cid)
                    .and_then(|p| p.batch_plan())
                {
                    self.shared.publish(Event::Plan(Box::new(JobPlan {
                        job: job.id,
                        cid: cmd.cid,
                        motions,
                        first: 0,
                    })));
                }
                self.shared.update(job.id, |j| {
                    j.state = JobState::Sent;
                    j.cid = Some(cmd.cid);
                    j.sent_ms = Some(now_ms());
                });
                self.inflight = Some(InFlight {
                    id: job.id,
                    op: job.op,
                    cid: cmd.cid,
                    sent_at: now,
                    deadline: now + timeout,
                    acked: false,
                    idle_since: None,
                    idle_stamp: None,
                    busy_stamp: None,
                });
            }
            None => {
                tracing::warn!(cid = cmd.cid, "stop sent");
                if let Some(stop) = &mut self.stop {
                    stop.deadline = Some(now + self.cfg.ack_timeout);
                }
            }
        }
    }
}
