"""Which robot models to process, and their results (plain data from the worker).

A model is processed when a launch file feeds it to xacro (with that launch's
xacro arguments), and every robot model installed anywhere in the package's
share folder (urdf/, description/, models/<robot>/, config/, the top …) that no
other installed file includes is processed on its own: the model a person opens
in RViz by hand is checked too. A robot model is a .urdf or .xacro file whose
root is <robot> and that gives the robot something outside macro definitions
(a link, a joint, a macro call …), itself or through a file it includes; a
macro library (only macros, properties and arguments, as xacro users write
them for others to include) is checked through the models that include it,
never alone. A file that is not XML at all is processed, so its error is named.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, TypedDict

from pkgforge.launch.records import LaunchFile, Resolution
from pkgforge.launch.resolve import run_requests, source_of
from pkgforge.model.package import PackageModel
from pkgforge.model.source import read_regular
from pkgforge.sandbox.protocol import ModelRequest
from pkgforge.tree import InstallTree
from pkgforge.urdf import SEMANTIC_SUFFIXES, XACRO_MODEL_SUFFIXES
from pkgforge.urdf.structure import ModelError, ModelStatus, RobotStructure
from pkgforge.walk import walk

if TYPE_CHECKING:
    from pkgforge.launch.resolve import WorkerLimits
    from pkgforge.sandbox.zygote import Zygote

# folders of a share folder whose files are no model of the package (as for launch files)
SKIPPED_FOLDERS = ("test", "tests", "__pycache__")
# a file larger than this is not read to classify it: processed (and reported as too large)
CLASSIFY_MAX_BYTES = 2 * 2**20
# xacro's own elements that give the robot nothing by themselves (if/unless: their content may)
XACRO_DEFINITIONS = {"macro", "property", "arg", "include"}
XACRO_CONDITIONALS = {"if", "unless"}
XACRO_NAMESPACE = "http://www.ros.org/wiki/xacro"


class LaunchOrigin(TypedDict):
    """A launch line that feeds the model to xacro."""

    launch: LaunchFile
    file: str | None
    line: int | None
    # the argument settings it is fed with when never with the defaults (Resolution.off_default)
    only_with: list[str]


@dataclass
class ModelResult:
    package: str  # the verified package that uses or installs the model
    installed: Path
    source: Path | None
    mappings: dict[str, str]
    origins: list[LaunchOrigin] = field(default_factory=list)  # launch lines that feed it to xacro
    status: ModelStatus = "ok"
    error: ModelError | None = None
    robot: RobotStructure | None = None
    includes: list[str] = field(default_factory=list)

    @property
    def links(self) -> set[str | None]:
        """The names of the model's links (None: a link without one)."""
        return {link["name"] for link in self.robot.get("links", [])} if self.robot else set()


@dataclass
class _Shape:
    """What a model file gives the robot, read without running it."""

    # <robot> at its root, or named a URDF (.urdf, .urdf.xacro: another root is the model's defect),
    # or not XML at all (processed all the same: the error is named)
    robot: bool = True
    content: bool = True  # something outside macro definitions (a link, a joint, a macro call …)
    includes: list[str] = field(default_factory=list)  # the names of the files it includes
    links: set[str] = field(default_factory=set)  # the links it defines (outside macro definitions)
    parents: set[str] = field(default_factory=set)  # the parent links its joints name


def _shape(path: Path, share: Path, package: str) -> _Shape:
    from lxml import etree

    try:
        data = read_regular(path, CLASSIFY_MAX_BYTES)  # (a FIFO or a device: refused, never read)
        if not data or (len(data) < 4096 and not data.strip()):
            # an empty file (rox_description's meca_wheel.xacro, 0 bytes in git; or blank) is no robot:
            # nothing xacro could read, and nothing includes it
            return _Shape(robot=False, content=False)
        parser = etree.XMLParser(
            remove_comments=True, remove_pis=True, resolve_entities=False, no_network=True, huge_tree=False
        )
        root = etree.fromstring(data, parser, base_url=str(path))
    except (OSError, etree.XMLSyntaxError, ValueError):  # (too large: FileTooLarge, an OSError)
        return _Shape()
    if root is None or not isinstance(root.tag, str):
        return _Shape()
    shape = _Shape(
        robot=etree.QName(root).localname == "robot" or path.name.endswith((".urdf", ".urdf.xacro")),
        content=False,
    )
    stack = list(root)
    while stack:  # no recursion: a file nests as deep as it likes
        element = stack.pop()
        if not isinstance(element.tag, str):
            continue
        name = etree.QName(element).localname
        if element.prefix != "xacro" and element.tag != f"{{{XACRO_NAMESPACE}}}{name}":
            shape.content = True  # a link, joint, material, gazebo … of its own
            if name == "link" and (link := element.get("name")):
                shape.links.add(link)
            elif name == "joint" and (parent := element.find("parent")) is not None:
                shape.parents.add(parent.get("link") or "")
        elif name == "include":
            filename = element.get("filename", "").strip()
            shape.includes.append(os.path.basename(filename))
            if _missing_include(filename, path, share, package):
                shape.content = True  # fails by itself, whoever includes it: processed, its line named
        elif name in XACRO_CONDITIONALS:
            stack.extend(element)
        elif name not in XACRO_DEFINITIONS:
            shape.content = True  # a macro call, xacro:element, xacro:insert_block …
    return shape


