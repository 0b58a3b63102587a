"""What urdfdom, the URDF parser of robot_state_publisher, RViz and Gazebo's URDF import, refuses
or silently drops in a processed model: read in its order, with its rules (ros/urdfdom
urdf_parser/src/model.cpp, link.cpp, joint.cpp, pose.cpp; urdfdom_headers' Vector3, Color and
strToDouble), the same in humble's 3.0 and jazzy's 4.0.

Runs in the model worker on the processed model; each problem names the element a person edits
(`Locate`: the element's own line in a plain URDF; for xacro output, the line where the offending
attribute's value is written when it is written once, else the link's or joint's line).

- `model`: urdfdom returns no model: robot_state_publisher exits at start, RViz shows no robot
  (a joint it cannot parse, a top-level material named twice, a <robot> without a name).
- `part`: urdfdom keeps the link but drops the <inertial>, <visual> or <collision> it cannot
  parse, and every part it would have read after it (parseLink stops at the first failure and
  model.cpp ignores its result).
- `color`: a material drawn in another colour than written (a malformed rgba, a name defined twice
  with two colours: the first wins, a name used before any <material> defines it).
- `mimic`: a moving joint's <mimic> naming no moving joint of the model (urdfdom does not look;
  joint_state_publisher and robot_state_publisher do).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Literal

from lxml import etree

from pkgforge.urdf.structure import UrdfProblem

Element = etree._Element
# (element, the attribute whose value is at fault or None, the owner: ("link"|"joint", name)) → place
Locate = Callable[[Element, "str | None", "tuple[str, str | None]"], "tuple[str, int | None]"]
Effect = Literal["model", "part", "color", "mimic"]

# std::stringstream >> double in the C locale, then eof required (urdfdom_headers' strToDouble):
# leading blanks are skipped, nothing may follow; no inf, nan, hex or decimal comma
CXX_DOUBLE = re.compile(r"\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
JOINT_TYPES = ("planar", "floating", "revolute", "continuous", "prismatic", "fixed")
SHAPES = ("sphere", "box", "cylinder", "mesh")
INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
REFUSED = "urdfdom refuses the whole model: robot_state_publisher exits at start and RViz shows no robot"


def is_double(text: str) -> bool:
    return CXX_DOUBLE.fullmatch(text) is not None


def _or(element: Element | None, other: Element) -> Element:
    """`element`, else `other` (an lxml element without children is false: never `or` them)."""
    return element if element is not None else other


def _children(element: Element) -> list[Element]:
    return [child for child in element if isinstance(child.tag, str)]


def _first(element: Element, tag: str) -> Element | None:
    return next((child for child in _children(element) if child.tag == tag), None)


def _vector(text: str) -> str | None:
    """Why urdfdom's Vector3::init refuses the text (split at single spaces, 3 numbers), or None."""
    pieces = [piece for piece in text.split(" ") if piece]
    bad = next((piece for piece in pieces if not is_double(piece)), None)
    if bad is not None:
        return f"'{bad}' is not a number"
    if len(pieces) != 3:
        return f"{len(pieces)} value(s), not 3"
    return None


def _pose(origin: Element | None) -> tuple[str, str] | None:
    """(attribute, why) when urdfdom cannot read an <origin>, else None."""
    if origin is None:
        return None
    for attribute in ("xyz", "rpy"):
        value = origin.get(attribute)
        why = _vector(value) if value is not None else None
        if why is not None:
            return attribute, f'<origin {attribute}="{value}">: {why}'
    return None


def _scalar(element: Element, attribute: str, *, required: bool) -> str | None:
    """Why urdfdom refuses the attribute as one number (absent: only when required), or None."""
    value = element.get(attribute)
    if value is None:
        return f"no {attribute}=" if required else None
    if not is_double(value):
        return f'{attribute}="{value}" is not a number'
    return None


