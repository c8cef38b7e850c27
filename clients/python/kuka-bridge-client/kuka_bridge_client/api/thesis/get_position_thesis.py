from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.thesis_problem import ThesisProblem
from ...models.thesis_response import ThesisResponse
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    access_token: str | Unset = UNSET,

) -> dict[str, Any]:
    

    

    params: dict[str, Any] = {}

    params["access_token"] = access_token


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/krl/getpos",
        "params": params,
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | ThesisProblem | ThesisResponse | None:
    if response.status_code == 200:
        response_200 = ThesisResponse.from_dict(response.json())



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
        response_4xx = ThesisProblem.from_dict(response.json())



        return response_4xx

    if 500 <= response.status_code <= 599:
        response_5xx = ThesisProblem.from_dict(response.json())



        return response_5xx

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | ThesisProblem | ThesisResponse]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    access_token: str | Unset = UNSET,

) -> Response[ProblemDetails | ThesisProblem | ThesisResponse]:
    """ Current position (thesis method 3): read through the controller program while
    the robot stands; while a motion runs, at once from the controller's live state
    (as `GET /api/v1/position` with `source: live`), with `age_ms`, the age of that sample.

     

    **Access:** role `viewer` or higher.

    Args:
        access_token (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | ThesisProblem | ThesisResponse]
     """


    kwargs = _get_kwargs(
        access_token=access_token,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,
    access_token: str | Unset = UNSET,

) -> ProblemDetails | ThesisProblem | ThesisResponse | None:
    """ Current position (thesis method 3): read through the controller program while
    the robot stands; while a motion runs, at once from the controller's live state
    (as `GET /api/v1/position` with `source: live`), with `age_ms`, the age of that sample.

     

    **Access:** role `viewer` or higher.

    Args:
        access_token (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | ThesisProblem | ThesisResponse
     """


    return sync_detailed(
        client=client,
access_token=access_token,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    access_token: str | Unset = UNSET,

) -> Response[ProblemDetails | ThesisProblem | ThesisResponse]:
    """ Current position (thesis method 3): read through the controller program while
    the robot stands; while a motion runs, at once from the controller's live state
    (as `GET /api/v1/position` with `source: live`), with `age_ms`, the age of that sample.

     

    **Access:** role `viewer` or higher.

    Args:
        access_token (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | ThesisProblem | ThesisResponse]
     """


    kwargs = _get_kwargs(
        access_token=access_token,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,
    access_token: str | Unset = UNSET,

) -> ProblemDetails | ThesisProblem | ThesisResponse | None:
    """ Current position (thesis method 3): read through the controller program while
    the robot stands; while a motion runs, at once from the controller's live state
    (as `GET /api/v1/position` with `source: live`), with `age_ms`, the age of that sample.

     

    **Access:** role `viewer` or higher.

    Args:
        access_token (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | ThesisProblem | ThesisResponse
     """


    return (await asyncio_detailed(
        client=client,
access_token=access_token,

    )).parsed
