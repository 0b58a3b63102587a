"""verify --simulate: a drop test of each robot model in MuJoCo (the `simulate` extra).

The parent writes a URDF of its own from the structure the model worker extracted (links with
their inertials and collision shapes, joints; no visuals, nothing else of the user's text) and
gives it to a separate Python process (simulate/drop.py) that loads it with MuJoCo's URDF
importer and runs it: base fixed (a URDF root is welded to the world), joints limp (no
actuators), gravity on, 2 s. That process runs with a memory and CPU limit, a timeout, no core
files, and (where the kernel has Landlock) no right to write anywhere: the model is the user's.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

from pkgforge.urdf import physics
from pkgforge.urdf.structure import Geometry, LinkDict, Part, RobotStructure

SECONDS = 2.0  # simulated
TIMEOUT = 60.0  # wall clock, per model (MuJoCo takes ~0.1-1 s for 2 s of a 30-link arm)
MEMORY = 2 << 30  # bytes of address space for the process (MuJoCo's arena is ~100 MiB)
MESH_FORMATS = (".stl", ".obj")  # what MuJoCo reads itself; another mesh stands as its bounding box


@dataclass
class Problem:
    """One thing the drop test found: kind refused | unstable | overlap."""

    kind: str
    message: str
    links: list[str] = field(default_factory=list)  # the links (MuJoCo bodies) it names
    joint: str | None = None


@dataclass
class Outcome:
    """A model's drop test: what it found, what it cost."""

    problems: list[Problem] = field(default_factory=list)
    seconds: float = 0.0  # wall clock of the process
    error: str | None = None  # the test could not run (no mujoco, timeout, limit): why


def available() -> bool:
    """Whether the `simulate` extra is installed (checked without importing MuJoCo here)."""
    import importlib.util

    return importlib.util.find_spec("mujoco") is not None


def model_urdf(robot: RobotStructure, resolve: Callable[[str], Path | None]) -> str:
    """The URDF MuJoCo loads: the model's links, inertials, collision shapes and joints."""
    lines = [
        f"<robot name={quoteattr(robot.get('name') or 'robot')}>",
        # absolute mesh paths as written; no visuals; inertias as given (not from the shapes)
        '<mujoco><compiler strippath="false" discardvisual="true" inertiafromgeom="false"/></mujoco>',
    ]
    for link in robot["links"]:
        lines.append(f"<link name={quoteattr(link['name'] or '')}>")
        lines += _inertial(link)
        for part in link.get("collisions", []):
            lines += _collision(part, resolve)
        lines.append("</link>")
    for joint in robot.get("joints", []):
        kind = joint.get("type") or "fixed"
        lines.append(f"<joint name={quoteattr(joint['name'] or '')} type={quoteattr(kind)}>")
        lines.append(f"<parent link={quoteattr(joint.get('parent') or '')}/>")
        lines.append(f"<child link={quoteattr(joint.get('child') or '')}/>")
        lines.append(_origin(joint["origin"]["xyz"], joint["origin"]["rpy"]))
        if joint.get("axis") is not None and kind not in ("fixed", "floating"):
            lines.append(f'<axis xyz="{_numbers(joint["axis"] or [])}"/>')
        limit = joint.get("limit")
        if limit is not None and kind in ("revolute", "prismatic"):
            lower, upper = limit.get("lower") or 0.0, limit.get("upper") or 0.0
            lines.append(f'<limit lower="{lower!r}" upper="{upper!r}" effort="1" velocity="1"/>')
        lines.append("</joint>")
    lines.append("</robot>")
    return "\n".join(lines)


def _numbers(values: list[float] | tuple[float, ...]) -> str:
    return " ".join(repr(float(v)) for v in values)


def _origin(xyz: list[float] | tuple[float, ...], rpy: list[float] | tuple[float, ...]) -> str:
    return f'<origin xyz="{_numbers(xyz)}" rpy="{_numbers(rpy)}"/>'


