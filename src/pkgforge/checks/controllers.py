"""Checks of the controller configurations a package gives ros2_control (issue 31 item 3): the YAML
given to ros2_control_node or to gz_ros2_control's <parameters>, the controllers' types and joints
on the target distro, the spawners, and how the description reaches the controller manager. What
the robot's models and the distros offer is read as checks/simulation reads it.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from pkgforge.checks.context import CheckContext
from pkgforge.checks.registry import register
from pkgforge.checks.simulation import (
    _distros,
    _failing,
    _models,
    _position,
    _robot_items,
    _systems,
    _which,
)
from pkgforge.diagnostics import Finding, Severity
from pkgforge.launch.records import Node, Resolution
from pkgforge.model.controllers import ControllerParameters, read_controller_parameters
from pkgforge.model.simulation import controller_types, controllers_branch, data

# the distros whose controller manager reads the description from the /robot_description topic
# only (ros2_control's jazzy branch, controller_manager.cpp: no robot_description parameter)
TOPIC_DISTROS = ("jazzy", "kilted", "lyrical", "rolling")
# spawner options that take a value (ros2_control's humble and jazzy spawner.py)
SPAWNER_VALUED = {
    "-c",
    "--controller-manager",
    "-p",
    "--param-file",
    "-n",
    "--namespace",
    "-t",
    "--controller-type",
    "--controller-manager-timeout",
    "--switch-timeout",
    "--service-call-timeout",
    "--controller-ros-args",
}


# --- controller configuration ------------------------------------------------------------------


@dataclass
class ControllerFile:
    installed: str  # the path the launch file or model gives
    source: Path  # where a person edits it
    parameters: ControllerParameters
    line: int | None  # where it is given (None: in a model)
    given: Path  # the file that gives it


def _joint_parameters(ctx: CheckContext) -> dict[str, list[str]]:
    merged: dict[str, set[str]] = {}
    for distro in _distros(ctx)[0]:
        for name, spec in controller_types(distro).items():
            merged.setdefault(name, set()).update(spec["joints"])
    return {name: sorted(joints) for name, joints in merged.items()}


def _controller_files(ctx: CheckContext) -> list[ControllerFile]:
    """The controller configurations of this package: the parameter files its launch files give
    ros2_control_node and the spawner (--param-file), and its models' gz_ros2_control <parameters>."""

    def compute() -> list[ControllerFile]:
        given: list[tuple[str, Path, int | None]] = []
        for resolution in ctx.resolutions:
            for node in resolution.nodes:
                position = ctx.source_position(resolution, node.file, node.line)
                if position is not None:
                    given += [(path, *position) for path in _files_given(node)]
        for result in _models(ctx):
            for plugin in _robot_items(result, "gazebo_plugins"):
                place = _position(ctx, result, plugin["file"], plugin["line"])
                given += [(text, *place) for text in plugin["parameters"]]
        files: list[ControllerFile] = []
        joint_parameters = _joint_parameters(ctx)
        for installed, where, line in dict.fromkeys(given):
            if not installed.endswith((".yaml", ".yml")) or not ctx.files.exists(installed):
                continue
            source = ctx.own_source(installed)
            if source is None:
                continue  # another package's file: its own verify reads it
            parameters = read_controller_parameters(ctx.text_head(installed), joint_parameters)
            files.append(ControllerFile(installed, source, parameters, line, where))
        return files

    found: list[ControllerFile] = ctx._shared(("controller-files", str(ctx.model.path)), compute)
    return found


def _files_given(node: Node) -> list[str]:
    """The parameters files a controller_manager node reads: ros2_control_node's, a spawner's
    --param-file."""
    if node.package != "controller_manager":
        return []
    if node.executable == "ros2_control_node":
        return [p.value_preview for p in node.parameters if p.form == "file"]
    return _spawner_files(node) if node.executable == "spawner" else []


def _spawner_files(node: Node) -> list[str]:
    words = [str(a) for a in node.arguments]
    return [words[i + 1] for i, w in enumerate(words[:-1]) if w in ("-p", "--param-file")]


