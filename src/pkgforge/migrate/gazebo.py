"""`migrate --gazebo`: a ROS 1 model's Gazebo Classic parts → what the target distro's Gazebo loads.

- gazebo_ros_control's plugin → the distro's gz ros2_control plugin (model.simulation's gz_names, what
  `new --sim gz` writes), with a <parameters> for each converted controller file;
- each <transmission> → a <ros2_control name=TRANSMISSION type="system"> at its place, with the
  distro's hardware plugin and its joint's command interface (one block per transmission: a
  transmission written in a xacro macro names its joint with the macro's parameters, which only
  the macro's own expansion gives);
- libgazebo_ros_diff_drive.so and libgazebo_ros_joint_state_publisher.so → the gz-sim systems,
  their parameters translated, and a ros_gz_bridge entry for their topics;
- a sensor plugin inside <sensor> is removed (the <sensor> stays); every other Classic plugin is
  removed with a note naming its gz replacement.

A model with such parts is re-serialised by lxml (comments and layout kept; quotes may change).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from lxml import etree

from pkgforge.model import ros1_names

if TYPE_CHECKING:
    from pathlib import Path

    from pkgforge.migrate.converted import Converted
    from pkgforge.migrate.models import Models
    from pkgforge.migrate.roslaunch import Action
    from pkgforge.scaffold.notes import Notes

# a launch token's kind → the ROS 1 substitution it was read from (for a message)
ROS1_SUBSTITUTIONS = {"var": "arg", "env": "optenv"}
DECLARATION = re.compile(rb"\s*<\?xml[^>]*\?>[ \t]*\r?\n?")
PROPERTY = re.compile(r"^\$\{\s*([A-Za-z_][\w]*)\s*\}$")


@dataclass(frozen=True)
class Bridge:
    """One ros_gz_bridge parameter_bridge argument: topic@ROS type, direction, gz type."""

    topic: str
    ros: str
    gz: str
    to_ros: bool

    def argument(self, msgs: str) -> str:
        return f"{self.topic}@{self.ros}{'[' if self.to_ros else ']'}{msgs}.{self.gz}"


@dataclass
class GazeboModels:
    """What the models' conversion needs from the rest of the package, and gives it."""

    controller_files: list[str]  # the package's converted controller files, relative
    package: str
    distro: str
    bridges: list[Bridge] = field(default_factory=list)
    depends: set[str] = field(default_factory=set)
    control: bool = False  # a gazebo_ros_control plugin was converted


def _classic(filename: str) -> bool:
    from pkgforge.model.simulation import CLASSIC_CONTROL, data

    name = filename.rsplit("/", 1)[-1]
    return ros1_names.is_gazebo_classic_plugin(name) or name in {
        *data()["classic"]["libraries"],
        CLASSIC_CONTROL,
    }


def properties(roots: list[etree._Element]) -> dict[str, set[str]]:
    """Each xacro property's values across the models (a plugin's filename="${plugin_name}")."""
    found: dict[str, set[str]] = {}
    for root in roots:
        for element in root.iter():
            if isinstance(element.tag, str) and etree.QName(element).localname == "property":
                if element.get("name") and element.get("value") is not None:
                    found.setdefault(element.get("name", ""), set()).add(element.get("value", ""))
    return found


def plugin_names(filename: str, props: dict[str, set[str]]) -> set[str]:
    """The library names a <plugin filename> may be: itself, or a property's values."""
    match = PROPERTY.match(filename.strip())
    if match is None:
        return {filename.strip()}
    return props.get(match.group(1), set()) or {filename.strip()}


def has_classic_control(roots: list[etree._Element], props: dict[str, set[str]]) -> bool:
    return any(
        ros1_names.GAZEBO_ROS_CONTROL in plugin_names(e.get("filename", ""), props)
        for root in roots
        for e in root.iter("plugin")
    )


def _indent(element: etree._Element) -> str:
    previous = element.getprevious()
    text = (previous.tail if previous is not None else element.getparent().text) or ""  # type: ignore[union-attr]
    return text.rsplit("\n", 1)[-1] if "\n" in text else ""


