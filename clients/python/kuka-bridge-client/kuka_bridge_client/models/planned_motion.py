from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="PlannedMotion")



@_attrs_define
class PlannedMotion:
    """ One motion of a [`JobPlan`].

        Attributes:
            type_ (str): `ptp`, `ptp_axes`, `lin`, `circ`, `slin`, `scirc`, `sptp`,
                `sptp_axes`, `spl`,
                or an action (`set_output`, `wait_input`, `dwell`: no target).
            aux (list[float] | None | Unset): Auxiliary point `[x, y, z]` of a `circ` or `scirc`.
            axes (list[float] | None | Unset): Target axis angles A1..A6 of a `ptp_axes` or `sptp_axes`.
            left (int | None | Unset): Of an `spl`: the points of its spline block from this one to the
                block's end (1 = the last point).
            target (list[float] | None | Unset): Target TCP pose in the base frame `[x, y, z, a, b, c]` (not for
                `ptp_axes`).
     """

    type_: str
    aux: list[float] | None | Unset = UNSET
    axes: list[float] | None | Unset = UNSET
    left: int | None | Unset = UNSET
    target: list[float] | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        type_ = self.type_

        aux: list[float] | None | Unset
        if isinstance(self.aux, Unset):
            aux = UNSET
        elif isinstance(self.aux, list):
            aux = self.aux


        else:
            aux = self.aux

        axes: list[float] | None | Unset
        if isinstance(self.axes, Unset):
            axes = UNSET
        elif isinstance(self.axes, list):
            axes = self.axes


        else:
            axes = self.axes

        left: int | None | Unset
        if isinstance(self.left, Unset):
            left = UNSET
        else:
            left = self.left

        target: list[float] | None | Unset
        if isinstance(self.target, Unset):
            target = UNSET
        elif isinstance(self.target, list):
            target = self.target


        else:
            target = self.target


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "type": type_,
        })
        if aux is not UNSET:
            field_dict["aux"] = aux
        if axes is not UNSET:
            field_dict["axes"] = axes
        if left is not UNSET:
            field_dict["left"] = left
        if target is not UNSET:
            field_dict["target"] = target

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        type_ = d.pop("type")

        def _parse_aux(data: object) -> list[float] | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, list):
                    raise TypeError()
                aux_type_0 = cast(list[float], data)

                return aux_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(list[float] | None | Unset, data)

        aux = _parse_aux(d.pop("aux", UNSET))


        def _parse_axes(data: object) -> list[float] | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, list):
                    raise TypeError()
                axes_type_0 = cast(list[float], data)

                return axes_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(list[float] | None | Unset, data)

        axes = _parse_axes(d.pop("axes", UNSET))


        def _parse_left(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        left = _parse_left(d.pop("left", UNSET))


        def _parse_target(data: object) -> list[float] | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, list):
                    raise TypeError()
                target_type_0 = cast(list[float], data)

                return target_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(list[float] | None | Unset, data)

        target = _parse_target(d.pop("target", UNSET))


        planned_motion = cls(
            type_=type_,
            aux=aux,
            axes=axes,
            left=left,
            target=target,
        )


        planned_motion.additional_properties = d
        return planned_motion

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
