from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast






T = TypeVar("T", bound="SimSnapshot")



@_attrs_define
class SimSnapshot:
    """ A snapshot of the simulated controller for tests and the API.

        Attributes:
            axes (list[float]): Current axis angles.
            busy (bool): Executing a batch.
            heartbeats (int): Heartbeats written.
            last_cid (int): Highest accepted CID.
            model (str): Robot model id.
            pose (list[float]): Current TCP `[x, y, z, a, b, c]`.
            sim_time_s (float): Simulated seconds spent moving since start.
     """

    axes: list[float]
    busy: bool
    heartbeats: int
    last_cid: int
    model: str
    pose: list[float]
    sim_time_s: float
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        axes = self.axes



        busy = self.busy

        heartbeats = self.heartbeats

        last_cid = self.last_cid

        model = self.model

        pose = self.pose



        sim_time_s = self.sim_time_s


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "axes": axes,
            "busy": busy,
            "heartbeats": heartbeats,
            "last_cid": last_cid,
            "model": model,
            "pose": pose,
            "sim_time_s": sim_time_s,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        axes = cast(list[float], d.pop("axes"))


        busy = d.pop("busy")

        heartbeats = d.pop("heartbeats")

        last_cid = d.pop("last_cid")

        model = d.pop("model")

        pose = cast(list[float], d.pop("pose"))


        sim_time_s = d.pop("sim_time_s")

        sim_snapshot = cls(
            axes=axes,
            busy=busy,
            heartbeats=heartbeats,
            last_cid=last_cid,
            model=model,
            pose=pose,
            sim_time_s=sim_time_s,
        )


        sim_snapshot.additional_properties = d
        return sim_snapshot

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
