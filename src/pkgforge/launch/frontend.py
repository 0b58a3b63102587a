"""XML and YAML launch files → the same built-in objects the Python API builds.

The tags and substitutions are the target distro's (api_names.json, generated from the
real sources): one the distro lacks is the error ROS gives ("Unrecognized entity of the
type", "Unknown substitution"); a real one pkgforge does not evaluate is recorded as
unsupported and the file goes on. Evaluated: <arg> (with <choice>), <let>, <include>
(with <arg>), <group> (scoped, forwarding, <keep>), <reset>, <node> (with <param>,
<remap>), <node_container>, <load_composable_node>, <executable>, <set_env>,
<append_env>, <unset_env>, <reset_env>, <timer>, <ros_timer>, <push-ros-namespace>,
<set_remap>, <set_parameter>, <set_use_sim_time>, <set_parameters_from_file>, <log>,
<shutdown>; and every substitution but the log-dir and parameter ones. Each object
records the line of the element it came from.
"""

from __future__ import annotations

from collections.abc import Callable
from types import TracebackType
from typing import Any

import yaml
from lxml import etree

from pkgforge.launch.builtin.launch.action import LaunchDescriptionEntity
from pkgforge.launch.builtin.launch.actions import (
    AppendEnvironmentVariable,
    DeclareLaunchArgument,
    GroupAction,
    LogInfo,
    ResetEnvironment,
    ResetLaunchConfigurations,
    SetEnvironmentVariable,
    SetLaunchConfiguration,
    Shutdown,
    TimerAction,
    UnsetEnvironmentVariable,
)
from pkgforge.launch.builtin.launch.command import Command
from pkgforge.launch.builtin.launch.conditions import Condition, IfCondition, UnlessCondition
from pkgforge.launch.builtin.launch.execute_process import ExecuteProcess
from pkgforge.launch.builtin.launch.include_launch_description import IncludeLaunchDescription
from pkgforge.launch.builtin.launch.launch_description import LaunchDescription
from pkgforge.launch.builtin.launch.launch_description_sources import AnyLaunchDescriptionSource
from pkgforge.launch.builtin.launch.substitution import Substitution, TextSubstitution
from pkgforge.launch.builtin.launch.substitutions import (
    AllSubstitution,
    AndSubstitution,
    AnonName,
    AnySubstitution,
    EnvironmentVariable,
    EqualsSubstitution,
    FileContent,
    FindExecutable,
    IfElseSubstitution,
    LaunchConfiguration,
    NotEqualsSubstitution,
    NotSubstitution,
    OrSubstitution,
    PythonExpression,
    ThisLaunchFile,
    ThisLaunchFileDir,
)
from pkgforge.launch.builtin.launch_ros.actions import (
    PushRosNamespace,
    SetParameter,
    SetParametersFromFile,
    SetRemap,
    SetUseSimTime,
)
from pkgforge.launch.builtin.launch_ros.composable_nodes import (
    ComposableNode,
    ComposableNodeContainer,
    LoadComposableNodes,
)
from pkgforge.launch.builtin.launch_ros.node import Node
from pkgforge.launch.builtin.launch_ros.parameter_descriptions import ParameterFile, ParameterValue
from pkgforge.launch.builtin.launch_ros.substitutions import (
    ExecutableInPackage,
    FindPackagePrefix,
    FindPackageShare,
)
from pkgforge.launch.builtin.unsupported import unsupported
from pkgforge.launch.place import FRONTEND_LOCATION, LAUNCH_FILES
from pkgforge.model.source import NotRegularFile, open_regular
from pkgforge.model.yamlnodes import YAMLLimit, compose, load

Subs = list[Substitution]  # one attribute's text as substitutions (parse_substitution)
Attribute = str | list[str]  # an XML attribute, or a YAML scalar or list of scalars
# one substitution's arguments -> the object (`arg(i, default)`: the i-th argument, or `default`)
Arg = Callable[..., "Subs | str | None"]
Maker = Callable[[list[Subs], Arg], Substitution]


class FrontendError(Exception):
    def __init__(self, message: str, line: int | None) -> None:
        super().__init__(message)
        self.line = line


