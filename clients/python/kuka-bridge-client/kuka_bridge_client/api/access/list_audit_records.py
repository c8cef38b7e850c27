from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.audit_record import AuditRecord
from ...models.problem_details import ProblemDetails
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    who: str | Unset = UNSET,
    path: str | Unset = UNSET,
    method: str | Unset = UNSET,
    failed: bool | Unset = UNSET,
    code: str | Unset = UNSET,
    since_ms: int | Unset = UNSET,
    until_ms: int | Unset = UNSET,
    limit: int | Unset = UNSET,

) -> dict[str, Any]:
    

    

    params: dict[str, Any] = {}

    params["who"] = who

    params["path"] = path

    params["method"] = method

    params["failed"] = failed

    params["code"] = code

    params["since_ms"] = since_ms

    params["until_ms"] = until_ms

    params["limit"] = limit


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/audit",
        "params": params,
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | list[AuditRecord] | None:
    if response.status_code == 200:
        response_200 = []
        _response_200 = response.json()
        for response_200_item_data in (_response_200):
            response_200_item = AuditRecord.from_dict(response_200_item_data)



            response_200.append(response_200_item)

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | list[AuditRecord]]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    who: str | Unset = UNSET,
    path: str | Unset = UNSET,
    method: str | Unset = UNSET,
    failed: bool | Unset = UNSET,
    code: str | Unset = UNSET,
    since_ms: int | Unset = UNSET,
    until_ms: int | Unset = UNSET,
    limit: int | Unset = UNSET,

) -> Response[ProblemDetails | list[AuditRecord]]:
    """ The audit trail: every mutating request, newest first.

     

    **Access:** role `admin` or higher.

    Args:
        who (str | Unset):
        path (str | Unset):
        method (str | Unset):
        failed (bool | Unset):
        code (str | Unset):
        since_ms (int | Unset):
        until_ms (int | Unset):
        limit (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | list[AuditRecord]]
     """


    kwargs = _get_kwargs(
        who=who,
path=path,
method=method,
failed=failed,
code=code,
since_ms=since_ms,
until_ms=until_ms,
limit=limit,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,
    who: str | Unset = UNSET,
    path: str | Unset = UNSET,
    method: str | Unset = UNSET,
    failed: bool | Unset = UNSET,
    code: str | Unset = UNSET,
    since_ms: int | Unset = UNSET,
    until_ms: int | Unset = UNSET,
    limit: int | Unset = UNSET,

) -> ProblemDetails | list[AuditRecord] | None:
    """ The audit trail: every mutating request, newest first.

     

    **Access:** role `admin` or higher.

    Args:
        who (str | Unset):
        path (str | Unset):
        method (str | Unset):
        failed (bool | Unset):
        code (str | Unset):
        since_ms (int | Unset):
        until_ms (int | Unset):
        limit (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | list[AuditRecord]
     """


    return sync_detailed(
        client=client,
who=who,
path=path,
method=method,
failed=failed,
code=code,
since_ms=since_ms,
until_ms=until_ms,
limit=limit,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    who: str | Unset = UNSET,
    path: str | Unset = UNSET,
    method: str | Unset = UNSET,
    failed: bool | Unset = UNSET,
    code: str | Unset = UNSET,
    since_ms: int | Unset = UNSET,
    until_ms: int | Unset = UNSET,
    limit: int | Unset = UNSET,

) -> Response[ProblemDetails | list[AuditRecord]]:
    """ The audit trail: every mutating request, newest first.

     

    **Access:** role `admin` or higher.

    Args:
        who (str | Unset):
        path (str | Unset):
        method (str | Unset):
        failed (bool | Unset):
        code (str | Unset):
        since_ms (int | Unset):
        until_ms (int | Unset):
        limit (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | list[AuditRecord]]
     """


    kwargs = _get_kwargs(
        who=who,
path=path,
method=method,
failed=failed,
code=code,
since_ms=since_ms,
until_ms=until_ms,
limit=limit,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,
    who: str | Unset = UNSET,
    path: str | Unset = UNSET,
    method: str | Unset = UNSET,
    failed: bool | Unset = UNSET,
    code: str | Unset = UNSET,
    since_ms: int | Unset = UNSET,
    until_ms: int | Unset = UNSET,
    limit: int | Unset = UNSET,

) -> ProblemDetails | list[AuditRecord] | None:
    """ The audit trail: every mutating request, newest first.

     

    **Access:** role `admin` or higher.

    Args:
        who (str | Unset):
        path (str | Unset):
        method (str | Unset):
        failed (bool | Unset):
        code (str | Unset):
        since_ms (int | Unset):
        until_ms (int | Unset):
        limit (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | list[AuditRecord]
     """


    return (await asyncio_detailed(
        client=client,
who=who,
path=path,
method=method,
failed=failed,
code=code,
since_ms=since_ms,
until_ms=until_ms,
limit=limit,

    )).parsed
