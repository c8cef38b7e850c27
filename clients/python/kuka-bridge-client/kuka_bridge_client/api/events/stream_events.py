from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    types: str | Unset = UNSET,
    last_event_id_query: int | Unset = UNSET,
    access_token: str | Unset = UNSET,
    last_event_id_header: int | None | Unset = UNSET,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}
    if not isinstance(last_event_id_header, Unset):
        headers["Last-Event-ID"] = last_event_id_header



    

    params: dict[str, Any] = {}

    params["types"] = types

    params["last_event_id"] = last_event_id_query

    params["access_token"] = access_token


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/events",
        "params": params,
    }


    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | str | None:
    if response.status_code == 200:
        response_200 = response.text
        return response_200

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

    if response.status_code == 422:
        response_422 = ProblemDetails.from_dict(response.json())



        return response_422

    if response.status_code == 429:
        response_429 = ProblemDetails.from_dict(response.json())



        return response_429

    if 400 <= response.status_code <= 499:
        response_4xx = ProblemDetails.from_dict(response.json())



        return response_4xx

    if 500 <= response.status_code <= 599:
        response_5xx = ProblemDetails.from_dict(response.json())



        return response_5xx

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | str]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    types: str | Unset = UNSET,
    last_event_id_query: int | Unset = UNSET,
    access_token: str | Unset = UNSET,
    last_event_id_header: int | None | Unset = UNSET,

) -> Response[ProblemDetails | str]:
    """ Live events (Server-Sent Events).

     Each SSE message has `event:` = `job`, `state`, `alarm`, `plan`, `io` or `analog` and `data:` = the
    JSON of the job, the robot state, the error (`code`, `detail`, `axis`, `motion`), the
    planned path of a move job (`JobPlan`, sent when its motions are written to the
    controller, before they run), a watched digital signal that changed (`IoChange`,
    docs/IO.md) or a watched analog channel that moved by its deadband (`AnalogChange`).
    A state event follows each heartbeat
    that changed something. A `lagged` event says the client was too slow and missed
    some (`data:` how many). The stream starts with the current state, and ends when the
    service shuts down or the caller's token is revoked.

    Job, plan, alarm, io and analog events carry an `id:` that grows by one per event; the service
    keeps the last 1000 of them. A client that reconnects with `Last-Event-ID` (browsers'
    `EventSource` does so by itself) or `?last_event_id=` first gets the held events it
    missed, then the current state, then live events; if some it missed are no longer
    held, a `lagged` event says how many. State events carry no id and are not replayed
    (the current state replaces them). An id from before a restart of the service replays
    every event held.

    **Access:** role `viewer` or higher.

    Args:
        types (str | Unset):
        last_event_id_query (int | Unset):
        access_token (str | Unset):
        last_event_id_header (int | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | str]
     """


    kwargs = _get_kwargs(
        types=types,
last_event_id_query=last_event_id_query,
access_token=access_token,
last_event_id_header=last_event_id_header,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,
    types: str | Unset = UNSET,
    last_event_id_query: int | Unset = UNSET,
    access_token: str | Unset = UNSET,
    last_event_id_header: int | None | Unset = UNSET,

) -> ProblemDetails | str | None:
    """ Live events (Server-Sent Events).

     Each SSE message has `event:` = `job`, `state`, `alarm`, `plan`, `io` or `analog` and `data:` = the
    JSON of the job, the robot state, the error (`code`, `detail`, `axis`, `motion`), the
    planned path of a move job (`JobPlan`, sent when its motions are written to the
    controller, before they run), a watched digital signal that changed (`IoChange`,
    docs/IO.md) or a watched analog channel that moved by its deadband (`AnalogChange`).
    A state event follows each heartbeat
    that changed something. A `lagged` event says the client was too slow and missed
    some (`data:` how many). The stream starts with the current state, and ends when the
    service shuts down or the caller's token is revoked.

    Job, plan, alarm, io and analog events carry an `id:` that grows by one per event; the service
    keeps the last 1000 of them. A client that reconnects with `Last-Event-ID` (browsers'
    `EventSource` does so by itself) or `?last_event_id=` first gets the held events it
    missed, then the current state, then live events; if some it missed are no longer
    held, a `lagged` event says how many. State events carry no id and are not replayed
    (the current state replaces them). An id from before a restart of the service replays
    every event held.

    **Access:** role `viewer` or higher.

    Args:
        types (str | Unset):
        last_event_id_query (int | Unset):
        access_token (str | Unset):
        last_event_id_header (int | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | str
     """


    return sync_detailed(
        client=client,
types=types,
last_event_id_query=last_event_id_query,
access_token=access_token,
last_event_id_header=last_event_id_header,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    types: str | Unset = UNSET,
    last_event_id_query: int | Unset = UNSET,
    access_token: str | Unset = UNSET,
    last_event_id_header: int | None | Unset = UNSET,

) -> Response[ProblemDetails | str]:
    """ Live events (Server-Sent Events).

     Each SSE message has `event:` = `job`, `state`, `alarm`, `plan`, `io` or `analog` and `data:` = the
    JSON of the job, the robot state, the error (`code`, `detail`, `axis`, `motion`), the
    planned path of a move job (`JobPlan`, sent when its motions are written to the
    controller, before they run), a watched digital signal that changed (`IoChange`,
    docs/IO.md) or a watched analog channel that moved by its deadband (`AnalogChange`).
    A state event follows each heartbeat
    that changed something. A `lagged` event says the client was too slow and missed
    some (`data:` how many). The stream starts with the current state, and ends when the
    service shuts down or the caller's token is revoked.

    Job, plan, alarm, io and analog events carry an `id:` that grows by one per event; the service
    keeps the last 1000 of them. A client that reconnects with `Last-Event-ID` (browsers'
    `EventSource` does so by itself) or `?last_event_id=` first gets the held events it
    missed, then the current state, then live events; if some it missed are no longer
    held, a `lagged` event says how many. State events carry no id and are not replayed
    (the current state replaces them). An id from before a restart of the service replays
    every event held.

    **Access:** role `viewer` or higher.

    Args:
        types (str | Unset):
        last_event_id_query (int | Unset):
        access_token (str | Unset):
        last_event_id_header (int | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | str]
     """


    kwargs = _get_kwargs(
        types=types,
last_event_id_query=last_event_id_query,
access_token=access_token,
last_event_id_header=last_event_id_header,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,
    types: str | Unset = UNSET,
    last_event_id_query: int | Unset = UNSET,
    access_token: str | Unset = UNSET,
    last_event_id_header: int | None | Unset = UNSET,

) -> ProblemDetails | str | None:
    """ Live events (Server-Sent Events).

     Each SSE message has `event:` = `job`, `state`, `alarm`, `plan`, `io` or `analog` and `data:` = the
    JSON of the job, the robot state, the error (`code`, `detail`, `axis`, `motion`), the
    planned path of a move job (`JobPlan`, sent when its motions are written to the
    controller, before they run), a watched digital signal that changed (`IoChange`,
    docs/IO.md) or a watched analog channel that moved by its deadband (`AnalogChange`).
    A state event follows each heartbeat
    that changed something. A `lagged` event says the client was too slow and missed
    some (`data:` how many). The stream starts with the current state, and ends when the
    service shuts down or the caller's token is revoked.

    Job, plan, alarm, io and analog events carry an `id:` that grows by one per event; the service
    keeps the last 1000 of them. A client that reconnects with `Last-Event-ID` (browsers'
    `EventSource` does so by itself) or `?last_event_id=` first gets the held events it
    missed, then the current state, then live events; if some it missed are no longer
    held, a `lagged` event says how many. State events carry no id and are not replayed
    (the current state replaces them). An id from before a restart of the service replays
    every event held.

    **Access:** role `viewer` or higher.

    Args:
        types (str | Unset):
        last_event_id_query (int | Unset):
        access_token (str | Unset):
        last_event_id_header (int | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | str
     """


    return (await asyncio_detailed(
        client=client,
types=types,
last_event_id_query=last_event_id_query,
access_token=access_token,
last_event_id_header=last_event_id_header,

    )).parsed
