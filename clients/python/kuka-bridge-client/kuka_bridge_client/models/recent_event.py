from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast

if TYPE_CHECKING:
  from ..models.recent_event_data import RecentEventData





T = TypeVar("T", bound="RecentEvent")



@_attrs_define
class RecentEvent:
    """ A job, plan, alarm, io or analog event as the service published it.

        Example:
            {'id': 1795629212950, 'type': 'job', 'at_ms': 1795629212958, 'data': {'id': 7, 'operation': 'move', 'state':
                'done', 'motions': 1, 'completed': 1}}

        Attributes:
            at_ms (int): When the service published it (Unix ms).
            data (RecentEventData): What the SSE `data:` carries: the `Job`, the `JobPlan`, the error (`code`,
                `detail`, `axis`, `motion`), the `IoChange` or the `AnalogChange`.
            id (int): The event id (the SSE `id:`; grows by one per job, plan, alarm, io or analog event).
            type_ (str): `job`, `plan`, `alarm`, `io` or `analog` (the SSE `event:`).
     """

    at_ms: int
    data: RecentEventData
    id: int
    type_: str
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.recent_event_data import RecentEventData # noqa: PLC0415
        at_ms = self.at_ms

        data = self.data.to_dict()

        id = self.id

        type_ = self.type_


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "at_ms": at_ms,
            "data": data,
            "id": id,
            "type": type_,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.recent_event_data import RecentEventData # noqa: PLC0415
        d = dict(src_dict)
        at_ms = d.pop("at_ms")

        data = RecentEventData.from_dict(d.pop("data"))




        id = d.pop("id")

        type_ = d.pop("type")

        recent_event = cls(
            at_ms=at_ms,
            data=data,
            id=id,
            type_=type_,
        )


        recent_event.additional_properties = d
        return recent_event

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
