from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="ProgramUpload")



@_attrs_define
class ProgramUpload:
    """ An upload: a program's name, its `.src` text, an optional `.dat` and
    the routine to run.

        Example:
            {'name': 'wave', 'src': 'DEF wave()\\n  PTP {A1 10}\\n  PTP {A1 -10}\\nEND\\n'}

        Attributes:
            name (str): Program name: a KRL name (letter or `_` first, then letters, digits,
                `_`; at most 24 characters). Case-insensitive; an upload with an
                existing name replaces that program.
            src (str): The `.src` text.
            dat (None | str | Unset): The `.dat` text (its `DEFDAT` must carry the first routine's name).
            entry (None | str | Unset): Routine to run (no parameters). Default: `fuploaded` if the file
                defines it (the thesis convention), else the first routine.
     """

    name: str
    src: str
    dat: None | str | Unset = UNSET
    entry: None | str | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        name = self.name

        src = self.src

        dat: None | str | Unset
        if isinstance(self.dat, Unset):
            dat = UNSET
        else:
            dat = self.dat

        entry: None | str | Unset
        if isinstance(self.entry, Unset):
            entry = UNSET
        else:
            entry = self.entry


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "name": name,
            "src": src,
        })
        if dat is not UNSET:
            field_dict["dat"] = dat
        if entry is not UNSET:
            field_dict["entry"] = entry

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        name = d.pop("name")

        src = d.pop("src")

        def _parse_dat(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        dat = _parse_dat(d.pop("dat", UNSET))


        def _parse_entry(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        entry = _parse_entry(d.pop("entry", UNSET))


        program_upload = cls(
            name=name,
            src=src,
            dat=dat,
            entry=entry,
        )

        return program_upload

