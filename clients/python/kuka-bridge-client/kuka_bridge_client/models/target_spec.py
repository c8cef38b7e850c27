from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="TargetSpec")



@_attrs_define
class TargetSpec:
    """ A Cartesian target; omitted components keep their current value (the
    previous motion's target inside a batch).

        Example:
            {'x': 200.0, 'y': 0.0, 'z': 70.0, 'a': 0.0, 'b': 180.0, 'c': 0.0}

        Attributes:
            a (float | None | Unset): A (about Z) in degrees.
            b (float | None | Unset): B (about Y) in degrees.
            c (float | None | Unset): C (about X) in degrees.
            s (int | None | Unset): Status (0..=7), PTP only; always obeyed. Omitted: chosen by the
                PTP's `config` (`auto`: the bridge chooses; `keep`: the current
                Status).
            t (int | None | Unset): Turn (0..=63), PTP only; always obeyed. Omitted: chosen with the
                Status (`auto`) or the shortest axis path (`keep`).
            x (float | None | Unset): X in mm.
            y (float | None | Unset): Y in mm.
            z (float | None | Unset): Z in mm.
     """

    a: float | None | Unset = UNSET
    b: float | None | Unset = UNSET
    c: float | None | Unset = UNSET
    s: int | None | Unset = UNSET
    t: int | None | Unset = UNSET
    x: float | None | Unset = UNSET
    y: float | None | Unset = UNSET
    z: float | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        a: float | None | Unset
        if isinstance(self.a, Unset):
            a = UNSET
        else:
            a = self.a

        b: float | None | Unset
        if isinstance(self.b, Unset):
            b = UNSET
        else:
            b = self.b

        c: float | None | Unset
        if isinstance(self.c, Unset):
            c = UNSET
        else:
            c = self.c

        s: int | None | Unset
        if isinstance(self.s, Unset):
            s = UNSET
        else:
            s = self.s

        t: int | None | Unset
        if isinstance(self.t, Unset):
            t = UNSET
        else:
            t = self.t

        x: float | None | Unset
        if isinstance(self.x, Unset):
            x = UNSET
        else:
            x = self.x

        y: float | None | Unset
        if isinstance(self.y, Unset):
            y = UNSET
        else:
            y = self.y

        z: float | None | Unset
        if isinstance(self.z, Unset):
            z = UNSET
        else:
            z = self.z


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if a is not UNSET:
            field_dict["a"] = a
        if b is not UNSET:
            field_dict["b"] = b
        if c is not UNSET:
            field_dict["c"] = c
        if s is not UNSET:
            field_dict["s"] = s
        if t is not UNSET:
            field_dict["t"] = t
        if x is not UNSET:
            field_dict["x"] = x
        if y is not UNSET:
            field_dict["y"] = y
        if z is not UNSET:
            field_dict["z"] = z

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_a(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        a = _parse_a(d.pop("a", UNSET))


        def _parse_b(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        b = _parse_b(d.pop("b", UNSET))


        def _parse_c(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        c = _parse_c(d.pop("c", UNSET))


        def _parse_s(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        s = _parse_s(d.pop("s", UNSET))


        def _parse_t(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        t = _parse_t(d.pop("t", UNSET))


        def _parse_x(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        x = _parse_x(d.pop("x", UNSET))


        def _parse_y(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        y = _parse_y(d.pop("y", UNSET))


        def _parse_z(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        z = _parse_z(d.pop("z", UNSET))


        target_spec = cls(
            a=a,
            b=b,
            c=c,
            s=s,
            t=t,
            x=x,
            y=y,
            z=z,
        )

        return target_spec