class Problems:
    """The problems found, each placed; one per element at fault, and one per place: a macro's
    defect expanded for several links or joints is one problem naming them."""

    def __init__(self, locate: Locate):
        self.locate = locate
        self.found: list[UrdfProblem] = []
        # (effect, file, line, the message after its owner) → (index in found, the owners' names)
        self.places: dict[tuple[str, str, int, str], tuple[int, list[str]]] = {}

    def first(self, material: Element, name: str) -> str:
        """' (first at file:line)' of a material's first definition, when its place is known."""
        file, line = self.locate(material, "name", ("material", name))
        return f" (first at {file.rsplit('/', 1)[-1]}:{line})" if line else ""

    def add(
        self,
        effect: Effect,
        message: str,
        element: Element,
        attribute: str | None,
        owner: tuple[str, str | None],
        part: str | None = None,
    ) -> None:
        file, line = self.locate(element, attribute, owner)
        prefix = f"{owner[0]} '{owner[1]}'"
        rest = message.removeprefix(prefix)
        if line is not None and rest != message:
            key = (effect, file, line, rest)
            if key in self.places:
                index, names = self.places[key]
                names.append(str(owner[1]))
                kind = f"{owner[0]}s"
                self.found[index]["message"] = f"{kind} {', '.join(repr(n) for n in names)}{rest}"
                return
            self.places[key] = (len(self.found), [str(owner[1])])
        self.found.append(
            {
                "effect": effect,
                "message": message,
                "file": file,
                "line": line,
                "link": owner[1] if owner[0] == "link" else None,
                "part": part,
            }
        )


def problems(root: Element, locate: Locate) -> list[UrdfProblem]:
    """What urdfdom refuses or drops in a model whose root is <robot>, in urdfdom's order."""
    found = Problems(locate)
    if root.get("name") is None:
        found.add("model", f"<robot> has no name=: {REFUSED}", root, None, ("robot", None))
    materials = _top_materials(root, found)
    colors = MaterialUses()
    for link in root.findall("link"):
        _link(link, materials, colors, found)
    colors.count(found)
    _joints(root, found)
    return found.found


# --- materials -------------------------------------------------------------------------------------

# a material as urdfdom keeps it: its colour (None: a texture only), and where it was defined
Material = tuple["tuple[float, ...] | None", Element]


def _color(material: Element) -> tuple[tuple[float, ...] | None, str | None, bool]:
    """(the colour urdfdom reads, why the rgba is malformed, whether it reads the material at all):
    Color::init throws on a piece that is not a number in [0, 1] (no colour: the material has only
    its texture, if any) and returns false on a count other than 4 after clearing the colour to
    black, which parseMaterial does not look at (the material is black)."""
    color = _first(material, "color")
    rgba = color.get("rgba") if color is not None else None
    texture = _first(material, "texture")
    has_texture = texture is not None and texture.get("filename") is not None
    if rgba is None:
        return None, None, has_texture
    pieces = [piece for piece in rgba.split(" ") if piece]
    for piece in pieces:
        if not is_double(piece) or not 0 <= float(piece) <= 1:
            return None, f"<color rgba=\"{rgba}\">: '{piece}' is not a number from 0 to 1", has_texture
    if len(pieces) != 4:
        return (0.0, 0.0, 0.0, 1.0), f'<color rgba="{rgba}"> has {len(pieces)} value(s), not 4', True
    return tuple(float(piece) for piece in pieces), None, True


def _top_materials(root: Element, found: Problems) -> dict[str, Material]:
    """The <material>s directly under <robot>, read before any link (model.cpp): a name defined
    twice refuses the model; a malformed colour leaves the material black (its result unread)."""
    materials: dict[str, Material] = {}
    for material in root.findall("material"):
        name = material.get("name")
        if name is None:
            continue  # urdfdom logs it and keeps a material without a name: nothing refers to it
        if name in materials:
            found.add(
                "model",
                f"material '{name}' is defined twice under <robot>{found.first(materials[name][1], name)}"
                f": {REFUSED} ('material {name} is not unique')",
                material,
                "name",
                ("material", name),
            )
            continue
        color, malformed, _ = _color(material)
        if malformed is not None:
            found.add(
                "color",
                f"material '{name}': {malformed}: urdfdom reads it as black",
                _or(_first(material, "color"), material),
                "rgba",
                ("material", name),
            )
            color = (0.0, 0.0, 0.0, 1.0)
        materials[name] = (color, material)
    return materials


