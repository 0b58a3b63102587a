"""Checks of launch files as resolved in the install tree."""

from __future__ import annotations

import difflib
import os
import re
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any, NamedTuple

from pkgforge.checks.context import NONE_TEXT, CheckContext, only_with
from pkgforge.checks.files import read_problem_hint, undeclared_find, untree, untree_xacro
from pkgforge.checks.install import install_fix, install_fix_data, link_hint
from pkgforge.checks.registry import register
from pkgforge.checks.sandbox import MARKER as GUARD_MARKER
from pkgforge.checks.sandbox import SANDBOX_TYPES, sandbox_records, stopped_by_guard
from pkgforge.diagnostics import Finding, Group, Severity
from pkgforge.launch.records import PREVIEW_LENGTH, PackageLookup, Record, Resolution, ResolvedPath
from pkgforge.launch.records import Error as LaunchError
from pkgforge.model.manifest import EXPORT_TAGS
from pkgforge.model.package import PackageModel
from pkgforge.model.references import Reference
from pkgforge.urdf import ANY_MODEL_SUFFIXES, XACRO_MODEL_SUFFIXES
from pkgforge.walk import UNREADABLE_HINT

JSP_PACKAGES = ("joint_state_publisher", "joint_state_publisher_gui")
# rviz2 depends on these: their displays come with whatever starts RViz (an rviz2 Node is checked
# where it is started; a config that another package's launch file opens needs nothing of its own)
RVIZ_BUILTIN = {"rviz_common", "rviz_default_plugins"}
# how a path that is only the first part of a name ends: no file is named like that
FRAGMENT_ENDINGS = ("_", "-", ".")
# uses that missing-exec-depend checks; unknown names there are xacro's or RViz's error to report
# ("import": a file read statically; a module that is no ROS package is a Python library)
STATIC_ONLY_FOR_DEPENDENCIES = {"import of", "import", "package://", "$(find)", "RViz display from"}
# `ros2 launch` (ros2launch) depends on these: whoever can launch has them
LAUNCH_INFRASTRUCTURE = {
    "launch",
    "launch_ros",
    "launch_xml",
    "launch_yaml",
    "ament_index_python",
    "ros2launch",
}
# a package name with an empty part: f"kuka_{family}_support" of an empty argument
EMPTY_PART = re.compile(r"^_|__|_$")
# a path part that is the text of None (an f-string of os.getenv() of a variable not set)
# a package a launch file, a model or a file of the package uses: (name, source path, line, how,
# the launch record, its resolution); the last two are None for a static reference
Use = tuple[str, Path, "int | None", str, "Record | None", "Resolution | None"]


def static_note(ctx: CheckContext, path: Path, item: Record | None) -> str:
    """What a finding read from a launch file that did not load says of it: that file's literal
    references are checked statically, as if it had loaded ('' for any other use)."""
    failed = ctx.failed_to_load(path) if item is None else None
    if failed is None:
        return ""
    if failed.status == "timeout":
        return f" (read statically: {path.name} did not finish within the time limit here)"
    if failed.status == "crashed":
        return f" (read statically: {path.name} ended its process while loading)"
    return f" (read statically: {path.name} does not load)"


def read_as_failed(ctx: CheckContext, path: Path, item: Record | None) -> bool:
    """Whether a use is read statically from a launch file that does not load (static_note says
    so): where another file names the same package, that use is the one to point at."""
    return item is None and ctx.failed_to_load(path) is not None


def _branch_note(item: Record, resolution: Resolution) -> str:
    """' (only with ...)' when the item was seen with some argument settings only (their shared
    settings and count when they are several: context.only_with; --explain-launch lists each)."""
    branches = [b for b in item.branches if b]
    if branches and len(branches) < resolution.branches and "" not in item.branches:  # "": while loading
        return only_with(branches)[0]
    return ""


@register(
    "PF301",
    "launch-load-error",
    "error",
    area="launch",
    bad=(
        "# launch/display.launch.py\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([Node(package='rviz2')])  # Node is not imported"
    ),
    good=(
        "# launch/display.launch.py\n"
        "from launch_ros.actions import Node\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([Node(package='rviz2', executable='rviz2')])"
    ),
    summary="a launch file raises, fails to import, or runs past the time limit",
    explanation="`ros2 launch` would stop at the same place; nothing after it starts. What the file "
    "names literally (Node packages, package lookups, xacro, paths into a package's share folder) is "
    "still checked, statically, as it would be if the file loaded (each such finding says so). A warning "
    "when the file fails only launched on its own, and another launch file of its package includes "
    "it with launch arguments and it loads there (a file made to be included), or names it in a "
    "launch file pkgforge could not evaluate here (whether it loads there is not known).",
    hint="fix the line named in the message (run `pkgforge verify --explain-launch FILE` to see the "
    "resolved tree)",
)
def launch_load_error(ctx: CheckContext) -> Iterator[Finding]:
    for resolution in ctx.resolutions:
        alone = _loads_when_included(ctx, resolution)
        error = resolution.error
        if resolution.status != "ok" and error is not None and ctx.load_error_kind(resolution) == "load":
            if stopped_by_guard(resolution):
                continue  # launch-writes-files says what was refused, and that loading stopped there
            position = ctx.source_position(resolution, error.file, error.line)
            if position is None:
                position = (resolution.launch.source or resolution.launch.installed, None)
            hint = None
            text = str(error.message or "")
            text = untree(ctx, text)  # name the user's files, not pkgforge's tree
            if resolution.status == "timeout":
                message = f"{resolution.launch.installed.name} {text}"
                hint = (
                    "look for what runs at load time without end: a loop, a blocking call (input(), a "
                    "socket, a subprocess that waits), a sleep; if the machine is only busy, raise "
                    "--launch-timeout"
                )
            elif resolution.status == "crashed":
                message = f"{resolution.launch.installed.name}: {text}"
                hint = read_problem_hint(text) or (
                    "the file ended the process without a Python error: look for os._exit(), os.kill() "
                    "or a compiled extension it imports"
                )
            else:
                message = f"loading {resolution.launch.installed.name} failed: {text}"
                hint = (
                    read_problem_hint(text)
                    or _decoding_hint(resolution.launch.installed.name, error.type, text)
                    or _import_hint(text)
                )
                if hint is None and position[1] is None:
                    hint = (
                        "the error names no line of this file: run `pkgforge verify --explain-launch "
                        "FILE` to see how far it got"
                    )
                if unset := ctx.none_from_unset(resolution, text):
                    # dobot: os.getenv('DOBOT_TYPE') + '_robot.xacro' → 'None_robot.xacro' not found
                    yield Finding(
                        f"{message} (None in it: environment variable {' or '.join(unset)} is not set here)",
                        *position,
                        severity=Severity.WARNING,
                        hint=f"set {unset[0]} when you run verify (e.g. {unset[0]}=value pkgforge verify), "
                        "or give it a default",
                    )
                    continue
            if alone is not None:
                yield _failing_alone(f"{message}{alone[0]}", position, alone[1])
                continue
            refused = _refused_before(resolution)
            if refused is not None:
                # the file wrote somewhere only this sandbox refuses (/tmp where the kernel gives no
                # private one), then failed reading it back: ros2 launch would have let it write
                yield Finding(
                    f"{message} (after pkgforge refused its write at line {refused}: maybe its consequence)",
                    *position,
                    severity=Severity.WARNING,
                    hint="write generated files with tempfile (verify gives each launch file a private "
                    "TMPDIR), or pass the content directly",
                )
                continue
            yield Finding(message, *position, hint=hint)
        for item in resolution.errors:
            if item.configuration is not None:
                continue  # launch-configuration-undefined says it, at the substitution
            if item.type in SANDBOX_TYPES:
                continue  # launch-writes-files reports what the worker's guard refused
            if item.type == "PermissionError" and GUARD_MARKER in (item.message or ""):
                # an action stopped by the guard's refusal, which ROS does not make (Automatic
                # Addison's OpaqueFunction rewriting ros2_controllers.yaml): launch-writes-files
                continue
            if item.message.startswith("executed command") and "xacro" in item.message:
                continue  # xacro-error reports it with xacro's message
            if ctx.unpredicted_file(item.message) is not None:
                continue  # a file of a package whose install is not known (unpredicted-lookup)
            if ctx.package_not_installed_here(item):
                continue  # an included file's import: that file is evaluated, and reported, on its own
            if item.read_from:
                continue  # an OpaqueFunction read a file of a package not installed here (launch-unevaluated)
            if item.event_values:
                continue  # an event handler's action on the event's run-time values (launch-unevaluated)
            if absent := ctx.absent_include(item.message):
                # its own xacro.process_file(), or xacro run in a subprocess whose stderr an action
                # raised (amiga_ros2_gazebo's OpaqueFunction): model-unevaluated says it (ROS has the file)
                if absent[0] in ctx.model.manifest.declared():
                    continue
            if item.type == "XacroException" and undeclared_find(ctx, item.message):
                continue  # $(find X) of an undeclared package: missing-exec-depend names it in the model
            if item.type == "KeyError" and ctx.variable_unset_here(item.message):
                continue  # an included file's os.environ['X'] (turtlebot3_gazebo's TURTLEBOT3_MODEL):
                # that file is evaluated, and reported (launch-environment-unset), on its own
            if item.program:
                continue  # FindExecutable(name='ros2') not on PATH here (launch-unevaluated)
            if ctx.unset_variable(item):
                continue  # EnvironmentVariable('USER') not set here (launch-environment-unset)
            position = ctx.source_position(resolution, item.file, item.line)
            if position is not None and item.read_before:
                # loading read a package not installed here, the action failed on something empty
                # after: maybe that read's consequence, maybe its own defect (an error neither way)
                yield Finding(
                    f"{item.entity or 'an action'} failed: {item.type}: {_one_line(_shown_error(ctx, item))}"
                    f" (the file read files of {item.read_before}, not installed here, while loading: "
                    f"maybe the cause){_branch_note(item, resolution)}",
                    *position,
                    severity=Severity.WARNING,
                    hint=f"verify on a machine with {item.read_before} installed (or --install-base) to tell",
                )
                continue
            if (
                position is not None
                and alone is not None
                and item.file in (None, str(resolution.launch.installed))
            ):
                message = (
                    f"{item.entity or 'an action'} failed: {item.type}: {_one_line(_shown_error(ctx, item))}"
                )
                yield _failing_alone(f"{message}{alone[0]}", position, alone[1])
                continue
            if position is not None:
                yield Finding(
                    # (the tree's paths named as the user's before a long value is shortened)
                    f"{item.entity or 'an action'} failed: {item.type}: {_one_line(_shown_error(ctx, item))}"
                    f"{_branch_note(item, resolution)}",
                    *position,
                )


