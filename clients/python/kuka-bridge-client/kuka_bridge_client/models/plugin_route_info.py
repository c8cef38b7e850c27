from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset







T = TypeVar("T", bound="PluginRouteInfo")



@_attrs_define
class PluginRouteInfo:
    """ A route of an installed plugin, as listed.

        Attributes:
            method (str): `GET` or `POST`.
            summary (str): The plugin's summary of the route.
            url (str): The full URL path, e.g. `/api/v1/plugins/draw-circle/circle`.
     """

    method: str
    summary: str
    url: str
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        method = self.method

        summary = self.summary

        url = self.url


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "method": method,
            "summary": summary,
            "url": url,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        method = d.pop("method")

        summary = d.pop("summary")

        url = d.pop("url")

        plugin_route_info = cls(
            method=method,
            summary=summary,
            url=url,
        )


        plugin_route_info.additional_properties = d
        return plugin_route_info

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
