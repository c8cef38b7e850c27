//! Paths (motion streams, protocol version 2): the open path's motions
//! between the clients and the controller's buffer.
//!
//! A path is a job like any other while it runs: its PATH command is the
//! one on the controller. Clients append motions ([`AppendRequest`]); each
//! append is resolved and checked against the end of what is already
//! appended (omitted coordinates, configuration, reachability, limits, the
//! swept path against the workspace rules), all or nothing, and waits in
//! the path's queue. The actor sends the queue in APPEND commands as the
//! controller's buffer has room (its state file's `room`), in order, each
//! motion once (the controller's `stored` count is the read position).
//! While the queue is full an append waits (back-pressure) up to its own
//! deadline, then fails with `path_full`. The first motions are held back
//! a moment (a lead) so that a client sending motion after motion gives
//! the controller enough to blend before the robot starts.

use super::*;
use crate::motion::set_default_approx;

/// Motions a path holds in the service (appended, not yet stored by the
/// controller): an append that would go beyond waits for room.
pub(crate) const MAX_PENDING: usize = 2000;
/// Motions per APPEND command (at most): the shipped KRL program takes the
/// first `kb_pth_chunk` (8) lines of a command and leaves the rest; a site
/// may raise that up to 40.
pub(super) const APPEND_CHUNK: usize = 40;
/// The first motions of a path wait this long for more before they are
/// sent (or until [`LEAD_MOTIONS`] are there, or the path is closed), so
/// that motions sent one by one blend from the start.
const LEAD: Duration = Duration::from_millis(100);
/// See [`LEAD`].
const LEAD_MOTIONS: usize = 20;
/// Once a path runs, an APPEND carries at least this many motions unless
/// the controller has fewer than this many stored ahead of the robot (or
/// the rest of the path goes with it): every command costs the KRL
/// program a result file (~8,000 Submit statements), so topping up the
/// buffer two motions at a time would cost a Submit pass over its budget
/// per two motions (docs/BENCHMARKS.md §10).
const APPEND_MIN: usize = 20;
/// A MOVE batch of more motions than this goes to the controller as a
/// closed path (PATH with its first [`APPEND_CHUNK`] motions, then APPENDs):
/// the KRL program reads each line once and starts the robot on the first
/// motion stored while it reads the rest, instead of reading the whole
/// batch first (a MOVE of 1000 motions: ~2 s standstill and ~33 file
/// operations per motion on the KRL program, docs/BENCHMARKS.md §8). A
/// MOVE of up to 4 motions (~2,400 Submit statements) is read within a
/// Submit cycle.
pub(super) const BATCH_AS_PATH: usize = 4;

/// Motions for an open path, from a client.
pub(crate) struct AppendRequest {
    /// The path (its job id).
    pub(crate) path: JobId,
    /// The motions, in order.
    pub(crate) motions: Vec<MotionRequest>,
    /// Close the path after them.
    pub(crate) close: bool,
    /// How long the append may wait for room.
    pub(crate) wait: Duration,
    /// A refused motion still appends the ones before it in this request
    /// (a JSON-lines stream, whose batches are arbitrary); otherwise the
    /// request is all or none.
    pub(crate) partial: bool,
    /// The client's input was refused before it became motions (a bad
    /// line of a JSON-lines stream): the path closes with this error, as
    /// for a refused motion.
    pub(crate) refusal: Option<BridgeError>,
    /// No motions: the client is still there ([`crate::Engine::keep_path_alive`]).
    pub(crate) keepalive: bool,
    /// The answer.
    pub(crate) reply: oneshot::Sender<Result<AppendOutcome>>,
}

/// An append waiting for room.
struct Parked {
    req: AppendRequest,
    deadline: Instant,
}

/// An APPEND on the channel.
struct AppendInFlight {
    cid: Cid,
    /// Motions it carries (from the path's `stored` on).
    count: usize,
    close: bool,
    /// When it was handed to the channel.
    sent_at: Instant,
}

