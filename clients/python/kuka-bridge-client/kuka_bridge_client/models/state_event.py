from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.state_event_type import StateEventType
from typing import cast

if TYPE_CHECKING:
  from ..models.robot_state import RobotState





T = TypeVar("T", bound="StateEvent")



@_attrs_define
class StateEvent:
    """ The robot state changed (at most at the heartbeat rate).

        Attributes:
            data (RobotState): The robot's state as the service knows it. Example: {'connection': 'online', 'controller':
                {'status': 'idle', 'mode': 'EXT', 'error': None, 'simulated': True, 'override_pct': 100.0, 'heartbeat_seq': 184,
                'heartbeat_age_ms': 28, 'last_cid': 3}, 'busy': False, 'current_job': None, 'queue_length': 0, 'position': {'x':
                355.0, 'y': 0.0, 'z': 625.0, 'a': 0.0, 'b': 90.0, 'c': 0.0, 's': 2, 't': 2}, 'axes': {'a1': 0.0, 'a2': -90.0,
                'a3': 90.0, 'a4': 0.0, 'a5': 0.0, 'a6': 0.0}, 'tool': {'x': 0.0, 'y': 0.0, 'z': 0.0, 'a': 0.0, 'b': 0.0, 'c':
                0.0}, 'base': {'x': 0.0, 'y': 0.0, 'z': 0.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}, 'speed': {'override_pct': 100.0,
                'ptp_velocity_pct': 20.0, 'ptp_acceleration_pct': 100.0, 'cp_velocity_m_s': 0.25, 'cp_acceleration_pct': 100.0},
                'model': 'kr3_r540', 'degraded': []}.
            type_ (StateEventType):
     """

    data: RobotState
    type_: StateEventType
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.robot_state import RobotState # noqa: PLC0415
        data = self.data.to_dict()

        type_ = self.type_.value


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "data": data,
            "type": type_,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.robot_state import RobotState # noqa: PLC0415
        d = dict(src_dict)
        data = RobotState.from_dict(d.pop("data"))




        type_ = StateEventType(d.pop("type"))




        state_event = cls(
            data=data,
            type_=type_,
        )


        state_event.additional_properties = d
        return state_event

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