def _replace(element: etree._Element, snippet: str | None) -> None:
    """Put the XML `snippet` (None: nothing) where `element` is, keeping what follows it."""
    parent = element.getparent()
    assert parent is not None
    if snippet is None:
        previous = element.getprevious()
        tail = element.tail or ""
        if previous is not None:
            previous.tail = (
                (previous.tail or "").rsplit("\n", 1)[0] + tail
                if "\n" in tail
                else (previous.tail or "") + tail
            )
        else:
            parent.text = (
                (parent.text or "").rsplit("\n", 1)[0] + tail if "\n" in tail else (parent.text or "") + tail
            )
        parent.remove(element)
        return
    new = etree.fromstring(snippet)
    new.tail = element.tail
    parent.replace(element, new)


def _joint_names(roots: list[etree._Element]) -> set[str]:
    return {
        e.get("name", "")
        for root in roots
        for e in root.iter("joint")
        if e.getparent() is not None
        and etree.QName(e.getparent()).localname not in ("transmission", "ros2_control")  # type: ignore[arg-type]
    }


def _interface(transmission: etree._Element) -> str | None:
    """The ROS 1 hardware interface a transmission names (its joint's, else its actuator's)."""
    for element in transmission.iter("hardwareInterface"):
        text = (element.text or "").strip().removeprefix("hardware_interface/")
        if text:
            return text
    return None


def transmissions(root: etree._Element, path: Path, joints: set[str], hardware: str, notes: Notes) -> bool:
    """Each <transmission> → a <ros2_control> system at its place (see the module's docstring).
    True when anything changed."""
    changed = False
    for transmission in list(root.iter("transmission")):
        joint = transmission.find("joint")
        name = transmission.get("name", "") or (joint.get("name", "") if joint is not None else "")
        joint_name = joint.get("name", "") if joint is not None else ""
        interface = _interface(transmission)
        command = ros1_names.HARDWARE_INTERFACES.get(interface or "")
        line = transmission.sourceline
        if not joint_name or "$" not in joint_name and joint_name not in joints:
            notes.add(
                "migrate-source-defect",
                f"transmission '{name}' names joint '{joint_name}', which the model does not have: left out "
                "(gazebo_ros_control skipped it too)",
                path,
                line,
            )
            _replace(transmission, None)
            changed = True
            continue
        if command is None:
            notes.add(
                "migrate-gazebo-classic",
                (
                    f"transmission '{name}' has hardware interface '{interface}', which no Gazebo ros2_control "
                    "system commands: left out"
                    if interface
                    else f"transmission '{name}' names no hardware interface: left out"
                ),
                path,
                line,
            )
            _replace(transmission, None)
            changed = True
            continue
        indent = _indent(transmission)
        inner = indent + "  "
        snippet = (
            f'<ros2_control name="{_attribute(name)}" type="system">\n'
            f"{inner}<hardware>\n{inner}  <plugin>{hardware}</plugin>\n{inner}</hardware>\n"
            f'{inner}<joint name="{_attribute(joint_name)}">\n'
            f'{inner}  <command_interface name="{command}"/>\n'
            f'{inner}  <state_interface name="position"/>\n'
            f'{inner}  <state_interface name="velocity"/>\n'
            f"{inner}</joint>\n{indent}</ros2_control>"
        )
        _replace(transmission, snippet)
        notes.add(
            "migrate-changed",
            f"transmission '{name}' ({interface}) → <ros2_control name=\"{name}\"> with {hardware}, "
            f"joint {joint_name}: {command} command, position and velocity state",
            path,
            line,
        )
        changed = True
    return changed


def _attribute(value: str) -> str:
    return value.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def _children(plugin: etree._Element) -> dict[str, str]:
    """A plugin's parameters by name (a xacro conditional inside it by its xacro: name)."""
    return {
        (f"xacro:{etree.QName(c).localname}" if c.prefix == "xacro" else etree.QName(c).localname): (
            c.text or ""
        ).strip()
        for c in plugin
        if isinstance(c.tag, str)
    }


def _topic(name: str) -> str:
    return "/" + name.strip().lstrip("/")


