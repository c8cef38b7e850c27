//! The engine: the single owner of the file channel. HTTP handlers (and
//! later plugins) submit operations and await their jobs; one actor task
//! serialises them onto the controller in arrival order, watches results
//! and heartbeats, enforces timeouts and publishes state and events.

mod actor;
mod history;
mod types;

use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use tokio::sync::{broadcast, oneshot, watch};

pub use history::{HISTORY_EVENTS, Published, Replay};
pub use types::*;

/// The oldest live position [`Engine::live_position`] answers with: five
/// heartbeats of the shipped KRL program (100 ms each).
pub const LIVE_POSITION_MAX_AGE: std::time::Duration = std::time::Duration::from_millis(500);

/// How long [`Engine::live_position_within`] waits for a fresh sample when
/// the newest one is too old while a job runs (a heartbeat late on a loaded
/// host): far shorter than queueing the read behind the motion.
pub const LIVE_POSITION_WAIT: std::time::Duration = std::time::Duration::from_secs(2);

use crate::channel::{Channel, ChannelError, CidStore};
use crate::error::{BridgeError, ErrorCode, Result};
use crate::motion::{MotionRequest, SpeedSettings};
use crate::safety::Safety;
use crate::settings::EngineSettings;

/// How many finished jobs are kept for `GET /jobs`.
const JOB_HISTORY: usize = 1000;

/// What the engine thread reacts to: requests from handlers, and file
/// events from the channel watcher (one queue, so one blocking wait).
pub(crate) enum Msg {
    Files(crate::channel::Changed),
    Submit(actor::QueuedJob),
    Cancel(JobId, oneshot::Sender<Result<Job>>),
    /// Cancels the job only if it is still in the queue (true), in one step
    /// of the engine thread: a job dispatched meanwhile is left alone.
    CancelQueued(JobId, oneshot::Sender<bool>),
    Stop(oneshot::Sender<Result<()>>),
    Shutdown(oneshot::Sender<()>),
    /// The dry run of a program job has finished (on its own thread).
    ProgramChecked(actor::QueuedJob, Result<crate::safety::ProgramCheck>),
    /// Motions for an open path.
    Append(actor::AppendRequest),
}

pub(crate) struct JobTable {
    jobs: HashMap<JobId, watch::Sender<Job>>,
    order: VecDeque<JobId>,
}

pub(crate) struct Shared {
    jobs: Mutex<JobTable>,
    state: watch::Sender<RobotState>,
    events: broadcast::Sender<Published>,
    /// Event ids and recent events; sending happens under its lock, so a
    /// subscriber takes the held events and the live stream at one instant.
    history: Mutex<history::History>,
    safety: Safety,
    next_id: AtomicU64,
    /// The first job id of this run: lower ids belong to earlier runs.
    first_id: JobId,
    /// Persists job ids in blocks, so a restarted service never reuses one.
    job_ids: Mutex<JobIdStore>,
    /// Unix ms when this run started (for the 410 answer).
    started_ms: u64,
    max_queue: usize,
    queued: AtomicU64,
    /// Set at shutdown: new jobs are refused.
    draining: std::sync::atomic::AtomicBool,
    /// Named digital I/O and the outputs clients may write (replaced as a
    /// whole when an admin edits it, [`Engine::set_io_config`]).
    io: std::sync::RwLock<Arc<crate::io::IoConfig>>,
}

impl Shared {
    /// The site's I/O configuration now.
    pub(crate) fn io(&self) -> Arc<crate::io::IoConfig> {
        self.io.read().unwrap_or_else(|p| p.into_inner()).clone()
    }

    fn table(&self) -> MutexGuard<'_, JobTable> {
        self.jobs.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Applies `f` to a job and publishes the change.
    pub(crate) fn update(&self, id: JobId, f: impl FnOnce(&mut Job)) -> Option<Job> {
        let job = {
            let table = self.table();
            let tx = table.jobs.get(&id)?;
            // Waiters care about the end, and appends to a path about its
            // leaving the queue: wake them only then (a wake-up per
            // intermediate state costs CPU on small machines).
            tx.send_if_modified(|j| {
                let was = j.state;
                f(j);
                if j.state.is_terminal()
                    && let Some(p) = j.path.as_mut()
                {
                    // An ended path takes nothing more, however it ended.
                    p.closed = true;
                }
                j.state.is_terminal() || (was == JobState::Queued && j.state != JobState::Queued)
            });
            tx.borrow().clone()
        };
        self.publish(Event::Job(Box::new(job.clone())));
        Some(job)
    }

