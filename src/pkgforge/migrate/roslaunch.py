"""ROS 1 launch XML (roslaunch) → plain actions, read with lxml so every element keeps its line.

Substitutions become tokens: Token("text", s), Token("find", pkg), Token("var", name),
Token("env", name, default), Token("anon", name), Token("dirname"). What ROS 2 cannot express is a
`migrate-dropped` note at its line.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Literal, NamedTuple

from lxml import etree

from pkgforge.errors import PkgforgeError
from pkgforge.model import ros1_names

if TYPE_CHECKING:
    from pkgforge.migrate.notes import Notes

SUBSTITUTION = re.compile(r"\$\(([a-z_]+)((?:\s+[^)\s]+)*)\s*\)")
XACRO_COMMAND = re.compile(
    r"^\s*(?:\$\(find xacro\)/xacro(?:\.py)?|xacro(?:\.py)?|rosrun xacro xacro(?:\.py)?)\s+"
)


class Unconvertible(Exception):
    pass


class Token(NamedTuple):
    """A piece of a roslaunch value: text, or a substitution the emitters write in ROS 2 terms."""

    kind: Literal["text", "find", "var", "env", "anon", "dirname"]
    value: str = ""  # the text, package, argument, variable or name ("" for dirname)
    default: str | None = None  # env: $(optenv NAME default)'s default


# <node if=...>/<group unless=...>: the attribute and its value
Condition = tuple[Literal["if", "unless"], list[Token]]


def tokens(text: str | None) -> list[Token]:
    """A roslaunch attribute value as tokens; $(eval) and unknown substitutions raise Unconvertible."""
    if text is None:
        return []
    found: list[Token] = []
    position = 0
    for match in SUBSTITUTION.finditer(text):
        if match.start() > position:
            found.append(Token("text", text[position : match.start()]))
        kind, words = match.group(1), match.group(2).split()
        if kind == "find" and len(words) == 1:
            found.append(Token("find", words[0]))
        elif kind == "arg" and len(words) == 1:
            found.append(Token("var", words[0]))
        elif kind in ("env", "optenv") and words:
            found.append(Token("env", words[0], " ".join(words[1:]) if kind == "optenv" else None))
        elif kind == "anon" and len(words) == 1:
            found.append(Token("anon", words[0]))
        elif kind == "dirname" and not words:
            found.append(Token("dirname"))
        else:
            raise Unconvertible(f"$({kind}) has no ROS 2 equivalent pkgforge can write")
        position = match.end()
    if "$(" in text[position:]:
        raise Unconvertible(f"'{text}' holds a substitution pkgforge cannot read")
    if position < len(text):
        found.append(Token("text", text[position:]))
    return found


def literal(parts: list[Token]) -> str | None:
    """The text of tokens that are all text, else None."""
    return "".join(p[1] for p in parts) if all(p[0] == "text" for p in parts) else None


def split_words(parts: list[Token]) -> list[list[Token]]:
    """Tokens split at white space in their text (node args)."""
    words: list[list[Token]] = [[]]
    for part in parts:
        if part[0] != "text":
            words[-1].append(part)
            continue
        pieces = re.split(r"(\s+)", part[1])
        for piece in pieces:
            if not piece:
                continue
            if piece.isspace():
                words.append([])
            else:
                words[-1].append(Token("text", piece.strip("'\"")))
    return [w for w in words if w]


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
    remaps: list[tuple[str | None, str | None]] = field(default_factory=list)  # (from=, to=)
    condition: Condition | None = None


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


class Reader:
    def __init__(
        self,
        path: Path,
        package: str,
        notes: Notes,
        *,
        gazebo: bool,
        rename_launch: Callable[[list[Token]], list[Token]],
    ):
        self.path, self.package, self.notes, self.gazebo = path, package, notes, gazebo
        self.rename_launch = rename_launch  # tokens of an included ROS 1 launch file → ROS 2 tokens
        # (xacro tokens, line, kind)
        self.description: tuple[list[Token], int | None, str] | None = None
        self.use_gui: list[Token] | None = None

    def note(self, name: str, message: str, element: etree._Element) -> None:
        self.notes.add(name, message, self.path, element.sourceline)

    def read(self) -> LaunchFile:
        try:
            root = etree.parse(str(self.path), etree.XMLParser(remove_comments=True)).getroot()
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
        return LaunchFile(self.path, actions)

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

    def required(self, element: etree._Element, *names: str) -> None:
        missing = [n for n in names if not element.get(n)]
        if missing:
            raise Unconvertible(f"it has no {', '.join(missing)}= attribute")

    def read_arg(self, element: etree._Element) -> Arg:
        self.required(element, "name")
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
                "robot_description from xacro: a string parameter of "
                "robot_state_publisher (ParameterValue(Command(['xacro ', ...]), value_type=str))",
                element,
            )
            return tokens(re.sub(r"\s+", " ", rest))
        return None

    def read_param(self, element: etree._Element) -> None:
        self.required(element, "name")
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
        raise Unconvertible(
            "global <rosparam>: ROS 2 has no global parameters (load it in a node's <param from>)"
        )

    def read_include(self, element: etree._Element) -> Include | None:
        self.required(element, "file")
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
            package, launch = ros1_names.GZ_WORLD_LAUNCH
            world = next((v for k, v in arguments if k == "world_name"), None)
            self.notes.add(
                "migrate-renamed",
                f"{gz_package} {text.lstrip('/')} → {package} {launch} (Gazebo, started running)",
                self.path,
                element.sourceline,
            )
            dropped = [k or "(unnamed)" for k, _ in arguments if k != "world_name"]
            if dropped:
                self.note(
                    "migrate-dropped",
                    f"arguments {', '.join(dropped)} of {text.lstrip('/')} have no "
                    f"{package} equivalent: left out",
                    element,
                )
            return Include(
                [Token("find", package), Token("text", "/" + launch)],
                element.sourceline,
                [("gz_args", (world or [Token("text", "empty.sdf")]) + [Token("text", " -r")])],
                condition,
            )
        renamed = self.rename_launch(path)
        if renamed != path:
            self.notes.add(
                "migrate-changed",
                "included ROS 1 launch file → its ROS 2 name",
                self.path,
                element.sourceline,
            )
        return Include(renamed, element.sourceline, arguments, condition)

    def read_node(self, element: etree._Element) -> Node | None:
        self.required(element, "pkg", "type")
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
        if new_executable == "static_transform_publisher":
            node.arguments = self.transform_arguments(node.arguments, element)
        for attribute in ("machine", "launch-prefix", "required", "cwd", "clear_params"):
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
                    node.remaps.append((child.get("from"), child.get("to")))
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
        """Global robot_description → robot_state_publisher's parameter; use_gui → which publisher."""
        found = list(nodes(actions))
        if self.description is not None:
            description, line, _ = self.description
            publishers = [n for n in found if n.package == "robot_state_publisher"]
            for node in publishers:
                if not any(p.name == "robot_description" for p in node.params):
                    node.params.insert(0, Param("robot_description", description, "description"))
            if not publishers and not any(n.package == "ros_gz_sim" for n in found):
                self.notes.add(
                    "migrate-dropped",
                    "global robot_description left out: no robot_state_publisher here to publish it",
                    self.path,
                    line,
                )
        if self.use_gui is None:
            return
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
        elif isinstance(action, Include):
            yield action.path
            yield from (value for _, value in action.arguments)
        elif isinstance(action, Group):
            yield action.namespace or []
            yield from token_lists(action.actions)


def _variables(actions: list[Action]) -> set[str]:
    """Names of the launch arguments anything in actions reads."""
    return {p[1] for parts in token_lists(actions) for p in parts if p[0] == "var"}