/// The open path.
pub(super) struct PathState {
    pub(super) job: JobId,
    /// The PATH command's id: the path's name on the channel.
    pub(super) cid: Cid,
    options: PathOptions,
    /// Resolved and checked motions the controller has not stored yet.
    pending: VecDeque<MotionRecord>,
    /// Motions appended by clients.
    appended: usize,
    /// Motions the controller has stored.
    stored: u32,
    /// Free slots of the controller's buffer, as last reported (and
    /// reduced by what was stored since).
    room: u32,
    /// The most room the controller reported: its buffer's size, so
    /// `max_room - room` motions are stored ahead of the robot.
    max_room: u32,
    close_requested: bool,
    close_sent: bool,
    /// Where everything appended ends: the start of the next append.
    end: StartPoint,
    append: Option<AppendInFlight>,
    parked: VecDeque<Parked>,
    /// The first motions wait until then (the lead).
    lead_until: Option<Instant>,
    /// The controller no longer takes motions for it (it answered
    /// PATH_CLOSED or an error): its result is on the way.
    over: bool,
    /// Why an append was refused: the path was closed there, and its job
    /// ends with this error when the robot has run what was accepted.
    pub(super) refused: Option<BridgeError>,
    /// A MOVE batch sent as a closed path ([`BATCH_AS_PATH`]): clients
    /// cannot append to it and its job shows no path progress.
    pub(super) batch: bool,
    /// A client asked to keep the path alive: the next APPEND goes even
    /// without motions.
    keepalive: bool,
}

impl PathState {
    pub(super) fn new(job: JobId, cid: Cid, options: PathOptions, end: StartPoint) -> Self {
        PathState {
            job,
            cid,
            options,
            pending: VecDeque::new(),
            appended: 0,
            stored: 0,
            room: 0,
            max_room: 0,
            close_requested: false,
            close_sent: false,
            end,
            append: None,
            parked: VecDeque::new(),
            lead_until: None,
            over: false,
            refused: None,
            batch: false,
            keepalive: false,
        }
    }

    /// A checked MOVE batch as a closed path whose PATH command carries its
    /// first `sent` motions (confirmed by the first state file that shows
    /// the path running, [`Actor::path_state`]).
    pub(super) fn batch(
        job: JobId,
        cid: Cid,
        end: StartPoint,
        records: Vec<MotionRecord>,
        sent: usize,
    ) -> Self {
        let total = records.len();
        PathState {
            pending: records.into(),
            appended: total,
            close_requested: true,
            append: Some(AppendInFlight {
                cid,
                count: sent,
                close: sent == total,
                sent_at: Instant::now(),
            }),
            batch: true,
            keepalive: false,
            ..PathState::new(job, cid, PathOptions::default(), end)
        }
    }

    /// The whole plan of a batch sent as a path (for the plan event when
    /// its PATH is written); `None` for a client's path.
    pub(super) fn batch_plan(&self) -> Option<Vec<PlannedMotion>> {
        self.batch
            .then(|| self.pending.iter().map(PlannedMotion::from).collect())
    }

    fn progress(&self) -> PathProgress {
        PathProgress {
            appended: self.appended,
            sent: self.stored as usize,
            closed: self.close_requested,
        }
    }
}

fn closed_error(path: JobId) -> BridgeError {
    BridgeError::new(
        ErrorCode::PathClosed,
        format!(
            "path {path} is not open: it was closed, ended, failed or was stopped (GET /api/v1/paths/{path} says how)"
        ),
    )
}