def _diff_drive(plugin: etree._Element, names: dict[str, str], models: GazeboModels) -> tuple[str, list[str]]:
    """libgazebo_ros_diff_drive.so's parameters → gz-sim's DiffDrive system's (and its bridges)."""
    given = _children(plugin)
    out: list[tuple[str, str]] = []
    for old, new in (
        ("leftJoint", "left_joint"),
        ("rightJoint", "right_joint"),
        ("wheelSeparation", "wheel_separation"),
    ):
        if given.get(old):
            out.append((new, given[old]))
    if given.get("wheelDiameter"):
        diameter = given["wheelDiameter"]
        radius = _half(diameter)
        if radius is not None:
            out.append(("wheel_radius", radius))
        else:
            given["wheelDiameter (no number)"] = diameter  # said left out
    command = _topic(given.get("commandTopic") or "cmd_vel")
    odometry = _topic(given.get("odometryTopic") or "odom")
    out += [("topic", command), ("odom_topic", odometry)]
    if given.get("odometryFrame"):
        out.append(("frame_id", given["odometryFrame"]))
    if given.get("robotBaseFrame"):
        out.append(("child_frame_id", given["robotBaseFrame"]))
    if given.get("updateRate"):
        out.append(("odom_publish_frequency", given["updateRate"]))
    publish_tf = given.get("publishOdomTF", "true").lower() in ("true", "1")
    if publish_tf:
        out.append(("tf_topic", "/tf"))
    models.bridges += [
        Bridge(command, "geometry_msgs/msg/Twist", "Twist", to_ros=False),
        Bridge(odometry, "nav_msgs/msg/Odometry", "Odometry", to_ros=True),
        *([Bridge("/tf", "tf2_msgs/msg/TFMessage", "Pose_V", to_ros=True)] if publish_tf else []),
    ]
    kept = {
        "leftJoint",
        "rightJoint",
        "wheelSeparation",
        "wheelDiameter",
        "commandTopic",
        "odometryTopic",
        "odometryFrame",
        "robotBaseFrame",
        "updateRate",
        "publishOdomTF",
    }
    return _system(names, "diff-drive", "DiffDrive", out), sorted(set(given) - kept)


def _half(value: str) -> str | None:
    """Half a wheel diameter: a number halved, a xacro expression ${...} halved by xacro; None for
    anything else (it was no number for Gazebo Classic either)."""
    try:
        return repr(float(value) / 2)
    except ValueError:
        expression = re.fullmatch(r"\$\{(.+)\}", value.strip())
        return f"${{({expression.group(1)}) / 2}}" if expression and "${" not in expression.group(1) else None


def _joint_state_publisher(
    plugin: etree._Element, names: dict[str, str], models: GazeboModels
) -> tuple[str, list[str]]:
    given = _children(plugin)
    joints = [j.strip() for j in re.split(r"[,\s]+", given.get("jointName", "")) if j.strip()]
    out = [("joint_name", j) for j in joints] + [("topic", "/joint_states")]
    models.bridges.append(Bridge("/joint_states", "sensor_msgs/msg/JointState", "Model", to_ros=True))
    return _system(names, "joint-state-publisher", "JointStatePublisher", out), sorted(
        set(given) - {"jointName"}
    )


def _system(names: dict[str, str], library: str, system: str, parameters: list[tuple[str, str]]) -> str:
    body = "".join(f"\n  <{k}>{_text(v)}</{k}>" for k, v in parameters)
    return (
        f'<plugin filename="{names["system"]}-{library}-system" name="{names["namespace"]}::systems::{system}">'
        f"{body}\n</plugin>"
    )


def _text(value: str) -> str:
    return value.replace("&", "&amp;").replace("<", "&lt;")


def _control(names: dict[str, str], models: GazeboModels) -> str:
    body = "".join(
        f"\n  <parameters>$(find {models.package})/{relative}</parameters>"
        for relative in models.controller_files
    )
    return f'<plugin filename="{names["plugin"]}" name="{names["plugin_name"]}">{body}\n</plugin>'


def _reindent(snippet: str, indent: str) -> str:
    return snippet.replace("\n", "\n" + indent)


