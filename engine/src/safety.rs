//! Checks every motion must pass before anything is written to the
//! channel: finite numbers, Status/Turn ranges, speed caps, the workspace
//! box and — with a robot model — a dry run of the whole batch through the
//! same planner the simulated controller executes (reachability, software
//! limit switches, singularities along LIN/CIRC paths). Uploaded KRL
//! programs get the same dry run when they stay within the simulator's KRL
//! subset ([`Safety::check_program`]).

use kuka_kinematics::MotionKind;
use kuka_kinematics::{IkError, MotionError, RobotModel, plan};
use kuka_krl_runtime::interp::{RunError, Start, Step};
use kuka_krl_runtime::program::PrepareError;
use kuka_protocol::{Frame, MAX_REAL, MotionRecord, SpeedRecord};

use crate::error::{BridgeError, ErrorCode, Result, shown};
use crate::motion::{MotionRequest, StartPoint, TargetSpec};
use crate::settings::{MotionConfig, WorkspaceBox, Zones};
use kuka_kinematics::configure::{self, ConfigError, Failure, Margins};

/// The safety gate shared by HTTP handlers and (later) plugins.
#[derive(Debug, Clone)]
pub struct Safety {
    motion: MotionConfig,
    workspace: Option<WorkspaceBox>,
    zones: Zones,
    model: Option<RobotModel>,
}

fn finite(what: &str, v: Option<f64>, i: usize) -> Result<()> {
    match v {
        Some(x) if !x.is_finite() || x.abs() > MAX_REAL => Err(BridgeError::invalid(format!(
            "motion {i}: {what} = {} is not a finite number within ±{MAX_REAL}",
            shown(x)
        ))
        .at_motion(i)),
        _ => Ok(()),
    }
}

fn check_target(t: &TargetSpec, i: usize, allow_st: bool) -> Result<()> {
    for (name, v) in [
        ("x", t.x),
        ("y", t.y),
        ("z", t.z),
        ("a", t.a),
        ("b", t.b),
        ("c", t.c),
    ] {
        finite(name, v, i)?;
    }
    if let Some(s) = t.s
        && !(allow_st && (0..=7).contains(&s))
    {
        let why = if allow_st {
            format!("Status {s} is not in 0..=7")
        } else {
            "Status applies to PTP only".into()
        };
        return Err(BridgeError::invalid(format!("motion {i}: {why}")).at_motion(i));
    }
    if let Some(t) = t.t
        && !(allow_st && (0..=63).contains(&t))
    {
        let why = if allow_st {
            format!("Turn {t} is not in 0..=63")
        } else {
            "Turn applies to PTP only".into()
        };
        return Err(BridgeError::invalid(format!("motion {i}: {why}")).at_motion(i));
    }
    Ok(())
}

impl Safety {
    /// A gate for this configuration and optional robot model.
    pub fn new(
        motion: MotionConfig,
        workspace: Option<WorkspaceBox>,
        zones: Zones,
        model: Option<RobotModel>,
    ) -> Self {
        Safety {
            motion,
            workspace,
            zones,
            model,
        }
    }

    /// Checks the way home (an axis PTP to the model's home at `velocity_pct`)
    /// against the workspace rules, as any motion's swept path is.
    pub fn check_home(
        &self,
        start: &StartPoint,
        tool: &Frame,
        base: &Frame,
        velocity_pct: f64,
    ) -> Result<()> {
        let Some(model) = &self.model else {
            return Ok(());
        };
        let home = plan::Motion {
            kind: MotionKind::PtpAxes { axes: model.home },
            velocity: velocity_pct.clamp(1.0, 100.0),
            acceleration_pct: 100.0,
            approx_mm: 0.0,
        };
        let to_pose = |f: &Frame| kuka_krl_runtime::frame_to_pose(f);
        let run = plan::plan(
            model,
            &start.axes,
            &to_pose(tool),
            &to_pose(base),
            &[home],
            &plan::PlanSettings::for_model(model),
        );
        match self.sweep_violation(&run.samples, |_| 0.0) {
            Some((_, p, why)) => Err(BridgeError::new(
                ErrorCode::WorkspaceViolation,
                format!(
                    "the way home passes ({:.1}, {:.1}, {:.1}) mm, {why}",
                    p[0], p[1], p[2]
                ),
            )),
            None => Ok(()),
        }
    }

