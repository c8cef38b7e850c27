from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="RunRequest")



@_attrs_define
class RunRequest:
    """ Options of a run.

        Attributes:
            timeout_ms (int | None | Unset): Job timeout in ms (default `programs.run_timeout_ms`, one hour).
            wait (bool | None | Unset): Wait for the program to end (default true); false answers 202 with the job.
     """

    timeout_ms: int | None | Unset = UNSET
    wait: bool | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        timeout_ms: int | None | Unset
        if isinstance(self.timeout_ms, Unset):
            timeout_ms = UNSET
        else:
            timeout_ms = self.timeout_ms

        wait: bool | None | Unset
        if isinstance(self.wait, Unset):
            wait = UNSET
        else:
            wait = self.wait


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if timeout_ms is not UNSET:
            field_dict["timeout_ms"] = timeout_ms
        if wait is not UNSET:
            field_dict["wait"] = wait

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_timeout_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        timeout_ms = _parse_timeout_ms(d.pop("timeout_ms", UNSET))


        def _parse_wait(data: object) -> bool | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(bool | None | Unset, data)

        wait = _parse_wait(d.pop("wait", UNSET))


        run_request = cls(
            timeout_ms=timeout_ms,
            wait=wait,
        )

        return run_request

