//! The engine's actor: owns the channel, the queue and the job on the
//! controller. It reacts to submissions, file events and a poll tick; the
//! poll is the source of truth, events only make it faster.

use crate::event_ids as events;
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use kuka_protocol::{
    Cid, Command, CommandFile, ControllerStatus, Frame, OperatingMode, ResultCode, ResultRecord,
    SpeedRecord, StateFile,
};
use std::sync::mpsc::{self, RecvTimeoutError, TryRecvError};

use tokio::sync::oneshot;

use super::{Msg, Shared};
use crate::channel::{Changed, Channel, ChannelError, CidStore, FileStamp, ReadOutcome};
use crate::engine::types::*;
use crate::error::{BridgeError, ErrorCode, Result};
use crate::motion::{SpeedSettings, StartPoint, resolve};
use crate::settings::{ChannelConfig, EngineSettings};

/// A job waiting in the queue.
pub(crate) struct QueuedJob {
    pub(crate) id: JobId,
    pub(crate) op: Operation,
    pub(crate) timeout: Option<Duration>,
    pub(crate) queued_at: Instant,
}

struct InFlight {
    id: JobId,
    op: Operation,
    cid: Cid,
    sent_at: Instant,
    deadline: Instant,
    acked: bool,
    /// When a state file first showed the controller not busy although it
    /// had accepted this command and no result for it was read: the
    /// command is lost (the controller restarted) if a result file written
    /// after that ([`LOST_GRACE`] later or more) still lacks it.
    idle_since: Option<Instant>,
    /// The result file's stamp at `idle_since`: a controller that cannot
    /// write its result (a locked file) leaves it unchanged, a restarted
    /// one rewrites it.
    idle_stamp: Option<FileStamp>,
}

/// How long the controller may look idle after accepting a command before
/// its missing result counts as lost. The protocol has the result written
/// before the state, so a result is normally read in the same refresh; the
/// grace covers a KRL program that rewrites its files in place.
const LOST_GRACE: Duration = Duration::from_millis(150);

/// How many command ids the engine remembers (sent ones, and ones whose
/// result it has handled). The result file holds the last 8.
const LEDGER_LEN: usize = 256;

/// The command ids of this run: which the service sent (and for which
/// job), and which results it has handled. A result is handled once; a
/// result for an id the service never sent is foreign: reported, never
/// taken for another command's answer, never used to pick new ids.
#[derive(Default)]
struct CidLedger {
    sent: VecDeque<(Cid, Option<JobId>)>,
    seen: VecDeque<Cid>,
}

impl CidLedger {
    fn sent(&mut self, cid: Cid, job: Option<JobId>) {
        if self.sent.len() >= LEDGER_LEN {
            self.sent.pop_front();
        }
        self.sent.push_back((cid, job));
    }

    /// The job a sent id belonged to: `Some(None)` for a STOP, `None` if
    /// this run never sent it.
    fn job_of(&self, cid: Cid) -> Option<Option<JobId>> {
        self.sent.iter().find(|(c, _)| *c == cid).map(|(_, j)| *j)
    }

    fn is_seen(&self, cid: Cid) -> bool {
        self.seen.contains(&cid)
    }

    fn see(&mut self, cid: Cid) {
        if self.seen.len() >= LEDGER_LEN {
            self.seen.pop_front();
        }
        self.seen.push_back(cid);
    }
}

/// Why commands cannot be sent at the moment, found by the engine's own
/// probes and failures (cleared by the next success).
#[derive(Default)]
struct Faults {
    /// The channel folder cannot be written.
    channel: Option<String>,
    /// The data folder (command id counter) cannot be written.
    data: Option<String>,
    /// The result or state file is larger than any protocol file.
    oversize: Option<String>,
}

struct StopInFlight {
    cid: Cid,
    /// Confirmation deadline, set once the STOP is on the channel.
    deadline: Option<Instant>,
    waiters: Vec<oneshot::Sender<Result<()>>>,
}

/// A command waiting for a locked command file to be released. The actor
/// keeps serving (state, stop, cancel) while it retries with backoff.
struct PendingWrite {
    cmd: CommandFile,
    /// The job it belongs to; None for a STOP.
    job: Option<(QueuedJob, Duration)>,
    give_up_at: Instant,
    next_try: Instant,
    backoff: Duration,
}

/// What the service knows about the controller.
#[derive(Default)]
struct ControllerView {
    state: Option<StateFile>,
    seq_changed_at: Option<Instant>,
    online: bool,
    locked: bool,
    /// The heartbeat went backwards: the controller program restarted.
    restarted_at: Option<Instant>,
    pose: Option<(Frame, u8, u8)>,
    axes: Option<[f64; 6]>,
    tool: Option<Frame>,
    base: Option<Frame>,
}

pub(crate) struct Actor {
    shared: Arc<Shared>,
    channel: Channel,
    cids: CidStore,
    cfg: ChannelConfig,
    default_approx_mm: f64,
    rx: mpsc::Receiver<Msg>,
    queue: VecDeque<QueuedJob>,
    inflight: Option<InFlight>,
    /// The result file as it was when the last command was written.
    spin_stamp: Option<FileStamp>,
    /// When the last command's answer came (for `request_spin_us`).
    answered_at: Option<Instant>,
    stop: Option<StopInFlight>,
    pending: Option<PendingWrite>,
    ctl: ControllerView,
    speeds: SpeedSettings,
    shutting_down: Option<oneshot::Sender<()>>,
    /// The controller's program folder for RUN modules.
    program_dir: Option<std::path::PathBuf>,
    /// Generated modules kept in it.
    keep_modules: usize,
    /// The program job whose dry run is running on its own thread (the
    /// queue waits behind it; STOP and cancel do not).
    checking: Option<JobId>,
    /// The engine's own queue, for answers from helper threads.
    events: Option<std::sync::mpsc::Sender<Msg>>,
    /// Command ids sent and results handled in this run.
    ledger: CidLedger,
    /// What stops commands from being sent (reported as `degraded`).
    faults: Faults,
    /// When the folders were last checked for writing.
    probed_at: Option<Instant>,
    /// Channel probes since the last data folder probe.
    probes: u32,
}

