from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    
) -> dict[str, Any]:
    

    

    

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/errors",
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | str | None:
    if response.status_code == 200:
        response_200 = response.text
        return response_200

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | str]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient | Client,

) -> Response[ProblemDetails | str]:
    """ The error catalogue: what each problem `code` means and what a client
    should do about it.

     Every problem's `type` is `/errors#<code>`, a link into this page,
    served by the service itself (no internet needed). Browsers get the
    page as HTML; a request with `Accept: application/json` gets the codes
    as JSON (code → title, HTTP status, thesis `statuscode`, sentence).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | str]
     """


    kwargs = _get_kwargs(
        
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient | Client,

) -> ProblemDetails | str | None:
    """ The error catalogue: what each problem `code` means and what a client
    should do about it.

     Every problem's `type` is `/errors#<code>`, a link into this page,
    served by the service itself (no internet needed). Browsers get the
    page as HTML; a request with `Accept: application/json` gets the codes
    as JSON (code → title, HTTP status, thesis `statuscode`, sentence).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | str
     """


    return sync_detailed(
        client=client,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient | Client,

) -> Response[ProblemDetails | str]:
    """ The error catalogue: what each problem `code` means and what a client
    should do about it.

     Every problem's `type` is `/errors#<code>`, a link into this page,
    served by the service itself (no internet needed). Browsers get the
    page as HTML; a request with `Accept: application/json` gets the codes
    as JSON (code → title, HTTP status, thesis `statuscode`, sentence).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | str]
     """


    kwargs = _get_kwargs(
        
    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient | Client,

) -> ProblemDetails | str | None:
    """ The error catalogue: what each problem `code` means and what a client
    should do about it.

     Every problem's `type` is `/errors#<code>`, a link into this page,
    served by the service itself (no internet needed). Browsers get the
    page as HTML; a request with `Accept: application/json` gets the codes
    as JSON (code → title, HTTP status, thesis `statuscode`, sentence).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | str
     """


    return (await asyncio_detailed(
        client=client,

    )).parsed