    /// The workspace box, if one is configured.
    pub fn workspace(&self) -> Option<&WorkspaceBox> {
        self.workspace.as_ref()
    }

    /// The floor and keep-out zones.
    pub fn zones(&self) -> &Zones {
        &self.zones
    }

    /// A workspace box, a floor or a keep-out zone is configured.
    fn has_path_rules(&self) -> bool {
        self.workspace.is_some() || self.zones.floor_z.is_some() || !self.zones.keep_out.is_empty()
    }

    /// The first place a swept path breaks the workspace rules: the motion
    /// (index into the planned motions), the point and why. Every sample is
    /// checked, and between two samples the straight piece too (a fast PTP
    /// samples several mm apart, enough to step over a thin zone). Where a
    /// motion is approximated its corner is cut by up to `approx(i)` mm, so
    /// keep-out zones are grown by it there.
    fn sweep_violation(
        &self,
        samples: &[plan::Sample],
        approx: impl Fn(usize) -> f64,
    ) -> Option<(usize, [f64; 3], String)> {
        if !self.has_path_rules() {
            return None;
        }
        let mut prev: Option<[f64; 3]> = None;
        for sample in samples {
            let q = sample.pose.position();
            let p = [q.x, q.y, q.z];
            let i = sample.motion;
            let margin = approx(i).max(if i > 0 { approx(i - 1) } else { 0.0 });
            if let Some(why) = self.place_violation(p, margin) {
                return Some((i, p, why));
            }
            if let Some(a) = prev
                && let Some(k) = self
                    .zones
                    .keep_out
                    .iter()
                    .find(|k| segment_hits_box(a, p, [k.x, k.y, k.z], margin))
            {
                return Some((
                    i,
                    p,
                    format!(
                        "passing through the keep-out zone `{}` x {:?}, y {:?}, z {:?} just before it",
                        k.name, k.x, k.y, k.z
                    ),
                ));
            }
            prev = Some(p);
        }
        None
    }

    /// Why a TCP position is not allowed (outside the box, below the
    /// floor, inside a keep-out zone grown by `margin` mm), or `None`.
    fn place_violation(&self, p: [f64; 3], margin: f64) -> Option<String> {
        if let Some(ws) = &self.workspace
            && !ws.contains(p[0], p[1], p[2])
        {
            return Some(format!(
                "outside the workspace box x {:?}, y {:?}, z {:?}",
                ws.x, ws.y, ws.z
            ));
        }
        if let Some(floor) = self.zones.floor_z
            && p[2] < floor
        {
            return Some(format!("below the floor (z = {floor} mm)"));
        }
        self.zones
            .keep_out
            .iter()
            .find(|k| k.contains(p, margin))
            .map(|k| {
                let grown = if margin > 0.0 {
                    format!(" (grown by the {margin} mm approximation)")
                } else {
                    String::new()
                };
                format!(
                    "inside the keep-out zone `{}` x {:?}, y {:?}, z {:?}{grown}",
                    k.name, k.x, k.y, k.z
                )
            })
    }

    /// The robot model in use, if any.
    pub fn model(&self) -> Option<&RobotModel> {
        self.model.as_ref()
    }

    /// The motion configuration.
    pub fn motion_config(&self) -> &MotionConfig {
        &self.motion
    }

