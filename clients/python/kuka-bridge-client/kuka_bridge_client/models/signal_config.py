from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset






T = TypeVar("T", bound="SignalConfig")



@_attrs_define
class SignalConfig:
    """ One named signal of the site.

        Attributes:
            index (int): `$IN`/`$OUT` index, 1..=4096.
            name (str): The name clients may use instead of the number (`gripper_close`):
                a lower-case letter, then lower-case letters, digits and `_`, at
                most 32 characters.
            pulse_ms (int | Unset): Outputs: a write without its own `pulse_ms` pulses this long (ms,
                up to 60000); 0 = the output stays.
            watch (bool | Unset): Changes of this signal are pushed as `io` events.
     """

    index: int
    name: str
    pulse_ms: int | Unset = UNSET
    watch: bool | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        index = self.index

        name = self.name

        pulse_ms = self.pulse_ms

        watch = self.watch


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "index": index,
            "name": name,
        })
        if pulse_ms is not UNSET:
            field_dict["pulse_ms"] = pulse_ms
        if watch is not UNSET:
            field_dict["watch"] = watch

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        index = d.pop("index")

        name = d.pop("name")

        pulse_ms = d.pop("pulse_ms", UNSET)

        watch = d.pop("watch", UNSET)

        signal_config = cls(
            index=index,
            name=name,
            pulse_ms=pulse_ms,
            watch=watch,
        )

        return signal_config

