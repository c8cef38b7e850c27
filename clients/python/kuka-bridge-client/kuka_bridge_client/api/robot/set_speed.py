from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.speed_settings import SpeedSettings
from ...models.speed_update import SpeedUpdate
from typing import cast



def _get_kwargs(
    *,
    body: SpeedUpdate,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/speed",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | SpeedSettings | None:
    if response.status_code == 200:
        response_200 = SpeedSettings.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | SpeedSettings]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: SpeedUpdate,

) -> Response[ProblemDetails | SpeedSettings]:
    """ Change override and default speeds (partial update); sent to the controller.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (SpeedUpdate): Partial update of the speed settings; omitted fields keep their value.
            Example: {'override_pct': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | SpeedSettings]
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
    body: SpeedUpdate,

) -> ProblemDetails | SpeedSettings | None:
    """ Change override and default speeds (partial update); sent to the controller.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (SpeedUpdate): Partial update of the speed settings; omitted fields keep their value.
            Example: {'override_pct': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | SpeedSettings
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: SpeedUpdate,

) -> Response[ProblemDetails | SpeedSettings]:
    """ Change override and default speeds (partial update); sent to the controller.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (SpeedUpdate): Partial update of the speed settings; omitted fields keep their value.
            Example: {'override_pct': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | SpeedSettings]
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
    body: SpeedUpdate,

) -> ProblemDetails | SpeedSettings | None:
    """ Change override and default speeds (partial update); sent to the controller.

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (SpeedUpdate): Partial update of the speed settings; omitted fields keep their value.
            Example: {'override_pct': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | SpeedSettings
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
