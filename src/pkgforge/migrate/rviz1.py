"""An RViz 1 config → an RViz 2 config: class names, the RobotModel's description, topics."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from pkgforge.errors import PkgforgeError
from pkgforge.model import ros1_names

if TYPE_CHECKING:
    from pkgforge.scaffold.notes import Notes

DESCRIPTION_TOPIC = {
    "Depth": 5,
    "Durability Policy": "Transient Local",
    "History Policy": "Keep Last",
    "Reliability Policy": "Reliable",
    "Value": "/robot_description",
}


def _topic(value: str) -> dict[str, str | int]:
    return {
        "Depth": 5,
        "Durability Policy": "Volatile",
        "History Policy": "Keep Last",
        "Reliability Policy": "Reliable",
        "Value": value,
    }


class _Lines:
    """The line of each `Class: X`, in file order (the YAML data keeps no lines)."""

    def __init__(self, text: str):
        self.lines = text.splitlines()
        self.position = 0

    def of(self, key: str, value: str) -> int | None:
        for index in range(self.position, len(self.lines)):
            stripped = self.lines[index].strip().lstrip("- ")
            if stripped.startswith(f"{key}:") and stripped.split(":", 1)[1].strip().strip("\"'") == value:
                self.position = index + 1
                return index + 1
        return None


def convert(
    text: str, path: Path, notes: Notes, links: set[str], root_link: str | None, by: str = "pkgforge migrate"
) -> str:
    """The RViz 2 config of an RViz 1 config's `text`; what it renamed, changed or left out goes to
    `notes`. With the model's `links`, a Fixed Frame that is none of them becomes `root_link`."""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        raise PkgforgeError(
            f"{path}:{mark.line + 1 if mark else 1}: not valid YAML ({getattr(exc, 'problem', exc)}): "
            "not an RViz config pkgforge can convert (nothing written)"
        ) from exc
    if not isinstance(data, dict) or "Visualization Manager" not in data:
        raise PkgforgeError(f"{path}:1: no 'Visualization Manager': not an RViz config (nothing written)")
    lines = _Lines(text)

    def walk(node: Any) -> bool:  # node: any part of the config's YAML data
        if isinstance(node, dict):
            cls = node.get("Class")
            if isinstance(cls, str) and cls:
                line = lines.of("Class", cls)
                if cls in ros1_names.RVIZ_CLASSES:
                    node["Class"] = ros1_names.RVIZ_CLASSES[cls]
                    notes.add("migrate-renamed", f"RViz class {cls} → {node['Class']}", path, line)
                elif not cls.startswith(("rviz_common/", "rviz_default_plugins/")):
                    notes.add(
                        "migrate-dropped",
                        f"RViz class {cls} has no RViz 2 equivalent pkgforge knows: left out",
                        path,
                        line,
                    )
                    return False
                if node["Class"] == "rviz_default_plugins/RobotModel":
                    node.pop("Robot Description", None)
                    node["Description File"] = ""
                    node["Description Source"] = "Topic"
                    node["Description Topic"] = dict(DESCRIPTION_TOPIC)
                    notes.add(
                        "migrate-changed",
                        "RobotModel: Robot Description parameter → Description Topic /robot_description",
                        path,
                        line,
                    )
                elif isinstance(node.get("Topic"), str):
                    node["Topic"] = _topic(node["Topic"])
                node.pop("Unreliable", None)
            for key, value in list(node.items()):
                if isinstance(value, list):
                    node[key] = [item for item in value if walk(item) is not False]
                elif isinstance(value, dict):
                    walk(value)
        return True

    walk(data)
    manager = data["Visualization Manager"]
    options = manager.setdefault("Global Options", {})
    frame = options.get("Fixed Frame")
    if links and frame not in links and root_link:
        line = _Lines(text).of("Fixed Frame", str(frame))
        notes.add(
            "migrate-generated",
            f"Fixed Frame '{frame}' is not a link of the model: set to its root link '{root_link}'",
            path,
            line,
        )
        options["Fixed Frame"] = root_link
    if isinstance(data.get("Window Geometry"), dict):
        data["Window Geometry"].pop("QMainWindow State", None)  # RViz 1's Qt layout, not RViz 2's
    return f"# Converted from RViz 1 {path.name} by {by}.\n" + yaml.safe_dump(
        data, sort_keys=False, default_flow_style=False, width=1000
    )
