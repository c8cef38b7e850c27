from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="AnalogWrite")



@_attrs_define
class AnalogWrite:
    """ The body of an analog output write.

        Example:
            {'value': 0.5}

        Attributes:
            value (float): Normalised value, −1..=1; the protocol carries 3 decimals.
     """

    value: float





    def to_dict(self) -> dict[str, Any]:
        value = self.value


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "value": value,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        value = d.pop("value")

        analog_write = cls(
            value=value,
        )

        return analog_write

