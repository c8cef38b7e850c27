from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.safety_change import SafetyChange
from typing import cast



def _get_kwargs(
    *,
    body: SafetyChange,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/sim/safety",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Any | ProblemDetails | None:
    if response.status_code == 204:
        response_204 = cast(Any, None)
        return response_204

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[Any | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: SafetyChange,

) -> Response[Any | ProblemDetails]:
    """ Press or release the simulated emergency stop, open or close the
    operator safety (`--simulate` only; either simulator).

     Opening the circuit does what a KRC does: the robot stops where it is
    (here without a braking distance), the drives switch off, a stop
    message appears, the running job fails with `controller_error` and
    every motion is refused until the operator acknowledges
    (`POST /api/v1/sim/acknowledge`) — which a KRC allows only once the
    circuit is closed again — and, if a job was ended, `POST
    /api/v1/reset`. `GET /api/v1/state` shows it in `controller.safety`.

    **Access:** role `operator` or higher.

    Args:
        body (SafetyChange): A change of the simulated cell's safety circuit. Example:
            {'emergency_stop': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Any | ProblemDetails]
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
    body: SafetyChange,

) -> Any | ProblemDetails | None:
    """ Press or release the simulated emergency stop, open or close the
    operator safety (`--simulate` only; either simulator).

     Opening the circuit does what a KRC does: the robot stops where it is
    (here without a braking distance), the drives switch off, a stop
    message appears, the running job fails with `controller_error` and
    every motion is refused until the operator acknowledges
    (`POST /api/v1/sim/acknowledge`) — which a KRC allows only once the
    circuit is closed again — and, if a job was ended, `POST
    /api/v1/reset`. `GET /api/v1/state` shows it in `controller.safety`.

    **Access:** role `operator` or higher.

    Args:
        body (SafetyChange): A change of the simulated cell's safety circuit. Example:
            {'emergency_stop': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Any | ProblemDetails
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: SafetyChange,

) -> Response[Any | ProblemDetails]:
    """ Press or release the simulated emergency stop, open or close the
    operator safety (`--simulate` only; either simulator).

     Opening the circuit does what a KRC does: the robot stops where it is
    (here without a braking distance), the drives switch off, a stop
    message appears, the running job fails with `controller_error` and
    every motion is refused until the operator acknowledges
    (`POST /api/v1/sim/acknowledge`) — which a KRC allows only once the
    circuit is closed again — and, if a job was ended, `POST
    /api/v1/reset`. `GET /api/v1/state` shows it in `controller.safety`.

    **Access:** role `operator` or higher.

    Args:
        body (SafetyChange): A change of the simulated cell's safety circuit. Example:
            {'emergency_stop': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Any | ProblemDetails]
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
    body: SafetyChange,

) -> Any | ProblemDetails | None:
    """ Press or release the simulated emergency stop, open or close the
    operator safety (`--simulate` only; either simulator).

     Opening the circuit does what a KRC does: the robot stops where it is
    (here without a braking distance), the drives switch off, a stop
    message appears, the running job fails with `controller_error` and
    every motion is refused until the operator acknowledges
    (`POST /api/v1/sim/acknowledge`) — which a KRC allows only once the
    circuit is closed again — and, if a job was ended, `POST
    /api/v1/reset`. `GET /api/v1/state` shows it in `controller.safety`.

    **Access:** role `operator` or higher.

    Args:
        body (SafetyChange): A change of the simulated cell's safety circuit. Example:
            {'emergency_stop': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Any | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