def _import_hint(text: str) -> str | None:
    """Where a launch name imported from the wrong module lives (FindPackageShare from
    launch.substitutions: it is launch_ros's)."""
    from pkgforge.checks.context import BUILTIN_IMPORT_ERROR, launch_name_home

    found = BUILTIN_IMPORT_ERROR.search(text)
    home = launch_name_home(found.group(1)) if found else None
    if found is None or home is None or found.group(0).endswith(f"'{home}'"):
        return None
    return f"import it from {home}: from {home} import {found.group(1)}"


def _shown_error(ctx: CheckContext, item: LaunchError) -> str:
    """An action's error message in the user's terms (a xacro failure as xacro_error shows it)."""
    return untree_xacro(ctx, item.message) if item.type == "XacroException" else untree(ctx, item.message)


def _loads_when_included(ctx: CheckContext, resolution: Resolution) -> tuple[str, str] | None:
    """(message note, hint) when another launch file of the package includes this one with launch
    arguments and evaluates it without an error there: a file made to be included (xarm's
    _robot_on_mbot_gazebo.launch.py, given moveit_config_dump by its includer) that fails only
    when launched on its own. `ros2 launch` of it alone fails too, but nobody launches it so."""
    installed = str(resolution.launch.installed)
    found = ctx.included_and_loaded(resolution)
    if found is not None:
        other, include = found
        includer = other.launch.source or other.launch.installed
        where = f"{includer.name}:{include.line}" if include.line else includer.name
        declared = {argument.name for argument in resolution.arguments}
        given = ", ".join(sorted(set(include.arguments) - declared))
        return (
            f" (launched on its own; {where} includes it with {given} and it loads there)",
            f"launch it through {includer.name}, or give its launch arguments defaults it runs with",
        )
    # an includer pkgforge could not evaluate here (its imports are not installed): it names the
    # file literally; whether the file loads there is unknown, so its failure alone is no error
    own = (ctx.model.share_name, ctx.model.name)
    for source, references in sorted(ctx.static_fallback().items()):
        if ctx.failed_to_load(source) is not None:
            continue  # an includer that does not load itself is no place this file loads in
        for reference in references:
            if (
                source != resolution.launch.source
                and reference.package in own
                and reference.relative
                and installed.endswith(f"/share/{ctx.model.share_name}/{reference.relative.strip('/')}")
            ):
                return (
                    f" (launched on its own; {source.name}:{reference.line} includes it and could "
                    "not be evaluated here: whether it loads there is not known)",
                    f"verify where {source.name} can be evaluated (its dependencies installed, or "
                    "--install-base), or give this file's launch arguments defaults it runs with",
                )
    return None


def _refused_before(resolution: Resolution) -> int | None:
    """The line of a write the sandbox refused, in the failing file, at or before the line it failed at
    (or by a process it started): the failure may be that write's consequence, not the file's."""
    error = resolution.error
    if error is None or error.line is None:
        return None
    for kind, _, _, _, item in sandbox_records(resolution):
        if (
            kind == "RefusedWrite"
            and item.file == error.file
            and item.line is not None
            and item.line <= error.line
        ):
            return item.line
    return None


def _decoding_hint(file_name: str, error_type: str | None, text: str) -> str | None:
    """The fix for a launch file ros2 launch cannot decode (None: another error). Python reads a
    launch file's bytes as UTF-8 (PEP 263) but in comments, unless it declares its coding; launch
    reads an XML or YAML file as UTF-8 text, whatever a BOM or an XML declaration says."""
    if file_name.endswith(".py"):
        if "cannot contain null bytes" in text:
            return "save the file as UTF-8: Python refuses a NUL byte (a UTF-16 file has one in each ASCII character)"
        if error_type == "SyntaxError" and "(unicode error) 'utf-8' codec can't decode" in text:
            return (
                "save the file as UTF-8, or declare its encoding on its first or second line "
                "(# -*- coding: latin-1 -*-): Python reads a launch file as UTF-8 but in comments"
            )
        return None
    if error_type == "UnicodeDecodeError":
        return (
            "save the file as UTF-8: ros2 launch reads XML and YAML launch files as UTF-8, whatever "
            "a BOM or an encoding declaration says"
        )
    return None


def _failing_alone(message: str, position: tuple[Path, int | None], hint: str) -> Finding:
    return Finding(message, *position, severity=Severity.WARNING, hint=hint)


def _one_line(message: str) -> str:
    """An error's message on one line: a long quoted value (a whole xacro output that launch_ros
    could not read as YAML) shortened to its start."""
    import re

    # (a path is kept whole: the report shows it in the user's terms, and its end is the file)
    def shorten(match: re.Match[str]) -> str:
        value = match.group(1)
        if value.startswith("/") and "\n" not in value:
            return match.group(0)
        return f"'{value[:60]}...'"

    # a quote opens after a blank or a bracket and closes before one: an apostrophe inside the
    # value (a comment's "humble's" in a URDF) neither opens nor closes it
    message = re.sub(r"(?:^|(?<=[\s(\[=]))'(.{80,}?)'(?=[\s,.:;)\]]|$)", shorten, message, flags=re.S)
    return " ".join(part.strip() for part in message.splitlines() if part.strip())