def decoded(data: bytes) -> str:
    """A front-end launch file's text as launch reads it: `open(file, 'r')` (launch.frontend's
    Parser.load), so the locale's encoding, UTF-8 where ROS 2 runs (it requires a UTF-8 locale),
    strict. A byte that is not UTF-8 refuses the file whatever its BOM or XML declaration says
    (a UTF-16 file, a Latin-1 one declaring encoding="ISO-8859-1"): FrontendError at the line of
    the first such byte, caused by the UnicodeDecodeError launch raises. Both engines say it
    through this function: the position is in the whole file (launch decodes it in chunks)."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise FrontendError(str(error), data.count(b"\n", 0, error.start) + 1) from error


# --- substitution syntax --------------------------------------------------------------------


def parse_substitution(text: str) -> Subs:
    """`a$(var x)b` → [TextSubstitution('a'), LaunchConfiguration('x'), TextSubstitution('b')]."""
    parts: Subs = []
    index = 0
    buffer: list[str] = []
    while index < len(text):
        if text[index] == "\\" and index + 1 < len(text):
            buffer.append(text[index + 1])  # launch's escapes: \$ \' \( ... are the character itself
            index += 2
        elif text.startswith("$(", index):
            if buffer:
                parts.append(TextSubstitution(text="".join(buffer)))
                buffer = []
            end = _matching_paren(text, index + 1)
            parts.append(_substitution(text[index + 2 : end]))
            index = end + 1
        else:
            buffer.append(text[index])
            index += 1
    if buffer:
        parts.append(TextSubstitution(text="".join(buffer)))
    return parts


def _matching_paren(text: str, open_index: int) -> int:
    depth, index = 0, open_index
    quote: str | None = None
    while index < len(text):
        char = text[index]
        if char == "\\":
            index += 2  # an escaped character neither quotes nor closes
            continue
        if quote:
            if char == quote:
                quote = None
        elif char in ("'", '"'):
            quote = char
        elif char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
            if depth == 0:
                return index
        index += 1
    raise FrontendError(f"unterminated substitution in {text!r}", None)


def _split_arguments(body: str) -> list[str]:
    args: list[str] = []
    current: list[str] = []
    quote: str | None = None
    depth = 0
    quoted = False  # '' is an argument too (an empty string)
    escaped = False
    for char in body:
        if escaped:  # kept with its backslash: parse_substitution of the argument reads it
            current.append(char)
            escaped = False
            continue
        if char == "\\":
            current.append(char)
            escaped = True
            continue
        if quote:
            if char == quote and depth == 0:
                quote = None
                continue
            current.append(char)
            if char == "(" and current[-2:-1] == ["$"]:
                depth += 1
            elif char == ")" and depth:
                depth -= 1
            continue
        if char in ("'", '"') and depth == 0:
            quote, quoted = char, True
            continue
        if char.isspace() and depth == 0:
            if current or quoted:
                args.append("".join(current))
                current, quoted = [], False
            continue
        if char == "(" and current[-1:] == ["$"]:
            depth += 1
        elif char == ")" and depth:
            depth -= 1
        current.append(char)
    if current or quoted:
        args.append("".join(current))
    return args


def _substitution(body: str) -> Substitution:
    words = _split_arguments(body)
    if not words:
        raise FrontendError("empty substitution $()", None)
    name, args = words[0], [parse_substitution(a) or [TextSubstitution(text="")] for a in words[1:]]

    def arg(i: int, default: str | None = None) -> Subs | str | None:
        return args[i] if i < len(args) else default

    from pkgforge.launch import api

    exposed = api.frontend()["substitutions"]
    if name not in exposed:
        raise RuntimeError(f"Unknown substitution: {name}")  # launch's own (frontend/expose.py)
    api.resolve(exposed[name])  # the real constructor's signature is checked from here on
    if name in SUBSTITUTIONS:
        return SUBSTITUTIONS[name](args, arg)
    unevaluated: Substitution = api.resolve(exposed[name])(*args)  # a real one pkgforge does not evaluate
    return unevaluated


def _count(name: str, args: list[Subs], low: int, high: int) -> None:
    if not low <= len(args) <= high:
        expected = str(low) if low == high else f"{low} to {high}"
        raise FrontendError(f"{name} substitution expects {expected} arguments", None)


def _boolean(cls: Callable[..., Substitution], name: str, count: int) -> Maker:
    def make(args: list[Subs], arg: Arg) -> Substitution:
        _count(name, args, count, count)
        return cls(*args)

    return make


def _counted(name: str, low: int, high: int, build: Callable[[Arg], Substitution]) -> Maker:
    """A substitution of `low` to `high` arguments, built from them by `build(arg)`."""

    def make(args: list[Subs], arg: Arg) -> Substitution:
        _count(name, args, low, high)
        return build(arg)

    return make


def _by_keyword(cls: Callable[..., Substitution]) -> Maker:
    """The arguments as `args=[...]`, as jazzy's parse passes them (its constructor takes *args)."""
    return lambda args, arg: cls(args=args)


