//! The bridge as plugins see it: [`EngineBridge`] implements the plugin
//! host's `BridgeApi` with the engine's own `execute` path, so every motion
//! a plugin asks for is validated, safety-checked, queued and logged exactly
//! like a `POST /api/v1/motions` (a plugin cannot do what a client could not).

use kuka_plugin_host as host;

use crate::access::RequestContext;
use crate::engine::{CartesianFrame, Engine, Operation, Position};
use crate::error::{BridgeError, ErrorCode};
use crate::io::{IoKind, OutputRequest};
use crate::motion::{AuxPoint, AxesSpec, MotionRequest, SignalRef, TargetSpec};

/// Forwards plugin host calls to the engine.
pub struct EngineBridge {
    /// The engine.
    pub engine: Engine,
    /// The control lease: a plugin's motions run under its caller's
    /// identity and are refused if someone else took control meanwhile.
    pub control: std::sync::Arc<crate::access::Control>,
}

fn host_error(e: BridgeError) -> host::HostError {
    host::host_error(
        e.code.as_str(),
        e.detail,
        e.motion.and_then(|m| u32::try_from(m).ok()),
    )
}

fn target(p: &host::Pose, s: Option<u8>, t: Option<u8>) -> TargetSpec {
    TargetSpec {
        x: Some(p.x),
        y: Some(p.y),
        z: Some(p.z),
        a: Some(p.a),
        b: Some(p.b),
        c: Some(p.c),
        s: s.map(i64::from),
        t: t.map(i64::from),
    }
}

/// A plugin motion as the REST API's motion request.
pub fn motion_request(m: host::Motion) -> MotionRequest {
    match m {
        host::Motion::Ptp(m) => MotionRequest::Ptp {
            target: target(&m.target, m.s, m.t),
            relative: false,
            velocity_pct: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
            // The site's motion.configuration.
            config: None,
        },
        host::Motion::PtpAxes(m) => MotionRequest::PtpAxes {
            axes: AxesSpec {
                a1: Some(m.target.a1),
                a2: Some(m.target.a2),
                a3: Some(m.target.a3),
                a4: Some(m.target.a4),
                a5: Some(m.target.a5),
                a6: Some(m.target.a6),
            },
            relative: false,
            velocity_pct: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
        },
        host::Motion::Lin(m) => MotionRequest::Lin {
            target: target(&m.target, None, None),
            relative: false,
            velocity_m_s: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
        },
        host::Motion::Circ(m) => MotionRequest::Circ {
            aux: aux_point(&m.aux),
            target: target(&m.target, None, None),
            relative: false,
            velocity_m_s: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
        },
    }
}

/// A plugin's auxiliary point (CIRC, SCIRC) as the REST API's.
fn aux_point(p: &host::Point) -> AuxPoint {
    AuxPoint {
        x: Some(p.x),
        y: Some(p.y),
        z: Some(p.z),
    }
}

/// A plugin motion of either family (the `splines` interface) as the REST
/// API's motion request: the spline motions become the REST API's `spl`,
/// `slin`, `scirc` and `sptp`, so the engine forms their spline blocks and
/// checks them exactly as for `POST /api/v1/motions`.
pub fn any_motion_request(m: host::AnyMotion) -> MotionRequest {
    match m {
        host::AnyMotion::Motion(m) => motion_request(m),
        host::AnyMotion::Spl(m) => MotionRequest::Spl {
            target: target(&m.target, None, None),
            relative: false,
            velocity_m_s: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
        },
        host::AnyMotion::Slin(m) => MotionRequest::Slin {
            target: target(&m.target, None, None),
            relative: false,
            velocity_m_s: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
        },
        host::AnyMotion::Scirc(m) => MotionRequest::Scirc {
            aux: aux_point(&m.aux),
            target: target(&m.target, None, None),
            relative: false,
            velocity_m_s: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
        },
        host::AnyMotion::Sptp(m) => MotionRequest::Sptp {
            target: target(&m.target, m.s, m.t),
            relative: false,
            velocity_pct: m.params.velocity,
            acceleration_pct: m.params.acceleration_pct,
            approx_mm: m.params.approx_mm,
            // The site's motion.configuration, as for a plugin's PTP.
            config: None,
        },
    }
}

