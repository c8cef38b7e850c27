from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast






T = TypeVar("T", bound="IoWindow")



@_attrs_define
class IoWindow:
    """ The I/O the controller reported in its last state file.

        Attributes:
            base (int): Index of the first signal (`inputs[0]` is `$IN[base]`).
            inputs (list[bool]): `$IN[base..base+30]`.
            outputs (list[bool]): `$OUT[base..base+30]`.
     """

    base: int
    inputs: list[bool]
    outputs: list[bool]
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        base = self.base

        inputs = self.inputs



        outputs = self.outputs




        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "base": base,
            "inputs": inputs,
            "outputs": outputs,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        base = d.pop("base")

        inputs = cast(list[bool], d.pop("inputs"))


        outputs = cast(list[bool], d.pop("outputs"))


        io_window = cls(
            base=base,
            inputs=inputs,
            outputs=outputs,
        )


        io_window.additional_properties = d
        return io_window

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
