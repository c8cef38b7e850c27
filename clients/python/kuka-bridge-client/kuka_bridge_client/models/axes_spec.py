from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="AxesSpec")



@_attrs_define
class AxesSpec:
    """ Axis angles; omitted axes keep their value.

        Example:
            {'a1': 30.0, 'a5': 45.0}

        Attributes:
            a1 (float | None | Unset): A1 in degrees.
            a2 (float | None | Unset): A2 in degrees.
            a3 (float | None | Unset): A3 in degrees.
            a4 (float | None | Unset): A4 in degrees.
            a5 (float | None | Unset): A5 in degrees.
            a6 (float | None | Unset): A6 in degrees.
     """

    a1: float | None | Unset = UNSET
    a2: float | None | Unset = UNSET
    a3: float | None | Unset = UNSET
    a4: float | None | Unset = UNSET
    a5: float | None | Unset = UNSET
    a6: float | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        a1: float | None | Unset
        if isinstance(self.a1, Unset):
            a1 = UNSET
        else:
            a1 = self.a1

        a2: float | None | Unset
        if isinstance(self.a2, Unset):
            a2 = UNSET
        else:
            a2 = self.a2

        a3: float | None | Unset
        if isinstance(self.a3, Unset):
            a3 = UNSET
        else:
            a3 = self.a3

        a4: float | None | Unset
        if isinstance(self.a4, Unset):
            a4 = UNSET
        else:
            a4 = self.a4

        a5: float | None | Unset
        if isinstance(self.a5, Unset):
            a5 = UNSET
        else:
            a5 = self.a5

        a6: float | None | Unset
        if isinstance(self.a6, Unset):
            a6 = UNSET
        else:
            a6 = self.a6


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if a1 is not UNSET:
            field_dict["a1"] = a1
        if a2 is not UNSET:
            field_dict["a2"] = a2
        if a3 is not UNSET:
            field_dict["a3"] = a3
        if a4 is not UNSET:
            field_dict["a4"] = a4
        if a5 is not UNSET:
            field_dict["a5"] = a5
        if a6 is not UNSET:
            field_dict["a6"] = a6

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_a1(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        a1 = _parse_a1(d.pop("a1", UNSET))


        def _parse_a2(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        a2 = _parse_a2(d.pop("a2", UNSET))


        def _parse_a3(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        a3 = _parse_a3(d.pop("a3", UNSET))


        def _parse_a4(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        a4 = _parse_a4(d.pop("a4", UNSET))


        def _parse_a5(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        a5 = _parse_a5(d.pop("a5", UNSET))


        def _parse_a6(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        a6 = _parse_a6(d.pop("a6", UNSET))


        axes_spec = cls(
            a1=a1,
            a2=a2,
            a3=a3,
            a4=a4,
            a5=a5,
            a6=a6,
        )

        return axes_spec

