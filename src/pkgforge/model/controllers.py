"""A controller configuration: the ROS parameters file ros2_control_node (or gz_ros2_control's
<parameters>) reads, as far as the simulation checks need it.

`read_controller_parameters` takes whether rcl reads the file from model/ros_params (the one
reader of rcl's rules, PF322's too) and reads from it what the controller checks need: each
controller, its type and the joints its parameters name.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import yaml

from pkgforge.model.ros_params import read_parameters
from pkgforge.model.yamlnodes import compose_all


@dataclass
class JointUse:
    parameter: str  # the controller parameter naming it (joints, left_wheel_names, ...)
    joint: str
    line: int


@dataclass
class Controller:
    name: str
    line: int  # where the controller manager's section names it
    type: str | None = None
    type_line: int | None = None
    joints: list[JointUse] = field(default_factory=list)


@dataclass
class ControllerParameters:
    error: str | None = None  # why it is no ROS parameters file
    error_line: int | None = None
    controllers: dict[str, Controller] = field(default_factory=dict)
    sections: set[str] = field(default_factory=set)  # every node name the file has parameters for


def _mapping(node: yaml.Node | None) -> dict[str, tuple[yaml.Node, yaml.Node]] | None:
    if not isinstance(node, yaml.MappingNode):
        return None
    return {str(k.value): (k, v) for k, v in node.value if isinstance(k, yaml.ScalarNode)}


def _line(node: yaml.Node) -> int:
    return int(node.start_mark.line) + 1


def read_controller_parameters(text: str, joint_parameters: dict[str, list[str]]) -> ControllerParameters:
    """The controllers a parameters file gives a controller manager, with their types and the
    joints their parameters name (`joint_parameters`: controller type → the parameters that name
    joints). A file rcl refuses gives `error` (and its line)."""
    found = ControllerParameters()
    refused = read_parameters(text).problem
    if refused is not None:
        found.error, found.error_line = refused.message, refused.line
        return found
    sections: dict[str, tuple[yaml.Node, yaml.Node]] = {}
    for root in compose_all(text):  # (rcl reads on from one document into the next)
        for name, section in _node_sections(root, found).items():
            sections.setdefault(name, section)
    for _name, (_key, parameters) in sections.items():
        for entry, (entry_key, value) in (_mapping(parameters) or {}).items():
            spec = _mapping(value)
            type_node = spec["type"][1] if spec is not None and "type" in spec else None
            # a controller type is always package/Class (a parameter named type is something else)
            if not isinstance(type_node, yaml.ScalarNode) or "/" not in str(type_node.value):
                continue
            controller = Controller(entry, _line(entry_key), str(type_node.value), _line(type_node))
            found.controllers.setdefault(entry, controller)
    for name, (key, parameters) in sections.items():
        # from Jazzy on a controller's own section may give its type (gz_ros2_control's demos:
        # diff_drive_base_controller: ros__parameters: type: ...)
        spec = _mapping(parameters)
        type_node = spec["type"][1] if spec is not None and "type" in spec else None
        if isinstance(type_node, yaml.ScalarNode) and "/" in str(type_node.value):
            found.controllers.setdefault(
                name, Controller(name, _line(key), str(type_node.value), _line(type_node))
            )
    for controller in found.controllers.values():
        own = sections.get(controller.name)
        for parameter in joint_parameters.get(controller.type or "", []):
            given = (_mapping(own[1]) or {}).get(parameter) if own is not None else None
            for item in _scalars(given[1] if given is not None else None):
                controller.joints.append(JointUse(parameter, str(item.value), _line(item)))
    return found


def _node_sections(root: yaml.Node, found: ControllerParameters) -> dict[str, tuple[yaml.Node, yaml.Node]]:
    """node name (its last part: /robot/controller_manager → controller_manager) → (key, its
    ros__parameters mapping); a node's parameters may sit under namespace keys (rcl nests them)."""
    sections: dict[str, tuple[yaml.Node, yaml.Node]] = {}
    top = _mapping(root)
    if top is None:  # (rcl refuses it: read_parameters said so first)
        return sections

    def visit(entries: dict[str, tuple[yaml.Node, yaml.Node]], depth: int) -> None:
        for name, (key, value) in entries.items():
            inner = _mapping(value)
            if inner is None or depth > 8:
                continue
            if "ros__parameters" in inner:
                short = name.strip("/").rsplit("/", 1)[-1]
                found.sections.add(short)
                sections.setdefault(short, (key, inner["ros__parameters"][1]))
            else:
                visit(inner, depth + 1)

    visit(top, 0)
    return sections


def _scalars(node: yaml.Node | None) -> list[yaml.ScalarNode]:
    if isinstance(node, yaml.ScalarNode):
        return [node] if node.value else []
    if isinstance(node, yaml.SequenceNode):
        return [item for item in node.value if isinstance(item, yaml.ScalarNode) and item.value]
    return []
