"""Robot models: the real xacro (xacro_run.py), then the URDF's structure as plain data.

Runs in the launch worker (xacro evaluates ${} and $(eval) expressions: user
code). The result names every link, joint and mesh URI with the file and line
a person would edit: the element's own line in a plain URDF; for xacro, the
line in the model or its includes where the name is written, else the file.
"""

from __future__ import annotations

import bisect
import re

from lxml import etree

from pkgforge.model.source import FileTooLarge, NotRegularFile, read_regular
from pkgforge.urdf.ros1_xacro import ros1_tags
from pkgforge.urdf.structure import (
    ControlJoint,
    ControlSystem,
    GazeboPlugin,
    Geometry,
    Inertial,
    Limit,
    LinkDict,
    MeshKind,
    ModelReply,
    Origin,
    Part,
    RobotStructure,
)
from pkgforge.urdf.urdfdom import problems
from pkgforge.urdf.xacro_run import EXPRESSION, LIBXML_TOO_DEEP, MAX_MODEL_BYTES, MAX_XML_DEPTH, expand

Element = etree._Element
Place = tuple[str, int]  # (file, line)


class Sources:
    """(tag, name) → (file, line) across a model's files: where the name (a mesh's filename) is
    written literally, else where a template of it is written (`<link name="${arm_id}_link1">`
    for panda_link1, in the macro that makes it): of the templates that match, the one with the
    most literal text, the first of the files when two have as much. A template that is nothing
    but an expression (`name="${name}"`) stands for a name only when it is the only one of its tag."""

    def __init__(self) -> None:
        self.literal: dict[tuple[str, str], Place] = {}
        # tag → [(the value as a pattern, its literal characters, file, line)]
        self.templates: dict[str, list[tuple[re.Pattern[str], int, str, int]]] = {}

    def add(self, tag: str, value: str, place: Place) -> None:
        if EXPRESSION.search(value) is None:
            self.literal.setdefault((tag, value), place)
            return
        pieces = EXPRESSION.split(value)
        pattern = re.compile(".*".join(re.escape(piece) for piece in pieces))
        self.templates.setdefault(tag, []).append((pattern, sum(map(len, pieces)), *place))

    def get(self, key: tuple[str, str | None], default: tuple[str, int | None]) -> tuple[str, int | None]:
        found = self.find(*key)
        return default if found is None else found

    def find(self, tag: str, name: str | None) -> Place | None:
        if name is None:
            return None
        if (tag, name) in self.literal:
            return self.literal[(tag, name)]
        templates = self.templates.get(tag, [])
        matching = [t for t in templates if t[0].fullmatch(name)]
        best = max((t[1] for t in matching), default=0)
        if best == 0 and len(templates) != 1:
            return None  # only bare expressions match, and there are several: any of them
        for _, literal, file, line in matching:
            if literal == best:
                return file, line
        return None


GEOMETRY_URI_TAGS = ("mesh",)


def process_model(path: str, mappings: dict[str, str]) -> ModelReply:
    """xacro (or plain URDF) → {status, error, robot: {links, joints, meshes, ...}}."""
    try:
        data = read_regular(path, MAX_MODEL_BYTES)  # a FIFO, /dev/zero: refused, never read
    except FileTooLarge as error:
        return {
            "status": "too-large",
            "error": {
                "message": f"{error.size / 1e6:.1f} MB; pkgforge processes models up to {MAX_MODEL_BYTES // 2**20} MB",
                "file": path,
                "line": None,
            },
        }
    except NotRegularFile as error:
        return {"status": "error", "error": {"message": str(error.strerror), "file": path, "line": None}}
    except OSError as error:
        return {"status": "error", "error": {"message": str(error), "file": path, "line": None}}
    try:
        data[:4096].decode("utf-8")
    except UnicodeDecodeError:
        return {
            "status": "error",
            "error": {
                "message": "not a text file (binary data, not XML)",
                "file": path,
                "line": 1,
                "stage": "xml",
            },
        }
    output = expand(path, data.decode("utf-8", errors="replace"), mappings)
    if not isinstance(output, tuple):
        return output
    text, includes = output
    try:
        root = parse_model_xml(text)
    except etree.XMLSyntaxError as exc:
        return {
            "status": "error",
            "error": {
                "message": xml_problem(exc),
                "file": path,
                "line": exc.lineno,
                "stage": "xml",
            },
        }
    expanded = includes is not None
    files = [path, *(includes or [])]
    sources = _name_index(files) if expanded else Sources()
    robot = _structure(root, path, sources, expanded, files)
    # xacro ran (or the file uses none of it) with ROS 1's bare tags left in as plain elements
    robot["ros1_tags"] = ros1_tags(files)
    return {"status": "ok", "error": None, "includes": includes or [], "robot": robot}