/// How often the engine checks that it can write the channel folder.
const PROBE_INTERVAL: Duration = Duration::from_secs(1);
/// How often it checks the data folder (a synced rewrite of the counter).
const DATA_PROBE_EVERY: u32 = 5;

fn result_error(r: &ResultRecord) -> Option<BridgeError> {
    let (code, detail) = match r.code {
        ResultCode::Ok => return None,
        ResultCode::Cancelled => (
            ErrorCode::Cancelled,
            format!("stopped after {} motion(s)", r.completed),
        ),
        ResultCode::Busy => (
            ErrorCode::ControllerBusy,
            "the controller was still executing an earlier command".into(),
        ),
        ResultCode::BadCommand => (
            ErrorCode::ProtocolError,
            "the controller rejected the command as malformed".into(),
        ),
        ResultCode::Unsupported => (
            ErrorCode::ProtocolError,
            "the controller program does not support this operation".into(),
        ),
        ResultCode::Unreachable => (
            ErrorCode::Unreachable,
            "the controller reports the target out of reach".into(),
        ),
        ResultCode::NoConfiguration => (
            ErrorCode::Unreachable,
            "the controller found no axis solution with the requested Status/Turn".into(),
        ),
        ResultCode::SoftwareLimit => (
            ErrorCode::SoftwareLimit,
            format!(
                "the controller stopped at the software limit switch of axis A{}",
                r.axis
            ),
        ),
        ResultCode::Singularity => (
            ErrorCode::Singularity,
            "the controller stopped at a singularity".into(),
        ),
        ResultCode::Geometry => (
            ErrorCode::InvalidInput,
            "the controller rejected the motion geometry (CIRC points coincide or are collinear)"
                .into(),
        ),
        ResultCode::ControllerError => (
            ErrorCode::ControllerError,
            "the controller is in an error state; acknowledge it with POST /api/v1/reset".into(),
        ),
        ResultCode::NotReady => (
            ErrorCode::ControllerError,
            "the controller is not ready (drives off or wrong mode)".into(),
        ),
        ResultCode::RuntimeError => (
            ErrorCode::ControllerError,
            "a KRL runtime error stopped the command".into(),
        ),
        ResultCode::Other(c) => (
            ErrorCode::ProtocolError,
            format!("the controller answered unknown result code {c}"),
        ),
    };
    let mut e = BridgeError::new(code, detail).on_axis(r.axis);
    if !matches!(
        r.code,
        ResultCode::Cancelled | ResultCode::Busy | ResultCode::ControllerError
    ) {
        e = e.at_motion(r.completed as usize);
    }
    Some(e)
}

/// A RUN result's error: `done` is the failing module line, mapped back to
/// the uploaded file; program-specific codes replace the generic ones.
fn program_result_error(e: BridgeError, r: &ResultRecord, program: &str) -> BridgeError {
    let line = crate::programs::upload_line(r.completed);
    let at = if line > 0 {
        format!(" at line {line}")
    } else {
        String::new()
    };
    let e = match r.code {
        ResultCode::BadCommand => BridgeError::new(
            ErrorCode::InvalidProgram,
            format!("the controller could not compile program {program}{at}"),
        ),
        ResultCode::Unsupported => BridgeError::new(
            ErrorCode::ProgramUnsupported,
            format!("program {program} uses KRL the controller cannot execute{at}"),
        ),
        ResultCode::RuntimeError => BridgeError::new(
            ErrorCode::ProgramFailed,
            format!("program {program} failed{at}"),
        ),
        ResultCode::Cancelled => BridgeError::new(
            ErrorCode::Cancelled,
            format!("program {program} was stopped"),
        ),
        _ => {
            let mut e = e;
            if line > 0 {
                e.detail = format!("{} (program {program}, line {line})", e.detail);
            }
            e
        }
    };
    if r.code == ResultCode::Cancelled {
        e
    } else {
        e.at_line("src", line)
    }
}

fn state_error(s: &StateFile) -> Option<BridgeError> {
    let code = s.error?;
    let r = ResultRecord {
        cid: 0,
        code,
        completed: 0,
        axis: s.error_axis,
        position: s.position,
        s: s.s,
        t: s.t,
        axes: s.axes,
    };
    result_error(&r).map(|mut e| {
        e.motion = None;
        e
    })
}

fn mode_name(m: OperatingMode) -> &'static str {
    match m {
        OperatingMode::T1 => "T1",
        OperatingMode::T2 => "T2",
        OperatingMode::Aut => "AUT",
        OperatingMode::Ext => "EXT",
        OperatingMode::Unknown => "unknown",
    }
}

impl Actor {
    pub(crate) fn new(
        shared: Arc<Shared>,
        channel: Channel,
        cids: CidStore,
        config: &EngineSettings,
        rx: mpsc::Receiver<Msg>,
        speeds: SpeedSettings,
    ) -> Self {
        Actor {
            shared,
            channel,
            cids,
            cfg: config.channel.clone(),
            program_dir: config.program_dir.clone(),
            keep_modules: config.keep_modules,
            checking: None,
            events: None,
            default_approx_mm: config.motion.default_batch_approx_mm,
            rx,
            queue: VecDeque::new(),
            inflight: None,
            spin_stamp: None,
            answered_at: None,
            stop: None,
            pending: None,
            ctl: ControllerView::default(),
            speeds,
            shutting_down: None,
            ledger: CidLedger::default(),
            faults: Faults::default(),
            probed_at: None,
            probes: 0,
        }
    }