@register(
    "PF705",
    "controller-config-invalid",
    "error",
    area="simulation",
    bad="# config/controllers.yaml\ncontroller_manager:\n  ros__parameters:\n    diff_drive: {type: diff_drive_controller/DiffDriveController",
    good="# config/controllers.yaml\ncontroller_manager:\n  ros__parameters:\n    diff_drive: {type: diff_drive_controller/DiffDriveController}",
    summary="a controller configuration that is no ROS parameters file",
    explanation="ros2_control_node (and gz_ros2_control's controller manager, given the file with "
    "<parameters>) read the file with rcl's parameter parser: it must be YAML, a mapping of node "
    "names, each with a ros__parameters mapping. rcl refuses anything else and the controller "
    "manager does not start. (A file a ros2_control_node is given as its parameters file is "
    "parameters-file-invalid's, PF322: one cause, one finding.)",
    hint="write node_name: {ros__parameters: {...}} (controller_manager: ros__parameters: <controller>: {type: ...})",
)
def controller_config_invalid(ctx: CheckContext) -> Iterator[Finding]:
    # one cause, one finding: a file a ros2_control_node is given as its parameters file is
    # parameters-file-invalid's (PF322: rcl refuses it, the node does not start)
    read_by_node = {
        path
        for resolution in ctx.resolutions
        for node in resolution.nodes
        if node.executable == "ros2_control_node"
        for path in _files_given(node)
    }
    for file in _controller_files(ctx):
        if file.parameters.error is not None and file.installed not in read_by_node:
            yield Finding(
                f"{file.source.name} is not a ROS parameters file: {file.parameters.error}",
                file.source,
                file.parameters.error_line,
            )


@register(
    "PF706",
    "controller-type-unavailable",
    "error",
    area="simulation",
    bad="# config/controllers.yaml (jazzy)\n    joint_state_controller:\n      type: joint_state_controller/JointStateController",
    good="# config/controllers.yaml (jazzy)\n    joint_state_broadcaster:\n      type: joint_state_broadcaster/JointStateBroadcaster",
    summary="a controller type that does not exist on the target distro",
    explanation="The controller manager loads a controller's `type` through pluginlib. The types of "
    "ros2_controllers are those its branch for the distro exports (humble, jazzy, kilted; master "
    "for Lyrical and Rolling: each controller's plugin XML); a type of another package needs that "
    "package released for the distro (rosdistro) or in the workspace. Otherwise loading fails.",
    hint="use a type the distro's ros2_controllers exports (e.g. joint_state_broadcaster/JointStateBroadcaster)",
)
def controller_type_unavailable(ctx: CheckContext) -> Iterator[Finding]:
    every = [t for d in data()["controllers"].values() for t in d["types"]] + data()["retired"]
    own_prefixes = {t.split("/", 1)[0] for t in every}
    for file in _controller_files(ctx):
        for controller in file.parameters.controllers.values():
            kind = controller.type or ""
            prefix = kind.split("/", 1)[0]
            if prefix not in own_prefixes:
                # a type's prefix is a pluginlib lookup name, not always a package (ros2_control_demos'
                # example_12 builds passthrough_controller/PassthroughController itself): only
                # ros2_controllers' own types are judged
                continue
            failing = _failing(ctx, {d: kind not in controller_types(d) for d in _distros(ctx)[0]})
            why = "ros2_controllers' {branch} branch exports no such type"
            if failing:
                yield Finding(
                    f"controller '{controller.name}' has type '{kind}', which does not exist on "
                    f"{_which(failing)}: " + why.format(branch=controllers_branch(failing[0])),
                    file.source,
                    controller.type_line,
                )


def _control_joints(ctx: CheckContext) -> set[str] | None:
    """The joints of every <ros2_control> of the package's models; None when there is none."""
    systems = [s for _, s in _systems(ctx)]
    if not systems:
        return None
    return {j["name"] for s in systems for j in s["joints"] if j["name"]}