def _share_reference(ctx: CheckContext, path: str) -> tuple[str, str, Path] | None:
    located = ctx.tree.locate(path) if ctx.tree is not None else None
    if located is None or ctx.tree is None or ctx.tree.is_phantom(path):
        return None
    return located


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


def _looked_up(ctx: CheckContext) -> Iterator[Use]:
    """(package name, source path, line, how, item, resolution) for every package a launch file uses."""
    for resolution in ctx.resolutions:
        for item in resolution.packages:
            position = ctx.source_position(resolution, item.file, item.line)
            if position is not None:
                yield item.name, position[0], position[1], item.via, item, resolution
        for include in resolution.includes:
            located = _share_reference(ctx, include.path) or (
                ctx.tree.locate(include.path) if ctx.tree is not None else None
            )
            position = ctx.source_position(resolution, include.file, include.line)
            if located is not None and position is not None:
                yield located[0], position[0], position[1], "included launch file", include, resolution
        error = resolution.error
        if resolution.status == "load-error" and error is not None and error.package:
            position = ctx.source_position(resolution, error.file, error.line)
            if position is not None:
                yield (
                    error.package,
                    position[0],
                    position[1],
                    "lookup",
                    PackageLookup(found=False),
                    resolution,
                )
    for references in ctx.static_fallback().values():
        for reference in references:
            yield reference.package, reference.path, reference.line, reference.via, None, None
    # models: $(find pkg) and package://pkg, as written and as xacro expanded them
    for reference in ctx.model.references:
        if reference.via in ("package://", "$(find)") and reference.path.name.endswith(ANY_MODEL_SUFFIXES):
            yield reference.package, reference.path, reference.line, reference.via, None, None
        elif reference.via == "rviz plugin":
            yield reference.package, reference.path, reference.line, "RViz display from", None, None
    for result in ctx.model_results:
        for mesh in result.robot["meshes"] if result.robot else []:
            if mesh["uri"].startswith("package://"):
                package = mesh["uri"][len("package://") :].split("/")[0]
                own = ctx.own_source(mesh.get("file") or "")
                # a mesh written in another package's file: this model's file, no line. Another
                # package's model (run by this package's launch file) needs its meshes' packages
                # itself: its own verification names them (andino_navigation runs
                # andino_gz_classic's model, whose meshes are andino_description's)
                if own:
                    yield package, own, mesh.get("line"), "package://", None, None
                elif result.source is not None:
                    yield package, result.source, None, "package://", None, None
    # a Python launch file that imports a ROS package's module needs that package at run time
    evaluated = {r.launch.source for r in ctx.resolutions if r.status == "ok" and r.launch.source}
    for reference in ctx.model.references:
        if (
            reference.via == "import"
            and reference.path in evaluated
            and reference.package not in LAUNCH_INFRASTRUCTURE
        ):
            yield reference.package, reference.path, reference.line, "import of", None, None


@register(
    "PF304",
    "unknown-package",
    "error",
    area="launch",
    bad=(
        "# launch/display.launch.py (the package is rob_description)\nFindPackageShare('robot_description')"
    ),
    good=("# launch/display.launch.py\nFindPackageShare('rob_description')"),
    summary="a launch file looks up a package that exists nowhere",
    explanation="The package is not in the workspace, not declared in package.xml, not "
    "installed and released in no active ROS 2 distro: almost always a typo or a "
    "package renamed (`robot_description` looked up where your package is named "
    "`rob_description`). Used only with argument "
    "settings other than the defaults, it is a warning: more likely an optional driver the "
    "robot's users build from source.",
    hint="fix the package name; if it is a package built from source (not released), add it to "
    "the workspace (or its .repos file) and declare it",
)
def unknown_package(ctx: CheckContext) -> Iterator[Finding]:
    if not ctx.model.manifest.valid:
        return  # with no readable manifest, nothing is known to be declared
    known = ctx.known_packages()
    nested = ctx.nested_packages()
    # a file checked statically: a lookup in a `try:` that handles its failure is optional, as in
    # ROS; a package evaluation already found missing in the file is that finding (one per cause)
    static = {(r.package, r.path, r.line): r for refs in ctx.static_fallback().values() for r in refs}
    guarded = {key for key, r in static.items() if r.guarded}
    evaluated: set[tuple[str, str]] = set()
    seen = set()
    for name, path, line, via, item, resolution in _looked_up(ctx):
        if name in known or (name, str(path), line) in seen or via in STATIC_ONLY_FOR_DEPENDENCIES:
            continue
        if resolution is None and ((name, path, line) in guarded or (name, str(path)) in evaluated):
            continue
        if resolution is not None:
            evaluated.add((name, str(path)))
        unset = ctx.none_from_unset(resolution, name) if resolution is not None else []
        if name in nested and path.is_relative_to(nested[name]):
            continue  # a template package's own files name it
        if not name or (
            resolution is not None
            and EMPTY_PART.search(name)
            and any(a.default == "" for a in resolution.arguments)
        ):
            continue  # built from a launch argument left empty (a template's caller gives it): no typo
        seen.add((name, str(path), line))
        message = (
            f"package '{name}' ({via}) is not in the workspace, not declared in package.xml "
            f"and released in no ROS 2 distro{static_note(ctx, path, item)}"
        )
        only = resolution.off_default(item) if resolution is not None and item is not None else []
        if unset:
            # dobot: get_package_share_directory(os.getenv('DOBOT_TYPE') + '_moveit') → 'None_moveit'
            yield Finding(
                f"{message} (None in it: environment variable {' or '.join(unset)} is not set here)",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"set {unset[0]} when you run verify (e.g. {unset[0]}=value pkgforge verify), "
                "or give it a default",
            )
            continue
        reference = static.get((name, path, line or 0)) if resolution is None else None
        branch = reference.python_branch if reference is not None else None
        if branch is not None and ctx.branch_on_distros(branch) is None:
            # a file read statically: used in one if/else branch of it, which runs is not known
            # (select_slam_launch.py's hector_mapping, started only when the user picks 3)
            yield Finding(
                f"{message} (only in the branch `{branch}`)",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"{_unknown_hint(ctx, name)}; if it is built from source, list it in a .repos file",
            )
            continue
        if not only:
            # one package named by many nodes or lookups of a file: one diagnostic naming them
            yield Finding(
                message,
                path,
                line,
                hint=_unknown_hint(ctx, name),
                group=Group(
                    f"unknown {name}",
                    via,
                    f"package '{name}' ({{items}}) is not in the workspace, not declared in package.xml "
                    "and released in no ROS 2 distro",
                ),
            )
            continue
        # used only with settings other than the defaults (linorobot2's sensor:=xv11 runs
        # xv_11_driver, which its users clone from source): more likely an optional driver built
        # from source than a typo
        note, detail = only_with(only)
        yield Finding(
            f"{message}{note}",
            path,
            line,
            severity=Severity.WARNING,
            hint=f"{_unknown_hint(ctx, name)}; if it is built from source, list it in a .repos file",
            detail=detail,
        )


class _OptionalUse(NamedTuple):
    """A model's use of a package that package.xml may leave out on purpose: where it stands, and
    when to declare the package all the same (the hint)."""

    where: str
    when: str


