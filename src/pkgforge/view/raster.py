"""A CPU rasteriser for robot previews: orthographic views, flat shading, painter's order.

numpy projects and shades every triangle at once; Pillow fills them far to near.
No display, no OpenGL: the same picture on a laptop, a container and CI.
"""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from .scene import Scene

BACKGROUND = (255, 255, 255)
SIZE = 640  # the drawing area, pixels square
MARGIN = 24
FOOTER = 44
AXIS_COLORS = ((220, 30, 30), (30, 170, 30), (30, 60, 230))

# camera: (direction it looks along, the world direction shown up); ROS: x forward, z up
VIEWS = {
    "front": ((-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),  # from in front of the robot
    "side": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),  # from its right side
    "top": ((0.0, 0.0, -1.0), (1.0, 0.0, 0.0)),  # from above, front up
    "iso": ((-1.0, 1.0, -1.0), (0.0, 0.0, 1.0)),  # from front-right-above
}


def camera(view: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(right, up, forward) unit vectors of the view."""
    forward, up = (np.asarray(v, dtype=float) for v in VIEWS[view])
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    return right, np.cross(right, forward), forward


def project(points: np.ndarray, view: str) -> np.ndarray:
    """(..., 3) points → (..., 3): screen right, screen up, depth (larger is farther)."""
    right, up, forward = camera(view)
    return np.stack([points @ right, points @ up, points @ forward], axis=-1)


def render(scene: Scene, view: str, *, title: str, frame: bool = True, size: int = SIZE) -> tuple[Image.Image, dict]:
    """The image of one view, and what a reader needs to measure it (pixels per metre, drawing area)."""
    image = Image.new("RGB", (size + 2 * MARGIN, size + 2 * MARGIN + FOOTER), BACKGROUND)
    draw = ImageDraw.Draw(image)
    info = {"view": view, "pixels_per_metre": None, "area": [MARGIN, MARGIN, MARGIN + size, MARGIN + size]}
    if len(scene.triangles):
        screen = project(scene.triangles, view)
        low, high = screen[..., :2].reshape(-1, 2).min(axis=0), screen[..., :2].reshape(-1, 2).max(axis=0)
        extent = np.maximum(high - low, 1e-9)
        scale = size / extent.max()
        offset = MARGIN + (size - extent * scale) / 2  # centred

        def to_pixels(uv: np.ndarray) -> np.ndarray:
            x = offset[0] + (uv[..., 0] - low[0]) * scale
            y = offset[1] + (high[1] - uv[..., 1]) * scale
            return np.stack([x, y], axis=-1)

        pixels = to_pixels(screen[..., :2])
        normals = np.cross(scene.triangles[:, 1] - scene.triangles[:, 0], scene.triangles[:, 2] - scene.triangles[:, 0])
        lengths = np.linalg.norm(normals, axis=1)
        lengths[lengths == 0] = 1.0
        _, _, forward = camera(view)
        light = np.abs(normals @ forward) / lengths
        # at most 92 % bright: a white part stays distinct from the white background
        shaded = np.clip(scene.colors * (0.3 + 0.62 * light)[:, None], 0, 1)
        fills = (shaded * 255).astype(np.uint8)
        order = np.argsort(-screen[..., 2].mean(axis=1), kind="stable")  # far first
        for corners, fill in zip(pixels[order].tolist(), fills[order].tolist()):
            draw.polygon([tuple(c) for c in corners], fill=tuple(fill), outline=tuple(fill))
        info.update(pixels_per_metre=float(scale), extent_m=[float(e) for e in extent])
        if frame:
            _frame(draw, to_pixels, view, 0.12 * float(np.ptp(scene.triangles.reshape(-1, 3), axis=0).max()))
    _footer(draw, image, scene, view, title)
    return image, info


def _frame(draw, to_pixels, view: str, length: float) -> None:
    """The root link's frame: x red, y green, z blue."""
    origin = to_pixels(project(np.zeros(3), view)[:2])
    for axis, color, label in zip(np.eye(3) * length, AXIS_COLORS, "xyz"):
        end = to_pixels(project(axis, view)[:2])
        if np.linalg.norm(end - origin) < 2:
            draw.ellipse([*(origin - 4), *(origin + 4)], outline=color, width=2)  # pointing at the viewer
            continue
        draw.line([tuple(origin), tuple(end)], fill=color, width=3)
        draw.text(tuple(end + 3), label, fill=color, font=_font(14))


def _font(size: int):
    try:
        return ImageFont.load_default(size)
    except TypeError:  # Pillow < 10.1: one bitmap size
        return ImageFont.load_default()


def size_text(scene: Scene) -> str:
    if not len(scene.triangles):
        return "no visual geometry"
    extent = np.ptp(scene.triangles.reshape(-1, 3), axis=0)
    return "size " + " x ".join(f"{e:.3g}" for e in extent) + " m (x, y, z)"


def _footer(draw, image, scene: Scene, view: str, title: str) -> None:
    top = image.height - FOOTER
    draw.line([(0, top), (image.width, top)], fill=(210, 210, 210))
    draw.text((MARGIN, top + 6), f"{title} · {view}", fill=(40, 40, 40), font=_font(15))
    draw.text((MARGIN, top + 24), size_text(scene), fill=(90, 90, 90), font=_font(13))