def _plugins(root: etree._Element, props: dict[str, set[str]]) -> Iterator[tuple[etree._Element, str]]:
    for plugin in list(root.iter("plugin")):
        parent = plugin.getparent()
        if parent is None or etree.QName(parent).localname in ("hardware", "ros2_control"):
            continue  # a ros2_control hardware <plugin>, not Gazebo's
        classic = sorted(n for n in plugin_names(plugin.get("filename", ""), props) if _classic(n))
        if classic:
            yield plugin, classic[0]


def plugins(
    root: etree._Element, path: Path, props: dict[str, set[str]], models: GazeboModels, notes: Notes
) -> bool:
    """Each Gazebo Classic <plugin> → its gz replacement, or removed (see the module's docstring).
    True when anything changed."""
    from pkgforge.model.simulation import CLASSIC_REPLACEMENTS, gz_names

    names = gz_names(models.distro)
    changed = False
    for plugin, library in _plugins(root, props):
        line, indent = plugin.sourceline, _indent(plugin)
        left: list[str] = []
        if library == ros1_names.GAZEBO_ROS_CONTROL:
            snippet: str | None = _control(names, models)
            models.depends.add(names["control"])  # which depends on controller_manager
            models.control = True
            left = sorted(set(_children(plugin)) - {"parameters"})
            files = (
                ", ".join(models.controller_files)
                or "none: the package's launch files load no controller file"
            )
            message = f"{library} → {names['plugin']} (ros2_control in Gazebo; controllers: {files})"
            if models.controller_files and path.suffix == ".urdf":
                message += (
                    "; its $(find) needs xacro, which the migrated launch files run on the .urdf "
                    "(ros_gz_sim create -file of the .urdf itself would not resolve it)"
                )
        elif library == "libgazebo_ros_diff_drive.so":
            snippet, left = _diff_drive(plugin, names, models)
            models.depends.add("ros_gz_bridge")
            message = f"{library} → {names['system']}-diff-drive-system, its topics bridged by ros_gz_bridge"
        elif library == "libgazebo_ros_joint_state_publisher.so":
            snippet, left = _joint_state_publisher(plugin, names, models)
            models.depends.add("ros_gz_bridge")
            message = f"{library} → {names['system']}-joint-state-publisher-system on /joint_states, bridged"
        elif any(
            etree.QName(a).localname == "sensor" for a in plugin.iterancestors() if isinstance(a.tag, str)
        ):
            snippet = None
            message = (
                f"sensor plugin {library} removed: the <sensor> stays, gz-sim runs it given the sensors "
                f"system ({names['system']}-sensors-system in the world); bridge its gz topic with ros_gz_bridge"
            )
        else:
            snippet = None
            replacement = CLASSIC_REPLACEMENTS.get(library)
            instead = f" (Gazebo has {replacement.replace('gz-sim', names['system'])})" if replacement else ""
            message = f"Gazebo Classic plugin {library} removed: it loads in no Gazebo (gz){instead}"
        if left:
            message += f"; left out: {', '.join(left)}"
        if snippet is None:
            _remove_plugin(plugin)
        else:
            _replace(plugin, _reindent(snippet, indent))
        kind = "migrate-changed" if snippet is not None else "migrate-gazebo-classic"
        notes.add(kind, message, path, line)
        changed = True
    return changed


def _remove_plugin(plugin: etree._Element) -> None:
    """The plugin left out, and the <gazebo> that held only it."""
    parent = plugin.getparent()
    _replace(plugin, None)
    if (
        parent is not None
        and etree.QName(parent).localname == "gazebo"
        and not len(parent)
        and parent.getparent() is not None
        and not (parent.text or "").strip()
    ):
        _replace(parent, None)


def convert_model(
    data: bytes, path: Path, models: GazeboModels, context: ModelContext, notes: Notes
) -> bytes:
    """The model's bytes with its Gazebo Classic parts converted (unchanged when it has none)."""
    from pkgforge.model.simulation import gz_names

    def convert(root: etree._Element) -> bool:
        changed = False
        if context.control:
            changed |= transmissions(root, path, context.joints, gz_names(models.distro)["hardware"], notes)
        return plugins(root, path, context.properties, models, notes) | changed

    return _rewritten(data, convert)


