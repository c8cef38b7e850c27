from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.lease import Lease
  from ..models.principal import Principal





T = TypeVar("T", bound="ControlState")



@_attrs_define
class ControlState:
    """ Who holds control.

        Example:
            {'lease': None, 'auth': True, 'you': {'name': 'line-3-pc', 'role': 'operator'}}

        Attributes:
            auth (bool): Whether tokens are required (without them everyone is `anonymous`
                and control changes nothing).
            you (Principal): Who is making a request.
            lease (Lease | None | Unset):
     """

    auth: bool
    you: Principal
    lease: Lease | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.lease import Lease # noqa: PLC0415
        from ..models.principal import Principal # noqa: PLC0415
        auth = self.auth

        you = self.you.to_dict()

        lease: dict[str, Any] | None | Unset
        if isinstance(self.lease, Unset):
            lease = UNSET
        elif isinstance(self.lease, Lease):
            lease = self.lease.to_dict()
        else:
            lease = self.lease


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "auth": auth,
            "you": you,
        })
        if lease is not UNSET:
            field_dict["lease"] = lease

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.lease import Lease # noqa: PLC0415
        from ..models.principal import Principal # noqa: PLC0415
        d = dict(src_dict)
        auth = d.pop("auth")

        you = Principal.from_dict(d.pop("you"))




        def _parse_lease(data: object) -> Lease | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                lease_type_0 = Lease.from_dict(data)



                return lease_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(Lease | None | Unset, data)

        lease = _parse_lease(d.pop("lease", UNSET))


        control_state = cls(
            auth=auth,
            you=you,
            lease=lease,
        )


        control_state.additional_properties = d
        return control_state

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
