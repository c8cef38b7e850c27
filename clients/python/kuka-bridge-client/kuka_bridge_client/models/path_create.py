from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.configuration import Configuration
from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="PathCreate")



@_attrs_define
class PathCreate:
    """ Opening a path.

        Example:
            {'config': 'auto'}

        Attributes:
            config (Configuration | None | Unset):
     """

    config: Configuration | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        config: None | str | Unset
        if isinstance(self.config, Unset):
            config = UNSET
        elif isinstance(self.config, Configuration):
            config = self.config.value
        else:
            config = self.config


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if config is not UNSET:
            field_dict["config"] = config

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        def _parse_config(data: object) -> Configuration | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                config_type_0 = Configuration(data)



                return config_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(Configuration | None | Unset, data)

        config = _parse_config(d.pop("config", UNSET))


        path_create = cls(
            config=config,
        )

        return path_create

