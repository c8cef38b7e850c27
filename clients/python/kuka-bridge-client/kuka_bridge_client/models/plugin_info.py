from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.error_body import ErrorBody
  from ..models.limits_info import LimitsInfo
  from ..models.plugin_route_info import PluginRouteInfo





T = TypeVar("T", bound="PluginInfo")



@_attrs_define
class PluginInfo:
    """ An installed plugin, as listed by `GET /api/v1/plugins`.

        Example:
            {'name': 'draw-circle', 'version': '0.1.0', 'status': 'active', 'routes': [{'method': 'POST', 'url':
                '/api/v1/plugins/draw-circle/circle', 'summary': 'Draw a circle'}], 'sha256': '3f1c…', 'wasm_bytes': 134326,
                'load_ms': 1.2, 'from_cache': True, 'limits': {'memory_mib': 64, 'cpu_time_ms': 2000, 'request_timeout_ms':
                120000, 'max_motions': 1000}}

        Attributes:
            limits (LimitsInfo): A plugin's limits, as listed.
            name (str): Its name (the URL prefix and the file name `<name>.wasm`).
            routes (list[PluginRouteInfo]): Its routes.
            status (str): `active` (serving), or `failed` (its file could not be loaded and no
                earlier version is active).
            file_error (ErrorBody | None | Unset):
            from_cache (bool | None | Unset): Its compiled code came from the cache.
            load_ms (float | None | Unset): Time to load it (compile or take from the cache, link, describe), ms.
            sha256 (None | str | Unset): SHA-256 of the active .wasm.
            version (None | str | Unset): The version it describes (of the active code).
            wasm_bytes (int | None | Unset): Size of the active .wasm.
     """

    limits: LimitsInfo
    name: str
    routes: list[PluginRouteInfo]
    status: str
    file_error: ErrorBody | None | Unset = UNSET
    from_cache: bool | None | Unset = UNSET
    load_ms: float | None | Unset = UNSET
    sha256: None | str | Unset = UNSET
    version: None | str | Unset = UNSET
    wasm_bytes: int | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.error_body import ErrorBody # noqa: PLC0415
        from ..models.limits_info import LimitsInfo # noqa: PLC0415
        from ..models.plugin_route_info import PluginRouteInfo # noqa: PLC0415
        limits = self.limits.to_dict()

        name = self.name

        routes = []
        for routes_item_data in self.routes:
            routes_item = routes_item_data.to_dict()
            routes.append(routes_item)



        status = self.status

        file_error: dict[str, Any] | None | Unset
        if isinstance(self.file_error, Unset):
            file_error = UNSET
        elif isinstance(self.file_error, ErrorBody):
            file_error = self.file_error.to_dict()
        else:
            file_error = self.file_error

        from_cache: bool | None | Unset
        if isinstance(self.from_cache, Unset):
            from_cache = UNSET
        else:
            from_cache = self.from_cache

        load_ms: float | None | Unset
        if isinstance(self.load_ms, Unset):
            load_ms = UNSET
        else:
            load_ms = self.load_ms

        sha256: None | str | Unset
        if isinstance(self.sha256, Unset):
            sha256 = UNSET
        else:
            sha256 = self.sha256

        version: None | str | Unset
        if isinstance(self.version, Unset):
            version = UNSET
        else:
            version = self.version

        wasm_bytes: int | None | Unset
        if isinstance(self.wasm_bytes, Unset):
            wasm_bytes = UNSET
        else:
            wasm_bytes = self.wasm_bytes


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "limits": limits,
            "name": name,
            "routes": routes,
            "status": status,
        })
        if file_error is not UNSET:
            field_dict["file_error"] = file_error
        if from_cache is not UNSET:
            field_dict["from_cache"] = from_cache
        if load_ms is not UNSET:
            field_dict["load_ms"] = load_ms
        if sha256 is not UNSET:
            field_dict["sha256"] = sha256
        if version is not UNSET:
            field_dict["version"] = version
        if wasm_bytes is not UNSET:
            field_dict["wasm_bytes"] = wasm_bytes

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.error_body import ErrorBody # noqa: PLC0415
        from ..models.limits_info import LimitsInfo # noqa: PLC0415
        from ..models.plugin_route_info import PluginRouteInfo # noqa: PLC0415
        d = dict(src_dict)
        limits = LimitsInfo.from_dict(d.pop("limits"))




        name = d.pop("name")

        routes = []
        _routes = d.pop("routes")
        for routes_item_data in (_routes):
            routes_item = PluginRouteInfo.from_dict(routes_item_data)



            routes.append(routes_item)


        status = d.pop("status")

        def _parse_file_error(data: object) -> ErrorBody | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                file_error_type_0 = ErrorBody.from_dict(data)



                return file_error_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(ErrorBody | None | Unset, data)

        file_error = _parse_file_error(d.pop("file_error", UNSET))


        def _parse_from_cache(data: object) -> bool | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(bool | None | Unset, data)

        from_cache = _parse_from_cache(d.pop("from_cache", UNSET))


        def _parse_load_ms(data: object) -> float | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | None | Unset, data)

        load_ms = _parse_load_ms(d.pop("load_ms", UNSET))


        def _parse_sha256(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        sha256 = _parse_sha256(d.pop("sha256", UNSET))


        def _parse_version(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        version = _parse_version(d.pop("version", UNSET))


        def _parse_wasm_bytes(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        wasm_bytes = _parse_wasm_bytes(d.pop("wasm_bytes", UNSET))


        plugin_info = cls(
            limits=limits,
            name=name,
            routes=routes,
            status=status,
            file_error=file_error,
            from_cache=from_cache,
            load_ms=load_ms,
            sha256=sha256,
            version=version,
            wasm_bytes=wasm_bytes,
        )


        plugin_info.additional_properties = d
        return plugin_info

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
