from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.analog_event_type import AnalogEventType
from typing import cast

if TYPE_CHECKING:
  from ..models.analog_change import AnalogChange





T = TypeVar("T", bound="AnalogEvent")



@_attrs_define
class AnalogEvent:
    """ A watched analog channel (`[io] analog_*` entries with
    `watch = true`) moved by its deadband.

        Attributes:
            data (AnalogChange): A watched analog channel moved by its deadband (an `analog` event). Example: {'kind':
                'input', 'index': 2, 'name': 'force', 'value': 0.25}.
            type_ (AnalogEventType):
     """

    data: AnalogChange
    type_: AnalogEventType
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.analog_change import AnalogChange # noqa: PLC0415
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
        from ..models.analog_change import AnalogChange # noqa: PLC0415
        d = dict(src_dict)
        data = AnalogChange.from_dict(d.pop("data"))




        type_ = AnalogEventType(d.pop("type"))




        analog_event = cls(
            data=data,
            type_=type_,
        )


        analog_event.additional_properties = d
        return analog_event

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
