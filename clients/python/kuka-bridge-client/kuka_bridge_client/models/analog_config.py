from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset






T = TypeVar("T", bound="AnalogConfig")



@_attrs_define
class AnalogConfig:
    """ One named analog channel of the site.

        Attributes:
            index (int): `$ANIN`/`$ANOUT` index, 1..=32.
            name (str): Its name, as for digital signals (`spindle_speed`).
            deadband (float | Unset): The change (normalised, 0 < deadband ≤ 2) that makes a watched
                channel publish an event; default 0.01, 1 % of full scale.
            watch (bool | Unset): Publish an `analog` event when its value moves by `deadband` or
                more from the last published one (channels 1..=8: the ones the
                controller reports).
     """

    index: int
    name: str
    deadband: float | Unset = UNSET
    watch: bool | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        index = self.index

        name = self.name

        deadband = self.deadband

        watch = self.watch


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "index": index,
            "name": name,
        })
        if deadband is not UNSET:
            field_dict["deadband"] = deadband
        if watch is not UNSET:
            field_dict["watch"] = watch

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        index = d.pop("index")

        name = d.pop("name")

        deadband = d.pop("deadband", UNSET)

        watch = d.pop("watch", UNSET)

        analog_config = cls(
            index=index,
            name=name,
            deadband=deadband,
            watch=watch,
        )

        return analog_config

