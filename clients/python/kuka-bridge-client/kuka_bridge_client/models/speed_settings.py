from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="SpeedSettings")



@_attrs_define
class SpeedSettings:
    """ The current default speeds (settable through the API).

        Example:
            {'override_pct': 100.0, 'ptp_velocity_pct': 20.0, 'ptp_acceleration_pct': 100.0, 'cp_velocity_m_s': 0.25,
                'cp_acceleration_pct': 100.0}

        Attributes:
            cp_acceleration_pct (float): Default LIN/CIRC acceleration in %.
            cp_velocity_m_s (float): Default LIN/CIRC velocity in m/s.
            override_pct (float): Program override in % ($OV_PRO).
            ptp_acceleration_pct (float): Default PTP acceleration in %.
            ptp_velocity_pct (float): Default PTP velocity in %.
     """

    cp_acceleration_pct: float
    cp_velocity_m_s: float
    override_pct: float
    ptp_acceleration_pct: float
    ptp_velocity_pct: float
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        cp_acceleration_pct = self.cp_acceleration_pct

        cp_velocity_m_s = self.cp_velocity_m_s

        override_pct = self.override_pct

        ptp_acceleration_pct = self.ptp_acceleration_pct

        ptp_velocity_pct = self.ptp_velocity_pct


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "cp_acceleration_pct": cp_acceleration_pct,
            "cp_velocity_m_s": cp_velocity_m_s,
            "override_pct": override_pct,
            "ptp_acceleration_pct": ptp_acceleration_pct,
            "ptp_velocity_pct": ptp_velocity_pct,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        cp_acceleration_pct = d.pop("cp_acceleration_pct")

        cp_velocity_m_s = d.pop("cp_velocity_m_s")

        override_pct = d.pop("override_pct")

        ptp_acceleration_pct = d.pop("ptp_acceleration_pct")

        ptp_velocity_pct = d.pop("ptp_velocity_pct")

        speed_settings = cls(
            cp_acceleration_pct=cp_acceleration_pct,
            cp_velocity_m_s=cp_velocity_m_s,
            override_pct=override_pct,
            ptp_acceleration_pct=ptp_acceleration_pct,
            ptp_velocity_pct=ptp_velocity_pct,
        )


        speed_settings.additional_properties = d
        return speed_settings

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
