"""`pkgforge view` and `verify --artifacts`: pictures of the robot models verify processes.

Each model that verify processed (the same xacro run, the same install tree)
becomes four PNG views (front, side, top, iso) and its kinematic tree as SVG,
with a view.json that says what was written and at what scale. Rendering
needs the `view` extra (numpy, Pillow, trimesh); the SVG tree needs nothing.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypedDict

from pkgforge.errors import PkgforgeError
from pkgforge.view.tree_svg import tree_svg

if TYPE_CHECKING:
    from PIL import Image

    from pkgforge.robot_models import ModelResult
    from pkgforge.tree import InstallTree
    from pkgforge.view.scene import Resolve, Robot

VIEW_NAMES = ("front", "side", "top", "iso")
INSTALL_HINT = "pip install 'ros-pkgforge[view]'"


def missing_renderer() -> str | None:
    """Why the images cannot be rendered here (a module of the `view` extra is missing), or None."""
    for module in ("numpy", "PIL", "trimesh"):
        try:
            __import__(module)
        except ImportError:
            return f"rendering images needs {module} (the `view` extra): {INSTALL_HINT}"
    return None


class _ViewEntry(TypedDict):
    model: str  # the model's source (or installed) file
    robot: str | None  # <robot name>
    joints: dict[str, float]  # the --joint positions it was drawn at
    images: list[dict[str, Any]]  # raster.render's record of each view, and its file name
    tree: str  # the SVG file's name
    # the xacro arguments of every processing of the file that gave this same model ({}: none)
    arguments: list[dict[str, str]]


class ViewEntry(_ViewEntry, total=False):
    """One model in view.json (and what `pkgforge view` lists)."""

    size: str  # with images: the model's extent


def parse_joints(texts: Iterable[str]) -> dict[str, float]:
    joints: dict[str, float] = {}
    for text in texts:
        name, sep, value = text.partition(":=")
        try:
            joints[name] = float(value)
        except ValueError:
            sep = ""
        if not sep or not name:
            raise PkgforgeError(f"--joint '{text}' is not NAME:=VALUE with a number (radians or metres)")
    return joints


# a file name's length at most (`<package>-<model>[-<n>]-<view>.png`): what every file system,
# archive format and CI artifact store takes
NAME_LIMIT = 100


def _stem(result: ModelResult) -> str:
    """`<package>-<model>`: the model's file name without .urdf/.xacro (its arguments are in summary.md)."""
    name = re.sub(r"\.(urdf|xacro)$", "", re.sub(r"\.xacro$", "", result.installed.name))
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", f"{result.package}-{name}")


def _numbered(stem: str, number: int) -> str:
    """The stem of the model's `number`th distinct geometry (1: the stem itself), short enough
    that its longest file name stays within NAME_LIMIT (a long stem keeps its start and a hash)."""
    import hashlib

    suffix = f"-{number}" if number > 1 else ""
    room = NAME_LIMIT - len(suffix) - len("-front.png")  # the longest of the views' and -tree.svg
    if len(stem) > room:
        stem = stem[: room - 9] + "-" + hashlib.sha1(stem.encode()).hexdigest()[:8]
    return stem + suffix


def _geometry_key(robot: dict[str, Any]) -> str:
    """What makes two processings the same picture: the model without where each part is written."""

    def bare(value: Any) -> Any:
        if isinstance(value, dict):
            return {k: bare(v) for k, v in value.items() if k not in ("file", "line")}
        if isinstance(value, list):
            return [bare(v) for v in value]
        return value

    return json.dumps(bare(robot), sort_keys=True, default=str)