def _var(args: list[Subs], arg: Arg) -> Substitution:
    _count("var", args, 1, 2)
    return LaunchConfiguration(arg(0), default=arg(1))


def _command(args: list[Subs], arg: Arg) -> Substitution:
    _count("command", args, 1, 2)
    return Command(arg(0), on_stderr=arg(1, "fail"))


def _if(args: list[Subs], arg: Arg) -> Substitution:
    _count("if", args, 2, 3)
    return IfElseSubstitution(arg(0), if_value=arg(1), else_value=arg(2, ""))


def _eval(args: list[Subs], arg: Arg) -> Substitution:
    _count("eval", args, 1, 2)
    return PythonExpression(arg(0)) if len(args) == 1 else PythonExpression(arg(0), arg(1))


SUBSTITUTIONS: dict[str, Maker] = {
    "var": _var,
    "find-pkg-share": _counted("find-pkg-share", 1, 1, lambda arg: FindPackageShare(arg(0))),
    "find-pkg-prefix": _counted("find-pkg-prefix", 1, 1, lambda arg: FindPackagePrefix(arg(0))),
    "find-exec": _counted("find-exec", 1, 1, lambda arg: FindExecutable(name=arg(0))),
    "exec-in-pkg": _counted("exec-in-pkg", 2, 2, lambda arg: ExecutableInPackage(arg(0), arg(1))),
    "command": _command,
    "env": _counted("env", 1, 2, lambda arg: EnvironmentVariable(arg(0), default_value=arg(1))),
    "eval": _eval,
    "dirname": _counted("dirname", 0, 0, lambda arg: ThisLaunchFileDir()),
    "filename": _counted("filename", 0, 0, lambda arg: ThisLaunchFile()),
    "anon": _counted("anon", 1, 1, lambda arg: AnonName(arg(0))),
    "not": _boolean(NotSubstitution, "not", 1),
    "and": _boolean(AndSubstitution, "and", 2),
    "or": _boolean(OrSubstitution, "or", 2),
    # jazzy's parse passes args=[...] to a constructor that takes *args: a TypeError in ROS too
    "all": _by_keyword(AllSubstitution),
    "any": _by_keyword(AnySubstitution),
    "equals": _boolean(EqualsSubstitution, "equals", 2),
    "not-equals": _boolean(NotEqualsSubstitution, "not-equals", 2),
    "if": _if,
    "file-content": _counted("file-content", 1, 1, lambda arg: FileContent(arg(0))),
}


# --- a format-neutral element ---------------------------------------------------------------


class Element:
    def __init__(
        self, tag: str, attrs: dict[str, Attribute], children: list[Element], line: int | None
    ) -> None:
        self.tag, self.attrs, self.children, self.line = tag, attrs, children, line

    def get(self, name: str, default: str | None = None) -> Attribute | None:
        return self.attrs.get(name, default)

    def sub(self, name: str) -> Subs | None:
        """An attribute's substitutions, standing on this element's line (an <include>'s <arg>,
        a <remap>: their own line, as the real front end locates what each element reads)."""
        value = self.get(name)
        if value is None:
            return None
        FRONTEND_LOCATION.append((FRONTEND_LOCATION[-1][0] if FRONTEND_LOCATION else None, self.line))
        try:
            return parse_substitution(str(value))
        finally:
            FRONTEND_LOCATION.pop()

    def named(self, tag: str) -> list[Element]:
        return [c for c in self.children if c.tag == tag]


def _from_xml(node: Any) -> Element:  # an lxml element
    children = [_from_xml(c) for c in node if isinstance(c.tag, str)]
    return Element(node.tag, dict(node.attrib), children, node.sourceline)


CHILD_KEYS = {"param", "remap", "arg", "choice", "children", "env", "launch", "keep", "composable_node"}


