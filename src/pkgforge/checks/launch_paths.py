"""Files and folders a launch file references: installed, and existing in the install tree or in
the source."""

from __future__ import annotations

import difflib
from collections.abc import Iterator
from pathlib import Path
from typing import NamedTuple

from pkgforge.checks.context import NONE_TEXT, CheckContext
from pkgforge.checks.install import install_fix, install_fix_data, link_hint
from pkgforge.checks.launch import _branch_note, static_note
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Severity
from pkgforge.launch.records import Resolution, ResolvedPath
from pkgforge.model.package import PackageModel
from pkgforge.model.references import Reference
from pkgforge.walk import UNREADABLE_HINT

# how a path that is only the first part of a name ends: no file is named like that
FRAGMENT_ENDINGS = ("_", "-", ".")


def _share_reference(ctx: CheckContext, path: str) -> tuple[str, str, Path] | None:
    located = ctx.tree.locate(path) if ctx.tree is not None else None
    if located is None or ctx.tree is None or ctx.tree.is_phantom(path):
        return None
    return located


def argument_default_in_branch(item: ResolvedPath, resolution: Resolution) -> tuple[str, str] | None:
    """(argument, the branch's setting) when a path missing only on some argument branches is
    another declared argument's default there: a default computed from a choice (panther's
    wheel_type:=custom makes controller_config_path's default .../custom_controller.yaml), which
    the user overrides when choosing it. None when the path is missing on every branch."""
    branches = [b for b in item.branches if b]
    if not branches or len(branches) >= resolution.branches:
        return None
    defaults = {a.name: a.default for a in resolution.arguments}
    changed = {
        name: value
        for name, value in item.branch.items()
        if value is not None and defaults.get(name) not in (None, "", value)
    }
    for argument in resolution.arguments:
        if argument.name in item.branch or not argument.default:
            continue
        text, used = argument.default, []
        for name, value in sorted(changed.items()):
            if str(defaults[name]) in text:
                text = text.replace(str(defaults[name]), value)
                used.append(f"{name}:={value}")
        if used and text == item.path:
            return argument.name, " ".join(used)
    return None


@register(
    "PF302",
    "uninstalled-reference",
    "error",
    area="launch",
    fix="safe",
    bad=(
        "# launch/display.launch.py (rviz/ is not in the install rules)\n"
        "rviz = PathJoinSubstitution([FindPackageShare('rob_description'), 'rviz', 'display.rviz'])"
    ),
    good=("# CMakeLists.txt\ninstall(DIRECTORY launch rviz urdf DESTINATION share/${PROJECT_NAME})"),
    summary="a launch file resolves a path that the install rules leave out",
    explanation="The file exists in src/ but not in install/share/<pkg>/, where `ros2 launch` "
    "looks: your RViz config never installed, RViz starts empty.",
    hint="extend the install rule",
)
def uninstalled_reference(ctx: CheckContext) -> Iterator[Finding]:
    yield from _missing_paths(ctx, want_source=True)


@register(
    "PF303",
    "missing-file",
    "error",
    area="launch",
    bad=(
        "# launch/display.launch.py (the file is urdf/robot.urdf.xacro)\n"
        "model = PathJoinSubstitution([FindPackageShare('rob_description'), 'urdf', 'robot.xacro'])"
    ),
    good=(
        "# launch/display.launch.py\n"
        "model = PathJoinSubstitution([FindPackageShare('rob_description'), 'urdf', 'robot.urdf.xacro'])"
    ),
    summary="a launch file resolves a path that exists nowhere",
    explanation="Neither the install tree nor the package's source has the file: a typo in a "
    "file or folder name, or a file never committed. A warning when the path is another "
    "argument's default on one argument choice only (wheel_type:=custom making "
    "wheel_config_path's default config/custom.yaml): with that choice the user gives it.",
    hint="fix the path in the launch file",
)
def missing_file(ctx: CheckContext) -> Iterator[Finding]:
    yield from _missing_paths(ctx, want_source=False)