def _same(one: tuple[float, ...] | None, other: tuple[float, ...] | None) -> bool:
    if one is None or other is None:
        return one is other
    return all(abs(a - b) < 1e-6 for a, b in zip(one, other, strict=True))


class MaterialUses:
    """One finding per material name: the first visual that gets another colour than written, and
    how many visuals do."""

    def __init__(self) -> None:
        self.first: dict[str, int] = {}  # name → index of its finding in Problems.found
        self.visuals: dict[str, int] = {}

    def said(self, name: str) -> bool:
        if name in self.first:
            self.visuals[name] += 1
            return True
        return False

    def add(self, name: str, found: Problems) -> None:
        self.first[name], self.visuals[name] = len(found.found) - 1, 1

    def count(self, found: Problems) -> None:
        for name, index in self.first.items():
            if self.visuals[name] > 1:
                found.found[index]["message"] += f" ({self.visuals[name]} visuals in all)"


def _visual_material(
    link: Element, visual: Element, materials: dict[str, Material], uses: MaterialUses, found: Problems
) -> None:
    """assignMaterial: a name already defined (under <robot> or by an earlier visual) gives that
    material, whatever the visual writes; else the visual's own, when urdfdom could read it; else
    none (RViz draws the link in its default colour)."""
    material = _first(visual, "material")
    name = material.get("name") if material is not None else None
    if material is None or name is None:
        return
    owner = ("link", link.get("name"))
    color, malformed, readable = _color(material)
    # an empty name: assignMaterial returns at once, the visual keeps what it wrote (SolidWorks'
    # exporter writes <material name=""> with each link's own colour)
    known = materials.get(name) if name else None
    where = f"link '{link.get('name')}'"
    if not name:
        if malformed is not None:
            effect = "urdfdom reads it as black" if readable else "RViz draws the link in its default colour"
            found.add("color", f"{where}: {malformed}: {effect}", material, "rgba", owner)
        return
    if known is None and readable:
        materials[name] = (color, material)
    if malformed is not None:
        if uses.said(name):
            return
        if known is not None:
            effect = f"drawn in the colour of the earlier material '{name}'"
        elif readable:
            effect = "urdfdom reads it as black"
        else:
            effect = "urdfdom drops the material and RViz draws the link in its default colour"
        found.add("color", f"{where}: material '{name}': {malformed}: {effect}", material, "rgba", owner)
        uses.add(name, found)
    elif known is not None and readable and not _same(color, known[0]):
        if uses.said(name):
            return
        found.add(
            "color",
            f"{where}: material '{name}' is given another colour than where it is first defined"
            f"{found.first(known[1], name)}: urdfdom keeps the first definition, and the link is "
            "drawn with it",
            _or(_first(material, "color"), material),
            "rgba",
            owner,
        )
        uses.add(name, found)
    elif known is None and not readable:
        if uses.said(name):
            return
        found.add(
            "color",
            f"{where}: material '{name}' is defined by no <material> before it (urdfdom reads them "
            "in order): RViz draws the link in its default colour",
            material,
            "name",
            owner,
        )
        uses.add(name, found)


# --- links -----------------------------------------------------------------------------------------


