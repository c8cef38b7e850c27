from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.variable import Variable
from ...models.variable_write import VariableWrite
from typing import cast



def _get_kwargs(
    name: str,
    *,
    body: VariableWrite,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/variables/{name}".format(name=quote(str(name), safe=""),),
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | Variable | None:
    if response.status_code == 200:
        response_200 = Variable.from_dict(response.json())



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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | Variable]:
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
    body: VariableWrite,

) -> Response[ProblemDetails | Variable]:
    """ Write a KRL variable on the site's allow-list.

     Only names in `[variables] writable` (else 403 `variable_not_allowed`,
    nothing sent). The value is typed JSON, turned into KRL text by the
    service; an operator's token and the control lease are needed; every
    write is audited. Answers the value the controller reports afterwards.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (VariableWrite): The body of a variable write. Example: {'value': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | Variable]
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
    body: VariableWrite,

) -> ProblemDetails | Variable | None:
    """ Write a KRL variable on the site's allow-list.

     Only names in `[variables] writable` (else 403 `variable_not_allowed`,
    nothing sent). The value is typed JSON, turned into KRL text by the
    service; an operator's token and the control lease are needed; every
    write is audited. Answers the value the controller reports afterwards.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (VariableWrite): The body of a variable write. Example: {'value': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | Variable
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
    body: VariableWrite,

) -> Response[ProblemDetails | Variable]:
    """ Write a KRL variable on the site's allow-list.

     Only names in `[variables] writable` (else 403 `variable_not_allowed`,
    nothing sent). The value is typed JSON, turned into KRL text by the
    service; an operator's token and the control lease are needed; every
    write is audited. Answers the value the controller reports afterwards.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (VariableWrite): The body of a variable write. Example: {'value': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | Variable]
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
    body: VariableWrite,

) -> ProblemDetails | Variable | None:
    """ Write a KRL variable on the site's allow-list.

     Only names in `[variables] writable` (else 403 `variable_not_allowed`,
    nothing sent). The value is typed JSON, turned into KRL text by the
    service; an operator's token and the control lease are needed; every
    write is audited. Answers the value the controller reports afterwards.

    **Access:** role `operator` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        name (str):
        body (VariableWrite): The body of a variable write. Example: {'value': 50}.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | Variable
     """


    return (await asyncio_detailed(
        name=name,
client=client,
body=body,

    )).parsed