def _unreadable_folder(owner: PackageModel, source: Path) -> Path | None:
    """The folder of owner's source that the walk could not read and that holds source."""
    for limit in [*owner.walk_limits, *owner.layout.walk_limits]:
        folder = Path(limit.path)
        if limit.hint == UNREADABLE_HINT and folder in source.parents and owner.path in folder.parents:
            return folder
    return None


def _may_install(owner: PackageModel, destination: str) -> tuple[Path, int] | None:
    """The (path, line) of an install rule pkgforge cannot evaluate that may install files at
    `destination` (its own destination unknown, or one `destination` is under), else None."""
    for path, line, where in owner.layout.may_install:
        if (
            where is None
            or where.strip("/.") == ""
            or destination == where
            or destination.startswith(where.rstrip("/") + "/")
        ):
            return path, line
    return None


class _Unresolved(NamedTuple):
    """A path a launch file resolves (or, read statically, names) that the tree does not have."""

    path: str  # in the tree
    source: Path  # the launch file that names it
    line: int | None
    item: ResolvedPath | None  # the record; None: read statically
    resolution: Resolution | None
    reference: Reference | None  # the static reference, when read statically


def _unresolved_paths(ctx: CheckContext) -> Iterator[_Unresolved]:
    """The paths launch files resolve that do not exist, then the literal paths into a workspace
    package's share folder that the files read statically (not evaluated, or not loading) name
    and that do not exist either."""
    for resolution in ctx.resolutions:
        for item in resolution.paths:
            if item.exists:
                continue
            if item.via == "PathJoinSubstitution" and item.path.endswith(FRAGMENT_ENDINGS):
                continue  # the start of a name the file goes on to build (interbotix's
                # [PathJoinSubstitution([share, 'config', 'motor_specs_']), robot_model, '.yaml'])
            checked = ctx.file_part(resolution, item.path)  # (gz_args 'world.sdf -r': world.sdf)
            if checked != item.path and ctx.files.exists(checked):
                continue
            position = ctx.source_position(resolution, item.file, item.line)
            if position is not None:
                yield _Unresolved(checked, position[0], position[1], item, resolution, None)
    for source, references in ctx.static_fallback().items():
        for reference in references:
            relative = (reference.relative or "").strip("/")
            share = ctx.tree.share(reference.package) if ctx.tree is not None and relative else None
            # (only a whole path: not the start of a name built on, nor one from a rebound name;
            # not one a `try:` handles the absence of)
            if (
                share is None
                or not reference.exact
                or reference.guarded
                or relative.endswith(FRAGMENT_ENDINGS)
            ):
                continue
            ctx.read_elsewhere.add(str(share / relative))  # (as a resolved path is: verify/cache.py)
            failed = ctx.failed_to_load(source)
            if (
                failed is not None
                and failed.error is not None
                and f"{reference.package}/{relative}" in failed.error.message
            ):
                continue  # the file fails reading that very path: its load error is this finding
            if not ctx.files.exists(share / relative):
                yield _Unresolved(str(share / relative), source, reference.line, None, None, reference)