def _optional_use(ctx: CheckContext, reference: Reference, read: set[Path] | None) -> _OptionalUse | None:
    """Whether a model's reference, as written, is needed only in some uses of the package:
    inside an <xacro:if>/<xacro:unless> that does not hold at the defaults (franka's
    $(find franka_gazebo_bringup) under gazebo:=true; franka_gazebo_bringup depends on
    franka_description), or in a model file no robot model of the package reads (husky's
    urdf/accessories/sick_lms1xx_mount.urdf.xacro and its $(find lms1xx)). `read`: the package's
    files its models read, None when not known."""
    if reference.guarded:
        # a file checked statically: its `try:` handles the package's absence (an optional driver)
        return _OptionalUse(
            "inside a `try:` of a launch file checked statically that handles its absence,",
            "if the package's users need what it adds",
        )
    if reference.python_branch is not None and ctx.branch_on_distros(reference.python_branch) is None:
        # a file checked statically (not evaluated here): which branch runs is unknown (a branch
        # on $ROS_DISTRO every target distro takes is no option)
        return _OptionalUse(
            f"in the branch `{reference.python_branch}` of a launch file not evaluated here,",
            "if the package's users run that branch",
        )
    if reference.condition is not None:
        kind, _, value = reference.condition.partition(" ")
        return _OptionalUse(
            f'inside <xacro:{kind} value="{value}">',
            f"if the model is used with that setting (leave it out when {reference.package} "
            "itself depends on this package)",
        )
    if (
        reference.via in ("$(find)", "package://")
        and read is not None
        and reference.path.name.endswith(XACRO_MODEL_SUFFIXES)
        and reference.path not in read
    ):
        return _OptionalUse(
            f"in {ctx.relative(reference.path)}, which no robot model of {ctx.model.name} reads,",
            "if the file is meant to be included (an accessory for other packages' models), "
            "or remove the file",
        )
    return None


def _unknown_hint(ctx: CheckContext, name: str) -> str:
    """The package's ROS 2 name, or close names from the workspace, package.xml and the distros."""
    from pkgforge.model.distro_data import load, replacement

    renamed = replacement(name)
    if renamed is not None:
        return f"use {renamed[0]}: {renamed[1]}"
    own = ctx.model.manifest.name or ctx.model.name
    if name == ctx.model.path.name and name != own:
        return (
            f"'{name}' is the name of the folder; the package is named '{own}' (package.xml "
            f"<name>), and lookups use that: write '{own}', or rename one to match the other"
        )
    ignored = ctx.ignored_packages().get(name)
    if ignored is not None:
        folder, marker = ignored
        base = ctx.workspace_base or folder.parent
        where = (
            f"its folder {folder.relative_to(base)} holds"
            if marker.parent == folder
            else f"its folder {folder.relative_to(base)} is inside {marker.parent.relative_to(base)}, which holds"
        )
        return f"{where} a {marker.name}, so colcon does not build it: delete that file to build it, or drop the lookup"
    # candidates are package names only: a folder's name is no package (the lookup of a folder
    # named unlike its package is this very mistake), and never the wrong name itself
    candidates = sorted((set(ctx.workspace) | ctx.model.manifest.declared() | {own}) - {name})
    near = difflib.get_close_matches(name, candidates, n=3, cutoff=0.5)
    near += [n for n in load().close_names(name, n=3) if n not in near and n != name]
    return f"did you mean {', '.join(near[:3])}?" if near else "check the name against package.xml <name>"


@register(
    "PF305",
    "missing-exec-depend",
    "error",
    area="launch",
    fix="safe",
    bad=(
        "# launch/display.launch.py (package.xml has no exec_depend on rviz2)\n"
        "Node(package='rviz2', executable='rviz2')"
    ),
    good=("<!-- package.xml -->\n<exec_depend>rviz2</exec_depend>"),
    summary="a package used at run time is not an exec_depend",
    explanation="rosdep and binary packages install only what package.xml declares: on a fresh "
    "machine, your package's node, file or tool is missing. A model's use that xacro reads "
    "only inside <xacro:if>/<xacro:unless>, or in a model file no robot model of the package "
    "reads (an accessory for others to include), is a warning, with no fix: such a package is often left out on purpose (a "
    "simulation package that itself depends on the description). A package that depends on "
    "this one already gets a warning with no fix too (declaring it back is a cycle colcon "
    "refuses). A package a declared one brings along (spot_description brings robot_state_"
    "publisher) is installed on a fresh machine all the same: a warning, with the fix. A launch "
    "file's use of a viewer (rviz2, rqt, joint_state_publisher_gui, plotjuggler) only with argument "
    "settings other than the defaults (rviz:=true, default false) is a warning with an unsafe fix "
    "(--unsafe-fixes declares it): a headless robot leaves RViz out on purpose; any other package such a setting needs (the "
    "simulator under sim:=true) stays an error, with the setting named. A use in one if/else "
    "branch of a launch file pkgforge could not evaluate is a warning too (which branch runs is "
    "unknown: turtlebot3's lidar driver by $LDS_MODEL), and, in a test package (dsr_tests) or "
    "under test/, a package declared only as <test_depend>. With no target distro stated, a "
    "package that has a successor and is released for older distros only (gazebo_ros: humble) "
    "gets no fix: the hint names the successor.",
    hint="declare it with <exec_depend>",
)
def missing_exec_depend(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    if not model.manifest.valid:
        return  # with no readable manifest, nothing is known to be declared
    # a <build_export_depend> is installed with the package too (rosdep installs every kind,
    # bloom puts it in the binary's Depends): stretch_calibration declares stretch_core so
    declared = {d.name for d in model.manifest.active_dependencies() if d.tag in EXPORT_TAGS}
    tested = {d.name for d in model.manifest.active_dependencies() if d.tag == "test_depend"} - declared
    own = {model.name, model.share_name}
    known = ctx.real_packages()
    # a model's reference as written (not as xacro made it), for the uses a package may leave out
    written: dict[tuple[str, Path, int | None], Reference] = {
        (r.package, r.path, r.line): r for r in model.references
    }
    read = ctx.model_files_read()
    chosen: dict[str, tuple[Use, _OptionalUse | None]] = {}
    # a use needed whatever the settings first, then one with a line, then one of a file that
    # loads (one read statically because it does not load is the same defect, said less surely):
    # where the diagnostic points
    for use in sorted(
        _looked_up(ctx),
        key=lambda x: (x[0], x[2] is None, read_as_failed(ctx, x[1], x[4]), str(x[1]), x[2] or 0),
    ):
        name, path, line, via, item, _ = use
        if name in own or name in declared or name not in known or name in LAUNCH_INFRASTRUCTURE:
            continue
        if name in RVIZ_BUILTIN and (via == "RViz display from" or "rviz2" in declared):
            continue  # rviz2 depends on them
        reference = written.get((name, path, line)) if item is None else None
        optional = _optional_use(ctx, reference, read) if reference is not None else None
        if name not in chosen or (chosen[name][1] is not None and optional is None):
            chosen[name] = use, optional
    for (name, path, line, via, item, resolution), optional in chosen.values():
        if optional is not None:
            yield Finding(
                f"{via} '{name}' is used only {optional.where} but package.xml does not declare it",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"add <exec_depend>{name}</exec_depend> {optional.when}",
            )  # no fix: only the user knows whether that use is meant for this package's users
            continue
        note = _branch_note(item, resolution) if resolution is not None and item is not None else ""
        note += static_note(ctx, path, item)
        written_use = written.get((name, path, line)) if item is None else None
        if written_use is not None and written_use.launch_condition and path in ctx.static_fallback():
            # a file checked statically: its action given a condition= off at the defaults
            note = f" (only with condition={written_use.launch_condition})"
        if name in ctx.workspace and ctx.depends_on(name, model.name):
            # (husky_description's xacro finds husky_control, which depends on husky_description)
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}; "
                f"{name} depends on {model.name}, so declaring it here makes a cycle colcon refuses",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"install {name} beside {model.name} (its users have it), or move the use into {name}",
            )  # no fix: the dependency the hint would add breaks the build
            continue
        provider = ctx.brought_along(name, EXPORT_TAGS)
        if provider is not None:
            # spot_ros2_control exec_depends spot_description, which exec_depends rviz2: installed
            # with it, the launch file runs; declaring what it uses directly is still the rule
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}; "
                f"{provider}, which it declares, brings it along",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"add <exec_depend>{name}</exec_depend> to package.xml",
                fix={"dependency": name, "tag": "exec_depend", "manifest": str(model.manifest.path)},
            )
            continue
        if name in tested and _for_tests(model, path):
            # Doosan's dsr_tests: launch files its own tests start, their packages declared as
            # <test_depend> (rosdep installs those for a source build): right if only the tests
            # launch them. A released binary does not bring test dependencies: elsewhere, an error
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml declares it only as <test_depend>{note}",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"if the launch file runs outside the package's tests, make it <exec_depend>{name}</exec_depend>",
            )
            continue
        if (
            note
            and resolution is not None
            and item is not None
            and resolution.off_default(item)
            and _viewer(name)
        ):
            # kobuki_description's rviz2 under rviz:=true (default false): a headless robot leaves
            # it out on purpose, as unknown-package and package-not-in-distro already allow
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"add <exec_depend>{name}</exec_depend> if the package's users launch it with that setting",
                # unsafe: only the user knows whether that setting is meant for this package's users
                fix={
                    "dependency": name,
                    "tag": "exec_depend",
                    "manifest": str(model.manifest.path),
                    "unsafe": True,
                },
            )
            continue
        only_tests = (
            "; it declares it only as <test_depend>, which a released binary does not bring"
            if name in tested
            else ""
        )
        superseded = _superseded(ctx, name)
        if superseded is not None:
            # gazebo_ros with no target distro stated: declaring it is right on humble only, and
            # pkgforge cannot tell whether the package targets humble; the fix would pin it there
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}{only_tests}",
                path,
                line,
                hint=superseded,
            )
            continue
        yield Finding(
            f"{via} '{name}' is used at run time but package.xml does not declare it{note}{only_tests}",
            path,
            line,
            hint=f"add <exec_depend>{name}</exec_depend> to package.xml"
            + (
                f" (after line {model.manifest.last_dependency_line()})"
                if model.manifest.last_dependency_line()
                else ""
            ),
            fix={"dependency": name, "tag": "exec_depend", "manifest": str(model.manifest.path)},
        )


