"""RViz configs (.rviz, YAML): global options and displays, with lines."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TypedDict

import yaml

from pkgforge.model.source import read_source
from pkgforge.model.yamlnodes import compose, problem

ROBOT_MODEL = "rviz_default_plugins/RobotModel"
# the plugin namespace of RViz 1's own classes (rviz/RobotModel, rviz/Orbit, rviz/Displays): rviz2
# knows none of them (its own are rviz_common/ and rviz_default_plugins/)
RVIZ1_PREFIX = "rviz/"


# one display of an RViz config (a group's displays too), as the checks read it ("class" is a
# keyword: the functional form)
Display = TypedDict(
    "Display",
    {
        "class": "str | None",  # rviz_default_plugins/RobotModel …
        "line": int,  # its Class line, else its first line
        "name": "str | None",
        "enabled": bool,
        "source": "str | None",  # Description Source: Topic | File
        "topic": "str | None",
        "topic_line": "int | None",
        "file": "str | None",
        "file_line": "int | None",
    },
)


@dataclass
class RvizConfig:
    path: Path
    error: str | None = None
    error_line: int | None = None
    fixed_frame: str | None = None
    fixed_frame_line: int | None = None
    displays: list[Display] = field(default_factory=list)
    # every RViz 1 class (display, panel, tool, view) the config names, with its line, in file order
    ros1_classes: list[tuple[str, int]] = field(default_factory=list)


def _line(node: yaml.Node) -> int:
    return node.start_mark.line + 1


def _mapping(node: yaml.Node | None) -> dict[str, yaml.Node]:
    """key → value node, for a YAML mapping node."""
    if not isinstance(node, yaml.MappingNode):
        return {}
    return {key.value: value for key, value in node.value if isinstance(key, yaml.ScalarNode)}


def _scalar(node: yaml.Node | None) -> str | None:
    return node.value if isinstance(node, yaml.ScalarNode) else None


def read_rviz(path: Path) -> RvizConfig:
    config = RvizConfig(path)
    source = read_source(path)
    if source.text is None:
        config.error, config.error_line = source.problem, source.problem_line
        return config
    try:
        document = compose(source.text)
    except yaml.YAMLError as error:  # (past the reader's bounds too: it says which)
        mark = getattr(error, "problem_mark", None)
        config.error = problem(error)
        config.error_line = mark.line + 1 if mark else None
        return config
    manager = _mapping(document).get("Visualization Manager")
    if manager is None:
        config.error, config.error_line = "no 'Visualization Manager': not an RViz config", 1
        return config
    options = _mapping(_mapping(manager).get("Global Options"))
    if "Fixed Frame" in options:
        config.fixed_frame = _scalar(options["Fixed Frame"])
        config.fixed_frame_line = _key_lines(_mapping(manager).get("Global Options"))["Fixed Frame"]
    # a group's displays follow the group, in the file's order (no recursion: groups nest freely)
    todo = list(reversed(_sequence(_mapping(manager).get("Displays"))))
    while todo:
        node = todo.pop()
        if _display(node, config.displays):
            todo += reversed(_sequence(_mapping(node).get("Displays")))
    config.ros1_classes = _ros1_classes(document)
    return config


def _sequence(node: yaml.Node | None) -> list[yaml.Node]:
    return node.value if isinstance(node, yaml.SequenceNode) else []


def _ros1_classes(document: yaml.Node | None) -> list[tuple[str, int]]:
    """(class, line) of every `Class: rviz/...` anywhere in the config (panels, displays in
    groups, tools, views), in file order."""
    found: list[tuple[str, int]] = []
    stack = [document]
    while stack:
        node = stack.pop()
        if isinstance(node, yaml.MappingNode):
            klass = _mapping(node).get("Class")
            value = _scalar(klass)
            if klass is not None and value and value.startswith(RVIZ1_PREFIX):
                found.append((value, _line(klass)))
            stack.extend(value for _, value in node.value)
        elif isinstance(node, yaml.SequenceNode):
            stack.extend(node.value)
    return sorted(found, key=lambda item: item[1])


def _key_lines(node: yaml.Node | None) -> dict[str, int]:
    if not isinstance(node, yaml.MappingNode):
        return {}
    return {key.value: _line(key) for key, _ in node.value if isinstance(key, yaml.ScalarNode)}


def _display(node: yaml.Node, out: list[Display]) -> bool:
    """Add the display; whether it is a group (whose Displays are displays too)."""
    entries = _mapping(node)
    keys = _key_lines(node)
    klass = _scalar(entries.get("Class"))
    topic_node = entries.get("Description Topic")
    topic = (
        _scalar(_mapping(topic_node).get("Value"))
        if isinstance(topic_node, yaml.MappingNode)
        else _scalar(topic_node)
    )
    out.append(
        {
            "class": klass,
            "line": _line(entries["Class"]) if "Class" in entries else _line(node),
            "name": _scalar(entries.get("Name")),
            "enabled": (_scalar(entries.get("Enabled")) or "true").lower() == "true",
            "source": _scalar(entries.get("Description Source")),
            "topic": topic,
            "topic_line": keys.get("Description Topic"),
            "file": _scalar(entries.get("Description File")),
            "file_line": keys.get("Description File"),
        }
    )
    return klass == "rviz_common/Group"
