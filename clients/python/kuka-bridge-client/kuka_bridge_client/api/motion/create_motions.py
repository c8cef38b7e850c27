from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.job import Job
from ...models.motion_batch import MotionBatch
from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    *,
    body: MotionBatch,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/motions",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Job | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = Job.from_dict(response.json())



        return response_200

    if response.status_code == 202:
        response_202 = Job.from_dict(response.json())



        return response_202

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

    if response.status_code == 409:
        response_409 = ProblemDetails.from_dict(response.json())



        return response_409

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[Job | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: MotionBatch,

) -> Response[Job | ProblemDetails]:
    """ Execute motions (PTP, axis PTP, LIN, CIRC), one or a continuous batch.

     Each request is validated (numbers, Status/Turn, speed caps, workspace box, and with a
    robot model a dry run for reachability, software limits and singularities) before
    anything is written; a rejected request moves nothing. Omitted coordinates keep the
    previous target's value; `relative: true` adds to it. Requests are executed in arrival
    order. With `wait` (default) the answer is the finished job; otherwise 202 and the
    queued job with a `Location` header.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (MotionBatch): A motion request: one motion or a continuous batch. Example:
            {'motions': [{'type': 'ptp', 'target': {'x': 200, 'y': 0, 'z': 100, 'a': 0, 'b': 180, 'c':
            0}}, {'type': 'lin', 'target': {'z': 70}, 'velocity_m_s': 0.1}, {'type': 'circ', 'aux':
            {'x': 250, 'y': 50}, 'target': {'x': 200, 'y': 100}, 'approx_mm': 2}, {'type': 'lin',
            'target': {'z': 100}}], 'wait': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
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
    body: MotionBatch,

) -> Job | ProblemDetails | None:
    """ Execute motions (PTP, axis PTP, LIN, CIRC), one or a continuous batch.

     Each request is validated (numbers, Status/Turn, speed caps, workspace box, and with a
    robot model a dry run for reachability, software limits and singularities) before
    anything is written; a rejected request moves nothing. Omitted coordinates keep the
    previous target's value; `relative: true` adds to it. Requests are executed in arrival
    order. With `wait` (default) the answer is the finished job; otherwise 202 and the
    queued job with a `Location` header.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (MotionBatch): A motion request: one motion or a continuous batch. Example:
            {'motions': [{'type': 'ptp', 'target': {'x': 200, 'y': 0, 'z': 100, 'a': 0, 'b': 180, 'c':
            0}}, {'type': 'lin', 'target': {'z': 70}, 'velocity_m_s': 0.1}, {'type': 'circ', 'aux':
            {'x': 250, 'y': 50}, 'target': {'x': 200, 'y': 100}, 'approx_mm': 2}, {'type': 'lin',
            'target': {'z': 100}}], 'wait': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: MotionBatch,

) -> Response[Job | ProblemDetails]:
    """ Execute motions (PTP, axis PTP, LIN, CIRC), one or a continuous batch.

     Each request is validated (numbers, Status/Turn, speed caps, workspace box, and with a
    robot model a dry run for reachability, software limits and singularities) before
    anything is written; a rejected request moves nothing. Omitted coordinates keep the
    previous target's value; `relative: true` adds to it. Requests are executed in arrival
    order. With `wait` (default) the answer is the finished job; otherwise 202 and the
    queued job with a `Location` header.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (MotionBatch): A motion request: one motion or a continuous batch. Example:
            {'motions': [{'type': 'ptp', 'target': {'x': 200, 'y': 0, 'z': 100, 'a': 0, 'b': 180, 'c':
            0}}, {'type': 'lin', 'target': {'z': 70}, 'velocity_m_s': 0.1}, {'type': 'circ', 'aux':
            {'x': 250, 'y': 50}, 'target': {'x': 200, 'y': 100}, 'approx_mm': 2}, {'type': 'lin',
            'target': {'z': 100}}], 'wait': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
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
    body: MotionBatch,

) -> Job | ProblemDetails | None:
    """ Execute motions (PTP, axis PTP, LIN, CIRC), one or a continuous batch.

     Each request is validated (numbers, Status/Turn, speed caps, workspace box, and with a
    robot model a dry run for reachability, software limits and singularities) before
    anything is written; a rejected request moves nothing. Omitted coordinates keep the
    previous target's value; `relative: true` adds to it. Requests are executed in arrival
    order. With `wait` (default) the answer is the finished job; otherwise 202 and the
    queued job with a `Location` header.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        body (MotionBatch): A motion request: one motion or a continuous batch. Example:
            {'motions': [{'type': 'ptp', 'target': {'x': 200, 'y': 0, 'z': 100, 'a': 0, 'b': 180, 'c':
            0}}, {'type': 'lin', 'target': {'z': 70}, 'velocity_m_s': 0.1}, {'type': 'circ', 'aux':
            {'x': 250, 'y': 50}, 'target': {'x': 200, 'y': 100}, 'approx_mm': 2}, {'type': 'lin',
            'target': {'z': 100}}], 'wait': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
