//! What the controller's answers mean to a client: result and state
//! codes mapped to the API's error codes and sentences.

use super::*;

pub(super) fn result_error(r: &ResultRecord) -> Option<BridgeError> {
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
        ResultCode::InputTimeout => (
            ErrorCode::InputTimeout,
            format!(
                "the input of wait_input {} did not come within its timeout; the robot stands where it waited and nothing after it ran",
                r.completed
            ),
        ),
        ResultCode::PathClosed => (
            ErrorCode::PathClosed,
            "the path is no longer open on the controller (it ended, failed or was stopped)".into(),
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
pub(super) fn program_result_error(e: BridgeError, r: &ResultRecord, program: &str) -> BridgeError {
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

/// A controller error's detail completed with what the controller's
/// safety state says (an emergency stop, the operator safety, the drives,
/// a stop message), so that a client whose job failed learns why and
/// what clears it. Other errors are returned as they are.
///
/// `simulated` (the state file says so): the teach pendant is the
/// simulator's API, and the detail names it.
pub(super) fn explain_safety(
    mut e: BridgeError,
    safety: Option<&kuka_protocol::SafetyState>,
    simulated: bool,
) -> BridgeError {
    let Some(s) = safety else { return e };
    if e.code != ErrorCode::ControllerError {
        return e;
    }
    let mut why = Vec::new();
    if !s.alarm_stop {
        why.push("an emergency stop is pressed");
    }
    if !s.user_safety {
        why.push("the operator safety (fence, enabling device) is open");
    }
    if !s.drives_ready {
        why.push("the drives are off");
    }
    if s.stop_message {
        why.push("a stop message waits for acknowledgement");
    }
    if why.is_empty() {
        return e;
    }
    let pendant = if simulated {
        "acknowledge the messages (the simulated controller: POST /api/v1/sim/acknowledge, which also switches the drives on and starts kb_main)"
    } else {
        "acknowledge the messages on the teach pendant, switch the drives on"
    };
    let clear = if circuit_open(s) {
        format!("release it, {pendant}, then POST /api/v1/reset")
    } else {
        format!("{pendant}, then POST /api/v1/reset")
    };
    e.detail = format!("{}: {}; {clear}", e.detail, why.join(", "));
    e
}

pub(super) fn state_error(s: &StateFile) -> Option<BridgeError> {
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
        explain_safety(e, s.safety.as_ref(), s.simulated)
    })
}

pub(super) fn mode_name(m: OperatingMode) -> &'static str {
    match m {
        OperatingMode::T1 => "T1",
        OperatingMode::T2 => "T2",
        OperatingMode::Aut => "AUT",
        OperatingMode::Ext => "EXT",
        OperatingMode::Unknown => "unknown",
    }
}

/// An emergency stop is pressed or the operator safety is open: no reset
/// can make the controller ready.
pub(super) fn circuit_open(s: &kuka_protocol::SafetyState) -> bool {
    !s.alarm_stop || !s.user_safety
}
