"""`migrate --gazebo`: a ROS 1 ros_control controller YAML (what a launch file loads with a global
<rosparam command="load"> for controller_manager's spawner) → a ROS 2 controller_manager
parameters file, which gz_ros2_control's controller manager reads through the model's
<parameters>.

ROS 1's controllers are the mappings with a `type` (at any depth: a file often nests them under
the robot's namespace); ROS 2's layout is controller_manager: ros__parameters: {update_rate,
<name>: {type}} and each controller's own <name>: ros__parameters: {...}. Types map through
model/ros1_names.CONTROLLER_TYPES; what has no ROS 2 equivalent is left out with a note.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from pkgforge.model import ros1_names

if TYPE_CHECKING:
    from pkgforge.scaffold.notes import Notes

# controller_manager's update rate in Gazebo: what `new --sim gz` writes
UPDATE_RATE = 100
# the state interfaces a trajectory controller reads (gz_ros2_control exports both)
STATE_INTERFACES = ["position", "velocity"]


@dataclass
class Ros1Controller:
    name: str
    type: str
    line: int  # the line of its type
    parameters: dict[str, Any]


@dataclass
class ControllerConversion:
    """What a converted controller file defines: ROS 1 name → ROS 2 name of each controller kept,
    the names left out, and the packages of the ROS 2 types."""

    names: dict[str, str] = field(default_factory=dict)
    dropped: set[str] = field(default_factory=set)
    packages: set[str] = field(default_factory=set)


def _controllers(text: str) -> list[Ros1Controller]:
    """Every mapping with a string `type` naming a class (pkg/Class), with the line of its type."""
    from pkgforge.model import yamlnodes

    root, data = yamlnodes.compose(text), yamlnodes.load(text)
    found: list[Ros1Controller] = []

    def walk(node: yaml.Node, value: Any, depth: int) -> None:
        if not isinstance(node, yaml.MappingNode) or not isinstance(value, dict) or depth > 4:
            return
        for key, child in node.value:
            name = key.value if isinstance(key, yaml.ScalarNode) else None
            if name is None or name not in value:
                continue
            item = value[name]
            kind = item.get("type") if isinstance(item, dict) else None
            if isinstance(kind, str) and "/" in kind:
                line = next(
                    (v.start_mark.line + 1 for k, v in child.value if getattr(k, "value", None) == "type"),
                    key.start_mark.line + 1,
                )
                found.append(Ros1Controller(str(name), kind, line, dict(item)))
            else:
                walk(child, item, depth + 1)

    if root is not None:
        walk(root, data, 0)
    return found


def _names(value: Any) -> list[str]:
    """A joint name or a list of them, as a list of strings."""
    if isinstance(value, str):
        return [value]
    if isinstance(value, list):
        return [str(v) for v in value if isinstance(v, str | int | float)]
    return []


def _parameters(
    controller: Ros1Controller, ros2_type: str, interface: str | None
) -> tuple[dict[str, Any], list[str]]:
    """(ROS 2 parameters of the controller, the ROS 1 parameters left out)."""
    given = {k: v for k, v in controller.parameters.items() if k != "type"}
    out: dict[str, Any] = {}
    kept: set[str] = set()
    if ros2_type == "joint_state_broadcaster/JointStateBroadcaster":
        extra = [
            e.get("name") for e in given.get("extra_joints") or [] if isinstance(e, dict) and e.get("name")
        ]
        if extra:
            out["extra_joints"] = extra
            kept.add("extra_joints")
    elif ros2_type == "joint_trajectory_controller/JointTrajectoryController":
        out["joints"] = _names(given.get("joints"))
        out["command_interfaces"] = [interface]
        out["state_interfaces"] = list(STATE_INTERFACES)
        out.update({k: given[k] for k in ros1_names.TRAJECTORY_KEPT if k in given})
        kept |= {"joints", *ros1_names.TRAJECTORY_KEPT}
    elif ros2_type == "diff_drive_controller/DiffDriveController":
        for old, new in ros1_names.DIFF_DRIVE_RENAMED.items():
            if old in given:
                out[new] = _names(given[old])
        out.update({k: v for k, v in given.items() if k in ros1_names.DIFF_DRIVE_KEPT})
        kept |= set(ros1_names.DIFF_DRIVE_RENAMED) | ros1_names.DIFF_DRIVE_KEPT
    elif ros2_type.endswith("GripperActionController"):
        out.update({k: v for k, v in given.items() if k in ("joint", "goal_tolerance", "max_effort")})
        kept |= {"joint", "goal_tolerance", "max_effort"}
    else:  # a group forwarding controller: ROS 1's one joint= or joints= → joints
        out["joints"] = _names(given.get("joints", given.get("joint")))
        kept |= {"joint", "joints"}
    return out, sorted(set(given) - kept)


def convert(content: bytes, path: Path, distro: str, notes: Notes) -> tuple[bytes, ControllerConversion]:
    """The ROS 2 controller_manager parameters file of a ROS 1 controller YAML, and what it defines.
    A file that is not YAML, or defines no controller, is copied as it is (empty conversion)."""
    from pkgforge.model.simulation import controller_types

    conversion = ControllerConversion()
    text = content.decode("utf-8", errors="replace")
    try:
        ros1 = _controllers(text)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        notes.add(
            "migrate-source-defect",
            f"{path.name} is not YAML ({getattr(error, 'problem', None) or error}): copied as written, "
            "no controller converted",
            path,
            mark.line + 1 if mark is not None else None,
        )
        return content, conversion
    if not ros1:
        return content, conversion
    available = controller_types(distro)
    manager: dict[str, Any] = {"update_rate": UPDATE_RATE, "use_sim_time": True}
    sections: dict[str, Any] = {"controller_manager": {"ros__parameters": manager}}
    for controller in ros1:
        mapped = ros1_names.CONTROLLER_TYPES.get(controller.type)
        if mapped is None or mapped[0] not in available:
            conversion.dropped.add(controller.name)
            notes.add(
                "migrate-gazebo-classic",
                f"controller '{controller.name}' ({controller.type}) has no ROS 2 equivalent on {distro}: "
                "left out, and out of the spawner",
                path,
                controller.line,
            )
            continue
        name = ros1_names.CONTROLLER_NAMES.get(controller.name, controller.name)
        parameters, left_out = _parameters(controller, mapped[0], mapped[1])
        conversion.names[controller.name] = name
        conversion.packages.add(mapped[0].split("/", 1)[0])
        manager[name] = {"type": mapped[0]}
        if parameters:
            sections[name] = {"ros__parameters": parameters}
        renamed = f" as '{name}'" if name != controller.name else ""
        dropped = f"; left out: {', '.join(left_out)}" if left_out else ""
        notes.add(
            "migrate-changed",
            f"controller '{controller.name}' ({controller.type}) → {mapped[0]}{renamed}{dropped}",
            path,
            controller.line,
        )
    header = (
        f"# Converted from ROS 1 {path.name} by pkgforge migrate --gazebo: {len(conversion.names)} "
        "controller(s) for\n# gz_ros2_control's controller manager (the model's <parameters> names this file).\n"
    )
    body = yaml.safe_dump(sections, sort_keys=False, default_flow_style=False, width=1000)
    return (header + body).encode("utf-8"), conversion