def _from_yaml(tag: str, node: yaml.Node, line: int | None) -> Element:
    attrs: dict[str, Attribute] = {}
    children: list[Element] = []
    if isinstance(node, yaml.MappingNode):
        for key_node, value_node in node.value:
            key = key_node.value
            if isinstance(value_node, yaml.SequenceNode) and (key in CHILD_KEYS or tag == "group"):
                for item in value_node.value:
                    if isinstance(item, yaml.MappingNode) and key in ("children", "launch"):
                        for sub_key, sub_value in item.value:
                            children.append(_from_yaml(sub_key.value, sub_value, sub_key.start_mark.line + 1))
                    else:
                        children.append(_from_yaml(key, item, item.start_mark.line + 1))
            elif isinstance(value_node, yaml.ScalarNode):
                attrs[key] = value_node.value
            elif isinstance(value_node, yaml.SequenceNode):
                attrs[key] = [v.value for v in value_node.value if isinstance(v, yaml.ScalarNode)]
    return Element(tag, attrs, children, line)


def parse_file(path: str, kind: str) -> LaunchDescription:
    LAUNCH_FILES.add(path)
    try:
        handle = open_regular(path)[0]  # an included FIFO or /dev/zero: no read that never ends
    except NotRegularFile as error:
        raise FrontendError(str(error.strerror), None) from None
    with open(handle, "rb", closefd=True) as stream:
        data = stream.read()
    text = decoded(data)
    if kind == "xml":
        try:
            # the bytes, not the text: expat, under launch's ElementTree, still reads the XML
            # declaration of the text it is given (ISO-8859-1 declared: each UTF-8 byte a character)
            root = etree.fromstring(data, etree.XMLParser(remove_comments=True, resolve_entities=False))
        except etree.XMLSyntaxError as error:
            raise FrontendError(f"not well-formed XML: {error.msg}", error.lineno) from None
        element = _from_xml(root)
    else:
        try:  # (libyaml's nodes and PyYAML's errors: model.yamlnodes)
            document = compose(text)
        except yaml.YAMLError as error:  # (past the reader's bounds too: nesting, aliases)
            mark = getattr(error, "problem_mark", None)
            words = error.problem if isinstance(error, YAMLLimit) else f"not valid YAML: {error}"
            raise FrontendError(str(words), mark.line + 1 if mark else None) from None
        if not isinstance(document, yaml.MappingNode) or not document.value:
            raise FrontendError("a YAML launch file is a mapping with a 'launch' list", 1)
        key, value = document.value[0]
        element = Element(key.value, {}, [], key.start_mark.line + 1)
        if isinstance(value, yaml.SequenceNode):
            for item in value.value:
                if isinstance(item, yaml.MappingNode):
                    for sub_key, sub_value in item.value:
                        element.children.append(
                            _from_yaml(sub_key.value, sub_value, sub_key.start_mark.line + 1)
                        )
    if element.tag != "launch":
        raise FrontendError(f"the root is <{element.tag}>, not <launch>", element.line)
    return LaunchDescription(_entities(element.children, path))


def _entities(elements: list[Element], path: str) -> list[LaunchDescriptionEntity]:
    out: list[LaunchDescriptionEntity] = []
    for element in elements:
        FRONTEND_LOCATION.append((path, element.line))
        try:
            entity = _entity(element, path)
        except FrontendError as error:
            if error.line is None:
                error.line = element.line
            raise
        except (TypeError, ValueError, RuntimeError) as error:  # what building the element raised
            raise FrontendError(f"{type(error).__name__}: {error}", element.line) from error
        finally:
            FRONTEND_LOCATION.pop()
        if entity is not None:
            out.append(entity)
    return out


def _condition(element: Element) -> Condition | None:
    if element.get("if") is not None:
        return IfCondition(element.sub("if"))
    if element.get("unless") is not None:
        return UnlessCondition(element.sub("unless"))
    return None


def _flag(element: Element, name: str) -> bool | None:
    """A bool attribute as the front end reads it (YAML rules; '1'/'0' too); None when absent."""
    value = element.get(name)
    if value is None:
        return None
    text = {"1": "true", "0": "false"}.get(str(value), str(value))
    loaded = load(text) if text else text
    if not isinstance(loaded, bool):
        raise FrontendError(f"Cannot convert value '{value}' to '{bool}'", element.line)
    return loaded


