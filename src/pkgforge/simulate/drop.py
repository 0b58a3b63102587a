"""The drop test's own process: reads {"urdf", "seconds", "memory", "cpu"} as JSON on stdin,
answers {"problems": [...], "error"} as JSON on stdout. Limits itself before it reads the model:
address space, CPU seconds, no core file, the parent's death ends it, and (Landlock) no writes."""

from __future__ import annotations

import json
import math
import re
import sys
from typing import Any

OVERLAP = 0.01  # m: collision shapes of links not joined to each other this deep inside each other
# (meshes count as their convex hulls: a concave link shell holds its neighbour a few mm deep)
LINEAR_SPEED = 100.0  # m/s: a limp arm falling for 2 s reaches a few m/s
ANGULAR_SPEED = 500.0  # rad/s (~4800 rpm)
SPEED_EVERY = 10  # steps between two looks at the links' speeds


def _limit(request: dict[str, Any]) -> None:
    import os
    import resource

    for kind, value in (
        (resource.RLIMIT_AS, int(request.get("memory") or 0)),
        (resource.RLIMIT_CPU, int(request.get("cpu") or 0)),
        (resource.RLIMIT_CORE, 0),
    ):
        if value or kind == resource.RLIMIT_CORE:
            try:
                resource.setrlimit(kind, (value, value))
            except (ValueError, OSError):
                pass
    from pkgforge.sandbox.landlock import LandlockError, restrict
    from pkgforge.sandbox.processes import die_with_parent

    die_with_parent(os.getppid())
    try:
        restrict([])  # writes nowhere (MuJoCo reads the model and its meshes, writes nothing)
    except LandlockError:
        pass  # a kernel without Landlock: the limits and the timeout still hold


def _named(message: str) -> list[str]:
    """The element names MuJoCo's message gives ("Element name 'arm', id 3")."""
    return re.findall(r"[Ee]lement name '([^']*)'", message)


def run(request: dict[str, Any]) -> dict[str, Any]:
    import mujoco
    import numpy

    try:
        model = mujoco.MjModel.from_xml_string(request["urdf"])
    except ValueError as error:  # (MuJoCo's XML and compiler errors)
        text = str(error).strip()
        first = next((line for line in text.splitlines() if line.strip()), text).removeprefix("Error: ")
        return {"problems": [{"kind": "refused", "message": first[:240], "links": _named(text)}]}
    data = mujoco.MjData(model)
    problems: list[dict[str, Any]] = []
    body = [model.body(i).name for i in range(model.nbody)]
    root = str(request.get("root") or "world")  # the link MuJoCo fuses into its world body
    _within_limits(model, data)
    mujoco.mj_forward(model, data)
    seen = set()
    for contact in data.contact[: data.ncon]:
        one, other = (int(model.geom_bodyid[g]) for g in contact.geom)
        # MuJoCo skips parent and child, but not a child of the world (the root link is fused
        # into the world body): joined by a joint all the same
        if one == other or model.body_parentid[one] == other or model.body_parentid[other] == one:
            continue
        first, second = (root if b == 0 else body[b] for b in (one, other))
        pair = tuple(sorted((first, second)))
        if contact.dist < -OVERLAP and pair not in seen:
            seen.add(pair)
            problems.append(
                {
                    "kind": "overlap",
                    "message": f"{-contact.dist * 1000:.3g} mm deep",
                    "links": list(pair),
                }
            )
    steps = max(1, round(float(request.get("seconds") or 2.0) / model.opt.timestep))
    velocity = numpy.zeros(6)
    bad = mujoco.mjtWarning.mjWARN_BADQACC
    for step in range(steps):
        mujoco.mj_step(model, data)
        if data.warning[bad].number or not (
            numpy.isfinite(data.qpos).all() and numpy.isfinite(data.qvel).all()
        ):
            dof = int(data.warning[bad].lastinfo)
            joint = model.joint(int(model.dof_jntid[dof])).name if 0 <= dof < model.nv else None
            problems.append(
                {
                    "kind": "unstable",
                    "message": f"non-finite or huge accelerations after {step * model.opt.timestep:.3g} s",
                    "joint": joint,
                    "links": [body[int(model.jnt_bodyid[model.dof_jntid[dof]])]] if joint is not None else [],
                }
            )
            break
        if step % SPEED_EVERY:
            continue
        fast = _too_fast(mujoco, model, data, velocity, body)
        if fast is not None:
            name, linear, angular = fast
            problems.append(
                {
                    "kind": "unstable",
                    "message": f"reaches {linear:.3g} m/s and {angular:.3g} rad/s after "
                    f"{step * model.opt.timestep:.3g} s",
                    "links": [name],
                }
            )
            break
    return {"problems": problems}


def _within_limits(model: Any, data: Any) -> None:
    """Each joint at 0, or at its nearest limit when 0 is outside them (the Panda's joint 4 runs
    from -3.07 to -0.07): where a simulator's limits put the robot at its first step."""
    for joint in range(model.njnt):
        if model.jnt_limited[joint] and model.jnt_type[joint] in (2, 3):  # slide, hinge
            low, high = model.jnt_range[joint]
            address = model.jnt_qposadr[joint]
            data.qpos[address] = min(max(0.0, low), high)


def _too_fast(
    mujoco: Any, model: Any, data: Any, velocity: Any, body: list[str]
) -> tuple[str, float, float] | None:
    for index in range(1, model.nbody):
        mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, index, velocity, 0)
        angular = math.sqrt(sum(v * v for v in velocity[:3]))
        linear = math.sqrt(sum(v * v for v in velocity[3:]))
        if linear > LINEAR_SPEED or angular > ANGULAR_SPEED:
            return body[index], linear, angular
    return None


def main() -> int:
    request = json.loads(sys.stdin.buffer.read().decode("utf-8"))
    _limit(request)
    try:
        answer = run(request)
    except ImportError:
        answer = {"problems": [], "error": "MuJoCo is not installed (pip install 'ros-pkgforge[simulate]')"}
    except MemoryError:
        answer = {"problems": [], "error": "the drop test ran out of memory"}
    sys.stdout.write(json.dumps(answer))
    return 0


if __name__ == "__main__":
    sys.exit(main())
