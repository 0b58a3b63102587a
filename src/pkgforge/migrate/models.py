"""The robot models of a ROS 1 package that migrate reads before it writes anything: each
model, its links and root, the meshes it names that are missing, the Gazebo Classic plugins."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.urdf import XACRO_MODEL_SUFFIXES

if TYPE_CHECKING:
    from pkgforge.scaffold.from_urdf import ModelFile, Reference
    from pkgforge.scaffold.notes import Notes


def is_ros1_launch(relative: str) -> bool:
    return relative.endswith(".launch")


@dataclass
class Models:
    """The package's models as read, and what the migration learnt from them."""

    read: dict[str, ModelFile] = field(default_factory=dict)
    links: set[str] = field(default_factory=set)
    root: str | None = None  # the root link of the first .urdf
    missing: list[Reference] = field(default_factory=list)
    found: dict[str, Path] = field(default_factory=dict)  # package://NAME/ naming no package → folder


def _used_models(models: list[str], texts: dict[str, str], launch_files: list[str]) -> set[str]:
    """The models a launch file names, and what they include (by file name: a model's name in a
    launch file or in a used model's text). A file nothing names is never read by ROS 1 tools."""
    used: set[str] = set()
    readers = list(launch_files)
    while readers:
        text = texts.get(readers.pop(), "")
        for model in models:
            if model not in used and (model in text or Path(model).name in text):
                used.add(model)
                readers.append(model)
    return used


def read_models(source: Path, files: list[str], notes: Notes) -> Models:
    """Each model read (a model with content after its root as ROS 1 read it), the links of all,
    the root link of the first .urdf, and the meshes that are missing. A model that is not
    well-formed XML stops the migration only when a launch file uses it (ROS 1 never read it
    otherwise): else it is copied as written, and reported. (Gazebo Classic plugins are
    migrate/gazebo.py's: converted with --gazebo, else left out.)"""
    from pkgforge.scaffold.from_urdf import ModelUnreadable, decode, read_model, root_link, trailing_message

    models = [r for r in files if r.endswith(XACRO_MODEL_SUFFIXES) or _model_part(source / r)]
    texts = {r: decode((source / r).read_bytes()) for r in [*models, *filter(is_ros1_launch, files)]}
    used = _used_models(models, texts, [r for r in files if is_ros1_launch(r)])
    result = Models()
    for relative in models:
        path = source / relative
        try:
            model = result.read[relative] = read_model(path)
        except ModelUnreadable as error:
            if relative in used:
                raise
            notes.add(
                "migrate-source-defect",
                f"{error.why}; no launch file uses it: copied as written",
                path,
                error.line,
            )
            continue
        if model.trailing_line is not None:
            notes.add("migrate-source-defect", trailing_message(model), path, model.trailing_line)
        result.links |= {name for e in model.root.iter("link") if (name := e.get("name"))}
        if result.root is None and relative.endswith(".urdf"):
            result.root = root_link(model.root)
        _check_meshes(model, relative in used, result, notes)
    return result


# fusion2urdf writes the model's Gazebo plugins and transmissions into urdf/<name>.gazebo and
# <name>.trans, files its xacro includes: whatever its name, a file whose root is <robot> is part of
# the model (its plugins converted or left out as the model's own)
ROBOT_ROOT = re.compile(rb"(?:\xef\xbb\xbf)?\s*(?:<\?xml[^>]*\?>\s*)?(?:<!--.*?-->\s*)*<robot\b", re.DOTALL)
OTHER_KINDS = (".launch", ".rviz", ".yaml", ".yml", ".sdf", ".world", ".dae", ".stl", ".obj", ".xml")


def _model_part(path: Path) -> bool:
    from pkgforge.model.source import read_head

    if path.name.lower().endswith(OTHER_KINDS):
        return False
    try:
        head, _ = read_head(path, 4096)
    except OSError:
        return False
    return ROBOT_ROOT.match(head) is not None


def _check_meshes(model: ModelFile, used: bool, result: Models, notes: Notes) -> None:
    """Each mesh and texture a model names literally must exist (a used model's missing mesh stops
    the migration; an unused model's is reported)."""
    from pkgforge.scaffold.from_urdf import model_references
    from pkgforge.scaffold.model_uris import COMPUTED, resolve

    reported: set[str] = set()
    for reference in model_references(model.path, model.root, model.text):
        if reference.kind not in ("mesh", "texture") or COMPUTED.search(reference.uri):
            continue
        found, problem = resolve(reference.uri, model.path, result.found)
        if found is not None and not found.is_file():
            found, problem = None, f"no file {found}"  # a folder, a FIFO: no mesh
        if found is not None:
            continue
        reference.problem = problem
        if used:
            result.missing.append(reference)
        elif reference.uri not in reported:
            reported.add(reference.uri)
            notes.add(
                "migrate-source-defect",
                f"{reference.kind} '{reference.uri}' not found ({problem}); no launch file uses this model: "
                "copied as written",
                model.path,
                reference.line,
            )
