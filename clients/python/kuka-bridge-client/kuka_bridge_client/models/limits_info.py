from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="LimitsInfo")



@_attrs_define
class LimitsInfo:
    """ A plugin's limits, as listed.

        Attributes:
            cpu_time_ms (int): Guest time per request, ms.
            max_motions (int): Motions per request.
            memory_mib (int): Largest linear memory, MiB.
            request_timeout_ms (int): Wall time per request, motions included, ms.
     """

    cpu_time_ms: int
    max_motions: int
    memory_mib: int
    request_timeout_ms: int
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        cpu_time_ms = self.cpu_time_ms

        max_motions = self.max_motions

        memory_mib = self.memory_mib

        request_timeout_ms = self.request_timeout_ms


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "cpu_time_ms": cpu_time_ms,
            "max_motions": max_motions,
            "memory_mib": memory_mib,
            "request_timeout_ms": request_timeout_ms,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        cpu_time_ms = d.pop("cpu_time_ms")

        max_motions = d.pop("max_motions")

        memory_mib = d.pop("memory_mib")

        request_timeout_ms = d.pop("request_timeout_ms")

        limits_info = cls(
            cpu_time_ms=cpu_time_ms,
            max_motions=max_motions,
            memory_mib=memory_mib,
            request_timeout_ms=request_timeout_ms,
        )


        limits_info.additional_properties = d
        return limits_info

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