def strip_model(data: bytes, path: Path, props: dict[str, set[str]], notes: Notes) -> bytes:
    """Without --gazebo: the model's bytes with each Gazebo Classic <plugin> left out, as the
    launch files' Classic actions are (ROS 1's plugins load in no Gazebo of a ROS 2 distro, and
    verify would report each, PF701); --gazebo converts them instead."""

    def strip(root: etree._Element) -> bool:
        found = list(_plugins(root, props))
        for plugin, library in found:
            notes.add(
                "migrate-gazebo-classic",
                f"Gazebo Classic plugin {library} left out: it loads in no Gazebo of a ROS 2 distro "
                "(migrate --gazebo converts it)",
                path,
                plugin.sourceline,
            )
            _remove_plugin(plugin)
        return bool(found)

    return _rewritten(data, strip)


def _rewritten(data: bytes, edit: Callable[[etree._Element], bool]) -> bytes:
    """The model's bytes after `edit` changed its tree (unchanged when it changed nothing), with
    the source's own XML declaration and line ends."""
    parser = etree.XMLParser(remove_comments=False, resolve_entities=False, no_network=True)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError:
        return data  # read as ROS 1 did (content after the root): reported by read_models
    if not edit(root):
        return data
    text = etree.tostring(root.getroottree(), encoding="utf-8")
    declaration = DECLARATION.match(data)
    if declaration is not None:  # the source's own, as it was written (lxml's quotes differ)
        encoding = re.search(rb"encoding\s*=\s*[\"']([^\"']+)", declaration.group(0))
        if encoding is None or encoding.group(1).lower() in (b"utf-8", b"utf8"):
            text = declaration.group(0) + text
        else:
            text = etree.tostring(root.getroottree(), encoding="utf-8", xml_declaration=True)
    text = text if text.endswith(b"\n") else text + b"\n"
    # the XML parser reads CRLF as LF: a CRLF file stays CRLF
    return text.replace(b"\r\n", b"\n").replace(b"\n", b"\r\n") if b"\r\n" in data else text


@dataclass
class ModelContext:
    """What every model's conversion reads of all the package's models."""

    control: bool  # a model loads gazebo_ros_control: transmissions become ros2_control
    joints: set[str]
    properties: dict[str, set[str]]

    @classmethod
    def of(cls, roots: list[etree._Element]) -> ModelContext:
        props = properties(roots)
        return cls(has_classic_control(roots, props), _joint_names(roots), props)


def convert_package(
    converted: Converted, models: Models, source: Path, package: str, distro: str, notes: Notes
) -> None:
    """--gazebo, after the launch files are read: their controller files converted, their spawners
    naming what those define, the models converted, the clock and the plugins' topics bridged."""
    from pkgforge.migrate.controllers import convert as convert_controllers
    from pkgforge.model.simulation import gz_names

    names: dict[str, str] = {}
    dropped: set[str] = set()
    gazebo = GazeboModels([], package, distro)
    for relative in _controller_files(converted, package, notes):
        converted.output[relative], conversion = convert_controllers(
            converted.output[relative], source / relative, distro, notes
        )
        if not (conversion.names or conversion.dropped):
            # copied as written: a ROS 1 file given to the controller manager stops it (rcl reads
            # node: ros__parameters: only), so no <parameters> names it
            notes.add(
                "migrate-gazebo-classic",
                f"{relative} holds no ros_control controller (a mapping with a type): copied as written, "
                "not given to gz_ros2_control",
                source / relative,
                None,
            )
            continue
        gazebo.controller_files.append(relative)
        names |= conversion.names
        dropped |= conversion.dropped
        gazebo.depends |= conversion.packages
    for launch in converted.launches.values():
        _fix_spawners(launch.actions, names, dropped)
    context = ModelContext.of([model.root for model in models.read.values()])
    for relative in models.read:
        if relative in converted.output:
            converted.output[relative] = convert_model(
                converted.output[relative], source / relative, gazebo, context, notes
            )
    if not gazebo.control:
        for relative in gazebo.controller_files:
            notes.add(
                "migrate-gazebo-classic",
                f"no model of this package loads gazebo_ros_control: {relative} reaches no controller manager "
                f"(name it in a <parameters> of the {gz_names(distro)['plugin']} plugin of the robot's model)",
                source / relative,
                None,
            )
    for relative, launch in converted.launches.items():
        _bridge(launch.actions, gazebo, converted.launch_sources[relative], notes)
    converted.depends |= gazebo.depends


