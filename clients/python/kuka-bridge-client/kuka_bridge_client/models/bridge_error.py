from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="BridgeError")



@_attrs_define
class BridgeError:
    """ An error with its code, sentence and context.

        Example:
            {'code': 'timeout', 'detail': 'the controller did not pick up command 12 within 2000 ms'}

        Attributes:
            code (str): A stable, machine-readable error code (never renamed; see /errors). The bridge's codes:
                invalid_input, workspace_violation, speed_limit, unreachable, software_limit, singularity, controller_offline,
                channel_locked, timeout, controller_error, controller_busy, cancelled, not_found, method_not_allowed,
                payload_too_large, unsupported_media_type, queue_full, invalid_program, program_unsupported, program_failed,
                programs_unavailable, plugin_invalid, plugin_timeout, plugin_memory, plugin_trap, plugin_bad_response,
                plugins_unavailable, unauthenticated, forbidden, control_held, too_many_attempts, overloaded, request_timeout,
                protocol_error, internal, storage_unavailable, command_lost, gone, shutting_down, path_closed, path_full,
                output_not_allowed, unknown_signal, signal_not_reported, input_timeout, variable_not_allowed, unknown_variable,
                variables_unavailable. A plugin's answer may carry a code of its own.
            detail (str): Human sentence.
            axis (int | None | Unset): 1-based axis for software-limit errors.
            file (None | str | Unset): For KRL program errors: the file (`src` or `dat`) the line is in.
            line (int | None | Unset): For KRL program errors: the 1-based line in the uploaded file.
            motion (int | None | Unset): 0-based index of the motion in the batch that failed.
     """

    code: str
    detail: str
    axis: int | None | Unset = UNSET
    file: None | str | Unset = UNSET
    line: int | None | Unset = UNSET
    motion: int | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        code = self.code

        detail = self.detail

        axis: int | None | Unset
        if isinstance(self.axis, Unset):
            axis = UNSET
        else:
            axis = self.axis

        file: None | str | Unset
        if isinstance(self.file, Unset):
            file = UNSET
        else:
            file = self.file

        line: int | None | Unset
        if isinstance(self.line, Unset):
            line = UNSET
        else:
            line = self.line

        motion: int | None | Unset
        if isinstance(self.motion, Unset):
            motion = UNSET
        else:
            motion = self.motion


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "code": code,
            "detail": detail,
        })
        if axis is not UNSET:
            field_dict["axis"] = axis
        if file is not UNSET:
            field_dict["file"] = file
        if line is not UNSET:
            field_dict["line"] = line
        if motion is not UNSET:
            field_dict["motion"] = motion

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        code = d.pop("code")

        detail = d.pop("detail")

        def _parse_axis(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        axis = _parse_axis(d.pop("axis", UNSET))


        def _parse_file(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        file = _parse_file(d.pop("file", UNSET))


        def _parse_line(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        line = _parse_line(d.pop("line", UNSET))


        def _parse_motion(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        motion = _parse_motion(d.pop("motion", UNSET))


        bridge_error = cls(
            code=code,
            detail=detail,
            axis=axis,
            file=file,
            line=line,
            motion=motion,
        )


        bridge_error.additional_properties = d
        return bridge_error

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