    /// Ends a job with this state and the reason.
    pub(crate) fn finish(&self, id: JobId, state: JobState, error: BridgeError) {
        self.update(id, |j| {
            j.state = state;
            j.finished_ms = Some(now_ms());
            j.error = Some(error);
        });
    }

    /// A job left the queue (sent, failed or cancelled before sending).
    pub(crate) fn dequeued(&self) {
        let _ = self
            .queued
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |q| {
                Some(q.saturating_sub(1))
            });
    }

    pub(crate) fn publish(&self, event: Event) {
        let mut history = self.history.lock().unwrap_or_else(|p| p.into_inner());
        let _ = self.events.send(history.stamp(event, now_ms()));
    }
}

/// Who asks for a job, passed with every submission: the engine records
/// the name in the job (`requested_by`) and tells `on_job` the new job's
/// id (access control keeps it for the request's audit record). The
/// engine knows nothing else of the caller.
#[derive(Clone, Default)]
pub struct Caller {
    /// The token name (`anonymous` when access control is off); `None` when
    /// nobody in particular asks.
    pub name: Option<String>,
    /// Called with the id of each job created for this caller.
    pub on_job: Option<Arc<dyn Fn(JobId) + Send + Sync>>,
}

/// A cheap, cloneable handle to the engine.
#[derive(Clone)]
pub struct Engine {
    shared: Arc<Shared>,
    tx: std::sync::mpsc::Sender<Msg>,
}

impl Engine {
    /// Starts the actor on a thread of its own.
    /// It opens the channel directory and the command id counter itself:
    /// nothing else touches the channel's files.
    pub fn start(settings: &EngineSettings, safety: Safety) -> Result<Engine, ChannelError> {
        let channel = Channel::open(&settings.channel_dir)?;
        let cids = CidStore::open(&settings.data_dir)?;
        let speeds = SpeedSettings::from_config(&settings.motion);
        let initial = RobotState {
            connection: Connection::Offline,
            controller: ControllerInfo {
                status: "unknown".into(),
                mode: "unknown".into(),
                error: None,
                simulated: false,
                override_pct: 100.0,
                heartbeat_seq: None,
                heartbeat_age_ms: None,
                last_cid: None,
                safety: None,
            },
            busy: false,
            current_job: None,
            queue_length: 0,
            position: None,
            axes: None,
            position_read_at: None,
            tool: None,
            base: None,
            speed: speeds,
            model: safety.model().map(|m| m.name.clone()),
            degraded: vec![BridgeError::new(
                ErrorCode::ControllerOffline,
                "no heartbeat from the controller yet",
            )],
            io: None,
            analog: None,
        };
        let (state, _) = watch::channel(initial);
        let job_ids = JobIdStore::open(&settings.data_dir);
        let first_id = job_ids.next;
        let (events, _) = broadcast::channel(1024);
        let started_ms = now_ms();
        let shared = Arc::new(Shared {
            jobs: Mutex::new(JobTable {
                jobs: HashMap::new(),
                order: VecDeque::new(),
            }),
            state,
            events,
            history: Mutex::new(history::History::new(started_ms)),
            safety,
            next_id: AtomicU64::new(first_id),
            first_id,
            job_ids: Mutex::new(job_ids),
            started_ms,
            max_queue: settings.motion.max_queue,
            queued: AtomicU64::new(0),
            draining: std::sync::atomic::AtomicBool::new(false),
            io: std::sync::RwLock::new(Arc::new(settings.io.clone())),
        });
        let (tx, rx) = std::sync::mpsc::channel();
        let actor = actor::Actor::new(shared.clone(), channel, cids, settings, rx, speeds);
        // The actor owns the channel and does small blocking file I/O: it gets
        // a thread of its own that blocks on one queue (requests and file
        // events), so a file event wakes it directly and HTTP work never
        // waits behind file I/O.
        let events = tx.clone();
        std::thread::Builder::new()
            .name("kuka-engine".into())
            .spawn(move || actor.run(events))
            .map_err(|source| ChannelError::Io {
                what: "cannot start the engine thread",
                path: String::new(),
                source,
            })?;
        Ok(Engine { shared, tx })
    }

