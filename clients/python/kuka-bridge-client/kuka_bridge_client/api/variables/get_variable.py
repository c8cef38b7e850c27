from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.variable import Variable
from typing import cast



def _get_kwargs(
    name: str,

) -> dict[str, Any]:
    

    

    

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/variables/{name}".format(name=quote(str(name), safe=""),),
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | Variable | None:
    if response.status_code == 200:
        response_200 = Variable.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | Variable]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    name: str,
    *,
    client: AuthenticatedClient,

) -> Response[ProblemDetails | Variable]:
    """ Read a KRL variable by name.

     Any variable the controller has: system variables (`$OV_PRO`,
    `$POS_ACT`, `$MODE_OP`, `$OUT[3]`), a component (`$POS_ACT.X`), table
    entries (`TOOL_DATA[3]`) and globals of loaded modules. Read through the
    controller's KUKAVARPROXY server (`[variables] proxy`; with
    `--simulate` the simulator's stand-in). The value comes as typed JSON
    with its KRL type and text. Indices in the URL: percent-encode `[`
    and `]` (`TOOL_DATA%5B3%5D`), or use `curl -g`.

    **Access:** role `viewer` or higher.

    Args:
        name (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | Variable]
     """


    kwargs = _get_kwargs(
        name=name,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    name: str,
    *,
    client: AuthenticatedClient,

) -> ProblemDetails | Variable | None:
    """ Read a KRL variable by name.

     Any variable the controller has: system variables (`$OV_PRO`,
    `$POS_ACT`, `$MODE_OP`, `$OUT[3]`), a component (`$POS_ACT.X`), table
    entries (`TOOL_DATA[3]`) and globals of loaded modules. Read through the
    controller's KUKAVARPROXY server (`[variables] proxy`; with
    `--simulate` the simulator's stand-in). The value comes as typed JSON
    with its KRL type and text. Indices in the URL: percent-encode `[`
    and `]` (`TOOL_DATA%5B3%5D`), or use `curl -g`.

    **Access:** role `viewer` or higher.

    Args:
        name (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | Variable
     """


    return sync_detailed(
        name=name,
client=client,

    ).parsed

async def asyncio_detailed(
    name: str,
    *,
    client: AuthenticatedClient,

) -> Response[ProblemDetails | Variable]:
    """ Read a KRL variable by name.

     Any variable the controller has: system variables (`$OV_PRO`,
    `$POS_ACT`, `$MODE_OP`, `$OUT[3]`), a component (`$POS_ACT.X`), table
    entries (`TOOL_DATA[3]`) and globals of loaded modules. Read through the
    controller's KUKAVARPROXY server (`[variables] proxy`; with
    `--simulate` the simulator's stand-in). The value comes as typed JSON
    with its KRL type and text. Indices in the URL: percent-encode `[`
    and `]` (`TOOL_DATA%5B3%5D`), or use `curl -g`.

    **Access:** role `viewer` or higher.

    Args:
        name (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | Variable]
     """


    kwargs = _get_kwargs(
        name=name,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    name: str,
    *,
    client: AuthenticatedClient,

) -> ProblemDetails | Variable | None:
    """ Read a KRL variable by name.

     Any variable the controller has: system variables (`$OV_PRO`,
    `$POS_ACT`, `$MODE_OP`, `$OUT[3]`), a component (`$POS_ACT.X`), table
    entries (`TOOL_DATA[3]`) and globals of loaded modules. Read through the
    controller's KUKAVARPROXY server (`[variables] proxy`; with
    `--simulate` the simulator's stand-in). The value comes as typed JSON
    with its KRL type and text. Indices in the URL: percent-encode `[`
    and `]` (`TOOL_DATA%5B3%5D`), or use `curl -g`.

    **Access:** role `viewer` or higher.

    Args:
        name (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | Variable
     """


    return (await asyncio_detailed(
        name=name,
client=client,

    )).parsed
