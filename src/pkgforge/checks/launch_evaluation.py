"""What evaluating a launch file found: arguments and configurations unset, launch API pkgforge
does not evaluate, environment variables unset, combinations not evaluated, lookups not predicted."""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from pkgforge.checks.context import NONE_TEXT, CheckContext
from pkgforge.checks.launch import _branch_note
from pkgforge.checks.launch_load import _one_line
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Group, Severity
from pkgforge.launch.records import Error as LaunchError
from pkgforge.launch.records import Resolution


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
    from pkgforge.checks.model_positions import model_item_position

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
