"""Launch files that fail to load, and why: the error as the user's file caused it, with a hint."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

from pkgforge.checks.context import CheckContext
from pkgforge.checks.files import read_problem_hint, undeclared_find, untree, untree_xacro
from pkgforge.checks.launch import _branch_note
from pkgforge.checks.registry import register
from pkgforge.checks.sandbox import MARKER as GUARD_MARKER
from pkgforge.checks.sandbox import SANDBOX_TYPES, sandbox_records, stopped_by_guard
from pkgforge.diagnostics import Finding, Severity
from pkgforge.launch.records import Error as LaunchError
from pkgforge.launch.records import Resolution


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
    from pkgforge.checks.context import BUILTIN_IMPORT_ERROR
    from pkgforge.checks.facts import launch_name_home

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
