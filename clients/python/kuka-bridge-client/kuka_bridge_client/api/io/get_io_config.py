from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.io_config import IoConfig
from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    
) -> dict[str, Any]:
    

    

    

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/io/config",
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> IoConfig | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = IoConfig.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[IoConfig | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,

) -> Response[IoConfig | ProblemDetails]:
    """ The site's I/O configuration now: named inputs, the outputs clients
    may write (the allow-list), named analog channels, and which of them
    publish events.

     From the configuration file's `[io]`, or, once an admin has edited it
    (`PUT`), from the copy the service keeps in its data folder
    (`io.json`), which then replaces the file's until `DELETE`.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[IoConfig | ProblemDetails]
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

) -> IoConfig | ProblemDetails | None:
    """ The site's I/O configuration now: named inputs, the outputs clients
    may write (the allow-list), named analog channels, and which of them
    publish events.

     From the configuration file's `[io]`, or, once an admin has edited it
    (`PUT`), from the copy the service keeps in its data folder
    (`io.json`), which then replaces the file's until `DELETE`.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        IoConfig | ProblemDetails
     """


    return sync_detailed(
        client=client,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,

) -> Response[IoConfig | ProblemDetails]:
    """ The site's I/O configuration now: named inputs, the outputs clients
    may write (the allow-list), named analog channels, and which of them
    publish events.

     From the configuration file's `[io]`, or, once an admin has edited it
    (`PUT`), from the copy the service keeps in its data folder
    (`io.json`), which then replaces the file's until `DELETE`.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[IoConfig | ProblemDetails]
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

) -> IoConfig | ProblemDetails | None:
    """ The site's I/O configuration now: named inputs, the outputs clients
    may write (the allow-list), named analog channels, and which of them
    publish events.

     From the configuration file's `[io]`, or, once an admin has edited it
    (`PUT`), from the copy the service keeps in its data folder
    (`io.json`), which then replaces the file's until `DELETE`.

    **Access:** role `viewer` or higher.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        IoConfig | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,

    )).parsed