    /// The safety gate (also used by plugins and handlers for early checks).
    pub fn safety(&self) -> &Safety {
        &self.shared.safety
    }

    /// The site's I/O configuration now (names, writable outputs).
    pub fn io_config(&self) -> Arc<crate::io::IoConfig> {
        self.shared.io()
    }

    /// Replaces the site's I/O configuration (an admin edited the names or
    /// the allow-lists); refused, with the reason, when it is not valid.
    /// Requests resolve their signals against the configuration of the
    /// moment they arrive: a job already queued keeps what it resolved.
    pub fn set_io_config(&self, io: crate::io::IoConfig) -> std::result::Result<(), String> {
        io.validate()?;
        *self.shared.io.write().unwrap_or_else(|p| p.into_inner()) = Arc::new(io);
        Ok(())
    }

    /// While a job runs on the online controller: the position of the
    /// newest state file (or result), if the service read it less than
    /// [`LIVE_POSITION_MAX_AGE`] ago, and how long ago; `None` when the
    /// controller is idle, offline or has not reported a position. A read
    /// that would queue behind the running motion answers from this
    /// instead (issue 22, live position).
    pub fn live_position(&self) -> Option<LivePosition> {
        let s = self.shared.state.borrow();
        if !runs_on_controller(&s) {
            return None;
        }
        let age = s.position_read_at?.elapsed();
        // A heartbeat that stalls makes the position stale: then the read
        // goes to the controller (and waits, or fails, with it).
        if age > LIVE_POSITION_MAX_AGE {
            return None;
        }
        Some(LivePosition {
            position: s.position?,
            axes: s.axes,
            age,
        })
    }

    /// [`Engine::live_position`], but when a job runs and the newest sample
    /// is too old, waits up to `wait` for a fresh one (the next heartbeat)
    /// instead of answering `None` at once. `None` when the controller is
    /// idle or offline, or no fresh sample came in time.
    pub async fn live_position_within(&self, wait: std::time::Duration) -> Option<LivePosition> {
        let mut rx = self.shared.state.subscribe();
        let deadline = tokio::time::Instant::now() + wait;
        loop {
            if let Some(live) = self.live_position() {
                return Some(live);
            }
            {
                if !runs_on_controller(&rx.borrow_and_update()) {
                    return None;
                }
            }
            match tokio::time::timeout_at(deadline, rx.changed()).await {
                Ok(Ok(())) => {}
                _ => return None,
            }
        }
    }

    /// The robot state as last read from the controller.
    pub fn state(&self) -> RobotState {
        self.shared.state.borrow().clone()
    }

    /// A receiver that sees every state change.
    pub fn watch_state(&self) -> watch::Receiver<RobotState> {
        self.shared.state.subscribe()
    }

    /// Subscribes to events.
    pub fn subscribe(&self) -> broadcast::Receiver<Published> {
        self.shared.events.subscribe()
    }

    /// The held events after the event id `after` (every one held for
    /// `None`, 0 or another run's id), the state, and the live events from
    /// that instant on: what a reconnecting client missed, without gaps or
    /// repeats.
    pub fn replay(&self, after: Option<u64>) -> Replay {
        let history = self
            .shared
            .history
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        let (missed, lost) = history.after(after);
        Replay {
            missed,
            lost,
            state: self.state(),
            live: self.shared.events.subscribe(),
        }
    }

    /// The held job, plan and alarm events after the event id `after`,
    /// oldest first (every one held for `None`, 0 or another run's id).
    pub fn held_events(&self, after: Option<u64>) -> Vec<Published> {
        let history = self
            .shared
            .history
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        history.after(after).0
    }

    /// Validates and queues an operation for `caller`; returns the queued job.
    pub async fn submit(
        &self,
        op: Operation,
        timeout: Option<Duration>,
        caller: Caller,
    ) -> Result<Job> {
        self.submit_from(op, timeout, None, caller).await
    }

