from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="VariableWrite")



@_attrs_define
class VariableWrite:
    """ The body of a variable write.

        Example:
            {'value': 50}

        Attributes:
            value (Any): The new value: a number, a boolean, a string (printable ASCII
                without `"`, at most 128), `{"enum": "NAME"}`, or an object of
                components (`{"X": 0, "Y": 0, "Z": 120}` sets those of a FRAME).
     """

    value: Any





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

        variable_write = cls(
            value=value,
        )

        return variable_write

