from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="SpeedUpdate")



@_attrs_define
class SpeedUpdate:
    """ Partial update of the speed settings; omitted fields keep their value.

        Example:
            {'override_pct': 50}

        Attributes:
            cp_acceleration_pct (float | None | Unset): Default LIN/CIRC acceleration in %.
            cp_velocity_m_s (float | None | Unset): Default LIN/CIRC velocity in m/s.
            override_pct (float | None | Unset): Program override in %.
            ptp_acceleration_pct (float | None | Unset): Default PTP acceleration in %.
            ptp_velocity_pct (float | None | Unset): Default PTP velocity in %.
     """

    cp_acceleration_pct: float | None | Unset = UNSET
    cp_velocity_m_s: float | None | Unset = UNSET
    override_pct: float | None | Unset = UNSET
    ptp_acceleration_pct: float | None | Unset = UNSET
    ptp_velocity_pct: float | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        cp_acceleration_pct: float | None | Unset
        if isinstance(self.cp_acceleration_pct, Unset):
            cp_acceleration_pct = UNSET
        else:
            cp_acceleration_pct = self.cp_acceleration_pct

        cp_velocity_m_s: float | None | Unset
        if isinstance(self.cp_velocity_m_s, Unset):
            cp_velocity_m_s = UNSET
        else:
            cp_velocity_m_s = self.cp_velocity_m_s

        override_pct: float | None | Unset
        if isinstance(self.override_pct, Unset):
            override_pct = UNSET
        else:
            override_pct = self.override_pct

        ptp_acceleration_pct: float | None | Unset
        if isinstance(self.ptp_acceleration_pct, Unset):
            ptp_acceleration_pct = UNSET
        else:
            ptp_acceleration_pct = self.ptp_acceleration_pct

        ptp_velocity_pct: float | None | Unset
        if isinstance(self.ptp_velocity_pct, Unset):
            ptp_velocity_pct = UNSET
        else:
            ptp_velocity_pct = self.ptp_velocity_pct


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if cp_acceleration_pct is not UNSET:
            field_dict["cp_acceleration_pct"] = cp_acceleration_pct
        if cp_velocity_m_s is not UNSET:
            field_dict["cp_velocity_m_s"] = cp_velocity_m_s
        if override_pct is not UNSET:
            field_dict["override_pct"] = override_pct
        if ptp_acceleration_pct is not UNSET:
            field_dict["ptp_acceleration_pct"] = ptp_acceleration_pct
        if ptp_velocity_pct is not UNSET:
            field_dict["ptp_velocity_pct"] = ptp_velocity_pct

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_cp_acceleration_pct(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        cp_acceleration_pct = _parse_cp_acceleration_pct(d.pop("cp_acceleration_pct", UNSET))


        def _parse_cp_velocity_m_s(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        cp_velocity_m_s = _parse_cp_velocity_m_s(d.pop("cp_velocity_m_s", UNSET))


        def _parse_override_pct(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        override_pct = _parse_override_pct(d.pop("override_pct", UNSET))


        def _parse_ptp_acceleration_pct(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        ptp_acceleration_pct = _parse_ptp_acceleration_pct(d.pop("ptp_acceleration_pct", UNSET))


        def _parse_ptp_velocity_pct(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        ptp_velocity_pct = _parse_ptp_velocity_pct(d.pop("ptp_velocity_pct", UNSET))


        speed_update = cls(
            cp_acceleration_pct=cp_acceleration_pct,
            cp_velocity_m_s=cp_velocity_m_s,
            override_pct=override_pct,
            ptp_acceleration_pct=ptp_acceleration_pct,
            ptp_velocity_pct=ptp_velocity_pct,
        )

        return speed_update