    /// The engine thread: blocks on its queue until a request, a file event,
    /// the next poll or a pending retry is due.
    pub(crate) fn run(mut self, events: std::sync::mpsc::Sender<Msg>) {
        self.events = Some(events.clone());
        let _watcher = self.channel.watch(move |changed| {
            let _ = events.send(Msg::Files(changed));
        });
        // Results already in the file belong to earlier runs.
        if let ReadOutcome::Record(r) = self.channel.read_results(true) {
            for rec in &r.results {
                self.ledger.see(rec.cid);
            }
        }
        tracing::info!(dir = %self.channel.dir().display(), "engine running");
        let poll = self.cfg.poll_interval();
        let mut next_poll = Instant::now();
        loop {
            let mut wake_at = next_poll;
            if let Some(p) = &self.pending {
                wake_at = wake_at.min(p.next_try);
            }
            match self.next_msg(wake_at) {
                Ok(msg) => self.handle(msg),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => break,
            }
            let now = Instant::now();
            if now >= next_poll {
                next_poll = now + poll;
                self.refresh(Changed::BOTH);
                self.check_timeouts();
                self.probe_folders(now);
                // The locked state ends when the holder lets go, not only at the next write.
                if self.ctl.locked && self.pending.is_none() && !self.channel.command_locked() {
                    tracing::warn!(event_id = events::CHANNEL_UNLOCKED, dir = %self.channel.dir().display(), "channel unlocked");
                    self.ctl.locked = false;
                }
                // Every handle is gone (the service was dropped without a
                // shutdown): nobody can ask for anything any more.
                if Arc::strong_count(&self.shared) == 1 && self.inflight.is_none() {
                    break;
                }
            }
            self.retry_pending();
            self.dispatch();
            self.publish_state();
            if self.shutting_down.is_some() && self.inflight.is_none() && self.pending.is_none() {
                break;
            }
        }
        if let Some(done) = self.shutting_down.take() {
            let _ = done.send(());
        }
        tracing::info!("engine stopped");
    }

    /// The next message, or a timeout at `wake_at`. Two busy loops save
    /// thread wake-ups (each costs tens of µs) when things go quickly:
    /// - for `channel.answer_spin_us` after a command was written the
    ///   engine watches for the answer itself, checking its queue and the
    ///   result file's metadata: a quick answer (the simulator, a query) is
    ///   seen without waking the file watcher's thread and then this one;
    /// - for `channel.request_spin_us` after an answer it watches its
    ///   queue: the next request of a client that sends command after
    ///   command is taken without waking this thread.
    fn next_msg(&mut self, wake_at: Instant) -> Result<Msg, RecvTimeoutError> {
        if let Some(f) = &self.inflight {
            let spin_until = (f.sent_at + self.cfg.answer_spin()).min(wake_at);
            let seen = self.spin_stamp;
            while Instant::now() < spin_until {
                if let Some(msg) = self.try_msg() {
                    return msg;
                }
                let now = self.channel.results_stamp();
                if now != seen {
                    self.spin_stamp = now;
                    return Ok(Msg::Files(Changed {
                        results: true,
                        state: false,
                    }));
                }
                std::hint::spin_loop();
            }
        } else if let Some(at) = self.answered_at {
            let spin_until = (at + self.cfg.request_spin()).min(wake_at);
            while Instant::now() < spin_until {
                if let Some(msg) = self.try_msg() {
                    return msg;
                }
                std::hint::spin_loop();
            }
            // Once per answer.
            self.answered_at = None;
        }
        self.rx
            .recv_timeout(wake_at.saturating_duration_since(Instant::now()))
    }

    /// A message already in the queue, if any.
    fn try_msg(&self) -> Option<Result<Msg, RecvTimeoutError>> {
        match self.rx.try_recv() {
            Ok(msg) => Some(Ok(msg)),
            Err(TryRecvError::Disconnected) => Some(Err(RecvTimeoutError::Disconnected)),
            Err(TryRecvError::Empty) => None,
        }
    }

    fn handle(&mut self, msg: Msg) {
        match msg {
            Msg::Files(changed) => self.refresh(changed),
            Msg::Submit(job) => {
                if self.shutting_down.is_some() {
                    self.finish_queued(
                        job.id,
                        JobState::Cancelled,
                        BridgeError::new(ErrorCode::Cancelled, "the service is shutting down"),
                    );
                } else {
                    self.queue.push_back(job);
                }
            }
            Msg::Cancel(id, reply) => {
                let result = self.cancel(id);
                let _ = reply.send(result);
            }
            Msg::Stop(reply) => self.stop(reply),
            Msg::ProgramChecked(job, result) => self.program_checked(job, result),
            Msg::Shutdown(done) => {
                tracing::info!(
                    queued = self.queue.len(),
                    running = self.inflight.is_some(),
                    "engine shutting down"
                );
                self.cancel_queue("the service is shutting down");
                self.cancel_checking("the service is shutting down");
                self.drop_pending_job(
                    JobState::Cancelled,
                    BridgeError::new(ErrorCode::Cancelled, "the service is shutting down"),
                );
                self.shutting_down = Some(done);
            }
        }
    }

    fn finish_queued(&self, id: JobId, state: JobState, error: BridgeError) {
        self.shared.dequeued();
        self.shared.finish(id, state, error);
    }

