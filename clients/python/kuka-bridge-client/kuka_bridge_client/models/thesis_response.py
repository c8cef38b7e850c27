from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="ThesisResponse")



@_attrs_define
class ThesisResponse:
    """ The thesis's response.

        Example:
            {'statuscode': 1, 'position': [200.0, 0.0, 70.0, 0.0, 180.0, 0.0]}

        Attributes:
            position (list[float]): `[x, y, z, a, b, c]`: the robot position (for `tcp`/`gettcp`: the tool frame).
            statuscode (int): 1 on success; see docs/errors.md for the other values.
            age_ms (int | None | Unset): `getpos` while a motion runs: the position comes from the
                controller's live state, read this many ms ago (absent otherwise:
                read through the controller program when the robot stands).
     """

    position: list[float]
    statuscode: int
    age_ms: int | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        position = self.position



        statuscode = self.statuscode

        age_ms: int | None | Unset
        if isinstance(self.age_ms, Unset):
            age_ms = UNSET
        else:
            age_ms = self.age_ms


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "position": position,
            "statuscode": statuscode,
        })
        if age_ms is not UNSET:
            field_dict["age_ms"] = age_ms

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        position = cast(list[float], d.pop("position"))


        statuscode = d.pop("statuscode")

        def _parse_age_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        age_ms = _parse_age_ms(d.pop("age_ms", UNSET))


        thesis_response = cls(
            position=position,
            statuscode=statuscode,
            age_ms=age_ms,
        )


        thesis_response.additional_properties = d
        return thesis_response

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
