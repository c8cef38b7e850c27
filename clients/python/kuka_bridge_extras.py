"""Hand-written helpers for the generated ``kuka_bridge_client`` package.

Only what the generator cannot express: connecting with or without a token
(the service needs one only beyond loopback), raising a typed error instead
of returning it, and calling a plugin's routes (they exist only at run time,
so they are not in the generated API).
"""

from __future__ import annotations

import json
from typing import Any, TypeVar

from kuka_bridge_client import AuthenticatedClient
from kuka_bridge_client.models import ProblemDetails

T = TypeVar("T")


class ProblemError(Exception):
    """An answer of ``application/problem+json``: ``problem.code`` is stable."""

    def __init__(self, problem: ProblemDetails):
        super().__init__(f"{problem.status} {problem.code}: {problem.detail}")
        self.problem = problem


def connect(base_url: str, token: str | None = None, timeout_s: float = 120.0) -> AuthenticatedClient:
    """A client for ``base_url``; ``token`` may be omitted on loopback."""
    import httpx

    if token:
        return AuthenticatedClient(
            base_url=base_url, token=token, timeout=httpx.Timeout(timeout_s), raise_on_unexpected_status=True
        )
    # The generated operations take an AuthenticatedClient; without a token
    # it sends a harmless header instead of an empty `Authorization`.
    return AuthenticatedClient(
        base_url=base_url,
        token="none",
        prefix="",
        auth_header_name="X-Kb-No-Token",
        timeout=httpx.Timeout(timeout_s),
        raise_on_unexpected_status=True,
    )


def ok(result: T | ProblemDetails | None) -> T | None:
    """The result, or :class:`ProblemError` for a problem document. ``None``
    for a documented answer without a body (204); an undocumented status
    raises ``errors.UnexpectedStatus`` already (the client of :func:`connect`)."""
    if isinstance(result, ProblemDetails):
        raise ProblemError(result)
    return result


def call_plugin(client: AuthenticatedClient, plugin: str, path: str, body: dict[str, Any] | None = None) -> Any:
    """POSTs ``body`` (or GETs without one) to a plugin route; its JSON answer,
    or :class:`ProblemError` with the plugin's own ``code`` when it refuses."""
    http = client.get_httpx_client()
    url = f"/api/v1/plugins/{plugin}{path}"
    response = http.get(url) if body is None else http.post(url, json=body)
    if response.status_code >= 400:
        raise ProblemError(ProblemDetails.from_dict(json.loads(response.content)))
    return response.json()
