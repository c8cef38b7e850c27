from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast






T = TypeVar("T", bound="KeepOut")



@_attrs_define
class KeepOut:
    """ A named box the TCP must not enter (base frame, mm).

        Attributes:
            name (str): Shown in errors and on the dashboard, e.g. `fixture`.
            x (list[float]): [min, max] X.
            y (list[float]): [min, max] Y.
            z (list[float]): [min, max] Z.
     """

    name: str
    x: list[float]
    y: list[float]
    z: list[float]





    def to_dict(self) -> dict[str, Any]:
        name = self.name

        x = self.x



        y = self.y



        z = self.z




        field_dict: dict[str, Any] = {}

        field_dict.update({
            "name": name,
            "x": x,
            "y": y,
            "z": z,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        name = d.pop("name")

        x = cast(list[float], d.pop("x"))


        y = cast(list[float], d.pop("y"))


        z = cast(list[float], d.pop("z"))


        keep_out = cls(
            name=name,
            x=x,
            y=y,
            z=z,
        )

        return keep_out

