from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.role import Role






T = TypeVar("T", bound="NewToken")



@_attrs_define
class NewToken:
    """ A new token.

        Example:
            {'name': 'line-3-pc', 'role': 'operator'}

        Attributes:
            name (str): Unique name: 1–64 letters, digits, `.`, `_`, `-`, `@`.
            role (Role): A token's role; each includes the ones below it.
     """

    name: str
    role: Role





    def to_dict(self) -> dict[str, Any]:
        name = self.name

        role = self.role.value


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "name": name,
            "role": role,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        name = d.pop("name")

        role = Role(d.pop("role"))




        new_token = cls(
            name=name,
            role=role,
        )

        return new_token

