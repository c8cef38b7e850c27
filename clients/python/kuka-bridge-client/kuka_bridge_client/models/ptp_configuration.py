from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.configuration_source import ConfigurationSource






T = TypeVar("T", bound="PtpConfiguration")



@_attrs_define
class PtpConfiguration:
    """ The arm configuration (Status and Turn) one Cartesian PTP got.

        Example:
            {'motion': 0, 's': 6, 't': 27, 'chosen': 'auto'}

        Attributes:
            chosen (ConfigurationSource): Who chose a PTP's configuration.
            motion (int): 0-based index of the motion in the batch.
            s (int): Status.
            t (int): Turn.
     """

    chosen: ConfigurationSource
    motion: int
    s: int
    t: int
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        chosen = self.chosen.value

        motion = self.motion

        s = self.s

        t = self.t


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "chosen": chosen,
            "motion": motion,
            "s": s,
            "t": t,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        chosen = ConfigurationSource(d.pop("chosen"))




        motion = d.pop("motion")

        s = d.pop("s")

        t = d.pop("t")

        ptp_configuration = cls(
            chosen=chosen,
            motion=motion,
            s=s,
            t=t,
        )


        ptp_configuration.additional_properties = d
        return ptp_configuration

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
