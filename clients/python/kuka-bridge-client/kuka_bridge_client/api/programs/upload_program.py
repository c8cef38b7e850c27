from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.program_info import ProgramInfo
from ...models.program_upload import ProgramUpload
from typing import cast



def _get_kwargs(
    *,
    body: ProgramUpload,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/programs",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | ProgramInfo | None:
    if response.status_code == 200:
        response_200 = ProgramInfo.from_dict(response.json())



        return response_200

    if response.status_code == 201:
        response_201 = ProgramInfo.from_dict(response.json())



        return response_201

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

    if response.status_code == 413:
        response_413 = ProblemDetails.from_dict(response.json())



        return response_413

    if response.status_code == 422:
        response_422 = ProblemDetails.from_dict(response.json())



        return response_422

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | ProgramInfo]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: ProgramUpload,

) -> Response[ProblemDetails | ProgramInfo]:
    """ Uploads (or replaces) a KRL program.

     The `.src` (and optional `.dat`) are parsed and checked before anything is stored or
    reaches the controller: syntax, names of at most 24 characters, the entry point (no
    parameters) and, when the service runs the simulated controller, its KRL subset.
    Errors are `invalid_program` / `program_unsupported` with `file` and `line`.

    **Access:** role `admin` or higher.

    Args:
        body (ProgramUpload): An upload: a program's name, its `.src` text, an optional `.dat` and
            the routine to run. Example: {'name': 'wave', 'src': 'DEF wave()\\n  PTP {A1 10}\\n  PTP
            {A1 -10}\\nEND\\n'}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | ProgramInfo]
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
    body: ProgramUpload,

) -> ProblemDetails | ProgramInfo | None:
    """ Uploads (or replaces) a KRL program.

     The `.src` (and optional `.dat`) are parsed and checked before anything is stored or
    reaches the controller: syntax, names of at most 24 characters, the entry point (no
    parameters) and, when the service runs the simulated controller, its KRL subset.
    Errors are `invalid_program` / `program_unsupported` with `file` and `line`.

    **Access:** role `admin` or higher.

    Args:
        body (ProgramUpload): An upload: a program's name, its `.src` text, an optional `.dat` and
            the routine to run. Example: {'name': 'wave', 'src': 'DEF wave()\\n  PTP {A1 10}\\n  PTP
            {A1 -10}\\nEND\\n'}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | ProgramInfo
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: ProgramUpload,

) -> Response[ProblemDetails | ProgramInfo]:
    """ Uploads (or replaces) a KRL program.

     The `.src` (and optional `.dat`) are parsed and checked before anything is stored or
    reaches the controller: syntax, names of at most 24 characters, the entry point (no
    parameters) and, when the service runs the simulated controller, its KRL subset.
    Errors are `invalid_program` / `program_unsupported` with `file` and `line`.

    **Access:** role `admin` or higher.

    Args:
        body (ProgramUpload): An upload: a program's name, its `.src` text, an optional `.dat` and
            the routine to run. Example: {'name': 'wave', 'src': 'DEF wave()\\n  PTP {A1 10}\\n  PTP
            {A1 -10}\\nEND\\n'}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | ProgramInfo]
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
    body: ProgramUpload,

) -> ProblemDetails | ProgramInfo | None:
    """ Uploads (or replaces) a KRL program.

     The `.src` (and optional `.dat`) are parsed and checked before anything is stored or
    reaches the controller: syntax, names of at most 24 characters, the entry point (no
    parameters) and, when the service runs the simulated controller, its KRL subset.
    Errors are `invalid_program` / `program_unsupported` with `file` and `line`.

    **Access:** role `admin` or higher.

    Args:
        body (ProgramUpload): An upload: a program's name, its `.src` text, an optional `.dat` and
            the routine to run. Example: {'name': 'wave', 'src': 'DEF wave()\\n  PTP {A1 10}\\n  PTP
            {A1 -10}\\nEND\\n'}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | ProgramInfo
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
