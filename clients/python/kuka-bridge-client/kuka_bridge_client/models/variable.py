from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="Variable")



@_attrs_define
class Variable:
    """ A variable's value as the API answers it.

        Example:
            {'name': '$OV_PRO', 'type': 'INT', 'value': 100, 'krl': '100'}

        Attributes:
            krl (str): The value as KRL text, as the controller showed it.
            name (str): The name as asked.
            type_ (str): `INT`, `REAL`, `BOOL`, `CHAR`, `ENUM`, or a structure's type
                (`E6POS`, `FRAME`, ...; `STRUC` when the controller did not name it).
            value (Any): The value: a number, a boolean, a string, `{"enum": "T1"}`, or an
                object of a structure's components.
     """

    krl: str
    name: str
    type_: str
    value: Any
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        krl = self.krl

        name = self.name

        type_ = self.type_

        value = self.value


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "krl": krl,
            "name": name,
            "type": type_,
            "value": value,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        krl = d.pop("krl")

        name = d.pop("name")

        type_ = d.pop("type")

        value = d.pop("value")

        variable = cls(
            krl=krl,
            name=name,
            type_=type_,
            value=value,
        )


        variable.additional_properties = d
        return variable

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
