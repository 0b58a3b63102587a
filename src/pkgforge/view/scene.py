"""A robot model's visual geometry as one triangle soup in the root link's frame.

Meshes (STL, COLLADA, OBJ) are loaded with trimesh; boxes, cylinders and
spheres are made here. Link poses come from pkgforge.urdf.physics, the same
kinematics `--explain-model` and the physical checks use.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from pkgforge.urdf import physics
from pkgforge.urdf.structure import Origin, RobotStructure

DEFAULT_COLOR = (0.72, 0.74, 0.78)
ROUND_SEGMENTS = 32

Floats = NDArray[np.float64]
Color = tuple[float, ...]  # red, green, blue (and alpha) in 0..1
# a mesh URI → its file, None when not found
Resolve = Callable[[str], "Path | None"]
# the model as the xacro worker reports it (JSON data: links, joints, geometry, ...)
# the renderer reads the model structure as plain JSON data (urdf.structure types its keys)
Robot = dict[str, Any]


@dataclass
class Scene:
    triangles: Floats  # (n, 3, 3) vertices in metres, root frame
    colors: Floats  # (n, 3) in 0..1
    problems: list[str]  # meshes that could not be loaded (drawn as nothing)


def _box(size: Sequence[float]) -> Floats:
    half = np.abs(np.asarray(size, dtype=np.float64)) / 2
    corners = (
        np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64) * half
    )
    faces = [
        (0, 1, 3),
        (0, 3, 2),
        (4, 6, 7),
        (4, 7, 5),
        (0, 4, 5),
        (0, 5, 1),
        (2, 3, 7),
        (2, 7, 6),
        (0, 2, 6),
        (0, 6, 4),
        (1, 5, 7),
        (1, 7, 3),
    ]
    triangles: Floats = corners[np.array(faces)]
    return triangles


def _cylinder(radius: float, length: float) -> Floats:
    angles = np.linspace(0, 2 * np.pi, ROUND_SEGMENTS, endpoint=False)
    ring = np.stack([np.cos(angles) * radius, np.sin(angles) * radius], axis=1)
    nxt = np.roll(ring, -1, axis=0)
    top, bottom = length / 2, -length / 2

    def at(points: Floats, z: float) -> Floats:
        return np.concatenate([points, np.full((len(points), 1), z)], axis=1)

    centre_top, centre_bottom = np.array([0, 0, top]), np.array([0, 0, bottom])
    sides = np.concatenate(
        [
            np.stack([at(ring, bottom), at(nxt, bottom), at(nxt, top)], axis=1),
            np.stack([at(ring, bottom), at(nxt, top), at(ring, top)], axis=1),
            np.stack([np.broadcast_to(centre_top, (len(ring), 3)), at(ring, top), at(nxt, top)], axis=1),
            np.stack(
                [np.broadcast_to(centre_bottom, (len(ring), 3)), at(nxt, bottom), at(ring, bottom)], axis=1
            ),
        ]
    )
    return sides


def _sphere(radius: float) -> Floats:
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=2, radius=radius)
    triangles: Floats = sphere.vertices[sphere.faces]
    return triangles


def _mesh(path: str, scale: Sequence[float]) -> tuple[Floats, Color | None]:
    import trimesh

    # what trimesh.load(path, force="mesh") does, with its type: every scene as one Trimesh
    loaded = trimesh.load_mesh(path, process=False)
    triangles = np.asarray(loaded.vertices, dtype=np.float64)[np.asarray(loaded.faces)] * np.asarray(
        scale, dtype=np.float64
    )
    return triangles, _mesh_color(loaded)


def _mesh_color(mesh: Any) -> Color | None:  # a trimesh object; its visual is read defensively
    """The mesh's own colour (COLLADA materials), when it has one."""
    visual: Any = getattr(mesh, "visual", None)
    try:
        if getattr(visual, "kind", None) == "texture":
            color = visual.material.main_color
        elif getattr(visual, "kind", None) in ("face", "vertex"):
            color = visual.main_color
        else:
            return None
    except (AttributeError, ValueError, IndexError):
        return None
    return tuple(float(c) / 255 for c in color[:3])


def _shape(
    geometry: dict[str, Any] | None, resolve: Resolve
) -> tuple[Floats | None, Color | None, str | None]:
    """(triangles in the shape's frame, its own colour, a problem)."""
    if geometry is None:
        return None, None, None
    kind = geometry.get("type")
    if kind == "box" and geometry.get("size"):
        return _box(geometry["size"]), None, None
    if kind in ("cylinder", "capsule") and geometry.get("radius") and geometry.get("length") is not None:
        return _cylinder(geometry["radius"], geometry["length"]), None, None
    if kind == "sphere" and geometry.get("radius"):
        return _sphere(geometry["radius"]), None, None
    if kind == "mesh" and geometry.get("uri"):
        path = resolve(geometry["uri"])
        if path is None:
            return None, None, f"{geometry['uri']}: not found"
        try:
            triangles, color = _mesh(str(path), geometry.get("scale") or [1.0, 1.0, 1.0])
        except Exception as error:  # trimesh raises many kinds on a broken file
            return None, None, f"{geometry['uri']}: {type(error).__name__}: {error}"
        return triangles, color, None
    return None, None, None


def _matrix(pose: tuple[Any, Any]) -> tuple[Floats, Floats]:
    rotation, offset = pose
    return np.asarray(rotation, dtype=np.float64), np.asarray(offset, dtype=np.float64)


def build(robot: Robot, resolve: Resolve, positions: dict[str, float] | None = None) -> Scene:
    poses = physics.link_poses(cast(RobotStructure, robot), positions)
    parts: list[Floats] = []
    colors: list[Floats] = []
    problems: list[str] = []
    for link in robot.get("links", []):
        pose = poses.get(link["name"])
        if pose is None:
            continue
        for visual in link.get("visuals", []):
            triangles, own_color, problem = _shape(visual.get("geometry"), resolve)
            if problem:
                problems.append(f"link {link['name']}: {problem}")
            if triangles is None or not len(triangles):
                continue
            rotation, offset = _matrix(
                physics.compose(
                    pose, cast(Origin, visual.get("origin") or {"xyz": [0.0] * 3, "rpy": [0.0] * 3})
                )
            )
            parts.append(triangles @ rotation.T + offset)
            color = visual.get("color") or own_color or DEFAULT_COLOR
            colors.append(np.broadcast_to(np.asarray(color[:3], dtype=np.float64), (len(triangles), 3)))
    if not parts:
        return Scene(np.zeros((0, 3, 3)), np.zeros((0, 3)), problems)
    return Scene(np.concatenate(parts), np.concatenate(colors), problems)