    /// Checks a request before it is queued (no knowledge of the start):
    /// [`Safety::check_batch`], then each motion's numbers and speeds.
    pub fn check_request(&self, requests: &[MotionRequest]) -> Result<()> {
        self.check_batch(requests)?;
        for (i, r) in requests.iter().enumerate() {
            match r {
                MotionRequest::Ptp { target, .. } | MotionRequest::Sptp { target, .. } => {
                    check_target(target, i, true)?
                }
                MotionRequest::Lin { target, .. }
                | MotionRequest::Slin { target, .. }
                | MotionRequest::Spl { target, .. } => check_target(target, i, false)?,
                MotionRequest::Circ { aux, target, .. }
                | MotionRequest::Scirc { aux, target, .. } => {
                    check_target(target, i, false)?;
                    for (name, v) in [("aux.x", aux.x), ("aux.y", aux.y), ("aux.z", aux.z)] {
                        finite(name, v, i)?;
                    }
                }
                MotionRequest::PtpAxes { axes, .. } | MotionRequest::SptpAxes { axes, .. } => {
                    let named = [
                        ("a1", axes.a1),
                        ("a2", axes.a2),
                        ("a3", axes.a3),
                        ("a4", axes.a4),
                        ("a5", axes.a5),
                        ("a6", axes.a6),
                    ];
                    for (name, v) in named {
                        finite(name, v, i)?;
                    }
                }
                // (Their signals and times: `resolve_signals`.)
                MotionRequest::SetOutput { .. }
                | MotionRequest::WaitInput { .. }
                | MotionRequest::Dwell { .. } => {}
            }
            let (vel, acc, apo) = r.speed();
            match (vel, r.is_ptp()) {
                (Some(v), true) => {
                    self.cap(i, "velocity_pct", v, self.motion.max_ptp_velocity_pct, "%")?
                }
                (Some(v), false) => {
                    self.cap(i, "velocity_m_s", v, self.motion.max_cp_velocity, " m/s")?
                }
                (None, _) => {}
            }
            if let Some(a) = acc
                && !(a.is_finite() && (1.0..=100.0).contains(&a))
            {
                return Err(BridgeError::invalid(format!(
                    "motion {i}: acceleration_pct = {a} is not in [1, 100]"
                ))
                .at_motion(i));
            }
            if let Some(d) = apo
                && !(d.is_finite() && d >= 0.0 && d <= self.motion.max_approx_mm)
            {
                return Err(BridgeError::invalid(format!(
                    "motion {i}: approx_mm = {d} is not in [0, {}]",
                    self.motion.max_approx_mm
                ))
                .at_motion(i));
            }
        }
        Ok(())
    }

    /// The request as a whole: at least one motion, at most `max_batch`.
    pub fn check_batch(&self, requests: &[MotionRequest]) -> Result<()> {
        if requests.is_empty() {
            return Err(BridgeError::invalid(
                "a motion request needs at least one motion",
            ));
        }
        if requests.len() > self.motion.max_batch {
            return Err(BridgeError::invalid(format!(
                "{} motions in one batch; at most {} are allowed",
                requests.len(),
                self.motion.max_batch
            )));
        }
        Ok(())
    }

    fn cap(&self, i: usize, name: &str, v: f64, max: f64, unit: &str) -> Result<()> {
        // Below the file protocol's step the controller would read 0.
        if !v.is_finite() || v < kuka_protocol::REAL_STEP {
            return Err(BridgeError::invalid(format!(
                "motion {i}: {name} = {} must be a positive number of at least {}",
                shown(v),
                kuka_protocol::REAL_STEP
            ))
            .at_motion(i));
        }
        if v > max {
            return Err(BridgeError::new(
                ErrorCode::SpeedLimit,
                format!(
                    "motion {i}: {name} = {}{unit} exceeds the configured cap of {max}{unit}",
                    shown(v)
                ),
            )
            .at_motion(i));
        }
        Ok(())
    }

