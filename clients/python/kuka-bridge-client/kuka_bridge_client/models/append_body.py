from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.axis_motion import AxisMotion
  from ..models.circ_motion import CircMotion
  from ..models.dwell_action import DwellAction
  from ..models.lin_motion import LinMotion
  from ..models.ptp_motion import PtpMotion
  from ..models.scirc_motion import ScircMotion
  from ..models.set_output_action import SetOutputAction
  from ..models.slin_motion import SlinMotion
  from ..models.spl_motion import SplMotion
  from ..models.sptp_axis_motion import SptpAxisMotion
  from ..models.sptp_motion import SptpMotion
  from ..models.wait_input_action import WaitInputAction





T = TypeVar("T", bound="AppendBody")



@_attrs_define
class AppendBody:
    """ Motions to append.

        Example:
            {'motions': [{'type': 'lin', 'target': {'x': 200, 'y': 10}, 'velocity_m_s': 0.2}, {'type': 'lin', 'target':
                {'x': 210, 'y': 20}, 'velocity_m_s': 0.2}], 'close': False}

        Attributes:
            close (bool | Unset): Close the path after these motions: it ends when they have run.
            motions (list[AxisMotion | CircMotion | DwellAction | LinMotion | PtpMotion | ScircMotion | SetOutputAction |
                SlinMotion | SplMotion | SptpAxisMotion | SptpMotion | WaitInputAction] | Unset): The motions, in order; they
                are approximated into each other and
                into what follows (`approx_mm` default of the site) unless they set
                `approx_mm`. May be empty (with `close`).
            wait_ms (int | None | Unset): How long to wait for room while the path's buffer is full (ms,
                default 30000); then `path_full` with `Retry-After`.
     """

    close: bool | Unset = UNSET
    motions: list[AxisMotion | CircMotion | DwellAction | LinMotion | PtpMotion | ScircMotion | SetOutputAction | SlinMotion | SplMotion | SptpAxisMotion | SptpMotion | WaitInputAction] | Unset = UNSET
    wait_ms: int | None | Unset = UNSET





    def to_dict(self) -> dict[str, Any]:
        from ..models.axis_motion import AxisMotion # noqa: PLC0415
        from ..models.circ_motion import CircMotion # noqa: PLC0415
        from ..models.dwell_action import DwellAction # noqa: PLC0415
        from ..models.lin_motion import LinMotion # noqa: PLC0415
        from ..models.ptp_motion import PtpMotion # noqa: PLC0415
        from ..models.scirc_motion import ScircMotion # noqa: PLC0415
        from ..models.set_output_action import SetOutputAction # noqa: PLC0415
        from ..models.slin_motion import SlinMotion # noqa: PLC0415
        from ..models.spl_motion import SplMotion # noqa: PLC0415
        from ..models.sptp_axis_motion import SptpAxisMotion # noqa: PLC0415
        from ..models.sptp_motion import SptpMotion # noqa: PLC0415
        from ..models.wait_input_action import WaitInputAction # noqa: PLC0415
        close = self.close

        motions: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.motions, Unset):
            motions = []
            for motions_item_data in self.motions:
                motions_item: dict[str, Any]
                if isinstance(motions_item_data, PtpMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, AxisMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, LinMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, CircMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, SlinMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, ScircMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, SptpMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, SptpAxisMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, SplMotion):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, SetOutputAction):
                    motions_item = motions_item_data.to_dict()
                elif isinstance(motions_item_data, WaitInputAction):
                    motions_item = motions_item_data.to_dict()
                else:
                    motions_item = motions_item_data.to_dict()

                motions.append(motions_item)



        wait_ms: int | None | Unset
        if isinstance(self.wait_ms, Unset):
            wait_ms = UNSET
        else:
            wait_ms = self.wait_ms


        field_dict: dict[str, Any] = {}

        field_dict.update({
        })
        if close is not UNSET:
            field_dict["close"] = close
        if motions is not UNSET:
            field_dict["motions"] = motions
        if wait_ms is not UNSET:
            field_dict["wait_ms"] = wait_ms

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.axis_motion import AxisMotion # noqa: PLC0415
        from ..models.circ_motion import CircMotion # noqa: PLC0415
        from ..models.dwell_action import DwellAction # noqa: PLC0415
        from ..models.lin_motion import LinMotion # noqa: PLC0415
        from ..models.ptp_motion import PtpMotion # noqa: PLC0415
        from ..models.scirc_motion import ScircMotion # noqa: PLC0415
        from ..models.set_output_action import SetOutputAction # noqa: PLC0415
        from ..models.slin_motion import SlinMotion # noqa: PLC0415
        from ..models.spl_motion import SplMotion # noqa: PLC0415
        from ..models.sptp_axis_motion import SptpAxisMotion # noqa: PLC0415
        from ..models.sptp_motion import SptpMotion # noqa: PLC0415
        from ..models.wait_input_action import WaitInputAction # noqa: PLC0415
        d = dict(src_dict)
        close = d.pop("close", UNSET)

        _motions = d.pop("motions", UNSET)
        motions: list[AxisMotion | CircMotion | DwellAction | LinMotion | PtpMotion | ScircMotion | SetOutputAction | SlinMotion | SplMotion | SptpAxisMotion | SptpMotion | WaitInputAction] | Unset = UNSET
        if _motions is not UNSET:
            motions = []
            for motions_item_data in _motions:
                def _parse_motions_item(data: object) -> AxisMotion | CircMotion | DwellAction | LinMotion | PtpMotion | ScircMotion | SetOutputAction | SlinMotion | SplMotion | SptpAxisMotion | SptpMotion | WaitInputAction:
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_0 = PtpMotion.from_dict(data)



                        return componentsschemas_motion_request_type_0
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_1 = AxisMotion.from_dict(data)



                        return componentsschemas_motion_request_type_1
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_2 = LinMotion.from_dict(data)



                        return componentsschemas_motion_request_type_2
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_3 = CircMotion.from_dict(data)



                        return componentsschemas_motion_request_type_3
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_4 = SlinMotion.from_dict(data)



                        return componentsschemas_motion_request_type_4
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_5 = ScircMotion.from_dict(data)



                        return componentsschemas_motion_request_type_5
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_6 = SptpMotion.from_dict(data)



                        return componentsschemas_motion_request_type_6
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_7 = SptpAxisMotion.from_dict(data)



                        return componentsschemas_motion_request_type_7
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_8 = SplMotion.from_dict(data)



                        return componentsschemas_motion_request_type_8
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_9 = SetOutputAction.from_dict(data)



                        return componentsschemas_motion_request_type_9
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    try:
                        if not isinstance(data, dict):
                            raise TypeError()
                        componentsschemas_motion_request_type_10 = WaitInputAction.from_dict(data)



                        return componentsschemas_motion_request_type_10
                    except (TypeError, ValueError, AttributeError, KeyError):
                        pass
                    if not isinstance(data, dict):
                        raise TypeError()
                    componentsschemas_motion_request_type_11 = DwellAction.from_dict(data)



                    return componentsschemas_motion_request_type_11

                motions_item = _parse_motions_item(motions_item_data)

                motions.append(motions_item)


        def _parse_wait_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        wait_ms = _parse_wait_ms(d.pop("wait_ms", UNSET))


        append_body = cls(
            close=close,
            motions=motions,
            wait_ms=wait_ms,
        )

        return append_body

