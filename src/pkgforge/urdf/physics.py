"""A robot model's physical numbers: mesh bounds, link poses, total mass and size.

Pure Python over the plain data robot.py gives (no numpy): verify runs the
physical checks on every model, and `--explain-model` and `pkgforge view`
show the same numbers. Mesh bounds are read once per file (binary STL with
struct, COLLADA position arrays with lxml and its <unit>, OBJ vertex lines).
"""

from __future__ import annotations

import math
import os
import re
import struct
import threading
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from functools import lru_cache
from os import PathLike
from types import ModuleType
from typing import TYPE_CHECKING, Any, Literal

from pkgforge.model.source import read_regular

if TYPE_CHECKING:
    from lxml import etree

    from pkgforge.urdf.structure import Geometry, JointDict, LinkDict, Origin, RobotStructure

Vec3 = tuple[float, float, float]
Matrix = tuple[Vec3, Vec3, Vec3]  # 3x3 rotation as three row tuples
Pose = tuple[Matrix, Vec3]  # (rotation, translation)
Box = tuple[Vec3, Vec3]  # (low, high)
Matrix4 = list[list[float]]  # a COLLADA node's 4x4 transform, rows
# a mesh's vertex positions: a list of (x, y, z), or a numpy (n, 3) array for a big file (numpy is
# optional: the `view` extra)
Points = Any
# a mesh URI → the mesh file, or None
Resolver = Callable[[str], "str | PathLike[str] | None"]
# a COLLADA geometry's id → its vertex positions and triangle count
Geometries = dict[str | None, tuple[Points, int]]
IDENTITY: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
MESH_READ_LIMIT = 64 * 2**20  # a bigger mesh file is not read for its bounds


@dataclass(frozen=True)
class MeshInfo:
    low: tuple[float, float, float]
    high: tuple[float, float, float]
    triangles: int

    @property
    def extent(self) -> float:
        return max(h - lo for lo, h in zip(self.low, self.high, strict=False))


def mesh_info(path: str) -> MeshInfo | None:
    """Bounds (in the file's metres, COLLADA <unit> applied) and triangle count; None if unreadable."""
    try:
        stat = os.stat(path)
    except OSError:
        return None
    if stat.st_size > MESH_READ_LIMIT or stat.st_size == 0:
        return None
    return _mesh_info(path, stat.st_size, stat.st_mtime_ns)


@lru_cache(maxsize=4096)
def _mesh_info(path: str, size: int, mtime: int) -> MeshInfo | None:
    suffix = os.path.splitext(path)[1].lower()
    try:
        data = read_regular(path, MESH_READ_LIMIT)  # (no FIFO or device swapped in since the stat)
        _STATE.large = len(data) > NUMPY_ABOVE
        if suffix == ".stl":
            return _stl(data)
        if suffix == ".dae":
            return _collada(data.lstrip())  # exporters leave blank lines before <?xml; assimp reads them
        if suffix == ".obj":
            return _obj(data)
    except Exception:  # noqa: BLE001 - a mesh file is the user's data: unreadable is "no numbers", never a crash
        return None
    return None


NUMPY_ABOVE = 1 << 20  # numpy (when installed) for bigger mesh files; below, its import costs more
_STATE = threading.local()


def _numpy() -> ModuleType | None:
    """numpy for a big mesh when installed (the `view` extra); else None: pure Python."""
    if not getattr(_STATE, "large", False):
        return None
    try:
        import numpy
    except ImportError:
        return None
    return numpy


def _bounds(points: Sequence[Sequence[float]], triangles: int) -> MeshInfo | None:
    xs, ys, zs = points
    if not xs:
        return None
    return MeshInfo((min(xs), min(ys), min(zs)), (max(xs), max(ys), max(zs)), triangles)