@register(
    "PF707",
    "controller-joint-unknown",
    "error",
    area="simulation",
    bad="# config/controllers.yaml\ndiff_drive:\n  ros__parameters:\n    left_wheel_names: [wheel_left]",
    good="# config/controllers.yaml\ndiff_drive:\n  ros__parameters:\n    left_wheel_names: [left_wheel_joint]",
    summary="a controller names a joint no <ros2_control> of the package's models has",
    explanation="A controller claims the interfaces of the joints its parameters name (joints, "
    "left_wheel_names, right_wheel_names, joint, ...: the joint-naming parameters of each "
    "controller's generate_parameter_library YAML in ros2_controllers' branch for the distro); a "
    "joint no <ros2_control> tag exports has no interface and the controller fails to activate.",
    hint="name a joint of the model's <ros2_control> tag",
)
def controller_joint_unknown(ctx: CheckContext) -> Iterator[Finding]:
    joints = _control_joints(ctx)
    if joints is None:
        return
    for file in _controller_files(ctx):
        for controller in file.parameters.controllers.values():
            for use in controller.joints:
                # chained controllers name the reference interfaces of another controller
                # (position_controller/joint1_position_controller/joint1), not joints
                if use.joint not in joints and use.joint.split("/", 1)[0] not in file.parameters.controllers:
                    yield Finding(
                        f"controller '{controller.name}' names joint '{use.joint}' ({use.parameter}), "
                        "which no <ros2_control> of the package's models has",
                        file.source,
                        use.line,
                    )


def _spawned(node: Node) -> tuple[list[str], bool]:
    """(the controller names a spawner is given, whether it is given a type with -t)."""
    names: list[str] = []
    typed = False
    words = [str(a) for a in node.arguments]
    skip = False
    for word in words:
        if word == "--ros-args":
            break
        if skip:
            skip = False
            continue
        if word in SPAWNER_VALUED:
            skip = True
            typed = typed or word in ("-t", "--controller-type")
            continue
        if word.startswith("-") or "=" in word:
            continue
        names.append(word)
    return names, typed


@register(
    "PF708",
    "spawner-controller-unknown",
    "error",
    area="simulation",
    bad="# launch/sim.launch.py\nNode(package='controller_manager', executable='spawner', arguments=['diff_controller'])",
    good="# launch/sim.launch.py\nNode(package='controller_manager', executable='spawner', arguments=['diff_drive'])",
    summary="a spawner names a controller that no controller configuration of the package defines",
    explanation="controller_manager's spawner (ros2_control's humble and jazzy spawner.py) loads "
    "each controller name it is given; the controller manager needs `<name>.type` from its "
    "parameters (the file given to ros2_control_node or gz_ros2_control, or a spawner "
    "--param-file). A name none of them defines fails to load. Judged when the package gives a "
    "controller configuration.",
    hint="spawn a controller the YAML defines, or add it there with its type",
)
def spawner_controller_unknown(ctx: CheckContext) -> Iterator[Finding]:
    files = _controller_files(ctx)
    broken = {f.installed for f in files if f.parameters.error}
    # one cause, one finding: a broken file (controller-config-invalid) defines nothing known
    if not files:
        return
    defined = {name for f in files for name in f.parameters.controllers}
    if broken and not defined:
        return  # every controller the package has is in a file it cannot read: none is known missing
    foreign_model_file = any(
        ctx.own_source(text) is None
        for result in _models(ctx)
        for plugin in _robot_items(result, "gazebo_plugins")
        for text in plugin["parameters"]
    )
    for resolution in ctx.resolutions:
        if foreign_model_file or _reads_foreign_configuration(ctx, resolution):
            continue  # what the controller manager is given is not all known here
        for node in resolution.nodes:
            if (node.package, node.executable) != ("controller_manager", "spawner"):
                continue
            position = ctx.source_position(resolution, node.file, node.line)
            names, typed = _spawned(node)
            if position is None or typed or broken & set(_spawner_files(node)):
                continue
            if any(
                p.form == "file" and p.value_preview in broken
                for r in ctx.resolutions
                for n in r.nodes
                for p in n.parameters
            ):
                return
            for name in names:
                if name not in defined:
                    yield Finding(
                        f"spawner loads controller '{name}', which no controller configuration of "
                        f"{ctx.model.name} defines ({', '.join(sorted(defined)) or 'none'})",
                        *position,
                    )


