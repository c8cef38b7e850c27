from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast






T = TypeVar("T", bound="WorkspaceBox")



@_attrs_define
class WorkspaceBox:
    """ An axis-aligned box in the base frame (mm).

        Attributes:
            x (list[float]): [min, max] X.
            y (list[float]): [min, max] Y.
            z (list[float]): [min, max] Z.
     """

    x: list[float]
    y: list[float]
    z: list[float]





    def to_dict(self) -> dict[str, Any]:
        x = self.x



        y = self.y



        z = self.z




        field_dict: dict[str, Any] = {}

        field_dict.update({
            "x": x,
            "y": y,
            "z": z,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        x = cast(list[float], d.pop("x"))


        y = cast(list[float], d.pop("y"))


        z = cast(list[float], d.pop("z"))


        workspace_box = cls(
            x=x,
            y=y,
            z=z,
        )

        return workspace_box

