"""Writing a small binary STL, so a new package ships a real mesh of its own."""

from __future__ import annotations

import struct

Vec = tuple[float, float, float]


def box_triangles(size: Vec, origin: Vec = (0.0, 0.0, 0.0)) -> list[tuple[Vec, Vec, Vec, Vec]]:
    """Twelve outward-facing triangles (normal, a, b, c) of an axis-aligned box.

    `origin` is the centre of the bottom face, so a link's mesh starts at its
    joint and extends along +z.
    """
    half_x, half_y, height = size[0] / 2.0, size[1] / 2.0, size[2]
    ox, oy, oz = origin
    x0, x1, y0, y1, z0, z1 = ox - half_x, ox + half_x, oy - half_y, oy + half_y, oz, oz + height
    corners = {
        (i, j, k): (x1 if i else x0, y1 if j else y0, z1 if k else z0)
        for i in (0, 1)
        for j in (0, 1)
        for k in (0, 1)
    }
    # each face: normal and its four corners counter-clockwise seen from outside
    faces = [
        ((-1.0, 0.0, 0.0), [(0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)]),
        ((1.0, 0.0, 0.0), [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)]),
        ((0.0, -1.0, 0.0), [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)]),
        ((0.0, 1.0, 0.0), [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)]),
        ((0.0, 0.0, -1.0), [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)]),
        ((0.0, 0.0, 1.0), [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]),
    ]
    triangles = []
    for normal, quad in faces:
        a, b, c, d = (corners[q] for q in quad)
        triangles.append((normal, a, b, c))
        triangles.append((normal, a, c, d))
    return triangles


def binary_stl(triangles: list[tuple[Vec, Vec, Vec, Vec]], header: str = "pkgforge") -> bytes:
    """Binary STL: 80-byte header, triangle count, 50 bytes per triangle."""
    head = header.encode("ascii", "replace")[:80].ljust(80, b" ")
    # a binary STL must not start with "solid", or readers take it for ASCII
    if head.startswith(b"solid"):
        head = b"STL " + head[4:]
    body = [head, struct.pack("<I", len(triangles))]
    for normal, a, b, c in triangles:
        body.append(struct.pack("<12fH", *normal, *a, *b, *c, 0))
    return b"".join(body)
