from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.cartesian_frame import CartesianFrame
from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    *,
    body: CartesianFrame,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/base",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> CartesianFrame | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = CartesianFrame.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[CartesianFrame | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: CartesianFrame,

) -> Response[CartesianFrame | ProblemDetails]:
    """ Set the base frame ($BASE) relative to the robot root; positions are given in it.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (CartesianFrame): A Cartesian frame in mm and degrees (A, B, C about Z, Y, X).
            Example: {'x': 0.0, 'y': 0.0, 'z': 100.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[CartesianFrame | ProblemDetails]
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
    body: CartesianFrame,

) -> CartesianFrame | ProblemDetails | None:
    """ Set the base frame ($BASE) relative to the robot root; positions are given in it.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (CartesianFrame): A Cartesian frame in mm and degrees (A, B, C about Z, Y, X).
            Example: {'x': 0.0, 'y': 0.0, 'z': 100.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        CartesianFrame | ProblemDetails
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: CartesianFrame,

) -> Response[CartesianFrame | ProblemDetails]:
    """ Set the base frame ($BASE) relative to the robot root; positions are given in it.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (CartesianFrame): A Cartesian frame in mm and degrees (A, B, C about Z, Y, X).
            Example: {'x': 0.0, 'y': 0.0, 'z': 100.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[CartesianFrame | ProblemDetails]
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
    body: CartesianFrame,

) -> CartesianFrame | ProblemDetails | None:
    """ Set the base frame ($BASE) relative to the robot root; positions are given in it.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (CartesianFrame): A Cartesian frame in mm and degrees (A, B, C about Z, Y, X).
            Example: {'x': 0.0, 'y': 0.0, 'z': 100.0, 'a': 0.0, 'b': 0.0, 'c': 0.0}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        CartesianFrame | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