def _geometry(part: Element) -> tuple[Element, str | None, str] | None:
    """(element, attribute, why) when urdfdom cannot read a part's <geometry>, else None."""
    geometry = _first(part, "geometry")
    if geometry is None:
        return part, None, "no <geometry>"
    shapes = _children(geometry)
    if not shapes:
        return geometry, None, "<geometry> holds no shape"
    shape = shapes[0]
    tag = str(shape.tag)
    if tag not in SHAPES:
        return shape, None, f"<{tag}> is no shape urdfdom knows (sphere, box, cylinder, mesh)"
    if tag == "sphere":
        why = _scalar(shape, "radius", required=True)
        return (shape, "radius", f"<sphere>: {why}") if why else None
    if tag == "cylinder":
        for attribute in ("length", "radius"):
            why = _scalar(shape, attribute, required=True)
            if why:
                return shape, attribute, f"<cylinder>: {why}"
        return None
    if tag == "box":
        size = shape.get("size")
        if size is None:
            return shape, None, "<box> has no size="
        why = _vector(size)
        return (shape, "size", f'<box size="{size}">: {why}') if why else None
    if shape.get("filename") is None:
        return shape, None, "<mesh> has no filename="
    scale = shape.get("scale")
    why = _vector(scale) if scale is not None else None
    return (shape, "scale", f'<mesh scale="{scale}">: {why}') if why else None


def _part(part: Element, kind: str) -> tuple[Element, str | None, str] | None:
    """(element, attribute, why) when urdfdom's parseVisual / parseCollision fails on the part."""
    origin = _first(part, "origin")
    pose = _pose(origin)
    if origin is not None and pose is not None:
        return origin, pose[0], pose[1]
    geometry = _geometry(part)
    if geometry is not None:
        return geometry
    material = _first(part, "material") if kind == "visual" else None
    if material is not None and material.get("name") is None:
        return material, None, "its <material> has no name="
    return None


def _inertial(inertial: Element) -> tuple[Element, str | None, str] | None:
    """(element, attribute, why) when urdfdom's parseInertial fails."""
    origin = _first(inertial, "origin")
    pose = _pose(origin)
    if origin is not None and pose is not None:
        return origin, pose[0], pose[1]
    mass = _first(inertial, "mass")
    if mass is None:
        return inertial, None, "no <mass>"
    why = _scalar(mass, "value", required=True)
    if why:
        return mass, "value", f"<mass>: {why}"
    inertia = _first(inertial, "inertia")
    if inertia is None:
        return inertial, None, "no <inertia>"
    for attribute in INERTIA:
        why = _scalar(inertia, attribute, required=True)
        if why:
            return inertia, attribute, f"<inertia>: {why}"
    return None


def _link(link: Element, materials: dict[str, Material], uses: MaterialUses, found: Problems) -> None:
    """parseLink's order: the inertial, each visual, each collision; the first failure ends it."""
    name = link.get("name")
    if name is None:
        return  # parseLink stops at once (urdf-invalid names the link without a name)
    owner = ("link", name)
    inertial = _first(link, "inertial")
    failure = _inertial(inertial) if inertial is not None else None
    if failure is not None:
        element, attribute, why = failure
        found.add(
            "part",
            f"link '{name}': <inertial>: {why}: urdfdom drops its visuals and collisions",
            element,
            attribute,
            owner,
            "inertial",
        )
        return
    visuals = [child for child in _children(link) if child.tag == "visual"]
    for index, visual in enumerate(visuals):
        failure = _part(visual, "visual")
        if failure is None:
            _visual_material(link, visual, materials, uses, found)  # (model.cpp: each parsed visual)
        else:
            element, attribute, why = failure
            later = len(visuals) - index - 1
            found.add(
                "part",
                f"link '{name}': <visual>{_ordinal(index, len(visuals))}: {why}: urdfdom drops it"
                + (f", the {later} visual(s) after it" if later else "")
                + " and every collision of the link",
                element,
                attribute,
                owner,
                "visual",
            )
            return
    collisions = [child for child in _children(link) if child.tag == "collision"]
    for index, collision in enumerate(collisions):
        failure = _part(collision, "collision")
        if failure is not None:
            element, attribute, why = failure
            later = len(collisions) - index - 1
            found.add(
                "part",
                f"link '{name}': <collision>{_ordinal(index, len(collisions))}: {why}: urdfdom drops it"
                + (f" and the {later} collision(s) after it" if later else ""),
                element,
                attribute,
                owner,
                "collision",
            )
            return


