from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.slin_motion_type import SlinMotionType
from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.target_spec import TargetSpec





T = TypeVar("T", bound="SlinMotion")



@_attrs_define
class SlinMotion:
    """ SLIN: a straight line of the spline family (KRL `SLIN`). Blends
    (`C_SPL`) only into spline motions (`slin`, `scirc`, `spl`); before
    a `ptp`/`lin`/`circ` the robot stops exactly, as on a KRC.

        Example:
            {'type': 'slin', 'target': {'x': 250, 'y': 100}, 'velocity_m_s': 0.1, 'approx_mm': 5}

        Attributes:
            target (TargetSpec): A Cartesian target; omitted components keep their current value (the
                previous motion's target inside a batch). Example: {'x': 200.0, 'y': 0.0, 'z': 70.0, 'a': 0.0, 'b': 180.0, 'c':
                0.0}.
            type_ (SlinMotionType):
            acceleration_pct (float | None | Unset): % of max acceleration.
            approx_mm (float | None | Unset): Approximation distance in mm (C_SPL).
            relative (bool | Unset): Add to the start instead of replacing.
            velocity_m_s (float | None | Unset): TCP speed in m/s.
     """

    target: TargetSpec
    type_: SlinMotionType
    acceleration_pct: float | None | Unset = UNSET
    approx_mm: float | None | Unset = UNSET
    relative: bool | Unset = UNSET
    velocity_m_s: float | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.target_spec import TargetSpec # noqa: PLC0415
        target = self.target.to_dict()

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

        velocity_m_s: float | None | Unset
        if isinstance(self.velocity_m_s, Unset):
            velocity_m_s = UNSET
        else:
            velocity_m_s = self.velocity_m_s


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "target": target,
            "type": type_,
        })
        if acceleration_pct is not UNSET:
            field_dict["acceleration_pct"] = acceleration_pct
        if approx_mm is not UNSET:
            field_dict["approx_mm"] = approx_mm
        if relative is not UNSET:
            field_dict["relative"] = relative
        if velocity_m_s is not UNSET:
            field_dict["velocity_m_s"] = velocity_m_s

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.target_spec import TargetSpec # noqa: PLC0415
        d = dict(src_dict)
        target = TargetSpec.from_dict(d.pop("target"))




        type_ = SlinMotionType(d.pop("type"))




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

        def _parse_velocity_m_s(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        velocity_m_s = _parse_velocity_m_s(d.pop("velocity_m_s", UNSET))


        slin_motion = cls(
            target=target,
            type_=type_,
            acceleration_pct=acceleration_pct,
            approx_mm=approx_mm,
            relative=relative,
            velocity_m_s=velocity_m_s,
        )


        slin_motion.additional_properties = d
        return slin_motion

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
