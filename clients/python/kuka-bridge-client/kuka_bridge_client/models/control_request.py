from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset






T = TypeVar("T", bound="ControlRequest")



@_attrs_define
class ControlRequest:
    """ Taking control.

        Example:
            {'take_over': False}

        Attributes:
            take_over (bool | Unset): Admins only: take control even if another client holds it.
     """

    take_over: bool | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        take_over = self.take_over


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if take_over is not UNSET:
            field_dict["take_over"] = take_over

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        take_over = d.pop("take_over", UNSET)

        control_request = cls(
            take_over=take_over,
        )

        return control_request