impl Actor {
    /// An append from a client: taken now, parked until there is room, or
    /// refused.
    pub(super) fn on_append(&mut self, req: AppendRequest) {
        let Some(p) = self.path.as_mut().filter(|p| p.job == req.path && !p.batch) else {
            let e = match self.shared_job(req.path) {
                Ok(j) if j.operation == "path" && j.state == JobState::Queued => {
                    // Not on the controller yet: wait like any append.
                    BridgeError::new(
                        ErrorCode::PathFull,
                        format!("path {} is still queued behind other jobs", req.path),
                    )
                }
                Ok(j) if j.operation == "path" => closed_error(req.path),
                Ok(_) => BridgeError::new(
                    ErrorCode::NotFound,
                    format!("job {} is not a path", req.path),
                ),
                Err(e) => e,
            };
            let _ = req.reply.send(Err(e));
            return;
        };
        if p.close_requested || p.over {
            let _ = req.reply.send(Err(closed_error(req.path)));
            return;
        }
        if let Some(e) = &req.refusal {
            tracing::warn!(path = p.job, code = e.code.as_str(), detail = %e.detail, "the client's input was refused; the path is closed at the last accepted motion");
            p.refused.get_or_insert_with(|| e.clone());
        }
        if req.motions.is_empty() {
            // A close (or nothing) needs no room: it does not wait behind
            // parked appends, which it ends.
            p.keepalive |= req.keepalive;
            let outcome = self.accept_append(&req);
            if req.close {
                self.refuse_parked("the path was closed while this append waited for room");
            }
            let _ = req.reply.send(outcome);
            return;
        }
        if req.motions.len() > MAX_PENDING {
            let _ = req.reply.send(Err(BridgeError::invalid(format!(
                "an append holds at most {MAX_PENDING} motions, not {}",
                req.motions.len()
            ))));
            return;
        }
        let deadline = Instant::now() + req.wait;
        p.parked.push_back(Parked { req, deadline });
        self.take_parked();
    }

    /// Parked appends are refused with `path_closed` (the path was closed or
    /// refused a motion before them).
    fn refuse_parked(&mut self, why: &str) {
        if let Some(p) = self.path.as_mut() {
            for a in p.parked.drain(..) {
                let _ = a.req.reply.send(Err(BridgeError::new(
                    ErrorCode::PathClosed,
                    format!("path {}: {why}", p.job),
                )));
            }
        }
    }

    /// Takes parked appends in order while they fit. An append whose
    /// client has gone (it stopped waiting) is dropped, never appended.
    fn take_parked(&mut self) {
        loop {
            let Some(p) = self.path.as_mut() else { return };
            while p.parked.front().is_some_and(|a| a.req.reply.is_closed()) {
                if let Some(a) = p.parked.pop_front() {
                    tracing::info!(
                        path = p.job,
                        motions = a.req.motions.len(),
                        "append withdrawn: its client stopped waiting"
                    );
                }
            }
            let fits = p
                .parked
                .front()
                .is_some_and(|a| p.pending.len() + a.req.motions.len() <= MAX_PENDING);
            if !fits {
                return;
            }
            let Some(a) = p.parked.pop_front() else {
                return;
            };
            let outcome = self.accept_append(&a.req);
            let _ = a.req.reply.send(outcome);
        }
    }

    /// Resolves and checks an append against the end of the path and
    /// queues it, all or nothing (with `partial`: the motions before a
    /// refused one). A refused motion closes the path there: the robot runs
    /// what was accepted and stops, and the path's job ends with the reason.
    fn accept_append(&mut self, req: &AppendRequest) -> Result<AppendOutcome> {
        match self.try_append(req, req.motions.len()) {
            Ok(o) => Ok(o),
            Err(e) if e.code == ErrorCode::PathClosed || e.code == ErrorCode::NotFound => Err(e),
            Err(e) => {
                let first = self.path.as_ref().map_or(0, |p| p.appended);
                let before = e.motion.map_or(0, |m| m.saturating_sub(first));
                if req.partial && before > 0 {
                    // The motions before the refused one are fine: appended.
                    let _ = self.try_append(req, before);
                }
                if let Some(p) = self.path.as_mut() {
                    tracing::warn!(path = p.job, code = e.code.as_str(), detail = %e.detail, "append refused; the path is closed at the last accepted motion");
                    p.close_requested = true;
                    p.refused.get_or_insert_with(|| e.clone());
                    let (job, progress, appended) = (p.job, p.progress(), p.appended);
                    self.shared.update(job, |j| {
                        j.motions = appended;
                        j.path = Some(progress);
                    });
                }
                self.refuse_parked("an earlier append was refused, which closed the path");
                Err(e)
            }
        }
    }