    /// Chooses the arm configuration of every Cartesian PTP without `s`
    /// whose `config` (else the site's `motion.configuration`) is `auto`,
    /// and writes the chosen Status and Turn into its record, so that the
    /// controller executes exactly that configuration
    /// ([`kuka_kinematics::configure`]; docs/CONFIGURATION.md). Without a
    /// robot model nothing is chosen (the controller keeps its Status).
    /// When no configuration lets the Cartesian motions after a PTP run,
    /// the error is that of the best configuration's first failing motion
    /// (its code and `motion`), with the PTP and every configuration tried
    /// in the detail.
    pub fn choose_configurations(
        &self,
        requests: &[MotionRequest],
        records: &mut [MotionRecord],
        start: &StartPoint,
        tool: &Frame,
        base: &Frame,
    ) -> Result<Vec<Option<configure::Chosen>>> {
        let Some(model) = &self.model else {
            return Ok(vec![None; records.len()]);
        };
        let modes: Vec<_> = requests
            .iter()
            .map(|r| r.config().unwrap_or(self.motion.configuration).into())
            .collect();
        let motions = kuka_krl_runtime::to_motions(records);
        let to_pose = |f: &Frame| kuka_krl_runtime::frame_to_pose(f);
        let (tool, base) = (to_pose(tool), to_pose(base));
        // A configuration whose PTP or following path would break the
        // workspace rules is dropped, as one that cannot reach is.
        let approx = |i: usize| motions.get(i).map_or(0.0, |m| m.approx_mm);
        let check = |first: usize, samples: &[plan::Sample]| {
            self.sweep_violation(samples, |k| approx(first + k))
                .map(|(k, p, why)| {
                    (
                        first + k,
                        format!(
                            "the path passes ({:.1}, {:.1}, {:.1}) mm, {why}",
                            p[0], p[1], p[2]
                        ),
                    )
                })
        };
        let cx = configure::Context {
            model,
            tool: &tool,
            base: &base,
            settings: &plan::PlanSettings::for_model(model),
            margins: &Margins::default(),
            // (Only with rules to check: planning the PTP too costs time.)
            path_check: self.has_path_rules().then_some(&check),
        };
        let chosen = configure::choose(&cx, &start.axes, &motions, &modes).map_err(|e| {
            let (code, axis, at) = match &e {
                ConfigError::NoConfiguration { tried, index } => {
                    tried
                        .first()
                        .map_or((ErrorCode::Unreachable, 0, *index), |c| match &c.error {
                            Failure::Motion(e) => {
                                let m = motion_error(e);
                                (m.code, m.axis.unwrap_or(0), c.failed_motion)
                            }
                            Failure::Path(_) => (ErrorCode::WorkspaceViolation, 0, c.failed_motion),
                        })
                }
                ConfigError::OutOfReach { index, per_status } => {
                    // Software limits if any Status reaches the target at all.
                    let limit = per_status.iter().find_map(|(_, e)| match e {
                        IkError::SoftwareLimit { axis, .. } => Some(*axis),
                        _ => None,
                    });
                    match limit {
                        Some(axis) => (ErrorCode::SoftwareLimit, axis, *index),
                        None => (ErrorCode::Unreachable, 0, *index),
                    }
                }
            };
            BridgeError::new(code, e.to_string())
                .on_axis(axis)
                .at_motion(at)
        })?;
        for (record, c) in records.iter_mut().zip(&chosen) {
            if let (MotionRecord::Ptp { s, t, .. } | MotionRecord::Sptp { s, t, .. }, Some(c)) =
                (record, c)
            {
                *s = Some(c.s);
                *t = Some(c.t);
            }
        }
        Ok(chosen)
    }

    /// Checks resolved motions from a known start: workspace box, then a
    /// dry run with the robot model (if configured). Returns, per motion,
    /// the Status and Turn the robot has at its end (empty without a model).
    pub fn check_resolved(
        &self,
        motions: &[MotionRecord],
        start: &StartPoint,
        tool: &Frame,
        base: &Frame,
    ) -> Result<Vec<(u8, u8)>> {
        self.check_resolved_with_end(motions, start, tool, base)
            .map(|(ends, _)| ends)
    }

    /// [`Self::check_resolved`] for motions appended to a path: where they
    /// end (the start of the next append). Without a robot model the axes
    /// stay those of `start` and the pose is the last Cartesian target.
    pub fn check_resolved_end(
        &self,
        motions: &[MotionRecord],
        start: &StartPoint,
        tool: &Frame,
        base: &Frame,
    ) -> Result<StartPoint> {
        self.check_resolved_with_end(motions, start, tool, base)
            .map(|(_, end)| end)
    }

