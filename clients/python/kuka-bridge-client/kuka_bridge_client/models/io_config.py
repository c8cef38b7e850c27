from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.analog_config import AnalogConfig
  from ..models.signal_config import SignalConfig





T = TypeVar("T", bound="IoConfig")



@_attrs_define
class IoConfig:
    """ The site's digital I/O: names for inputs, and the outputs clients may
    write (every other output is refused with `output_not_allowed`).

        Example:
            {'inputs': [{'name': 'part_present', 'index': 3, 'pulse_ms': 0, 'watch': True}], 'outputs': [{'name':
                'gripper_close', 'index': 1, 'pulse_ms': 0, 'watch': True}], 'analog_inputs': [{'name': 'force', 'index': 2,
                'watch': True, 'deadband': 0.05}], 'analog_outputs': [{'name': 'spindle_speed', 'index': 1, 'watch': False,
                'deadband': 0.01}]}

        Attributes:
            analog_inputs (list[AnalogConfig] | Unset): Named analog inputs (`$ANIN[1..=32]`).
            analog_outputs (list[AnalogConfig] | Unset): The analog outputs clients may write (`$ANOUT[1..=32]`).
            inputs (list[SignalConfig] | Unset): Named inputs (reading needs no entry: any input in the window can be
                read by number).
            outputs (list[SignalConfig] | Unset): The outputs clients may write, by name and number (reading needs
                no entry).
     """

    analog_inputs: list[AnalogConfig] | Unset = UNSET
    analog_outputs: list[AnalogConfig] | Unset = UNSET
    inputs: list[SignalConfig] | Unset = UNSET
    outputs: list[SignalConfig] | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        from ..models.analog_config import AnalogConfig # noqa: PLC0415
        from ..models.signal_config import SignalConfig # noqa: PLC0415
        analog_inputs: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.analog_inputs, Unset):
            analog_inputs = []
            for analog_inputs_item_data in self.analog_inputs:
                analog_inputs_item = analog_inputs_item_data.to_dict()
                analog_inputs.append(analog_inputs_item)



        analog_outputs: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.analog_outputs, Unset):
            analog_outputs = []
            for analog_outputs_item_data in self.analog_outputs:
                analog_outputs_item = analog_outputs_item_data.to_dict()
                analog_outputs.append(analog_outputs_item)



        inputs: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.inputs, Unset):
            inputs = []
            for inputs_item_data in self.inputs:
                inputs_item = inputs_item_data.to_dict()
                inputs.append(inputs_item)



        outputs: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.outputs, Unset):
            outputs = []
            for outputs_item_data in self.outputs:
                outputs_item = outputs_item_data.to_dict()
                outputs.append(outputs_item)




        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if analog_inputs is not UNSET:
            field_dict["analog_inputs"] = analog_inputs
        if analog_outputs is not UNSET:
            field_dict["analog_outputs"] = analog_outputs
        if inputs is not UNSET:
            field_dict["inputs"] = inputs
        if outputs is not UNSET:
            field_dict["outputs"] = outputs

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.analog_config import AnalogConfig # noqa: PLC0415
        from ..models.signal_config import SignalConfig # noqa: PLC0415
        d = dict(src_dict)
        _analog_inputs = d.pop("analog_inputs", UNSET)
        analog_inputs: list[AnalogConfig] | Unset = UNSET
        if _analog_inputs is not UNSET:
            analog_inputs = []
            for analog_inputs_item_data in _analog_inputs:
                analog_inputs_item = AnalogConfig.from_dict(analog_inputs_item_data)



                analog_inputs.append(analog_inputs_item)


        _analog_outputs = d.pop("analog_outputs", UNSET)
        analog_outputs: list[AnalogConfig] | Unset = UNSET
        if _analog_outputs is not UNSET:
            analog_outputs = []
            for analog_outputs_item_data in _analog_outputs:
                analog_outputs_item = AnalogConfig.from_dict(analog_outputs_item_data)



                analog_outputs.append(analog_outputs_item)


        _inputs = d.pop("inputs", UNSET)
        inputs: list[SignalConfig] | Unset = UNSET
        if _inputs is not UNSET:
            inputs = []
            for inputs_item_data in _inputs:
                inputs_item = SignalConfig.from_dict(inputs_item_data)



                inputs.append(inputs_item)


        _outputs = d.pop("outputs", UNSET)
        outputs: list[SignalConfig] | Unset = UNSET
        if _outputs is not UNSET:
            outputs = []
            for outputs_item_data in _outputs:
                outputs_item = SignalConfig.from_dict(outputs_item_data)



                outputs.append(outputs_item)


        io_config = cls(
            analog_inputs=analog_inputs,
            analog_outputs=analog_outputs,
            inputs=inputs,
            outputs=outputs,
        )

        return io_config