def _superseded(ctx: CheckContext, name: str) -> str | None:
    """The hint, without a fix, for a package with a successor (distro_data.replacement) that is
    not released for every active distro its successor is, when no target distro is stated:
    `fix` would add gazebo_ros, released for humble only, to a package that may target jazzy. With
    a target, a name not released for it is package-not-in-distro's, never a fix's."""
    if ctx.distros or name in ctx.workspace:
        return None
    from pkgforge.model.distro_data import load, replacement

    better = replacement(name)
    if better is None:
        return None
    data = load()
    released = data.released_in(name)
    elsewhere = [d for d in data.released_in(better[0]) if d not in released]
    if not released or not elsewhere:
        return None
    return (
        f"use {better[0]} instead ({better[1]}); or, for a package that targets "
        f"{' or '.join(released)} only, add <exec_depend>{name}</exec_depend> to package.xml and "
        f'say so in pkgforge.toml ([verify] distro = "{released[0]}")'
    )


def _for_tests(model: PackageModel, path: Path) -> bool:
    """Whether a launch file is its package's tests' own: under a test/ folder, or in a package
    named for tests (dsr_tests, *_test, *_testing)."""
    try:
        parts = path.relative_to(model.path).parts
    except ValueError:
        parts = ()
    return any(part in ("test", "tests") for part in parts[:-1]) or model.name.endswith(
        ("_test", "_tests", "_testing")
    )


# tools a person looks through, which a headless robot's package leaves out on purpose
VIEWERS = frozenset({"joint_state_publisher_gui", "plotjuggler", "foxglove_bridge", "rviz2", "rqt_gui"})


def _viewer(name: str) -> bool:
    return name in VIEWERS or name.startswith(("rqt_", "rviz_"))


def _read_as_is_by_rsp(ctx: CheckContext, resolution: Resolution, argument: str) -> bool:
    """Whether a plain model file (no xacro in it) is, as it is, what robot_state_publisher gets
    as robot_description in the same launch file: ros_gz_project_template's rrbot_setup.launch.py
    reads model.sdf into robot_description and hands the same file to joint_state_publisher_gui,
    which reads it as robot_state_publisher does (main's description_file; <sdf> too)."""
    if not os.path.isabs(argument):
        return False  # the node opens it from where it is started: nothing to compare
    head = ctx.text_head(argument)
    if not head or "xmlns:xacro" in head or "<xacro:" in head:
        return False
    if any(
        node.package == "robot_state_publisher" and argument in node.arguments for node in resolution.nodes
    ):
        # robot_state_publisher given the same file on its command line reads it as it is (argv[1]:
        # robot_state_publisher.cpp; rsp-model-argument says to pass it as a parameter instead)
        return True
    return any(
        parameter.name == "robot_description"
        and parameter.form in ("plain", "typed-str")
        and parameter.value_preview
        and head[: len(parameter.value_preview)] == parameter.value_preview
        and len(parameter.value_preview) == min(len(head), PREVIEW_LENGTH)
        for node in resolution.nodes
        if node.package == "robot_state_publisher"
        for parameter in node.parameters
    )


@register(
    "PF306",
    "jsp-model-argument",
    "error",
    area="launch",
    fix="safe",
    bad=(
        "# launch/display.launch.py\n"
        "Node(package='joint_state_publisher_gui', executable='joint_state_publisher_gui',\n"
        "     arguments=[model])"
    ),
    good=(
        "# launch/display.launch.py\n"
        "Node(package='joint_state_publisher_gui', executable='joint_state_publisher_gui')"
    ),
    summary="joint_state_publisher is given the robot model as an argument",
    explanation="Copied from older tutorials: joint_state_publisher(_gui) then parses the file "
    "itself, unexpanded (links go missing, the TF tree breaks). It reads "
    "/robot_description from robot_state_publisher. A plain .urdf or .sdf file whose text the "
    "launch file also gives robot_state_publisher as it is (not through xacro), as its "
    "robot_description or on its command line, is read the same way by both: no finding.",
    hint="remove the model from the node's arguments",
)
def jsp_model_argument(ctx: CheckContext) -> Iterator[Finding]:
    seen = set()
    for resolution in ctx.resolutions:
        for node in resolution.nodes:
            if node.package not in JSP_PACKAGES:
                continue
            # a xacro file: parsed as URDF by the node itself, unexpanded. A plain .urdf or .sdf it
            # reads as robot_state_publisher does (main's description_file; configure_robot takes
            # <sdf> too: ros_gz_project_template's rrbot_setup.launch.py): no harm done
            models = [
                a
                for a in node.arguments
                if str(a).endswith(ANY_MODEL_SUFFIXES) and not _read_as_is_by_rsp(ctx, resolution, str(a))
            ]
            position = ctx.source_position(resolution, node.file, node.line)
            if models and position is not None and position not in seen:
                seen.add(position)
                yield Finding(
                    f"{node.package} is given {Path(models[0]).name} in arguments; it reads "
                    f"/robot_description instead{_branch_note(node, resolution)}",
                    *position,
                    hint=f"remove arguments=[...] from the {node.package} node: "
                    "robot_state_publisher publishes /robot_description",
                )


@register(
    "PF307",
    "robot-description-not-string",
    "warning",
    area="launch",
    fix="safe",
    bad=("# launch/display.launch.py\nparameters=[{'robot_description': Command(['xacro ', model])}]"),
    good=(
        "# launch/display.launch.py\n"
        "parameters=[{'robot_description': ParameterValue(Command(['xacro ', model]), value_type=str)}]"
    ),
    summary="robot_description comes from Command() without ParameterValue(..., value_type=str)",
    explanation="launch_ros parses a parameter's text as YAML; the xacro output then fails to "
    "load whenever it looks like YAML (since Jazzy launch refuses it).",
    hint="wrap it: ParameterValue(Command([...]), value_type=str)",
)
def robot_description_not_string(ctx: CheckContext) -> Iterator[Finding]:
    for resolution in ctx.resolutions:
        if resolution.launch.installed.suffix != ".py":
            continue
        for node in resolution.nodes:
            if node.package != "robot_state_publisher":
                continue
            for parameter in node.parameters:
                if parameter.name == "robot_description" and parameter.form == "command-untyped":
                    position = ctx.source_position(resolution, parameter.file, parameter.line)
                    if position is not None:
                        yield Finding(
                            "robot_description is a Command() that launch_ros will parse as YAML", *position
                        )


