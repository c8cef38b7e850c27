from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.io_kind import IoKind






T = TypeVar("T", bound="AnalogChange")



@_attrs_define
class AnalogChange:
    """ A watched analog channel moved by its deadband (an `analog` event).

        Example:
            {'kind': 'input', 'index': 2, 'name': 'force', 'value': 0.25}

        Attributes:
            index (int): Its index, 1..=8.
            kind (IoKind): Inputs or outputs.
            name (str): Its configured name.
            value (float): The new value, normalised −1..=1 (3 decimals, as the controller
                reports it).
     """

    index: int
    kind: IoKind
    name: str
    value: float
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        index = self.index

        kind = self.kind.value

        name = self.name

        value = self.value


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "index": index,
            "kind": kind,
            "name": name,
            "value": value,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        index = d.pop("index")

        kind = IoKind(d.pop("kind"))




        name = d.pop("name")

        value = d.pop("value")

        analog_change = cls(
            index=index,
            kind=kind,
            name=name,
            value=value,
        )


        analog_change.additional_properties = d
        return analog_change

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
