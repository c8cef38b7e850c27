//! The engine's actor: owns the channel, the queue and the job on the
//! controller. It reacts to submissions, file events and a poll tick; the
//! poll is the source of truth, events only make it faster.
//!
//! This file holds its state, the loop, the queue, stop and cancel,
//! dispatch and the published state; the rest is split along its seams:
//! [`writes`] (command ids, writing the command file), [`reads`] (the
//! controller's files and what they mean for the running job),
//! [`program_jobs`] (program modules and RUN) and [`outcome`] (result and
//! state codes as API errors).

use crate::event_ids as events;
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use kuka_protocol::{
    Cid, Command, CommandFile, ControllerStatus, Frame, MotionRecord, OperatingMode, PathChunk,
    ResultCode, ResultRecord, SpeedRecord, StateFile,
};
use std::sync::mpsc::{self, RecvTimeoutError, TryRecvError};

use tokio::sync::oneshot;

use super::{Msg, Shared};

mod outcome;
mod paths;
mod program_jobs;
mod reads;
mod writes;

pub(crate) use paths::AppendRequest;

use crate::channel::{Changed, Channel, ChannelError, CidStore, FileStamp, ReadOutcome};
use crate::engine::types::*;
use crate::error::{BridgeError, ErrorCode, Result};
use crate::motion::{MotionRequest, SpeedSettings, StartPoint, resolve};
use crate::settings::{ChannelTiming, EngineSettings};
use outcome::*;

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
    /// The result file's stamp when a state file last showed the command
    /// running: a controller restarted between that state and the first
    /// that shows it idle (a KRL program rewrites its result file at
    /// start) has already changed the file by then.
    busy_stamp: Option<FileStamp>,
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
    /// The result or state file (its name, and the sentence) is larger
    /// than any protocol file.
    oversize: Option<(&'static str, String)>,
    /// The controller's state file speaks another protocol version.
    version: Option<String>,
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
    /// The job it belongs to; None for a STOP or an APPEND.
    job: Option<(QueuedJob, Duration)>,
    /// An APPEND of the open path.
    append: bool,
    give_up_at: Instant,
    next_try: Instant,
    backoff: Duration,
}

/// How long a RESET's result waits for a state file written after it
/// ([`Actor::hold_reset`]): a few heartbeats of the KRL program.
const RESET_STATE_WAIT: Duration = Duration::from_millis(500);

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
    /// The command whose result last set `pose`/`axes`: a state file
    /// written before that result must not set them back.
    result_cid: Option<Cid>,
    /// When the file that last set `pose`/`axes` was read.
    pose_at: Option<Instant>,
    /// Probes in a row that found the command file locked.
    lock_probes: u32,
    /// A RESET the controller took with its safety circuit closed: state
    /// files written before it no longer show the error it cleared.
    reset_cid: Option<Cid>,
    /// A RESET's result held back until a state file written after it
    /// says whether the safety circuit is still open (the newest one was
    /// older and showed it open: the operator may have closed it since),
    /// and when it was first held.
    reset_held: Option<(ResultRecord, Instant)>,
    /// The value each analog channel (inputs, outputs; 1..=8) had when
    /// it last published an `analog` event, or when first reported.
    analog_published: [[Option<f64>; kuka_protocol::AnalogState::WIDTH]; 2],
}

pub(crate) struct Actor {
    shared: Arc<Shared>,
    channel: Channel,
    cids: CidStore,
    cfg: ChannelTiming,
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
    /// The open path (a path job on the controller).
    path: Option<paths::PathState>,
    /// The command on the channel, until the controller has read it and
    /// the file is removed (`channel.remove_read_command`).
    on_channel: Option<Cid>,
}

