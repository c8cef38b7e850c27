from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.analog_view import AnalogView
from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    
) -> dict[str, Any]:
    

    

    

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/io/analog",
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> AnalogView | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = AnalogView.from_dict(response.json())



        return response_200

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[AnalogView | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,

) -> Response[AnalogView | ProblemDetails]:
    """ The analog inputs and outputs the controller reports.

     `$ANIN[1..8]` and `$ANOUT[1..8]` from the controller's state file
    (live, no round trip), normalised −1..1, with the names of the site's
    `[io] analog_inputs`/`analog_outputs` and which outputs clients may
    write.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[AnalogView | ProblemDetails]
     """


    kwargs = _get_kwargs(
        
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,

) -> AnalogView | ProblemDetails | None:
    """ The analog inputs and outputs the controller reports.

     `$ANIN[1..8]` and `$ANOUT[1..8]` from the controller's state file
    (live, no round trip), normalised −1..1, with the names of the site's
    `[io] analog_inputs`/`analog_outputs` and which outputs clients may
    write.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        AnalogView | ProblemDetails
     """


    return sync_detailed(
        client=client,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,

) -> Response[AnalogView | ProblemDetails]:
    """ The analog inputs and outputs the controller reports.

     `$ANIN[1..8]` and `$ANOUT[1..8]` from the controller's state file
    (live, no round trip), normalised −1..1, with the names of the site's
    `[io] analog_inputs`/`analog_outputs` and which outputs clients may
    write.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[AnalogView | ProblemDetails]
     """


    kwargs = _get_kwargs(
        
    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,

) -> AnalogView | ProblemDetails | None:
    """ The analog inputs and outputs the controller reports.

     `$ANIN[1..8]` and `$ANOUT[1..8]` from the controller's state file
    (live, no round trip), normalised −1..1, with the names of the site's
    `[io] analog_inputs`/`analog_outputs` and which outputs clients may
    write.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        AnalogView | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,

    )).parsed
