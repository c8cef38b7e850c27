from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.role import Role
from ..types import UNSET, Unset
from typing import cast






T = TypeVar("T", bound="AuditRecord")



@_attrs_define
class AuditRecord:
    """ One audited request.

        Example:
            {'time_ms': 1763856000123, 'who': 'line-3-pc', 'role': 'operator', 'client': '10.0.3.17', 'method': 'POST',
                'path': '/api/v1/motions', 'route': '/api/v1/motions', 'params': {'body': {'motions': [{'type': 'ptp', 'target':
                {'x': 200, 'y': 0, 'z': 100}}]}}, 'jobs': [42], 'status': 200, 'duration_ms': 812.4}

        Attributes:
            client (str): Client address.
            duration_ms (float): Time to the answer (ms).
            method (str): HTTP method.
            params (Any): Query parameters and JSON body (bodies of other types by size only).
            path (str): Request path (no query string).
            role (Role): A token's role; each includes the ones below it.
            route (str): The route it matched.
            status (int): HTTP status of the answer.
            time_ms (int): When the request arrived (Unix ms).
            who (str): Token name (`anonymous` when auth is off).
            code (None | str | Unset): Problem code when it failed.
            jobs (list[int] | Unset): Jobs the request created.
     """

    client: str
    duration_ms: float
    method: str
    params: Any
    path: str
    role: Role
    route: str
    status: int
    time_ms: int
    who: str
    code: None | str | Unset = UNSET
    jobs: list[int] | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        client = self.client

        duration_ms = self.duration_ms

        method = self.method

        params = self.params

        path = self.path

        role = self.role.value

        route = self.route

        status = self.status

        time_ms = self.time_ms

        who = self.who

        code: None | str | Unset
        if isinstance(self.code, Unset):
            code = UNSET
        else:
            code = self.code

        jobs: list[int] | Unset = UNSET
        if not isinstance(self.jobs, Unset):
            jobs = self.jobs




        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "client": client,
            "duration_ms": duration_ms,
            "method": method,
            "params": params,
            "path": path,
            "role": role,
            "route": route,
            "status": status,
            "time_ms": time_ms,
            "who": who,
        })
        if code is not UNSET:
            field_dict["code"] = code
        if jobs is not UNSET:
            field_dict["jobs"] = jobs

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        client = d.pop("client")

        duration_ms = d.pop("duration_ms")

        method = d.pop("method")

        params = d.pop("params")

        path = d.pop("path")

        role = Role(d.pop("role"))




        route = d.pop("route")

        status = d.pop("status")

        time_ms = d.pop("time_ms")

        who = d.pop("who")

        def _parse_code(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        code = _parse_code(d.pop("code", UNSET))


        jobs = cast(list[int], d.pop("jobs", UNSET))


        audit_record = cls(
            client=client,
            duration_ms=duration_ms,
            method=method,
            params=params,
            path=path,
            role=role,
            route=route,
            status=status,
            time_ms=time_ms,
            who=who,
            code=code,
            jobs=jobs,
        )


        audit_record.additional_properties = d
        return audit_record

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
