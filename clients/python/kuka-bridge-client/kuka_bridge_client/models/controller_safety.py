from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="ControllerSafety")



@_attrs_define
class ControllerSafety:
    """ The controller's safety and program state (the KRL system variables
    `$PERI_RDY`, `$USER_SAF`, `$ALARM_STOP`, `$STOPMESS`, `$PRO_STATE1`).

        Attributes:
            drives_ready (bool): `$PERI_RDY`: the drives are switched on.
            emergency_stop (bool): An emergency stop is pressed (`$ALARM_STOP` FALSE).
            program (str): The robot program (`$PRO_STATE1`): `free`, `reset`, `active`,
                `stopped` or `ended`.
            stop_message (bool): `$STOPMESS`: a stop message waits for acknowledgement.
            user_safety (bool): `$USER_SAF`: the operator safety (fence, enabling device) is closed.
     """

    drives_ready: bool
    emergency_stop: bool
    program: str
    stop_message: bool
    user_safety: bool
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        drives_ready = self.drives_ready

        emergency_stop = self.emergency_stop

        program = self.program

        stop_message = self.stop_message

        user_safety = self.user_safety


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "drives_ready": drives_ready,
            "emergency_stop": emergency_stop,
            "program": program,
            "stop_message": stop_message,
            "user_safety": user_safety,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        drives_ready = d.pop("drives_ready")

        emergency_stop = d.pop("emergency_stop")

        program = d.pop("program")

        stop_message = d.pop("stop_message")

        user_safety = d.pop("user_safety")

        controller_safety = cls(
            drives_ready=drives_ready,
            emergency_stop=emergency_stop,
            program=program,
            stop_message=stop_message,
            user_safety=user_safety,
        )


        controller_safety.additional_properties = d
        return controller_safety

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
