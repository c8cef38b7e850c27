from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="ErrorCodeInfo")



@_attrs_define
class ErrorCodeInfo:
    """ One code of the catalogue.

        Example:
            {'title': 'Software limit switch', 'status': 422, 'thesis_statuscode': 21, 'summary': 'an axis would pass its
                software limit switch', 'type': '/errors#software_limit'}

        Attributes:
            status (int): The HTTP status a problem with this code has.
            summary (str): What it means, in a sentence (the catalogue's summary table).
            thesis_statuscode (int): The `statuscode` the thesis endpoints (`/krl/*`) answer for it.
            title (str): The problem's `title` for this code.
            type_ (str): The problem's `type` for this code: its section of the HTML page.
     """

    status: int
    summary: str
    thesis_statuscode: int
    title: str
    type_: str
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        status = self.status

        summary = self.summary

        thesis_statuscode = self.thesis_statuscode

        title = self.title

        type_ = self.type_


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "status": status,
            "summary": summary,
            "thesis_statuscode": thesis_statuscode,
            "title": title,
            "type": type_,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        status = d.pop("status")

        summary = d.pop("summary")

        thesis_statuscode = d.pop("thesis_statuscode")

        title = d.pop("title")

        type_ = d.pop("type")

        error_code_info = cls(
            status=status,
            summary=summary,
            thesis_statuscode=thesis_statuscode,
            title=title,
            type_=type_,
        )


        error_code_info.additional_properties = d
        return error_code_info

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