def _keeps(element: Element) -> dict[tuple[Substitution, ...], Subs | None] | None:
    keeps = element.named("keep")
    if not keeps:
        return None
    return {tuple(_required(k.sub("name"))): k.sub("value") for k in keeps}


def _required(subs: Subs | None) -> Subs:
    """An attribute the element cannot do without; missing: the TypeError building it raised."""
    if subs is None:
        raise TypeError("'NoneType' object is not iterable")
    return subs


def _entity(element: Element, path: str) -> LaunchDescriptionEntity:
    from pkgforge.launch import api

    tag, condition = element.tag, _condition(element)
    exposed = api.frontend()["actions"]
    if tag not in exposed:
        raise FrontendError(f"Unrecognized entity of the type: {tag}", element.line)
    if tag == "arg":
        choices = [c.get("value") for c in element.named("choice")] or None
        return DeclareLaunchArgument(
            element.get("name"),
            default_value=element.sub("default"),
            description=element.get("description"),
            choices=choices,
            condition=condition,
        )
    if tag == "let":
        return SetLaunchConfiguration(element.sub("name"), element.sub("value"), condition=condition)
    if tag == "include":
        arguments = [(a.sub("name"), a.sub("value")) for a in element.named("arg")]
        return IncludeLaunchDescription(
            AnyLaunchDescriptionSource(element.sub("file")),
            launch_arguments=arguments,
            condition=condition,
        )
    if tag == "group":
        options: dict[str, object] = {
            k: v
            for k, v in (("scoped", _flag(element, "scoped")), ("forwarding", _flag(element, "forwarding")))
            if v is not None
        }
        keeps = _keeps(element)
        if keeps is not None:
            options["launch_configurations"] = keeps
        children = [c for c in element.children if c.tag != "keep"]
        return GroupAction(_entities(children, path), condition=condition, **options)
    if tag == "reset":
        return ResetLaunchConfigurations(_keeps(element), condition=condition)
    if tag == "node":
        ros_args = element.get("ros_args")
        return Node(
            package=element.sub("pkg"),
            executable=element.sub("exec"),
            name=element.sub("name"),
            namespace=element.sub("namespace"),
            exec_name=element.sub("exec_name"),
            arguments=_arguments(element.get("args")),
            ros_arguments=None if ros_args is None else _arguments(ros_args),
            parameters=_parameters(element),
            remappings=[(r.sub("from"), r.sub("to")) for r in element.named("remap")],
            condition=condition,
            **_process_options(element),
        )
    if tag == "node_container":
        return ComposableNodeContainer(
            package=element.sub("pkg"),
            executable=element.sub("exec"),
            name=element.sub("name"),
            namespace=element.sub("namespace"),
            parameters=_parameters(element),
            composable_node_descriptions=[_composable(c) for c in element.named("composable_node")],
            condition=condition,
        )
    if tag == "load_composable_node":
        return LoadComposableNodes(
            composable_node_descriptions=[_composable(c) for c in element.named("composable_node")],
            target_container=element.sub("target"),
            condition=condition,
        )
    if tag == "executable":
        return ExecuteProcess(
            cmd=_arguments(element.get("cmd")),
            shell=bool(_flag(element, "shell")),
            name=element.sub("name"),
            condition=condition,
            **_process_options(element),
        )
    if tag == "set_env":
        return SetEnvironmentVariable(element.sub("name"), element.sub("value"), condition=condition)
    if tag == "append_env":
        options = {}  # (the dict[str, object] of <group>'s options)
        if _flag(element, "prepend") is not None:
            options["prepend"] = _flag(element, "prepend")
        if element.get("separator") is not None:
            options["separator"] = element.sub("separator")
        return AppendEnvironmentVariable(
            element.sub("name"), element.sub("value"), condition=condition, **options
        )
    if tag == "unset_env":
        return UnsetEnvironmentVariable(element.sub("name"), condition=condition)
    if tag == "reset_env":
        return ResetEnvironment(condition=condition)
    if tag in ("timer", "ros_timer"):
        return TimerAction(
            period=element.sub("period"), actions=_entities(element.children, path), condition=condition
        )
    if tag in ("push-ros-namespace", "push_ros_namespace"):
        return PushRosNamespace(element.sub("namespace"), condition=condition)
    if tag == "set_remap":
        return SetRemap(element.sub("from"), element.sub("to"), condition=condition)
    if tag == "set_parameter":
        return SetParameter(element.sub("name"), element.sub("value"), condition=condition)
    if tag == "set_use_sim_time":
        sim_time: LaunchDescriptionEntity = SetUseSimTime(element.sub("value"), condition=condition)
        return sim_time  # (an unsupported name: builtin/unsupported.py's class)
    if tag == "set_parameters_from_file":
        return SetParametersFromFile(element.sub("filename"), condition=condition)
    if tag == "log":
        return LogInfo(msg=element.sub("message"), condition=condition)
    if tag == "shutdown":
        return Shutdown(condition=condition)
    # a real tag pkgforge does not evaluate (set_ros_log_dir…): recorded, and the file goes on
    recorded: LaunchDescriptionEntity = unsupported(f"<{tag}>")()
    return recorded