/// How often the engine checks that it can write the channel folder.
const PROBE_INTERVAL: Duration = Duration::from_secs(1);
/// How often it checks the data folder (a synced rewrite of the counter).
const DATA_PROBE_EVERY: u32 = 5;

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
            cfg: config.channel,
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
            path: None,
            on_channel: None,
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
        let poll = self.cfg.poll_interval;
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
            self.reconcile_path();
            self.pump_path();
            self.remove_read_command();
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
            let spin_until = (f.sent_at + self.cfg.answer_spin).min(wake_at);
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
            let spin_until = (at + self.cfg.request_spin).min(wake_at);
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
            Msg::CancelQueued(id, reply) => {
                let why = BridgeError::new(
                    ErrorCode::Cancelled,
                    "ended before it started; nothing was sent",
                );
                let _ = reply.send(self.cancel_queued(id, why));
            }
            Msg::Stop(reply) => self.stop(reply),
            Msg::ProgramChecked(job, result) => self.program_checked(job, result),
            Msg::Append(req) => self.on_append(req),
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

    /// Cancels job `id` if it waits in the queue; whether it did.
    fn cancel_queued(&mut self, id: JobId, why: BridgeError) -> bool {
        let pos = self.queue.iter().position(|j| j.id == id);
        match pos.and_then(|pos| self.queue.remove(pos)) {
            Some(job) => {
                self.finish_queued(job.id, JobState::Cancelled, why);
                true
            }
            None => false,
        }
    }

    fn cancel(&mut self, id: JobId) -> Result<Job> {
        let why = || BridgeError::new(ErrorCode::Cancelled, "cancelled by request");
        if self.cancel_queued(id, why()) {
            // Taken out of the queue: nothing was sent.
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
            let (state, error) = if state == JobState::Cancelled {
                self.stopped_path(job.id, error)
            } else {
                (state, error)
            };
            self.shared.finish(job.id, state, error);
        }
    }

    fn fail_inflight(&mut self, error: BridgeError) {
        if let Some(f) = self.inflight.take() {
            tracing::warn!(event_id = events::JOB_FAILED, job = f.id, cid = f.cid, code = error.code.as_str(), detail = %error.detail, "job failed");
            self.shared.finish(f.id, JobState::Failed, error);
        }
    }

    fn check_timeouts(&mut self) {
        // A RESET's result held for a fresh state file: no longer than
        // RESET_STATE_WAIT (the controller may have stopped writing).
        if let Some((r, since)) = self.ctl.reset_held
            && since.elapsed() >= RESET_STATE_WAIT
        {
            self.on_result(r);
        }
        let now = Instant::now();
        let mut supersede = false;
        if let Some(f) = &self.inflight {
            if !f.acked && now.duration_since(f.sent_at) > self.cfg.ack_timeout {
                let e = BridgeError::new(
                    ErrorCode::Timeout,
                    format!(
                        "the controller did not pick up command {} within {} ms",
                        f.cid,
                        self.cfg.ack_timeout.as_millis()
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
        self.expire_parked(now);
        // Queued jobs wait at most their own timeout (e.g. behind a command
        // the controller keeps running after its job failed).
        let default_timeout = self.cfg.command_timeout;
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
        if let Operation::Path(options) = &job.op {
            let (start, _, _) = self.start_point()?;
            let cid = self.next_cid()?;
            self.path = Some(paths::PathState::new(job.id, cid, *options, start));
            // A path has no overall deadline: it runs while motions come
            // (the controller ends it after kb_path_idle_ms without any).
            let forever = Duration::from_secs(10 * 365 * 24 * 3600);
            let command = Command::OpenPath(PathChunk {
                path: cid,
                first: 0,
                motions: Vec::new(),
                close: false,
            });
            self.write(CommandFile { cid, command }, Some((job, forever)));
            return Ok(());
        }
        let command = match &job.op {
            Operation::Move(requests) => {
                let (start, tool, base) = self.start_point()?;
                let mut records = resolve(requests, &start, &self.speeds, self.default_approx_mm)?;
                let safety = &self.shared.safety;
                let chosen =
                    safety.choose_configurations(requests, &mut records, &start, &tool, &base)?;
                let ends = safety.check_resolved(&records, &start, &tool, &base)?;
                let configurations: Vec<PtpConfiguration> = requests
                    .iter()
                    .zip(&chosen)
                    .zip(&ends)
                    .enumerate()
                    .filter_map(|(motion, ((req, chosen), &(s, t)))| {
                        let (MotionRequest::Ptp { target, .. }
                        | MotionRequest::Sptp { target, .. }) = req
                        else {
                            return None;
                        };
                        // What was sent: the request's S/T as given, the
                        // chosen ones, or (keep) what the dry run reached.
                        let given = |v: Option<i64>, or: u8| {
                            v.and_then(|v| u8::try_from(v).ok()).unwrap_or(or)
                        };
                        let (chosen, s, t) = match (target.s, chosen) {
                            (Some(_), _) => (
                                ConfigurationSource::Given,
                                given(target.s, s),
                                given(target.t, t),
                            ),
                            (None, Some(c)) => (ConfigurationSource::Auto, c.s, c.t),
                            (None, None) => (ConfigurationSource::Keep, s, t),
                        };
                        Some(PtpConfiguration {
                            motion,
                            s,
                            t,
                            chosen,
                        })
                    })
                    .collect();
                if !configurations.is_empty() {
                    self.shared
                        .update(job.id, |j| j.configurations = configurations);
                }
                if records.len() > paths::BATCH_AS_PATH {
                    // A big batch streams: the robot starts on its first
                    // chunk while the rest follows (paths::BATCH_AS_PATH).
                    let cid = self.next_cid()?;
                    // (A spline block is never split between commands.)
                    let sent = kuka_protocol::whole_blocks(&records, paths::APPEND_CHUNK);
                    let chunk = PathChunk {
                        path: cid,
                        first: 0,
                        motions: records[..sent].to_vec(),
                        close: sent == records.len(),
                    };
                    let timeout = job
                        .timeout
                        .unwrap_or(self.cfg.command_timeout + waiting_time(&records));
                    self.path = Some(paths::PathState::batch(job.id, cid, start, records, sent));
                    let command = Command::OpenPath(chunk);
                    self.write(CommandFile { cid, command }, Some((job, timeout)));
                    return Ok(());
                }
                Command::Move(records)
            }
            Operation::GetPosition => Command::GetPosition,
            Operation::Home => {
                let (start, tool, base) = self.start_point()?;
                self.shared.safety.check_home(
                    &start,
                    &tool,
                    &base,
                    self.speeds.ptp_velocity_pct,
                )?;
                Command::Home
            }
            Operation::SetTool(f) => Command::SetTool((*f).into()),
            Operation::GetTool => Command::GetTool,
            Operation::SetBase(f) => Command::SetBase((*f).into()),
            Operation::GetBase => Command::GetBase,
            Operation::SetSpeed(s) => Command::SetSpeed((*s).into()),
            Operation::Reset => Command::Reset,
            Operation::SetAnalogOutput(a) => {
                Command::SetAnalogOutput(kuka_protocol::AnalogOutputRecord {
                    index: a.index,
                    value: (a.value * 1000.0).round() / 1000.0,
                })
            }
            Operation::SetOutput(o) => Command::SetOutput(kuka_protocol::OutputRecord {
                index: o.index,
                value: o.value,
                pulse_ms: o.pulse_ms,
            }),
            Operation::RunProgram(_) | Operation::Path(_) => {
                return Err(BridgeError::new(
                    ErrorCode::Internal,
                    "program runs and paths are sent above",
                ));
            }
        };
        let cid = self.next_cid()?;
        let waits = match &command {
            Command::Move(records) => waiting_time(records),
            _ => Duration::ZERO,
        };
        let timeout = job.timeout.unwrap_or(self.cfg.command_timeout + waits);
        self.write(CommandFile { cid, command }, Some((job, timeout)));
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
        if let Some((_, fault)) = &self.faults.oversize {
            add(ErrorCode::ProtocolError, fault);
        }
        if let Some(fault) = &self.faults.version {
            add(ErrorCode::ProtocolError, fault);
        }
        if let Some(e) = self.ctl.state.as_ref().and_then(state_error) {
            // (The detail says what clears it.)
            out.push(BridgeError::new(ErrorCode::ControllerError, e.detail));
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

    /// Ends the path whose job is no longer on the channel (finished,
    /// failed, cancelled, or never written).
    fn reconcile_path(&mut self) {
        let Some(job) = self.path.as_ref().map(|p| p.job) else {
            return;
        };
        let on_channel = self.inflight.as_ref().is_some_and(|f| f.id == job)
            || self
                .pending
                .as_ref()
                .is_some_and(|p| p.job.as_ref().is_some_and(|(j, _)| j.id == job));
        if !on_channel {
            self.end_path(job);
        }
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
            safety: s.and_then(|s| s.safety.as_ref()).map(Into::into),
        };
        let next = RobotState {
            connection,
            controller,
            busy: self.inflight.is_some(),
            current_job: self.inflight.as_ref().map(|f| f.id),
            queue_length: self.queue.len(),
            position: self.ctl.pose.map(|(f, s, t)| Position::new(&f, s, t)),
            axes: self.ctl.axes.map(Into::into),
            position_read_at: self.ctl.pose_at,
            tool: self.ctl.tool.map(Into::into),
            base: self.ctl.base.map(Into::into),
            speed: self.speeds,
            model: self.shared.safety.model().map(|m| m.name.clone()),
            degraded: self.degraded(),
            io: s.and_then(|s| s.io.as_ref()).map(Into::into),
            // A controller program may write the ANS line with only some
            // state files (the shipped one, parsing by characters): the
            // last values read stay until the next line.
            analog: s
                .and_then(|s| s.analog.as_ref())
                .map(Into::into)
                .or_else(|| self.shared.state.borrow().analog.clone()),
        };
        let changed = self.shared.state.send_if_modified(|cur| {
            // The heartbeat age changes every call; publish only real changes.
            let mut a = cur.clone();
            a.controller.heartbeat_age_ms = next.controller.heartbeat_age_ms;
            a.position_read_at = next.position_read_at;
            let differs = a != next;
            *cur = next.clone();
            differs
        });
        if changed {
            self.shared.publish(Event::State(Box::new(next)));
        }
    }
}

/// The longest time a batch's actions may keep the robot standing (each
/// `wait_input` its whole timeout, each `dwell`): added to the default
/// command timeout, so that a wait the client asked for is not cut short
/// by the service.
fn waiting_time(records: &[MotionRecord]) -> Duration {
    let ms: u64 = records
        .iter()
        .map(|r| match r {
            MotionRecord::WaitInput { timeout_ms, .. } => u64::from(*timeout_ms),
            MotionRecord::Dwell { ms } => u64::from(*ms),
            _ => 0,
        })
        .sum();
    Duration::from_millis(ms)
}
