from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.keep_out import KeepOut
  from ..models.workspace_box import WorkspaceBox





T = TypeVar("T", bound="WorkspaceInfo")



@_attrs_define
class WorkspaceInfo:
    """ Where the TCP may go: the workspace box, the floor and the keep-out zones.

        Example:
            {'box': {'x': [0.0, 500.0], 'y': [-400.0, 400.0], 'z': [20.0, 700.0]}, 'floor_z': 0.0, 'keep_out': [{'name':
                'fixture', 'x': [300.0, 400.0], 'y': [-50.0, 50.0], 'z': [0.0, 120.0]}]}

        Attributes:
            keep_out (list[KeepOut]): Boxes the TCP must not enter (`zones.keep_out`).
            box (None | Unset | WorkspaceBox):
            floor_z (float | None | Unset): The TCP stays at or above this Z (`zones.floor_z`), if configured.
     """

    keep_out: list[KeepOut]
    box: None | Unset | WorkspaceBox = UNSET
    floor_z: float | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.keep_out import KeepOut # noqa: PLC0415
        from ..models.workspace_box import WorkspaceBox # noqa: PLC0415
        keep_out = []
        for keep_out_item_data in self.keep_out:
            keep_out_item = keep_out_item_data.to_dict()
            keep_out.append(keep_out_item)



        box: dict[str, Any] | None | Unset
        if isinstance(self.box, Unset):
            box = UNSET
        elif isinstance(self.box, WorkspaceBox):
            box = self.box.to_dict()
        else:
            box = self.box

        floor_z: float | None | Unset
        if isinstance(self.floor_z, Unset):
            floor_z = UNSET
        else:
            floor_z = self.floor_z


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "keep_out": keep_out,
        })
        if box is not UNSET:
            field_dict["box"] = box
        if floor_z is not UNSET:
            field_dict["floor_z"] = floor_z

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.keep_out import KeepOut # noqa: PLC0415
        from ..models.workspace_box import WorkspaceBox # noqa: PLC0415
        d = dict(src_dict)
        keep_out = []
        _keep_out = d.pop("keep_out")
        for keep_out_item_data in (_keep_out):
            keep_out_item = KeepOut.from_dict(keep_out_item_data)



            keep_out.append(keep_out_item)


        def _parse_box(data: object) -> None | Unset | WorkspaceBox:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                box_type_0 = WorkspaceBox.from_dict(data)



                return box_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(None | Unset | WorkspaceBox, data)

        box = _parse_box(d.pop("box", UNSET))


        def _parse_floor_z(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        floor_z = _parse_floor_z(d.pop("floor_z", UNSET))


        workspace_info = cls(
            keep_out=keep_out,
            box=box,
            floor_z=floor_z,
        )


        workspace_info.additional_properties = d
        return workspace_info

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