def _missing_paths(ctx: CheckContext, *, want_source: bool) -> Iterator[Finding]:
    # one defect, one diagnostic: the first line of a file that names the path, "and N more"
    found: dict[tuple[str, str, str], tuple[PackageModel | None, _Unresolved, list[int | None]]] = {}
    for unresolved in _unresolved_paths(ctx):
        located = _share_reference(ctx, unresolved.path)
        if located is None:
            continue
        package, relative, _ = located
        if ctx.tree is not None and package in ctx.tree.unpredicted:
            continue  # its install is not known: not known to be missing (unpredicted-lookup)
        resolution = unresolved.resolution
        if NONE_TEXT.search(relative) and (resolution is None or ctx.unset_environment(resolution)):
            continue  # launch-environment-unset: os.getenv() gave None here
        owner = ctx.model_for_share(package)
        source = owner.path / relative if owner is not None else None
        in_source = source is not None and ctx.files.exists(source)
        if in_source != want_source:
            continue
        path, line = unresolved.source, unresolved.line
        if unresolved.item is not None:
            line = ctx.static_line(path, package, relative, line) or line
        lines = found.setdefault((str(path), package, relative), (owner, unresolved, []))[2]
        if line not in lines:
            lines.append(line)
    for (_, package, relative), (owner, unresolved, lines) in found.items():
        lines.sort(key=lambda n: (n is None, n or 0))
        path, line = unresolved.source, lines[0]
        others = [str(n) for n in lines[1:] if n is not None]
        more = (
            f" (and {len(lines) - 1} more in this file" + (f": line {', '.join(others)})" if others else ")")
            if len(lines) > 1
            else ""
        )
        shown = f"share/{package}/{relative}"
        source = owner.path / relative if owner is not None else None
        item, resolution, reference = unresolved.item, unresolved.resolution, unresolved.reference
        note = _branch_note(item, resolution) if item is not None and resolution is not None else ""
        note += static_note(ctx, path, item)
        # a file read statically: a path named in one if/else branch of it is needed only if that
        # branch runs, which is not known (an error when the file would reach it whatever happens)
        branch = (
            reference.python_branch
            if reference is not None
            and reference.python_branch is not None
            and ctx.branch_on_distros(reference.python_branch) is None
            else None
        )
        severity = Severity.WARNING if branch else None
        if branch:
            note += f" (only in the branch `{branch}`)"
        linked = link_hint(ctx.files, owner, relative) if owner is not None else None
        if linked is not None and source is not None:
            if want_source == ctx.files.exists(source):  # report it once, under either code
                yield Finding(
                    f"{shown} is not in the install tree: {linked[0]}{note}{more}",
                    path,
                    line,
                    hint=linked[1],
                    severity=severity,
                )
        elif (
            want_source
            and owner is not None
            and (not owner.layout.known or (may := _may_install(owner, f"share/{package}/{relative}")))
        ):
            # an install rule pkgforge cannot evaluate (PF206) may install it: limo_ros2's
            # voice_control setup.py computes its data_files (and the hint's glob broke the build)
            rule = f" ({ctx.relative(may[0])}:{may[1]})" if owner.layout.known and may else ""
            yield Finding(
                f"{shown} is not in the predicted install tree: {relative} is in the source of "
                f"{package}, and an install rule pkgforge cannot evaluate{rule} may install it"
                f"{note}{more}",
                path,
                line,
                severity=Severity.WARNING,
                hint="check against a real build: pkgforge verify --build (or --install-base install)",
            )
        elif want_source and owner is not None:
            elsewhere = next((d for d, f in owner.layout.files.items() if f.source == source), None)
            why = f"an install rule installs it as {elsewhere}" if elsewhere else "no install rule covers it"
            yield Finding(
                f"{shown} is not installed: {relative} is in the source of {package} but {why}{note}{more}",
                path,
                line,
                hint=install_fix(owner, relative.split("/")[0], relative),
                fix=install_fix_data(owner, relative.split("/")[0]),
                severity=severity,
            )
        elif (
            owner is not None
            and source is not None
            and (folder := _unreadable_folder(owner, source)) is not None
        ):
            yield Finding(
                f"{shown} cannot be checked: {package}'s folder {folder.relative_to(owner.path)}/ "
                f"cannot be read{note}{more}",
                path,
                line,
                hint=UNREADABLE_HINT,
            )
        elif (
            item is not None
            and resolution is not None
            and (default := argument_default_in_branch(item, resolution)) is not None
        ):
            argument, setting = default
            yield Finding(
                f"{shown} does not exist: it is the default of argument '{argument}' with "
                f"{setting}, so that setting works only when {argument} is given too{more}",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"with {setting}, give {argument}:=PATH (say so in the argument's description), "
                f"or add {relative} to {package}",
            )
        else:
            hint = None
            if owner is not None:
                near = difflib.get_close_matches(relative, [str(f) for f in owner.files], n=1)
                hint = f"did you mean {near[0]}?" if near else f"no file {relative} in {package}"
            yield Finding(
                f"{shown} does not exist, in the install tree or in {package}'s source{note}{more}",
                path,
                line,
                hint=hint,
                severity=severity,
            )
