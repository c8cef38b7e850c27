from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.sptp_axis_motion_type import SptpAxisMotionType
from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.axes_spec import AxesSpec





T = TypeVar("T", bound="SptpAxisMotion")



@_attrs_define
class SptpAxisMotion:
    """ SPTP to axis angles (KRL `SPTP` to an E6AXIS, as `SPTP XHOME`):
    the spline family's axis PTP; stops exactly at its end, like
    `ptp_axes`, and follows its rules within a batch.

        Example:
            {'type': 'sptp_axes', 'axes': {'a1': 0, 'a2': -90, 'a3': 90, 'a4': 0, 'a5': 0, 'a6': 0}}

        Attributes:
            axes (AxesSpec): Axis angles; omitted axes keep their value. Example: {'a1': 30.0, 'a5': 45.0}.
            type_ (SptpAxisMotionType):
            acceleration_pct (float | None | Unset): % of max acceleration.
            approx_mm (float | None | Unset): Approximation distance in mm (not used: an SPTP stops exactly).
            relative (bool | Unset): Add to the start instead of replacing.
            velocity_pct (float | None | Unset): % of max axis speed.
     """

    axes: AxesSpec
    type_: SptpAxisMotionType
    acceleration_pct: float | None | Unset = UNSET
    approx_mm: float | None | Unset = UNSET
    relative: bool | Unset = UNSET
    velocity_pct: float | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.axes_spec import AxesSpec # noqa: PLC0415
        axes = self.axes.to_dict()

        type_ = self.type_.value

        acceleration_pct: float | None | Unset
        if isinstance(self.acceleration_pct, Unset):
            acceleration_pct = UNSET
        else:
            acceleration_pct = self.acceleration_pct

        approx_mm: float | None | Unset
        if isinstance(self.approx_mm, Unset):
            approx_mm = UNSET
        else:
            approx_mm = self.approx_mm

        relative = self.relative

        velocity_pct: float | None | Unset
        if isinstance(self.velocity_pct, Unset):
            velocity_pct = UNSET
        else:
            velocity_pct = self.velocity_pct


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "axes": axes,
            "type": type_,
        })
        if acceleration_pct is not UNSET:
            field_dict["acceleration_pct"] = acceleration_pct
        if approx_mm is not UNSET:
            field_dict["approx_mm"] = approx_mm
        if relative is not UNSET:
            field_dict["relative"] = relative
        if velocity_pct is not UNSET:
            field_dict["velocity_pct"] = velocity_pct

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.axes_spec import AxesSpec # noqa: PLC0415
        d = dict(src_dict)
        axes = AxesSpec.from_dict(d.pop("axes"))




        type_ = SptpAxisMotionType(d.pop("type"))




        def _parse_acceleration_pct(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        acceleration_pct = _parse_acceleration_pct(d.pop("acceleration_pct", UNSET))


        def _parse_approx_mm(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        approx_mm = _parse_approx_mm(d.pop("approx_mm", UNSET))


        relative = d.pop("relative", UNSET)

        def _parse_velocity_pct(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        velocity_pct = _parse_velocity_pct(d.pop("velocity_pct", UNSET))


        sptp_axis_motion = cls(
            axes=axes,
            type_=type_,
            acceleration_pct=acceleration_pct,
            approx_mm=approx_mm,
            relative=relative,
            velocity_pct=velocity_pct,
        )


        sptp_axis_motion.additional_properties = d
        return sptp_axis_motion

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
