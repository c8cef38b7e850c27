from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from typing import cast

if TYPE_CHECKING:
  from ..models.opw_lengths import OpwLengths





T = TypeVar("T", bound="ModelInfo")



@_attrs_define
class ModelInfo:
    """ The robot model the service checks motions against: enough to draw the
    arm (a stick model from the OPW lengths and the axis angles of
    `/api/v1/state`) and to show each axis against its software limits.

        Example:
            {'name': 'kr3_r540', 'opw_mm': {'a1': 20.0, 'a2': -20.0, 'b': 0.0, 'c1': 345.0, 'c2': 260.0, 'c3': 260.0, 'c4':
                75.0}, 'limits_deg': [[-170.0, 170.0], [-170.0, 50.0], [-110.0, 155.0], [-175.0, 175.0], [-120.0, 120.0],
                [-350.0, 350.0]], 'max_speed_deg_s': [530.0, 529.0, 538.0, 600.0, 600.0, 800.0], 'max_acc_deg_s2': [300.0,
                300.0, 300.0, 300.0, 300.0, 300.0], 'home': [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]}

        Attributes:
            home (list[float]): Home position A1..A6 in degrees.
            limits_deg (list[list[float]]): Software limit switches per axis A1..A6: `[negative, positive]` degrees.
            max_acc_deg_s2 (list[float]): Axis accelerations A1..A6 at 100 % in deg/s² (what the dry run and
                the simulators plan with; an assumption unless the site set them).
            max_speed_deg_s (list[float]): Maximum axis speeds A1..A6 in deg/s.
            name (str): Model id (`kr3_r540`, ... or the custom model's name).
            opw_mm (OpwLengths): OPW lengths in mm (rs-opw-kinematics' names).
     """

    home: list[float]
    limits_deg: list[list[float]]
    max_acc_deg_s2: list[float]
    max_speed_deg_s: list[float]
    name: str
    opw_mm: OpwLengths
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.opw_lengths import OpwLengths # noqa: PLC0415
        home = self.home



        limits_deg = []
        for limits_deg_item_data in self.limits_deg:
            limits_deg_item = limits_deg_item_data


            limits_deg.append(limits_deg_item)



        max_acc_deg_s2 = self.max_acc_deg_s2



        max_speed_deg_s = self.max_speed_deg_s



        name = self.name

        opw_mm = self.opw_mm.to_dict()


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "home": home,
            "limits_deg": limits_deg,
            "max_acc_deg_s2": max_acc_deg_s2,
            "max_speed_deg_s": max_speed_deg_s,
            "name": name,
            "opw_mm": opw_mm,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.opw_lengths import OpwLengths # noqa: PLC0415
        d = dict(src_dict)
        home = cast(list[float], d.pop("home"))


        limits_deg = []
        _limits_deg = d.pop("limits_deg")
        for limits_deg_item_data in (_limits_deg):
            limits_deg_item = cast(list[float], limits_deg_item_data)

            limits_deg.append(limits_deg_item)


        max_acc_deg_s2 = cast(list[float], d.pop("max_acc_deg_s2"))


        max_speed_deg_s = cast(list[float], d.pop("max_speed_deg_s"))


        name = d.pop("name")

        opw_mm = OpwLengths.from_dict(d.pop("opw_mm"))




        model_info = cls(
            home=home,
            limits_deg=limits_deg,
            max_acc_deg_s2=max_acc_deg_s2,
            max_speed_deg_s=max_speed_deg_s,
            name=name,
            opw_mm=opw_mm,
        )


        model_info.additional_properties = d
        return model_info

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