    fn check_resolved_with_end(
        &self,
        motions: &[MotionRecord],
        start: &StartPoint,
        tool: &Frame,
        base: &Frame,
    ) -> Result<(Vec<(u8, u8)>, StartPoint)> {
        // The targets (and CIRC auxiliary points): without a robot model all
        // that can be checked; with one, after the swept path (which names
        // the first point outside), for a path the dry run cannot finish.
        let targets = || -> Result<()> {
            for (i, m) in motions.iter().enumerate() {
                let mut points: Vec<[f64; 3]> = Vec::with_capacity(2);
                points.extend(m.aux());
                points.extend(m.target().map(|t| [t.x, t.y, t.z]));
                for p in points {
                    if let Some(why) = self.place_violation(p, 0.0) {
                        return Err(BridgeError::new(
                            ErrorCode::WorkspaceViolation,
                            format!(
                                "motion {i}: point ({:.1}, {:.1}, {:.1}) mm lies {why}",
                                p[0], p[1], p[2]
                            ),
                        )
                        .at_motion(i));
                    }
                }
            }
            Ok(())
        };
        let Some(model) = &self.model else {
            targets()?;
            let pose = motions
                .iter()
                .rev()
                .find_map(|m| m.target().copied())
                .unwrap_or(start.pose);
            return Ok((
                Vec::new(),
                StartPoint {
                    pose,
                    axes: start.axes,
                },
            ));
        };
        let records = motions;
        let motions = kuka_krl_runtime::to_motions(records);
        let to_pose = |f: &Frame| kuka_krl_runtime::frame_to_pose(f);
        let execution = plan::plan(
            model,
            &start.axes,
            &to_pose(tool),
            &to_pose(base),
            &motions,
            &plan::PlanSettings::for_model(model),
        );
        // The swept path: every sample of the dry run (PTP joint paths, LIN
        // lines, CIRC arcs) and the pieces between, up to where it stops.
        let approx = |i: usize| motions.get(i).map_or(0.0, |m| m.approx_mm);
        if let Some((i, p, why)) = self.sweep_violation(&execution.samples, approx) {
            return Err(BridgeError::new(
                ErrorCode::WorkspaceViolation,
                format!(
                    "motion {i}: the path passes ({:.1}, {:.1}, {:.1}) mm, {why}",
                    p[0], p[1], p[2]
                ),
            )
            .at_motion(i));
        }
        targets()?;
        if execution.error.is_none() {
            switch_point_lengths(records, &execution.samples)?;
        }
        match execution.error {
            None => {
                // S/T as the controller will report them: from the axes
                // with the protocol's 3 decimals (an axis at -0.0002° is 0).
                let st = |a: &[f64; 6]| {
                    let a = a.map(|v| (v * 1000.0).round() / 1000.0);
                    (model.status(&a), RobotModel::turn(&a))
                };
                let mut ends = vec![st(&start.axes); records.len()];
                for sample in &execution.samples {
                    if let Some(end) = ends.get_mut(sample.motion) {
                        *end = st(&sample.axes);
                    }
                }
                let axes = execution.end_axes;
                let pose = kuka_krl_runtime::pose_to_frame(&model.forward(
                    &axes,
                    &to_pose(tool),
                    &to_pose(base),
                ));
                Ok((ends, StartPoint { pose, axes }))
            }
            Some((i, e)) => {
                let mut err = motion_error(&e).at_motion(i);
                // KUKA keeps the Status of a PTP without S: say how to change it.
                if let Some(MotionRecord::Ptp { s: None, .. } | MotionRecord::Sptp { s: None, .. }) =
                    records.get(i)
                    && matches!(err.code, ErrorCode::SoftwareLimit | ErrorCode::Unreachable)
                {
                    err.detail.push_str(&format!(
                        " (a PTP without `s` keeps the current Status {}; give `s`, 0..7, to choose another arm configuration)",
                        model.status(&start.axes)
                    ));
                }
                Err(err)
            }
        }
    }
}

/// Slack (mm) of [`switch_point_lengths`]: the dry run's path is a chain
/// of 12 ms chords, a little shorter than an arc.
const SWITCH_POINT_SLACK_MM: f64 = 0.5;

/// The dry run's check of the `set_output` actions with `path_mm`
/// (docs/IO.md): a KRL `TRIGGER WHEN PATH` shifts its switching point at
/// most back to the start of its motion and forward to the next exact
/// stop, so |path_mm| may be at most the length of the motion before it
/// (negative) or after it (positive), as planned: from where the motion
/// takes over from the one before (the middle of an approximation arc) to
/// where it hands over to the next. Longer: 422 `invalid_input`.
fn switch_point_lengths(records: &[MotionRecord], samples: &[plan::Sample]) -> Result<()> {
    for (i, p, motion) in crate::motion::switch_points(records) {
        // The motion's piece of the path, with the step into its first
        // sample from the last one of the motion before.
        let first = samples.iter().position(|s| s.motion == motion);
        let last = samples.iter().rposition(|s| s.motion == motion);
        let length = match (first, last) {
            (Some(a), Some(b)) => samples[a.saturating_sub(1)..=b]
                .windows(2)
                .map(|w| w[1].pose.distance_mm(&w[0].pose))
                .sum(),
            _ => 0.0,
        };
        if p.abs() > length + SWITCH_POINT_SLACK_MM {
            let side = if p < 0.0 { "before" } else { "after" };
            return Err(BridgeError::invalid(format!(
                "motion {i}: path_mm = {p} lies {:.1} mm {side} the end point of the motion before it, \
                 but motion {motion} is only {length:.1} mm long (a KRL path trigger shifts at most \
                 to the start of its motion or to the next exact stop)",
                p.abs()
            ))
            .at_motion(i));
        }
    }
    Ok(())
}