/// A plugin step of the `io` interface (a motion or an I/O action) as the
/// REST API's request: the `steps` interface's step without a distance.
pub fn step_request(s: host::Step) -> MotionRequest {
    any_step_request(match s {
        host::Step::Motion(m) => host::AnyStep::Motion(host::AnyMotion::Motion(m)),
        // (The WIT `io.set-output` record has no distance: plugins switch
        // as the next motion starts.)
        host::Step::SetOutput(o) => host::AnyStep::SetOutput(host::SwitchOutput {
            signal: o.signal,
            value: o.value,
            pulse_ms: o.pulse_ms,
            path_mm: None,
        }),
        host::Step::WaitInput(w) => host::AnyStep::WaitInput(w),
        host::Step::Dwell(ms) => host::AnyStep::Dwell(ms),
    })
}

/// A step of the `steps` interface (a motion of either family or an I/O
/// action, an output possibly at a distance along the path) as the REST
/// API's request.
pub fn any_step_request(s: host::AnyStep) -> MotionRequest {
    match s {
        host::AnyStep::Motion(m) => any_motion_request(m),
        host::AnyStep::SetOutput(o) => MotionRequest::SetOutput {
            signal: SignalRef::Name(o.signal),
            value: o.value,
            pulse_ms: o.pulse_ms,
            path_mm: o.path_mm,
        },
        host::AnyStep::WaitInput(w) => MotionRequest::WaitInput {
            signal: SignalRef::Name(w.signal),
            value: w.value,
            timeout_ms: w.timeout_ms,
        },
        host::AnyStep::Dwell(ms) => MotionRequest::Dwell { ms },
    }
}

/// `[x, y, z, a, b, c]` as a plugin pose.
fn pose([x, y, z, a, b, c]: [f64; 6]) -> host::Pose {
    host::Pose { x, y, z, a, b, c }
}

fn frame_pose(f: &CartesianFrame) -> host::Pose {
    pose([f.x, f.y, f.z, f.a, f.b, f.c])
}

/// A position; axes the controller has not reported yet are NaN.
fn position(p: &Position, axes: Option<&crate::engine::AxisAngles>) -> host::Position {
    let [a1, a2, a3, a4, a5, a6] =
        axes.map_or([f64::NAN; 6], |a| [a.a1, a.a2, a.a3, a.a4, a.a5, a.a6]);
    host::Position {
        pose: pose(p.xyzabc()),
        s: p.s,
        t: p.t,
        axes: host::Axes {
            a1,
            a2,
            a3,
            a4,
            a5,
            a6,
        },
    }
}

fn unknown(what: &str) -> host::HostError {
    host::host_error(
        ErrorCode::ControllerOffline.as_str(),
        format!("the {what} is not known yet (no heartbeat from the controller)"),
        None,
    )
}

impl EngineBridge {
    /// Runs a batch for a plugin: under its caller's identity and control
    /// lease, as long as the plugin's request may take (a drawing can
    /// outlast `channel.command_timeout_ms`).
    async fn run_batch(
        &self,
        ctx: &host::CallContext,
        requests: Vec<MotionRequest>,
    ) -> Result<host::Done, host::HostError> {
        let count = requests.len();
        let who = ctx
            .caller
            .clone()
            .and_then(|c| c.downcast::<RequestContext>().ok());
        if let Some(who) = &who {
            // The caller's own HTTP call holds the lease meanwhile.
            drop(self.control.check(&who.principal).map_err(host_error)?);
        }
        tracing::info!(plugin = %ctx.plugin, version = %ctx.version, motions = count, "plugin motion batch");
        let job = self
            .engine
            // The batch may take as long as the plugin's request (a
            // drawing can outlast `channel.command_timeout_ms`).
            .execute_from(
                Operation::Move(requests),
                Some(ctx.request_time),
                ctx.request_time,
                Some(format!("plugin:{}@{}", ctx.plugin, ctx.version)),
                who.map(|w| w.caller()).unwrap_or_default(),
            )
            .await
            .map_err(host_error)?;
        let state = self.engine.state();
        let at = job
            .position
            .or(state.position)
            .ok_or_else(|| unknown("position"))?;
        Ok(host::Done {
            completed: u32::try_from(job.completed).unwrap_or(u32::MAX),
            position: position(&at, job.axes.as_ref().or(state.axes.as_ref())),
        })
    }

