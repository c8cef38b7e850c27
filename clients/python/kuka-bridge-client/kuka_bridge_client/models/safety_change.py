from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="SafetyChange")



@_attrs_define
class SafetyChange:
    """ A change of the simulated cell's safety circuit.

        Example:
            {'emergency_stop': True}

        Attributes:
            emergency_stop (bool | None | Unset): Press (`true`) or release (`false`) the emergency stop
                (`$ALARM_STOP`); absent: unchanged.
            user_safety (bool | None | Unset): Close (`true`) or open (`false`) the operator safety: the fence
                door, the enabling device (`$USER_SAF`); absent: unchanged.
     """

    emergency_stop: bool | None | Unset = UNSET
    user_safety: bool | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        emergency_stop: bool | None | Unset
        if isinstance(self.emergency_stop, Unset):
            emergency_stop = UNSET
        else:
            emergency_stop = self.emergency_stop

        user_safety: bool | None | Unset
        if isinstance(self.user_safety, Unset):
            user_safety = UNSET
        else:
            user_safety = self.user_safety


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if emergency_stop is not UNSET:
            field_dict["emergency_stop"] = emergency_stop
        if user_safety is not UNSET:
            field_dict["user_safety"] = user_safety

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_emergency_stop(data: object) -> bool | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(bool | None | Unset, data)

        emergency_stop = _parse_emergency_stop(d.pop("emergency_stop", UNSET))


        def _parse_user_safety(data: object) -> bool | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(bool | None | Unset, data)

        user_safety = _parse_user_safety(d.pop("user_safety", UNSET))


        safety_change = cls(
            emergency_stop=emergency_stop,
            user_safety=user_safety,
        )

        return safety_change