impl Safety {
    /// Dry-runs an uploaded program before it is sent, when it can be: a
    /// robot model is configured and the program stays within the
    /// simulator's KRL subset (the interpreter runs it ahead, as KRL's
    /// advance run would). Every motion is held to the speed caps and the
    /// workspace box, then the run is planned phase by phase from `start`
    /// (reachability, software limits, singularities). Errors name the
    /// program line. A program outside the subset (only a real KRC can
    /// run it) is sent unchecked; one that does not end within the
    /// interpreter's statement, evaluation or step limits (a cyclic
    /// program, run until stopped) is checked up to there; one that nests
    /// too deep or holds too many values (`RunError::Limit`) is refused
    /// as `invalid_program` with its line and the limit.
    pub fn check_program(
        &self,
        program: &crate::programs::StoredProgram,
        start: &StartPoint,
        tool: &Frame,
        base: &Frame,
        speed: SpeedRecord,
    ) -> Result<ProgramCheck> {
        let unchecked = ProgramCheck::default();
        let Some(model) = &self.model else {
            return Ok(unchecked);
        };
        // Dry-run exactly what the controller will run: the generated
        // module (with its BCO run); lines map back to the upload.
        let module = crate::programs::module_text(0, program);
        let up = crate::programs::upload_line;
        let st = Start {
            model,
            axes: start.axes,
            tool: kuka_krl_runtime::frame_to_pose(tool),
            base: kuka_krl_runtime::frame_to_pose(base),
            speed,
        };
        let run = kuka_krl_runtime::program::interpret(
            &module.src,
            module.dat.as_deref(),
            &module.name,
            &st,
        );
        let (steps, complete) = match run {
            Ok(steps) => (steps, true),
            Err(PrepareError::Parse(e)) => return Err(crate::programs::program_error(&e)),
            Err(PrepareError::Run(RunError::TooLong { steps, .. })) => (steps, false),
            // Beyond the simulator's subset: only a real KRC can run it.
            Err(PrepareError::Run(RunError::Unsupported(_))) => return Ok(unchecked),
            // Hosted-mode outcomes: an unhosted dry run never returns them.
            Err(PrepareError::Run(RunError::Cancelled | RunError::Resumed { .. })) => {
                return Ok(unchecked);
            }
            // Too deep or too large for the interpreter (kuka_krl_runtime::interp's
            // limits): refused like a program that does not parse.
            Err(PrepareError::Run(RunError::Limit { line, message })) => {
                return Err(BridgeError::new(
                    ErrorCode::InvalidProgram,
                    format!(
                        "program {} cannot be run: line {}: {}",
                        program.info.name,
                        up(line),
                        crate::programs::upload_lines_in(&message)
                    ),
                )
                .at_line("src", up(line)));
            }
            Err(PrepareError::Run(RunError::Runtime { line, message })) => {
                return Err(BridgeError::new(
                    ErrorCode::ProgramFailed,
                    format!(
                        "program {} would fail at line {}: {}",
                        program.info.name,
                        up(line),
                        crate::programs::upload_lines_in(&message)
                    ),
                )
                .at_line("src", up(line)));
            }
        };
        let count = steps.len();
        let at = |e: BridgeError, line: u32| {
            let line = up(line);
            let mut e = e.at_line("src", line);
            e.motion = None;
            e.detail = format!("{} (program {}, line {line})", e.detail, program.info.name);
            e
        };
        for step in &steps {
            let Step::Move { motion, line, .. } = step else {
                continue;
            };
            let (name, max, unit) = match motion.kind {
                MotionKind::Ptp { .. } | MotionKind::PtpAxes { .. } => {
                    ("velocity", self.motion.max_ptp_velocity_pct, "%")
                }
                _ => ("$VEL.CP", self.motion.max_cp_velocity, " m/s"),
            };
            let v = motion.velocity;
            if !(v.is_finite() && v > 0.0) {
                let e = BridgeError::invalid(format!(
                    "{name} = {} must be a positive number",
                    shown(v)
                ));
                return Err(at(e, *line));
            }
            if v > max {
                let e = BridgeError::new(
                    ErrorCode::SpeedLimit,
                    format!(
                        "{name} = {}{unit} exceeds the configured cap of {max}{unit}",
                        shown(v)
                    ),
                );
                return Err(at(e, *line));
            }
            if let Some(ws) = &self.workspace {
                let mut points = Vec::with_capacity(2);
                match &motion.kind {
                    MotionKind::Ptp { target, .. }
                    | MotionKind::Lin { target }
                    | MotionKind::Spl { target, .. } => points.push(*target),
                    MotionKind::Circ { aux, target } => points.extend([*aux, *target]),
                    MotionKind::PtpAxes { .. } | MotionKind::Hold { .. } | MotionKind::Mark => {}
                }
                for p in points {
                    if !ws.contains(p.x, p.y, p.z) {
                        let e = BridgeError::new(
                            ErrorCode::WorkspaceViolation,
                            format!(
                                "point ({:.1}, {:.1}, {:.1}) mm lies outside the workspace box x {:?}, y {:?}, z {:?}",
                                p.x, p.y, p.z, ws.x, ws.y, ws.z
                            ),
                        );
                        return Err(at(e, *line));
                    }
                }
            }
        }
        let phases = kuka_krl_runtime::program::phases(steps);
        let settings = plan::PlanSettings::for_model(model);
        // Phase by phase, as the program runs: the swept path of each
        // checked against the workspace rules, then its planning error.
        let mut axes = start.axes;
        for phase in &phases {
            let kuka_krl_runtime::program::Phase::Moves {
                tool,
                base,
                motions,
                lines,
            } = phase
            else {
                continue;
            };
            let run = plan::plan(model, &axes, tool, base, motions, &settings);
            let approx = |i: usize| motions.get(i).map_or(0.0, |m| m.approx_mm);
            if let Some((i, p, why)) = self.sweep_violation(&run.samples, approx) {
                let e = BridgeError::new(
                    ErrorCode::WorkspaceViolation,
                    format!(
                        "the path passes ({:.1}, {:.1}, {:.1}) mm, {why}",
                        p[0], p[1], p[2]
                    ),
                );
                return Err(at(e, lines.get(i).copied().unwrap_or(0)));
            }
            if let Some((i, error)) = run.error {
                return Err(at(motion_error(&error), lines.get(i).copied().unwrap_or(0)));
            }
            axes = run.end_axes;
        }
        Ok(ProgramCheck {
            checked: true,
            complete,
            steps: Some(count),
        })
    }
}

