from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast






T = TypeVar("T", bound="TraceSample")



@_attrs_define
class TraceSample:
    """ One executed point of the TCP trace.

        Attributes:
            axes (list[float]): Axis angles A1..A6.
            cid (int): Command that moved the robot here.
            motion (int): Motion index within that command's batch.
            pose (list[float]): TCP pose in the base frame `[x, y, z, a, b, c]`.
            stop (bool): The robot stands still from here on. The KRC-like runtime marks
                every stop (exact stops inside a batch, its end, an error stop);
                the native simulator marks where each batch ends.
            t (float): Simulated time in seconds since the controller started.
     """

    axes: list[float]
    cid: int
    motion: int
    pose: list[float]
    stop: bool
    t: float
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        axes = self.axes



        cid = self.cid

        motion = self.motion

        pose = self.pose



        stop = self.stop

        t = self.t


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "axes": axes,
            "cid": cid,
            "motion": motion,
            "pose": pose,
            "stop": stop,
            "t": t,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        axes = cast(list[float], d.pop("axes"))


        cid = d.pop("cid")

        motion = d.pop("motion")

        pose = cast(list[float], d.pop("pose"))


        stop = d.pop("stop")

        t = d.pop("t")

        trace_sample = cls(
            axes=axes,
            cid=cid,
            motion=motion,
            pose=pose,
            stop=stop,
            t=t,
        )


        trace_sample.additional_properties = d
        return trace_sample

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
