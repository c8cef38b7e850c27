from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.configuration import Configuration
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





T = TypeVar("T", bound="MotionBatch")



@_attrs_define
class MotionBatch:
    """ A motion request: one motion or a continuous batch.

        Example:
            {'motions': [{'type': 'ptp', 'target': {'x': 200, 'y': 0, 'z': 100, 'a': 0, 'b': 180, 'c': 0}}, {'type': 'lin',
                'target': {'z': 70}, 'velocity_m_s': 0.1}, {'type': 'circ', 'aux': {'x': 250, 'y': 50}, 'target': {'x': 200,
                'y': 100}, 'approx_mm': 2}, {'type': 'lin', 'target': {'z': 100}}], 'wait': True}

        Attributes:
            motions (list[AxisMotion | CircMotion | DwellAction | LinMotion | PtpMotion | ScircMotion | SetOutputAction |
                SlinMotion | SplMotion | SptpAxisMotion | SptpMotion | WaitInputAction]): The motions, executed in order as one
                continuous batch (approximated
                between motions unless `approx_mm` is 0).
            config (Configuration | None | Unset):
            timeout_ms (int | None | Unset): Fail the job (and stop the robot) if it has not finished after this many ms.
            wait (bool | None | Unset): Wait for completion (default true). With false the answer is 202
                with the queued job; poll `/api/v1/jobs/{id}` or listen to events.
     """

    motions: list[AxisMotion | CircMotion | DwellAction | LinMotion | PtpMotion | ScircMotion | SetOutputAction | SlinMotion | SplMotion | SptpAxisMotion | SptpMotion | WaitInputAction]
    config: Configuration | None | Unset = UNSET
    timeout_ms: int | None | Unset = UNSET
    wait: bool | None | Unset = UNSET





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



        config: None | str | Unset
        if isinstance(self.config, Unset):
            config = UNSET
        elif isinstance(self.config, Configuration):
            config = self.config.value
        else:
            config = self.config

        timeout_ms: int | None | Unset
        if isinstance(self.timeout_ms, Unset):
            timeout_ms = UNSET
        else:
            timeout_ms = self.timeout_ms

        wait: bool | None | Unset
        if isinstance(self.wait, Unset):
            wait = UNSET
        else:
            wait = self.wait


        field_dict: dict[str, Any] = {}

        field_dict.update({
            "motions": motions,
        })
        if config is not UNSET:
            field_dict["config"] = config
        if timeout_ms is not UNSET:
            field_dict["timeout_ms"] = timeout_ms
        if wait is not UNSET:
            field_dict["wait"] = wait

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
        motions = []
        _motions = d.pop("motions")
        for motions_item_data in (_motions):
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


        def _parse_timeout_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        timeout_ms = _parse_timeout_ms(d.pop("timeout_ms", UNSET))


        def _parse_wait(data: object) -> bool | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(bool | None | Unset, data)

        wait = _parse_wait(d.pop("wait", UNSET))


        motion_batch = cls(
            motions=motions,
            config=config,
            timeout_ms=timeout_ms,
            wait=wait,
        )

        return motion_batch

