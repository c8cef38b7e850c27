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
        "method": "post",
        "url": "/api/v1/sim/acknowledge",
    }


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

) -> Response[Any | ProblemDetails]:
    """ The operator acknowledges the controller's stop message, switches the
    drives on and (KRC-like runtime) starts the bridge's program again.

     After a safety stop (`PUT /api/v1/sim/safety`) or an error stop (a
    program that failed, a motion stopped on its path) a KRC waits for the
    operator: the message is acknowledged on the teach pendant (or by the
    PLC), the drives are switched on and `kb_main` selected and started
    again. Until then the state reports `controller_error` ("not ready").
    This does what the operator would, on the simulated controller. A job
    the stop ended leaves the controller in its error state until
    `POST /api/v1/reset`, as on a KRC. 409 `controller_error` while the
    emergency stop is still pressed or the operator safety still open.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Any | ProblemDetails]
     """


    kwargs = _get_kwargs(
        
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,

) -> Any | ProblemDetails | None:
    """ The operator acknowledges the controller's stop message, switches the
    drives on and (KRC-like runtime) starts the bridge's program again.

     After a safety stop (`PUT /api/v1/sim/safety`) or an error stop (a
    program that failed, a motion stopped on its path) a KRC waits for the
    operator: the message is acknowledged on the teach pendant (or by the
    PLC), the drives are switched on and `kb_main` selected and started
    again. Until then the state reports `controller_error` ("not ready").
    This does what the operator would, on the simulated controller. A job
    the stop ended leaves the controller in its error state until
    `POST /api/v1/reset`, as on a KRC. 409 `controller_error` while the
    emergency stop is still pressed or the operator safety still open.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Any | ProblemDetails
     """


    return sync_detailed(
        client=client,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,

) -> Response[Any | ProblemDetails]:
    """ The operator acknowledges the controller's stop message, switches the
    drives on and (KRC-like runtime) starts the bridge's program again.

     After a safety stop (`PUT /api/v1/sim/safety`) or an error stop (a
    program that failed, a motion stopped on its path) a KRC waits for the
    operator: the message is acknowledged on the teach pendant (or by the
    PLC), the drives are switched on and `kb_main` selected and started
    again. Until then the state reports `controller_error` ("not ready").
    This does what the operator would, on the simulated controller. A job
    the stop ended leaves the controller in its error state until
    `POST /api/v1/reset`, as on a KRC. 409 `controller_error` while the
    emergency stop is still pressed or the operator safety still open.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Any | ProblemDetails]
     """


    kwargs = _get_kwargs(
        
    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,

) -> Any | ProblemDetails | None:
    """ The operator acknowledges the controller's stop message, switches the
    drives on and (KRC-like runtime) starts the bridge's program again.

     After a safety stop (`PUT /api/v1/sim/safety`) or an error stop (a
    program that failed, a motion stopped on its path) a KRC waits for the
    operator: the message is acknowledged on the teach pendant (or by the
    PLC), the drives are switched on and `kb_main` selected and started
    again. Until then the state reports `controller_error` ("not ready").
    This does what the operator would, on the simulated controller. A job
    the stop ended leaves the controller in its error state until
    `POST /api/v1/reset`, as on a KRC. 409 `controller_error` while the
    emergency stop is still pressed or the operator safety still open.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Any | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,

    )).parsed
