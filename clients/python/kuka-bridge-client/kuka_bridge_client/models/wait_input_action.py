from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.wait_input_action_type import WaitInputActionType
from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="WaitInputAction")



@_attrs_define
class WaitInputAction:
    """ An I/O action: the robot stops exactly at the end of the motion
    before it and waits until the input has `value` (KRL `WAIT FOR`).
    If it does not within `timeout_ms`, the job fails with
    `input_timeout` and the robot stands there; nothing after it runs.

        Example:
            {'type': 'wait_input', 'signal': 'part_present', 'value': True, 'timeout_ms': 2000}

        Attributes:
            signal (int | str): A digital signal in a request: its number or its configured name.
            timeout_ms (int): Longest wait in ms, 1..=600000 (nothing waits for ever).
            type_ (WaitInputActionType):
            value (bool | Unset): The value waited for (default true).
     """

    signal: int | str
    timeout_ms: int
    type_: WaitInputActionType
    value: bool | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        signal: int | str
        signal = self.signal

        timeout_ms = self.timeout_ms

        type_ = self.type_.value

        value = self.value


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "signal": signal,
            "timeout_ms": timeout_ms,
            "type": type_,
        })
        if value is not UNSET:
            field_dict["value"] = value

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_signal(data: object) -> int | str:
            return cast(int | str, data)

        signal = _parse_signal(d.pop("signal"))


        timeout_ms = d.pop("timeout_ms")

        type_ = WaitInputActionType(d.pop("type"))




        value = d.pop("value", UNSET)

        wait_input_action = cls(
            signal=signal,
            timeout_ms=timeout_ms,
            type_=type_,
            value=value,
        )


        wait_input_action.additional_properties = d
        return wait_input_action

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
