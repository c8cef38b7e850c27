from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="ProgramInfo")



@_attrs_define
class ProgramInfo:
    """ What the service knows about a stored program.

        Attributes:
            bytes_ (int): Size of `.src` plus `.dat` in bytes.
            entry (str): The routine a run calls.
            entry_kind (str): `def` or `deffct`.
            name (str): Program name.
            simulator_checked (bool): Checked against what the simulated controller can run (true when the
                service runs a simulator, native or KRC-like; a real controller runs
                all of KRL).
            src_lines (int): Lines of the `.src`.
            uploaded_ms (int): Upload time (ms since the Unix epoch).
            dat_lines (int | None | Unset): Lines of the `.dat`, if there is one.
     """

    bytes_: int
    entry: str
    entry_kind: str
    name: str
    simulator_checked: bool
    src_lines: int
    uploaded_ms: int
    dat_lines: int | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        bytes_ = self.bytes_

        entry = self.entry

        entry_kind = self.entry_kind

        name = self.name

        simulator_checked = self.simulator_checked

        src_lines = self.src_lines

        uploaded_ms = self.uploaded_ms

        dat_lines: int | None | Unset
        if isinstance(self.dat_lines, Unset):
            dat_lines = UNSET
        else:
            dat_lines = self.dat_lines


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "bytes": bytes_,
            "entry": entry,
            "entry_kind": entry_kind,
            "name": name,
            "simulator_checked": simulator_checked,
            "src_lines": src_lines,
            "uploaded_ms": uploaded_ms,
        })
        if dat_lines is not UNSET:
            field_dict["dat_lines"] = dat_lines

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        bytes_ = d.pop("bytes")

        entry = d.pop("entry")

        entry_kind = d.pop("entry_kind")

        name = d.pop("name")

        simulator_checked = d.pop("simulator_checked")

        src_lines = d.pop("src_lines")

        uploaded_ms = d.pop("uploaded_ms")

        def _parse_dat_lines(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        dat_lines = _parse_dat_lines(d.pop("dat_lines", UNSET))


        program_info = cls(
            bytes_=bytes_,
            entry=entry,
            entry_kind=entry_kind,
            name=name,
            simulator_checked=simulator_checked,
            src_lines=src_lines,
            uploaded_ms=uploaded_ms,
            dat_lines=dat_lines,
        )


        program_info.additional_properties = d
        return program_info

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
