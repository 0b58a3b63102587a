"""A CPU rasteriser for robot previews: orthographic views, flat shading, a depth buffer.

numpy projects, shades and rasterises every triangle at once (triangles grouped by the size
of their pixel box, each group tested against its pixel centres in one array operation);
Pillow draws the frame and the text. No display, no OpenGL: the same picture on a laptop,
a container and CI.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw, ImageFont

from pkgforge.view.scene import Floats, Scene

Ints = NDArray[np.int64]
# (flat pixel index, depth, triangle) of candidate pixels → the z-buffer keeps the nearest
KeepNearest = Callable[[Ints, Floats, Ints], None]

BACKGROUND = (255, 255, 255)
SIZE = 640  # the drawing area, pixels square
MARGIN = 24
FOOTER = 44
AXIS_COLORS = ((220, 30, 30), (30, 170, 30), (30, 60, 230))
DARK = 0.35  # a colour's luma below which faces are lifted by the light (a black part shows its shape)
DARK_LIFT = 0.35

# camera: (direction it looks along, the world direction shown up); ROS: x forward, z up
VIEWS = {
    "front": ((-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),  # from in front of the robot
    "side": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),  # from its right side
    "top": ((0.0, 0.0, -1.0), (1.0, 0.0, 0.0)),  # from above, front up
    "iso": ((-1.0, 1.0, -1.0), (0.0, 0.0, 1.0)),  # from front-right-above
}


def camera(view: str) -> tuple[Floats, Floats, Floats]:
    """(right, up, forward) unit vectors of the view."""
    forward, up = (np.asarray(v, dtype=np.float64) for v in VIEWS[view])
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    return right, np.cross(right, forward), forward


def project(points: Floats, view: str) -> Floats:
    """(..., 3) points → (..., 3): screen right, screen up, depth (larger is farther)."""
    right, up, forward = camera(view)
    return np.stack([points @ right, points @ up, points @ forward], axis=-1)


def render(
    scene: Scene, view: str, *, title: str, frame: bool = True, size: int = SIZE
) -> tuple[Image.Image, dict[str, Any]]:
    """The image of one view, and what a reader needs to measure it (pixels per metre, drawing area).

    The dict is view.json's record of the image (JSON data)."""
    image = Image.new("RGB", (size + 2 * MARGIN, size + 2 * MARGIN + FOOTER), BACKGROUND)
    draw = ImageDraw.Draw(image)
    info: dict[str, Any] = {
        "view": view,
        "pixels_per_metre": None,
        "area": [MARGIN, MARGIN, MARGIN + size, MARGIN + size],
    }
    if len(scene.triangles):
        screen = project(scene.triangles, view)
        low, high = screen[..., :2].reshape(-1, 2).min(axis=0), screen[..., :2].reshape(-1, 2).max(axis=0)
        extent = np.maximum(high - low, 1e-9)
        scale = size / extent.max()
        offset = MARGIN + (size - extent * scale) / 2  # centred

        def to_pixels(uv: Floats) -> Floats:
            x = offset[0] + (uv[..., 0] - low[0]) * scale
            y = offset[1] + (high[1] - uv[..., 1]) * scale
            return np.stack([x, y], axis=-1)

        pixels = to_pixels(screen[..., :2])
        normals = np.cross(
            scene.triangles[:, 1] - scene.triangles[:, 0], scene.triangles[:, 2] - scene.triangles[:, 0]
        )
        lengths = np.linalg.norm(normals, axis=1)
        lengths[lengths == 0] = 1.0
        right, up, forward = camera(view)
        # a key light above and left of the viewer, not along the view: faces facing different
        # ways get different shades (a headlight shades a box's three visible faces alike in iso)
        key = 0.75 * forward - 0.5 * up + 0.45 * right
        light = np.abs(normals @ (key / np.linalg.norm(key))) / lengths
        # at most 92 % bright: a white part stays distinct from the white background
        shaded = scene.colors * (0.3 + 0.62 * light)[:, None]
        # a dark material (black anodised links, tyres) scaled by the light stays black on every
        # face, a flat silhouette: it gets up to DARK_LIFT of grey more where the light falls
        luma = scene.colors @ np.array([0.299, 0.587, 0.114])
        lift = DARK_LIFT * np.clip((DARK - luma) / DARK, 0, 1) * light
        shaded = np.clip(shaded + lift[:, None], 0, 1)
        fills = (shaded * 255).astype(np.uint8)
        canvas = np.asarray(image).copy()
        _rasterise(canvas, pixels, screen[..., 2], fills)
        image.paste(Image.fromarray(canvas))
        info.update(pixels_per_metre=float(scale), extent_m=[float(e) for e in extent])
        if frame:
            _frame(draw, to_pixels, view, 0.12 * float(np.ptp(scene.triangles.reshape(-1, 3), axis=0).max()))
    _footer(draw, image, scene, view, title)
    return image, info


