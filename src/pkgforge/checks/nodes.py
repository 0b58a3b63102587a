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