def strip_package(converted: Converted, models: Models, source: Path, notes: Notes) -> None:
    """Without --gazebo: every model written leaves its Gazebo Classic plugins out."""
    props = properties([model.root for model in models.read.values()])
    for relative in models.read:
        if relative in converted.output:
            converted.output[relative] = strip_model(
                converted.output[relative], source / relative, props, notes
            )


def _controller_files(converted: Converted, package: str, notes: Notes) -> list[str]:
    """The package's own files its launch files load for the spawner (relative paths), in order."""
    from pkgforge.migrate.tokens import Token

    found: list[str] = []
    for relative, launch in converted.launches.items():
        for parts, line in launch.controller_files:
            own = len(parts) == 2 and parts[0] == Token("find", package) and parts[1][0] == "text"
            file = parts[1][1].lstrip("/") if own else None
            if file is not None and file in converted.output:
                found.append(file)
                continue
            shown = "".join(
                p[1] if p[0] == "text" else f"$({ROS1_SUBSTITUTIONS.get(p[0], p[0])} {p[1]})" for p in parts
            )
            why = (
                "is no file of the package"
                if own
                else "names no file of this package pkgforge can tell (another package's, or computed)"
            )
            notes.add(
                "migrate-gazebo-classic",
                f"controller file {shown} {why}: not converted, and gz_ros2_control is not given it (convert it "
                "to a controller_manager parameters file and add a <parameters> naming it)",
                converted.launch_sources[relative],
                line,
            )
    return list(dict.fromkeys(found))


def _fix_spawners(actions: list[Action], names: dict[str, str], dropped: set[str]) -> None:
    """Each spawner names the ROS 2 controllers: renamed ones by their new name, left-out ones not
    at all (a spawner left with none is left out too)."""
    from pkgforge.migrate.roslaunch import Group, Node
    from pkgforge.migrate.tokens import Token, literal

    for action in list(actions):
        if isinstance(action, Group):
            _fix_spawners(action.actions, names, dropped)
        elif (
            isinstance(action, Node) and (action.package, action.executable) == ros1_names.CONTROLLER_SPAWNER
        ):
            words = [w for w in action.arguments if literal(w) not in dropped]
            action.arguments = [
                [Token("text", names[word])] if (word := literal(w)) in names else w for w in words
            ]
            if dropped and all((literal(w) or "").startswith("-") for w in action.arguments):
                actions.remove(action)


def _bridge(actions: list[Action], gazebo: GazeboModels, path: Path, notes: Notes) -> None:
    """After the include of ros_gz_sim's gz_sim.launch.py: ros_gz_bridge's parameter_bridge of the
    clock (use_sim_time) and of the converted plugins' topics."""
    from pkgforge.migrate.roslaunch import Group, Include, Node
    from pkgforge.migrate.tokens import Token
    from pkgforge.model.simulation import gz_names

    msgs = gz_names(gazebo.distro)["msgs"]
    world = [Token("find", ros1_names.GZ_WORLD_LAUNCH[0]), Token("text", "/" + ros1_names.GZ_WORLD_LAUNCH[1])]
    for action in list(actions):
        if isinstance(action, Group):
            _bridge(action.actions, gazebo, path, notes)
        elif isinstance(action, Include) and action.path == world:
            bridges = [Bridge("/clock", "rosgraph_msgs/msg/Clock", "Clock", to_ros=True), *gazebo.bridges]
            arguments = [b.argument(msgs) for b in dict.fromkeys(bridges)]
            bridge = Node(
                "ros_gz_bridge",
                "parameter_bridge",
                action.line,
                arguments=[[Token("text", a)] for a in arguments],
                condition=action.condition,
            )
            actions.insert(actions.index(action) + 1, bridge)
            gazebo.depends |= {"ros_gz_bridge", "ros_gz_sim"}
            notes.add(
                "migrate-generated",
                f"ros_gz_bridge parameter_bridge started beside Gazebo: {', '.join(b.topic for b in dict.fromkeys(bridges))}"
                " (the clock for use_sim_time)",
                path,
                action.line,
            )
