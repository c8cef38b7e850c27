from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.bridge_error import BridgeError
  from ..models.controller_safety import ControllerSafety





T = TypeVar("T", bound="ControllerInfo")



@_attrs_define
class ControllerInfo:
    """ What the controller reports about itself.

        Attributes:
            mode (str): `T1`, `T2`, `AUT`, `EXT` or `unknown`.
            override_pct (float): Program override in %.
            simulated (bool): True when the controller is the simulator.
            status (str): `idle`, `busy`, `error` or `unknown`.
            error (BridgeError | None | Unset):
            heartbeat_age_ms (int | None | Unset): Milliseconds since the heartbeat last changed.
            heartbeat_seq (int | None | Unset): Last heartbeat sequence number.
            last_cid (int | None | Unset): Highest command id the controller has accepted.
            safety (ControllerSafety | None | Unset):
     """

    mode: str
    override_pct: float
    simulated: bool
    status: str
    error: BridgeError | None | Unset = UNSET
    heartbeat_age_ms: int | None | Unset = UNSET
    heartbeat_seq: int | None | Unset = UNSET
    last_cid: int | None | Unset = UNSET
    safety: ControllerSafety | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        from ..models.controller_safety import ControllerSafety # noqa: PLC0415
        mode = self.mode

        override_pct = self.override_pct

        simulated = self.simulated

        status = self.status

        error: dict[str, Any] | None | Unset
        if isinstance(self.error, Unset):
            error = UNSET
        elif isinstance(self.error, BridgeError):
            error = self.error.to_dict()
        else:
            error = self.error

        heartbeat_age_ms: int | None | Unset
        if isinstance(self.heartbeat_age_ms, Unset):
            heartbeat_age_ms = UNSET
        else:
            heartbeat_age_ms = self.heartbeat_age_ms

        heartbeat_seq: int | None | Unset
        if isinstance(self.heartbeat_seq, Unset):
            heartbeat_seq = UNSET
        else:
            heartbeat_seq = self.heartbeat_seq

        last_cid: int | None | Unset
        if isinstance(self.last_cid, Unset):
            last_cid = UNSET
        else:
            last_cid = self.last_cid

        safety: dict[str, Any] | None | Unset
        if isinstance(self.safety, Unset):
            safety = UNSET
        elif isinstance(self.safety, ControllerSafety):
            safety = self.safety.to_dict()
        else:
            safety = self.safety


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "mode": mode,
            "override_pct": override_pct,
            "simulated": simulated,
            "status": status,
        })
        if error is not UNSET:
            field_dict["error"] = error
        if heartbeat_age_ms is not UNSET:
            field_dict["heartbeat_age_ms"] = heartbeat_age_ms
        if heartbeat_seq is not UNSET:
            field_dict["heartbeat_seq"] = heartbeat_seq
        if last_cid is not UNSET:
            field_dict["last_cid"] = last_cid
        if safety is not UNSET:
            field_dict["safety"] = safety

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        from ..models.controller_safety import ControllerSafety # noqa: PLC0415
        d = dict(src_dict)
        mode = d.pop("mode")

        override_pct = d.pop("override_pct")

        simulated = d.pop("simulated")

        status = d.pop("status")

        def _parse_error(data: object) -> BridgeError | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                error_type_0 = BridgeError.from_dict(data)



                return error_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(BridgeError | None | Unset, data)

        error = _parse_error(d.pop("error", UNSET))


        def _parse_heartbeat_age_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        heartbeat_age_ms = _parse_heartbeat_age_ms(d.pop("heartbeat_age_ms", UNSET))


        def _parse_heartbeat_seq(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        heartbeat_seq = _parse_heartbeat_seq(d.pop("heartbeat_seq", UNSET))


        def _parse_last_cid(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        last_cid = _parse_last_cid(d.pop("last_cid", UNSET))


        def _parse_safety(data: object) -> ControllerSafety | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                safety_type_0 = ControllerSafety.from_dict(data)



                return safety_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(ControllerSafety | None | Unset, data)

        safety = _parse_safety(d.pop("safety", UNSET))


        controller_info = cls(
            mode=mode,
            override_pct=override_pct,
            simulated=simulated,
            status=status,
            error=error,
            heartbeat_age_ms=heartbeat_age_ms,
            heartbeat_seq=heartbeat_seq,
            last_cid=last_cid,
            safety=safety,
        )


        controller_info.additional_properties = d
        return controller_info

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
