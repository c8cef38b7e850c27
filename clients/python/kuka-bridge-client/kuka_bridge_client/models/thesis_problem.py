from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.schema_violation import SchemaViolation





T = TypeVar("T", bound="ThesisProblem")



@_attrs_define
class ThesisProblem:
    """ A thesis failure: the problem details plus `statuscode` and `position`.

        Example:
            {'statuscode': 20, 'position': [355.0, 0.0, 625.0, 0.0, 90.0, 0.0], 'type': '/errors#unreachable', 'title':
                'Target unreachable', 'status': 422, 'detail': 'target is out of reach of the robot', 'code': 'unreachable',
                'motion': 0}

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
            detail (str): Human explanation of this occurrence.
            status (int): HTTP status.
            title (str): Short summary of the problem type.
            type_ (str): The problem type: `/errors#<code>`, a URI reference relative to the
                request's URL; the service's error catalogue (`GET /errors`)
                explains the code there.
            position (list[float]): Last known position `[x, y, z, a, b, c]` (zeros when unknown).
            statuscode (int): Never 1.
            axis (int | None | Unset): Axis (1..6) for software-limit errors.
            errors (list[SchemaViolation] | None | Unset): For `invalid_input` against a plugin's request schema: each
                violation
                (at most 10).
            file (None | str | Unset): For KRL program errors: the uploaded file (`src` or `dat`) of `line`.
            job_id (int | None | Unset):
            line (int | None | Unset): For KRL program errors: the 1-based line in the uploaded file.
            motion (int | None | Unset): Index of the failing motion in the batch.
            plugin (None | str | Unset): On a plugin route: the plugin that answered or whose request was refused.
            request_id (None | str | Unset): The request's id (also the `x-request-id` header): the service log
                has the request's internal details (paths, operating system errors)
                under it.
     """

    code: str
    detail: str
    status: int
    title: str
    type_: str
    position: list[float]
    statuscode: int
    axis: int | None | Unset = UNSET
    errors: list[SchemaViolation] | None | Unset = UNSET
    file: None | str | Unset = UNSET
    job_id: int | None | Unset = UNSET
    line: int | None | Unset = UNSET
    motion: int | None | Unset = UNSET
    plugin: None | str | Unset = UNSET
    request_id: None | str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.schema_violation import SchemaViolation # noqa: PLC0415
        code = self.code

        detail = self.detail

        status = self.status

        title = self.title

        type_ = self.type_

        position = self.position



        statuscode = self.statuscode

        axis: int | None | Unset
        if isinstance(self.axis, Unset):
            axis = UNSET
        else:
            axis = self.axis

        errors: list[dict[str, Any]] | None | Unset
        if isinstance(self.errors, Unset):
            errors = UNSET
        elif isinstance(self.errors, list):
            errors = []
            for errors_type_0_item_data in self.errors:
                errors_type_0_item = errors_type_0_item_data.to_dict()
                errors.append(errors_type_0_item)


        else:
            errors = self.errors

        file: None | str | Unset
        if isinstance(self.file, Unset):
            file = UNSET
        else:
            file = self.file

        job_id: int | None | Unset
        if isinstance(self.job_id, Unset):
            job_id = UNSET
        else:
            job_id = self.job_id

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

        plugin: None | str | Unset
        if isinstance(self.plugin, Unset):
            plugin = UNSET
        else:
            plugin = self.plugin

        request_id: None | str | Unset
        if isinstance(self.request_id, Unset):
            request_id = UNSET
        else:
            request_id = self.request_id


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "code": code,
            "detail": detail,
            "status": status,
            "title": title,
            "type": type_,
            "position": position,
            "statuscode": statuscode,
        })
        if axis is not UNSET:
            field_dict["axis"] = axis
        if errors is not UNSET:
            field_dict["errors"] = errors
        if file is not UNSET:
            field_dict["file"] = file
        if job_id is not UNSET:
            field_dict["job_id"] = job_id
        if line is not UNSET:
            field_dict["line"] = line
        if motion is not UNSET:
            field_dict["motion"] = motion
        if plugin is not UNSET:
            field_dict["plugin"] = plugin
        if request_id is not UNSET:
            field_dict["request_id"] = request_id

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.schema_violation import SchemaViolation # noqa: PLC0415
        d = dict(src_dict)
        code = d.pop("code")

        detail = d.pop("detail")

        status = d.pop("status")

        title = d.pop("title")

        type_ = d.pop("type")

        position = cast(list[float], d.pop("position"))


        statuscode = d.pop("statuscode")

        def _parse_axis(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        axis = _parse_axis(d.pop("axis", UNSET))


        def _parse_errors(data: object) -> list[SchemaViolation] | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, list):
                    raise TypeError()
                errors_type_0 = []
                _errors_type_0 = data
                for errors_type_0_item_data in (_errors_type_0):
                    errors_type_0_item = SchemaViolation.from_dict(errors_type_0_item_data)



                    errors_type_0.append(errors_type_0_item)

                return errors_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(list[SchemaViolation] | None | Unset, data)

        errors = _parse_errors(d.pop("errors", UNSET))


        def _parse_file(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        file = _parse_file(d.pop("file", UNSET))


        def _parse_job_id(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        job_id = _parse_job_id(d.pop("job_id", UNSET))


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


        def _parse_plugin(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        plugin = _parse_plugin(d.pop("plugin", UNSET))


        def _parse_request_id(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        request_id = _parse_request_id(d.pop("request_id", UNSET))


        thesis_problem = cls(
            code=code,
            detail=detail,
            status=status,
            title=title,
            type_=type_,
            position=position,
            statuscode=statuscode,
            axis=axis,
            errors=errors,
            file=file,
            job_id=job_id,
            line=line,
            motion=motion,
            plugin=plugin,
            request_id=request_id,
        )


        thesis_problem.additional_properties = d
        return thesis_problem

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
