"""Checks of how launch files start nodes (read from the resolved `nodes` records).

Each check reads the records through one small function (`_node_records`), so a
change of the record type touches one place.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from pkgforge.checks.context import CheckContext
from pkgforge.checks.launch import _branch_note
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Severity
from pkgforge.launch.records import Node, Resolution
from pkgforge.urdf import ANY_MODEL_SUFFIXES


def _node_records(
    ctx: CheckContext,
) -> Iterator[tuple[str | None, list[str], tuple[Path, int | None], Node, Resolution]]:
    """(package, arguments, source position, record, resolution) of every node a launch file starts."""
    for resolution in ctx.resolutions:
        for node in resolution.nodes:
            position = ctx.source_position(resolution, node.file, node.line)
            if position is not None:
                yield node.package, [str(a) for a in node.arguments or []], position, node, resolution


def _split_characters(arguments: list[str]) -> bool:
    """launch iterates a string given as arguments: one argument per character."""
    return len(arguments) >= 2 and all(len(a) <= 1 for a in arguments) and any(a.strip() for a in arguments)


@register(
    "PF313",
    "node-arguments-string",
    "error",
    area="launch",
    bad=("# launch/display.launch.py\nNode(package='rviz2', executable='rviz2', arguments='-d ' + config)"),
    good=("# launch/display.launch.py\nNode(package='rviz2', executable='rviz2', arguments=['-d', config])"),
    summary="a Node's arguments is a string, not a list",
    explanation="launch_ros iterates `arguments`: a string becomes one argument per character "
    "(`-d x.rviz` reaches the program as '-', 'd', ' ', 'x', ...), and the node "
    "fails or ignores them.",
    hint="pass a list: arguments=['-d', 'config.rviz']",
)
def node_arguments_string(ctx: CheckContext) -> Iterator[Finding]:
    seen = set()
    for package, arguments, position, node, resolution in _node_records(ctx):
        if not _split_characters(arguments) or position in seen:
            continue
        seen.add(position)
        text = "".join(arguments)
        as_list = ", ".join(repr(part) for part in text.split())
        yield Finding(
            f"{package or 'a node'} gets arguments='{text}', a string: launch passes "
            f"{len(arguments)} one-character arguments{_branch_note(node, resolution)}",
            *position,
            hint=f"write arguments=[{as_list}]",
        )


@register(
    "PF314",
    "rsp-model-argument",
    "warning",
    area="launch",
    bad=(
        "# launch/display.launch.py\n"
        "Node(package='robot_state_publisher', executable='robot_state_publisher', arguments=[urdf_file])"
    ),
    good=(
        "# launch/display.launch.py\n"
        "Node(package='robot_state_publisher', executable='robot_state_publisher',\n"
        "     parameters=[{'robot_description':\n"
        "         ParameterValue(Command(['xacro ', urdf_file]), value_type=str)}])"
    ),
    summary="robot_state_publisher is given the robot model file as a command-line argument",
    explanation="Reading the URDF from a file argument is deprecated in robot_state_publisher "
    "and removed in Rolling: the node then starts with no model (an error when "
    "the target distro is Rolling). It takes the model as the robot_description "
    "parameter.",
    hint="pass robot_description as a parameter: parameters=[{'robot_description': "
    "ParameterValue(Command(['xacro ', model]), value_type=str)}]",
)
def rsp_model_argument(ctx: CheckContext) -> Iterator[Finding]:
    seen = set()
    for package, arguments, position, node, resolution in _node_records(ctx):
        if package != "robot_state_publisher" or position in seen:
            continue
        models = [a for a in arguments if a.endswith(ANY_MODEL_SUFFIXES)]
        if models:
            seen.add(position)
            # removed in Rolling: there the node starts with no model at all
            severity = Severity.ERROR if "rolling" in ctx.distros else None
            yield Finding(
                f"robot_state_publisher is given {Path(models[0]).name} as an argument; pass the "
                f"model as the robot_description parameter{_branch_note(node, resolution)}",
                *position,
                severity=severity,
            )


# --- robot_state_publisher's description, parameter files, ros_gz_bridge configs -----------------

# what a node's command line after --ros-args may give it a parameter with
ROS_PARAMETER_FLAGS = ("-p", "--param", "--params-file")


def _ros_arguments(node: Node) -> tuple[list[str], list[str]]:
    """(the arguments the program itself gets, the ROS arguments): launch_ros puts `arguments`
    first, then `--ros-args` and ros_arguments; a `--ros-args` in `arguments` starts ROS
    arguments, up to a `--` (rcl_parse_arguments' rule)."""
    own: list[str] = []
    ros: list[str] = []
    inside = False
    for argument in [str(a) for a in node.arguments or []]:
        if argument == "--ros-args":
            inside = True
        elif argument == "--" and inside:
            inside = False
        else:
            (ros if inside else own).append(argument)
    return own, ros + [str(a) for a in node.ros_arguments or []]


def _parameter_files(node: Node) -> list[str]:
    return [p.value_preview for p in node.parameters if p.form == "file"]


def _where(ctx: CheckContext, position: tuple[Path, int | None]) -> str:
    path, line = position
    return f"{ctx.relative(path)}:{line}" if line is not None else ctx.relative(path)


def _node_label(node: Node) -> str:
    if node.package and node.executable and node.executable != node.package:
        return f"{node.package}/{node.executable}"
    return node.package or node.executable or "a node"


def _description_given(ctx: CheckContext, node: Node) -> bool:
    """Whether robot_state_publisher may get its model: a robot_description parameter, a model
    file as its first argument (robot_state_publisher.cpp reads argv[1]), a parameter rule on its
    ROS command line, or a parameters file that holds robot_description or cannot be read here
    (what it holds is not known)."""
    own, ros = _ros_arguments(node)
    if own or any(flag in ros for flag in ROS_PARAMETER_FLAGS):
        return True
    if any(p.name == "robot_description" for p in node.parameters):
        return True
    for path in _parameter_files(node):
        read = ctx.parameters_file(path)
        if read is None or read.problem is not None or not read.judged:
            return True  # not known; a file rcl refuses is parameters-file-invalid's
        if "robot_description" in read.parameters:
            return True
    return False


@register(
    "PF321",
    "rsp-no-description",
    "error",
    area="launch",
    bad=(
        "# launch/display.launch.py\n"
        "Node(package='robot_state_publisher', executable='robot_state_publisher',\n"
        "     parameters=[{'use_sim_time': True}])"
    ),
    good=(
        "# launch/display.launch.py\n"
        "Node(package='robot_state_publisher', executable='robot_state_publisher',\n"
        "     parameters=[{'robot_description':\n"
        "         ParameterValue(Command(['xacro ', model]), value_type=str)}])"
    ),
    summary="robot_state_publisher is started with no robot_description",
    explanation="robot_state_publisher reads the model from its robot_description parameter, or "
    "(deprecated) from a file named as its first argument; with neither it stops at once "
    "('robot_description parameter must not be empty'; its README: it must be set at "
    "startup). A parameters file it is given counts when it holds robot_description, or "
    "when pkgforge cannot read what it holds.",
    hint="pass the model: parameters=[{'robot_description': "
    "ParameterValue(Command(['xacro ', model]), value_type=str)}]",
)
def rsp_no_description(ctx: CheckContext) -> Iterator[Finding]:
    seen = set()
    for package, _, position, node, resolution in _node_records(ctx):
        if (
            package != "robot_state_publisher"
            or node.kind != "node"
            or node.executable not in (None, "robot_state_publisher")
            or position in seen
            or _description_given(ctx, node)
            or any(e.file == node.file and e.line == node.line for e in resolution.errors)
        ):
            continue  # (a node launch_ros refuses never starts: launch-load-error says why)
        seen.add(position)
        files = _parameter_files(node)
        given = (
            f" (its parameters file{'s' if len(files) > 1 else ''} hold{'' if len(files) > 1 else 's'} none)"
            if files
            else ""
        )
        yield Finding(
            f"robot_state_publisher gets no robot_description parameter and no model file{given}: "
            f"it stops at start{_branch_note(node, resolution)}",
            *position,
        )


def _yaml_place(
    ctx: CheckContext, path: str, line: int, node_position: tuple[Path, int | None]
) -> tuple[Path, int | None, str]:
    """(file, line, note) of a finding about a YAML file a launch file hands a node: at its own
    line when it is this package's file; at the node's line, naming it, when it is another's."""
    source = ctx.own_source(path)
    if source is not None:
        return source, line, ""
    located = ctx.tree.locate(path) if ctx.tree is not None else None
    shown = f"share/{located[0]}/{located[1]}" if located is not None else path
    return node_position[0], node_position[1], f"{shown}:{line}: "


@register(
    "PF322",
    "parameters-file-invalid",
    "error",
    area="launch",
    bad=(
        "# config/teleop.yaml\n"
        "teleop_node:\n"
        "  ros_parameters:        # not ros__parameters\n"
        "    scale: [0.5, 1, 2]   # and a list of doubles and integers"
    ),
    good=("# config/teleop.yaml\nteleop_node:\n  ros__parameters:\n    scale: [0.5, 1.0, 2.0]"),
    summary="a parameters file a launch file gives a node is one rcl refuses",
    explanation="A node given `parameters=[file]` (or <param from=...>, SetParametersFromFile) "
    "reads it with rcl's parser when it starts, and does not start when that refuses it: invalid "
    "YAML (a tab in the indentation), a top level that is not node names (or /**) each holding "
    "ros__parameters, a value outside ros__parameters (ros__parameters misspelt), a parameter "
    "with no value, a list mixing types ([0.5, 1]), a YAML alias, an invalid node name. Said "
    "once, at the file's line.",
    hint="lay it out as <node name or /**>: ros__parameters: name: value (lists of one type); "
    "try it with: ros2 run <package> <executable> --ros-args --params-file FILE",
)
def parameters_file_invalid(ctx: CheckContext) -> Iterator[Finding]:
    said: dict[tuple[Path, int | None, str], list[str]] = {}
    order: list[tuple[tuple[Path, int | None, str], str, Node, Resolution]] = []
    for _, _, position, node, resolution in _node_records(ctx):
        if node.kind != "node":
            continue
        for path in _parameter_files(node):
            read = ctx.parameters_file(path)
            if read is None or read.problem is None:
                continue
            file, line, note = _yaml_place(ctx, path, read.problem.line, position)
            key = (file, line, read.problem.message)
            who = f"{_node_label(node)} ({_where(ctx, position)})"
            if key not in said:
                said[key] = []
                order.append((key, f"{note}{read.problem.message}", node, resolution))
            if who not in said[key]:
                said[key].append(who)
    for key, message, node, resolution in order:
        nodes = said[key]
        more = f" and {len(nodes) - 1} more" if len(nodes) > 1 else ""
        yield Finding(
            f"rcl refuses this parameters file: {message}; {nodes[0]}{more} does not start"
            f"{_branch_note(node, resolution)}",
            key[0],
            key[1],
        )


def _bridge_configs(
    ctx: CheckContext,
) -> Iterator[tuple[str, tuple[Path, int | None], str, Node | None, Resolution]]:
    """(config file, where it is given, who reads it, node record, resolution) of every
    ros_gz_bridge config_file: a parameter of a ros_gz_bridge node, or the config_file argument
    of a ros_gz_bridge or ros_gz_sim launch file included."""
    for _, _, position, node, resolution in _node_records(ctx):
        if node.package == "ros_gz_bridge" and node.kind == "node":
            for parameter in node.parameters:
                if parameter.name == "config_file" and parameter.form in ("plain", "typed-str", "typed"):
                    yield (
                        parameter.value_preview,
                        position,
                        f"{_node_label(node)} ({_where(ctx, position)})",
                        node,
                        resolution,
                    )
    for resolution in ctx.resolutions:
        for include in resolution.includes:
            located = ctx.tree.locate(include.path) if ctx.tree is not None else None
            config = include.arguments.get("config_file")
            where = ctx.source_position(resolution, include.file, include.line)
            if (
                located is None
                or located[0] not in ("ros_gz_bridge", "ros_gz_sim")
                or not config
                or where is None
            ):
                continue
            yield (
                config,
                where,
                f"{located[0]}'s {Path(located[1]).name} ({_where(ctx, where)})",
                None,
                resolution,
            )


@register(
    "PF323",
    "bridge-config-invalid",
    "error",
    area="launch",
    bad=(
        "# config/bridge.yaml\n"
        "clock:                    # a map, not a list of entries\n"
        "  ros_type_name: rosgraph_msgs/msg/Clock\n"
        "  gz_type_name: gz.msgs.Clock"
    ),
    good=(
        "# config/bridge.yaml\n"
        "- ros_topic_name: clock\n"
        "  ros_type_name: rosgraph_msgs/msg/Clock\n"
        "  gz_type_name: gz.msgs.Clock\n"
        "  direction: GZ_TO_ROS"
    ),
    summary="a ros_gz_bridge config_file is one the bridge cannot read",
    explanation="ros_gz_bridge reads its config_file as a YAML list of entries, each a map with "
    "ros_type_name and gz_type_name, a topic (topic_name, or ros_topic_name and/or "
    "gz_topic_name) and a direction (BIDIRECTIONAL, GZ_TO_ROS, ROS_TO_GZ). Invalid YAML ends the "
    "node; a top level that is not a list bridges nothing; an entry it cannot read is logged and "
    "skipped, its topic not bridged. A warning for what only some target distros read "
    "(humble's ign_type_name, IGN_TO_ROS).",
    hint="write each entry as - ros_topic_name: ..., gz_topic_name: ..., ros_type_name: ..., "
    "gz_type_name: ..., direction: GZ_TO_ROS",
)
def bridge_config_invalid(ctx: CheckContext) -> Iterator[Finding]:
    from pkgforge.model.distro_data import active_distros

    targets = set(ctx.distros or active_distros())
    said: set[tuple[Path, int | None, str]] = set()
    for path, position, who, node, resolution in _bridge_configs(ctx):
        for problem in ctx.bridge_config(path) or []:
            fine = targets & set(problem.fine_on)
            if fine == targets:
                continue
            file, line, note = _yaml_place(ctx, path, problem.line, position)
            if (file, line, problem.message) in said:
                continue
            said.add((file, line, problem.message))
            branch = _branch_note(node, resolution) if node is not None else ""
            yield Finding(
                f"ros_gz_bridge cannot use this config: {note}{problem.message} (given to {who}){branch}",
                file,
                line,
                severity=Severity.WARNING if fine else None,
            )