CHUNK = 1 << 22  # pixels rasterised at once (bounds the memory to ~200 MB)


def _within(counts: Ints) -> Ints:
    """0..count-1 for each count, concatenated."""
    total = int(counts.sum())
    starts = np.repeat(np.cumsum(counts) - counts, counts)
    return np.arange(total) - starts


def _rasterise(canvas: NDArray[np.uint8], pixels: Floats, depth: Floats, fills: NDArray[np.uint8]) -> None:
    """Fill the triangles (pixel coordinates, depth per corner), nearest wins, into canvas (h, w, 3).

    Scanlines, vectorised: every triangle becomes its pixel rows, every row its pixel span, so
    the work is the pixels covered, whatever the triangles' shapes.
    """
    height, width = canvas.shape[:2]
    zbuffer = np.full(height * width, np.inf)
    owner = np.full(height * width, -1, dtype=np.int64)

    def keep_nearest(flat: Ints, z: Floats, triangle: Ints) -> None:
        order = np.lexsort((z, flat))
        flat, z, triangle = flat[order], z[order], triangle[order]
        first = np.ones(len(flat), dtype=bool)
        first[1:] = flat[1:] != flat[:-1]
        flat, z, triangle = flat[first], z[first], triangle[first]
        nearer = z < zbuffer[flat]
        zbuffer[flat[nearer]] = z[nearer]
        owner[flat[nearer]] = triangle[nearer]

    # the depth plane z = z0 + zx·x + zy·y of each triangle (edge-on ones keep their mean depth)
    a, b, c = pixels[:, 0], pixels[:, 1], pixels[:, 2]
    ab, ac = b - a, c - a
    det = ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]
    flat_det = np.where(np.abs(det) > 1e-12, det, np.inf)
    dz1, dz2 = depth[:, 1] - depth[:, 0], depth[:, 2] - depth[:, 0]
    zx = (dz1 * ac[:, 1] - dz2 * ab[:, 1]) / flat_det
    zy = (dz2 * ab[:, 0] - dz1 * ac[:, 0]) / flat_det
    z0 = depth[:, 0] - zx * a[:, 0] - zy * a[:, 1]
    z0 = np.where(np.isfinite(flat_det), z0, depth.mean(axis=1))

    # every triangle owns at least its centroid's pixel: sub-pixel parts still show
    centre = np.floor(pixels.mean(axis=1)).astype(np.int64)
    on = (centre[:, 0] >= 0) & (centre[:, 0] < width) & (centre[:, 1] >= 0) & (centre[:, 1] < height)
    keep_nearest(centre[on, 1] * width + centre[on, 0], depth[on].mean(axis=1), np.nonzero(on)[0])

    top = np.clip(np.ceil(pixels[:, :, 1].min(axis=1) - 0.5), 0, height).astype(np.int64)
    bottom = np.clip(np.floor(pixels[:, :, 1].max(axis=1) - 0.5), -1, height - 1).astype(np.int64)
    rows = np.maximum(bottom - top + 1, 0)
    widths = np.ceil(pixels[:, :, 0].max(axis=1) - pixels[:, :, 0].min(axis=1)) + 1
    cost = np.cumsum(rows * widths)
    start = 0
    while start < len(pixels):
        end = max(start + 1, int(np.searchsorted(cost, (cost[start - 1] if start else 0) + CHUNK)))
        _scan(slice(start, end), pixels, top, rows, z0, zx, zy, width, keep_nearest)
        start = end
    drawn = owner >= 0
    canvas.reshape(-1, 3)[drawn] = fills[owner[drawn]]


