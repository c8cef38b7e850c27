from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.analog_signal import AnalogSignal
from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    signal: str,

) -> dict[str, Any]:
    

    

    

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/io/analog-outputs/{signal}".format(signal=quote(str(signal), safe=""),),
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> AnalogSignal | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = AnalogSignal.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[AnalogSignal | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    signal: str,
    *,
    client: AuthenticatedClient,

) -> Response[AnalogSignal | ProblemDetails]:
    """ One analog output, by number (1..=32) or configured name.

     

    **Access:** role `viewer` or higher.

    Args:
        signal (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[AnalogSignal | ProblemDetails]
     """


    kwargs = _get_kwargs(
        signal=signal,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    signal: str,
    *,
    client: AuthenticatedClient,

) -> AnalogSignal | ProblemDetails | None:
    """ One analog output, by number (1..=32) or configured name.

     

    **Access:** role `viewer` or higher.

    Args:
        signal (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        AnalogSignal | ProblemDetails
     """


    return sync_detailed(
        signal=signal,
client=client,

    ).parsed

async def asyncio_detailed(
    signal: str,
    *,
    client: AuthenticatedClient,

) -> Response[AnalogSignal | ProblemDetails]:
    """ One analog output, by number (1..=32) or configured name.

     

    **Access:** role `viewer` or higher.

    Args:
        signal (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[AnalogSignal | ProblemDetails]
     """


    kwargs = _get_kwargs(
        signal=signal,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    signal: str,
    *,
    client: AuthenticatedClient,

) -> AnalogSignal | ProblemDetails | None:
    """ One analog output, by number (1..=32) or configured name.

     

    **Access:** role `viewer` or higher.

    Args:
        signal (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        AnalogSignal | ProblemDetails
     """


    return (await asyncio_detailed(
        signal=signal,
client=client,

    )).parsed
