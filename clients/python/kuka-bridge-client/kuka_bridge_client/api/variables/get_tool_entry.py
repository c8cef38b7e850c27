from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.table_entry import TableEntry
from typing import cast



def _get_kwargs(
    number: int,

) -> dict[str, Any]:
    

    

    

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/tools/{number}".format(number=quote(str(number), safe=""),),
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | TableEntry | None:
    if response.status_code == 200:
        response_200 = TableEntry.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | TableEntry]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    number: int,
    *,
    client: AuthenticatedClient,

) -> Response[ProblemDetails | TableEntry]:
    """ Read an entry of the controller's tool table (`TOOL_DATA[1..16]`).

     Read through KUKAVARPROXY like every variable (503
    `variables_unavailable` without one). Write entries with
    `PUT /api/v1/variables/TOOL_DATA[n]` where the site allows it.

    **Access:** role `viewer` or higher.

    Args:
        number (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | TableEntry]
     """


    kwargs = _get_kwargs(
        number=number,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    number: int,
    *,
    client: AuthenticatedClient,

) -> ProblemDetails | TableEntry | None:
    """ Read an entry of the controller's tool table (`TOOL_DATA[1..16]`).

     Read through KUKAVARPROXY like every variable (503
    `variables_unavailable` without one). Write entries with
    `PUT /api/v1/variables/TOOL_DATA[n]` where the site allows it.

    **Access:** role `viewer` or higher.

    Args:
        number (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | TableEntry
     """


    return sync_detailed(
        number=number,
client=client,

    ).parsed

async def asyncio_detailed(
    number: int,
    *,
    client: AuthenticatedClient,

) -> Response[ProblemDetails | TableEntry]:
    """ Read an entry of the controller's tool table (`TOOL_DATA[1..16]`).

     Read through KUKAVARPROXY like every variable (503
    `variables_unavailable` without one). Write entries with
    `PUT /api/v1/variables/TOOL_DATA[n]` where the site allows it.

    **Access:** role `viewer` or higher.

    Args:
        number (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | TableEntry]
     """


    kwargs = _get_kwargs(
        number=number,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    number: int,
    *,
    client: AuthenticatedClient,

) -> ProblemDetails | TableEntry | None:
    """ Read an entry of the controller's tool table (`TOOL_DATA[1..16]`).

     Read through KUKAVARPROXY like every variable (503
    `variables_unavailable` without one). Write entries with
    `PUT /api/v1/variables/TOOL_DATA[n]` where the site allows it.

    **Access:** role `viewer` or higher.

    Args:
        number (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | TableEntry
     """


    return (await asyncio_detailed(
        number=number,
client=client,

    )).parsed
