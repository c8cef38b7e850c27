from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.recent_event import RecentEvent
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    limit: int | Unset = UNSET,
    types: str | Unset = UNSET,
    after: int | Unset = UNSET,

) -> dict[str, Any]:
    

    

    params: dict[str, Any] = {}

    params["limit"] = limit

    params["types"] = types

    params["after"] = after


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/events/recent",
        "params": params,
    }


    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | list[RecentEvent] | None:
    if response.status_code == 200:
        response_200 = []
        _response_200 = response.json()
        for response_200_item_data in (_response_200):
            response_200_item = RecentEvent.from_dict(response_200_item_data)



            response_200.append(response_200_item)

        return response_200

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | list[RecentEvent]]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    types: str | Unset = UNSET,
    after: int | Unset = UNSET,

) -> Response[ProblemDetails | list[RecentEvent]]:
    """ Recent job, plan, alarm, io and analog events.

     The newest events the service still holds (it keeps the last 1000 job, plan, alarm, io and analog
    events of this run; state events are not kept), oldest first, with the ids and data of
    the event stream: a page that reloads shows what happened before, then opens
    `GET /api/v1/events?last_event_id=<the last id>` to continue without a gap.

    **Access:** role `viewer` or higher.

    Args:
        limit (int | Unset):
        types (str | Unset):
        after (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | list[RecentEvent]]
     """


    kwargs = _get_kwargs(
        limit=limit,
types=types,
after=after,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    types: str | Unset = UNSET,
    after: int | Unset = UNSET,

) -> ProblemDetails | list[RecentEvent] | None:
    """ Recent job, plan, alarm, io and analog events.

     The newest events the service still holds (it keeps the last 1000 job, plan, alarm, io and analog
    events of this run; state events are not kept), oldest first, with the ids and data of
    the event stream: a page that reloads shows what happened before, then opens
    `GET /api/v1/events?last_event_id=<the last id>` to continue without a gap.

    **Access:** role `viewer` or higher.

    Args:
        limit (int | Unset):
        types (str | Unset):
        after (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | list[RecentEvent]
     """


    return sync_detailed(
        client=client,
limit=limit,
types=types,
after=after,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    types: str | Unset = UNSET,
    after: int | Unset = UNSET,

) -> Response[ProblemDetails | list[RecentEvent]]:
    """ Recent job, plan, alarm, io and analog events.

     The newest events the service still holds (it keeps the last 1000 job, plan, alarm, io and analog
    events of this run; state events are not kept), oldest first, with the ids and data of
    the event stream: a page that reloads shows what happened before, then opens
    `GET /api/v1/events?last_event_id=<the last id>` to continue without a gap.

    **Access:** role `viewer` or higher.

    Args:
        limit (int | Unset):
        types (str | Unset):
        after (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | list[RecentEvent]]
     """


    kwargs = _get_kwargs(
        limit=limit,
types=types,
after=after,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    types: str | Unset = UNSET,
    after: int | Unset = UNSET,

) -> ProblemDetails | list[RecentEvent] | None:
    """ Recent job, plan, alarm, io and analog events.

     The newest events the service still holds (it keeps the last 1000 job, plan, alarm, io and analog
    events of this run; state events are not kept), oldest first, with the ids and data of
    the event stream: a page that reloads shows what happened before, then opens
    `GET /api/v1/events?last_event_id=<the last id>` to continue without a gap.

    **Access:** role `viewer` or higher.

    Args:
        limit (int | Unset):
        types (str | Unset):
        after (int | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | list[RecentEvent]
     """


    return (await asyncio_detailed(
        client=client,
limit=limit,
types=types,
after=after,

    )).parsed