def _inertial(link: LinkDict) -> list[str]:
    inertial = link.get("inertial")
    if inertial is None or inertial.get("mass") is None:
        return []
    inertia = inertial.get("inertia") or {}
    moments = " ".join(
        f'{key}="{float(inertia.get(key, 0.0))!r}"' for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    )
    origin = inertial.get("origin") or {"xyz": [0.0] * 3, "rpy": [0.0] * 3}
    return [
        "<inertial>",
        _origin(origin["xyz"], origin["rpy"]),
        f'<mass value="{float(inertial["mass"] or 0.0)!r}"/>',
        f"<inertia {moments}/>",
        "</inertial>",
    ]


def _collision(part: Part, resolve: Callable[[str], Path | None]) -> list[str]:
    geometry: Geometry = part.get("geometry") or {"type": ""}
    origin = part.get("origin") or {"xyz": [0.0] * 3, "rpy": [0.0] * 3}
    kind = geometry.get("type")
    shape: str | None = None
    if kind == "box" and geometry.get("size"):
        shape = f'<box size="{_numbers(geometry["size"] or [])}"/>'
    elif kind == "cylinder" and geometry.get("radius") is not None and geometry.get("length") is not None:
        shape = f'<cylinder radius="{geometry["radius"]!r}" length="{geometry["length"]!r}"/>'
    elif kind == "sphere" and geometry.get("radius") is not None:
        shape = f'<sphere radius="{geometry["radius"]!r}"/>'
    elif kind == "mesh" and geometry.get("uri"):
        path = resolve(geometry["uri"] or "")
        if path is not None and path.suffix.lower() in MESH_FORMATS:
            scale = geometry.get("scale") or [1.0, 1.0, 1.0]
            shape = f"<mesh filename={quoteattr(str(path))} scale={quoteattr(_numbers(scale))}/>"
        else:
            # a format MuJoCo does not read (COLLADA): the box around it, where it stands
            box = physics.local_box(geometry, resolve)
            if box is None:
                return []  # a mesh not found: nothing collides there (the mesh checks say so)
            low, high = box
            centre = [(lo + hi) / 2 for lo, hi in zip(low, high, strict=True)]
            moved = physics.apply((physics.rotation(origin["rpy"]), (0.0, 0.0, 0.0)), centre)
            xyz = [o + m for o, m in zip(origin["xyz"], moved, strict=True)]
            size = [max(hi - lo, 1e-6) for lo, hi in zip(low, high, strict=True)]
            return [
                "<collision>",
                _origin(xyz, origin["rpy"]),
                f'<geometry><box size="{_numbers(size)}"/></geometry>',
                "</collision>",
            ]
    if shape is None:
        return []
    return [
        "<collision>",
        _origin(origin["xyz"], origin["rpy"]),
        f"<geometry>{shape}</geometry>",
        "</collision>",
    ]


def drop_test(
    urdf: str, root: str | None = None, seconds: float = SECONDS, timeout: float = TIMEOUT
) -> Outcome:
    """Run the drop test of one model (`root`: its root link) in its own limited process; never raises."""
    request = json.dumps(
        {"urdf": urdf, "root": root, "seconds": seconds, "memory": MEMORY, "cpu": int(timeout) + 1}
    )
    started = time.monotonic()
    environment = {
        key: os.environ[key] for key in ("PATH", "HOME", "LANG", "PYTHONPATH") if key in os.environ
    }
    environment["MUJOCO_GL"] = "disable"  # headless: no display, no GPU
    try:
        process = subprocess.Popen(
            [sys.executable, "-m", "pkgforge.simulate.drop"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            env=environment,
            start_new_session=True,  # its own group: a timeout ends all of it
        )
    except OSError as error:
        return Outcome(error=f"cannot start the drop test: {error}")
    try:
        out, err = process.communicate(request.encode("utf-8"), timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        return Outcome(
            seconds=time.monotonic() - started, error=f"the drop test took more than {timeout:g} s"
        )
    elapsed = time.monotonic() - started
    try:
        answer: dict[str, Any] = json.loads(out.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError):
        tail = err.decode("utf-8", errors="replace").strip().splitlines()[-1:] or [
            f"exit status {process.returncode}"
        ]
        return Outcome(seconds=elapsed, error=f"the drop test ended without an answer: {tail[0][:200]}")
    problems = [
        Problem(p["kind"], p["message"], list(p.get("links", [])), p.get("joint"))
        for p in answer.get("problems", [])
    ]
    return Outcome(problems, elapsed, answer.get("error"))
