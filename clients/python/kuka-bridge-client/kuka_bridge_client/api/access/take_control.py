from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.control_request import ControlRequest
from ...models.control_state import ControlState
from ...models.problem_details import ProblemDetails
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    body: ControlRequest | None | Unset = UNSET,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/control",
    }

    
    if isinstance(body, ControlRequest):
        _kwargs["json"] = body.to_dict()
    else:
        _kwargs["json"] = body

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ControlState | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = ControlState.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ControlState | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: ControlRequest | None | Unset = UNSET,

) -> Response[ControlState | ProblemDetails]:
    """ Take (or renew) control of the robot.

     While you hold control, other clients' motions and settings are refused with 409
    `control_held`; reads and stop are never refused. Every mutating call of yours renews
    the lease; it lapses after `lease_ms` without one. An admin may `take_over`.

    **Access:** role `operator` or higher.

    Args:
        body (ControlRequest | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ControlState | ProblemDetails]
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
    body: ControlRequest | None | Unset = UNSET,

) -> ControlState | ProblemDetails | None:
    """ Take (or renew) control of the robot.

     While you hold control, other clients' motions and settings are refused with 409
    `control_held`; reads and stop are never refused. Every mutating call of yours renews
    the lease; it lapses after `lease_ms` without one. An admin may `take_over`.

    **Access:** role `operator` or higher.

    Args:
        body (ControlRequest | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ControlState | ProblemDetails
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: ControlRequest | None | Unset = UNSET,

) -> Response[ControlState | ProblemDetails]:
    """ Take (or renew) control of the robot.

     While you hold control, other clients' motions and settings are refused with 409
    `control_held`; reads and stop are never refused. Every mutating call of yours renews
    the lease; it lapses after `lease_ms` without one. An admin may `take_over`.

    **Access:** role `operator` or higher.

    Args:
        body (ControlRequest | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ControlState | ProblemDetails]
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
    body: ControlRequest | None | Unset = UNSET,

) -> ControlState | ProblemDetails | None:
    """ Take (or renew) control of the robot.

     While you hold control, other clients' motions and settings are refused with 409
    `control_held`; reads and stop are never refused. Every mutating call of yours renews
    the lease; it lapses after `lease_ms` without one. An admin may `take_over`.

    **Access:** role `operator` or higher.

    Args:
        body (ControlRequest | None | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ControlState | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
