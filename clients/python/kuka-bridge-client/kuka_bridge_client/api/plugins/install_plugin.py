from http import HTTPStatus
from typing import Any, cast
from urllib.parse import quote

import httpx

from ...client import AuthenticatedClient, Client
from ...types import Response, UNSET
from ... import errors

from ...models.plugin_info import PluginInfo
from ...models.problem_details import ProblemDetails
from ...types import File, FileTypes
from io import BytesIO
from typing import cast



def _get_kwargs(
    name: str,
    *,
    body: File,

) -> dict[str, Any]:
    headers: dict[str, Any] = {}


    

    

    _kwargs: dict[str, Any] = {
        "method": "put",
        "url": "/api/v1/plugins/{name}".format(name=quote(str(name), safe=""),),
    }

    _kwargs["content"] = body.payload
    headers["Content-Type"] = "application/wasm"

    _kwargs["headers"] = headers
    return _kwargs



def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> PluginInfo | ProblemDetails | None:
    if response.status_code == 200:
        response_200 = PluginInfo.from_dict(response.json())



        return response_200

    if response.status_code == 201:
        response_201 = PluginInfo.from_dict(response.json())



        return response_201

    if response.status_code == 401:
        response_401 = ProblemDetails.from_dict(response.json())



        return response_401

    if response.status_code == 403:
        response_403 = ProblemDetails.from_dict(response.json())



        return response_403

    if response.status_code == 413:
        response_413 = ProblemDetails.from_dict(response.json())



        return response_413

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


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[PluginInfo | ProblemDetails]:
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
    body: File,

) -> Response[PluginInfo | ProblemDetails]:
    """ Install or replace a plugin.

     The body is the plugin's `.wasm` (a WebAssembly component of the world
    `kuka-bridge:plugin/bridge-plugin@0.1.0`, see docs/PLUGINS.md). It is
    compiled, linked and described before it is activated: a component of
    another world, a description with invalid routes or schemas, or a name
    other than `{name}` is refused and changes nothing. A new version replaces
    the old one atomically; requests in flight finish on the old one. The
    file is kept in the plugins folder and loads again at the next start.

    **Access:** role `admin` or higher.

    Args:
        name (str):
        body (File):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PluginInfo | ProblemDetails]
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
    body: File,

) -> PluginInfo | ProblemDetails | None:
    """ Install or replace a plugin.

     The body is the plugin's `.wasm` (a WebAssembly component of the world
    `kuka-bridge:plugin/bridge-plugin@0.1.0`, see docs/PLUGINS.md). It is
    compiled, linked and described before it is activated: a component of
    another world, a description with invalid routes or schemas, or a name
    other than `{name}` is refused and changes nothing. A new version replaces
    the old one atomically; requests in flight finish on the old one. The
    file is kept in the plugins folder and loads again at the next start.

    **Access:** role `admin` or higher.

    Args:
        name (str):
        body (File):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PluginInfo | ProblemDetails
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
    body: File,

) -> Response[PluginInfo | ProblemDetails]:
    """ Install or replace a plugin.

     The body is the plugin's `.wasm` (a WebAssembly component of the world
    `kuka-bridge:plugin/bridge-plugin@0.1.0`, see docs/PLUGINS.md). It is
    compiled, linked and described before it is activated: a component of
    another world, a description with invalid routes or schemas, or a name
    other than `{name}` is refused and changes nothing. A new version replaces
    the old one atomically; requests in flight finish on the old one. The
    file is kept in the plugins folder and loads again at the next start.

    **Access:** role `admin` or higher.

    Args:
        name (str):
        body (File):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PluginInfo | ProblemDetails]
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
    body: File,

) -> PluginInfo | ProblemDetails | None:
    """ Install or replace a plugin.

     The body is the plugin's `.wasm` (a WebAssembly component of the world
    `kuka-bridge:plugin/bridge-plugin@0.1.0`, see docs/PLUGINS.md). It is
    compiled, linked and described before it is activated: a component of
    another world, a description with invalid routes or schemas, or a name
    other than `{name}` is refused and changes nothing. A new version replaces
    the old one atomically; requests in flight finish on the old one. The
    file is kept in the plugins folder and loads again at the next start.

    **Access:** role `admin` or higher.

    Args:
        name (str):
        body (File):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PluginInfo | ProblemDetails
     """


    return (await asyncio_detailed(
        name=name,
client=client,
body=body,

    )).parsed