    /// [`Self::submit`] on behalf of `origin` (recorded in the job).
    pub async fn submit_from(
        &self,
        op: Operation,
        timeout: Option<Duration>,
        origin: Option<String>,
        caller: Caller,
    ) -> Result<Job> {
        if self.shared.draining.load(Ordering::SeqCst) {
            return Err(BridgeError::new(
                ErrorCode::ShuttingDown,
                "the service is shutting down and takes no new jobs; stop still works",
            ));
        }
        let mut op = op;
        if let Operation::Move(motions) = &mut op {
            self.shared.safety.check_request(motions)?;
            // Signal names to numbers, the outputs against the allow-list:
            // nothing reaches the channel for another output.
            crate::motion::resolve_signals(motions, &self.shared.io())?;
            crate::motion::check_switch_points(motions)?;
        }
        if let Operation::SetSpeed(s) = &op {
            check_speeds(s, &self.shared.safety)?;
        }
        if let Operation::SetOutput(o) = &op {
            // The allow-list: nothing reaches the channel for another output.
            self.shared.io().writable(o.index)?;
            if o.pulse_ms > kuka_protocol::MAX_PULSE_MS {
                return Err(BridgeError::invalid(format!(
                    "pulse_ms = {} is above {} ms",
                    o.pulse_ms,
                    kuka_protocol::MAX_PULSE_MS
                )));
            }
        }
        if let Operation::SetAnalogOutput(a) = &op {
            self.shared.io().analog_writable(a.index)?;
            if !(a.value.is_finite() && (-1.0..=1.0).contains(&a.value)) {
                return Err(BridgeError::invalid(format!(
                    "value = {} is not between -1 and 1 (the normalised analog range)",
                    crate::error::shown(a.value)
                )));
            }
        }
        if self.state().connection == Connection::Offline {
            return Err(BridgeError::new(
                ErrorCode::ControllerOffline,
                "the controller is offline (no heartbeat); nothing was sent",
            ));
        }
        // Reserve a queue place atomically (concurrent requests cannot overshoot).
        let max = self.shared.max_queue as u64;
        let reserved = self
            .shared
            .queued
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |q| {
                (q < max).then_some(q + 1)
            });
        if reserved.is_err() {
            return Err(BridgeError::new(
                ErrorCode::QueueFull,
                format!(
                    "{} jobs are already waiting; try again later",
                    self.shared.max_queue
                ),
            ));
        }
        let id = self.shared.next_id.fetch_add(1, Ordering::SeqCst);
        self.shared
            .job_ids
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .reserve_through(id);
        let job = Job {
            id,
            operation: op.name().into(),
            state: JobState::Queued,
            motions: if let Operation::Move(m) = &op {
                m.len()
            } else {
                0
            },
            completed: 0,
            cid: None,
            created_ms: now_ms(),
            sent_ms: None,
            finished_ms: None,
            position: None,
            axes: None,
            frame: None,
            error: None,
            origin,
            requested_by: caller.name.clone(),
            late_result: false,
            configurations: Vec::new(),
            path: matches!(op, Operation::Path(_)).then(PathProgress::default),
        };
        if let Some(on_job) = &caller.on_job {
            on_job(id);
        }
        {
            let mut table = self.shared.table();
            let (tx, _) = watch::channel(job.clone());
            table.jobs.insert(id, tx);
            table.order.push_back(id);
            while table.order.len() > JOB_HISTORY {
                let Some(old) = table.order.front().copied() else {
                    break;
                };
                let finished = table
                    .jobs
                    .get(&old)
                    .is_none_or(|j| j.borrow().state.is_terminal());
                if !finished {
                    break;
                }
                table.order.pop_front();
                table.jobs.remove(&old);
            }
        }
        self.shared.publish(Event::Job(Box::new(job.clone())));
        let queued = actor::QueuedJob {
            id,
            op,
            timeout,
            queued_at: Instant::now(),
        };
        if self.tx.send(Msg::Submit(queued)).is_err() {
            return Err(BridgeError::new(
                ErrorCode::Internal,
                "the engine has stopped",
            ));
        }
        Ok(job)
    }

    /// Waits until the job is finished or `max` elapses; returns its latest state.
    pub async fn wait(&self, id: JobId, max: Duration) -> Result<Job> {
        let mut rx = {
            let table = self.shared.table();
            table
                .jobs
                .get(&id)
                .map(|tx| tx.subscribe())
                .ok_or_else(|| self.unknown_job(id))?
        };
        let finished = tokio::time::timeout(max, rx.wait_for(|j| j.state.is_terminal()))
            .await
            .map(|r| r.map(|j| j.clone()));
        match finished {
            Ok(Ok(job)) => Ok(job),
            _ => Ok(rx.borrow().clone()),
        }
    }

    /// Submits for `caller`, waits, and turns a failed job into its error.
    pub async fn execute(
        &self,
        op: Operation,
        timeout: Option<Duration>,
        max_wait: Duration,
        caller: Caller,
    ) -> Result<Job> {
        self.execute_from(op, timeout, max_wait, None, caller).await
    }

    /// [`Self::execute`] on behalf of `origin` (recorded in the job).
    pub async fn execute_from(
        &self,
        op: Operation,
        timeout: Option<Duration>,
        max_wait: Duration,
        origin: Option<String>,
        caller: Caller,
    ) -> Result<Job> {
        let job = self.submit_from(op, timeout, origin, caller).await?;
        let job = self.wait(job.id, max_wait).await?;
        match (&job.state, &job.error) {
            (JobState::Done, _) => Ok(job),
            (_, Some(e)) => Err(e.clone()),
            (state, None) if !state.is_terminal() => Err(BridgeError::new(
                ErrorCode::Timeout,
                format!(
                    "job {} is still {} after {} ms; poll /api/v1/jobs/{}",
                    job.id,
                    state.as_str(),
                    max_wait.as_millis(),
                    job.id
                ),
            )),
            _ => Err(BridgeError::new(
                ErrorCode::Internal,
                format!("job {} ended without a result", job.id),
            )),
        }
    }

    /// One job.
    pub fn job(&self, id: JobId) -> Result<Job> {
        let table = self.shared.table();
        table
            .jobs
            .get(&id)
            .map(|tx| tx.borrow().clone())
            .ok_or_else(|| self.unknown_job(id))
    }

    /// The error for a job id not in the table: 410 for an id of an
    /// earlier run or one no longer kept, 404 for one never issued.
    fn unknown_job(&self, id: JobId) -> BridgeError {
        if id == 0 {
            not_found(id)
        } else if id < self.shared.first_id {
            BridgeError::new(
                ErrorCode::Gone,
                format!(
                    "job {id} belonged to an earlier run of the service, which restarted at {} (Unix ms); its outcome was not kept, and a job still queued or running then did not go on",
                    self.shared.started_ms
                ),
            )
        } else if id < self.shared.next_id.load(Ordering::SeqCst) {
            BridgeError::new(
                ErrorCode::Gone,
                format!(
                    "job {id} finished too long ago: only the last {JOB_HISTORY} jobs are kept"
                ),
            )
        } else {
            not_found(id)
        }
    }

    /// Recent jobs, newest first.
    pub fn jobs(&self, limit: usize) -> Vec<Job> {
        let table = self.shared.table();
        table
            .order
            .iter()
            .rev()
            .take(limit)
            .filter_map(|id| table.jobs.get(id).map(|tx| tx.borrow().clone()))
            .collect()
    }

    /// Cancels a queued or running job.
    pub async fn cancel(&self, id: JobId) -> Result<Job> {
        self.job(id)?;
        let (tx, rx) = oneshot::channel();
        self.tx.send(Msg::Cancel(id, tx)).map_err(|_| stopped())?;
        rx.await.map_err(|_| stopped())?
    }

    /// Cancels job `id` if it is still waiting in the queue, and says
    /// whether it did. Unlike reading its state and then cancelling, a job
    /// sent to the controller in between is not touched (nothing is
    /// stopped): closing a path that has just started must not stop it.
    pub async fn cancel_if_queued(&self, id: JobId) -> Result<bool> {
        self.job(id)?;
        let (tx, rx) = oneshot::channel();
        self.tx
            .send(Msg::CancelQueued(id, tx))
            .map_err(|_| stopped())?;
        rx.await.map_err(|_| stopped())
    }

    /// Appends motions to the open path `path` (a job of
    /// [`Operation::Path`]), and closes it after them with `close`. The
    /// motions are checked against the end of what the path already holds
    /// and appended all or none; while the path's queue in the service is
    /// full the call waits (back-pressure) for at most `wait`, then fails
    /// with `path_full`. An empty `motions` with `close` only closes.
    pub async fn append(
        &self,
        path: JobId,
        motions: Vec<MotionRequest>,
        close: bool,
        wait: Duration,
    ) -> Result<AppendOutcome> {
        self.append_with(path, motions, close, wait, false).await
    }

    /// [`Self::append`]; with `partial` a refused motion still appends the
    /// motions before it in this call (a JSON-lines stream, whose batches
    /// are arbitrary). Either way a refused motion closes the path there.
    pub async fn append_with(
        &self,
        path: JobId,
        motions: Vec<MotionRequest>,
        close: bool,
        wait: Duration,
        partial: bool,
    ) -> Result<AppendOutcome> {
        let job = self.job(path)?;
        if job.operation != "path" {
            return Err(BridgeError::new(
                ErrorCode::NotFound,
                format!("job {path} is not a path"),
            ));
        }
        if !motions.is_empty() {
            // The request as a whole (too many motions): refused without
            // touching the path. Each motion is checked by the actor, which
            // closes the path at a refused one like any refusal.
            self.shared.safety.check_batch(&motions)?;
        }
        // A path queued behind other jobs takes appends once it is on the
        // controller: wait for that (within the append's own wait).
        let started = Instant::now();
        self.wait_path_started(path, job.state, wait).await?;
        let wait = wait.saturating_sub(started.elapsed());
        let (tx, rx) = oneshot::channel();
        self.tx
            .send(Msg::Append(actor::AppendRequest {
                path,
                motions,
                close,
                wait,
                partial,
                refusal: None,
                keepalive: false,
                reply: tx,
            }))
            .map_err(|_| stopped())?;
        rx.await.map_err(|_| stopped())?
    }

    /// Waits (up to `wait`) until a queued path is on the controller.
    async fn wait_path_started(&self, path: JobId, state: JobState, wait: Duration) -> Result<()> {
        if state != JobState::Queued {
            return Ok(());
        }
        let mut rx = {
            let table = self.shared.table();
            table
                .jobs
                .get(&path)
                .map(|tx| tx.subscribe())
                .ok_or_else(|| self.unknown_job(path))?
        };
        let left = tokio::time::timeout(wait, rx.wait_for(|j| j.state != JobState::Queued)).await;
        if left.is_err() {
            return Err(BridgeError::new(
                ErrorCode::PathFull,
                format!(
                    "path {path} is still queued behind other jobs after {} ms",
                    wait.as_millis()
                ),
            ));
        }
        Ok(())
    }

    /// Closes the path because the client's input was refused before it
    /// became motions (e.g. a bad line of a JSON-lines stream): the robot
    /// stops at the last motion appended and the path's job fails with
    /// `error`, as when a motion is refused. A path still queued behind
    /// other jobs is refused once it is on the controller (it then ends at
    /// once), or cancelled if it is not within 30 s.
    pub async fn refuse_path(&self, path: JobId, error: BridgeError) -> Result<AppendOutcome> {
        let job = self.job(path)?;
        if let Err(e) = self
            .wait_path_started(path, job.state, Duration::from_secs(30))
            .await
        {
            let _ = self.cancel(path).await;
            return Err(e);
        }
        let (tx, rx) = oneshot::channel();
        self.tx
            .send(Msg::Append(actor::AppendRequest {
                path,
                motions: Vec::new(),
                close: true,
                wait: std::time::Duration::from_secs(10),
                partial: false,
                refusal: Some(error),
                keepalive: false,
                reply: tx,
            }))
            .map_err(|_| stopped())?;
        rx.await.map_err(|_| stopped())?
    }

    /// Keeps an open path alive while its client is still there but sends
    /// nothing (a JSON-lines stream that pauses): if the controller has
    /// nothing else coming, an APPEND without motions tells it the service
    /// is there, so the KRL program's idle end of a path (`kb_path_idle_ms`,
    /// meant for a service that is gone) does not end it.
    pub async fn keep_path_alive(&self, path: JobId) -> Result<AppendOutcome> {
        let (tx, rx) = oneshot::channel();
        self.tx
            .send(Msg::Append(actor::AppendRequest {
                path,
                motions: Vec::new(),
                close: false,
                wait: std::time::Duration::from_secs(1),
                partial: false,
                refusal: None,
                keepalive: true,
                reply: tx,
            }))
            .map_err(|_| stopped())?;
        rx.await.map_err(|_| stopped())?
    }

    /// Stops the robot: brakes, cancels the running job and every queued one.
    pub async fn stop(&self) -> Result<()> {
        let (tx, rx) = oneshot::channel();
        self.tx.send(Msg::Stop(tx)).map_err(|_| stopped())?;
        rx.await.map_err(|_| stopped())?
    }

    /// Graceful shutdown: queued jobs are cancelled, the running one may
    /// finish (bounded by its timeout), then the actor exits.
    pub async fn shutdown(&self) {
        self.shared.draining.store(true, Ordering::SeqCst);
        let (tx, rx) = oneshot::channel();
        if self.tx.send(Msg::Shutdown(tx)).is_ok() {
            let _ = rx.await;
        }
    }
}

