//! The service's domain error: a stable machine-readable code, a human
//! sentence and, for motion errors, the axis and the motion index. The API
//! turns it into `application/problem+json`.

use serde::Serialize;
use utoipa::ToSchema;

/// Stable error codes (part of the API contract; never renamed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum ErrorCode {
    /// The request is malformed or a value is out of range.
    InvalidInput,
    /// A target lies outside the configured workspace box.
    WorkspaceViolation,
    /// A speed exceeds the configured cap.
    SpeedLimit,
    /// The target or a path point is out of the robot's reach.
    Unreachable,
    /// An axis would pass its software limit switch.
    SoftwareLimit,
    /// The path passes a singularity.
    Singularity,
    /// No heartbeat from the controller.
    ControllerOffline,
    /// The command file is locked by another process.
    ChannelLocked,
    /// The controller did not answer in time.
    Timeout,
    /// The controller is in an error state (acknowledge with reset).
    ControllerError,
    /// The controller was still busy with an earlier command.
    ControllerBusy,
    /// The job was cancelled (stop or cancel).
    Cancelled,
    /// No such resource.
    NotFound,
    /// The endpoint exists but not with this HTTP method.
    MethodNotAllowed,
    /// The request body is larger than the service accepts.
    PayloadTooLarge,
    /// The request body is not `application/json`.
    UnsupportedMediaType,
    /// Too many jobs waiting.
    QueueFull,
    /// An uploaded KRL program does not parse or fails its checks (with its line).
    InvalidProgram,
    /// An uploaded KRL program uses what the simulated controller cannot execute (with its line).
    ProgramUnsupported,
    /// An uploaded KRL program failed while running (with its line).
    ProgramFailed,
    /// No program folder is configured, so programs cannot be run.
    ProgramsUnavailable,
    /// A plugin is not a valid component of the bridge's world, or its description is invalid.
    PluginInvalid,
    /// A plugin used up its CPU budget or its request time.
    PluginTimeout,
    /// A plugin tried to use more memory than allowed.
    PluginMemory,
    /// A plugin crashed (panic, abort, out-of-bounds access...).
    PluginTrap,
    /// A plugin answered with an invalid status or a body that is not JSON.
    PluginBadResponse,
    /// Plugins are switched off in the configuration.
    PluginsUnavailable,
    /// No valid token was presented (auth is on).
    Unauthenticated,
    /// The token's role does not allow this operation.
    Forbidden,
    /// Another client holds control of the robot.
    ControlHeld,
    /// Too many failed authentication attempts from this address.
    TooManyAttempts,
    /// Too many requests are in progress; retry after `Retry-After`.
    Overloaded,
    /// The request took longer than `server.max_request_ms`.
    RequestTimeout,
    /// The controller answered something this service does not understand.
    ProtocolError,
    /// A bug or an unexpected I/O failure.
    Internal,
    /// The service cannot write the channel folder or its data folder
    /// (disk full, permissions); nothing was sent.
    StorageUnavailable,
    /// The controller accepted the command but lost it (it restarted, or
    /// went idle without a result); `completed` says how far it got.
    CommandLost,
    /// The job belonged to an earlier run of the service, or is no longer kept.
    Gone,
    /// The service is shutting down: it takes no new jobs (stop and reads still work).
    ShuttingDown,
    /// The path is no longer open: it was closed, ended, failed or stopped.
    PathClosed,
    /// The path's buffer stayed full for the request's wait; retry after `Retry-After`.
    PathFull,
    /// The output is not on the site's list of outputs clients may write (`[io] outputs`).
    OutputNotAllowed,
    /// No digital input or output has this name in the site's `[io]` configuration.
    UnknownSignal,
    /// The signal lies outside the I/O the controller reports (its state file's window).
    SignalNotReported,
    /// A `wait_input` action's input did not come within its timeout; the robot stands where it waited.
    InputTimeout,
    /// The variable is not on the site's list of variables clients may write (`[variables] writable`).
    VariableNotAllowed,
    /// The controller has no such variable (KUKAVARPROXY refused to read or write it).
    UnknownVariable,
    /// No KUKAVARPROXY server is configured or reachable.
    VariablesUnavailable,
}

