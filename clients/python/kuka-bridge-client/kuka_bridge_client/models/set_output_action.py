from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.set_output_action_type import SetOutputActionType
from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="SetOutputAction")



@_attrs_define
class SetOutputAction:
    """ An I/O action, not a motion: set a digital output when the robot
    passes this point of the sequence, i.e. as the next motion starts
    (KRL `TRIGGER WHEN DISTANCE=0`), without stopping the robot: the
    motions on either side blend as if it were not there. Before a
    `wait_input`/`dwell`, or at the end, it switches once the motions
    before it have ended. With `path_mm` it switches at that distance
    along the path from the end point of the motion before it (KRL
    `TRIGGER WHEN PATH`). Only outputs on the site's allow-list
    (`[io] outputs`, docs/IO.md).

        Example:
            {'type': 'set_output', 'signal': 'glue_valve', 'value': False, 'path_mm': -5.0}

        Attributes:
            signal (int | str): A digital signal in a request: its number or its configured name.
            type_ (SetOutputActionType):
            value (bool): The value to set.
            path_mm (float | None | Unset): Switch at this distance in mm along the path from the end point
                of the motion before the action (KRL `TRIGGER WHEN PATH =
                path_mm DELAY = 0` on that motion): negative = that many mm
                before the end point (on that motion), positive = after it,
                along the next motion (the motion before must blend into it).
                Needs a `lin`, `circ`, `slin` or `scirc` before it in the same
                request (only other `set_output` actions between); a positive
                value also a motion after it into which that one blends. With a
                robot model, |path_mm| is at most the length of the motion
                before (negative) or after (positive). Else 422
                `invalid_input`. Omitted: as the next motion starts.
                Resolution 0.001 mm.
            pulse_ms (int | None | Unset): Return to the other value after this many ms (default: the
                signal's configured `pulse_ms`, else none).
     """

    signal: int | str
    type_: SetOutputActionType
    value: bool
    path_mm: float | None | Unset = UNSET
    pulse_ms: int | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        signal: int | str
        signal = self.signal

        type_ = self.type_.value

        value = self.value

        path_mm: float | None | Unset
        if isinstance(self.path_mm, Unset):
            path_mm = UNSET
        else:
            path_mm = self.path_mm

        pulse_ms: int | None | Unset
        if isinstance(self.pulse_ms, Unset):
            pulse_ms = UNSET
        else:
            pulse_ms = self.pulse_ms


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "signal": signal,
            "type": type_,
            "value": value,
        })
        if path_mm is not UNSET:
            field_dict["path_mm"] = path_mm
        if pulse_ms is not UNSET:
            field_dict["pulse_ms"] = pulse_ms

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_signal(data: object) -> int | str:
            return cast(int | str, data)

        signal = _parse_signal(d.pop("signal"))


        type_ = SetOutputActionType(d.pop("type"))




        value = d.pop("value")

        def _parse_path_mm(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        path_mm = _parse_path_mm(d.pop("path_mm", UNSET))


        def _parse_pulse_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        pulse_ms = _parse_pulse_ms(d.pop("pulse_ms", UNSET))


        set_output_action = cls(
            signal=signal,
            type_=type_,
            value=value,
            path_mm=path_mm,
            pulse_ms=pulse_ms,
        )


        set_output_action.additional_properties = d
        return set_output_action

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
