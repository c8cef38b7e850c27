from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="AxisAngles")



@_attrs_define
class AxisAngles:
    """ Axis angles A1..A6 in degrees.

        Example:
            {'a1': 0.0, 'a2': -90.0, 'a3': 90.0, 'a4': 0.0, 'a5': 0.0, 'a6': 0.0}

        Attributes:
            a1 (float): A1.
            a2 (float): A2.
            a3 (float): A3.
            a4 (float): A4.
            a5 (float): A5.
            a6 (float): A6.
     """

    a1: float
    a2: float
    a3: float
    a4: float
    a5: float
    a6: float
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        a1 = self.a1

        a2 = self.a2

        a3 = self.a3

        a4 = self.a4

        a5 = self.a5

        a6 = self.a6


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "a1": a1,
            "a2": a2,
            "a3": a3,
            "a4": a4,
            "a5": a5,
            "a6": a6,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        a1 = d.pop("a1")

        a2 = d.pop("a2")

        a3 = d.pop("a3")

        a4 = d.pop("a4")

        a5 = d.pop("a5")

        a6 = d.pop("a6")

        axis_angles = cls(
            a1=a1,
            a2=a2,
            a3=a3,
            a4=a4,
            a5=a5,
            a6=a6,
        )


        axis_angles.additional_properties = d
        return axis_angles

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
