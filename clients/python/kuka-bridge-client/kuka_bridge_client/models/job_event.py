from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.job_event_type import JobEventType
from typing import cast

if TYPE_CHECKING:
  from ..models.job import Job





T = TypeVar("T", bound="JobEvent")



@_attrs_define
class JobEvent:
    """ A job changed state or progressed.

        Attributes:
            data (Job): A job as clients see it. Example: {'id': 7, 'operation': 'move', 'state': 'done', 'motions': 2,
                'completed': 2, 'cid': 1042, 'created_ms': 1795373060215, 'sent_ms': 1795373060221, 'finished_ms':
                1795373060931, 'position': {'x': 250.0, 'y': 100.0, 'z': 70.0, 'a': 180.0, 'b': 0.0, 'c': 180.0, 's': 6, 't':
                51}, 'axes': {'a1': -21.801, 'a2': -13.511, 'a3': 108.689, 'a4': 0.0, 'a5': -5.178, 'a6': -21.801}, 'frame':
                None, 'error': None}.
            type_ (JobEventType):
     """

    data: Job
    type_: JobEventType
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.job import Job # noqa: PLC0415
        data = self.data.to_dict()

        type_ = self.type_.value


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "data": data,
            "type": type_,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.job import Job # noqa: PLC0415
        d = dict(src_dict)
        data = Job.from_dict(d.pop("data"))




        type_ = JobEventType(d.pop("type"))




        job_event = cls(
            data=data,
            type_=type_,
        )


        job_event.additional_properties = d
        return job_event

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
