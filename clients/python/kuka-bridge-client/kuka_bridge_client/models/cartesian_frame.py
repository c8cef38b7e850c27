from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="CartesianFrame")



@_attrs_define
class CartesianFrame:
    """ A Cartesian frame in mm and degrees (A, B, C about Z, Y, X).

        Example:
            {'x': 0.0, 'y': 0.0, 'z': 100.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}

        Attributes:
            a (float): A (about Z) in degrees.
            b (float): B (about Y) in degrees.
            c (float): C (about X) in degrees.
            x (float): X in mm.
            y (float): Y in mm.
            z (float): Z in mm.
     """

    a: float
    b: float
    c: float
    x: float
    y: float
    z: float





    def to_dict(self) -> dict[str, Any]:
        a = self.a

        b = self.b

        c = self.c

        x = self.x

        y = self.y

        z = self.z


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "a": a,
            "b": b,
            "c": c,
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

        x = d.pop("x")

        y = d.pop("y")

        z = d.pop("z")

        cartesian_frame = cls(
            a=a,
            b=b,
            c=c,
            x=x,
            y=y,
            z=z,
        )

        return cartesian_frame