def _ordinal(index: int, count: int) -> str:
    return f" {index + 1} of {count}" if count > 1 else ""


# --- joints ----------------------------------------------------------------------------------------

# child element → (attribute, required) in the order urdfdom reads them (joint.cpp)
JOINT_PARTS: tuple[tuple[str, tuple[tuple[str, bool], ...]], ...] = (
    ("limit", (("lower", False), ("upper", False), ("effort", True), ("velocity", True))),
    (
        "safety_controller",
        (
            ("soft_lower_limit", False),
            ("soft_upper_limit", False),
            ("k_position", False),
            ("k_velocity", True),
        ),
    ),
    ("calibration", (("rising", False), ("falling", False))),
    ("mimic", (("multiplier", False), ("offset", False))),
    ("dynamics", (("damping", False), ("friction", False))),
)


def _joint(joint: Element) -> tuple[Element, str | None, str] | None:
    """(element, attribute, why) when urdfdom's parseJoint fails (a revolute or prismatic joint
    without <limit> is joint-limit-invalid's)."""
    if joint.get("name") is None:
        return joint, None, "no name="
    origin = _first(joint, "origin")
    pose = _pose(origin)
    if origin is not None and pose is not None:
        return origin, pose[0], pose[1]
    kind = joint.get("type")
    if kind is None:
        return joint, None, "no type="
    if kind not in JOINT_TYPES:
        return joint, "type", f'type="{kind}" is no joint type ({", ".join(JOINT_TYPES)})'
    axis = _first(joint, "axis")
    if kind not in ("floating", "fixed") and axis is not None and axis.get("xyz") is not None:
        why = _vector(axis.get("xyz", ""))
        if why:
            return axis, "xyz", f'<axis xyz="{axis.get("xyz")}">: {why}'
    for tag, attributes in JOINT_PARTS:
        element = _first(joint, tag)
        if element is None:
            continue
        if tag == "mimic" and element.get("joint") is None:
            return element, None, "<mimic> has no joint="
        for attribute, required in attributes:
            why = _scalar(element, attribute, required=required)
            if why:
                return element, attribute, f"<{tag}>: {why}"
        if tag == "dynamics" and element.get("damping") is None and element.get("friction") is None:
            return element, None, "<dynamics> has neither damping= nor friction="
    return None


# joint types joint_state_publisher publishes no position for (it skips them), and those a mimic moves
STILL = ("fixed", "floating", "planar")


def _joints(root: Element, found: Problems) -> None:
    joints = root.findall("joint")
    types = {joint.get("name"): joint.get("type") for joint in joints}
    for joint in joints:
        name = joint.get("name")
        failure = _joint(joint)
        if failure is not None:
            element, attribute, why = failure
            label = f"joint '{name}'" if name is not None else "a <joint>"
            found.add("model", f"{label}: {why}: {REFUSED}", element, attribute, ("joint", name))
            continue
        mimic = _first(joint, "mimic")
        target = mimic.get("joint") if mimic is not None else None
        if mimic is None or joint.get("type") in STILL or (target in types and types[target] not in STILL):
            continue
        # joint_state_publisher takes the mimicked joint's position from the joints it publishes
        # (free_joints[parent]: KeyError for any other name) and robot_state_publisher moves a mimic
        # joint only with a position of the joint it names
        what = "which is no joint of the model" if target not in types else f"a {types[target]} joint"
        found.add(
            "mimic",
            f"joint '{name}' mimics '{target}', {what} (urdfdom does not check): joint_state_publisher "
            f"stops on it (KeyError '{target}') and robot_state_publisher publishes no transform for "
            f"joint '{name}'",
            mimic,
            "joint",
            ("joint", name),
        )
