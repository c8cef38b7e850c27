"""A plugin's own error code reaches the generated client unchanged.

    python plugin_errors.py BASE_URL MISBEHAVE_WASM

Installs the test plugin ``misbehave`` from its bytes and asks its
``/refuse`` route for an error with a code of its own.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "kuka-bridge-client"))

from kuka_bridge_client.api.plugins import install_plugin, remove_plugin  # noqa: E402
from kuka_bridge_client.types import File  # noqa: E402
from kuka_bridge_extras import ProblemError, call_plugin, connect, ok  # noqa: E402


def main() -> int:
    client = connect(sys.argv[1])
    ok(install_plugin.sync("misbehave", client=client, body=File(payload=Path(sys.argv[2]).read_bytes())))
    try:
        call_plugin(client, "misbehave", "/refuse", {"status": 409, "code": "cable_snag", "detail": "the cable is caught"})
        print("the plugin's refusal was taken for success")
        return 1
    except ProblemError as e:
        print(f"plugin code: {e.problem.code}, status {e.problem.status}, detail {e.problem.detail}")
    remove_plugin.sync_detailed("misbehave", client=client)
    return 0


if __name__ == "__main__":
    sys.exit(main())