    /// Appends the first `count` motions of the request.
    fn try_append(&mut self, req: &AppendRequest, count: usize) -> Result<AppendOutcome> {
        let (tool, base) = (
            self.ctl.tool.unwrap_or_default(),
            self.ctl.base.unwrap_or_default(),
        );
        let approx = self.default_approx_mm;
        let safety = self.shared.safety.clone();
        let Some(p) = self.path.as_mut() else {
            return Err(closed_error(req.path));
        };
        let first = p.appended;
        let motions = &req.motions[..count.min(req.motions.len())];
        if !motions.is_empty() {
            let mut requests = motions.to_vec();
            if let Some(c) = p.options.config {
                requests.iter_mut().for_each(|m| m.default_config(c));
            }
            let at = |mut e: BridgeError| {
                if let Some(m) = e.motion {
                    e.motion = Some(first + m);
                    // The path-wide number, unless the detail already
                    // says it (the first append's own numbering).
                    if first > 0 || !e.detail.starts_with(&format!("motion {m}")) {
                        e.detail = format!("{} (motion {} of the path)", e.detail, first + m);
                    }
                }
                e
            };
            // Numbers and speed caps first: a motion refused here closes
            // the path like one the plan refuses, and says where.
            safety.check_request(&requests).map_err(at)?;
            crate::motion::resolve_signals(&mut requests, &self.shared.io()).map_err(at)?;
            crate::motion::check_switch_points(&requests).map_err(at)?;
            let mut records = resolve(&requests, &p.end, &self.speeds, approx).map_err(at)?;
            // Within a path the last motion of an append blends into the
            // next append's first (the robot stops at the path's end).
            set_default_approx(&requests, &mut records, approx);
            safety
                .choose_configurations(&requests, &mut records, &p.end, &tool, &base)
                .map_err(at)?;
            let end = safety
                .check_resolved_end(&records, &p.end, &tool, &base)
                .map_err(at)?;
            p.end = end;
            self.shared.publish(Event::Plan(Box::new(JobPlan {
                job: p.job,
                cid: p.cid,
                motions: records.iter().map(PlannedMotion::from).collect(),
                first,
            })));
            p.pending.extend(records);
            p.appended += motions.len();
            if p.lead_until.is_none() {
                p.lead_until = Some(Instant::now() + LEAD);
            }
        }
        if req.close && count == req.motions.len() {
            p.close_requested = true;
        }
        let outcome = AppendOutcome {
            path: p.job,
            first,
            appended: motions.len(),
            total: p.appended,
            closed: p.close_requested,
            end: p.end.pose.into(),
        };
        let (job, progress, appended) = (p.job, p.progress(), p.appended);
        self.shared.update(job, |j| {
            j.motions = appended;
            j.path = Some(progress);
        });
        Ok(outcome)
    }

