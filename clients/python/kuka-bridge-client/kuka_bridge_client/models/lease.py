from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.role import Role






T = TypeVar("T", bound="Lease")



@_attrs_define
class Lease:
    """ A live lease, as the API shows it.

        Example:
            {'id': '5f1c0a9e2b7d4c31', 'holder': 'line-3-pc', 'role': 'operator', 'acquired_ms': 1763856000000,
                'expires_ms': 1763856030000, 'lease_ms': 30000}

        Attributes:
            acquired_ms (int): When control was taken (Unix ms).
            expires_ms (int): When the lease lapses unless renewed (Unix ms).
            holder (str): The token name holding control.
            id (str): Lease id (changes when control changes hands).
            lease_ms (int): Lease length; each mutating call of the holder renews it.
            role (Role): A token's role; each includes the ones below it.
     """

    acquired_ms: int
    expires_ms: int
    holder: str
    id: str
    lease_ms: int
    role: Role
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        acquired_ms = self.acquired_ms

        expires_ms = self.expires_ms

        holder = self.holder

        id = self.id

        lease_ms = self.lease_ms

        role = self.role.value


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "acquired_ms": acquired_ms,
            "expires_ms": expires_ms,
            "holder": holder,
            "id": id,
            "lease_ms": lease_ms,
            "role": role,
        })

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        acquired_ms = d.pop("acquired_ms")

        expires_ms = d.pop("expires_ms")

        holder = d.pop("holder")

        id = d.pop("id")

        lease_ms = d.pop("lease_ms")

        role = Role(d.pop("role"))




        lease = cls(
            acquired_ms=acquired_ms,
            expires_ms=expires_ms,
            holder=holder,
            id=id,
            lease_ms=lease_ms,
            role=role,
        )


        lease.additional_properties = d
        return lease

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
