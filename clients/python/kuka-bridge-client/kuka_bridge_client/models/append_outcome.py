from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast

if TYPE_CHECKING:
  from ..models.cartesian_frame import CartesianFrame





T = TypeVar("T", bound="AppendOutcome")



@_attrs_define
class AppendOutcome:
    """ The answer to an append.

        Example:
            {'path': 12, 'first': 40, 'appended': 20, 'total': 60, 'closed': False, 'end': {'x': 200.0, 'y': 40.0, 'z':
                100.0, 'a': 0.0, 'b': 180.0, 'c': 0.0}}

        Attributes:
            appended (int): Motions appended by this request.
            closed (bool): The path is closed now.
            end (CartesianFrame): A Cartesian frame in mm and degrees (A, B, C about Z, Y, X). Example: {'x': 0.0, 'y': 0.0,
                'z': 100.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}.
            first (int): Path-wide index of the first motion of this append.
            path (int): The path (its job id).
            total (int): Motions appended to the path so far.
     """

    appended: int
    closed: bool
    end: CartesianFrame
    first: int
    path: int
    total: int
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        appended = self.appended

        closed = self.closed

        end = self.end.to_dict()

        first = self.first

        path = self.path

        total = self.total


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "appended": appended,
            "closed": closed,
            "end": end,
            "first": first,
            "path": path,
            "total": total,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        d = dict(src_dict)
        appended = d.pop("appended")

        closed = d.pop("closed")

        end = CartesianFrame.from_dict(d.pop("end"))




        first = d.pop("first")

        path = d.pop("path")

        total = d.pop("total")

        append_outcome = cls(
            appended=appended,
            closed=closed,
            end=end,
            first=first,
            path=path,
            total=total,
        )


        append_outcome.additional_properties = d
        return append_outcome

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