    fn cancel_queue(&mut self, why: &str) {
        for job in std::mem::take(&mut self.queue) {
            self.finish_queued(
                job.id,
                JobState::Cancelled,
                BridgeError::new(ErrorCode::Cancelled, why),
            );
        }
    }

    fn fail_queue(&mut self, error: &BridgeError) {
        for job in std::mem::take(&mut self.queue) {
            self.finish_queued(job.id, JobState::Failed, error.clone());
        }
    }

    fn cancel(&mut self, id: JobId) -> Result<Job> {
        let why = || BridgeError::new(ErrorCode::Cancelled, "cancelled by request");
        if let Some(pos) = self.queue.iter().position(|j| j.id == id) {
            if let Some(job) = self.queue.remove(pos) {
                self.finish_queued(job.id, JobState::Cancelled, why());
            }
        } else if self
            .pending
            .as_ref()
            .is_some_and(|p| p.job.as_ref().is_some_and(|(j, _)| j.id == id))
        {
            self.drop_pending_job(JobState::Cancelled, why());
        } else if self.inflight.as_ref().is_some_and(|f| f.id == id) {
            // The controller answers the running command with CANCELLED.
            self.request_stop(None);
        } else if self.checking == Some(id) {
            self.cancel_checking("cancelled by request");
        }
        self.shared_job(id)
    }

    /// Ends the program job whose dry run is running; its answer is
    /// ignored when it comes.
    fn cancel_checking(&mut self, why: &str) {
        if let Some(id) = self.checking.take() {
            self.shared.finish(
                id,
                JobState::Cancelled,
                BridgeError::new(ErrorCode::Cancelled, format!("{why}; nothing was sent")),
            );
        }
    }

    fn shared_job(&self, id: JobId) -> Result<Job> {
        let table = self.shared.table();
        table
            .jobs
            .get(&id)
            .map(|tx| tx.borrow().clone())
            .ok_or_else(|| BridgeError::new(ErrorCode::NotFound, format!("no job {id}")))
    }

    fn stop(&mut self, reply: oneshot::Sender<Result<()>>) {
        self.cancel_queue("cancelled by stop");
        self.cancel_checking("cancelled by stop");
        if !self.ctl.online {
            // Still leave a STOP on the channel: a controller that comes back
            // reads the newest command first.
            self.request_stop(None);
            if self.stop.is_none() {
                // Not even written (the channel folder cannot be written).
                let _ = reply.send(Err(BridgeError::new(
                    ErrorCode::StorageUnavailable,
                    "the controller is offline and the stop could not be written to the channel folder; nothing was sent",
                )));
                return;
            }
            let _ = reply.send(Err(BridgeError::new(
                ErrorCode::ControllerOffline,
                "the controller is offline: a stop command was left on the channel, but nothing confirms it",
            )));
            return;
        }
        self.request_stop(Some(reply));
    }

    /// Brakes: a STOP supersedes any command still waiting for the lock and
    /// goes out at once (or as soon as the file is free).
    fn request_stop(&mut self, waiter: Option<oneshot::Sender<Result<()>>>) {
        if let Some(stop) = &mut self.stop {
            stop.waiters.extend(waiter);
            return;
        }
        self.drop_pending_job(
            JobState::Cancelled,
            BridgeError::new(ErrorCode::Cancelled, "stopped before it was sent"),
        );
        // A STOP never waits for the counter file: it goes out even when
        // the data folder cannot be written.
        let (cid, error) = self.cids.next_for_stop(self.last_accepted());
        if let Some(e) = error {
            tracing::error!(error = %crate::error::chain(&e), cid, "command id counter not written; sending the stop anyway");
            self.data_fault();
        }
        self.stop = Some(StopInFlight {
            cid,
            deadline: None,
            waiters: waiter.into_iter().collect(),
        });
        tracing::warn!(cid, "stop requested");
        self.write(
            CommandFile {
                cid,
                command: Command::Stop,
            },
            None,
        );
    }

    /// Ends a job whose command was still waiting for the lock.
    fn drop_pending_job(&mut self, state: JobState, error: BridgeError) {
        if let Some(PendingWrite {
            job: Some((job, _)),
            ..
        }) = self.pending.take_if(|p| p.job.is_some())
        {
            self.shared.finish(job.id, state, error);
        }
    }

    /// The id the controller last accepted, as its state file says. Only
    /// the state counts: result lines are not a floor for new ids (a
    /// foreign line could otherwise push the counter anywhere).
    fn last_accepted(&self) -> Cid {
        self.ctl.state.as_ref().map_or(0, |s| s.last_cid)
    }

