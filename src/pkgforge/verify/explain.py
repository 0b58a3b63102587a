"""`pkgforge verify --explain-launch FILE`: how one launch file resolves in the install tree."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pkgforge.errors import PkgforgeError
from pkgforge.printable import printable
from pkgforge.verify.discovery import load_models
from pkgforge.verify.pipeline import VerifyOptions, make_tree
from pkgforge.workspace import locate

if TYPE_CHECKING:
    from pkgforge.launch.engines import LaunchEngine
    from pkgforge.launch.records import CommandRun, Node, PackageLookup, Record, Resolution
    from pkgforge.model.package import PackageModel
    from pkgforge.tree import InstallTree
    from pkgforge.urdf.structure import JointDict, MeshDict, ModelError, RobotStructure

OK, MISSING, UNCHECKED = "✓", "✗", "·"


def _installed_path(file: Path, tree: InstallTree, models: Iterable[PackageModel]) -> tuple[Path, str]:
    if not file.is_file():
        raise PkgforgeError(
            f"{file}: {'is not a file' if file.exists() else 'does not exist'}; give a file of a package "
            "of the workspace (or of its install tree)"
        )
    file = Path(tree.in_tree(str(file.resolve())))  # the user's install base → the worker's shadow of it
    located = tree.locate(str(file))
    if located is not None:
        return file, located[0]
    for model in models:
        for destination, installed in model.layout.files.items():
            if installed.source is not None and installed.source.resolve() == file:
                for prefix in tree.prefixes:
                    if (prefix / destination).exists():
                        return prefix / destination, model.name
    raise PkgforgeError(
        f"{file} is not installed by any package under the workspace: "
        "is it in a folder the install rules cover?"
    )


@contextmanager
def _installed(
    path: Path, file: Path, options: VerifyOptions
) -> Iterator[tuple[InstallTree, Path, str, PackageModel | None]]:
    """(tree, installed path of FILE, its package, the package's model); the tree closes after."""
    workspace = locate(path)
    _, models = load_models(workspace, 1)
    tree = make_tree(options, workspace, list(models.values()))
    try:
        installed, package = _installed_path(file, tree, models.values())
        owner = next((m for m in models.values() if package in (m.name, m.share_name)), None)
        yield tree, installed, package, owner
    finally:
        tree.close()


def explain_launch_file(path: Path, file: Path, options: VerifyOptions) -> str:
    from pkgforge.launch.records import LaunchFile
    from pkgforge.launch.resolve import WorkerLimits, resolve, source_of
    from pkgforge.verify.pipeline import check_launch_arguments

    with _installed(path, file, options) as (tree, installed, package, owner):
        launch = LaunchFile(package, installed, source_of(installed, tree, owner))
        (resolution,) = resolve(
            [launch],
            tree,
            timeout=options.launch_timeout,
            arguments=options.launch_arguments,
            engine=_engine_for(path, owner, options),
            limits=WorkerLimits(options.launch_timeout, options.worker_memory),
        )
        # a --launch-arg value outside the file's choices: exit 2 naming them, as verify does
        check_launch_arguments(options.launch_arguments, {package: [resolution]})
        return _render(resolution, tree)


def _engine_for(path: Path, owner: PackageModel | None, options: VerifyOptions) -> LaunchEngine:
    """The engine verify evaluates the package's launch files with: the built-in one follows the
    package's target distro (pkgforge.toml, its CI files), as in verify."""
    engine = options.engine()
    if engine.name != "builtin" or owner is None:
        return engine
    from pkgforge.launch.engines import builtin
    from pkgforge.verify.config import load_config
    from pkgforge.verify.distros import launch_distro

    workspace = locate(path)
    distro, _ = launch_distro(owner.path, workspace, load_config(workspace.root, options.selection), options)
    return engine if distro == engine.distro else builtin(distro)


def _short(path: str, tree: InstallTree) -> str:
    located = tree.locate(path)
    if located is None:
        return path
    return f"share/{located[0]}/{located[1]}"


def _mark(path: str, exists: bool, tree: InstallTree) -> str:
    if tree.is_phantom(path):
        return UNCHECKED
    return OK if exists else MISSING


def _place_with_branches(item: Record) -> str:
    """`file.py:12 [branch, ...]`: where a launch item stands and the branches it was seen in."""
    place = f"{os.path.basename(item.file)}:{item.line}" if item.file else f"line {item.line}"
    branches = [b for b in item.branches if b]
    return place + (f" [{', '.join(branches)}]" if branches else "")


def _node(n: Node, tree: InstallTree) -> list[str]:
    text = f"{n.package}/{n.executable}" if n.kind == "node" else " ".join(n.cmd or [])
    if n.arguments:
        text += f" args {[_short(a, tree) for a in n.arguments]}"
    return [text, *(f"      param {p.name or '(file)'}: {p.form}" for p in n.parameters)]


def _package(p: PackageLookup, tree: InstallTree) -> str:
    phantom = p.name in tree.phantom_packages
    mark = UNCHECKED if phantom else MISSING if p.found is False else OK
    return f"{mark} {p.name} ({p.via})" + (" — declared, not installed here" if phantom else "")


def _command(c: CommandRun, tree: InstallTree) -> list[str]:
    text = f"{OK if c.ok else MISSING} {' '.join(_short(w, tree) for w in c.command)}"
    if c.runtime_only:
        return [f"{UNCHECKED} {' '.join(c.command)} (run time only, not executed)"]
    if not c.ok and c.message:
        return [text, f"      {c.message.splitlines()[0]}"]
    return [text]


def _render(resolution: Resolution, tree: InstallTree) -> str:
    launch = resolution.launch
    engine = (
        f"ROS 2 {resolution.distro or '(distro unknown)'}'s launch"
        if resolution.engine == "ros"
        else "the built-in launch engine" + (f" ({resolution.distro})" if resolution.distro else "")
    )
    lines = [
        f"{launch.source or launch.installed}",
        f"  installed as {_short(str(launch.installed), tree)} "
        f"in the {tree.kind} tree, evaluated by {engine}",
    ]
    if resolution.status != "ok":
        error = resolution.error
        lines.append(
            f"  {MISSING} {resolution.status}: {error.message if error else None} "
            f"(line {error.line if error else None})"
        )
    if resolution.arguments:
        lines.append("arguments:")
        for argument in resolution.arguments:
            values = " | ".join(argument.choices) if argument.choices else argument.default
            shown = _short(values, tree) if isinstance(values, str) and values.startswith("/") else values
            lines.append(f"  {argument.name} = {shown if shown is not None else '(required)'}")
    if resolution.branch_names:
        lines.append(f"evaluated for: {'; '.join(resolution.branch_names)}")
    if resolution.unevaluated:
        lines.append(
            f"not evaluated within the time limit: {resolution.unevaluated} of "
            f"{resolution.branching.planned} argument combinations"
        )
    # each kind with how to show one of its records (Node, PackageLookup, Include …), as lines
    sections: list[tuple[str, Callable[[Any, InstallTree], list[str]]]] = [
        ("nodes", _node),
        ("packages", lambda p, t: [_package(p, t)]),
        ("includes", lambda i, t: [f"{_mark(i.path, i.exists, t)} {_short(i.path, t)} {i.arguments or ''}"]),
        ("paths", lambda p, t: [f"{_mark(p.path, p.exists, t)} {_short(p.path, t)} ({p.via})"]),
        ("commands", _command),
        ("errors", lambda e, t: [f"{MISSING} {e.entity}: {e.message}"]),
        ("unsupported", lambda u, t: [f"{UNCHECKED} {u.name} (not evaluated)"]),
    ]
    for kind, show in sections:
        items = getattr(resolution, kind)
        if items:
            lines.append(f"{kind}:")
            seen: set[tuple[str, ...]] = set()
            for item in sorted(items, key=lambda i: i.line or 0):
                entry = [printable(line) for line in show(item, tree)]
                entry[0] = f"  {entry[0]}"
                entry[-1] += f"  @ {printable(_place_with_branches(item))}"
                if tuple(entry) not in seen:
                    seen.add(tuple(entry))
                    lines += entry
    return _printed(lines)


def _printed(lines: list[str]) -> str:
    """The lines, one line each: a name's or a message's own newline or escape sequence shown,
    not acted on (printable is idempotent: a line already made printable stays as it is)."""
    return "".join(printable(line) + "\n" for line in lines)


def explain_model_file(path: Path, file: Path, options: VerifyOptions) -> str:
    """The model's link/joint tree with every mesh URI and whether it resolves (check_urdf, with meshes)."""
    from pkgforge.launch.resolve import source_of
    from pkgforge.urdf import select as robot_models
    from pkgforge.urdf.meshes import resolve_uri

    with _installed(path, file, options) as (tree, installed, package, owner):
        result = robot_models.ModelResult(
            package, installed, source_of(installed, tree, owner), dict(options.launch_arguments)
        )
        (result,) = robot_models.process([result], tree, jobs=1, timeout=options.launch_timeout)
        lines = [
            f"{result.source or installed}",
            f"  installed as {_short(str(installed), tree)} in the {tree.kind} tree",
        ]
        if result.status not in ("ok", "library"):
            error: ModelError = result.error or {}
            lines.append(
                f"  {MISSING} {result.status}: {error.get('message')} "
                f"({os.path.basename(error.get('file') or '')}:{error.get('line')})"
            )
            return _printed(lines)
        robot = result.robot
        if robot is None or robot.get("root_tag") != "robot":
            raise PkgforgeError(
                f"{file} is not a robot model: its root element is "
                f"<{robot.get('root_tag') if robot is not None else None}>, not <robot>"
            )
        links, joints = robot.get("links", []), robot.get("joints", [])
        if not links:
            lines.append("a macro library: no links of its own (checked through the models that include it)")
            return _printed(lines)
        lines.append(f"robot {robot.get('name')}: {len(links)} links, {len(joints)} joints")
        lines += _model_numbers(robot, tree, installed)
        meshes: dict[str | None, list[MeshDict]] = {}
        for mesh in robot.get("meshes", []):
            meshes.setdefault(mesh.get("link"), []).append(mesh)
        children: dict[str | None, list[JointDict]] = {}
        for joint in joints:
            children.setdefault(joint.get("parent"), []).append(joint)
        child_names = {j.get("child") for j in joints}

        def mesh_lines(link: str | None, indent: str) -> None:
            for mesh in meshes.get(link, []):
                lookup = resolve_uri(mesh["uri"], tree, installed)
                mark = {"found": OK, "unchecked": UNCHECKED}.get(lookup.status, MISSING)
                note = "" if lookup.status in ("found", "unchecked") else f"  ({lookup.status})"
                if lookup.status == "found" and lookup.path is not None:
                    note = _mesh_note(lookup.path)
                lines.append(f"{indent}{mesh['kind']} {mark} {mesh['uri']}{note}")

        def joints_below(link: str | None) -> list[JointDict]:  # in name order, the first last (popped)
            return sorted(children.get(link, []), key=lambda j: j.get("name") or "")[::-1]

        def walk(root: str | None) -> None:
            """Each joint below root, depth first; a link already on the way down is not entered
            again (a loop). Without recursion: a chain of links is as deep as it is long."""
            on_path: dict[str | None, int] = {root: 1}
            stack: list[tuple[str | None, str, list[JointDict]]] = [(root, "", joints_below(root))]
            while stack:
                link, indent, left = stack[-1]
                if not left:
                    stack.pop()
                    on_path[link] -= 1
                    continue
                joint = left.pop()
                last = not left
                lines.append(
                    f"{indent}{'└─' if last else '├─'} {joint['name']} ({joint['type']}) → {joint['child']}"
                )
                deeper = indent + ("   " if last else "│  ")
                mesh_lines(joint["child"], deeper + "  ")
                if not on_path.get(joint["child"]):
                    on_path[joint["child"]] = on_path.get(joint["child"], 0) + 1
                    stack.append((joint["child"], deeper, joints_below(joint["child"])))

        for root in [link["name"] for link in links if link["name"] not in child_names]:
            lines.append(str(root))
            mesh_lines(root, "  ")
            walk(root)
        return _printed(lines)


def _size(low: Iterable[float], high: Iterable[float]) -> str:
    return " × ".join(f"{h - lo:.3g}" for lo, h in zip(low, high, strict=False)) + " m"


def _model_numbers(robot: RobotStructure, tree: InstallTree, installed: Path) -> list[str]:
    """Total mass and size (the same numbers `pkgforge view` writes on its images)."""
    from pkgforge.urdf.meshes import resolve_uri
    from pkgforge.urdf.physics import total_mass, world_bounds

    def resolve(uri: str) -> Path | None:
        lookup = resolve_uri(uri, tree, installed)
        return lookup.path if lookup.status == "found" else None

    with_mass = sum(
        1 for link in robot.get("links", []) if (inertial := link.get("inertial")) and inertial.get("mass")
    )
    lines = [
        f"mass: {total_mass(robot):.4g} kg total ({with_mass} of {len(robot.get('links', []))} links "
        "have a mass)"
    ]
    bounds = world_bounds(robot, resolve)
    if bounds is None:
        lines.append("size: no visual geometry")
    else:
        lines.append(
            f"size: {_size(*bounds)} (x × y × z of the visual geometry at the zero pose, "
            "in the root link's frame)"
        )
    return lines


def _mesh_note(path: Path) -> str:
    from pkgforge.urdf.physics import mesh_info

    info = mesh_info(str(path))
    if info is None:
        return "  (bounds not read)"
    return f"  [{_size(info.low, info.high)} in the file, {info.triangles} triangles]"
