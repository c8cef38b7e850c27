from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast

if TYPE_CHECKING:
  from ..models.planned_motion import PlannedMotion





T = TypeVar("T", bound="JobPlan")



@_attrs_define
class JobPlan:
    """ The motions of a move job as written to the controller, with omitted
    and relative coordinates resolved: what the robot is about to do.

        Example:
            {'job': 7, 'cid': 1042, 'motions': [{'type': 'lin', 'target': [200.0, 0.0, 70.0, 0.0, 180.0, 0.0]}, {'type':
                'circ', 'aux': [250.0, 50.0, 70.0], 'target': [200.0, 100.0, 70.0, 0.0, 180.0, 0.0]}]}

        Attributes:
            cid (int): Command id on the channel.
            first (int): For a path: the index in the path of the first of these motions (a
                path publishes one plan per append, from where the last one ended);
                0 for a batch.
            job (int): The job.
            motions (list[PlannedMotion]): The motions in order.
     """

    cid: int
    first: int
    job: int
    motions: list[PlannedMotion]
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.planned_motion import PlannedMotion # noqa: PLC0415
        cid = self.cid

        first = self.first

        job = self.job

        motions = []
        for motions_item_data in self.motions:
            motions_item = motions_item_data.to_dict()
            motions.append(motions_item)




        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "cid": cid,
            "first": first,
            "job": job,
            "motions": motions,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.planned_motion import PlannedMotion # noqa: PLC0415
        d = dict(src_dict)
        cid = d.pop("cid")

        first = d.pop("first")

        job = d.pop("job")

        motions = []
        _motions = d.pop("motions")
        for motions_item_data in (_motions):
            motions_item = PlannedMotion.from_dict(motions_item_data)



            motions.append(motions_item)


        job_plan = cls(
            cid=cid,
            first=first,
            job=job,
            motions=motions,
        )


        job_plan.additional_properties = d
        return job_plan

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