fn check_speeds(s: &SpeedSettings, safety: &Safety) -> Result<()> {
    let m = safety.motion_config();
    for (name, v, max) in [
        ("override_pct", s.override_pct, 100.0),
        (
            "ptp_velocity_pct",
            s.ptp_velocity_pct,
            m.max_ptp_velocity_pct,
        ),
        ("ptp_acceleration_pct", s.ptp_acceleration_pct, 100.0),
        ("cp_acceleration_pct", s.cp_acceleration_pct, 100.0),
        ("cp_velocity_m_s", s.cp_velocity_m_s, m.max_cp_velocity),
    ] {
        // Below the file protocol's step the controller would read 0.
        if !v.is_finite() || v < kuka_protocol::REAL_STEP {
            return Err(BridgeError::invalid(format!(
                "{name} = {} must be a positive number of at least {}",
                crate::error::shown(v),
                kuka_protocol::REAL_STEP
            )));
        }
        if v > max {
            let code = if name.contains("velocity") {
                ErrorCode::SpeedLimit
            } else {
                ErrorCode::InvalidInput
            };
            return Err(BridgeError::new(
                code,
                format!("{name} = {v} exceeds the maximum {max}"),
            ));
        }
    }
    Ok(())
}

fn not_found(id: JobId) -> BridgeError {
    BridgeError::new(ErrorCode::NotFound, format!("no job {id} was ever created"))
}