def _scan(
    part: slice,
    pixels: Floats,
    top: Ints,
    rows: Ints,
    z0: Floats,
    zx: Floats,
    zy: Floats,
    width: int,
    keep_nearest: KeepNearest,
) -> None:
    index = np.arange(len(pixels))[part]
    triangle = np.repeat(index, rows[part])
    if not len(triangle):
        return
    y = top[triangle] + _within(rows[part])
    centre = y + 0.5
    left = np.full(len(y), np.inf)
    right = np.full(len(y), -np.inf)
    corners = pixels[triangle]
    for i, j in ((0, 1), (1, 2), (2, 0)):
        x0, y0, x1, y1 = corners[:, i, 0], corners[:, i, 1], corners[:, j, 0], corners[:, j, 1]
        crosses = (np.minimum(y0, y1) <= centre) & (centre <= np.maximum(y0, y1)) & (y0 != y1)
        x = x0 + (centre - y0) * (x1 - x0) / np.where(y0 != y1, y1 - y0, 1.0)
        left = np.where(crosses, np.minimum(left, x), left)
        right = np.where(crosses, np.maximum(right, x), right)
    first = np.clip(np.ceil(left - 0.5), 0, width).astype(np.int64)
    last = np.clip(np.floor(right - 0.5), -1, width - 1).astype(np.int64)
    counts = np.where(np.isfinite(left), np.maximum(last - first + 1, 0), 0)
    owner = np.repeat(triangle, counts)
    if not len(owner):
        return
    column = np.repeat(first, counts) + _within(counts)  # (x above is a float crossing)
    y = np.repeat(y, counts)
    z = z0[owner] + zx[owner] * (column + 0.5) + zy[owner] * (y + 0.5)
    keep_nearest(y * width + column, z, owner)


def _frame(
    draw: ImageDraw.ImageDraw, to_pixels: Callable[[Floats], Floats], view: str, length: float
) -> None:
    """The root link's frame: x red, y green, z blue."""
    origin = to_pixels(project(np.zeros(3), view)[:2])
    for axis, color, label in zip(np.eye(3) * length, AXIS_COLORS, "xyz", strict=False):
        end = to_pixels(project(axis, view)[:2])
        if np.linalg.norm(end - origin) < 2:
            draw.ellipse([*(origin - 4), *(origin + 4)], outline=color, width=2)  # pointing at the viewer
            continue
        draw.line([tuple(origin), tuple(end)], fill=color, width=3)
        draw.text(tuple(end + 3), label, fill=color, font=_font(14))


def _font(size: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    try:
        return ImageFont.load_default(size)
    except TypeError:  # Pillow < 10.1: one bitmap size
        return ImageFont.load_default()


def size_text(scene: Scene) -> str:
    if not len(scene.triangles):
        return "no visual geometry"
    extent = np.ptp(scene.triangles.reshape(-1, 3), axis=0)
    return "size " + " x ".join(f"{e:.3g}" for e in extent) + " m (x, y, z)"


def _footer(draw: ImageDraw.ImageDraw, image: Image.Image, scene: Scene, view: str, title: str) -> None:
    top = image.height - FOOTER
    draw.line([(0, top), (image.width, top)], fill=(210, 210, 210))
    draw.text((MARGIN, top + 6), f"{title} · {view}", fill=(40, 40, 40), font=_font(15))
    draw.text((MARGIN, top + 24), size_text(scene), fill=(90, 90, 90), font=_font(13))
