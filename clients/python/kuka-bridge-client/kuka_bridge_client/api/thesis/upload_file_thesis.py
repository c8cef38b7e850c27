from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.problem_details import ProblemDetails
from ...models.thesis_problem import ThesisProblem
from ...models.thesis_response import ThesisResponse
from ...models.upload_form import UploadForm
from ...types import UNSET, Unset
from typing import cast



def _get_kwargs(
    *,
    body:    UploadForm  |     str  | Unset = UNSET,
    access_token: str | Unset = UNSET,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    params: dict[str, Any] = {}

    params["access_token"] = access_token


    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}


    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/krl/uploadfile",
        "params": params,
    }

    if isinstance(body, UploadForm):
        _kwargs["files"] = body.to_multipart()

        headers["Content-Type"] = "multipart/form-data; boundary=+++"
    if isinstance(body, str):
        _kwargs["content"] = body.payload
        headers["Content-Type"] = "text/plain"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> ProblemDetails | ThesisProblem | ThesisResponse | None:
    if response.status_code == 200:
        response_200 = ThesisResponse.from_dict(response.json())



        return response_200

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
        response_4xx = ThesisProblem.from_dict(response.json())



        return response_4xx

    if 500 <= response.status_code <= 599:
        response_5xx = ThesisProblem.from_dict(response.json())



        return response_5xx

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[ProblemDetails | ThesisProblem | ThesisResponse]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body:    UploadForm  |     str  | Unset = UNSET,
    access_token: str | Unset = UNSET,

) -> Response[ProblemDetails | ThesisProblem | ThesisResponse]:
    """ Uploads a KRL file and runs it (thesis method 10).

     The body is the `.src` text, either as a `multipart/form-data` file part (the thesis
    client's form upload: the part named `file`, else the first part with a file name) or as
    the raw request body. The file
    must define `DEFFCT INT fuploaded()` (the thesis convention) or its first routine is
    run. It is checked before anything reaches the controller, stored as program
    `uploaded`, written as a new module and run — every upload runs its own code, not the
    first one. Answers when the program has ended.

    **Access:** role `admin` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        access_token (str | Unset):
        body (UploadForm): The form a thesis client posts to `/krl/uploadfile`.
        body (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | ThesisProblem | ThesisResponse]
     """


    kwargs = _get_kwargs(
        body=body,
access_token=access_token,

    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)

def sync(
    *,
    client: AuthenticatedClient,
    body:    UploadForm  |     str  | Unset = UNSET,
    access_token: str | Unset = UNSET,

) -> ProblemDetails | ThesisProblem | ThesisResponse | None:
    """ Uploads a KRL file and runs it (thesis method 10).

     The body is the `.src` text, either as a `multipart/form-data` file part (the thesis
    client's form upload: the part named `file`, else the first part with a file name) or as
    the raw request body. The file
    must define `DEFFCT INT fuploaded()` (the thesis convention) or its first routine is
    run. It is checked before anything reaches the controller, stored as program
    `uploaded`, written as a new module and run — every upload runs its own code, not the
    first one. Answers when the program has ended.

    **Access:** role `admin` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        access_token (str | Unset):
        body (UploadForm): The form a thesis client posts to `/krl/uploadfile`.
        body (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | ThesisProblem | ThesisResponse
     """


    return sync_detailed(
        client=client,
body=body,
access_token=access_token,

    ).parsed

async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body:    UploadForm  |     str  | Unset = UNSET,
    access_token: str | Unset = UNSET,

) -> Response[ProblemDetails | ThesisProblem | ThesisResponse]:
    """ Uploads a KRL file and runs it (thesis method 10).

     The body is the `.src` text, either as a `multipart/form-data` file part (the thesis
    client's form upload: the part named `file`, else the first part with a file name) or as
    the raw request body. The file
    must define `DEFFCT INT fuploaded()` (the thesis convention) or its first routine is
    run. It is checked before anything reaches the controller, stored as program
    `uploaded`, written as a new module and run — every upload runs its own code, not the
    first one. Answers when the program has ended.

    **Access:** role `admin` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        access_token (str | Unset):
        body (UploadForm): The form a thesis client posts to `/krl/uploadfile`.
        body (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ProblemDetails | ThesisProblem | ThesisResponse]
     """


    kwargs = _get_kwargs(
        body=body,
access_token=access_token,

    )

    response = await client.get_async_httpx_client().request(
        **kwargs
    )

    return _build_response(client=client, response=response)

async def asyncio(
    *,
    client: AuthenticatedClient,
    body:    UploadForm  |     str  | Unset = UNSET,
    access_token: str | Unset = UNSET,

) -> ProblemDetails | ThesisProblem | ThesisResponse | None:
    """ Uploads a KRL file and runs it (thesis method 10).

     The body is the `.src` text, either as a `multipart/form-data` file part (the thesis
    client's form upload: the part named `file`, else the first part with a file name) or as
    the raw request body. The file
    must define `DEFFCT INT fuploaded()` (the thesis convention) or its first routine is
    run. It is checked before anything reaches the controller, stored as program
    `uploaded`, written as a new module and run — every upload runs its own code, not the
    first one. Answers when the program has ended.

    **Access:** role `admin` or higher; refused with 409 `control_held` while another client holds
    control.

    Args:
        access_token (str | Unset):
        body (UploadForm): The form a thesis client posts to `/krl/uploadfile`.
        body (str):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ProblemDetails | ThesisProblem | ThesisResponse
     """


    return (await asyncio_detailed(
        client=client,
body=body,
access_token=access_token,

    )).parsed
