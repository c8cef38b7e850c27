from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="PathProgress")



@_attrs_define
class PathProgress:
    """ A path's progress, in its job record.

        Example:
            {'appended': 120, 'sent': 80, 'closed': False}

        Attributes:
            appended (int): Motions appended by clients (checked and accepted).
            closed (bool): The path was closed: it ends when its last motion has run.
            sent (int): Motions the controller has stored (the rest wait in the service).
     """

    appended: int
    closed: bool
    sent: int
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        appended = self.appended

        closed = self.closed

        sent = self.sent


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "appended": appended,
            "closed": closed,
            "sent": sent,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        appended = d.pop("appended")

        closed = d.pop("closed")

        sent = d.pop("sent")

        path_progress = cls(
            appended=appended,
            closed=closed,
            sent=sent,
        )


        path_progress.additional_properties = d
        return path_progress

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
