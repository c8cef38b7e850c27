"""Drive a robot through kuka-bridge from Python with the generated client.

    python quickstart.py [BASE_URL] [PLUGIN_WASM]

BASE_URL defaults to http://127.0.0.1:8080 (``kuka-bridge run --simulate``);
KB_TOKEN, if set, is sent as the bearer token. PLUGIN_WASM, if given, is
installed as the plugin ``draw-circle`` and called.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "kuka-bridge-client"))

from kuka_bridge_client.api.motion import create_motions, get_job, move_home  # noqa: E402
from kuka_bridge_client.api.plugins import install_plugin  # noqa: E402
from kuka_bridge_client.api.robot import get_state  # noqa: E402
from kuka_bridge_client.models import (  # noqa: E402
    AuxPoint,
    CircMotion,
    CircMotionType,
    JobState,
    LinMotion,
    LinMotionType,
    MotionBatch,
    PtpMotion,
    PtpMotionType,
    TargetSpec,
)
from kuka_bridge_client.types import File  # noqa: E402
from kuka_bridge_extras import ProblemError, call_plugin, connect, ok  # noqa: E402


def ptp(x: float, y: float, z: float) -> PtpMotion:
    return PtpMotion(type_=PtpMotionType.PTP, target=TargetSpec(x=x, y=y, z=z))


def lin(x: float, y: float, z: float, speed: float = 0.2) -> LinMotion:
    return LinMotion(type_=LinMotionType.LIN, target=TargetSpec(x=x, y=y, z=z), velocity_m_s=speed)


def circ(aux: tuple[float, float, float], to: tuple[float, float, float]) -> CircMotion:
    return CircMotion(
        type_=CircMotionType.CIRC,
        aux=AuxPoint(x=aux[0], y=aux[1], z=aux[2]),
        target=TargetSpec(x=to[0], y=to[1], z=to[2]),
        velocity_m_s=0.2,
    )


def smiley(cx: float, cy: float, z: float, up: float = 20.0) -> list:
    """A face (two half circles), two eyes and a mouth; travel above the paper."""
    r = 40.0
    return [
        ptp(cx + r, cy, z + up),
        lin(cx + r, cy, z),
        circ((cx, cy + r, z), (cx - r, cy, z)),
        circ((cx, cy - r, z), (cx + r, cy, z)),
        lin(cx + r, cy, z + up),
        ptp(cx + 12, cy + 15, z + up),
        lin(cx + 12, cy + 15, z),
        lin(cx + 12, cy + 15, z + up),
        ptp(cx + 12, cy - 15, z + up),
        lin(cx + 12, cy - 15, z),
        lin(cx + 12, cy - 15, z + up),
        ptp(cx - 10, cy + 20, z + up),
        lin(cx - 10, cy + 20, z),
        circ((cx - 22, cy, z), (cx - 10, cy - 20, z)),
        lin(cx - 10, cy - 20, z + up),
    ]


def main() -> int:
    base_url = sys.argv[1] if len(sys.argv) > 1 else "http://127.0.0.1:8080"
    client = connect(base_url, os.environ.get("KB_TOKEN"))

    # 1. Read the state.
    state = ok(get_state.sync(client=client))
    print(f"connection {state.connection}, position {state.position}")

    # 2. PTP, LIN and CIRC, one request each (each answers when done).
    ok(move_home.sync(client=client))
    here = ok(get_state.sync(client=client)).position
    x, y, z = here.x, here.y, here.z - 100
    for motion in (ptp(x - 60, y, z), lin(x - 60, y + 40, z), circ((x - 20, y + 80, z), (x + 20, y + 40, z))):
        job = ok(create_motions.sync(client=client, body=MotionBatch(motions=[motion])))
        print(f"{motion.type_.value}: job {job.id} {job.state.value}")

    # 3. The smiley as one continuous batch, sent without waiting; the job is polled.
    job = ok(create_motions.sync(client=client, body=MotionBatch(motions=smiley(x - 40, y, z - 50), wait=False)))
    while job.state not in (JobState.DONE, JobState.FAILED, JobState.CANCELLED):
        time.sleep(0.1)
        job = ok(get_job.sync(job.id, client=client))
    print(f"smiley: job {job.id} {job.state.value}, {job.completed}/{job.motions} motions")
    if job.state != JobState.DONE:
        return 1

    # 4. An unreachable target is a typed error with a stable code; nothing moves.
    try:
        ok(create_motions.sync(client=client, body=MotionBatch(motions=[ptp(5000, 0, 0)])))
        print("an unreachable target was accepted")
        return 1
    except ProblemError as e:
        print(f"refused as expected: {e.problem.code} ({e.problem.detail})")

    # 5. A plugin installed from its bytes, then called.
    if len(sys.argv) > 2:
        wasm = Path(sys.argv[2]).read_bytes()
        info = ok(install_plugin.sync("draw-circle", client=client, body=File(payload=wasm)))
        print(f"installed {info.name} {info.version}")
        done = call_plugin(client, "draw-circle", "/circle", {"x": x - 40, "y": y, "z": z - 50, "radius": 30})
        print(f"plugin drew {done['completed']} motions")
        try:
            call_plugin(client, "draw-circle", "/circle", {"x": 5000, "y": 0, "z": 0, "radius": 30})
            print("an unreachable circle was accepted")
            return 1
        except ProblemError as e:
            print(f"plugin refused as expected: {e.problem.code}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