    /// Sends the next APPEND when the controller runs the path, nothing
    /// else is on the channel, the lead has passed and its buffer has room.
    pub(super) fn pump_path(&mut self) {
        if self.stop.is_some() || self.pending.is_some() {
            return;
        }
        let running = self.inflight.as_ref().is_some_and(|f| f.acked)
            && self.ctl.state.as_ref().is_some_and(|s| {
                s.status == ControllerStatus::Busy
                    && self.path.as_ref().is_some_and(|p| s.busy_cid == p.cid)
            });
        let Some(p) = self.path.as_mut() else { return };
        if !running || p.append.is_some() || p.over || p.close_sent {
            return;
        }
        let now = Instant::now();
        let lead_over = p.close_requested
            || p.pending.len() >= LEAD_MOTIONS
            || p.lead_until.is_some_and(|t| now >= t)
            || p.stored > 0;
        if !lead_over {
            return;
        }
        // (A spline block is never split between commands: it waits for
        // room for all its points.)
        let max = p.pending.len().min(p.room as usize).min(APPEND_CHUNK);
        let count = kuka_protocol::whole_blocks(p.pending.make_contiguous(), max);
        let close = p.close_requested && count == p.pending.len();
        // (A keep-alive is an APPEND without motions, only when nothing
        // else is coming.)
        let keepalive = p.keepalive && p.pending.is_empty();
        if count == 0 && !close && !keepalive {
            return;
        }
        p.keepalive = false;
        let ahead = p.max_room.saturating_sub(p.room) as usize;
        if p.stored > 0 && count < APPEND_MIN && !close && !keepalive && ahead >= APPEND_MIN {
            // Enough to run on: wait until a fuller APPEND is worth it.
            return;
        }
        let chunk = PathChunk {
            path: p.cid,
            first: p.stored,
            motions: p.pending.iter().take(count).cloned().collect(),
            close,
        };
        let cid = match self.next_cid() {
            Ok(cid) => cid,
            Err(e) => {
                self.fail_path(e);
                return;
            }
        };
        if let Some(p) = self.path.as_mut() {
            p.append = Some(AppendInFlight {
                cid,
                count,
                close,
                sent_at: Instant::now(),
            });
        }
        self.write_append(CommandFile {
            cid,
            command: Command::Append(chunk),
        });
    }

    /// The controller's answer to an APPEND; false if `r` is not one.
    pub(super) fn on_append_result(&mut self, r: &ResultRecord) -> bool {
        let Some(p) = self.path.as_mut() else {
            return false;
        };
        // The PATH's own motions (a batch) are confirmed by a state file;
        // a result with the PATH's CID is the path's end, not an answer
        // to them (at time scale 0 it can come before any state file).
        let path_cid = p.cid;
        let Some(a) = p.append.take_if(|a| a.cid == r.cid && a.cid != path_cid) else {
            return false;
        };
        match r.code {
            ResultCode::Ok | ResultCode::BadCommand if r.completed >= p.stored => {
                // `done` is the controller's stored count: what it took of
                // this chunk (a resend skips what it already has).
                let taken = ((r.completed - p.stored) as usize).min(p.pending.len());
                p.pending.drain(..taken);
                p.stored = r.completed;
                // Fewer than sent: the controller reads at most a few lines
                // per command (`kb_pth_chunk` of the shipped program), or
                // its buffer is full. The room known from its last state
                // file tells which; an APPEND it took nothing of means full
                // (the state file was older than the last motions stored):
                // wait for the next state file's room.
                p.room = p.room.saturating_sub(taken as u32);
                if taken == 0 && a.count > 0 {
                    p.room = 0;
                }
                tracing::debug!(
                    cid = r.cid,
                    sent = a.count,
                    taken,
                    stored = p.stored,
                    room = p.room,
                    "append answered"
                );
                if a.close && r.code == ResultCode::Ok && taken == a.count {
                    p.close_sent = true;
                }
                if r.code == ResultCode::BadCommand {
                    tracing::warn!(
                        cid = r.cid,
                        path = p.cid,
                        stored = r.completed,
                        "append refused; sending again from the controller's stored count"
                    );
                }
            }
            code => {
                tracing::warn!(
                    cid = r.cid,
                    path = p.cid,
                    code = code.code(),
                    "the controller no longer takes motions for the path"
                );
                p.over = true;
            }
        }
        let (job, progress, batch) = (p.job, p.progress(), p.batch);
        if !batch {
            self.shared.update(job, |j| j.path = Some(progress));
        }
        self.take_parked();
        true
    }

