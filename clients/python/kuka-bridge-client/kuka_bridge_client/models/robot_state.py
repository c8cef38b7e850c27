from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.connection import Connection
from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.analog_window import AnalogWindow
  from ..models.axis_angles import AxisAngles
  from ..models.bridge_error import BridgeError
  from ..models.cartesian_frame import CartesianFrame
  from ..models.controller_info import ControllerInfo
  from ..models.io_window import IoWindow
  from ..models.position import Position
  from ..models.speed_settings import SpeedSettings





T = TypeVar("T", bound="RobotState")



@_attrs_define
class RobotState:
    """ The robot's state as the service knows it.

        Example:
            {'connection': 'online', 'controller': {'status': 'idle', 'mode': 'EXT', 'error': None, 'simulated': True,
                'override_pct': 100.0, 'heartbeat_seq': 184, 'heartbeat_age_ms': 28, 'last_cid': 3}, 'busy': False,
                'current_job': None, 'queue_length': 0, 'position': {'x': 355.0, 'y': 0.0, 'z': 625.0, 'a': 0.0, 'b': 90.0, 'c':
                0.0, 's': 2, 't': 2}, 'axes': {'a1': 0.0, 'a2': -90.0, 'a3': 90.0, 'a4': 0.0, 'a5': 0.0, 'a6': 0.0}, 'tool':
                {'x': 0.0, 'y': 0.0, 'z': 0.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}, 'base': {'x': 0.0, 'y': 0.0, 'z': 0.0, 'a': 0.0,
                'b': 0.0, 'c': 0.0}, 'speed': {'override_pct': 100.0, 'ptp_velocity_pct': 20.0, 'ptp_acceleration_pct': 100.0,
                'cp_velocity_m_s': 0.25, 'cp_acceleration_pct': 100.0}, 'model': 'kr3_r540', 'degraded': []}

        Attributes:
            busy (bool): A job is on the controller.
            connection (Connection): Connection to the controller.
            controller (ControllerInfo): What the controller reports about itself.
            degraded (list[BridgeError]): Why commands cannot be sent now; empty when they can. Each entry has
                a stable `code` (`controller_offline`, `channel_locked`,
                `storage_unavailable`, `controller_error`, `protocol_error`,
                `shutting_down`) and a sentence. `/health` says `degraded` while
                this is not empty.
            queue_length (int): Jobs waiting.
            speed (SpeedSettings): The current default speeds (settable through the API). Example: {'override_pct': 100.0,
                'ptp_velocity_pct': 20.0, 'ptp_acceleration_pct': 100.0, 'cp_velocity_m_s': 0.25, 'cp_acceleration_pct': 100.0}.
            analog (AnalogWindow | None | Unset):
            axes (AxisAngles | None | Unset):
            base (CartesianFrame | None | Unset):
            current_job (int | None | Unset):
            io (IoWindow | None | Unset):
            model (None | str | Unset): Robot model used for checks (None: checks off).
            position (None | Position | Unset):
            tool (CartesianFrame | None | Unset):
     """

    busy: bool
    connection: Connection
    controller: ControllerInfo
    degraded: list[BridgeError]
    queue_length: int
    speed: SpeedSettings
    analog: AnalogWindow | None | Unset = UNSET
    axes: AxisAngles | None | Unset = UNSET
    base: CartesianFrame | None | Unset = UNSET
    current_job: int | None | Unset = UNSET
    io: IoWindow | None | Unset = UNSET
    model: None | str | Unset = UNSET
    position: None | Position | Unset = UNSET
    tool: CartesianFrame | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.analog_window import AnalogWindow # noqa: PLC0415
        from ..models.axis_angles import AxisAngles # noqa: PLC0415
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        from ..models.controller_info import ControllerInfo # noqa: PLC0415
        from ..models.io_window import IoWindow # noqa: PLC0415
        from ..models.position import Position # noqa: PLC0415
        from ..models.speed_settings import SpeedSettings # noqa: PLC0415
        busy = self.busy

        connection = self.connection.value

        controller = self.controller.to_dict()

        degraded = []
        for degraded_item_data in self.degraded:
            degraded_item = degraded_item_data.to_dict()
            degraded.append(degraded_item)



        queue_length = self.queue_length

        speed = self.speed.to_dict()

        analog: dict[str, Any] | None | Unset
        if isinstance(self.analog, Unset):
            analog = UNSET
        elif isinstance(self.analog, AnalogWindow):
            analog = self.analog.to_dict()
        else:
            analog = self.analog

        axes: dict[str, Any] | None | Unset
        if isinstance(self.axes, Unset):
            axes = UNSET
        elif isinstance(self.axes, AxisAngles):
            axes = self.axes.to_dict()
        else:
            axes = self.axes

        base: dict[str, Any] | None | Unset
        if isinstance(self.base, Unset):
            base = UNSET
        elif isinstance(self.base, CartesianFrame):
            base = self.base.to_dict()
        else:
            base = self.base

        current_job: int | None | Unset
        if isinstance(self.current_job, Unset):
            current_job = UNSET
        else:
            current_job = self.current_job

        io: dict[str, Any] | None | Unset
        if isinstance(self.io, Unset):
            io = UNSET
        elif isinstance(self.io, IoWindow):
            io = self.io.to_dict()
        else:
            io = self.io

        model: None | str | Unset
        if isinstance(self.model, Unset):
            model = UNSET
        else:
            model = self.model

        position: dict[str, Any] | None | Unset
        if isinstance(self.position, Unset):
            position = UNSET
        elif isinstance(self.position, Position):
            position = self.position.to_dict()
        else:
            position = self.position

        tool: dict[str, Any] | None | Unset
        if isinstance(self.tool, Unset):
            tool = UNSET
        elif isinstance(self.tool, CartesianFrame):
            tool = self.tool.to_dict()
        else:
            tool = self.tool


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "busy": busy,
            "connection": connection,
            "controller": controller,
            "degraded": degraded,
            "queue_length": queue_length,
            "speed": speed,
        })
        if analog is not UNSET:
            field_dict["analog"] = analog
        if axes is not UNSET:
            field_dict["axes"] = axes
        if base is not UNSET:
            field_dict["base"] = base
        if current_job is not UNSET:
            field_dict["current_job"] = current_job
        if io is not UNSET:
            field_dict["io"] = io
        if model is not UNSET:
            field_dict["model"] = model
        if position is not UNSET:
            field_dict["position"] = position
        if tool is not UNSET:
            field_dict["tool"] = tool

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.analog_window import AnalogWindow # noqa: PLC0415
        from ..models.axis_angles import AxisAngles # noqa: PLC0415
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        from ..models.controller_info import ControllerInfo # noqa: PLC0415
        from ..models.io_window import IoWindow # noqa: PLC0415
        from ..models.position import Position # noqa: PLC0415
        from ..models.speed_settings import SpeedSettings # noqa: PLC0415
        d = dict(src_dict)
        busy = d.pop("busy")

        connection = Connection(d.pop("connection"))




        controller = ControllerInfo.from_dict(d.pop("controller"))




        degraded = []
        _degraded = d.pop("degraded")
        for degraded_item_data in (_degraded):
            degraded_item = BridgeError.from_dict(degraded_item_data)



            degraded.append(degraded_item)


        queue_length = d.pop("queue_length")

        speed = SpeedSettings.from_dict(d.pop("speed"))




        def _parse_analog(data: object) -> AnalogWindow | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                analog_type_0 = AnalogWindow.from_dict(data)



                return analog_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(AnalogWindow | None | Unset, data)

        analog = _parse_analog(d.pop("analog", UNSET))


        def _parse_axes(data: object) -> AxisAngles | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                axes_type_0 = AxisAngles.from_dict(data)



                return axes_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(AxisAngles | None | Unset, data)

        axes = _parse_axes(d.pop("axes", UNSET))


        def _parse_base(data: object) -> CartesianFrame | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                base_type_0 = CartesianFrame.from_dict(data)



                return base_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(CartesianFrame | None | Unset, data)

        base = _parse_base(d.pop("base", UNSET))


        def _parse_current_job(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        current_job = _parse_current_job(d.pop("current_job", UNSET))


        def _parse_io(data: object) -> IoWindow | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                io_type_0 = IoWindow.from_dict(data)



                return io_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(IoWindow | None | Unset, data)

        io = _parse_io(d.pop("io", UNSET))


        def _parse_model(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        model = _parse_model(d.pop("model", UNSET))


        def _parse_position(data: object) -> None | Position | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                position_type_0 = Position.from_dict(data)



                return position_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(None | Position | Unset, data)

        position = _parse_position(d.pop("position", UNSET))


        def _parse_tool(data: object) -> CartesianFrame | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                tool_type_0 = CartesianFrame.from_dict(data)



                return tool_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(CartesianFrame | None | Unset, data)

        tool = _parse_tool(d.pop("tool", UNSET))


        robot_state = cls(
            busy=busy,
            connection=connection,
            controller=controller,
            degraded=degraded,
            queue_length=queue_length,
            speed=speed,
            analog=analog,
            axes=axes,
            base=base,
            current_job=current_job,
            io=io,
            model=model,
            position=position,
            tool=tool,
        )


        robot_state.additional_properties = d
        return robot_state

    @property
    def additional_keys(self) -> list[str]:
        return list(self.additional_properties.keys())

    def __getitem__(self, key: str) -> Any:
        return self.additional_properties[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self.additional_properties[key] = value

    def __delitem__(self, key: str) -> None:
        del self.additional_properties[key]

    def __contains__(self, key: str) -> bool:
        return key in self.additional_properties
