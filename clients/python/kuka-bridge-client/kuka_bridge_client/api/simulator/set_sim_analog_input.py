from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.analog_input_value import AnalogInputValue
from ...models.problem_details import ProblemDetails
from typing import cast



def _get_kwargs(
    index: str,
    *,
    body: AnalogInputValue,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/sim/analog-inputs/{index}".format(index=quote(str(index), safe=""),),
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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[Any | ProblemDetails]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    index: str,
    *,
    client: AuthenticatedClient,
    body: AnalogInputValue,

) -> Response[Any | ProblemDetails]:
    """ Set an analog input of the simulated controller (`$ANIN[index]`,
    1..=32, or an analog input's name from the site's `[io]`), as a sensor
    would; the next state file reports it (`GET /api/v1/io/analog`).

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        index (str):
        body (AnalogInputValue): The body of a simulated analog input. Example: {'value': 0.25}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Any | ProblemDetails]
     """


    kwargs = _get_kwargs(
        index=index,
body=body,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    index: str,
    *,
    client: AuthenticatedClient,
    body: AnalogInputValue,

) -> Any | ProblemDetails | None:
    """ Set an analog input of the simulated controller (`$ANIN[index]`,
    1..=32, or an analog input's name from the site's `[io]`), as a sensor
    would; the next state file reports it (`GET /api/v1/io/analog`).

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        index (str):
        body (AnalogInputValue): The body of a simulated analog input. Example: {'value': 0.25}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Any | ProblemDetails
     """


    return sync_detailed(
        index=index,
client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    index: str,
    *,
    client: AuthenticatedClient,
    body: AnalogInputValue,

) -> Response[Any | ProblemDetails]:
    """ Set an analog input of the simulated controller (`$ANIN[index]`,
    1..=32, or an analog input's name from the site's `[io]`), as a sensor
    would; the next state file reports it (`GET /api/v1/io/analog`).

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        index (str):
        body (AnalogInputValue): The body of a simulated analog input. Example: {'value': 0.25}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Any | ProblemDetails]
     """


    kwargs = _get_kwargs(
        index=index,
body=body,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    index: str,
    *,
    client: AuthenticatedClient,
    body: AnalogInputValue,

) -> Any | ProblemDetails | None:
    """ Set an analog input of the simulated controller (`$ANIN[index]`,
    1..=32, or an analog input's name from the site's `[io]`), as a sensor
    would; the next state file reports it (`GET /api/v1/io/analog`).

     

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        index (str):
        body (AnalogInputValue): The body of a simulated analog input. Example: {'value': 0.25}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Any | ProblemDetails
     """


    return (await asyncio_detailed(
        index=index,
client=client,
body=body,

    )).parsed
