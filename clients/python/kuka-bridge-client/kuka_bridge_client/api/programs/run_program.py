from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.job import Job
from ...models.problem_details import ProblemDetails
from ...models.run_request import RunRequest
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    name: str,
    *,
    body: None | RunRequest | Unset = UNSET,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/programs/{name}/run".format(name=quote(str(name), safe=""),),
    }

    
    if isinstance(body, RunRequest):
        _kwargs["json"] = body.to_dict()
    else:
        _kwargs["json"] = body

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
    name: str,
    *,
    client: AuthenticatedClient,
    body: None | RunRequest | Unset = UNSET,

) -> Response[Job | ProblemDetails]:
    """ Runs a stored program on the controller.

     Writes the module `kbu<cid>` (a new name every time) into the controller's program
    folder and sends one RUN command; queued like any motion. Waits for the end by default.
    A failure names the program line (`line`): `program_failed`, `program_unsupported`,
    or a motion error such as `unreachable`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (None | RunRequest | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
     """


    kwargs = _get_kwargs(
        name=name,
body=body,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    name: str,
    *,
    client: AuthenticatedClient,
    body: None | RunRequest | Unset = UNSET,

) -> Job | ProblemDetails | None:
    """ Runs a stored program on the controller.

     Writes the module `kbu<cid>` (a new name every time) into the controller's program
    folder and sends one RUN command; queued like any motion. Waits for the end by default.
    A failure names the program line (`line`): `program_failed`, `program_unsupported`,
    or a motion error such as `unreachable`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (None | RunRequest | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return sync_detailed(
        name=name,
client=client,
body=body,

    ).parsed

async def asyncio_detailed(
    name: str,
    *,
    client: AuthenticatedClient,
    body: None | RunRequest | Unset = UNSET,

) -> Response[Job | ProblemDetails]:
    """ Runs a stored program on the controller.

     Writes the module `kbu<cid>` (a new name every time) into the controller's program
    folder and sends one RUN command; queued like any motion. Waits for the end by default.
    A failure names the program line (`line`): `program_failed`, `program_unsupported`,
    or a motion error such as `unreachable`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (None | RunRequest | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job | ProblemDetails]
     """


    kwargs = _get_kwargs(
        name=name,
body=body,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    name: str,
    *,
    client: AuthenticatedClient,
    body: None | RunRequest | Unset = UNSET,

) -> Job | ProblemDetails | None:
    """ Runs a stored program on the controller.

     Writes the module `kbu<cid>` (a new name every time) into the controller's program
    folder and sends one RUN command; queued like any motion. Waits for the end by default.
    A failure names the program line (`line`): `program_failed`, `program_unsupported`,
    or a motion error such as `unreachable`.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (None | RunRequest | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job | ProblemDetails
     """


    return (await asyncio_detailed(
        name=name,
client=client,
body=body,

    )).parsed