def xml_problem(exc: etree.XMLSyntaxError) -> str:
    """lxml's error in words about the file (its line is the error's)."""
    if exc.msg and exc.msg.startswith(LIBXML_TOO_DEEP):  # libxml2's bound, named by its option
        return f"elements nest deeper than {MAX_XML_DEPTH} levels: pkgforge reads XML up to that depth"
    return f"not well-formed XML: {exc.msg}"


def parse_model_xml(text: str) -> etree._Element:
    """A processed model as robot_state_publisher reads it: urdfdom parses with tinyxml2, which
    knows no namespaces, so a prefix nobody declared (c300's gz:expressed_in inside <gazebo>) is
    no error there and none here; any other XML error raises XMLSyntaxError as lxml's own."""
    data = text.encode("utf-8")
    try:
        return etree.fromstring(data, etree.XMLParser(remove_comments=True, huge_tree=False))
    except etree.XMLSyntaxError:
        lenient = etree.XMLParser(remove_comments=True, huge_tree=False, recover=True)
        root = etree.fromstring(data, lenient)
        other = next((e for e in lenient.error_log if e.domain_name != "NAMESPACE"), None)
        if other is not None:
            raise etree.XMLSyntaxError(other.message, other.type, other.line, other.column) from None
        if root is None:
            raise
        return root


def structure_of_output(path: str, urdf: str, includes: list[str]) -> RobotStructure | None:
    """The structure of a xacro output produced elsewhere (a launch file's Command), or None."""
    try:
        root = parse_model_xml(urdf)
    except etree.XMLSyntaxError:
        return None
    files = [path, *includes]
    return _structure(root, path, _name_index(files), True, files)


NAME_ATTRIBUTE = re.compile(
    r"<\s*(link|joint)\b[^>]*?\bname\s*=\s*\"([^\"]+)\"|<\s*(link|joint)\b[^>]*?\bname\s*=\s*'([^']+)'"
)
MESH_ATTRIBUTE = re.compile(
    r"<\s*(mesh|texture)\b[^>]*?\bfilename\s*=\s*\"([^\"]+)\"|<\s*(mesh|texture)\b[^>]*?\bfilename\s*=\s*'([^']+)'"
)
JOINT_TYPE = re.compile(r"\btype\s*=")


def _name_index(files: list[str]) -> Sources:
    """(tag, name) → (file, line) across the model's files (Sources: literal names and templates).

    A tag may span lines (SolidWorks exports write `<joint` and `name=` on lines of their
    own), so the patterns run over the whole text. A `<joint>` without `type=` is not a
    URDF joint but a ros2_control or transmission one naming it: never its place.
    """
    index = Sources()
    for file in files:
        try:
            with open(file, encoding="utf-8", errors="replace") as handle:
                text = handle.read()
        except OSError:
            continue
        text = re.sub(r"<!--.*?-->", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S)
        newlines = [offset for offset, char in enumerate(text) if char == "\n"]
        for pattern in (NAME_ATTRIBUTE, MESH_ATTRIBUTE):
            for match in pattern.finditer(text):
                tag, value = match.group(1) or match.group(3), match.group(2) or match.group(4)
                end = text.find(">", match.end())
                if tag == "joint" and not JOINT_TYPE.search(
                    text, match.start(), end if end >= 0 else len(text)
                ):
                    continue
                index.add(tag, value, (file, bisect.bisect_left(newlines, match.start()) + 1))
    return index