impl ErrorCode {
    /// HTTP status for this code.
    pub fn http_status(self) -> u16 {
        match self {
            ErrorCode::InvalidInput
            | ErrorCode::WorkspaceViolation
            | ErrorCode::SpeedLimit
            | ErrorCode::Unreachable
            | ErrorCode::SoftwareLimit
            | ErrorCode::Singularity
            | ErrorCode::InvalidProgram
            | ErrorCode::ProgramUnsupported => 422,
            ErrorCode::ProgramFailed => 409,
            ErrorCode::ProgramsUnavailable | ErrorCode::PluginsUnavailable => 503,
            ErrorCode::PluginInvalid => 422,
            ErrorCode::PluginTimeout => 504,
            ErrorCode::PluginMemory | ErrorCode::PluginTrap | ErrorCode::PluginBadResponse => 502,
            ErrorCode::ControllerOffline | ErrorCode::ChannelLocked | ErrorCode::QueueFull => 503,
            ErrorCode::Timeout => 504,
            ErrorCode::ControllerError | ErrorCode::ControllerBusy | ErrorCode::Cancelled => 409,
            ErrorCode::NotFound => 404,
            ErrorCode::MethodNotAllowed => 405,
            ErrorCode::PayloadTooLarge => 413,
            ErrorCode::UnsupportedMediaType => 415,
            ErrorCode::Unauthenticated => 401,
            ErrorCode::Forbidden => 403,
            ErrorCode::ControlHeld => 409,
            ErrorCode::TooManyAttempts => 429,
            ErrorCode::Overloaded => 503,
            ErrorCode::RequestTimeout => 504,
            ErrorCode::ProtocolError => 502,
            ErrorCode::Internal => 500,
            ErrorCode::StorageUnavailable | ErrorCode::ShuttingDown => 503,
            ErrorCode::CommandLost => 502,
            ErrorCode::Gone => 410,
            ErrorCode::PathClosed => 409,
            ErrorCode::PathFull => 503,
            ErrorCode::OutputNotAllowed => 403,
            ErrorCode::UnknownSignal => 404,
            ErrorCode::SignalNotReported => 422,
            ErrorCode::InputTimeout => 422,
            ErrorCode::VariableNotAllowed => 403,
            ErrorCode::UnknownVariable => 404,
            ErrorCode::VariablesUnavailable => 503,
        }
    }

    /// Short title for problem+json.
    pub fn title(self) -> &'static str {
        match self {
            ErrorCode::InvalidInput => "Invalid input",
            ErrorCode::WorkspaceViolation => "Outside the workspace",
            ErrorCode::SpeedLimit => "Speed above the configured cap",
            ErrorCode::Unreachable => "Target unreachable",
            ErrorCode::SoftwareLimit => "Software limit switch",
            ErrorCode::Singularity => "Singularity",
            ErrorCode::ControllerOffline => "Controller offline",
            ErrorCode::ChannelLocked => "Channel locked",
            ErrorCode::Timeout => "Controller timeout",
            ErrorCode::ControllerError => "Controller in error state",
            ErrorCode::ControllerBusy => "Controller busy",
            ErrorCode::Cancelled => "Cancelled",
            ErrorCode::NotFound => "Not found",
            ErrorCode::MethodNotAllowed => "Method not allowed",
            ErrorCode::PayloadTooLarge => "Payload too large",
            ErrorCode::UnsupportedMediaType => "Unsupported media type",
            ErrorCode::QueueFull => "Queue full",
            ErrorCode::InvalidProgram => "Invalid KRL program",
            ErrorCode::ProgramUnsupported => "KRL not supported by the simulator",
            ErrorCode::ProgramFailed => "KRL program failed",
            ErrorCode::ProgramsUnavailable => "Programs unavailable",
            ErrorCode::PluginInvalid => "Invalid plugin",
            ErrorCode::PluginTimeout => "Plugin timeout",
            ErrorCode::PluginMemory => "Plugin out of memory",
            ErrorCode::PluginTrap => "Plugin crashed",
            ErrorCode::PluginBadResponse => "Invalid plugin response",
            ErrorCode::PluginsUnavailable => "Plugins unavailable",
            ErrorCode::Unauthenticated => "Unauthenticated",
            ErrorCode::Forbidden => "Forbidden",
            ErrorCode::ControlHeld => "Control held by another client",
            ErrorCode::TooManyAttempts => "Too many failed attempts",
            ErrorCode::Overloaded => "Overloaded",
            ErrorCode::RequestTimeout => "Request timeout",
            ErrorCode::ProtocolError => "Protocol error",
            ErrorCode::Internal => "Internal error",
            ErrorCode::StorageUnavailable => "Storage unavailable",
            ErrorCode::CommandLost => "Command lost by the controller",
            ErrorCode::Gone => "Gone",
            ErrorCode::ShuttingDown => "Shutting down",
            ErrorCode::PathClosed => "Path closed",
            ErrorCode::PathFull => "Path buffer full",
            ErrorCode::OutputNotAllowed => "Output not allowed",
            ErrorCode::UnknownSignal => "Unknown signal",
            ErrorCode::SignalNotReported => "Signal not reported",
            ErrorCode::InputTimeout => "Input timeout",
            ErrorCode::VariableNotAllowed => "Variable not allowed",
            ErrorCode::UnknownVariable => "Unknown variable",
            ErrorCode::VariablesUnavailable => "Variables unavailable",
        }
    }

    /// The code as it appears in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            ErrorCode::InvalidInput => "invalid_input",
            ErrorCode::WorkspaceViolation => "workspace_violation",
            ErrorCode::SpeedLimit => "speed_limit",
            ErrorCode::Unreachable => "unreachable",
            ErrorCode::SoftwareLimit => "software_limit",
            ErrorCode::Singularity => "singularity",
            ErrorCode::ControllerOffline => "controller_offline",
            ErrorCode::ChannelLocked => "channel_locked",
            ErrorCode::Timeout => "timeout",
            ErrorCode::ControllerError => "controller_error",
            ErrorCode::ControllerBusy => "controller_busy",
            ErrorCode::Cancelled => "cancelled",
            ErrorCode::NotFound => "not_found",
            ErrorCode::MethodNotAllowed => "method_not_allowed",
            ErrorCode::PayloadTooLarge => "payload_too_large",
            ErrorCode::UnsupportedMediaType => "unsupported_media_type",
            ErrorCode::QueueFull => "queue_full",
            ErrorCode::InvalidProgram => "invalid_program",
            ErrorCode::ProgramUnsupported => "program_unsupported",
            ErrorCode::ProgramFailed => "program_failed",
            ErrorCode::ProgramsUnavailable => "programs_unavailable",
            ErrorCode::PluginInvalid => "plugin_invalid",
            ErrorCode::PluginTimeout => "plugin_timeout",
            ErrorCode::PluginMemory => "plugin_memory",
            ErrorCode::PluginTrap => "plugin_trap",
            ErrorCode::PluginBadResponse => "plugin_bad_response",
            ErrorCode::PluginsUnavailable => "plugins_unavailable",
            ErrorCode::Unauthenticated => "unauthenticated",
            ErrorCode::Forbidden => "forbidden",
            ErrorCode::ControlHeld => "control_held",
            ErrorCode::TooManyAttempts => "too_many_attempts",
            ErrorCode::Overloaded => "overloaded",
            ErrorCode::RequestTimeout => "request_timeout",
            ErrorCode::ProtocolError => "protocol_error",
            ErrorCode::Internal => "internal",
            ErrorCode::StorageUnavailable => "storage_unavailable",
            ErrorCode::CommandLost => "command_lost",
            ErrorCode::Gone => "gone",
            ErrorCode::ShuttingDown => "shutting_down",
            ErrorCode::PathClosed => "path_closed",
            ErrorCode::PathFull => "path_full",
            ErrorCode::OutputNotAllowed => "output_not_allowed",
            ErrorCode::UnknownSignal => "unknown_signal",
            ErrorCode::SignalNotReported => "signal_not_reported",
            ErrorCode::InputTimeout => "input_timeout",
            ErrorCode::VariableNotAllowed => "variable_not_allowed",
            ErrorCode::UnknownVariable => "unknown_variable",
            ErrorCode::VariablesUnavailable => "variables_unavailable",
        }
    }
}