@register(
    "PF309",
    "launch-argument-required",
    "info",
    area="launch",
    bad=("# launch/display.launch.py\nDeclareLaunchArgument('model')"),
    good=("# launch/display.launch.py\nDeclareLaunchArgument('model', default_value='robot.urdf.xacro')"),
    summary="a launch argument has no default, and no value was given",
    explanation="What depends on it is skipped, not guessed. Give a value with "
    "--launch-arg name:=value to check it.",
    hint="pass --launch-arg NAME:=VALUE, or give the argument a default",
)
def launch_argument_required(ctx: CheckContext) -> Iterator[Finding]:
    seen = set()
    for resolution in ctx.resolutions:
        for item in resolution.required:
            if item.skipped is not None:
                continue
            position = ctx.source_position(resolution, item.file, item.line)
            if position is not None and (item.name, position) not in seen:
                seen.add((item.name, position))
                yield Finding(
                    f"launch argument '{item.name}' has no default and no value",
                    *position,
                    group=Group(
                        "required",
                        item.name,
                        "{count} launch arguments have no default and no value: {items}",
                    ),
                )


@register(
    "PF320",
    "launch-configuration-undefined",
    "error",
    area="launch",
    bad=(
        "# launch/robot.launch.py (nothing declares use_sim_time)\n"
        "Node(package='robot_state_publisher', executable='robot_state_publisher',\n"
        "     parameters=[{'use_sim_time': LaunchConfiguration('use_sim_time')}])"
    ),
    good=(
        "# launch/robot.launch.py\n"
        "DeclareLaunchArgument('use_sim_time', default_value='false'),\n"
        "Node(package='robot_state_publisher', executable='robot_state_publisher',\n"
        "     parameters=[{'use_sim_time': LaunchConfiguration('use_sim_time')}])"
    ),
    summary="a launch file uses a launch configuration that nothing declares or sets",
    explanation="LaunchConfiguration('x') (XML/YAML `$(var x)`) with no default, where no "
    "DeclareLaunchArgument, SetLaunchConfiguration (`<let>`), include argument or --launch-arg has "
    'given x a value when the action is executed: `ros2 launch` stops with "launch configuration '
    "'x' does not exist\" (exit 1). Typical of a file copied from another that declared "
    "use_sim_time. An argument declared in an included file counts after the include (unless a "
    "scoped GroupAction holds it), and a declared argument without a default is launch-argument-"
    "required's. A TimerAction's actions and an event handler's run after the whole launch "
    "description: a configuration a scoped GroupAction (or an include in one) set is gone by then "
    "(ros2/launch#825). A warning when the file fails only launched on its own, and another launch "
    "file of its package includes it where the configuration is set (a file made to be included); "
    "info when a launch file included before the use could not be evaluated here (its package not "
    "installed): it may declare the configuration.",
    hint="declare it with DeclareLaunchArgument('x', default_value=...) or give "
    "LaunchConfiguration('x', default=...)",
)
def launch_configuration_undefined(ctx: CheckContext) -> Iterator[Finding]:
    # (an included file's use fails in its own resolution and in its includer's: said once)
    found: dict[tuple[Path, int | None, str], list[tuple[Resolution, LaunchError]]] = {}
    for resolution in ctx.resolutions:
        for item in resolution.errors if resolution.status == "ok" else []:
            if item.configuration is None:
                continue
            position = ctx.source_position(resolution, item.file, item.line)
            if position is not None:
                found.setdefault((*position, item.configuration), []).append((resolution, item))
    for (path, line, name), uses in found.items():
        certain = [(r, i) for r, i in uses if i.unevaluated_include is None]
        resolution, item = (certain or uses)[0]
        if not certain:  # an include before it could not be evaluated: it may declare the name
            yield Finding(
                f"launch configuration '{name}' is not set when {_a(item.entity or 'action')} uses it, "
                f"unless {_included_name(item.unevaluated_include)}, included before it and not "
                f"evaluated here, declares it (if not, `ros2 launch` stops here){_branch_note(item, resolution)}",
                path,
                line,
                severity=Severity.INFO,
                hint="verify where the included file's package is installed (--install-base) to tell, or "
                + _declare_hint(path, name, item),
            )
            continue
        uses = certain
        alone = [(r, i) for r, i in uses if i.file in (None, str(r.launch.installed))]
        message = _unset_message(name, item, resolution)
        if len(alone) == len(uses) and (includer := _set_by_includer(ctx, resolution, item)) is not None:
            yield Finding(
                f"{message}, when {resolution.launch.installed.name} is launched on its own; {includer}",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"launch it through its includer, or {_declare_hint(path, name, item)}",
            )
            continue
        if not alone:  # only through another launch file of the package
            message += f" (launched through {resolution.launch.installed.name})"
        yield Finding(message, path, line, hint=_declare_hint(path, name, item))


def _unset_message(name: str, item: LaunchError, resolution: Resolution) -> str:
    message = (
        f"launch configuration '{name}' does not exist when {_a(item.entity or 'action')} uses it: nothing "
        f"declares, sets or defaults it, so `ros2 launch` stops here{_branch_note(item, resolution)}"
    )
    if item.deferred:
        # (said in few words: the message is one line of at most 300 characters)
        runs = "when its period has passed" if item.deferred == "TimerAction" else "when its event comes"
        if item.scoped_away:
            message += (
                f" (in {_a(item.deferred)}, run {runs}: {name} is set where the {item.deferred} stands, "
                "but the scoped GroupAction around it has ended by then)"
            )
        else:
            message += (
                f" (in {_a(item.deferred)}: its actions run {runs}, after the rest of the launch description)"
            )
    return message


def _included_name(path: str | None) -> str:
    """An included launch file as its package names it (`pkg/launch/x.launch.py`)."""
    if not path:
        return "a launch file"
    return path.rsplit("/share/", 1)[-1] if "/share/" in path else os.path.basename(path)


def _a(word: str) -> str:
    return f"{'an' if word[:1].lower() in 'aeiou' else 'a'} {word}"


def _declare_hint(path: Path, name: str, item: LaunchError) -> str:
    if path.name.endswith(".xml"):
        hint = f'declare it with <arg name="{name}" default="..."/> or give $(var {name} DEFAULT)'
    elif path.name.endswith((".yaml", ".yml")):
        hint = f"declare it with `- arg: {{name: {name}, default: ...}}` or give $(var {name} DEFAULT)"
    else:
        hint = (
            f"declare it with DeclareLaunchArgument('{name}', default_value=...) or give "
            f"LaunchConfiguration('{name}', default=...)"
        )
    hint += f" (without either, only `ros2 launch ... {name}:=VALUE` runs it)"
    if item.scoped_away:
        hint += f"; or set {name} outside the scoped GroupAction (or make it scoped=False)"
    return hint


def _set_by_includer(ctx: CheckContext, resolution: Resolution, item: LaunchError) -> str | None:
    """How another launch file of the package includes this one where `item`'s configuration is
    set (it evaluated this file without that failure), else None: a file made to be included
    (nav2-style robot_state_publisher.launch.py, given use_sim_time by its bringup)."""
    installed = str(resolution.launch.installed)
    for other in ctx.resolutions:
        if other is resolution or other.status != "ok" or installed not in other.files:
            continue
        if any(
            e.configuration == item.configuration and e.file == item.file and e.line == item.line
            for e in other.errors
        ):
            continue  # it fails there too
        include = next((i for i in other.includes if i.path == installed), None)
        includer = (other.launch.source or other.launch.installed).name
        if include is not None and include.file:  # (the include may stand in a file it includes)
            includer = Path(include.file).name
        where = f"{includer}:{include.line}" if include is not None and include.line else includer
        given = include is not None and item.configuration in include.arguments
        how = f"with {item.configuration}:=..." if given else f"where {item.configuration} is set"
        return f"{where} includes it {how}, and it runs there"
    return None


