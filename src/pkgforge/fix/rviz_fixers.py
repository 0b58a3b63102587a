"""The fixers of RViz configs: a RobotModel's description, the fixed frame, a ROS 1 config."""

from __future__ import annotations

import json
import re
from typing import TYPE_CHECKING

from pkgforge.diagnostics import Diagnostic
from pkgforge.fix.edits import Edit, SourceText, Unfixable
from pkgforge.fix.registry import Fix, FixContext, fixer, given

if TYPE_CHECKING:  # imported where used: `pkgforge fix` loads only what its fixers need
    import yaml

ROBOT_DESCRIPTION_TOPIC = "/robot_description"


def _yaml(source: SourceText) -> yaml.Node | None:  # None: an empty file
    import yaml

    from pkgforge.model.yamlnodes import compose

    try:
        return compose(source.text)
    except yaml.YAMLError as exc:  # (past the reader's bounds too)
        raise Unfixable(f"{source.path.name} is not valid YAML") from exc


def _mapping(node: yaml.Node | None) -> dict[str, tuple[yaml.Node, yaml.Node]]:
    import yaml

    if not isinstance(node, yaml.MappingNode):
        return {}
    return {key.value: (key, value) for key, value in node.value if isinstance(key, yaml.ScalarNode)}


def _plain(value: str) -> str:
    return value if re.fullmatch(r"[A-Za-z_/][A-Za-z0-9_./\-]*", value) else json.dumps(value)


def _replace_scalar(node: yaml.Node, value: str) -> Edit:
    import yaml

    if not isinstance(node, yaml.ScalarNode):
        raise Unfixable("the value is not a plain scalar")
    if node.start_mark.index == node.end_mark.index:  # `Key:` with nothing after it
        return Edit(node.start_mark.index, node.end_mark.index, " " + _plain(value))
    return Edit(node.start_mark.index, node.end_mark.index, _plain(value))


def _find_display(node: yaml.Node | None, line: int) -> yaml.MappingNode | None:
    """The mapping whose Class value stands at `line` (a display, possibly in a group), the first
    in the file's order."""
    import yaml

    todo = [node]
    while todo:  # (no recursion: the config nests as deep as the reader lets it)
        current = todo.pop()
        if isinstance(current, yaml.MappingNode):
            entries = _mapping(current)
            if "Class" in entries and entries["Class"][1].start_mark.line + 1 == line:
                return current
            todo += reversed([value for _, value in current.value])
        elif isinstance(current, yaml.SequenceNode):
            todo += reversed(current.value)
    return None


def _insert_key(source: SourceText, mapping: yaml.MappingNode, key: str, lines: list[str]) -> Edit:
    """New `key` lines in a block mapping, in alphabetical order where RViz keeps its keys."""
    entries = list(mapping.value)
    column = entries[0][0].start_mark.column
    indent = source.text[source.line_start(entries[0][0].start_mark.line + 1) :][:column]
    indent = indent if indent.strip(" ") == "" else " " * column
    text = "".join(indent + line + source.eol for line in lines)
    previous = [(k, v) for k, v in entries if str(k.value) < key]
    if previous:
        value = previous[-1][1]
        end = value.end_mark
        offset = end.index if end.column == 0 else source.line_end(end.line + 1)
        return Edit(offset, offset, text, key)
    first = entries[0][0]
    if source.is_blank_before(first.start_mark.index):
        start = source.line_start(first.start_mark.line + 1)
        return Edit(start, start, text, key)
    value = entries[0][1]
    offset = value.end_mark.index if value.end_mark.column == 0 else source.line_end(value.end_mark.line + 1)
    return Edit(offset, offset, text, key)


@fixer("rviz-no-description")
def fix_rviz_description(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    import yaml

    line = (diagnostic.fix or {}).get("display_line")
    source = ctx.files.get(diagnostic.path)
    display = _find_display(_yaml(source), line) if line else None
    if display is None:
        raise Unfixable("cannot find the RobotModel display")
    entries = _mapping(display)
    fix = Fix(f"RobotModel: Description Source Topic, Description Topic {ROBOT_DESCRIPTION_TOPIC}")
    if "Description Source" in entries:
        value = entries["Description Source"][1]
        if getattr(value, "value", None) != "Topic":
            fix.add(source.path, _replace_scalar(value, "Topic"))
    else:
        fix.add(
            source.path, _insert_key(source, display, "Description Source", ["Description Source: Topic"])
        )
    if "Description Topic" in entries:
        value = entries["Description Topic"][1]
        if isinstance(value, yaml.MappingNode):
            inner = _mapping(value)
            if "Value" in inner:
                fix.add(source.path, _replace_scalar(inner["Value"][1], ROBOT_DESCRIPTION_TOPIC))
            else:
                fix.add(
                    source.path, _insert_key(source, value, "Value", [f"Value: {ROBOT_DESCRIPTION_TOPIC}"])
                )
        else:
            fix.add(source.path, _replace_scalar(value, ROBOT_DESCRIPTION_TOPIC))
    else:
        fix.add(
            source.path,
            _insert_key(
                source,
                display,
                "Description Topic",
                [
                    "Description Topic:",
                    "  Depth: 5",
                    "  Durability Policy: Transient Local",
                    "  History Policy: Keep Last",
                    "  Reliability Policy: Reliable",
                    f"  Value: {ROBOT_DESCRIPTION_TOPIC}",
                ],
            ),
        )
    return fix


@fixer("rviz-fixed-frame-unknown")
def fix_fixed_frame(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    frame = given(diagnostic, "frame", "the model's root link is not known")
    source = ctx.files.get(diagnostic.path)
    manager = _mapping(_yaml(source)).get("Visualization Manager")
    options = _mapping(manager[1]).get("Global Options") if manager else None
    fixed = _mapping(options[1]).get("Fixed Frame") if options else None
    if fixed is None:
        raise Unfixable("no Global Options: Fixed Frame to change")
    fix = Fix(f"Fixed Frame {getattr(fixed[1], 'value', '?')} → {frame} (the model's root link)")
    fix.add(source.path, _replace_scalar(fixed[1], frame))
    return fix


@fixer("rviz-ros1-config")
def fix_rviz1_config(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    """The whole config converted as `pkgforge migrate` converts one (unsafe: the file is written
    anew, its comments and RViz 1's window layout are not kept, classes RViz 2 lacks are left out)."""
    from pkgforge.errors import PkgforgeError
    from pkgforge.migrate.rviz1 import convert
    from pkgforge.scaffold.notes import Notes

    source = ctx.files.get(diagnostic.path)
    notes = Notes(diagnostic.package)
    try:
        converted = convert(source.text, source.path, notes, set(), None, by="pkgforge fix")
    except PkgforgeError as exc:
        raise Unfixable(str(exc).split(": ", 1)[-1]) from exc
    renamed = sum(1 for d in notes.diagnostics if d.name == "migrate-renamed")
    dropped = sum(1 for d in notes.diagnostics if d.name == "migrate-dropped")
    fix = Fix(
        f"converted to RViz 2: {renamed} class(es) renamed"
        + (f", {dropped} without an RViz 2 class left out" if dropped else "")
    )
    fix.add(source.path, Edit(0, len(source.text), converted.replace("\n", source.eol)))
    return fix