    /// A state file while the path runs: the controller's buffer room.
    pub(super) fn path_state(&mut self, s: &StateFile) {
        let Some(p) = self.path.as_mut() else { return };
        if s.status == ControllerStatus::Busy && s.busy_cid == p.cid {
            if let Some(a) = p.append.take_if(|a| a.cid == p.cid) {
                // The motions the PATH command carried: the controller's
                // stored count says how many it took.
                let taken = (s.stored.saturating_sub(p.stored) as usize).min(p.pending.len());
                p.pending.drain(..taken);
                p.stored = p.stored.max(s.stored);
                if a.close && taken == a.count {
                    p.close_sent = true;
                }
            }
            // Motions stored after this state was written hold room too.
            p.room = s.room.saturating_sub(p.stored.saturating_sub(s.stored));
            p.max_room = p.max_room.max(s.room);
        }
    }

    /// Appends whose wait has run out fail with `path_full`; an APPEND the
    /// controller has not answered within `ack_timeout` (its result was
    /// lost, e.g. the result file was rewritten meanwhile) is given up: the
    /// next one starts from the stored count of the newest state file, so
    /// nothing is sent twice into the path and nothing is skipped.
    pub(super) fn expire_parked(&mut self, now: Instant) {
        let ack = self.cfg.ack_timeout;
        let state = self.ctl.state;
        let Some(p) = self.path.as_mut() else { return };
        if let Some(a) = p.append.take_if(|a| now.duration_since(a.sent_at) > ack) {
            let resync = state
                .as_ref()
                .filter(|s| s.status == ControllerStatus::Busy && s.busy_cid == p.cid)
                .map(|s| s.stored);
            tracing::warn!(cid = a.cid, path = p.cid, stored = ?resync, "no answer to the append; sending again from the controller's stored count");
            if let Some(stored) = resync
                && stored >= p.stored
            {
                let taken = ((stored - p.stored) as usize).min(p.pending.len());
                p.pending.drain(..taken);
                p.stored = stored;
            }
        }
        let (job, pending) = (p.job, p.pending.len());
        let (expired, waiting): (Vec<Parked>, Vec<Parked>) = p
            .parked
            .drain(..)
            .partition(|a| a.deadline <= now || a.req.reply.is_closed());
        p.parked = waiting.into();
        for a in expired {
            let e = BridgeError::new(
                ErrorCode::PathFull,
                format!(
                    "path {job} holds {pending} motions not yet sent to the controller (at most {MAX_PENDING}); there was no room for these {} within {} ms",
                    a.req.motions.len(),
                    a.req.wait.as_millis()
                ),
            );
            let _ = a.req.reply.send(Err(e));
        }
    }

    /// The path's job has ended (result, failure, stop): waiting appends
    /// hear that it is closed; the rest is dropped.
    pub(super) fn end_path(&mut self, job: JobId) {
        if let Some(p) = self.path.take_if(|p| p.job == job) {
            let dropped = p.pending.len();
            if dropped > 0 {
                tracing::info!(path = p.job, dropped, "path ended with motions not sent");
            }
            for a in p.parked {
                let _ = a.req.reply.send(Err(closed_error(job)));
            }
        }
    }

    /// How the job `job` ends when a stop ends it: with the refusal that
    /// closed its path first, if it is a path that refused a motion
    /// (failed, "…; then" the stop's sentence: the simulators agree
    /// however fast the stop came), else cancelled with `stop`.
    pub(super) fn stopped_path(&self, job: JobId, stop: BridgeError) -> (JobState, BridgeError) {
        let refused = self
            .path
            .as_ref()
            .filter(|p| p.job == job)
            .and_then(|p| p.refused.clone());
        match refused {
            Some(mut e) => {
                e.detail = format!("{}; then {}", e.detail, stop.detail);
                (JobState::Failed, e)
            }
            None => (JobState::Cancelled, stop),
        }
    }

    /// The path cannot go on (its APPEND could not be written): its job
    /// fails and the robot stops.
    pub(super) fn fail_path(&mut self, e: BridgeError) {
        if let Some(job) = self.path.as_ref().map(|p| p.job) {
            if self.inflight.as_ref().is_some_and(|f| f.id == job) {
                self.fail_inflight(e);
            }
            self.end_path(job);
            self.request_stop(None);
        }
    }
}