@register(
    "PF310",
    "unsupported-launch-api",
    "info",
    area="launch",
    bad=("# launch/display.launch.py\nlog_dir = LaunchLogDir()"),
    good=("# launch/display.launch.py\n# (nothing to fix: check this part by running the launch file)"),
    summary="a launch file uses a real launch API that pkgforge does not evaluate",
    explanation="The construct is recorded and skipped; what it would do is not checked.",
    hint="nothing to fix; check this part by running the launch file",
)
def unsupported_launch_api(ctx: CheckContext) -> Iterator[Finding]:
    seen = set()
    for resolution in ctx.resolutions:
        # a run-time only Command (launch/records.runs_at_verify_time) is not run: said once, as info
        runtime = [
            (f"Command '{' '.join(c.command[:3])}' (run-time only)", c)
            for c in resolution.commands
            if c.runtime_only
        ]
        for name, item in [(u.name, u) for u in resolution.unsupported] + runtime:
            position = ctx.source_position(resolution, item.file, item.line)
            if position is not None and (name, position) not in seen:
                seen.add((name, position))
                yield Finding(f"{name} is not evaluated by pkgforge", *position)
        newer = ctx.newer_launch_name(resolution)
        error = resolution.error
        if newer is not None and ctx.load_error_kind(resolution) == "newer-api" and error is not None:
            position = ctx.source_position(resolution, error.file, error.line) or (
                resolution.launch.source or resolution.launch.installed,
                None,
            )
            yield Finding(
                f"{resolution.launch.installed.name} imports {newer}, which pkgforge's built-in "
                "engine knows only in ROS 2 releases after Jazzy (or not at all); checked "
                "statically instead",
                *position,
                hint="give --distro humble or jazzy if the package targets one (then a missing "
                "name is ROS's ImportError too), or verify where that distro is installed",
            )


@register(
    "PF311",
    "launch-unevaluated",
    "info",
    area="launch",
    bad=(
        "# launch/bringup.launch.py (nav2_common is declared, not installed here)\n"
        "from nav2_common.launch import RewrittenYaml"
    ),
    good="$ pkgforge verify . --install-base install   # on a machine with nav2_common installed",
    summary="a launch file imports a module of a ROS package, reads its files (or runs a program) "
    "not installed here",
    explanation="Not the launch file's fault: the package (or a program it runs while loading, "
    "such as ros2, or one an action finds on PATH with FindExecutable) is simply not on this "
    "machine. A file that reads a declared package's files "
    "while loading (the MoveIt tutorials' load_yaml) and fails on what it did not find (None "
    "from its own `except EnvironmentError`) is this too: where the package is installed, the "
    "files are there. Its "
    "literal package and path references are still checked, statically; a package it does not "
    "declare is missing-exec-depend's.",
    hint="verify on a machine with the dependency installed (or --install-base) to evaluate it",
)
def launch_unevaluated(ctx: CheckContext) -> Iterator[Finding]:
    said: set[tuple[Path, int | None, str]] = set()  # (an included file's action: said once, at its line)
    for resolution in ctx.resolutions:
        error = resolution.error
        if ctx.load_error_kind(resolution) == "unevaluated" and error is not None:
            position = ctx.source_position(resolution, error.file, error.line) or (
                resolution.launch.source or resolution.launch.installed,
                None,
            )
            if error.program:
                what = f"runs {error.program} while loading, a program not installed here"
            elif error.read_from:
                what = f"reads files of {error.read_from} while loading, a package not installed here"
            elif ctx.through_workspace_module(error):
                what = f"imports a workspace package's module that imports {error.module}, not installed here"
            else:
                what = f"imports {error.module}, from a package not installed here"
            yield Finding(f"{resolution.launch.installed.name} {what}; checked statically instead", *position)
        for item in resolution.errors if resolution.status == "ok" else []:
            unchecked = _action_unchecked(resolution, item)
            where = ctx.source_position(resolution, item.file, item.line) if unchecked else None
            if unchecked is None or where is None or (*where, unchecked[0]) in said:
                continue
            said.add((*where, unchecked[0]))
            # (a FindExecutable's program: named by the file the action stands in)
            named = where[0].name if unchecked[0] == item.program else resolution.launch.installed.name
            yield Finding(f"{named}: {item.entity or 'an action'} {unchecked[1]}", *where)


def _action_unchecked(resolution: Resolution, item: LaunchError) -> tuple[str, str] | None:
    """(what it is said once per line for, what the action does) for an action of a loaded file
    that could not be evaluated here, else None."""
    if item.event_values:
        return "event", (
            f"of an event handler uses what only the run gives the event ({item.type}: "
            f"{_one_line(item.message)}); it is not checked"
        )
    if item.program:
        # FindExecutable(name='ros2') in an ExecuteProcess (the "Using event handlers"
        # tutorial): where ROS is sourced, ros2 is on PATH
        return item.program, (
            f"finds {item.program} on PATH (FindExecutable), a program not installed here; what it "
            f"starts is not checked{_branch_note(item, resolution)}"
        )
    if item.read_from:
        # ardupilot_gz's launch_setup (an OpaqueFunction) opens ardupilot_gazebo's model.sdf
        return item.read_from, (
            f"reads files of {item.read_from}, a package not installed here; what it starts is not checked"
        )
    return None


@register(
    "PF317",
    "launch-environment-unset",
    "info",
    area="launch",
    bad=("# launch/robot.launch.py\nmodel = os.environ['TURTLEBOT3_MODEL']"),
    good="$ TURTLEBOT3_MODEL=burger pkgforge verify .",
    summary="a launch file reads an environment variable that is not set here",
    explanation="os.environ['X'], os.getenv('X') or EnvironmentVariable('X') with no default: the "
    "robot's own setup (or the user's shell) sets it (TURTLEBOT3_MODEL, a robot base name, USER). "
    "Without it the file stops (KeyError), builds paths with the text None, or the action using "
    "the substitution fails (SubstitutionFailure); what depends on it is not checked. When it "
    "stops the file, "
    "what the file names literally (packages, paths, nodes) is still checked, as for a file that "
    "cannot be evaluated here.",
    hint="set it when you run verify (e.g. NAME=value pkgforge verify), or give it a default",
)
def launch_environment_unset(ctx: CheckContext) -> Iterator[Finding]:
    said: set[tuple[Path, int | None, str]] = set()  # (an included file's action: said once, at its line)
    for resolution in ctx.resolutions:
        for item in resolution.errors if resolution.status == "ok" else []:
            variable = ctx.unset_variable(item)
            at = ctx.source_position(resolution, item.file, item.line) if variable else None
            if variable is None or at is None or (*at, variable) in said:
                continue
            said.add((*at, variable))
            yield Finding(
                f"{at[0].name}: {item.entity or 'an action'} fails: environment variable {variable} "
                "is not set here (EnvironmentVariable without a default); what depends on it is not "
                f"checked{_branch_note(item, resolution)}",
                *at,
            )
        names = ctx.unset_environment(resolution)
        if not names:
            continue
        failed = ctx.load_error_kind(resolution) == "environment"
        none_paths = [item for item in resolution.paths if not item.exists and NONE_TEXT.search(item.path)]
        if not failed and not none_paths:
            continue
        error = resolution.error
        where = (
            (error.file, error.line)
            if failed and error is not None
            else (none_paths[0].file, none_paths[0].line)
        )
        position = ctx.source_position(resolution, *where) or (
            resolution.launch.source or resolution.launch.installed,
            None,
        )
        what = "stops loading" if failed else "resolves a path with 'None' in it"
        rest = "what depends on it is not checked" + ("; the rest checked statically" if failed else "")
        yield Finding(
            f"{resolution.launch.installed.name} {what}: environment variable "
            f"{' or '.join(names)} is not set here; {rest}",
            *position,
        )