    /// Appends to a path for a plugin (all or none, as a JSON append of the
    /// REST API); how many motions the path holds now.
    async fn append_requests(
        &self,
        ctx: &host::CallContext,
        path: u64,
        requests: Vec<MotionRequest>,
    ) -> Result<u32, host::HostError> {
        // Waiting for room is the plugin's back-pressure, within its request time.
        let o = self
            .engine
            .append(path, requests, false, ctx.request_time)
            .await
            .map_err(host_error)?;
        Ok(u32::try_from(o.total).unwrap_or(u32::MAX))
    }
}

impl host::BridgeApi for EngineBridge {
    fn run_motions<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        motions: Vec<host::Motion>,
    ) -> host::BoxFuture<'a, Result<host::Done, host::HostError>> {
        let requests: Vec<MotionRequest> = motions.into_iter().map(motion_request).collect();
        Box::pin(self.run_batch(ctx, requests))
    }

    fn run_steps<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        steps: Vec<host::Step>,
    ) -> host::BoxFuture<'a, Result<host::Done, host::HostError>> {
        let requests: Vec<MotionRequest> = steps.into_iter().map(step_request).collect();
        Box::pin(self.run_batch(ctx, requests))
    }

    fn run_spline_motions<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        motions: Vec<host::AnyMotion>,
    ) -> host::BoxFuture<'a, Result<host::Done, host::HostError>> {
        let requests: Vec<MotionRequest> = motions.into_iter().map(any_motion_request).collect();
        Box::pin(self.run_batch(ctx, requests))
    }

    fn append_spline_motions<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        path: u64,
        motions: Vec<host::AnyMotion>,
    ) -> host::BoxFuture<'a, Result<u32, host::HostError>> {
        let requests: Vec<MotionRequest> = motions.into_iter().map(any_motion_request).collect();
        Box::pin(self.append_requests(ctx, path, requests))
    }

    fn run_any_steps<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        steps: Vec<host::AnyStep>,
    ) -> host::BoxFuture<'a, Result<host::Done, host::HostError>> {
        let requests: Vec<MotionRequest> = steps.into_iter().map(any_step_request).collect();
        Box::pin(self.run_batch(ctx, requests))
    }

    fn append_any_steps<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        path: u64,
        steps: Vec<host::AnyStep>,
    ) -> host::BoxFuture<'a, Result<u32, host::HostError>> {
        let requests: Vec<MotionRequest> = steps.into_iter().map(any_step_request).collect();
        Box::pin(self.append_requests(ctx, path, requests))
    }

    fn read_signal(&self, output: bool, signal: &str) -> Result<bool, host::HostError> {
        let kind = if output {
            IoKind::Output
        } else {
            IoKind::Input
        };
        let (index, _) = self
            .engine
            .io_config()
            .resolve(kind, signal)
            .map_err(host_error)?;
        let state = self.engine.state();
        let w = state.io.as_ref().ok_or_else(|| {
            host::host_error(
                ErrorCode::SignalNotReported.as_str(),
                "the controller program reports no I/O",
                None,
            )
        })?;
        w.get(kind, index).ok_or_else(|| {
            host::host_error(
                ErrorCode::SignalNotReported.as_str(),
                format!(
                    "the controller reports {io}[{}..{}] only, not {io}[{index}]",
                    w.base,
                    w.base + w.inputs.len() as u16 - 1,
                    io = kind.krl()
                ),
                None,
            )
        })
    }

    fn write_output<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        signal: String,
        value: bool,
        pulse_ms: Option<u32>,
    ) -> host::BoxFuture<'a, Result<(), host::HostError>> {
        Box::pin(async move {
            let io = self.engine.io_config();
            let (index, _) = io.resolve(IoKind::Output, &signal).map_err(host_error)?;
            let entry = io.writable(index).map_err(host_error)?;
            let op = Operation::SetOutput(OutputRequest {
                index,
                value,
                pulse_ms: pulse_ms.unwrap_or(entry.pulse_ms),
            });
            let who = ctx
                .caller
                .clone()
                .and_then(|c| c.downcast::<RequestContext>().ok());
            if let Some(who) = &who {
                drop(self.control.check(&who.principal).map_err(host_error)?);
            }
            tracing::info!(plugin = %ctx.plugin, version = %ctx.version, index, value, "plugin sets an output");
            self.engine
                .execute_from(
                    op,
                    None,
                    ctx.request_time,
                    Some(format!("plugin:{}@{}", ctx.plugin, ctx.version)),
                    who.map(|w| w.caller()).unwrap_or_default(),
                )
                .await
                .map_err(host_error)?;
            Ok(())
        })
    }

    fn position(&self) -> Result<host::Position, host::HostError> {
        let state = self.engine.state();
        let p = state.position.ok_or_else(|| unknown("position"))?;
        Ok(position(&p, state.axes.as_ref()))
    }

    fn state_json(&self) -> String {
        serde_json::to_string(&self.engine.state()).unwrap_or_else(|_| "{}".into())
    }

    fn tool(&self) -> Result<host::Pose, host::HostError> {
        let state = self.engine.state();
        state
            .tool
            .as_ref()
            .map(frame_pose)
            .ok_or_else(|| unknown("tool"))
    }

    fn base(&self) -> Result<host::Pose, host::HostError> {
        let state = self.engine.state();
        state
            .base
            .as_ref()
            .map(frame_pose)
            .ok_or_else(|| unknown("base"))
    }

    fn open_path<'a>(
        &'a self,
        ctx: &'a host::CallContext,
    ) -> host::BoxFuture<'a, Result<u64, host::HostError>> {
        Box::pin(async move {
            let who = ctx
                .caller
                .clone()
                .and_then(|c| c.downcast::<RequestContext>().ok());
            if let Some(who) = &who {
                drop(self.control.check(&who.principal).map_err(host_error)?);
            }
            tracing::info!(plugin = %ctx.plugin, version = %ctx.version, "plugin opens a path");
            let job = self
                .engine
                .submit_from(
                    Operation::Path(crate::engine::PathOptions::default()),
                    None,
                    Some(format!("plugin:{}@{}", ctx.plugin, ctx.version)),
                    who.map(|w| w.caller()).unwrap_or_default(),
                )
                .await
                .map_err(host_error)?;
            Ok(job.id)
        })
    }

    fn append<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        path: u64,
        motions: Vec<host::Motion>,
    ) -> host::BoxFuture<'a, Result<u32, host::HostError>> {
        let requests: Vec<MotionRequest> = motions.into_iter().map(motion_request).collect();
        Box::pin(self.append_requests(ctx, path, requests))
    }

    fn finish_path<'a>(
        &'a self,
        ctx: &'a host::CallContext,
        path: u64,
    ) -> host::BoxFuture<'a, Result<host::Done, host::HostError>> {
        Box::pin(async move {
            match self
                .engine
                .append(path, Vec::new(), true, std::time::Duration::from_secs(10))
                .await
            {
                // Ended already: its job says how.
                Ok(_) => {}
                Err(e) if e.code == ErrorCode::PathClosed => {}
                Err(e) => return Err(host_error(e)),
            }
            let job = self
                .engine
                .wait(path, ctx.request_time)
                .await
                .map_err(host_error)?;
            if let Some(e) = job.error.clone() {
                return Err(host_error(e));
            }
            let state = self.engine.state();
            let at = job
                .position
                .or(state.position)
                .ok_or_else(|| unknown("position"))?;
            Ok(host::Done {
                completed: u32::try_from(job.completed).unwrap_or(u32::MAX),
                position: position(&at, job.axes.as_ref().or(state.axes.as_ref())),
            })
        })
    }

    fn cancel_path<'a>(&'a self, path: u64) -> host::BoxFuture<'a, Result<(), host::HostError>> {
        Box::pin(async move {
            self.engine.cancel(path).await.map_err(host_error)?;
            Ok(())
        })
    }

    fn abandon_path(&self, path: u64) {
        let engine = self.engine.clone();
        match tokio::runtime::Handle::try_current() {
            Ok(rt) => {
                rt.spawn(async move {
                    let _ = engine
                        .append(path, Vec::new(), true, std::time::Duration::from_secs(10))
                        .await;
                });
            }
            Err(_) => tracing::warn!(
                path,
                "no runtime to close the plugin's path; the controller ends it when idle"
            ),
        }
    }
}
