from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast






T = TypeVar("T", bound="AnalogWindow")



@_attrs_define
class AnalogWindow:
    """ The analog channels the controller reported in its last state file
    (`$ANIN`/`$ANOUT[1..=8]`, normalised −1..=1).

        Attributes:
            inputs (list[float]): `$ANIN[1..=8]`.
            outputs (list[float]): `$ANOUT[1..=8]`.
     """

    inputs: list[float]
    outputs: list[float]
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        inputs = self.inputs



        outputs = self.outputs




        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "inputs": inputs,
            "outputs": outputs,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        inputs = cast(list[float], d.pop("inputs"))


        outputs = cast(list[float], d.pop("outputs"))


        analog_window = cls(
            inputs=inputs,
            outputs=outputs,
        )


        analog_window.additional_properties = d
        return analog_window

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