def _reads_foreign_configuration(ctx: CheckContext, resolution: Resolution) -> bool:
    """Whether a controller manager this launch file starts, or one of its spawners, is given a
    parameters file that is not this package's (protobot_bringup's ros2_control_node and spawner
    read ros2_control_demo_example_9's rrbot_controllers.yaml): the controllers it defines are
    that package's to check."""
    return any(ctx.own_source(path) is None for node in resolution.nodes for path in _files_given(node))


def _description_given(node: Node) -> bool:
    return any(p.name == "robot_description" for p in node.parameters)


def _remapped(node: Node) -> bool:
    return any(str(pair[0]).endswith("robot_description") for pair in node.remappings if pair)


@register(
    "PF709",
    "controller-description-delivery",
    "warning",
    area="simulation",
    bad="# launch/control.launch.py (jazzy)\nNode(package='controller_manager', executable='ros2_control_node', "
    "parameters=[{'robot_description': description}, controllers])",
    good="# launch/control.launch.py (jazzy)\nNode(package='controller_manager', executable='ros2_control_node', "
    "parameters=[controllers])  # robot_state_publisher publishes /robot_description",
    summary="ros2_control_node gets the robot description the way the target distro does not read it",
    explanation="ros2_control's controller_manager.cpp: on Humble it reads the robot_description "
    "parameter (deprecated) and, without it, subscribes to ~/robot_description "
    "(/controller_manager/robot_description unless remapped: robot_state_publisher publishes "
    "/robot_description); from Jazzy on (branches jazzy, kilted) it only subscribes to the "
    "robot_description topic and ignores the parameter. A controller manager without its "
    "description never loads its hardware. `pkgforge fix` drops the parameter where every target "
    "distro ignores it (written in the node: a dict entry in Python, a <param> in XML, a param item in "
    "YAML launch files): "
    "safe, since the node never read it.",
    fix="safe",
    hint="Jazzy and later: drop the parameter and run robot_state_publisher; Humble: pass robot_description, "
    "or remap ~/robot_description to /robot_description",
)
def controller_description_delivery(ctx: CheckContext) -> Iterator[Finding]:
    for resolution in ctx.resolutions:
        for node in resolution.nodes:
            if (node.package, node.executable) != ("controller_manager", "ros2_control_node"):
                continue
            position = ctx.source_position(resolution, node.file, node.line)
            if position is None:
                continue
            given, remapped = _description_given(node), _remapped(node)
            ignored = _failing(ctx, {d: d in TOPIC_DISTROS and given for d in _distros(ctx)[0]})
            if ignored:
                yield Finding(
                    f"ros2_control_node gets a robot_description parameter, which it ignores on "
                    f"{_which(ignored)}: it reads the /robot_description topic",
                    *position,
                    hint="drop the parameter; robot_state_publisher publishes /robot_description",
                    # dropped only where no target reads it (humble too: the user's decision)
                    fix={"drop": True} if len(ignored) == len(_distros(ctx)[0]) else None,
                )
            missing = _failing(
                ctx, {d: d not in TOPIC_DISTROS and not given and not remapped for d in _distros(ctx)[0]}
            )
            if missing:
                yield Finding(
                    f"ros2_control_node gets no robot_description on {_which(missing)}: it reads the "
                    "parameter, else ~/robot_description, which nothing remaps to /robot_description",
                    *position,
                    severity=Severity.ERROR,
                    hint="remap ('~/robot_description', '/robot_description'), or pass the robot_description parameter",
                )