class _Texts:
    """The model's files as text, read once, to find where an attribute's value is written."""

    def __init__(self, files: list[str]):
        self.files = list(dict.fromkeys(files))
        self.texts: dict[str, str] = {}

    def text(self, file: str) -> str:
        if file not in self.texts:
            try:
                with open(file, encoding="utf-8", errors="replace") as handle:
                    self.texts[file] = handle.read(MAX_MODEL_BYTES)
            except OSError:
                self.texts[file] = ""
        return self.texts[file]

    def written_once(self, tag: str, attribute: str, value: str) -> tuple[str, int] | None:
        """(file, line) of the one `<tag ... attribute="value"` across the files, or None when it
        is written nowhere literally (an expression) or more than once."""
        pattern = re.compile(rf"\b{re.escape(attribute)}\s*=\s*([\"']){re.escape(value)}\1")
        found: list[tuple[str, int]] = []
        for file in self.files:
            text = self.text(file)
            for match in pattern.finditer(text):
                start = text.rfind("<", 0, match.start())
                if re.match(rf"<\s*{re.escape(tag)}[\s/>]", text[start:]):
                    found.append((file, text.count("\n", 0, match.start()) + 1))
                    if len(found) > 1:
                        return None
        return found[0] if found else None

    def first_written(
        self, tag: str, attribute: str | None, value: str, untyped: bool = False
    ) -> tuple[str, int] | None:
        """(file, line) of the first `<tag ... attribute="value"` across the files (`attribute`
        None: `<tag>value</tag>`); `untyped`: only a tag without type= (a ros2_control <joint>,
        not the URDF joint of that name)."""
        if attribute is None:
            pattern = re.compile(rf"<\s*{re.escape(tag)}\s*>\s*{re.escape(value)}\s*<")
        else:
            pattern = re.compile(rf"\b{re.escape(attribute)}\s*=\s*([\"']){re.escape(value)}\1")
        for file in self.files:
            text = self.text(file)
            for match in pattern.finditer(text):
                start = match.start() if attribute is None else text.rfind("<", 0, match.start())
                if not re.match(rf"<\s*{re.escape(tag)}[\s/>]", text[start:]):
                    continue
                end = text.find(">", start)
                if untyped and JOINT_TYPE.search(text, start, end if end >= 0 else len(text)):
                    continue
                return file, text.count("\n", 0, match.start()) + 1
        return None


def _structure(
    root: Element, path: str, sources: Sources, expanded: bool, files: list[str] | None = None
) -> RobotStructure:
    plain = not expanded  # element lines are the file's own lines
    texts = _Texts(files or [path])

    def where(element: Element, tag: str | None = None, name: str | None = None) -> tuple[str, int | None]:
        found = sources.find(tag, name) if tag and not plain else None
        if found is not None:
            return found
        return (path, element.sourceline if plain else None)

    def place(
        element: Element, attribute: str | None, owner: tuple[str, str | None]
    ) -> tuple[str, int | None]:
        """Where a person edits what urdfdom refuses: the element's line in a plain file; in xacro
        output, where the attribute's value is written (once), else its link's or joint's line."""
        if plain:
            return path, element.sourceline
        value = element.get(attribute) if attribute else None
        written = texts.written_once(str(element.tag), attribute, value) if attribute and value else None
        if written is not None:
            return written
        return where(element, *owner)

    robot: RobotStructure = {
        "root_tag": root.tag if isinstance(root.tag, str) else None,
        "name": root.get("name"),
        "links": [],
        "joints": [],
        "meshes": [],
        "urdfdom": [],
        "ros1_tags": [],
        "joint_users": {},
        "gazebo_plugins": [],
        "ros2_control": [],
    }
    if root.tag != "robot":
        return robot
    robot["urdfdom"] = problems(root, place)
    materials = _materials(root)
    for link in root.findall("link"):
        name = link.get("name")
        file, line = where(link, "link", name)
        inertial, visuals, collisions = _physical_link(link, materials, plain and line)
        entry: LinkDict = {
            "name": name,
            "file": file,
            "line": line,
            "inertial": inertial,
            "visuals": visuals,
            "collisions": collisions,
        }
        robot["links"].append(entry)
        kinds: tuple[MeshKind, ...] = ("visual", "collision")
        for kind in kinds:
            for part in link.findall(kind):
                for mesh in part.iter(*GEOMETRY_URI_TAGS):
                    uri = mesh.get("filename")
                    if uri:
                        mesh_file, mesh_line = (
                            (path, mesh.sourceline) if plain else sources.get(("mesh", uri), (file, line))
                        )
                        robot["meshes"].append(
                            {"uri": uri, "link": name, "kind": kind, "file": mesh_file, "line": mesh_line}
                        )
    for material in root.iter("texture"):
        if texture := material.get("filename"):
            texture_file, texture_line = (
                (path, material.sourceline) if plain else sources.get(("texture", texture), (path, None))
            )
            robot["meshes"].append(
                {"uri": texture, "link": None, "kind": "texture", "file": texture_file, "line": texture_line}
            )
    for joint in root.findall("joint"):
        name = joint.get("name")
        file, line = where(joint, "joint", name)
        parent, child = joint.find("parent"), joint.find("child")
        axis, limit = _physical_joint(joint, plain and line)
        robot["joints"].append(
            {
                "name": name,
                "type": joint.get("type"),
                "file": file,
                "line": line,
                "parent": parent.get("link") if parent is not None else None,
                "child": child.get("link") if child is not None else None,
                "origin": _origin(joint),
                "axis": axis,
                "limit": limit,
            }
        )
    robot["joint_users"] = _joint_users(root, {j["name"] for j in robot["joints"] if j["name"]})
    robot["gazebo_plugins"] = _gazebo_plugins(root, path, plain, texts)
    robot["ros2_control"] = _control_systems(root, path, plain, texts)
    return robot