class Artifacts:
    """Writes the pictures of every processed model into `out` (the verify hook)."""

    def __init__(
        self, out: Path, joints: dict[str, float] | None = None, *, frame: bool = True, images: bool = True
    ):
        self.out, self.joints, self.frame = out, joints or {}, frame
        self.missing = missing_renderer() if images else "images not asked for"
        self.written: list[Path] = []
        self.entries: list[ViewEntry] = []
        self.problems: list[str] = []
        self.used_joints: set[str] = set()

    def __call__(self, tree: InstallTree, results: Iterable[ModelResult]) -> None:
        from pkgforge.urdf.meshes import resolve_uri

        try:
            self.out.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise PkgforgeError(f"cannot write {self.out}: {error.strerror}") from None
        # one set of pictures per distinct geometry of each model file: argument combinations
        # that give the same model share it (their arguments are listed with it)
        drawn: dict[tuple[str, str], ViewEntry] = {}
        numbers: dict[str, int] = {}
        for result in results:
            robot = result.robot
            if (
                result.status != "ok"
                or robot is None
                or robot.get("root_tag") != "robot"
                or not robot.get("links")
            ):
                continue
            stem = _stem(result)
            key = (stem, _geometry_key(dict(robot)))
            arguments = dict(sorted(result.mappings.items()))
            if key in drawn:
                if arguments not in drawn[key]["arguments"]:
                    drawn[key]["arguments"].append(arguments)
                continue
            numbers[stem] = numbers.get(stem, 0) + 1

            def resolve(uri: str, result: ModelResult = result) -> Path | None:
                lookup = resolve_uri(uri, tree, result.installed)
                return lookup.path if lookup.status == "found" else None

            drawn[key] = self.model(
                dict(robot), resolve, _numbered(stem, numbers[stem]), str(result.source or result.installed)
            )
            drawn[key]["arguments"].append(arguments)
        for entry in drawn.values():  # in one order whatever order the workers answered in
            entry["arguments"].sort(key=lambda given: sorted(given.items()))

    def model(self, robot: Robot, resolve: Resolve, stem: str, source: str) -> ViewEntry:
        names = {j.get("name") for j in robot.get("joints", [])}
        positions = {k: v for k, v in self.joints.items() if k in names}
        self.used_joints |= set(positions)
        svg = self.out / f"{stem}-tree.svg"
        self._write(svg, tree_svg(robot).encode("utf-8"))
        entry: ViewEntry = {
            "model": source,
            "robot": robot.get("name"),
            "joints": positions,
            "images": [],
            "tree": svg.name,
            "arguments": [],
        }
        if self.missing is None:
            from pkgforge.view import raster
            from pkgforge.view import scene as scenes

            scene = scenes.build(robot, resolve, positions)
            self.problems += [f"{source}: {p}" for p in scene.problems]
            for view in VIEW_NAMES:
                image, info = raster.render(
                    scene, view, title=str(robot.get("name") or stem), frame=self.frame
                )
                path = self.out / f"{stem}-{view}.png"
                self._save(path, image)
                entry["images"].append({**info, "file": path.name})
            entry["size"] = raster.size_text(scene)
        self.entries.append(entry)
        return entry

    def _write(self, path: Path, data: bytes) -> None:
        """Whole or not at all: a temporary file renamed into place."""
        temporary = path.with_name(f".{path.name}.tmp")
        try:
            temporary.write_bytes(data)
            os.replace(temporary, path)
        except OSError as error:
            temporary.unlink(missing_ok=True)
            raise PkgforgeError(f"cannot write {path}: {error.strerror}") from None
        self.written.append(path)

    def _save(self, path: Path, image: Image.Image) -> None:
        import io

        buffer = io.BytesIO()
        image.save(buffer, format="PNG", optimize=False)
        self._write(path, buffer.getvalue())

    def finish(self) -> Path:
        """view.json (what was written, at what scale) and a Markdown page for a CI job summary."""
        unknown = set(self.joints) - self.used_joints
        if unknown:
            raise PkgforgeError(f"--joint {', '.join(sorted(unknown))}: no processed model has such a joint")
        index = self.out / "view.json"
        self._write(index, json.dumps({"models": self.entries, "problems": self.problems}, indent=2).encode())
        self._write(self.out / "summary.md", summary_markdown(self.entries, self.missing).encode("utf-8"))
        return index


def summary_markdown(entries: list[ViewEntry], missing: str | None, link_base: str = "") -> str:
    lines = ["## Robot models", ""]
    if not entries:
        lines.append("No robot model was processed.")
    for entry in entries:
        lines += [f"### {entry['robot']} ({entry['model']})", ""]
        if any(entry.get("arguments", [])):
            shown = "; ".join(
                " ".join(f"`{k}:={v}`" for k, v in a.items()) if a else "(defaults)"
                for a in entry["arguments"]
            )
            lines += [f"xacro arguments: {shown}", ""]
        if entry.get("size"):
            lines += [entry["size"], ""]
        if entry["images"]:
            lines.append(" ".join(f"![{i['view']}]({link_base}{i['file']})" for i in entry["images"]))
        elif missing:
            lines.append(f"(no images: {missing})")
        lines += ["", f"Kinematic tree: [{entry['tree']}]({link_base}{entry['tree']})", ""]
    return "\n".join(lines) + "\n"
