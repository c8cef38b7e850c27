from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="AnalogSignal")



@_attrs_define
class AnalogSignal:
    """ One analog channel and its value.

        Example:
            {'index': 1, 'name': 'spindle_speed', 'value': 0.5, 'writable': True}

        Attributes:
            index (int): `$ANIN`/`$ANOUT` index.
            value (float): Normalised value, −1..1 (±1 = the channel's full scale, ±10 V on
                the usual cards), 3 decimals: as last reported, or as written.
            writable (bool): Clients may write it (an analog output on the site's list).
            name (None | str | Unset): Its name in the site's `[io]` configuration.
     """

    index: int
    value: float
    writable: bool
    name: None | str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        index = self.index

        value = self.value

        writable = self.writable

        name: None | str | Unset
        if isinstance(self.name, Unset):
            name = UNSET
        else:
            name = self.name


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "index": index,
            "value": value,
            "writable": writable,
        })
        if name is not UNSET:
            field_dict["name"] = name

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        index = d.pop("index")

        value = d.pop("value")

        writable = d.pop("writable")

        def _parse_name(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        name = _parse_name(d.pop("name", UNSET))


        analog_signal = cls(
            index=index,
            value=value,
            writable=writable,
            name=name,
        )


        analog_signal.additional_properties = d
        return analog_signal

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
