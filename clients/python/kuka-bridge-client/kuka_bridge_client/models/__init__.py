""" Contains all the data models used in inputs/outputs """

from .alarm_event import AlarmEvent
from .alarm_event_type import AlarmEventType
from .analog_change import AnalogChange
from .analog_config import AnalogConfig
from .analog_event import AnalogEvent
from .analog_event_type import AnalogEventType
from .analog_input_value import AnalogInputValue
from .analog_signal import AnalogSignal
from .analog_view import AnalogView
from .analog_window import AnalogWindow
from .analog_write import AnalogWrite
from .append_body import AppendBody
from .append_outcome import AppendOutcome
from .audit_record import AuditRecord
from .aux_point import AuxPoint
from .axes_spec import AxesSpec
from .axis_angles import AxisAngles
from .axis_motion import AxisMotion
from .axis_motion_type import AxisMotionType
from .bridge_error import BridgeError
from .cartesian_frame import CartesianFrame
from .circ_motion import CircMotion
from .circ_motion_type import CircMotionType
from .configuration import Configuration
from .configuration_source import ConfigurationSource
from .connection import Connection
from .control_request import ControlRequest
from .control_state import ControlState
from .controller_info import ControllerInfo
from .controller_safety import ControllerSafety
from .created_token import CreatedToken
from .dwell_action import DwellAction
from .dwell_action_type import DwellActionType
from .error_body import ErrorBody
from .error_code_info import ErrorCodeInfo
from .health import Health
from .input_value import InputValue
from .io_change import IoChange
from .io_config import IoConfig
from .io_event import IoEvent
from .io_event_type import IoEventType
from .io_kind import IoKind
from .io_view import IoView
from .io_window import IoWindow
from .job import Job
from .job_event import JobEvent
from .job_event_type import JobEventType
from .job_plan import JobPlan
from .job_state import JobState
from .keep_out import KeepOut
from .lease import Lease
from .limits_info import LimitsInfo
from .lin_motion import LinMotion
from .lin_motion_type import LinMotionType
from .model_info import ModelInfo
from .motion_batch import MotionBatch
from .new_token import NewToken
from .opw_lengths import OpwLengths
from .output_write import OutputWrite
from .path_create import PathCreate
from .path_progress import PathProgress
from .plan_event import PlanEvent
from .plan_event_type import PlanEventType
from .planned_motion import PlannedMotion
from .plugin_info import PluginInfo
from .plugin_route_info import PluginRouteInfo
from .position import Position
from .position_report import PositionReport
from .position_source import PositionSource
from .principal import Principal
from .problem_details import ProblemDetails
from .program_info import ProgramInfo
from .program_upload import ProgramUpload
from .ptp_configuration import PtpConfiguration
from .ptp_motion import PtpMotion
from .ptp_motion_type import PtpMotionType
from .recent_event import RecentEvent
from .recent_event_data import RecentEventData
from .robot_state import RobotState
from .role import Role
from .run_request import RunRequest
from .safety_change import SafetyChange
from .schema_violation import SchemaViolation
from .scirc_motion import ScircMotion
from .scirc_motion_type import ScircMotionType
from .set_output_action import SetOutputAction
from .set_output_action_type import SetOutputActionType
from .signal import Signal
from .signal_config import SignalConfig
from .sim_snapshot import SimSnapshot
from .slin_motion import SlinMotion
from .slin_motion_type import SlinMotionType
from .speed_settings import SpeedSettings
from .speed_update import SpeedUpdate
from .spl_motion import SplMotion
from .spl_motion_type import SplMotionType
from .sptp_axis_motion import SptpAxisMotion
from .sptp_axis_motion_type import SptpAxisMotionType
from .sptp_motion import SptpMotion
from .sptp_motion_type import SptpMotionType
from .state_event import StateEvent
from .state_event_type import StateEventType
from .stopped import Stopped
from .stored_program import StoredProgram
from .table_entry import TableEntry
from .target_spec import TargetSpec
from .thesis_problem import ThesisProblem
from .thesis_response import ThesisResponse
from .token_info import TokenInfo
from .trace_sample import TraceSample
from .upload_form import UploadForm
from .variable import Variable
from .variable_write import VariableWrite
from .wait_input_action import WaitInputAction
from .wait_input_action_type import WaitInputActionType
from .workspace_box import WorkspaceBox
from .workspace_info import WorkspaceInfo

__all__ = (
    "AlarmEvent",
    "AlarmEventType",
    "AnalogChange",
    "AnalogConfig",
    "AnalogEvent",
    "AnalogEventType",
    "AnalogInputValue",
    "AnalogSignal",
    "AnalogView",
    "AnalogWindow",
    "AnalogWrite",
    "AppendBody",
    "AppendOutcome",
    "AuditRecord",
    "AuxPoint",
    "AxesSpec",
    "AxisAngles",
    "AxisMotion",
    "AxisMotionType",
    "BridgeError",
    "CartesianFrame",
    "CircMotion",
    "CircMotionType",
    "Configuration",
    "ConfigurationSource",
    "Connection",
    "ControllerInfo",
    "ControllerSafety",
    "ControlRequest",
    "ControlState",
    "CreatedToken",
    "DwellAction",
    "DwellActionType",
    "ErrorBody",
    "ErrorCodeInfo",
    "Health",
    "InputValue",
    "IoChange",
    "IoConfig",
    "IoEvent",
    "IoEventType",
    "IoKind",
    "IoView",
    "IoWindow",
    "Job",
    "JobEvent",
    "JobEventType",
    "JobPlan",
    "JobState",
    "KeepOut",
    "Lease",
    "LimitsInfo",
    "LinMotion",
    "LinMotionType",
    "ModelInfo",
    "MotionBatch",
    "NewToken",
    "OpwLengths",
    "OutputWrite",
    "PathCreate",
    "PathProgress",
    "PlanEvent",
    "PlanEventType",
    "PlannedMotion",
    "PluginInfo",
    "PluginRouteInfo",
    "Position",
    "PositionReport",
    "PositionSource",
    "Principal",
    "ProblemDetails",
    "ProgramInfo",
    "ProgramUpload",
    "PtpConfiguration",
    "PtpMotion",
    "PtpMotionType",
    "RecentEvent",
    "RecentEventData",
    "RobotState",
    "Role",
    "RunRequest",
    "SafetyChange",
    "SchemaViolation",
    "ScircMotion",
    "ScircMotionType",
    "SetOutputAction",
    "SetOutputActionType",
    "Signal",
    "SignalConfig",
    "SimSnapshot",
    "SlinMotion",
    "SlinMotionType",
    "SpeedSettings",
    "SpeedUpdate",
    "SplMotion",
    "SplMotionType",
    "SptpAxisMotion",
    "SptpAxisMotionType",
    "SptpMotion",
    "SptpMotionType",
    "StateEvent",
    "StateEventType",
    "Stopped",
    "StoredProgram",
    "TableEntry",
    "TargetSpec",
    "ThesisProblem",
    "ThesisResponse",
    "TokenInfo",
    "TraceSample",
    "UploadForm",
    "Variable",
    "VariableWrite",
    "WaitInputAction",
    "WaitInputActionType",
    "WorkspaceBox",
    "WorkspaceInfo",
)
