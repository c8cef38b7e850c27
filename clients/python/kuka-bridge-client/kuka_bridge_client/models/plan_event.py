from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.plan_event_type import PlanEventType
from typing import cast

if TYPE_CHECKING:
  from ..models.job_plan import JobPlan





T = TypeVar("T", bound="PlanEvent")



@_attrs_define
class PlanEvent:
    """ A move job's motions as written to the controller (the planned path).

        Attributes:
            data (JobPlan): The motions of a move job as written to the controller, with omitted
                and relative coordinates resolved: what the robot is about to do. Example: {'job': 7, 'cid': 1042, 'motions':
                [{'type': 'lin', 'target': [200.0, 0.0, 70.0, 0.0, 180.0, 0.0]}, {'type': 'circ', 'aux': [250.0, 50.0, 70.0],
                'target': [200.0, 100.0, 70.0, 0.0, 180.0, 0.0]}]}.
            type_ (PlanEventType):
     """

    data: JobPlan
    type_: PlanEventType
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.job_plan import JobPlan # noqa: PLC0415
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
        from ..models.job_plan import JobPlan # noqa: PLC0415
        d = dict(src_dict)
        data = JobPlan.from_dict(d.pop("data"))




        type_ = PlanEventType(d.pop("type"))




        plan_event = cls(
            data=data,
            type_=type_,
        )


        plan_event.additional_properties = d
        return plan_event

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