    fn next_cid(&mut self) -> Result<Cid> {
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
    fn data_fault(&mut self) -> BridgeError {
        let detail = "the service cannot write its data folder (command id counter); nothing was sent. Check the disk and the folder's permissions".to_string();
        self.faults.data = Some(detail.clone());
        BridgeError::new(ErrorCode::StorageUnavailable, detail)
    }

    /// Writes a command now, or keeps it pending while the file is locked.
    fn write(&mut self, cmd: CommandFile, job: Option<(QueuedJob, Duration)>) {
        let now = Instant::now();
        self.pending = Some(PendingWrite {
            cmd,
            job,
            give_up_at: now + self.cfg.lock_timeout(),
            next_try: now,
            backoff: Duration::from_micros(500),
        });
        self.retry_pending();
    }

    /// One attempt at the pending write (when due). Never sleeps: while the
    /// file stays locked the actor keeps answering, and after `lock_timeout`
    /// the command fails with `channel_locked`.
    fn retry_pending(&mut self) {
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
                if self.ctl.locked {
                    tracing::warn!(event_id = events::CHANNEL_UNLOCKED, dir = %self.channel.dir().display(), "channel unlocked");
                    self.ctl.locked = false;
                }
                if let Some(p) = self.pending.take() {
                    self.written(p.cmd, p.job, now);
                }
            }
            Err(ChannelError::Write(kuka_protocol::files::WriteError::Locked { path })) => {
                if now >= p.give_up_at {
                    let e = BridgeError::new(
                        ErrorCode::ChannelLocked,
                        format!(
                            "{path} stayed locked by another process for {} ms; nothing was sent. Close the program holding it (on a KRC: the KRL program's open file handle)",
                            self.cfg.lock_timeout_ms
                        ),
                    );
                    self.write_failed(e);
                    return;
                }
                p.next_try = now + p.backoff;
                p.backoff = (p.backoff * 2).min(Duration::from_millis(50));
                if !self.ctl.locked {
                    tracing::warn!(event_id = events::CHANNEL_LOCKED, %path, "command file locked by another process; retrying");
                    self.ctl.locked = true;
                    self.shared.publish(Event::Alarm(BridgeError::new(
                        ErrorCode::ChannelLocked,
                        format!("{path} is locked by another process"),
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

    /// The pending command could not be written: its job fails (and, for a
    /// lock, so do the queued jobs: the lock would hold them too), or the
    /// STOP's waiters hear why.
    fn write_failed(&mut self, e: BridgeError) {
        let Some(p) = self.pending.take() else { return };
        tracing::error!(cid = p.cmd.cid, code = e.code.as_str(), detail = %e.detail, "command not written");
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
    fn written(&mut self, cmd: CommandFile, job: Option<(QueuedJob, Duration)>, now: Instant) {
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
                });
            }
            None => {
                tracing::warn!(cid = cmd.cid, "stop sent");
                if let Some(stop) = &mut self.stop {
                    stop.deadline = Some(now + self.cfg.ack_timeout());
                }
            }
        }
    }

    /// Reads the state and result files and reacts to what changed.
    fn refresh(&mut self, changed: Changed) {
        let now = Instant::now();
        let state = if changed.state {
            self.channel.read_state()
        } else {
            ReadOutcome::Missing
        };
        match state {
            ReadOutcome::Record(s) => {
                self.oversize(kuka_protocol::STATE_FILE, None);
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
            .is_some_and(|t| now.duration_since(t) < self.cfg.offline_after());
        if online != self.ctl.online {
            self.ctl.online = online;
            if online {
                tracing::info!(event_id = events::CONTROLLER_ONLINE, "controller online");
            } else {
                tracing::warn!(
                    event_id = events::CONTROLLER_OFFLINE,
                    after_ms = self.cfg.offline_after_ms,
                    "controller offline: heartbeat stopped"
                );
                self.on_offline();
            }
        }
    }

    fn on_state(&mut self, s: StateFile, now: Instant) {
        self.ctl.pose = Some((s.position, s.s, s.t));
        self.ctl.axes = Some(s.axes);
        self.ctl.tool = Some(s.tool);
        self.ctl.base = Some(s.base);
        let stamp = match &self.inflight {
            Some(f) if f.idle_since.is_none() => Some(self.channel.results_stamp()),
            _ => None,
        };
        if let Some(f) = &mut self.inflight {
            // last_cid is f.cid or newer: accepted.
            let accepted = s.last_cid > 0 && !kuka_protocol::cid_is_newer(f.cid, s.last_cid);
            let picked = accepted || s.busy_cid == f.cid;
            if picked && !f.acked {
                f.acked = true;
            }
            let running = s.status == ControllerStatus::Busy && s.busy_cid == f.cid;
            if accepted && !running {
                if f.idle_since.is_none() {
                    f.idle_since = Some(now);
                    f.idle_stamp = stamp.flatten();
                }
            } else {
                f.idle_since = None;
                f.idle_stamp = None;
            }
            if s.status == ControllerStatus::Busy && s.busy_cid == f.cid {
                let id = f.id;
                let index = s.busy_index as usize;
                let current = self.shared_job(id).ok();
                if current.is_some_and(|j| j.state != JobState::Executing || j.completed != index) {
                    self.shared.update(id, |j| {
                        j.state = JobState::Executing;
                        j.completed = index;
                    });
                }
            }
        }
        self.ctl.state = Some(s);
    }

    fn on_result(&mut self, r: ResultRecord) {
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
                self.shared.finish(f.id, JobState::Cancelled, why);
            }
            return;
        }
        let Some(f) = self.inflight.take_if(|f| f.cid == r.cid) else {
            self.on_other_result(r);
            return;
        };
        self.answered_at = Some(Instant::now());
        self.ctl.axes = Some(r.axes);
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
        let mut error = result_error(&r);
        if !matches!(f.op, Operation::Move(_))
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
        // Publish what the result changed (pose, frames, speeds) before the
        // job completes, so a client woken by the job reads the new state.
        self.publish_state();
        self.shared.update(f.id, |j| {
            j.finished_ms = Some(now_ms());
            j.completed = if matches!(f.op, Operation::Move(_))
                || (matches!(f.op, Operation::RunProgram(_)) && r.code == ResultCode::Ok)
            {
                r.completed as usize
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
                ResultCode::Ok => JobState::Done,
                ResultCode::Cancelled => JobState::Cancelled,
                _ => JobState::Failed,
            };
            j.error = error;
        });
    }

    /// A result that is neither the running command's nor the STOP's: the
    /// late answer of a command whose job has already ended (it then
    /// takes the controller's outcome), or a foreign line (reported).
    fn on_other_result(&mut self, r: ResultRecord) {
        match self.ledger.job_of(r.cid) {
            Some(Some(id)) => {
                let Ok(job) = self.shared_job(id) else { return };
                let state = match r.code {
                    ResultCode::Ok => JobState::Done,
                    ResultCode::Cancelled => JobState::Cancelled,
                    _ => JobState::Failed,
                };
                let mut error = result_error(&r);
                if job.operation != "move"
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
                    if j.operation == "move" || r.code == ResultCode::Ok {
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
    fn check_lost(&mut self, now: Instant) {
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
    fn on_restart(&mut self, old: i32, new: i32, now: Instant) {
        tracing::warn!(
            event_id = events::CONTROLLER_RESTARTED,
            old_seq = old,
            new_seq = new,
            "controller restarted (heartbeat number went back)"
        );
        self.ctl.restarted_at = Some(now);
        self.shared.publish(Event::Alarm(BridgeError::new(
            ErrorCode::ControllerOffline,
            "the controller program restarted (its heartbeat number started again)",
        )));
    }

    /// A result or state file over [`kuka_protocol::MAX_CONTROLLER_FILE_LEN`]
    /// (`Some(size)`), or one of normal size again (`None`).
    fn oversize(&mut self, file: &str, len: Option<u64>) {
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
                    self.faults.oversize = Some(detail);
                }
            }
            None => {
                if self
                    .faults
                    .oversize
                    .as_deref()
                    .is_some_and(|d| d.starts_with(file))
                {
                    self.faults.oversize = None;
                }
            }
        }
    }

    /// Checks now and then that the channel and data folders can be
    /// written, so `degraded` shows before a command fails.
    fn probe_folders(&mut self, now: Instant) {
        if self
            .probed_at
            .is_some_and(|t| now.duration_since(t) < PROBE_INTERVAL)
        {
            return;
        }
        self.probed_at = Some(now);
        // A lock shows before a command meets it.
        if !self.ctl.locked && self.pending.is_none() && self.channel.command_locked() {
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

    fn fail_inflight(&mut self, error: BridgeError) {
        if let Some(f) = self.inflight.take() {
            tracing::warn!(event_id = events::JOB_FAILED, job = f.id, cid = f.cid, code = error.code.as_str(), detail = %error.detail, "job failed");
            self.shared.finish(f.id, JobState::Failed, error);
        }
    }

    fn on_offline(&mut self) {
        let secs = self.cfg.offline_after_ms as f64 / 1000.0;
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

    fn check_timeouts(&mut self) {
        let now = Instant::now();
        let mut supersede = false;
        if let Some(f) = &self.inflight {
            if !f.acked && now.duration_since(f.sent_at) > self.cfg.ack_timeout() {
                let e = BridgeError::new(
                    ErrorCode::Timeout,
                    format!(
                        "the controller did not pick up command {} within {} ms",
                        f.cid, self.cfg.ack_timeout_ms
                    ),
                );
                self.fail_inflight(e);
                supersede = true;
            } else if now > f.deadline {
                let e = BridgeError::new(
                    ErrorCode::Timeout,
                    format!(
                        "command {} got no result within {} ms; it was stopped",
                        f.cid,
                        f.deadline.duration_since(f.sent_at).as_millis()
                    ),
                );
                self.fail_inflight(e);
                supersede = true;
            }
        }
        if supersede {
            // A newer command supersedes one the controller has not read yet,
            // and brakes one it is executing: a timed-out motion never runs
            // on unobserved.
            self.request_stop(None);
        }
        // Queued jobs wait at most their own timeout (e.g. behind a command
        // the controller keeps running after its job failed).
        let default_timeout = self.cfg.command_timeout();
        let expired: Vec<JobId> = self
            .queue
            .iter()
            .filter(|j| now.duration_since(j.queued_at) > j.timeout.unwrap_or(default_timeout))
            .map(|j| j.id)
            .collect();
        for id in expired {
            self.queue.retain(|j| j.id != id);
            let waited = BridgeError::new(
                ErrorCode::Timeout,
                "the job waited in the queue longer than its timeout without being sent (the controller stayed busy)",
            );
            self.finish_queued(id, JobState::Failed, waited);
        }
        if let Some(stop) = &self.stop
            && stop.deadline.is_some_and(|d| now > d)
            && let Some(stop) = self.stop.take()
        {
            let e = BridgeError::new(
                ErrorCode::Timeout,
                format!("the controller did not confirm stop command {}", stop.cid),
            );
            tracing::error!(cid = stop.cid, "stop not confirmed");
            for w in stop.waiters {
                let _ = w.send(Err(e.clone()));
            }
        }
    }

    /// Sends the next queued job when the controller is free.
    fn dispatch(&mut self) {
        while self.inflight.is_none()
            && self.stop.is_none()
            && self.pending.is_none()
            && self.checking.is_none()
        {
            if !self.ctl.online {
                if !self.queue.is_empty() {
                    let e = BridgeError::new(
                        ErrorCode::ControllerOffline,
                        "the controller is offline (no heartbeat); nothing was sent",
                    );
                    self.fail_queue(&e);
                }
                return;
            }
            // The controller may still run a command whose job already
            // failed (e.g. after a timeout): wait for it to become idle.
            if let Some(s) = &self.ctl.state
                && s.status == ControllerStatus::Busy
                && s.busy_cid != 0
                && !self.ledger.is_seen(s.busy_cid)
            {
                return;
            }
            let Some(job) = self.queue.pop_front() else {
                return;
            };
            self.shared.dequeued();
            let id = job.id;
            if let Err(e) = self.send(job) {
                tracing::warn!(job = id, code = e.code.as_str(), detail = %e.detail, "job not sent");
                self.shared.finish(id, JobState::Failed, e);
            }
        }
    }

    fn start_point(&self) -> Result<(StartPoint, Frame, Frame)> {
        match (self.ctl.pose, self.ctl.axes) {
            (Some((pose, _, _)), Some(axes)) => Ok((
                StartPoint { pose, axes },
                self.ctl.tool.unwrap_or_default(),
                self.ctl.base.unwrap_or_default(),
            )),
            _ => Err(BridgeError::new(
                ErrorCode::ControllerOffline,
                "the robot position is not known yet (no heartbeat read)",
            )),
        }
    }

    /// Resolves and checks the job, then writes it (or leaves it pending
    /// while the file is locked).
    fn send(&mut self, job: QueuedJob) -> Result<()> {
        if let Operation::RunProgram(program) = &job.op {
            // Fail fast: nothing to dry-run for if the module cannot be written.
            if self.program_dir.is_none() {
                return Err(BridgeError::new(
                    ErrorCode::ProgramsUnavailable,
                    "no program folder is configured (programs.controller_dir)",
                ));
            }
            let (start, tool, base) = self.start_point()?;
            let speed = SpeedRecord::from(self.speeds);
            // The dry run may take a while (a long program, up to the
            // interpreter's limits): it runs on a thread of its own and
            // answers with Msg::ProgramChecked; meanwhile the engine keeps
            // serving state, STOP and cancel, and the queue waits.
            let safety = self.shared.safety.clone();
            let events = self.events.clone().ok_or_else(|| {
                BridgeError::new(ErrorCode::Internal, "the engine queue is not set up")
            })?;
            let program = program.clone();
            let id = job.id;
            std::thread::Builder::new()
                .name("kuka-dry-run".into())
                // A margin: the interpreter's own limits keep its deepest
                // run within a 2 MiB stack in a debug build.
                .stack_size(kuka_krl_runtime::program::DRY_RUN_STACK_BYTES)
                .spawn(move || {
                    let result = safety.check_program(&program, &start, &tool, &base, speed);
                    let _ = events.send(Msg::ProgramChecked(job, result));
                })
                .map_err(|e| {
                    BridgeError::new(
                        ErrorCode::Internal,
                        format!("cannot start the dry run: {e}"),
                    )
                })?;
            self.checking = Some(id);
            return Ok(());
        }
        let command = match &job.op {
            Operation::Move(requests) => {
                let (start, tool, base) = self.start_point()?;
                let records = resolve(requests, &start, &self.speeds, self.default_approx_mm)?;
                self.shared
                    .safety
                    .check_resolved(&records, &start, &tool, &base)?;
                Command::Move(records)
            }
            Operation::GetPosition => Command::GetPosition,
            Operation::Home => Command::Home,
            Operation::SetTool(f) => Command::SetTool((*f).into()),
            Operation::GetTool => Command::GetTool,
            Operation::SetBase(f) => Command::SetBase((*f).into()),
            Operation::GetBase => Command::GetBase,
            Operation::SetSpeed(s) => Command::SetSpeed((*s).into()),
            Operation::Reset => Command::Reset,
            Operation::RunProgram(_) => {
                return Err(BridgeError::new(
                    ErrorCode::Internal,
                    "program runs are sent above",
                ));
            }
        };
        let cid = self.next_cid()?;
        let timeout = job.timeout.unwrap_or(self.cfg.command_timeout());
        self.write(CommandFile { cid, command }, Some((job, timeout)));
        Ok(())
    }

    /// A program job's dry run has finished: send it, or fail it.
    fn program_checked(&mut self, job: QueuedJob, result: Result<crate::safety::ProgramCheck>) {
        if self.checking != Some(job.id) {
            return; // cancelled meanwhile
        }
        self.checking = None;
        let id = job.id;
        let sent = result.and_then(|check| {
            let Operation::RunProgram(program) = &job.op else {
                return Err(BridgeError::new(ErrorCode::Internal, "not a program job"));
            };
            if check.checked && !check.complete {
                tracing::warn!(
                    program = %program.info.name,
                    steps = check.steps,
                    "program does not end within the dry run's limits; checked up to there"
                );
            }
            if !check.checked {
                tracing::info!(
                    program = %program.info.name,
                    "program sent without a dry run (no robot model, or KRL beyond the simulator's subset)"
                );
            }
            if let Some(n) = check.steps.filter(|_| check.complete) {
                self.shared.update(id, |j| j.motions = n);
            }
            if !self.ctl.online {
                return Err(BridgeError::new(
                    ErrorCode::ControllerOffline,
                    "the controller went offline during the dry run; nothing was sent",
                ));
            }
            let dir = self.program_dir.clone().ok_or_else(|| {
                BridgeError::new(ErrorCode::ProgramsUnavailable, "no program folder is configured")
            })?;
            let program = program.clone();
            let cid = self.next_cid()?;
            self.write_module(&dir, cid, &program)?;
            let timeout = job.timeout.unwrap_or(self.cfg.command_timeout());
            self.write(
                CommandFile {
                    cid,
                    command: Command::Run(cid),
                },
                Some((job, timeout)),
            );
            Ok(())
        });
        if let Err(e) = sent {
            tracing::warn!(job = id, code = e.code.as_str(), detail = %e.detail, "job not sent");
            self.shared.finish(id, JobState::Failed, e);
        }
    }

    /// Writes module `kbu<cid>` into the program folder and deletes the
    /// oldest generated modules beyond `keep_modules`.
    fn write_module(
        &self,
        dir: &std::path::Path,
        cid: Cid,
        program: &crate::programs::StoredProgram,
    ) -> Result<()> {
        let m = crate::programs::module_text(cid, program);
        let fail = |e: &dyn std::fmt::Display| {
            tracing::error!(module = %m.name, dir = %dir.display(), error = %e, "program module not written");
            BridgeError::new(
                ErrorCode::ProgramsUnavailable,
                format!(
                    "cannot write module {} into the controller's program folder (programs.controller_dir); the service log says why",
                    m.name
                ),
            )
        };
        std::fs::create_dir_all(dir).map_err(|e| fail(&e))?;
        let tag = format!("svc{}", std::process::id());
        // KRL files on a KRC use the 8-bit Windows code page.
        let ansi = crate::programs::encode_ansi;
        kuka_protocol::files::atomic_write_bytes(
            dir,
            &format!("{}.src", m.name),
            &tag,
            &ansi(&m.src),
        )
        .map_err(|e| fail(&e))?;
        if let Some(dat) = &m.dat {
            kuka_protocol::files::atomic_write_bytes(
                dir,
                &format!("{}.dat", m.name),
                &tag,
                &ansi(dat),
            )
            .map_err(|e| fail(&e))?;
        }
        tracing::info!(module = %m.name, program = %program.info.name, "program module written");
        // Keep the newest modules only (by number; ours are the only kbu* files).
        let mut numbers: Vec<i64> = std::fs::read_dir(dir)
            .map(|rd| {
                rd.flatten()
                    .filter_map(|e| {
                        let name = e.file_name().to_string_lossy().into_owned();
                        name.strip_prefix("kbu")?.strip_suffix(".src")?.parse().ok()
                    })
                    .collect()
            })
            .unwrap_or_default();
        numbers.sort_unstable();
        let excess = numbers.len().saturating_sub(self.keep_modules.max(1));
        for n in &numbers[..excess] {
            for ext in ["src", "dat"] {
                let _ = std::fs::remove_file(dir.join(format!("kbu{n}.{ext}")));
            }
        }
        Ok(())
    }

    /// Why commands cannot be sent now (see [`RobotState::degraded`]).
    fn degraded(&self) -> Vec<BridgeError> {
        let mut out = Vec::new();
        let mut add = |code, detail: &str| out.push(BridgeError::new(code, detail));
        if self.shutting_down.is_some() {
            add(
                ErrorCode::ShuttingDown,
                "the service is shutting down: it takes no new jobs; stop still works",
            );
        }
        if !self.ctl.online {
            add(
                ErrorCode::ControllerOffline,
                "no heartbeat from the controller (is its program running?)",
            );
        }
        if self.ctl.locked {
            add(
                ErrorCode::ChannelLocked,
                "the command file is locked by another process",
            );
        }
        for fault in [&self.faults.channel, &self.faults.data]
            .into_iter()
            .flatten()
        {
            add(ErrorCode::StorageUnavailable, fault);
        }
        if let Some(fault) = &self.faults.oversize {
            add(ErrorCode::ProtocolError, fault);
        }
        if let Some(e) = self.ctl.state.as_ref().and_then(state_error) {
            out.push(BridgeError::new(
                ErrorCode::ControllerError,
                format!("the controller is in its error state ({}): acknowledge it with POST /api/v1/reset", e.detail),
            ));
        } else if self
            .ctl
            .state
            .as_ref()
            .is_some_and(|s| s.status == ControllerStatus::Error)
        {
            out.push(BridgeError::new(
                ErrorCode::ControllerError,
                "the controller is in its error state: acknowledge it with POST /api/v1/reset",
            ));
        }
        out
    }

    fn publish_state(&self) {
        let now = Instant::now();
        let s = self.ctl.state.as_ref();
        let connection = if !self.ctl.online {
            Connection::Offline
        } else if self.ctl.locked {
            Connection::Locked
        } else {
            Connection::Online
        };
        let controller = ControllerInfo {
            status: match s.map(|s| s.status) {
                Some(ControllerStatus::Idle) => "idle",
                Some(ControllerStatus::Busy) => "busy",
                Some(ControllerStatus::Error) => "error",
                None => "unknown",
            }
            .into(),
            mode: s.map_or("unknown", |s| mode_name(s.mode)).into(),
            error: s.and_then(state_error),
            simulated: s.is_some_and(|s| s.simulated),
            override_pct: s.map_or(self.speeds.override_pct, |s| s.override_pct),
            heartbeat_seq: s.map(|s| s.seq),
            heartbeat_age_ms: self
                .ctl
                .seq_changed_at
                .map(|t| now.duration_since(t).as_millis() as u64),
            last_cid: s.map(|s| s.last_cid),
        };
        let next = RobotState {
            connection,
            controller,
            busy: self.inflight.is_some(),
            current_job: self.inflight.as_ref().map(|f| f.id),
            queue_length: self.queue.len(),
            position: self.ctl.pose.map(|(f, s, t)| Position::new(&f, s, t)),
            axes: self.ctl.axes.map(Into::into),
            tool: self.ctl.tool.map(Into::into),
            base: self.ctl.base.map(Into::into),
            speed: self.speeds,
            model: self.shared.safety.model().map(|m| m.name.clone()),
            degraded: self.degraded(),
        };
        let changed = self.shared.state.send_if_modified(|cur| {
            // The heartbeat age changes every call; publish only real changes.
            let mut a = cur.clone();
            a.controller.heartbeat_age_ms = next.controller.heartbeat_age_ms;
            let differs = a != next;
            *cur = next.clone();
            differs
        });
        if changed {
            self.shared.publish(Event::State(Box::new(next)));
        }
    }
}
