from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.connection import Connection
from typing import cast

if TYPE_CHECKING:
  from ..models.bridge_error import BridgeError





T = TypeVar("T", bound="Health")



@_attrs_define
class Health:
    """ Service health.

        Example:
            {'status': 'ok', 'version': '0.1.0', 'connection': 'online', 'simulated': True, 'degraded': []}

        Attributes:
            connection (Connection): Connection to the controller.
            degraded (list[BridgeError]): Why commands cannot be sent now, each with a stable `code` and a
                sentence (empty when `status` is `ok`); the same list as
                `degraded` in `/api/v1/state`.
            simulated (bool): True when running on the embedded simulator.
            status (str): `ok` when commands can be sent; `degraded` when something stops
                them (the reasons are in `degraded`).
            version (str): Service version.
     """

    connection: Connection
    degraded: list[BridgeError]
    simulated: bool
    status: str
    version: str
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        connection = self.connection.value

        degraded = []
        for degraded_item_data in self.degraded:
            degraded_item = degraded_item_data.to_dict()
            degraded.append(degraded_item)



        simulated = self.simulated

        status = self.status

        version = self.version


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "connection": connection,
            "degraded": degraded,
            "simulated": simulated,
            "status": status,
            "version": version,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        d = dict(src_dict)
        connection = Connection(d.pop("connection"))




        degraded = []
        _degraded = d.pop("degraded")
        for degraded_item_data in (_degraded):
            degraded_item = BridgeError.from_dict(degraded_item_data)



            degraded.append(degraded_item)


        simulated = d.pop("simulated")

        status = d.pop("status")

        version = d.pop("version")

        health = cls(
            connection=connection,
            degraded=degraded,
            simulated=simulated,
            status=status,
            version=version,
        )


        health.additional_properties = d
        return health

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
