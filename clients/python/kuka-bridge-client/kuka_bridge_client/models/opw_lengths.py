from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="OpwLengths")



@_attrs_define
class OpwLengths:
    """ OPW lengths in mm (rs-opw-kinematics' names).

        Attributes:
            a1 (float): A1 axis to A2 axis, horizontally.
            a2 (float): Elbow offset (A3 to forearm), negative on KUKA arms.
            b (float): Lateral offset.
            c1 (float): Floor to A2 axis.
            c2 (float): Upper arm (A2 to A3).
            c3 (float): Forearm (A3 to wrist point).
            c4 (float): Wrist point to flange.
     """

    a1: float
    a2: float
    b: float
    c1: float
    c2: float
    c3: float
    c4: float
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        a1 = self.a1

        a2 = self.a2

        b = self.b

        c1 = self.c1

        c2 = self.c2

        c3 = self.c3

        c4 = self.c4


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "a1": a1,
            "a2": a2,
            "b": b,
            "c1": c1,
            "c2": c2,
            "c3": c3,
            "c4": c4,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        a1 = d.pop("a1")

        a2 = d.pop("a2")

        b = d.pop("b")

        c1 = d.pop("c1")

        c2 = d.pop("c2")

        c3 = d.pop("c3")

        c4 = d.pop("c4")

        opw_lengths = cls(
            a1=a1,
            a2=a2,
            b=b,
            c1=c1,
            c2=c2,
            c3=c3,
            c4=c4,
        )


        opw_lengths.additional_properties = d
        return opw_lengths

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
