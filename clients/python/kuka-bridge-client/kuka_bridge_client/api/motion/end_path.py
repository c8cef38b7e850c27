from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.job import Job
from ...models.problem_details import ProblemDetails
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    id: int,
    *,
    cancel: bool | Unset = UNSET,

) -> dict[str, Any]:
    

    

    params: dict[str, Any] = {}

    params["cancel"] = cancel


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "delete",
        "url": "/api/v1/paths/{id}".format(id=quote(str(id), safe=""),),
        "params": params,
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Job | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = Job.from_dict(response.json())



        return response_200

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
    id: int,
    *,
    client: AuthenticatedClient,
    cancel: bool | Unset = UNSET,

) -> Response[Job | ProblemDetails]:
    """ End a path: it is closed and the robot finishes the motions already appended (the
    job becomes `done` when the last has run); with `cancel=true` the robot stops now
    and the path is cancelled. A path still queued behind other jobs (it has no motions
    yet) is cancelled at once. A path that has ended already is returned unchanged.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        cancel (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
     """


    kwargs = _get_kwargs(
        id=id,
cancel=cancel,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    cancel: bool | Unset = UNSET,

) -> Job | ProblemDetails | None:
    """ End a path: it is closed and the robot finishes the motions already appended (the
    job becomes `done` when the last has run); with `cancel=true` the robot stops now
    and the path is cancelled. A path still queued behind other jobs (it has no motions
    yet) is cancelled at once. A path that has ended already is returned unchanged.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        cancel (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return sync_detailed(
        id=id,
client=client,
cancel=cancel,

    ).parsed

async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    cancel: bool | Unset = UNSET,

) -> Response[Job | ProblemDetails]:
    """ End a path: it is closed and the robot finishes the motions already appended (the
    job becomes `done` when the last has run); with `cancel=true` the robot stops now
    and the path is cancelled. A path still queued behind other jobs (it has no motions
    yet) is cancelled at once. A path that has ended already is returned unchanged.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        cancel (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
     """


    kwargs = _get_kwargs(
        id=id,
cancel=cancel,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    cancel: bool | Unset = UNSET,

) -> Job | ProblemDetails | None:
    """ End a path: it is closed and the robot finishes the motions already appended (the
    job becomes `done` when the last has run); with `cancel=true` the robot stops now
    and the path is cancelled. A path still queued behind other jobs (it has no motions
    yet) is cancelled at once. A path that has ended already is returned unchanged.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        id (int):
        cancel (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return (await asyncio_detailed(
        id=id,
client=client,
cancel=cancel,

    )).parsed