def _stl(data: bytes) -> MeshInfo | None:
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * count == len(data):
            np = _numpy()
            if np is not None and count:
                records = np.frombuffer(
                    data,
                    dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                    count=count,
                    offset=84,
                )
                vertices = records["v"].reshape(-1, 3).astype(float)
                return MeshInfo(
                    tuple(vertices.min(axis=0).tolist()), tuple(vertices.max(axis=0).tolist()), count
                )
            xs: list[float] = []
            ys: list[float] = []
            zs: list[float] = []
            for record in struct.iter_unpack("<12fH", data[84:]):
                xs += record[3:12:3]
                ys += record[4:12:3]
                zs += record[5:12:3]
            return _bounds((xs, ys, zs), count)
    vertices = re.findall(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)", data)
    columns = [[float(v[i]) for v in vertices] for i in range(3)]
    return _bounds(columns, len(vertices) // 3)


def _collada(data: bytes) -> MeshInfo | None:
    """Bounds of the geometry the visual scene places (node matrices and <unit> applied)."""
    from lxml import etree

    root = etree.fromstring(data, etree.XMLParser(huge_tree=True, remove_comments=True))
    unit = next((float(u.get("meter") or "") for u in root.iter("{*}unit") if u.get("meter")), 1.0)
    sources = {s.get("id"): s for s in root.iter("{*}source")}
    geometries: Geometries = {}
    for geometry in root.iter("{*}geometry"):
        points: list[Points] = []
        triangles = 0
        for vertices in geometry.iter("{*}vertices"):
            for source in _position_sources(sources, vertices):
                points.append(_floats(source.text or ""))
        for tag in ("triangles", "polylist", "polygons"):
            triangles += sum(int(e.get("count", "0")) for e in geometry.iter("{*}" + tag))
        geometries[geometry.get("id")] = (_join(points), triangles)
    placed: list[Box | None] = []
    count = 0
    scenes = list(root.iter("{*}visual_scene"))
    if scenes:
        for node in scenes[0]:
            if isinstance(node.tag, str) and node.tag.endswith("node"):
                count += _place(node, _scaled_identity(unit), geometries, placed)
    else:
        for points, triangles in geometries.values():
            placed.append(_transform(_scaled_identity(unit), points))
            count += triangles
    boxes = [b for b in placed if b is not None]
    if not boxes:
        return None
    low, high = _box(
        [min(b[0][i] for b in boxes) for i in range(3)], [max(b[1][i] for b in boxes) for i in range(3)]
    )
    return MeshInfo(low, high, count)


def _floats(text: str) -> Points:
    np = _numpy()
    if np is not None:
        return np.array(text.split(), dtype=float)
    return [float(v) for v in text.split()]


def _join(arrays: list[Points]) -> Points:
    """The x, y, z triples of several position arrays, as one (n, 3) array or list of triples."""
    np = _numpy()
    if np is not None:
        flat = np.concatenate(arrays) if arrays else np.zeros(0)
        return flat[: len(flat) // 3 * 3].reshape(-1, 3)
    values = [v for array in arrays for v in array]
    return list(zip(values[0::3], values[1::3], values[2::3], strict=False))


def _transform(m: Matrix4, points: Points) -> Box | None:
    """(low, high) of the points under the 4x4 matrix m, or None when there are none."""
    if len(points) == 0:
        return None
    np = _numpy()
    if np is not None:
        moved = points @ np.asarray(m, dtype=float)[:3, :3].T + np.asarray(m, dtype=float)[:3, 3]
        return tuple(moved.min(axis=0).tolist()), tuple(moved.max(axis=0).tolist())
    moved = [
        (
            m[0][0] * x + m[0][1] * y + m[0][2] * z + m[0][3],
            m[1][0] * x + m[1][1] * y + m[1][2] * z + m[1][3],
            m[2][0] * x + m[2][1] * y + m[2][2] * z + m[2][3],
        )
        for x, y, z in points
    ]
    return tuple(min(p[i] for p in moved) for i in range(3)), tuple(
        max(p[i] for p in moved) for i in range(3)
    )


def _scaled_identity(unit: float) -> list[list[float]]:
    return [[unit, 0, 0, 0], [0, unit, 0, 0], [0, 0, unit, 0], [0, 0, 0, 1]]


def _matmul4(a: Matrix4, b: Matrix4) -> Matrix4:
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def _node_matrix(node: etree._Element) -> Matrix4:
    matrix = _scaled_identity(1.0)
    for child in node:
        tag = child.tag.rsplit("}", 1)[-1] if isinstance(child.tag, str) else ""
        values = (
            [float(v) for v in (child.text or "").split()]
            if tag in ("matrix", "translate", "rotate", "scale")
            else []
        )
        local: Matrix4
        if tag == "matrix" and len(values) == 16:
            local = [values[0:4], values[4:8], values[8:12], values[12:16]]
        elif tag == "translate" and len(values) == 3:
            local = [[1, 0, 0, values[0]], [0, 1, 0, values[1]], [0, 0, 1, values[2]], [0, 0, 0, 1]]
        elif tag == "scale" and len(values) == 3:
            local = [[values[0], 0, 0, 0], [0, values[1], 0, 0], [0, 0, values[2], 0], [0, 0, 0, 1]]
        elif tag == "rotate" and len(values) == 4:
            r = axis_angle((values[0], values[1], values[2]), math.radians(values[3]))
            local = [[*r[0], 0], [*r[1], 0], [*r[2], 0], [0, 0, 0, 1]]
        else:
            continue
        matrix = _matmul4(matrix, local)
    return matrix


def _place(
    node: etree._Element, parent: Matrix4, geometries: Geometries, placed: list[Box | None], depth: int = 0
) -> int:
    """Add the bounds of the node's geometry (and its children's) in the scene's frame."""
    if depth > 64:
        return 0
    matrix = _matmul4(parent, _node_matrix(node))
    count = 0
    for child in node:
        tag = child.tag.rsplit("}", 1)[-1] if isinstance(child.tag, str) else ""
        if tag == "instance_geometry":
            points, triangles = geometries.get((child.get("url") or "").lstrip("#"), ([], 0))
            count += triangles
            placed.append(_transform(matrix, points))
        elif tag == "node":
            count += _place(child, matrix, geometries, placed, depth + 1)
    return count


def _position_sources(
    sources: dict[str | None, etree._Element], vertices: etree._Element
) -> Iterator[etree._Element]:
    for child in vertices:
        if isinstance(child.tag, str) and child.tag.endswith("input") and child.get("semantic") == "POSITION":
            source = sources.get((child.get("source") or "").lstrip("#"))
            if source is not None:
                yield from source.iter("{*}float_array")


def _obj(data: bytes) -> MeshInfo | None:
    xs: list[float] = []
    ys: list[float] = []
    zs: list[float] = []
    faces = 0
    for line in data.splitlines():
        if line.startswith(b"v "):
            parts = line.split()
            xs.append(float(parts[1]))
            ys.append(float(parts[2]))
            zs.append(float(parts[3]))
        elif line.startswith(b"f "):
            faces += max(1, len(line.split()) - 3)
    return _bounds((xs, ys, zs), faces)


# --- poses -------------------------------------------------------------------------------------


def rotation(rpy: Sequence[float], axis: Sequence[float] | None = None, angle: float = 0.0) -> Matrix:
    """URDF fixed-axis roll-pitch-yaw (Rz·Ry·Rx), then `angle` about `axis` (a revolute joint)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    matrix: Matrix = (
        (cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
        (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
        (-sp, cp * sr, cp * cr),
    )
    if axis is not None and angle:
        matrix = multiply(matrix, axis_angle(axis, angle))
    return matrix


def axis_angle(axis: Sequence[float], angle: float) -> Matrix:
    norm = math.sqrt(sum(a * a for a in axis)) or 1.0
    x, y, z = (a / norm for a in axis)
    c, s, t = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    return (
        (t * x * x + c, t * x * y - s * z, t * x * z + s * y),
        (t * x * y + s * z, t * y * y + c, t * y * z - s * x),
        (t * x * z - s * y, t * y * z + s * x, t * z * z + c),
    )


def multiply(a: Matrix, b: Matrix) -> Matrix:
    def row(i: int) -> Vec3:
        x, y, z = (sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3))
        return x, y, z

    return row(0), row(1), row(2)


def apply(pose: Pose, point: Sequence[float]) -> Vec3:
    matrix, offset = pose
    x, y, z = (sum(matrix[i][k] * point[k] for k in range(3)) + offset[i] for i in range(3))
    return x, y, z


def compose(
    pose: Pose,
    origin: Origin,
    axis: Sequence[float] | None = None,
    angle: float = 0.0,
    slide: float = 0.0,
) -> Pose:
    """pose · origin (· the joint's motion): (rotation, translation)."""
    matrix, offset = pose
    local = rotation(origin["rpy"], axis, angle)
    xyz = list(origin["xyz"])
    if axis is not None and slide:
        norm = math.sqrt(sum(a * a for a in axis)) or 1.0
        moved = apply((rotation(origin["rpy"]), (0.0, 0.0, 0.0)), [a / norm * slide for a in axis])
        xyz = [x + m for x, m in zip(xyz, moved, strict=False)]
    return multiply(matrix, local), apply(pose, xyz)


def _zero_origin() -> Origin:
    return {"xyz": [0.0] * 3, "rpy": [0.0] * 3}


def link_poses(robot: RobotStructure, positions: dict[str, float] | None = None) -> dict[str | None, Pose]:
    """Each link's pose in the root link's frame, at zero or the given joint positions (a name
    the model leaves out is None)."""
    positions = positions or {}
    children: dict[str | None, list[JointDict]] = {}
    child_names: set[str | None] = set()
    for joint in robot.get("joints", []):
        children.setdefault(joint.get("parent"), []).append(joint)
        child_names.add(joint.get("child"))
    poses: dict[str | None, Pose] = {}
    roots = [link["name"] for link in robot.get("links", []) if link["name"] not in child_names]
    stack: list[tuple[str | None, Pose]] = [(root, (IDENTITY, (0.0, 0.0, 0.0))) for root in roots[:1]]
    while stack:
        name, pose = stack.pop()
        if name in poses:
            continue
        poses[name] = pose
        for joint in children.get(name, []):
            joint_name = joint.get("name")
            value = positions.get(joint_name, 0.0) if joint_name is not None else 0.0
            axis = joint.get("axis") or [1.0, 0.0, 0.0]
            kind = joint.get("type")
            origin = joint.get("origin") or _zero_origin()
            child_pose = compose(
                pose,
                origin,
                axis,
                angle=value if kind in ("revolute", "continuous") else 0.0,
                slide=value if kind == "prismatic" else 0.0,
            )
            stack.append((joint.get("child"), child_pose))
    return poses


# --- shapes and numbers ------------------------------------------------------------------------


def local_box(geometry: Geometry | None, resolve: Resolver) -> Box | None:
    """(low, high) of a shape in its own frame; `resolve(uri)` → a mesh file path or None."""
    if not geometry:
        return None
    kind = geometry.get("type")
    size, radius, length = geometry.get("size"), geometry.get("radius"), geometry.get("length")
    if kind == "box" and size:
        x, y, z = (abs(s) / 2 for s in size)
        return (-x, -y, -z), (x, y, z)
    if kind in ("cylinder", "capsule") and radius is not None and length is not None:
        r, h = abs(radius), abs(length) / 2 + (abs(radius) if kind == "capsule" else 0)
        return (-r, -r, -h), (r, r, h)
    if kind == "sphere" and radius is not None:
        r = abs(radius)
        return (-r, -r, -r), (r, r, r)
    uri = geometry.get("uri")
    if kind == "mesh" and uri:
        path = resolve(uri)
        info = mesh_info(str(path)) if path else None
        if info is None:
            return None
        scale = geometry.get("scale") or [1.0, 1.0, 1.0]
        corners = [(lo * s, hi * s) for lo, hi, s in zip(info.low, info.high, scale, strict=False)]
        return _box([min(c) for c in corners], [max(c) for c in corners])
    return None


def _box(low: Sequence[float], high: Sequence[float]) -> Box:
    return (low[0], low[1], low[2]), (high[0], high[1], high[2])


def box_corners(box: Box) -> list[Vec3]:
    low, high = box
    return [(x, y, z) for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])]


def world_bounds(
    robot: RobotStructure,
    resolve: Resolver,
    positions: dict[str, float] | None = None,
    kinds: Sequence[Literal["visuals", "collisions"]] = ("visuals",),
) -> Box | None:
    """The axis-aligned bounds of the model's shapes in the root frame, or None when it has none."""
    poses = link_poses(robot, positions)
    points: list[Vec3] = []
    for link in robot.get("links", []):
        pose = poses.get(link["name"])
        if pose is None:
            continue
        for kind in kinds:
            for part in link.get(kind, []):
                box = local_box(part.get("geometry"), resolve)
                if box is None:
                    continue
                part_pose = compose(pose, part.get("origin") or _zero_origin())
                points += [apply(part_pose, corner) for corner in box_corners(box)]
    if not points:
        return None
    return _box([min(p[i] for p in points) for i in range(3)], [max(p[i] for p in points) for i in range(3)])


def total_mass(robot: RobotStructure) -> float:
    return sum(_mass(link) for link in robot.get("links", []))


def _mass(link: LinkDict) -> float:
    inertial = link.get("inertial")
    return (inertial.get("mass") if inertial else None) or 0.0


def principal_moments(inertia: dict[str, float]) -> list[float]:
    """Eigenvalues of the symmetric inertia tensor (closed form), smallest first."""
    a, b, c = inertia["ixx"], inertia["iyy"], inertia["izz"]
    d, e, f = inertia["ixy"], inertia["iyz"], inertia["ixz"]
    off = d * d + e * e + f * f
    if off == 0:
        return sorted([a, b, c])
    q = (a + b + c) / 3
    p2 = (a - q) ** 2 + (b - q) ** 2 + (c - q) ** 2 + 2 * off
    p = math.sqrt(p2 / 6)
    # B = (A - qI) / p; r = det(B) / 2
    ba, bb, bc, bd, be, bf = (a - q) / p, (b - q) / p, (c - q) / p, d / p, e / p, f / p
    det = ba * (bb * bc - be * be) - bd * (bd * bc - be * bf) + bf * (bd * be - bb * bf)
    r = max(-1.0, min(1.0, det / 2))
    phi = math.acos(r) / 3
    high = q + 2 * p * math.cos(phi)
    low = q + 2 * p * math.cos(phi + 2 * math.pi / 3)
    return sorted([low, 3 * q - high - low, high])
