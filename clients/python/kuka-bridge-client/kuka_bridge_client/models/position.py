from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="Position")



@_attrs_define
class Position:
    """ TCP position in the base frame with Status and Turn (a KUKA E6POS without external axes).

        Example:
            {'x': 200.0, 'y': 0.0, 'z': 70.0, 'a': 0.0, 'b': 180.0, 'c': 0.0, 's': 2, 't': 2}

        Attributes:
            a (float): A in degrees.
            b (float): B in degrees.
            c (float): C in degrees.
            s (int): Status bits.
            t (int): Turn bits.
            x (float): X in mm.
            y (float): Y in mm.
            z (float): Z in mm.
     """

    a: float
    b: float
    c: float
    s: int
    t: int
    x: float
    y: float
    z: float
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        a = self.a

        b = self.b

        c = self.c

        s = self.s

        t = self.t

        x = self.x

        y = self.y

        z = self.z


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "a": a,
            "b": b,
            "c": c,
            "s": s,
            "t": t,
            "x": x,
            "y": y,
            "z": z,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        a = d.pop("a")

        b = d.pop("b")

        c = d.pop("c")

        s = d.pop("s")

        t = d.pop("t")

        x = d.pop("x")

        y = d.pop("y")

        z = d.pop("z")

        position = cls(
            a=a,
            b=b,
            c=c,
            s=s,
            t=t,
            x=x,
            y=y,
            z=z,
        )


        position.additional_properties = d
        return position

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