def _process_options(element: Element) -> dict[str, Any]:
    """What launch's ExecuteProcess.parse reads of a <node> or <executable> that its execute
    performs: cwd, launch-prefix, output, respawn and the <env> children (additional_env)."""
    options: dict[str, Any] = {}
    for attribute, keyword in (
        ("cwd", "cwd"),
        ("launch-prefix", "prefix"),
        ("output", "output"),
        ("respawn", "respawn"),
    ):
        if element.get(attribute) is not None:
            options[keyword] = element.sub(attribute)
    variables = element.named("env")
    if variables:
        options["additional_env"] = {tuple(_required(e.sub("name"))): e.sub("value") for e in variables}
    return options


def _composable(element: Element) -> ComposableNode:
    with _located_at(element):
        return _composable_here(element)


def _composable_here(element: Element) -> ComposableNode:
    return ComposableNode(
        package=element.sub("pkg"),
        plugin=element.sub("plugin"),
        name=element.sub("name"),
        namespace=element.sub("namespace"),
        parameters=_parameters(element),
        remappings=[(r.sub("from"), r.sub("to")) for r in element.named("remap")],
    )


def _arguments(text: Attribute | None) -> list[Subs]:
    if text is None:
        return []
    if isinstance(text, list):
        return [parse_substitution(str(t)) for t in text]
    return [parse_substitution(word) for word in _split_arguments(str(text))]


def _parameters(element: Element) -> list[ParameterFile | ParameterDict]:
    """As launch_ros's front end: one group per <param>, in the elements' order (a parameter file
    or a one-entry dict, nested <param>s as a nested dict), each located at its own line."""
    out: list[ParameterFile | ParameterDict] = []
    for param in element.named("param"):
        with _located_at(param):
            if param.get("from") is not None:
                allowed = param.get("allow_substs")
                substs = False if allowed is None else _allow_substs(param, allowed)
                out.append(ParameterFile(param.sub("from"), allow_substs=substs))
            else:
                out.append(_parameter_dict([param]))
    return out


def _allow_substs(param: Element, value: Attribute) -> bool | Subs:
    """<param from=... allow_substs=...>: read as a bool (launch's get_attr(data_type=bool));
    text that is no bool is substitutions, as launch_ros takes it."""
    if isinstance(value, str):
        text = {"1": "true", "0": "false"}.get(value, value)
        try:
            loaded = yaml.safe_load(text) if text else text
        except yaml.YAMLError:
            loaded = None
        if isinstance(loaded, bool):
            return loaded
        return parse_substitution(value)
    return bool(value)


# name -> value, or a nested dict of them (as launch_ros's front end builds it)
ParameterDict = dict["Attribute | None", "ParameterValue | ParameterDict"]


def _parameter_dict(params: list[Element]) -> ParameterDict:
    values: ParameterDict = {}
    for param in params:
        with _located_at(param):
            nested = param.named("param")
            if nested:
                values[param.get("name")] = _parameter_dict(nested)
            else:
                value_type = str if param.get("type") in ("str", "string") else None
                values[param.get("name")] = ParameterValue(param.sub("value") or [], value_type=value_type)
    return values


class _located_at:
    """What is built inside is located at the element's line (in the same file)."""

    def __init__(self, element: Element) -> None:
        self.where = (FRONTEND_LOCATION[-1][0] if FRONTEND_LOCATION else None, element.line)

    def __enter__(self) -> None:
        FRONTEND_LOCATION.append(self.where)

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        FRONTEND_LOCATION.pop()
