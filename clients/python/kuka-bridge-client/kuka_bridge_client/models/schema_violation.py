from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="SchemaViolation")



@_attrs_define
class SchemaViolation:
    """ One place where a request does not match a JSON schema.

        Attributes:
            keyword (str): The schema keyword that failed (`type`, `additionalProperties`, …).
            message (str): What is wrong, as a sentence.
            pointer (str): JSON Pointer to the offending value (`/x`; empty for the whole body).
     """

    keyword: str
    message: str
    pointer: str
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        keyword = self.keyword

        message = self.message

        pointer = self.pointer


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "keyword": keyword,
            "message": message,
            "pointer": pointer,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        keyword = d.pop("keyword")

        message = d.pop("message")

        pointer = d.pop("pointer")

        schema_violation = cls(
            keyword=keyword,
            message=message,
            pointer=pointer,
        )


        schema_violation.additional_properties = d
        return schema_violation

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