def _joint_users(root: Element, joints: set[str]) -> dict[str, str]:
    """joint → what in the model enforces its limits: a <ros2_control> block naming it (its
    hardware interface and controllers), else a Gazebo plugin naming it in one of its elements
    (gazebo_ros_diff_drive's <left_joint>, a joint state plugin's <joint_name>)."""
    users: dict[str, str] = {}
    for block in root.iter("ros2_control"):
        for joint in block.iter("joint"):
            name = joint.get("name")
            if name in joints:
                users.setdefault(name, "<ros2_control>")
    for gazebo in root.iter("gazebo"):
        for plugin in gazebo.iter("plugin"):
            what = plugin.get("filename") or plugin.get("name") or "plugin"
            for element in plugin.iter():
                text = (element.text or "").strip() if isinstance(element.tag, str) else ""
                for name in {text, element.get("name") if element.tag == "joint" else None}:
                    if name in joints:
                        users.setdefault(name, f"Gazebo plugin {what}")
    return users


def _written(
    element: Element, path: str, plain: bool, found: tuple[str, int] | None, fallback: tuple[str, int | None]
) -> tuple[str, int | None]:
    """Where a person edits an element: its line in a plain file; in xacro output, where its
    identifying value is first written, else `fallback`."""
    if plain:
        return path, element.sourceline
    return found if found is not None else fallback


def _gazebo_plugins(root: Element, path: str, plain: bool, texts: _Texts) -> list[GazeboPlugin]:
    plugins: list[GazeboPlugin] = []
    for gazebo in root.findall("gazebo"):
        for plugin in gazebo.iter("plugin"):
            filename = (plugin.get("filename") or "").strip()
            if not filename:
                continue
            file, line = _written(
                plugin, path, plain, texts.first_written("plugin", "filename", filename), (path, None)
            )
            parameters = [(p.text or "").strip() for p in plugin.iter("parameters") if (p.text or "").strip()]
            plugins.append(
                {
                    "filename": filename,
                    "name": plugin.get("name"),
                    "parameters": parameters,
                    "file": file,
                    "line": line,
                }
            )
    return plugins


def _control_systems(root: Element, path: str, plain: bool, texts: _Texts) -> list[ControlSystem]:
    systems: list[ControlSystem] = []
    for control in root.findall("ros2_control"):
        name = control.get("name")
        found = texts.first_written("ros2_control", "name", name) if name else None
        file, line = _written(control, path, plain, found, (path, None))
        hardware = control.find("hardware/plugin")
        plugin = (hardware.text or "").strip() if hardware is not None else None
        plugin_place = (
            _written(hardware, path, plain, texts.first_written("plugin", None, plugin), (file, line))
            if hardware is not None and plugin
            else (file, line)
        )
        joints: list[ControlJoint] = []
        for kind in ("joint", "sensor", "gpio"):
            for joint in control.findall(kind):
                joint_name = joint.get("name")
                written = texts.first_written(kind, "name", joint_name, untyped=True) if joint_name else None
                joint_file, joint_line = _written(joint, path, plain, written, (file, line))
                joints.append(
                    {
                        "name": joint_name,
                        "kind": kind,
                        "command": [i.get("name") or "" for i in joint.findall("command_interface")],
                        "state": [i.get("name") or "" for i in joint.findall("state_interface")],
                        "file": joint_file,
                        "line": joint_line,
                    }
                )
        systems.append(
            {
                "name": name,
                "type": control.get("type"),
                "plugin": plugin,
                "file": file,
                "line": line,
                "plugin_file": plugin_place[0],
                "plugin_line": plugin_place[1],
                "joints": joints,
            }
        )
    return systems


