from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.output_write import OutputWrite
from ...models.problem_details import ProblemDetails
from ...models.signal import Signal
from typing import cast



def _get_kwargs(
    signal: str,
    *,
    body: OutputWrite,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/io/outputs/{signal}".format(signal=quote(str(signal), safe=""),),
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | Signal | None:
    if response.status_code == 200:
        response_200 = Signal.from_dict(response.json())



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

    if response.status_code == 409:
        response_409 = ProblemDetails.from_dict(response.json())



        return response_409

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | Signal]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    signal: str,
    *,
    client: AuthenticatedClient,
    body: OutputWrite,

) -> Response[ProblemDetails | Signal]:
    """ Set a digital output the site allows clients to write.

     Only outputs listed in the site's `[io] outputs` may be written (by number
    or name); any other is refused with 403 `output_not_allowed` and nothing
    reaches the controller. Queued like every command: it runs after the
    motions sent before it. `pulse_ms` returns the output to the other value
    after that time. Answers the signal as set.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        signal (str):
        body (OutputWrite): The body of an output write. Example: {'value': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | Signal]
     """


    kwargs = _get_kwargs(
        signal=signal,
body=body,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    signal: str,
    *,
    client: AuthenticatedClient,
    body: OutputWrite,

) -> ProblemDetails | Signal | None:
    """ Set a digital output the site allows clients to write.

     Only outputs listed in the site's `[io] outputs` may be written (by number
    or name); any other is refused with 403 `output_not_allowed` and nothing
    reaches the controller. Queued like every command: it runs after the
    motions sent before it. `pulse_ms` returns the output to the other value
    after that time. Answers the signal as set.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        signal (str):
        body (OutputWrite): The body of an output write. Example: {'value': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | Signal
     """


    return sync_detailed(
        signal=signal,
client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    signal: str,
    *,
    client: AuthenticatedClient,
    body: OutputWrite,

) -> Response[ProblemDetails | Signal]:
    """ Set a digital output the site allows clients to write.

     Only outputs listed in the site's `[io] outputs` may be written (by number
    or name); any other is refused with 403 `output_not_allowed` and nothing
    reaches the controller. Queued like every command: it runs after the
    motions sent before it. `pulse_ms` returns the output to the other value
    after that time. Answers the signal as set.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        signal (str):
        body (OutputWrite): The body of an output write. Example: {'value': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | Signal]
     """


    kwargs = _get_kwargs(
        signal=signal,
body=body,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    signal: str,
    *,
    client: AuthenticatedClient,
    body: OutputWrite,

) -> ProblemDetails | Signal | None:
    """ Set a digital output the site allows clients to write.

     Only outputs listed in the site's `[io] outputs` may be written (by number
    or name); any other is refused with 403 `output_not_allowed` and nothing
    reaches the controller. Queued like every command: it runs after the
    motions sent before it. `pulse_ms` returns the output to the other value
    after that time. Answers the signal as set.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        signal (str):
        body (OutputWrite): The body of an output write. Example: {'value': True}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | Signal
     """


    return (await asyncio_detailed(
        signal=signal,
client=client,
body=body,

    )).parsed