/// How many job ids are reserved on disk at a time.
const JOB_ID_BLOCK: u64 = 1024;

/// Job ids that stay unique across restarts: like command ids, they are
/// reserved in blocks in `<data_dir>/next_job` before use. Without a
/// readable file (first start, or a lost file) ids start at 1, or above
/// the current time in seconds × 1000 when the file exists but is
/// unreadable, so that an earlier run's ids are not reused.
struct JobIdStore {
    path: std::path::PathBuf,
    next: JobId,
    /// Ids below this are covered by the file.
    reserved_until: JobId,
}

impl JobIdStore {
    fn open(data_dir: &std::path::Path) -> JobIdStore {
        let path = data_dir.join("next_job");
        let next = match std::fs::read_to_string(&path) {
            Ok(text) => text.trim().parse::<JobId>().ok().filter(|v| *v >= 1).unwrap_or_else(|| {
                tracing::warn!(path = %path.display(), "job id counter unreadable; starting above the clock");
                (now_ms() / 1000).max(1) * 1000
            }),
            Err(_) => 1,
        };
        let mut store = JobIdStore {
            path,
            next,
            reserved_until: next,
        };
        store.reserve_through(next);
        store
    }

    /// Makes sure the file covers `id` (writes the next block when not).
    fn reserve_through(&mut self, id: JobId) {
        if id < self.reserved_until {
            return;
        }
        let until = id + JOB_ID_BLOCK;
        match crate::channel::write_replacing(&self.path, until.to_string().as_bytes()) {
            Ok(()) => self.reserved_until = until,
            Err(e) => {
                // Ids stay unique within this run; only a restart could
                // reuse them. `degraded` reports the data folder.
                tracing::error!(error = %crate::error::chain(&e), "job id counter not written");
            }
        }
    }
}

fn stopped() -> BridgeError {
    BridgeError::new(ErrorCode::Internal, "the engine has stopped")
}

/// A job runs on a controller whose state file the service reads: the
/// condition for live positions. A locked command file (the controller
/// holds it open while it reads) does not make the state stale.
fn runs_on_controller(s: &RobotState) -> bool {
    s.busy && matches!(s.connection, Connection::Online | Connection::Locked)
}
