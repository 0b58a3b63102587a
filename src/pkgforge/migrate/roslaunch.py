"""ROS 1 launch XML (roslaunch) → plain actions, read with lxml so every element keeps its line.

Substitutions become tokens (migrate/tokens). What ROS 2 cannot express is a `migrate-dropped` note
at its line.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from lxml import etree

from pkgforge.errors import PkgforgeError
from pkgforge.migrate.tokens import (
    XACRO_COMMAND,
    Condition,
    Token,
    Unconvertible,
    literal,
    split_words,
    tokens,
)
from pkgforge.model import ros1_names

if TYPE_CHECKING:
    from pkgforge.model.distros import Distro
    from pkgforge.scaffold.notes import Notes


# lines are lxml's sourceline: None only where libxml2 could not count (it does for every file read)
@dataclass
class Arg:
    name: str
    default: list[Token] | None
    doc: str | None
    line: int | None
    fixed: bool = False  # <arg value=...>: a constant (ROS 2: let)


@dataclass
class Param:
    name: str | None  # None: <param> without name= (written as found)
    value: list[Token]
    # value | description (xacro of a file, as a string) | file (a YAML file)
    kind: Literal["value", "description", "file"] = "value"


@dataclass
class Node:
    package: str
    executable: str
    line: int | None
    name: str | None = None
    namespace: str | None = None
    arguments: list[list[Token]] = field(default_factory=list)
    output: str | None = None
    respawn: str | None = None
    params: list[Param] = field(default_factory=list)
    # (from=, to=), each with its substitutions ($(arg scan_topic)): tokens
    remaps: list[tuple[list[Token], list[Token]]] = field(default_factory=list)
    condition: Condition | None = None
    required: bool = False  # ROS 1's required="true": the launch ends when it exits (on_exit=Shutdown())


@dataclass
class Include:
    path: list[Token]
    line: int | None
    arguments: list[tuple[str | None, list[Token]]] = field(default_factory=list)  # (name=, value)
    condition: Condition | None = None


@dataclass
class Group:
    line: int | None
    namespace: list[Token] | None = None
    condition: Condition | None = None
    actions: list[Action] = field(default_factory=list)


Action = Arg | Node | Include | Group


@dataclass
class LaunchFile:
    source: Path
    actions: list[Action]
    used_args: set[str] = field(default_factory=set)
    # the robot description this file gives robot_state_publisher, its arguments' defaults filled in
    description: list[Token] | None = None
    # --gazebo: the files a global <rosparam command="load"> gives controller_manager's spawner
    # (ROS 1's controller configuration), with the line of each; gz_ros2_control reads them
    controller_files: list[tuple[list[Token], int | None]] = field(default_factory=list)

    def runs_anything(self) -> bool:
        """Whether it starts or includes anything (a file of arguments only launches nothing)."""
        return any(not isinstance(a, Arg) for a in _flat(self.actions))


def _flat(actions: list[Action]) -> Iterator[Action]:
    for action in actions:
        if isinstance(action, Group):
            yield from _flat(action.actions)
        else:
            yield action


class Reader:
    def __init__(
        self,
        path: Path,
        package: str,
        notes: Notes,
        *,
        gazebo: bool,
        rename_launch: Callable[[list[Token]], list[Token]],
        distro: Distro,
        launch_format: str = "py",
        package_description: list[Token] | None = None,
        content: bytes | None = None,
    ):
        self.path, self.package, self.notes, self.gazebo = path, package, notes, gazebo
        # the file's bytes as read (the package's old name already rewritten: a name with a space
        # in it, as exporters write, is no $(find) argument until then); None: read from path
        self.content = content
        self.rename_launch = rename_launch  # tokens of an included ROS 1 launch file → ROS 2 tokens
        self.distro, self.launch_format = distro, launch_format
        # the model the package's other launch files describe the robot with (ROS 1 set it as a
        # global parameter that a node of this file read), for a node here that needs it
        self.package_description = package_description
        # (xacro tokens, line, kind)
        self.description: tuple[list[Token], int | None, str] | None = None
        self.use_gui: list[Token] | None = None
        self.rosparams: list[tuple[list[Token], etree._Element]] = []  # global <rosparam file> (--gazebo)

    def note(self, name: str, message: str, element: etree._Element) -> None:
        self.notes.add(name, message, self.path, element.sourceline)

    def read(self) -> LaunchFile:
        try:
            parser = etree.XMLParser(remove_comments=True)
            if self.content is None:
                root = etree.parse(str(self.path), parser).getroot()
            else:
                root = etree.fromstring(self.content, parser)
        except etree.XMLSyntaxError as exc:
            raise PkgforgeError(
                f"{self.path}:{exc.lineno}: not well-formed XML: {exc.msg}; fix the launch file "
                "(nothing written)"
            ) from exc
        if root.tag != "launch":
            raise PkgforgeError(
                f"{self.path}:{root.sourceline}: the root element is <{root.tag!s}>, not <launch>: "
                "not a ROS 1 launch file (nothing written)"
            )
        actions = self.block(root)
        self.finish(actions)
        description = self.description[0] if self.description else None
        for node in nodes(actions):
            description = description or next((p.value for p in node.params if p.kind == "description"), None)
        resolved = _with_defaults(description, actions) if description else None
        used = _variables(actions)
        for arg in [a for a in actions if isinstance(a, Arg) and a.default is None and a.name not in used]:
            actions.remove(arg)
            self.notes.add(
                "migrate-changed",
                f"argument '{arg.name}' has no default and nothing uses it: left out "
                "(ROS 2 would refuse to start without a value)",
                self.path,
                arg.line,
            )
        return LaunchFile(
            self.path, actions, description=resolved, controller_files=self.controller_files(actions)
        )

    def controller_files(self, actions: list[Action]) -> list[tuple[list[Token], int | None]]:
        """--gazebo: the global <rosparam> files of a launch file that starts controller_manager's
        spawner (ROS 1's controller configuration: gz_ros2_control reads it once converted); any
        other global <rosparam> is left out as without --gazebo."""
        spawns = any((n.package, n.executable) == ros1_names.CONTROLLER_SPAWNER for n in nodes(actions))
        for _, element in self.rosparams:
            if spawns:
                self.note(
                    "migrate-changed",
                    "global <rosparam> loaded for the spawner: its controllers become a ROS 2 "
                    "controller_manager parameters file (--gazebo; see that file's notes)",
                    element,
                )
            else:
                self.note(
                    "migrate-dropped",
                    "<rosparam> left out: global <rosparam>: ROS 2 has no global parameters (load it in a "
                    "node's <param from>)",
                    element,
                )
        return [(parts, element.sourceline) for parts, element in self.rosparams] if spawns else []

    def value(self, element: etree._Element, attribute: str) -> list[Token] | None:
        text = element.get(attribute)
        if text is None:
            return None
        return tokens(text)

    def condition(self, element: etree._Element) -> Condition | None:
        kinds: tuple[Literal["if", "unless"], ...] = ("if", "unless")
        for kind in kinds:
            if element.get(kind) is not None:
                return kind, tokens(element.get(kind))
        return None

    def block(self, parent: etree._Element) -> list[Action]:
        actions: list[Action] = []
        for element in parent:
            if not isinstance(element.tag, str):
                continue
            try:
                action: Callable[[etree._Element], Action | None] | None = getattr(
                    self, "read_" + element.tag.replace("-", "_"), None
                )
                if action is None:
                    self.note(
                        "migrate-dropped",
                        f"<{element.tag}> has no ROS 2 launch equivalent: left out",
                        element,
                    )
                    continue
                result = action(element)
            except Unconvertible as exc:
                self.note("migrate-dropped", f"<{element.tag}> left out: {exc}", element)
                continue
            if result is not None:
                actions.append(result)
        return actions

    def need(self, element: etree._Element, *names: str) -> None:
        missing = [n for n in names if not element.get(n)]
        if missing:
            raise Unconvertible(f"it has no {', '.join(missing)}= attribute")

    def read_arg(self, element: etree._Element) -> Arg:
        self.need(element, "name")
        name = element.get("name", "")  # required: never the default
        if element.get("value") is not None:
            return Arg(name, tokens(element.get("value")), element.get("doc"), element.sourceline, fixed=True)
        return Arg(name, self.value(element, "default"), element.get("doc"), element.sourceline)

    def read_group(self, element: etree._Element) -> Group:
        group = Group(element.sourceline, self.value(element, "ns"), self.condition(element))
        group.actions = self.block(element)
        return group

    def description_of(self, element: etree._Element) -> list[Token] | None:
        """xacro command tokens of a robot_description <param textfile=|command=>."""
        if element.get("textfile") is not None:
            self.note(
                "migrate-changed",
                "robot_description from textfile: robot_state_publisher gets the "
                "model through xacro (a URDF passes through unchanged), as a string parameter",
                element,
            )
            return tokens(element.get("textfile"))
        command = element.get("command")
        if command is not None:
            match = XACRO_COMMAND.match(command)
            if match is None:
                raise Unconvertible(f'command="{command}" is not a xacro call')
            rest = command[match.end() :].replace("--inorder", " ").strip()
            self.note(
                "migrate-changed",
                "robot_description from xacro: a string parameter "
                "(ParameterValue(Command(['xacro ', ...]), value_type=str))",
                element,
            )
            return tokens(re.sub(r"\s+", " ", rest))
        return None

    def read_param(self, element: etree._Element) -> None:
        self.need(element, "name")
        name = element.get("name", "")
        if name.lstrip("/") == "robot_description":
            self.description = (
                self.description_of(element) or self.value(element, "value") or [],
                element.sourceline,
                "description",
            )
            return None
        if name.lstrip("/") == "use_gui":
            self.use_gui = self.value(element, "value")
            self.note(
                "migrate-changed",
                "use_gui: ROS 2's joint_state_publisher has no GUI; "
                "joint_state_publisher_gui is started instead where it is true",
                element,
            )
            return None
        raise Unconvertible(f"global parameter '{name}': ROS 2 has no global parameters")

    def read_rosparam(self, element: etree._Element) -> None:
        if self.gazebo and element.get("file") and element.get("command", "load") == "load":
            self.rosparams.append((tokens(element.get("file")), element))  # a spawner's, if one is here
            return None
        raise Unconvertible(
            "global <rosparam>: ROS 2 has no global parameters (load it in a node's <param from>)"
        )

    def read_include(self, element: etree._Element) -> Include | None:
        self.need(element, "file")
        path = tokens(element.get("file"))
        arguments = [
            (a.get("name"), tokens(a.get("value", a.get("default", ""))))
            for a in element
            if isinstance(a.tag, str) and a.tag == "arg"
        ]
        condition = self.condition(element)
        text = literal([p for p in path if p[0] == "text"]) or ""
        finds = [p[1] for p in path if p[0] == "find"]
        gz_package, worlds = ros1_names.GAZEBO_WORLD_LAUNCH
        if finds == [gz_package] and text.rsplit("/", 1)[-1] in worlds:
            if not self.gazebo:
                self.notes.add(
                    "migrate-gazebo-classic",
                    f"Gazebo Classic's {gz_package} {text.lstrip('/')} "
                    "left out (--gazebo starts Gazebo with ros_gz_sim)",
                    self.path,
                    element.sourceline,
                )
                return None
            return self.gz_sim(element, arguments, condition, text.lstrip("/"))
        renamed = self.rename_launch(path)
        if renamed != path:
            self.notes.add(
                "migrate-changed",
                "included ROS 1 launch file → its ROS 2 name",
                self.path,
                element.sourceline,
            )
        return Include(renamed, element.sourceline, arguments, condition)

    def gz_sim(
        self,
        element: etree._Element,
        arguments: list[tuple[str | None, list[Token]]],
        condition: Condition | None,
        classic: str,
    ) -> Include:
        """gazebo_ros's empty_world.launch → ros_gz_sim's gz_sim.launch.py: the world, started
        running unless paused:=true, server only when gui:=false."""
        package, launch = ros1_names.GZ_WORLD_LAUNCH
        values = {k: v for k, v in arguments if k}
        world = self.gz_world(values.get("world_name"), element)
        flags = []
        paused = _literal_value(values.get("paused"))
        if paused not in ("true", "1"):
            flags.append("-r")  # Gazebo Classic started running unless paused
        how = "started paused" if paused in ("true", "1") else "started running"
        self.note("migrate-renamed", f"gazebo_ros {classic} → {package} {launch} (Gazebo, {how})", element)
        gui = _literal_value(values.get("gui"))
        if gui in ("false", "0"):
            flags.append("-s")  # no GUI: the server only
        handled = {
            "world_name",
            *(["paused"] if paused is not None else []),
            *(["gui"] if gui is not None else []),
        }
        dropped = [k or "(unnamed)" for k, _ in arguments if k not in handled]
        if dropped:
            self.note(
                "migrate-dropped",
                f"arguments {', '.join(dropped)} of {classic} have no {package} equivalent: left out",
                element,
            )
        gz_args = world + ([Token("text", " " + " ".join(flags))] if flags else [])
        return Include(
            [Token("find", package), Token("text", "/" + launch)],
            element.sourceline,
            [("gz_args", gz_args)],
            condition,
        )

    def gz_world(self, world: list[Token] | None, element: etree._Element) -> list[Token]:
        """The world gz sim opens: Gazebo Classic's own worlds (worlds/empty.world, found in Classic's
        resource path, or gazebo_ros's) have no file for gz sim: its empty.sdf instead."""
        empty = [Token("text", "empty.sdf")]
        if world is None:
            return empty
        text = literal(world)
        finds = [p[1] for p in world if p[0] == "find"]
        classic = (
            text is not None and (text.strip().startswith("worlds/") or not text.strip())
        ) or finds == ["gazebo_ros"]
        shown = "".join(p[1] if p[0] == "text" else f"$({p[0]} {p[1]})" for p in world)
        if classic:
            if not (text or "").strip().endswith("empty.world"):
                self.note(
                    "migrate-gazebo-classic",
                    f"world {shown} is Gazebo Classic's, which gz sim has not: empty.sdf instead (convert the world)",
                    element,
                )
            return empty
        self.note(
            "migrate-gazebo-classic",
            f"world {shown} is a Gazebo Classic world: gz sim reads its SDF, not Classic's plugins",
            element,
        )
        return world

    def read_node(self, element: etree._Element) -> Node | None:
        self.need(element, "pkg", "type")
        package, executable = element.get("pkg", ""), element.get("type", "")  # required
        line = element.sourceline
        if (package, executable) == ros1_names.GAZEBO_SPAWNER:
            return self.spawner(element)
        if package in ros1_names.COMMAND_NODES:
            raise Unconvertible(
                f"{package} is a ROS 1 command-line tool; ROS 2 has `{ros1_names.COMMAND_NODES[package]}`, "
                "a command, not a node"
            )
        new_package, new_executable = ros1_names.executable(package, executable)
        if (new_package, new_executable) != (package, executable):
            self.note(
                "migrate-renamed", f"node {package}/{executable} → {new_package}/{new_executable}", element
            )
        node = Node(
            new_package,
            new_executable,
            line,
            element.get("name"),
            element.get("ns"),
            output=element.get("output"),
            respawn=element.get("respawn"),
            condition=self.condition(element),
        )
        node.arguments = split_words(tokens(element.get("args", "")))
        if (new_package, new_executable) == ros1_names.CONTROLLER_SPAWNER:
            node.arguments = self.spawner_arguments(node.arguments, element)
        if new_executable == "static_transform_publisher":
            node.arguments = self.transform_arguments(node.arguments, element)
        self.required_node(element, node)
        for attribute in ("machine", "launch-prefix", "cwd", "clear_params"):
            if element.get(attribute) is not None:
                self.note(
                    "migrate-dropped",
                    f'node attribute {attribute}="{element.get(attribute)}" left out',
                    element,
                )
        for child in element:
            if not isinstance(child.tag, str):
                continue
            try:
                if child.tag == "param":
                    if child.get("name", "").lstrip("~") == "robot_description":
                        # no value at all: an empty xacro command, as for a global robot_description
                        description = self.description_of(child) or self.value(child, "value") or []
                        node.params.append(Param("robot_description", description, "description"))
                    elif child.get("name") == "use_gui":
                        self.use_gui = self.value(child, "value")
                    elif child.get("value") is not None:
                        node.params.append(Param(child.get("name"), tokens(child.get("value"))))
                    else:
                        raise Unconvertible("only value= parameters convert")
                elif child.tag == "rosparam" and child.get("file") and child.get("command", "load") == "load":
                    node.params.append(Param("", tokens(child.get("file")), "file"))
                elif child.tag == "remap":
                    self.need(child, "from", "to")
                    node.remaps.append((tokens(child.get("from")), tokens(child.get("to"))))
                else:
                    raise Unconvertible("no ROS 2 equivalent")
            except Unconvertible as exc:
                self.note("migrate-dropped", f"<{child.tag}> of node {executable} left out: {exc}", child)
        if new_package in ("joint_state_publisher", "joint_state_publisher_gui") and node.arguments:
            node.arguments = []
            self.note(
                "migrate-changed",
                f"{new_package}'s arguments left out: it reads /robot_description, "
                "never the model as an argument",
                element,
            )
        return node

    def required_node(self, element: etree._Element, node: Node) -> None:
        """required="true": ROS 1 ends the launch when the node exits; ROS 2 says so with the
        node's on_exit=Shutdown() (Python; XML and YAML after Humble: on_exit="shutdown")."""
        value = element.get("required")
        if value is None:
            return
        if value.strip().lower() not in ("true", "1"):
            self.note("migrate-changed", f'node attribute required="{value}": the default, left out', element)
        elif self.launch_format == "py" or self.distro.frontend_on_exit:
            node.required = True
            form = "on_exit=Shutdown()" if self.launch_format == "py" else 'on_exit="shutdown"'
            self.note(
                "migrate-changed",
                f'node attribute required="true" → {form}: the launch ends when it exits',
                element,
            )
        else:
            self.note(
                "migrate-dropped",
                f'node attribute required="true" left out: {self.distro.name}\'s {self.launch_format.upper()} launch '
                "has no on_exit (Python's on_exit=Shutdown() has: --launch-format py)",
                element,
            )

    def spawner_arguments(self, words: list[list[Token]], element: etree._Element) -> list[list[Token]]:
        """controller_manager's spawner: ROS 1's controller names and options → ROS 2's."""
        converted: list[list[Token]] = []
        index = 0
        while index < len(words):
            word = literal(words[index])
            if word in ros1_names.CONTROLLER_NAMES:
                converted.append([Token("text", ros1_names.CONTROLLER_NAMES[word])])
                self.note(
                    "migrate-renamed", f"controller {word} → {ros1_names.CONTROLLER_NAMES[word]}", element
                )
            elif (
                word is not None
                and word.startswith("--")
                and word.split("=")[0] in ros1_names.SPAWNER_OPTIONS
            ):
                option, _, value = word.partition("=")
                takes = option not in ros1_names.SPAWNER_FLAGS and not value
                new = ros1_names.SPAWNER_OPTIONS[option]
                if new is None:
                    self.note(
                        "migrate-dropped",
                        f"spawner option {option} has no ROS 2 equivalent: left out",
                        element,
                    )
                else:
                    converted.append([Token("text", new + (f"={value}" if value else ""))])
                    if takes and index + 1 < len(words):
                        converted.append(words[index + 1])
                    self.note("migrate-renamed", f"spawner option {option} → {new}", element)
                index += 2 if takes else 1
                continue
            else:
                converted.append(words[index])
            index += 1
        return converted

    def transform_arguments(self, words: list[list[Token]], element: etree._Element) -> list[list[Token]]:
        """tf's `x y z yaw pitch roll frame child period` → tf2_ros's named options."""
        names6 = ["--x", "--y", "--z", "--yaw", "--pitch", "--roll"]
        names7 = ["--x", "--y", "--z", "--qx", "--qy", "--qz", "--qw"]
        for names in (names6, names7):
            if len(words) in (len(names) + 2, len(names) + 3):
                if len(words) == len(names) + 3:
                    self.note(
                        "migrate-changed",
                        "static_transform_publisher: the period argument left out "
                        "(tf2_ros publishes static transforms once, latched)",
                        element,
                    )
                converted: list[list[Token]] = []
                for option, word in zip([*names, "--frame-id", "--child-frame-id"], words, strict=False):
                    converted += [[Token("text", option)], word]
                return converted
        return words

    def spawner(self, element: etree._Element) -> Node | None:
        words = split_words(tokens(element.get("args", "")))
        if not self.gazebo:
            self.note(
                "migrate-gazebo-classic",
                "gazebo_ros spawn_model (Gazebo Classic) left out (--gazebo spawns with ros_gz_sim create)",
                element,
            )
            return None
        package, executable = ros1_names.GZ_SPAWNER
        self.note("migrate-renamed", f"gazebo_ros/spawn_model → {package}/{executable}", element)
        converted: list[list[Token]] = []
        index = 0
        flags = ("-urdf", "-sdf", "-unpause", "-wait")
        while index < len(words):
            option = literal(words[index]) or ""
            takes_value = option not in flags and index + 1 < len(words)
            new = ros1_names.SPAWN_OPTIONS.get(option)
            if new:
                converted.append([Token("text", new)])
                if takes_value:
                    converted.append(
                        [Token("text", "robot_description")] if option == "-param" else words[index + 1]
                    )
            elif option not in flags:
                self.note(
                    "migrate-dropped",
                    f"spawn_model option {option} has no ros_gz_sim create equivalent: left out",
                    element,
                )
            index += 2 if takes_value else 1
        return Node(
            package,
            executable,
            element.sourceline,
            element.get("name"),
            arguments=converted,
            output=element.get("output"),
        )

    def finish(self, actions: list[Action]) -> None:
        """Global robot_description → robot_state_publisher's parameter (ros_gz_sim create's when it
        is alone); use_gui → which publisher."""
        found = list(nodes(actions))
        description, line = (self.description[0], self.description[1]) if self.description else (None, None)
        publishers = [n for n in found if n.package == "robot_state_publisher"]
        for node in publishers:
            if any(p.name == "robot_description" for p in node.params):
                continue
            if description is not None:
                node.params.insert(0, Param("robot_description", description, "description"))
            elif self.package_description is not None:
                node.params.insert(0, Param("robot_description", self.package_description, "description"))
                self.notes.add(
                    "migrate-generated",
                    "robot_state_publisher read ROS 1's global robot_description, which another launch file "
                    "set: given the model the package's launch files describe the robot with",
                    self.path,
                    node.line,
                )
        spawned = self.spawn_description(found, publishers, description)
        if description is not None and not publishers and not spawned:
            self.notes.add(
                "migrate-dropped",
                "global robot_description left out: no robot_state_publisher here to publish it",
                self.path,
                line,
            )
        if self.use_gui is None:
            return
        self.gui_publisher(actions)

    def spawn_description(
        self, found: list[Node], publishers: list[Node], description: list[Token] | None
    ) -> bool:
        """ros_gz_sim create -topic robot_description reads what robot_state_publisher publishes: with
        none in this file, create gets the description as its own parameter instead (-param: ROS 1's
        spawn_model -param read the global parameter). True when a create node took it."""
        took = False
        for node in found:
            words = [literal(w) for w in node.arguments]
            if (
                (node.package, node.executable) != ros1_names.GZ_SPAWNER
                or publishers
                or "-topic" not in words
            ):
                continue
            at = words.index("-topic")
            if at + 1 >= len(words) or words[at + 1] != "robot_description":
                continue
            model = description or self.package_description
            if model is None:
                self.notes.add(
                    "migrate-gazebo-classic",
                    "ros_gz_sim create waits for /robot_description, which nothing here publishes (ROS 1 "
                    "read the global parameter another launch file set): start robot_state_publisher too",
                    self.path,
                    node.line,
                )
                continue
            node.arguments[at] = [Token("text", "-param")]
            node.params.append(Param("robot_description", model, "description"))
            took = True
            self.notes.add(
                "migrate-changed",
                "ros_gz_sim create -param robot_description: create reads the model as its own parameter "
                "(nothing here publishes /robot_description)",
                self.path,
                node.line,
            )
        return took

    def gui_publisher(self, actions: list[Action]) -> None:
        assert self.use_gui is not None
        gui = literal(self.use_gui)
        for container, node in _node_places(actions):
            if node.package != "joint_state_publisher" or node.condition is not None:
                continue
            if gui is not None:
                if gui.strip().lower() in ("true", "1"):
                    node.package = node.executable = "joint_state_publisher_gui"
                continue
            with_gui = Node(
                "joint_state_publisher_gui",
                "joint_state_publisher_gui",
                node.line,
                output=node.output,
                condition=("if", self.use_gui),
            )
            node.condition = ("unless", self.use_gui)
            container.insert(container.index(node) + 1, with_gui)


def _literal_value(parts: list[Token] | None) -> str | None:
    """An argument's value when it is written literally, lower case; None otherwise."""
    text = literal(parts) if parts is not None else None
    return text.strip().lower() if text else None


def _with_defaults(parts: list[Token], actions: list[Action]) -> list[Token] | None:
    """The tokens with each launch argument replaced by its default (a description another launch
    file can use), or None when one has no default that is free of arguments."""
    defaults = {a.name: a.default for a in actions if isinstance(a, Arg) and a.default is not None}
    out: list[Token] = []
    for part in parts:
        if part[0] != "var":
            out.append(part)
            continue
        default = defaults.get(part[1])
        if default is None or any(p[0] == "var" for p in default):
            return None
        out.extend(default)
    return out


def _node_places(actions: list[Action]) -> Iterator[tuple[list[Action], Node]]:
    for action in list(actions):
        if isinstance(action, Node):
            yield actions, action
        elif isinstance(action, Group):
            yield from _node_places(action.actions)


def nodes(actions: list[Action]) -> Iterator[Node]:
    for _, node in _node_places(actions):
        yield node


def token_lists(actions: list[Action]) -> Iterator[list[Token]]:
    """Every token list in actions: defaults, arguments, parameters, conditions, includes."""
    for action in actions:
        condition = None if isinstance(action, Arg) else action.condition
        if condition:
            yield condition[1]
        if isinstance(action, Arg):
            yield action.default or []
        elif isinstance(action, Node):
            yield from action.arguments
            yield from (param.value or [] for param in action.params)
            yield from (part for remap in action.remaps for part in remap)
        elif isinstance(action, Include):
            yield action.path
            yield from (value for _, value in action.arguments)
        elif isinstance(action, Group):
            yield action.namespace or []
            yield from token_lists(action.actions)


def _variables(actions: list[Action]) -> set[str]:
    """Names of the launch arguments anything in actions reads."""
    return {p[1] for parts in token_lists(actions) for p in parts if p[0] == "var"}
