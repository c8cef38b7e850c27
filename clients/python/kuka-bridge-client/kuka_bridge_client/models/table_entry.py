from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.cartesian_frame import CartesianFrame





T = TypeVar("T", bound="TableEntry")



@_attrs_define
class TableEntry:
    """ An entry of the controller's tool or base table.

        Example:
            {'table': 'TOOL_DATA', 'number': 3, 'name': 'gripper', 'frame': {'x': 0.0, 'y': 0.0, 'z': 120.0, 'a': 0.0, 'b':
                0.0, 'c': 0.0}}

        Attributes:
            frame (CartesianFrame): A Cartesian frame in mm and degrees (A, B, C about Z, Y, X). Example: {'x': 0.0, 'y':
                0.0, 'z': 100.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}.
            number (int): The entry's number (tools 1..=16, bases 1..=32).
            table (str): `TOOL_DATA` or `BASE_DATA`.
            name (None | str | Unset): Its name as the teach pendant shows it (`TOOL_NAME[n,]`,
                `BASE_NAME[n,]`, trailing blanks removed); `null` when the
                controller has none to read or the entry is unnamed.
     """

    frame: CartesianFrame
    number: int
    table: str
    name: None | str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        frame = self.frame.to_dict()

        number = self.number

        table = self.table

        name: None | str | Unset
        if isinstance(self.name, Unset):
            name = UNSET
        else:
            name = self.name


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "frame": frame,
            "number": number,
            "table": table,
        })
        if name is not UNSET:
            field_dict["name"] = name

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        d = dict(src_dict)
        frame = CartesianFrame.from_dict(d.pop("frame"))




        number = d.pop("number")

        table = d.pop("table")

        def _parse_name(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        name = _parse_name(d.pop("name", UNSET))


        table_entry = cls(
            frame=frame,
            number=number,
            table=table,
            name=name,
        )


        table_entry.additional_properties = d
        return table_entry

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
