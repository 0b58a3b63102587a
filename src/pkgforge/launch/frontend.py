"""XML and YAML launch files → the same runtime objects the Python API builds.

Covers <launch>, <arg> (with <choice>), <let>, <include> (with <arg>), <group>,
<node> (with <param>, <remap>), <executable>, <set_env>, <timer>, and the
substitutions $(var) $(find-pkg-share) $(find-pkg-prefix) $(find-exec)
$(exec-in-pkg) $(command) $(env) $(eval) $(dirname) $(filename) $(anon)
$(not) $(and) $(or) $(equals) $(not-equals). Each object records the line of
the element it came from.
"""

from __future__ import annotations

import yaml
from lxml import etree

from . import runtime as rt

UNSUPPORTED_TAGS_OK = {"log", "push-ros-namespace", "push_ros_namespace", "set_parameter",
                       "set_remap", "set-remap", "set-parameter", "unset_env", "set_use_sim_time"}


class FrontendError(Exception):
    def __init__(self, message: str, line: int | None):
        super().__init__(message)
        self.line = line


# --- substitution syntax --------------------------------------------------------------------

def parse_substitution(text: str) -> list:
    """`a$(var x)b` → [TextSubstitution('a'), LaunchConfiguration('x'), TextSubstitution('b')]."""
    parts, index, buffer = [], 0, []
    while index < len(text):
        if text.startswith("$(", index):
            if buffer:
                parts.append(rt.TextSubstitution(text="".join(buffer)))
                buffer = []
            end = _matching_paren(text, index + 1)
            parts.append(_substitution(text[index + 2:end]))
            index = end + 1
        else:
            buffer.append(text[index])
            index += 1
    if buffer:
        parts.append(rt.TextSubstitution(text="".join(buffer)))
    return parts


def _matching_paren(text: str, open_index: int) -> int:
    depth, quote, index = 0, None, open_index
    while index < len(text):
        char = text[index]
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
    args, current, quote, depth = [], [], None, 0
    for char in body:
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
            quote = char
            continue
        if char.isspace() and depth == 0:
            if current:
                args.append("".join(current))
                current = []
            continue
        if char == "(" and current[-1:] == ["$"]:
            depth += 1
        elif char == ")" and depth:
            depth -= 1
        current.append(char)
    if current:
        args.append("".join(current))
    return args


def _substitution(body: str):
    words = _split_arguments(body)
    if not words:
        raise FrontendError("empty substitution $()", None)
    name, args = words[0], [parse_substitution(a) for a in words[1:]]

    def arg(i, default=None):
        return args[i] if i < len(args) else default

    if name == "var":
        return rt.LaunchConfiguration(arg(0), default=arg(1))
    if name == "find-pkg-share":
        return rt.FindPackageShare(arg(0))
    if name == "find-pkg-prefix":
        return rt.FindPackagePrefix(arg(0))
    if name == "find-exec":
        return rt.FindExecutable(name=arg(0))
    if name == "exec-in-pkg":
        return rt.ExecutableInPackage(arg(0), arg(1))
    if name == "command":
        return rt.Command(arg(0, []))
    if name == "env":
        return rt.EnvironmentVariable(arg(0), default_value=arg(1))
    if name == "eval":
        return rt.PythonExpression(arg(0, []))
    if name == "dirname":
        return rt.ThisLaunchFileDir()
    if name == "filename":
        return rt.ThisLaunchFile()
    if name == "anon":
        return rt.AnonName(arg(0))
    if name == "not":
        return rt.NotSubstitution(arg(0))
    if name == "and":
        return rt.AndSubstitution(*args)
    if name == "or":
        return rt.OrSubstitution(*args)
    if name == "equals":
        return rt.EqualsSubstitution(arg(0), arg(1))
    if name == "not-equals":
        return rt.NotEqualsSubstitution(arg(0), arg(1))
    return rt.unsupported(f"$({name})", rt.Substitution)()


# --- a format-neutral element ---------------------------------------------------------------

class Element:
    def __init__(self, tag: str, attrs: dict, children: list, line: int | None):
        self.tag, self.attrs, self.children, self.line = tag, attrs, children, line

    def get(self, name, default=None):
        return self.attrs.get(name, default)

    def sub(self, name):
        value = self.get(name)
        return None if value is None else parse_substitution(str(value))

    def named(self, tag):
        return [c for c in self.children if c.tag == tag]


def _from_xml(node) -> Element:
    children = [_from_xml(c) for c in node if isinstance(c.tag, str)]
    return Element(node.tag, dict(node.attrib), children, node.sourceline)


CHILD_KEYS = {"param", "remap", "arg", "choice", "children", "env", "launch"}


