"""ROS 1's un-prefixed xacro tags: <macro>, <property>, <include>, <arg>, <if>, <unless>.

ROS 1's xacro took them (deprecated since Jade) as if written xacro:macro ...; ROS 2's xacro
matches the tag name with its prefix (eval_all: node.tagName == 'xacro:macro') and evaluates any
other element as an ordinary one: a bare <macro> stays in the output, its body evaluated on the
spot (the Python NameError of a macro parameter), a bare <property> defines nothing, <include>
includes nothing, <if> keeps its content whatever the condition. Runs in the model worker on the
files xacro read.
"""

from __future__ import annotations

import re

from lxml import etree

from pkgforge.urdf.structure import Ros1Tag

# the bare tag → the attribute ROS 1's xacro required of it (an element without it is something else)
TAGS = {
    "macro": "name",
    "property": "name",
    "include": "filename",
    "arg": "name",
    "if": "value",
    "unless": "value",
}
# elements that hold another format's XML (SDF inside <gazebo>, plugin parameters): their <include>
# or <arg> is no xacro tag
FOREIGN = frozenset(
    {"gazebo", "plugin", "ros2_control", "hardware", "sensor", "transmission", "sdf", "world"}
)
CANDIDATE = re.compile(rb"<\s*(?:macro|property|include|arg|if|unless)[\s/>]")
MAX_BYTES = 8 * 1024 * 1024


def ros1_tags(files: list[str]) -> list[Ros1Tag]:
    """Every un-prefixed xacro tag in `files` (in file order), inside <robot> and outside the
    elements that hold other formats."""
    found: list[Ros1Tag] = []
    for file in dict.fromkeys(files):
        try:
            with open(file, "rb") as handle:
                data = handle.read(MAX_BYTES)
        except OSError:
            continue
        if not CANDIDATE.search(data):
            continue
        parser = etree.XMLParser(recover=True, resolve_entities=False, no_network=True, huge_tree=False)
        try:
            root = etree.fromstring(data, parser)
        except etree.XMLSyntaxError:
            continue
        if root is None or root.tag != "robot":
            continue
        for element in root.iter(*TAGS):
            if element.get(TAGS[str(element.tag)]) is None:
                continue
            if any(isinstance(a.tag, str) and a.tag in FOREIGN for a in element.iterancestors()):
                continue
            found.append({"tag": str(element.tag), "file": file, "line": element.sourceline})
    return found


def describe(tags: list[Ros1Tag], model: str) -> str:
    """`<macro> (line 12), <property> (lines 3, 4) of x.xacro`: the tags by kind and file, in order."""
    parts: list[str] = []
    for file in dict.fromkeys(tag["file"] for tag in tags):
        kinds: dict[str, list[str]] = {}
        for tag in tags:
            if tag["file"] == file:
                kinds.setdefault(tag["tag"], []).append(str(tag["line"]))
        shown = ", ".join(
            f"<{kind}> (line{'s' if len(lines) > 1 else ''} {', '.join(lines[:5])}"
            + (f" and {len(lines) - 5} more" if len(lines) > 5 else "")
            + ")"
            for kind, lines in kinds.items()
        )
        parts.append(shown if file == model else f"{shown} in {file.rsplit('/', 1)[-1]}")
    return "; ".join(parts)
