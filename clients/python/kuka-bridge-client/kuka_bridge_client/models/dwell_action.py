from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.dwell_action_type import DwellActionType






T = TypeVar("T", bound="DwellAction")



@_attrs_define
class DwellAction:
    """ The robot stops exactly at the end of the motion before it and
    stands for `ms` (KRL `WAIT SEC`).

        Example:
            {'type': 'dwell', 'ms': 500}

        Attributes:
            ms (int): Standstill in ms, 0..=600000.
            type_ (DwellActionType):
     """

    ms: int
    type_: DwellActionType
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        ms = self.ms

        type_ = self.type_.value


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "ms": ms,
            "type": type_,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        ms = d.pop("ms")

        type_ = DwellActionType(d.pop("type"))




        dwell_action = cls(
            ms=ms,
            type_=type_,
        )


        dwell_action.additional_properties = d
        return dwell_action

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
