"""Checks of launch files as resolved in the install tree: what the launch checks share (the
launch_* modules import it), the model a launch file hands its nodes, launch files that are no
ROS 2 launch file or are not installed."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

from pkgforge.checks.context import CheckContext, only_with
from pkgforge.checks.install import install_fix
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding
from pkgforge.launch.records import PREVIEW_LENGTH, Record, Resolution
from pkgforge.urdf import ANY_MODEL_SUFFIXES

JSP_PACKAGES = ("joint_state_publisher", "joint_state_publisher_gui")


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
