from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, BinaryIO, TextIO, TYPE_CHECKING, Generator

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

from ..models.job_state import JobState
from ..types import UNSET, Unset
from typing import cast

if TYPE_CHECKING:
  from ..models.axis_angles import AxisAngles
  from ..models.bridge_error import BridgeError
  from ..models.cartesian_frame import CartesianFrame
  from ..models.path_progress import PathProgress
  from ..models.position import Position
  from ..models.ptp_configuration import PtpConfiguration





T = TypeVar("T", bound="Job")



@_attrs_define
class Job:
    """ A job as clients see it.

        Example:
            {'id': 7, 'operation': 'move', 'state': 'done', 'motions': 2, 'completed': 2, 'cid': 1042, 'created_ms':
                1795373060215, 'sent_ms': 1795373060221, 'finished_ms': 1795373060931, 'position': {'x': 250.0, 'y': 100.0, 'z':
                70.0, 'a': 180.0, 'b': 0.0, 'c': 180.0, 's': 6, 't': 51}, 'axes': {'a1': -21.801, 'a2': -13.511, 'a3': 108.689,
                'a4': 0.0, 'a5': -5.178, 'a6': -21.801}, 'frame': None, 'error': None}

        Attributes:
            completed (int): Motions completed so far.
            created_ms (int): Creation time (Unix ms).
            id (int): Job id.
            motions (int): Number of motions (for `move`).
            operation (str): Operation name (`move`, `home`, `get_position`, ...).
            state (JobState): Life of a job: queued → sent → executing → done | failed | cancelled.
            axes (AxisAngles | None | Unset):
            cid (int | None | Unset): Command id used on the channel, once sent.
            configurations (list[PtpConfiguration] | Unset): The arm configuration each Cartesian PTP of a move got (with a
                robot model): send these `s`/`t` to replay it exactly.
            error (BridgeError | None | Unset):
            finished_ms (int | None | Unset): When finished (Unix ms).
            frame (CartesianFrame | None | Unset):
            late_result (bool | Unset): True when the controller's result came after the job had already
                ended (reported `timeout` while the result file was unreadable, for
                example): `state`, `error` and `completed` are then the controller's
                own outcome, which replaced the earlier one.
            origin (None | str | Unset): Who asked for it when not an HTTP client directly: `plugin:<name>@<version>`.
            path (None | PathProgress | Unset):
            position (None | Position | Unset):
            requested_by (None | str | Unset): The token name of the client whose request created it (`anonymous`
                when auth is off).
            sent_ms (int | None | Unset): When written to the channel (Unix ms).
     """

    completed: int
    created_ms: int
    id: int
    motions: int
    operation: str
    state: JobState
    axes: AxisAngles | None | Unset = UNSET
    cid: int | None | Unset = UNSET
    configurations: list[PtpConfiguration] | Unset = UNSET
    error: BridgeError | None | Unset = UNSET
    finished_ms: int | None | Unset = UNSET
    frame: CartesianFrame | None | Unset = UNSET
    late_result: bool | Unset = UNSET
    origin: None | str | Unset = UNSET
    path: None | PathProgress | Unset = UNSET
    position: None | Position | Unset = UNSET
    requested_by: None | str | Unset = UNSET
    sent_ms: int | None | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)





    def to_dict(self) -> dict[str, Any]:
        from ..models.axis_angles import AxisAngles # noqa: PLC0415
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        from ..models.path_progress import PathProgress # noqa: PLC0415
        from ..models.position import Position # noqa: PLC0415
        from ..models.ptp_configuration import PtpConfiguration # noqa: PLC0415
        completed = self.completed

        created_ms = self.created_ms

        id = self.id

        motions = self.motions

        operation = self.operation

        state = self.state.value

        axes: dict[str, Any] | None | Unset
        if isinstance(self.axes, Unset):
            axes = UNSET
        elif isinstance(self.axes, AxisAngles):
            axes = self.axes.to_dict()
        else:
            axes = self.axes

        cid: int | None | Unset
        if isinstance(self.cid, Unset):
            cid = UNSET
        else:
            cid = self.cid

        configurations: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.configurations, Unset):
            configurations = []
            for configurations_item_data in self.configurations:
                configurations_item = configurations_item_data.to_dict()
                configurations.append(configurations_item)



        error: dict[str, Any] | None | Unset
        if isinstance(self.error, Unset):
            error = UNSET
        elif isinstance(self.error, BridgeError):
            error = self.error.to_dict()
        else:
            error = self.error

        finished_ms: int | None | Unset
        if isinstance(self.finished_ms, Unset):
            finished_ms = UNSET
        else:
            finished_ms = self.finished_ms

        frame: dict[str, Any] | None | Unset
        if isinstance(self.frame, Unset):
            frame = UNSET
        elif isinstance(self.frame, CartesianFrame):
            frame = self.frame.to_dict()
        else:
            frame = self.frame

        late_result = self.late_result

        origin: None | str | Unset
        if isinstance(self.origin, Unset):
            origin = UNSET
        else:
            origin = self.origin

        path: dict[str, Any] | None | Unset
        if isinstance(self.path, Unset):
            path = UNSET
        elif isinstance(self.path, PathProgress):
            path = self.path.to_dict()
        else:
            path = self.path

        position: dict[str, Any] | None | Unset
        if isinstance(self.position, Unset):
            position = UNSET
        elif isinstance(self.position, Position):
            position = self.position.to_dict()
        else:
            position = self.position

        requested_by: None | str | Unset
        if isinstance(self.requested_by, Unset):
            requested_by = UNSET
        else:
            requested_by = self.requested_by

        sent_ms: int | None | Unset
        if isinstance(self.sent_ms, Unset):
            sent_ms = UNSET
        else:
            sent_ms = self.sent_ms


        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({
            "completed": completed,
            "created_ms": created_ms,
            "id": id,
            "motions": motions,
            "operation": operation,
            "state": state,
        })
        if axes is not UNSET:
            field_dict["axes"] = axes
        if cid is not UNSET:
            field_dict["cid"] = cid
        if configurations is not UNSET:
            field_dict["configurations"] = configurations
        if error is not UNSET:
            field_dict["error"] = error
        if finished_ms is not UNSET:
            field_dict["finished_ms"] = finished_ms
        if frame is not UNSET:
            field_dict["frame"] = frame
        if late_result is not UNSET:
            field_dict["late_result"] = late_result
        if origin is not UNSET:
            field_dict["origin"] = origin
        if path is not UNSET:
            field_dict["path"] = path
        if position is not UNSET:
            field_dict["position"] = position
        if requested_by is not UNSET:
            field_dict["requested_by"] = requested_by
        if sent_ms is not UNSET:
            field_dict["sent_ms"] = sent_ms

        return field_dict



    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.axis_angles import AxisAngles # noqa: PLC0415
        from ..models.bridge_error import BridgeError # noqa: PLC0415
        from ..models.cartesian_frame import CartesianFrame # noqa: PLC0415
        from ..models.path_progress import PathProgress # noqa: PLC0415
        from ..models.position import Position # noqa: PLC0415
        from ..models.ptp_configuration import PtpConfiguration # noqa: PLC0415
        d = dict(src_dict)
        completed = d.pop("completed")

        created_ms = d.pop("created_ms")

        id = d.pop("id")

        motions = d.pop("motions")

        operation = d.pop("operation")

        state = JobState(d.pop("state"))




        def _parse_axes(data: object) -> AxisAngles | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                axes_type_0 = AxisAngles.from_dict(data)



                return axes_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(AxisAngles | None | Unset, data)

        axes = _parse_axes(d.pop("axes", UNSET))


        def _parse_cid(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        cid = _parse_cid(d.pop("cid", UNSET))


        _configurations = d.pop("configurations", UNSET)
        configurations: list[PtpConfiguration] | Unset = UNSET
        if _configurations is not UNSET:
            configurations = []
            for configurations_item_data in _configurations:
                configurations_item = PtpConfiguration.from_dict(configurations_item_data)



                configurations.append(configurations_item)


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


        def _parse_finished_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        finished_ms = _parse_finished_ms(d.pop("finished_ms", UNSET))


        def _parse_frame(data: object) -> CartesianFrame | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                frame_type_0 = CartesianFrame.from_dict(data)



                return frame_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(CartesianFrame | None | Unset, data)

        frame = _parse_frame(d.pop("frame", UNSET))


        late_result = d.pop("late_result", UNSET)

        def _parse_origin(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        origin = _parse_origin(d.pop("origin", UNSET))


        def _parse_path(data: object) -> None | PathProgress | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                path_type_0 = PathProgress.from_dict(data)



                return path_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(None | PathProgress | Unset, data)

        path = _parse_path(d.pop("path", UNSET))


        def _parse_position(data: object) -> None | Position | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                position_type_0 = Position.from_dict(data)



                return position_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(None | Position | Unset, data)

        position = _parse_position(d.pop("position", UNSET))


        def _parse_requested_by(data: object) -> None | str | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(None | str | Unset, data)

        requested_by = _parse_requested_by(d.pop("requested_by", UNSET))


        def _parse_sent_ms(data: object) -> int | None | Unset:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | None | Unset, data)

        sent_ms = _parse_sent_ms(d.pop("sent_ms", UNSET))


        job = cls(
            completed=completed,
            created_ms=created_ms,
            id=id,
            motions=motions,
            operation=operation,
            state=state,
            axes=axes,
            cid=cid,
            configurations=configurations,
            error=error,
            finished_ms=finished_ms,
            frame=frame,
            late_result=late_result,
            origin=origin,
            path=path,
            position=position,
            requested_by=requested_by,
            sent_ms=sent_ms,
        )


        job.additional_properties = d
        return job

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
