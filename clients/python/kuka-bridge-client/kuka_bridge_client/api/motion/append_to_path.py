from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.append_body import AppendBody
from ...models.append_outcome import AppendOutcome
from ...models.problem_details import ProblemDetails
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    id: int,
    *,
    body: AppendBody,
    close: bool | Unset = UNSET,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    params: dict[str, Any] = {}

    params["close"] = close


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/paths/{id}/motions".format(id=quote(str(id), safe=""),),
        "params": params,
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> AppendOutcome | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = AppendOutcome.from_dict(response.json())



        return response_200

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

    if response.status_code == 404:
        response_404 = ProblemDetails.from_dict(response.json())



        return response_404

    if response.status_code == 409:
        response_409 = ProblemDetails.from_dict(response.json())



        return response_409

    if response.status_code == 415:
        response_415 = ProblemDetails.from_dict(response.json())



        return response_415

    if response.status_code == 422:
        response_422 = ProblemDetails.from_dict(response.json())



        return response_422

    if response.status_code == 429:
        response_429 = ProblemDetails.from_dict(response.json())



        return response_429

    if response.status_code == 503:
        response_503 = ProblemDetails.from_dict(response.json())



        return response_503

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[AppendOutcome | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    body: AppendBody,
    close: bool | Unset = UNSET,

) -> Response[AppendOutcome | ProblemDetails]:
    """ Append motions to an open path.

     Either a JSON object (`AppendBody`: the motions, `close`, `wait_ms`), appended all or
    none, or a stream of JSON lines (`Content-Type: application/x-ndjson`, one motion
    object per line) for a path of any length: the lines are appended as they arrive and
    the connection's flow control holds the client back while the path is full. Each
    motion is checked (reachability, limits, configuration, the swept path against the
    workspace rules) against the end of what the path already holds before anything is
    sent; a refused motion closes the path at the last accepted motion (the answer names
    it and says why; a JSON object is appended all or none, a JSON-lines stream keeps the
    lines before the refused one). Omitted coordinates keep
    the previous motion's value, across appends. While the path holds 2000 motions not
    yet on the controller an append waits for room, up to `wait_ms`,
    then answers `path_full` with `Retry-After`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        close (bool | Unset):
        body (AppendBody): Motions to append. Example: {'motions': [{'type': 'lin', 'target':
            {'x': 200, 'y': 10}, 'velocity_m_s': 0.2}, {'type': 'lin', 'target': {'x': 210, 'y': 20},
            'velocity_m_s': 0.2}], 'close': False}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[AppendOutcome | ProblemDetails]
     """


    kwargs = _get_kwargs(
        id=id,
body=body,
close=close,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    body: AppendBody,
    close: bool | Unset = UNSET,

) -> AppendOutcome | ProblemDetails | None:
    """ Append motions to an open path.

     Either a JSON object (`AppendBody`: the motions, `close`, `wait_ms`), appended all or
    none, or a stream of JSON lines (`Content-Type: application/x-ndjson`, one motion
    object per line) for a path of any length: the lines are appended as they arrive and
    the connection's flow control holds the client back while the path is full. Each
    motion is checked (reachability, limits, configuration, the swept path against the
    workspace rules) against the end of what the path already holds before anything is
    sent; a refused motion closes the path at the last accepted motion (the answer names
    it and says why; a JSON object is appended all or none, a JSON-lines stream keeps the
    lines before the refused one). Omitted coordinates keep
    the previous motion's value, across appends. While the path holds 2000 motions not
    yet on the controller an append waits for room, up to `wait_ms`,
    then answers `path_full` with `Retry-After`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        close (bool | Unset):
        body (AppendBody): Motions to append. Example: {'motions': [{'type': 'lin', 'target':
            {'x': 200, 'y': 10}, 'velocity_m_s': 0.2}, {'type': 'lin', 'target': {'x': 210, 'y': 20},
            'velocity_m_s': 0.2}], 'close': False}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        AppendOutcome | ProblemDetails
     """


    return sync_detailed(
        id=id,
client=client,
body=body,
close=close,

    ).parsed

async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    body: AppendBody,
    close: bool | Unset = UNSET,

) -> Response[AppendOutcome | ProblemDetails]:
    """ Append motions to an open path.

     Either a JSON object (`AppendBody`: the motions, `close`, `wait_ms`), appended all or
    none, or a stream of JSON lines (`Content-Type: application/x-ndjson`, one motion
    object per line) for a path of any length: the lines are appended as they arrive and
    the connection's flow control holds the client back while the path is full. Each
    motion is checked (reachability, limits, configuration, the swept path against the
    workspace rules) against the end of what the path already holds before anything is
    sent; a refused motion closes the path at the last accepted motion (the answer names
    it and says why; a JSON object is appended all or none, a JSON-lines stream keeps the
    lines before the refused one). Omitted coordinates keep
    the previous motion's value, across appends. While the path holds 2000 motions not
    yet on the controller an append waits for room, up to `wait_ms`,
    then answers `path_full` with `Retry-After`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        close (bool | Unset):
        body (AppendBody): Motions to append. Example: {'motions': [{'type': 'lin', 'target':
            {'x': 200, 'y': 10}, 'velocity_m_s': 0.2}, {'type': 'lin', 'target': {'x': 210, 'y': 20},
            'velocity_m_s': 0.2}], 'close': False}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[AppendOutcome | ProblemDetails]
     """


    kwargs = _get_kwargs(
        id=id,
body=body,
close=close,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    body: AppendBody,
    close: bool | Unset = UNSET,

) -> AppendOutcome | ProblemDetails | None:
    """ Append motions to an open path.

     Either a JSON object (`AppendBody`: the motions, `close`, `wait_ms`), appended all or
    none, or a stream of JSON lines (`Content-Type: application/x-ndjson`, one motion
    object per line) for a path of any length: the lines are appended as they arrive and
    the connection's flow control holds the client back while the path is full. Each
    motion is checked (reachability, limits, configuration, the swept path against the
    workspace rules) against the end of what the path already holds before anything is
    sent; a refused motion closes the path at the last accepted motion (the answer names
    it and says why; a JSON object is appended all or none, a JSON-lines stream keeps the
    lines before the refused one). Omitted coordinates keep
    the previous motion's value, across appends. While the path holds 2000 motions not
    yet on the controller an append waits for room, up to `wait_ms`,
    then answers `path_full` with `Retry-After`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        close (bool | Unset):
        body (AppendBody): Motions to append. Example: {'motions': [{'type': 'lin', 'target':
            {'x': 200, 'y': 10}, 'velocity_m_s': 0.2}, {'type': 'lin', 'target': {'x': 210, 'y': 20},
            'velocity_m_s': 0.2}], 'close': False}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        AppendOutcome | ProblemDetails
     """


    return (await asyncio_detailed(
        id=id,
client=client,
body=body,
close=close,

    )).parsed
