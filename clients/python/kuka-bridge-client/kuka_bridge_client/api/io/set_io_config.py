from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.io_config import IoConfig
from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    *,
    body: IoConfig,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/io/config",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> IoConfig | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = IoConfig.from_dict(response.json())



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

    if response.status_code == 503:
        response_503 = ProblemDetails.from_dict(response.json())



        return response_503

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[IoConfig | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: IoConfig,

) -> Response[IoConfig | ProblemDetails]:
    """ Replace the site's I/O configuration (admin): names, the outputs
    clients may write, analog channels, watched signals.

     Checked as at start (names, ranges, duplicates; 422 `invalid_input`
    with the reason, nothing changed), then used at once for every request
    that arrives afterwards (a job already queued keeps the signals it
    resolved), and kept in the data folder (`io.json`, private) so that it
    survives a restart; it replaces the configuration file's `[io]` until
    `DELETE /api/v1/io/config`. The change is in the audit trail.

    **Access:** role `admin` or higher.

    Args:
        body (IoConfig): The site's digital I/O: names for inputs, and the outputs clients may
            write (every other output is refused with `output_not_allowed`). Example: {'inputs':
            [{'name': 'part_present', 'index': 3, 'pulse_ms': 0, 'watch': True}], 'outputs': [{'name':
            'gripper_close', 'index': 1, 'pulse_ms': 0, 'watch': True}], 'analog_inputs': [{'name':
            'force', 'index': 2, 'watch': True, 'deadband': 0.05}], 'analog_outputs': [{'name':
            'spindle_speed', 'index': 1, 'watch': False, 'deadband': 0.01}]}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[IoConfig | ProblemDetails]
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
    body: IoConfig,

) -> IoConfig | ProblemDetails | None:
    """ Replace the site's I/O configuration (admin): names, the outputs
    clients may write, analog channels, watched signals.

     Checked as at start (names, ranges, duplicates; 422 `invalid_input`
    with the reason, nothing changed), then used at once for every request
    that arrives afterwards (a job already queued keeps the signals it
    resolved), and kept in the data folder (`io.json`, private) so that it
    survives a restart; it replaces the configuration file's `[io]` until
    `DELETE /api/v1/io/config`. The change is in the audit trail.

    **Access:** role `admin` or higher.

    Args:
        body (IoConfig): The site's digital I/O: names for inputs, and the outputs clients may
            write (every other output is refused with `output_not_allowed`). Example: {'inputs':
            [{'name': 'part_present', 'index': 3, 'pulse_ms': 0, 'watch': True}], 'outputs': [{'name':
            'gripper_close', 'index': 1, 'pulse_ms': 0, 'watch': True}], 'analog_inputs': [{'name':
            'force', 'index': 2, 'watch': True, 'deadband': 0.05}], 'analog_outputs': [{'name':
            'spindle_speed', 'index': 1, 'watch': False, 'deadband': 0.01}]}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        IoConfig | ProblemDetails
     """


    return sync_detailed(
        client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: IoConfig,

) -> Response[IoConfig | ProblemDetails]:
    """ Replace the site's I/O configuration (admin): names, the outputs
    clients may write, analog channels, watched signals.

     Checked as at start (names, ranges, duplicates; 422 `invalid_input`
    with the reason, nothing changed), then used at once for every request
    that arrives afterwards (a job already queued keeps the signals it
    resolved), and kept in the data folder (`io.json`, private) so that it
    survives a restart; it replaces the configuration file's `[io]` until
    `DELETE /api/v1/io/config`. The change is in the audit trail.

    **Access:** role `admin` or higher.

    Args:
        body (IoConfig): The site's digital I/O: names for inputs, and the outputs clients may
            write (every other output is refused with `output_not_allowed`). Example: {'inputs':
            [{'name': 'part_present', 'index': 3, 'pulse_ms': 0, 'watch': True}], 'outputs': [{'name':
            'gripper_close', 'index': 1, 'pulse_ms': 0, 'watch': True}], 'analog_inputs': [{'name':
            'force', 'index': 2, 'watch': True, 'deadband': 0.05}], 'analog_outputs': [{'name':
            'spindle_speed', 'index': 1, 'watch': False, 'deadband': 0.01}]}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[IoConfig | ProblemDetails]
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
    body: IoConfig,

) -> IoConfig | ProblemDetails | None:
    """ Replace the site's I/O configuration (admin): names, the outputs
    clients may write, analog channels, watched signals.

     Checked as at start (names, ranges, duplicates; 422 `invalid_input`
    with the reason, nothing changed), then used at once for every request
    that arrives afterwards (a job already queued keeps the signals it
    resolved), and kept in the data folder (`io.json`, private) so that it
    survives a restart; it replaces the configuration file's `[io]` until
    `DELETE /api/v1/io/config`. The change is in the audit trail.

    **Access:** role `admin` or higher.

    Args:
        body (IoConfig): The site's digital I/O: names for inputs, and the outputs clients may
            write (every other output is refused with `output_not_allowed`). Example: {'inputs':
            [{'name': 'part_present', 'index': 3, 'pulse_ms': 0, 'watch': True}], 'outputs': [{'name':
            'gripper_close', 'index': 1, 'pulse_ms': 0, 'watch': True}], 'analog_inputs': [{'name':
            'force', 'index': 2, 'watch': True, 'deadband': 0.05}], 'analog_outputs': [{'name':
            'spindle_speed', 'index': 1, 'watch': False, 'deadband': 0.01}]}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        IoConfig | ProblemDetails
     """


    return (await asyncio_detailed(
        client=client,
body=body,

    )).parsed
