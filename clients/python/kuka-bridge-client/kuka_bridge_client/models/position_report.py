from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.position_source import PositionSource
from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.axis_angles import AxisAngles
  from ..models.position import Position





T = TypeVar("T", bound="PositionReport")



@_attrs_define
class PositionReport:
    """ Position with axis angles.

        Example:
            {'position': {'x': 355.0, 'y': 0.0, 'z': 625.0, 'a': 0.0, 'b': 90.0, 'c': 0.0, 's': 2, 't': 2}, 'axes': {'a1':
                0.0, 'a2': -90.0, 'a3': 90.0, 'a4': 0.0, 'a5': 0.0, 'a6': 0.0}, 'source': 'controller', 'age_ms': 0}

        Attributes:
            age_ms (int): For `live`: milliseconds since the service read the state file that
                carried the position (the controller writes it every heartbeat,
                100 ms in the shipped KRL program). 0 for `controller`.
            position (Position): TCP position in the base frame with Status and Turn (a KUKA E6POS without external axes).
                Example: {'x': 200.0, 'y': 0.0, 'z': 70.0, 'a': 0.0, 'b': 180.0, 'c': 0.0, 's': 2, 't': 2}.
            source (PositionSource): Where a reported position comes from.
            axes (AxisAngles | None | Unset):
     """

    age_ms: int
    position: Position
    source: PositionSource
    axes: AxisAngles | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.axis_angles import AxisAngles # noqa: PLC0415
        from ..models.position import Position # noqa: PLC0415
        age_ms = self.age_ms

        position = self.position.to_dict()

        source = self.source.value

        axes: dict[str, Any] | None | Unset
        if isinstance(self.axes, Unset):
            axes = UNSET
        elif isinstance(self.axes, AxisAngles):
            axes = self.axes.to_dict()
        else:
            axes = self.axes


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "age_ms": age_ms,
            "position": position,
            "source": source,
        })
        if axes is not UNSET:
            field_dict["axes"] = axes

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.axis_angles import AxisAngles # noqa: PLC0415
        from ..models.position import Position # noqa: PLC0415
        d = dict(src_dict)
        age_ms = d.pop("age_ms")

        position = Position.from_dict(d.pop("position"))




        source = PositionSource(d.pop("source"))




        def _parse_axes(data: object) -> AxisAngles | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                axes_type_0 = AxisAngles.from_dict(data)



                return axes_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(AxisAngles | None | Unset, data)

        axes = _parse_axes(d.pop("axes", UNSET))


        position_report = cls(
            age_ms=age_ms,
            position=position,
            source=source,
            axes=axes,
        )


        position_report.additional_properties = d
        return position_report

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
