from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="OutputWrite")



@_attrs_define
class OutputWrite:
    """ The body of an output write.

        Example:
            {'value': True}

        Attributes:
            value (bool): The value to set.
            pulse_ms (int | None | Unset): Return to the other value after this many ms (0..=60000); default:
                the output's `pulse_ms` in the configuration (0: it stays).
     """

    value: bool
    pulse_ms: int | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        value = self.value

        pulse_ms: int | None | Unset
        if isinstance(self.pulse_ms, Unset):
            pulse_ms = UNSET
        else:
            pulse_ms = self.pulse_ms


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "value": value,
        })
        if pulse_ms is not UNSET:
            field_dict["pulse_ms"] = pulse_ms

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        value = d.pop("value")

        def _parse_pulse_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        pulse_ms = _parse_pulse_ms(d.pop("pulse_ms", UNSET))


        output_write = cls(
            value=value,
            pulse_ms=pulse_ms,
        )

        return output_write

