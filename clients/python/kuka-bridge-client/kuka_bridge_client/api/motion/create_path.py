from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.job import Job
from ...models.path_create import PathCreate
from ...models.problem_details import ProblemDetails
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    body: None | PathCreate | Unset = UNSET,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/paths",
    }

    
    if isinstance(body, PathCreate):
        _kwargs["json"] = body.to_dict()
    else:
        _kwargs["json"] = body

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Job | ProblemDetails | None:
    if response.status_code == 201:
        response_201 = Job.from_dict(response.json())



        return response_201

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

    if response.status_code == 409:
        response_409 = ProblemDetails.from_dict(response.json())



        return response_409

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[Job | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: None | PathCreate | Unset = UNSET,

) -> Response[Job | ProblemDetails]:
    """ Open a path: a motion stream that stays open while motions are appended.

     The answer is the path's job (`operation: path`), 201 with a `Location`. The path
    takes the controller like any job (it waits behind queued jobs), then runs motions
    as they are appended with `POST /api/v1/paths/{id}/motions`: motions appended while
    the robot moves are approximated into it, so a path sent motion by motion does not
    stop between motions as long as they come faster than the robot runs them. End it
    with `DELETE /api/v1/paths/{id}` (the robot finishes what was appended), or stop.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (None | PathCreate | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
     """


    kwargs = _get_kwargs(
        body=body,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,
    body: None | PathCreate | Unset = UNSET,

) -> Job | ProblemDetails | None:
    """ Open a path: a motion stream that stays open while motions are appended.

     The answer is the path's job (`operation: path`), 201 with a `Location`. The path
    takes the controller like any job (it waits behind queued jobs), then runs motions
    as they are appended with `POST /api/v1/paths/{id}/motions`: motions appended while
    the robot moves are approximated into it, so a path sent motion by motion does not
    stop between motions as long as they come faster than the robot runs them. End it
    with `DELETE /api/v1/paths/{id}` (the robot finishes what was appended), or stop.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (None | PathCreate | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: None | PathCreate | Unset = UNSET,

) -> Response[Job | ProblemDetails]:
    """ Open a path: a motion stream that stays open while motions are appended.

     The answer is the path's job (`operation: path`), 201 with a `Location`. The path
    takes the controller like any job (it waits behind queued jobs), then runs motions
    as they are appended with `POST /api/v1/paths/{id}/motions`: motions appended while
    the robot moves are approximated into it, so a path sent motion by motion does not
    stop between motions as long as they come faster than the robot runs them. End it
    with `DELETE /api/v1/paths/{id}` (the robot finishes what was appended), or stop.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (None | PathCreate | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
     """


    kwargs = _get_kwargs(
        body=body,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,
    body: None | PathCreate | Unset = UNSET,

) -> Job | ProblemDetails | None:
    """ Open a path: a motion stream that stays open while motions are appended.

     The answer is the path's job (`operation: path`), 201 with a `Location`. The path
    takes the controller like any job (it waits behind queued jobs), then runs motions
    as they are appended with `POST /api/v1/paths/{id}/motions`: motions appended while
    the robot moves are approximated into it, so a path sent motion by motion does not
    stop between motions as long as they come faster than the robot runs them. End it
    with `DELETE /api/v1/paths/{id}` (the robot finishes what was appended), or stop.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (None | PathCreate | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