@register(
    "PF318",
    "launch-combinations-unevaluated",
    "info",
    area="launch",
    bad=(
        "# launch/bringup.launch.py: 8 true/false arguments, each combination slow to evaluate\n"
        "DeclareLaunchArgument('use_sim', default_value='false')  # ... and 7 more"
    ),
    good="$ pkgforge verify . --launch-timeout 60   # time for every combination",
    summary="the time limit left some of a launch file's argument combinations unevaluated",
    explanation="The defaults are evaluated under the whole --launch-timeout; the other values "
    "of true/false and choices arguments only while time remains. A file whose "
    "defaults finish is never an error for want of time: the combinations left out "
    "are said here, and what they would start is not checked. Machine-dependent, "
    "so never cached.",
    hint="nothing is wrong with the file; raise --launch-timeout (or verify on a less busy machine) "
    "to check every combination",
)
def launch_combinations_unevaluated(ctx: CheckContext) -> Iterator[Finding]:
    for resolution in ctx.resolutions:
        missing = resolution.unevaluated
        if not missing:
            continue
        branching = resolution.branching
        stopped: Mapping[str, Any] = branching.stopped or {}
        position = ctx.source_position(resolution, stopped.get("file"), stopped.get("line")) or (
            resolution.launch.source or resolution.launch.installed,
            None,
        )
        how = ""
        if stopped.get("branch"):
            how = f"; {stopped['branch']} was stopped" + (" at this line" if position[1] is not None else "")
        yield Finding(
            f"{resolution.launch.installed.name}: {branching.evaluated} of {branching.planned} "
            f"argument combinations evaluated within the {branching.limit or 0:g} s limit "
            f"(the defaults first); {missing} not checked{how}",
            *position,
        )


@register(
    "PF319",
    "unpredicted-lookup",
    "info",
    area="launch",
    bad=(
        "# robot_bringup/launch/robot.launch.py (robot_description's setup.py imports a module that is\n"
        "# not installed here, so what it installs cannot be predicted)\n"
        "xacro.process_file(os.path.join(get_package_share_directory('robot_description'), 'urdf', 'x.xacro'))"
    ),
    good="$ pkgforge verify . --build   # a real install of robot_description to look into",
    summary="a launch file or model looks up a file of a workspace package whose install "
    "pkgforge cannot predict",
    explanation="The package's install rules could not be evaluated (install-rule-unevaluated "
    "says where): what it installs is unknown, not empty. Its share folder in the predicted tree "
    "holds its source files where they are in its source, so lookups of those work and are "
    "checked; a file that is not there may still be installed (a computed data_files can put a "
    "file in another folder than its source's), so the lookup is not checked, and nothing that "
    "depends on it is.",
    hint="make the package's install rules evaluable (install-rule-unevaluated says why they are "
    "not), or verify against a real build (--build, --install-base)",
)
def unpredicted_lookup(ctx: CheckContext) -> Iterator[Finding]:
    from pkgforge.checks.urdf import model_item_position

    said: set[tuple[Path, int | None, str, str]] = set()

    def finding(
        found: tuple[str, str], what: str, position: tuple[Path, int | None] | None
    ) -> Iterator[Finding]:
        package, relative = found
        if position is None or (*position, package, relative) in said:
            return
        said.add((*position, package, relative))
        yield Finding(
            f"{what} share/{package}/{relative}, which the predicted install tree does not have; "
            f"{package}'s install cannot be predicted ({ctx.unpredicted_where(package)}), so the "
            "lookup is not checked",
            *position,
        )

    for resolution in ctx.resolutions:
        error = resolution.error
        if error is not None and ctx.load_error_kind(resolution) == "unpredicted":
            found = ctx.unpredicted_file(error.message)
            position = ctx.source_position(resolution, error.file, error.line) or (
                resolution.launch.source or resolution.launch.installed,
                None,
            )
            if found is not None:
                name = resolution.launch.installed.name
                yield from finding(found, f"{name} stopped loading on", position)
        for item in resolution.errors:
            found = ctx.unpredicted_file(item.message)
            if found is not None:
                where = ctx.source_position(resolution, item.file, item.line)
                yield from finding(found, f"{item.entity or 'an action'} failed on", where)
        for path in resolution.paths:
            found = ctx.unpredicted_file(path.path) if not path.exists else None
            if found is not None:
                where = ctx.source_position(resolution, path.file, path.line)
                yield from finding(found, "it looks up", where)
        for command in resolution.commands:
            found = None if command.ok else ctx.unpredicted_file(command.message)
            if found is not None:
                where = ctx.source_position(resolution, command.file, command.line)
                yield from finding(found, "xacro failed on", where)
    for result in ctx.model_results:
        message = (result.error or {}).get("message")
        found = ctx.unpredicted_file(message) if result.status != "ok" else None
        if found is not None:
            yield from finding(
                found,
                f"xacro {result.installed.name} failed on",
                model_item_position(ctx, result, result.error or {}),
            )


@register(
    "PF312",
    "ros1-launch-file",
    "info",
    area="launch",
    bad=(
        "# CMakeLists.txt (launch/display.launch is a roslaunch XML file)\n"
        "install(FILES launch/display.launch DESTINATION share/${PROJECT_NAME}/launch)"
    ),
    good=(
        "# CMakeLists.txt (ported to launch/display.launch.xml)\n"
        "install(FILES launch/display.launch.xml DESTINATION share/${PROJECT_NAME}/launch)"
    ),
    summary="a ROS 1 .launch file is installed",
    explanation="ROS 2 launches .launch.py, .launch.xml and .launch.yaml files; a roslaunch "
    "file is left over from a ROS 1 package.",
    hint="port it to a ROS 2 launch file, or stop installing it",
)
def ros1_launch_file(ctx: CheckContext) -> Iterator[Finding]:
    for launch in ctx.ros1_launch_files:
        yield Finding(f"{launch.installed.name} is a ROS 1 launch file", launch.source or launch.installed)


@register(
    "PF315",
    "launch-not-installed",
    "warning",
    area="launch",
    bad=(
        "# CMakeLists.txt (launch/ also holds gazebo.launch.py)\n"
        "install(FILES launch/display.launch.py DESTINATION share/${PROJECT_NAME}/launch)"
    ),
    good=("# CMakeLists.txt\ninstall(DIRECTORY launch DESTINATION share/${PROJECT_NAME})"),
    summary="a launch file in the source is left out of the install rules",
    explanation="`ros2 launch <pkg> <file>` looks in install/share/<pkg>/ and cannot find it. pkgforge "
    "evaluates it from the source, so what it references is still checked. Reported "
    "here when other files of its folder are installed (else directory-not-installed "
    "reports the folder).",
    hint="install it with the other launch files",
)
def launch_not_installed(ctx: CheckContext) -> Iterator[Finding]:
    from pkgforge.launch.uninstalled import is_uninstalled
    from pkgforge.model.package import RESOURCE_FOLDERS

    installed = ctx.model.layout.installed_sources()
    for resolution in ctx.resolutions:
        launch = resolution.launch
        # a workspace may hold two folders with one package name (colcon refuses to build it; verify
        # still reports both): resolutions are grouped by name, so keep this folder's files only
        if (
            not is_uninstalled(launch)
            or launch.source is None
            or not launch.source.is_relative_to(ctx.model.path)
        ):
            continue
        relative = launch.source.relative_to(ctx.model.path)
        folder = relative.parts[0] if len(relative.parts) > 1 else None
        siblings = ctx.model.top_level_folders().get(folder, []) if folder else []
        if folder in RESOURCE_FOLDERS and not any(ctx.model.path / f in installed for f in siblings):
            continue  # directory-not-installed reports the whole folder
        yield Finding(
            f"{relative} is not installed: `ros2 launch {ctx.model.name} {launch.source.name}` "
            "cannot find it (evaluated from the source)",
            launch.source,
            None,
            hint=install_fix(ctx.model, folder) if folder else "install it to share/<package>",
        )