# --- the numbers physics and rendering need (pkgforge.urdf.physics, pkgforge.view) -------------------


def _numbers(text: str | None, count: int) -> list[float] | None:
    """`count` floats from a space-separated attribute; None when absent or not numbers."""
    if text is None:
        return None
    try:
        values = [float(word) for word in text.split()]
    except ValueError:
        return None
    return values if len(values) == count else None


def _number(text: str | None) -> float | None:
    values = _numbers(text, 1)
    return values[0] if values else None


def _origin(element: Element | None) -> Origin:
    origin = element.find("origin") if element is not None else None
    if origin is None:
        return {"xyz": [0.0, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]}
    return {
        "xyz": _numbers(origin.get("xyz", "0 0 0"), 3) or [0.0, 0.0, 0.0],
        "rpy": _numbers(origin.get("rpy", "0 0 0"), 3) or [0.0, 0.0, 0.0],
    }


def _color(material: Element | None) -> list[float] | None:
    color = material.find("color") if material is not None else None
    return _numbers(color.get("rgba"), 4) if color is not None else None


def _materials(root: Element) -> dict[str, list[float]]:
    colors = {m.get("name"): _color(m) for m in root.findall("material")}
    return {name: color for name, color in colors.items() if name and color}


def _geometry(part: Element) -> Geometry | None:
    geometry = part.find("geometry")
    shape = next(iter(geometry), None) if geometry is not None else None
    if shape is None or not isinstance(shape.tag, str):
        return None
    if shape.tag == "box":
        return {"type": "box", "size": _numbers(shape.get("size"), 3)}
    if shape.tag in ("cylinder", "capsule"):
        return {
            "type": shape.tag,
            "radius": _number(shape.get("radius")),
            "length": _number(shape.get("length")),
        }
    if shape.tag == "sphere":
        return {"type": "sphere", "radius": _number(shape.get("radius"))}
    if shape.tag == "mesh":
        return {
            "type": "mesh",
            "uri": shape.get("filename"),
            "scale": _numbers(shape.get("scale"), 3) or [1.0, 1.0, 1.0],
        }
    return {"type": shape.tag}


def _physical_link(
    link: Element, materials: dict[str, list[float]], line: int | bool | None
) -> tuple[Inertial | None, list[Part], list[Part]]:
    """A link's inertial and its visual and collision shapes, as plain numbers."""

    def line_of(element: Element) -> int | None:
        return element.sourceline if line else None

    inertial = link.find("inertial")
    data: Inertial | None = None
    parts: dict[str, list[Part]] = {"visual": [], "collision": []}
    if inertial is not None:
        mass, tensor = inertial.find("mass"), inertial.find("inertia")
        data = {
            "mass": _number(mass.get("value")) if mass is not None else None,
            "inertia": None
            if tensor is None
            else {k: _number(tensor.get(k)) or 0.0 for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")},
            "origin": _origin(inertial),
            "line": line_of(inertial),
        }
    for kind in ("visual", "collision"):
        for part in link.findall(kind):
            material = part.find("material") if kind == "visual" else None
            color = _color(material) or (
                materials.get(material.get("name") or "") if material is not None else None
            )
            shape = part.find("geometry")
            parts[kind].append(
                {
                    "geometry": _geometry(part),
                    "origin": _origin(part),
                    "color": color,
                    "line": line_of(next(iter(shape), part) if shape is not None else part),
                }
            )
    return data, parts["visual"], parts["collision"]


def _physical_joint(joint: Element, line: int | bool | None) -> tuple[list[float] | None, Limit | None]:
    """A joint's axis and limit, as plain numbers."""
    axis, limit = joint.find("axis"), joint.find("limit")
    return (
        None if axis is None else _numbers(axis.get("xyz", "1 0 0"), 3),
        None
        if limit is None
        else {
            "lower": _number(limit.get("lower")),
            "upper": _number(limit.get("upper")),
            "velocity": _number(limit.get("velocity")),
            "effort": _number(limit.get("effort")),
            "line": limit.sourceline if line else None,
        },
    )