def _from_yaml(tag: str, node, line: int | None) -> Element:
    attrs, children = {}, []
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


def parse_file(path: str, kind: str):
    rt._LAUNCH_FILES.add(path)
    with open(path, "rb") as handle:
        data = handle.read()
    if kind == "xml":
        try:
            root = etree.fromstring(data, etree.XMLParser(remove_comments=True, resolve_entities=False))
        except etree.XMLSyntaxError as error:
            raise FrontendError(f"not well-formed XML: {error.msg}", error.lineno) from None
        element = _from_xml(root)
    else:
        try:
            document = yaml.compose(data.decode("utf-8"))
        except yaml.YAMLError as error:
            mark = getattr(error, "problem_mark", None)
            raise FrontendError(f"not valid YAML: {error}", mark.line + 1 if mark else None) from None
        if not isinstance(document, yaml.MappingNode) or not document.value:
            raise FrontendError("a YAML launch file is a mapping with a 'launch' list", 1)
        key, value = document.value[0]
        element = Element(key.value, {}, [], key.start_mark.line + 1)
        if isinstance(value, yaml.SequenceNode):
            for item in value.value:
                if isinstance(item, yaml.MappingNode):
                    for sub_key, sub_value in item.value:
                        element.children.append(_from_yaml(sub_key.value, sub_value, sub_key.start_mark.line + 1))
    if element.tag != "launch":
        raise FrontendError(f"the root is <{element.tag}>, not <launch>", element.line)
    return rt.LaunchDescription(_entities(element.children, path))


def _entities(elements: list[Element], path: str) -> list:
    out = []
    for element in elements:
        rt._FRONTEND_LOCATION.append((path, element.line))
        try:
            entity = _entity(element, path)
        finally:
            rt._FRONTEND_LOCATION.pop()
        if entity is not None:
            out.append(entity)
    return out


def _condition(element: Element):
    if element.get("if") is not None:
        return rt.IfCondition(element.sub("if"))
    if element.get("unless") is not None:
        return rt.UnlessCondition(element.sub("unless"))
    return None


def _entity(element: Element, path: str):
    tag, condition = element.tag, _condition(element)
    if tag == "arg":
        choices = [c.get("value") for c in element.named("choice")] or None
        return rt.DeclareLaunchArgument(element.get("name"), default_value=element.sub("default"),
                                        description=element.get("description"), choices=choices,
                                        condition=condition)
    if tag == "let":
        return rt.SetLaunchConfiguration(element.get("name"), element.sub("value"), condition=condition)
    if tag == "include":
        arguments = [(a.get("name"), a.sub("value")) for a in element.named("arg")]
        return rt.IncludeLaunchDescription(rt.AnyLaunchDescriptionSource(element.sub("file")),
                                           launch_arguments=arguments, condition=condition)
    if tag == "group":
        scoped = str(element.get("scoped", "true")).lower() != "false"
        return rt.GroupAction(_entities(element.children, path), scoped=scoped, condition=condition)
    if tag in ("node", "lifecycle_node"):
        return rt.Node(package=element.sub("pkg"), executable=element.sub("exec"), name=element.sub("name"),
                       namespace=element.sub("namespace"), arguments=_arguments(element.get("args")),
                       parameters=_parameters(element), remappings=[(r.sub("from"), r.sub("to"))
                                                                     for r in element.named("remap")],
                       condition=condition)
    if tag == "executable":
        return rt.ExecuteProcess(cmd=_arguments(element.get("cmd")), condition=condition)
    if tag in ("set_env", "set-env"):
        return rt.SetEnvironmentVariable(element.get("name"), element.sub("value"), condition=condition)
    if tag == "timer":
        return rt.TimerAction(period=element.get("period"), actions=_entities(element.children, path),
                              condition=condition)
    if tag in UNSUPPORTED_TAGS_OK:
        return None
    return rt.unsupported(f"<{tag}>")()


def _arguments(text) -> list:
    if text is None:
        return []
    if isinstance(text, list):
        return [parse_substitution(str(t)) for t in text]
    return [parse_substitution(word) for word in _split_arguments(str(text))]


def _parameters(element: Element) -> list:
    values, files = {}, []
    for param in element.named("param"):
        if param.get("from") is not None:
            files.append(rt.ParameterFile(param.sub("from")))
            continue
        rt._FRONTEND_LOCATION.append((rt._FRONTEND_LOCATION[-1][0] if rt._FRONTEND_LOCATION else None,
                                      param.line))
        try:
            value_type = str if param.get("type") in ("str", "string") else None
            values[param.get("name")] = rt.ParameterValue(param.sub("value") or [], value_type=value_type)
        finally:
            rt._FRONTEND_LOCATION.pop()
    return ([values] if values else []) + files