/// An error with its code, sentence and context.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema, thiserror::Error)]
#[schema(example = json!({"code": "timeout", "detail": "the controller did not pick up command 12 within 2000 ms"}))]
#[error("{code:?}: {detail}")]
pub struct BridgeError {
    /// Stable code.
    pub code: ErrorCode,
    /// Human sentence.
    pub detail: String,
    /// 1-based axis for software-limit errors.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis: Option<u8>,
    /// 0-based index of the motion in the batch that failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motion: Option<usize>,
    /// For KRL program errors: the file (`src` or `dat`) the line is in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// For KRL program errors: the 1-based line in the uploaded file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<u32>,
}

impl BridgeError {
    /// An error with a code and a sentence.
    pub fn new(code: ErrorCode, detail: impl Into<String>) -> Self {
        BridgeError {
            code,
            detail: detail.into(),
            axis: None,
            motion: None,
            file: None,
            line: None,
        }
    }

    /// Shorthand for `invalid_input`.
    pub fn invalid(detail: impl Into<String>) -> Self {
        Self::new(ErrorCode::InvalidInput, detail)
    }

    /// Adds the motion index.
    pub fn at_motion(mut self, index: usize) -> Self {
        self.motion = Some(index);
        self
    }

    /// Names the line of an uploaded program the error is on.
    pub fn at_line(mut self, file: &str, line: u32) -> Self {
        if line > 0 {
            self.file = Some(file.to_string());
            self.line = Some(line);
        }
        self
    }

    /// Adds the axis.
    pub fn on_axis(mut self, axis: u8) -> Self {
        if axis > 0 {
            self.axis = Some(axis);
        }
        self
    }
}

/// Result alias for the service library.
pub type Result<T, E = BridgeError> = std::result::Result<T, E>;

/// A number from a request as an error sentence shows it: compact for very
/// large or very small values (`1e300`, not 301 digits).
pub fn shown(v: f64) -> String {
    if v.is_finite() && v != 0.0 && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// An error and its causes as one sentence ("a: b: c"), for places that
/// must turn an error chain into a `detail`.
pub fn chain(e: &dyn std::error::Error) -> String {
    let mut out = e.to_string();
    let mut cur = e.source();
    while let Some(s) = cur {
        out.push_str(": ");
        out.push_str(&s.to_string());
        cur = s.source();
    }
    out
}
