from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.signal import Signal





T = TypeVar("T", bound="IoView")



@_attrs_define
class IoView:
    """ The digital I/O the controller reports.

        Attributes:
            base (int): Index of the first signal reported (the KRL program's `kb_io_base`).
            inputs (list[Signal]): `$IN[base..base+30]`.
            outputs (list[Signal]): `$OUT[base..base+30]`.
            age_ms (int | None | Unset): Milliseconds since the service read the state file they come from.
     """

    base: int
    inputs: list[Signal]
    outputs: list[Signal]
    age_ms: int | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.signal import Signal # noqa: PLC0415
        base = self.base

        inputs = []
        for inputs_item_data in self.inputs:
            inputs_item = inputs_item_data.to_dict()
            inputs.append(inputs_item)



        outputs = []
        for outputs_item_data in self.outputs:
            outputs_item = outputs_item_data.to_dict()
            outputs.append(outputs_item)



        age_ms: int | None | Unset
        if isinstance(self.age_ms, Unset):
            age_ms = UNSET
        else:
            age_ms = self.age_ms


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "base": base,
            "inputs": inputs,
            "outputs": outputs,
        })
        if age_ms is not UNSET:
            field_dict["age_ms"] = age_ms

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.signal import Signal # noqa: PLC0415
        d = dict(src_dict)
        base = d.pop("base")

        inputs = []
        _inputs = d.pop("inputs")
        for inputs_item_data in (_inputs):
            inputs_item = Signal.from_dict(inputs_item_data)



            inputs.append(inputs_item)


        outputs = []
        _outputs = d.pop("outputs")
        for outputs_item_data in (_outputs):
            outputs_item = Signal.from_dict(outputs_item_data)



            outputs.append(outputs_item)


        def _parse_age_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        age_ms = _parse_age_ms(d.pop("age_ms", UNSET))


        io_view = cls(
            base=base,
            inputs=inputs,
            outputs=outputs,
            age_ms=age_ms,
        )


        io_view.additional_properties = d
        return io_view

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
