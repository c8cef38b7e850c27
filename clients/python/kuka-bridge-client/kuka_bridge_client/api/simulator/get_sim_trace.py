from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.trace_sample import TraceSample
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    since: float | Unset = UNSET,

) -> dict[str, Any]:
    

    

    params: dict[str, Any] = {}

    params["since"] = since


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/sim/trace",
        "params": params,
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | list[TraceSample] | None:
    if response.status_code == 200:
        response_200 = []
        _response_200 = response.json()
        for response_200_item_data in (_response_200):
            response_200_item = TraceSample.from_dict(response_200_item_data)



            response_200.append(response_200_item)

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | list[TraceSample]]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    since: float | Unset = UNSET,

) -> Response[ProblemDetails | list[TraceSample]]:
    """ The executed TCP trace: `{t, cid, motion, pose: [x,y,z,a,b,c], axes, stop}` per sample (native: IPO
    step of 12 ms; krc: interpreter cycle, which may record one pose twice and then move two steps, so
    take speeds over several samples); `stop` marks where the robot stands still.

     

    **Access:** role `viewer` or higher.

    Args:
        since (float | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | list[TraceSample]]
     """


    kwargs = _get_kwargs(
        since=since,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,
    since: float | Unset = UNSET,

) -> ProblemDetails | list[TraceSample] | None:
    """ The executed TCP trace: `{t, cid, motion, pose: [x,y,z,a,b,c], axes, stop}` per sample (native: IPO
    step of 12 ms; krc: interpreter cycle, which may record one pose twice and then move two steps, so
    take speeds over several samples); `stop` marks where the robot stands still.

     

    **Access:** role `viewer` or higher.

    Args:
        since (float | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | list[TraceSample]
     """


    return sync_detailed(
        client=client,
since=since,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    since: float | Unset = UNSET,

) -> Response[ProblemDetails | list[TraceSample]]:
    """ The executed TCP trace: `{t, cid, motion, pose: [x,y,z,a,b,c], axes, stop}` per sample (native: IPO
    step of 12 ms; krc: interpreter cycle, which may record one pose twice and then move two steps, so
    take speeds over several samples); `stop` marks where the robot stands still.

     

    **Access:** role `viewer` or higher.

    Args:
        since (float | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | list[TraceSample]]
     """


    kwargs = _get_kwargs(
        since=since,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,
    since: float | Unset = UNSET,

) -> ProblemDetails | list[TraceSample] | None:
    """ The executed TCP trace: `{t, cid, motion, pose: [x,y,z,a,b,c], axes, stop}` per sample (native: IPO
    step of 12 ms; krc: interpreter cycle, which may record one pose twice and then move two steps, so
    take speeds over several samples); `stop` marks where the robot stands still.

     

    **Access:** role `viewer` or higher.

    Args:
        since (float | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | list[TraceSample]
     """


    return (await asyncio_detailed(
        client=client,
since=since,

    )).parsed