/// Whether the segment `a`–`b` meets the box (grown by `margin`): the slab
/// test, axis by axis.
fn segment_hits_box(a: [f64; 3], b: [f64; 3], r: [[f64; 2]; 3], margin: f64) -> bool {
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for k in 0..3 {
        let (lo, hi) = (r[k][0] - margin, r[k][1] + margin);
        let d = b[k] - a[k];
        if d.abs() < 1e-12 {
            if a[k] <= lo || a[k] >= hi {
                return false;
            }
            continue;
        }
        let (mut u, mut v) = ((lo - a[k]) / d, (hi - a[k]) / d);
        if u > v {
            std::mem::swap(&mut u, &mut v);
        }
        t0 = t0.max(u);
        t1 = t1.min(v);
        if t0 >= t1 {
            return false;
        }
    }
    true
}

/// What [`Safety::check_program`] could check.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ProgramCheck {
    /// The program was dry-run.
    pub checked: bool,
    /// The dry run reached the program's end (false: it stopped at the
    /// interpreter's limits, e.g. a program that runs until stopped).
    pub complete: bool,
    /// Motions and dwells the dry run found (up to the limit).
    pub steps: Option<usize>,
}

/// Maps a planner error to the API error (the same mapping as controller results).
pub fn motion_error(e: &MotionError) -> BridgeError {
    let (code, axis) = match e {
        MotionError::Ik(IkError::Unreachable)
        | MotionError::Ik(IkError::NoMatchingConfiguration { .. }) => (ErrorCode::Unreachable, 0),
        MotionError::Ik(IkError::SoftwareLimit { axis, .. }) => (ErrorCode::SoftwareLimit, *axis),
        MotionError::Singularity(_) => (ErrorCode::Singularity, 0),
        MotionError::Geometry(_) | MotionError::Parameter(_) => (ErrorCode::InvalidInput, 0),
    };
    BridgeError::new(code, e.to_string()).on_axis(axis)
}