def _missing_include(filename: str, path: Path, share: Path, package: str) -> bool:
    """Whether an include names a file that is not there, whatever includes its file: a path
    relative to the file, or in the package's own share folder ($(find <package>))."""
    filename = filename.replace(f"$(find {package})", str(share))
    if not filename or "$" in filename:
        return False  # a property, an argument or another package: the includer decides
    if any(c in filename for c in "*[?"):
        return False  # a pattern (xacro globs it; no match is only a warning)
    return not (path.parent / filename).exists()


def _installed_models(tree: InstallTree, model: PackageModel) -> list[Path]:
    """The robot models installed in the package's share folder that no installed file includes."""
    share = tree.share(model.share_name)
    if share is None:
        return []
    shapes: dict[Path, _Shape] = {}
    for root, dirs, files in walk(share, follow_links=True, inside=(model.path,), limits=model.walk_limits):
        dirs[:] = sorted(d for d in dirs if d not in SKIPPED_FOLDERS and not d.startswith("."))
        for name in sorted(files):
            if name.endswith(XACRO_MODEL_SUFFIXES) and not name.endswith(SEMANTIC_SUFFIXES):
                shapes[Path(root) / name] = _shape(Path(root) / name, share, model.share_name)
    by_name: dict[str, list[_Shape]] = {}
    for path, shape in shapes.items():
        by_name.setdefault(path.name, []).append(shape)
    included = {name for path, shape in shapes.items() for name in shape.includes if name != path.name}
    return [
        path
        for path, shape in shapes.items()
        if shape.robot
        and path.name not in included
        and _gives_content(shape, by_name)
        and not (path.name.endswith(".xacro") and _fragment(shape, by_name))
    ]


def _fragment(shape: _Shape, by_name: dict[str, list[_Shape]]) -> bool:
    """Whether a xacro file hangs its joints on a link that neither it nor the installed files it
    includes define (a camera.xacro on 'chassis'): a piece of a robot, meant to be included (often by
    an include that is commented out), not a robot; processed alone it could only fail."""
    links, seen, stack = set(), set(), [shape]
    while stack:
        current = stack.pop()
        links |= current.links
        for name in current.includes:
            if name not in seen:
                seen.add(name)
                stack.extend(by_name.get(name, []))
    return any(parent and "$" not in parent and parent not in links for parent in shape.parents)


def _gives_content(shape: _Shape, by_name: dict[str, list[_Shape]]) -> bool:
    """Whether the file, with the installed files it includes, gives the robot anything: a file
    including only libraries (or files of other packages) is a library itself."""
    seen, stack = set(), [shape]
    while stack:
        current = stack.pop()
        if current.content:
            return True
        for name in current.includes:
            if name not in seen:
                seen.add(name)
                stack.extend(by_name.get(name, []))
    return False


def collect(
    tree: InstallTree, models: list[PackageModel], resolutions: dict[str, list[Resolution]]
) -> list[ModelResult]:
    # (package, model, its xacro arguments) → its result
    jobs: dict[tuple[str, str, tuple[tuple[str, str], ...]], ModelResult] = {}
    by_name = {m.name: m for m in models}
    for package, package_resolutions in resolutions.items():
        owner = by_name.get(package)
        for resolution in package_resolutions:
            for command in resolution.commands:
                model_path = command.model
                if (
                    not model_path
                    or model_path.endswith(SEMANTIC_SUFFIXES)
                    or not os.path.isfile(model_path)
                    or tree.is_phantom(model_path)
                ):
                    continue
                key = (package, os.path.normpath(model_path), tuple(sorted(command.mappings.items())))
                if key not in jobs:
                    jobs[key] = ModelResult(
                        package, Path(key[1]), source_of(Path(key[1]), tree, owner), dict(command.mappings)
                    )
                if command.robot and jobs[key].robot is None:
                    # the launch's own xacro run already gave the structure
                    jobs[key].robot, jobs[key].includes = command.robot, list(command.includes)
                jobs[key].origins.append(
                    {
                        "launch": resolution.launch,
                        "file": command.file,
                        "line": command.line,
                        "only_with": resolution.off_default(command),
                    }
                )
    fed = {key[:2] for key in jobs}  # (package, model) a launch file feeds to xacro
    for model in models:
        for path in _installed_models(tree, model):
            key = (model.name, os.path.normpath(path), ())
            if key[:2] not in fed:
                fed.add(key[:2])
                jobs[key] = ModelResult(model.name, path, source_of(path, tree, model), {})
    return list(jobs.values())


def process(
    results: list[ModelResult],
    tree: InstallTree,
    *,
    jobs: int,
    timeout: float,
    on_done: Callable[[], None] | None = None,
    limits: WorkerLimits | None = None,
    zygote: Zygote | None = None,
) -> list[ModelResult]:
    """Run xacro on the models whose structure no launch file's xacro run already gave."""
    pending = [r for r in results if r.robot is None]
    requests: list[ModelRequest] = [{"model": str(r.installed), "mappings": r.mappings} for r in pending]
    for result, reply in zip(
        pending,
        run_requests(
            requests, tree, jobs=jobs, timeout=timeout, on_done=on_done, limits=limits, zygote=zygote
        ),
        strict=False,
    ):
        result.status = reply.get("status", "crashed")
        result.error = reply.get("error")
        result.robot = reply.get("robot")
        result.includes = reply.get("includes", [])
        if result.status == "ok" and not result.origins and not result.links:
            result.status = "library"  # only macros and properties: checked through its includers
        if result.status == "needs-arguments" and result.origins:
            result.status = "error"  # a launch file gave it no value either
    for result in results:
        if result not in pending and not result.links and not result.origins:
            result.status = "library"
    return results
