"""Actions read from a ROS 1 launch file → a ROS 2 launch file: Python, XML or YAML."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, TypeAlias

import yaml

from pkgforge.migrate.roslaunch import Action, Arg, Group, Include, Node
from pkgforge.migrate.tokens import Condition, Token

if TYPE_CHECKING:
    from pkgforge.model.distros import Distro

HEADER = "Converted from ROS 1 {source} by pkgforge migrate."

# what to_yaml hands yaml.safe_dump
YamlData: TypeAlias = "str | None | list[YamlData] | dict[str, YamlData]"


# --- frontend (XML, YAML) ---------------------------------------------------------------------


def frontend(parts: list[Token] | None) -> str:
    out: list[str] = []
    for part in parts or []:
        kind = part[0]
        if kind == "text":
            out.append(part[1])
        elif kind == "find":
            out.append(f"$(find-pkg-share {part[1]})")
        elif kind == "var":
            out.append(f"$(var {part[1]})")
        elif kind == "env":
            out.append(f"$(env {part[1]}{' ' + part[2] if part[2] else ''})")
        elif kind == "anon":
            out.append(f"$(anon {part[1]})")
        elif kind == "dirname":
            out.append("$(dirname)")
    return "".join(out)


def _words(words: list[list[Token]]) -> str:
    return " ".join(frontend(w) for w in words)


def _description(parts: list[Token]) -> str:
    return f"$(command 'xacro {frontend(parts)}')"


def _xml_attr(value: str) -> str:
    return value.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def to_xml(actions: list[Action], source: str, *, distro: Distro) -> str:
    param_type = distro.frontend_param_type
    lines = ['<?xml version="1.0"?>', f"<!-- {HEADER.format(source=source)} -->", "<launch>"]

    def attrs(pairs: Iterable[tuple[str, str | None]]) -> str:
        return "".join(f' {k}="{_xml_attr(v)}"' for k, v in pairs if v is not None)

    def cond(condition: Condition | None) -> list[tuple[str, str | None]]:
        return [(condition[0], frontend(condition[1]))] if condition else []

    def emit(items: list[Action], indent: str) -> None:
        for action in items:
            if isinstance(action, Arg):
                if action.fixed:
                    lines.append(
                        f"{indent}<let{attrs([('name', action.name), ('value', frontend(action.default))])}/>"
                    )
                else:
                    default = frontend(action.default) if action.default is not None else None
                    lines.append(
                        f"{indent}<arg{attrs([('name', action.name), ('default', default), ('description', action.doc)])}/>"
                    )
            elif isinstance(action, Node):
                head = attrs(
                    [
                        ("pkg", action.package),
                        ("exec", action.executable),
                        ("name", action.name),
                        ("namespace", action.namespace),
                        ("output", action.output),
                        ("respawn", action.respawn),
                        ("on_exit", "shutdown" if action.required and distro.frontend_on_exit else None),
                        ("args", _words(action.arguments) if action.arguments else None),
                        *cond(action.condition),
                    ]
                )
                children: list[str] = []
                for param in action.params:
                    if param.kind == "file":
                        children.append(f"<param{attrs([('from', frontend(param.value))])}/>")
                    elif param.kind == "description":
                        children.append(
                            f"<param{attrs([('name', param.name), ('value', _description(param.value)), ('type', 'str' if param_type else None)])}/>"
                        )
                    else:
                        children.append(
                            f"<param{attrs([('name', param.name), ('value', frontend(param.value))])}/>"
                        )
                children += [
                    f"<remap{attrs([('from', frontend(a)), ('to', frontend(b))])}/>" for a, b in action.remaps
                ]
                if children:
                    lines.append(f"{indent}<node{head}>")
                    lines.extend(f"{indent}  {c}" for c in children)
                    lines.append(f"{indent}</node>")
                else:
                    lines.append(f"{indent}<node{head}/>")
            elif isinstance(action, Include):
                head = attrs([("file", frontend(action.path)), *cond(action.condition)])
                if action.arguments:
                    lines.append(f"{indent}<include{head}>")
                    lines.extend(
                        f"{indent}  <arg{attrs([('name', k), ('value', frontend(v))])}/>"
                        for k, v in action.arguments
                    )
                    lines.append(f"{indent}</include>")
                else:
                    lines.append(f"{indent}<include{head}/>")
            elif isinstance(action, Group):
                lines.append(f"{indent}<group{attrs(cond(action.condition))}>")
                if action.namespace:
                    lines.append(
                        f'{indent}  <push-ros-namespace namespace="{_xml_attr(frontend(action.namespace))}"/>'
                    )
                emit(action.actions, indent + "  ")
                lines.append(f"{indent}</group>")

    emit(actions, "  ")
    lines.append("</launch>")
    return "\n".join(lines) + "\n"


def to_yaml(actions: list[Action], source: str, *, distro: Distro) -> str:
    param_type = distro.frontend_param_type

    def cond(condition: Condition | None) -> dict[str, YamlData]:
        return {condition[0]: frontend(condition[1])} if condition else {}

    def convert(items: list[Action]) -> list[YamlData]:
        out: list[YamlData] = []
        for action in items:
            if isinstance(action, Arg):
                if action.fixed:
                    out.append({"let": {"name": action.name, "value": frontend(action.default)}})
                    continue
                entry: dict[str, YamlData] = {"name": action.name}
                if action.default is not None:
                    entry["default"] = frontend(action.default)
                if action.doc:
                    entry["description"] = action.doc
                out.append({"arg": entry})
            elif isinstance(action, Node):
                entry = {"pkg": action.package, "exec": action.executable}
                for key, value in (
                    ("name", action.name),
                    ("namespace", action.namespace),
                    ("output", action.output),
                    ("respawn", action.respawn),
                ):
                    if value is not None:
                        entry[key] = value
                if action.required and distro.frontend_on_exit:
                    entry["on_exit"] = "shutdown"
                if action.arguments:
                    entry["args"] = _words(action.arguments)
                entry.update(cond(action.condition))
                params: list[YamlData] = []
                for param in action.params:
                    if param.kind == "file":
                        params.append({"from": frontend(param.value)})
                    elif param.kind == "description":
                        params.append(
                            {
                                "name": param.name,
                                "value": _description(param.value),
                                **({"type": "str"} if param_type else {}),
                            }
                        )
                    else:
                        params.append({"name": param.name, "value": frontend(param.value)})
                if params:
                    entry["param"] = params
                if action.remaps:
                    entry["remap"] = [{"from": frontend(a), "to": frontend(b)} for a, b in action.remaps]
                out.append({"node": entry})
            elif isinstance(action, Include):
                entry = {"file": frontend(action.path), **cond(action.condition)}
                if action.arguments:
                    entry["arg"] = [{"name": k, "value": frontend(v)} for k, v in action.arguments]
                out.append({"include": entry})
            elif isinstance(action, Group):
                children = convert(action.actions)
                if action.namespace:
                    children.insert(0, {"push-ros-namespace": {"namespace": frontend(action.namespace)}})
                out.append({"group": {**cond(action.condition), "children": children}})
        return out

    body = yaml.safe_dump({"launch": convert(actions)}, sort_keys=False, default_flow_style=False, width=1000)
    return f"# {HEADER.format(source=source)}\n" + body


# --- Python -----------------------------------------------------------------------------------


def py(parts: list[Token] | None) -> str:
    out: list[str] = []
    for part in parts or []:
        kind = part[0]
        if kind == "text":
            out.append(repr(part[1]))
        elif kind == "find":
            out.append(f"FindPackageShare({part[1]!r})")
        elif kind == "var":
            out.append(f"LaunchConfiguration({part[1]!r})")
        elif kind == "env":
            default = f", default_value={part[2]!r}" if part[2] else ""
            out.append(f"EnvironmentVariable({part[1]!r}{default})")
        elif kind == "anon":
            out.append(f"AnonName({part[1]!r})")
        elif kind == "dirname":
            out.append("ThisLaunchFileDir()")
    if len(out) == 1:
        return out[0]
    return "[" + ", ".join(out) + "]"


def _py_condition(condition: Condition) -> str:
    kind = "IfCondition" if condition[0] == "if" else "UnlessCondition"
    return f"{kind}({py(condition[1])})"


def to_python(actions: list[Action], source: str) -> str:
    body: list[str] = []

    def call(name: str, fields: list[str], condition: Condition | None, indent: str) -> None:
        if condition:
            fields = [*fields, f"condition={_py_condition(condition)}"]
        body.append(f"{indent}{name}(")
        body.extend(f"{indent}    {f}," for f in fields)
        body.append(f"{indent}),")

    def emit(items: list[Action], indent: str) -> None:
        for action in items:
            if isinstance(action, Arg):
                if action.fixed:
                    body.append(f"{indent}SetLaunchConfiguration({action.name!r}, {py(action.default)}),")
                    continue
                extra = f", default_value={py(action.default)}" if action.default is not None else ""
                doc = f", description={action.doc!r}" if action.doc else ""
                body.append(f"{indent}DeclareLaunchArgument({action.name!r}{extra}{doc}),")
            elif isinstance(action, Node):
                fields = [f"package={action.package!r}", f"executable={action.executable!r}"]
                for key, value in (
                    ("name", action.name),
                    ("namespace", action.namespace),
                    ("output", action.output),
                ):
                    if value is not None:
                        fields.append(f"{key}={value!r}")
                if action.respawn is not None:
                    fields.append(f"respawn={action.respawn.strip().lower() == 'true'!r}")
                if action.required:
                    fields.append("on_exit=Shutdown()")
                if action.arguments:
                    fields.append("arguments=[" + ", ".join(py(w) for w in action.arguments) + "]")
                params: list[str] = []
                for param in action.params:
                    if param.kind == "file":
                        params.append(py(param.value))
                    elif param.kind == "description":
                        command = (
                            "Command([" + ", ".join(["'xacro '", *(py([p]) for p in param.value)]) + "])"
                        )
                        params.append(f"{{{param.name!r}: ParameterValue({command}, value_type=str)}}")
                    else:
                        value = py(param.value)
                        if len(param.value) > 1 or param.value and param.value[0][0] != "text":
                            value = f"ParameterValue({value})"
                        params.append(f"{{{param.name!r}: {value}}}")
                if params:
                    fields.append("parameters=[" + ", ".join(params) + "]")
                if action.remaps:
                    fields.append(
                        "remappings=[" + ", ".join(f"({py(a)}, {py(b)})" for a, b in action.remaps) + "]"
                    )
                call("Node", fields, action.condition, indent)
            elif isinstance(action, Include):
                fields = [f"AnyLaunchDescriptionSource({py(action.path)})"]
                if action.arguments:
                    fields.append(
                        "launch_arguments=["
                        + ", ".join(f"({k!r}, {py(v)})" for k, v in action.arguments)
                        + "]"
                    )
                call("IncludeLaunchDescription", fields, action.condition, indent)
            elif isinstance(action, Group):
                body.append(f"{indent}GroupAction(")
                if action.condition:
                    body.append(f"{indent}    condition={_py_condition(action.condition)},")
                body.append(f"{indent}    actions=[")
                if action.namespace:
                    body.append(f"{indent}        PushRosNamespace({py(action.namespace)}),")
                emit(action.actions, indent + "        ")
                body.append(f"{indent}    ],")
                body.append(f"{indent}),")

    emit(actions, "        ")
    text = "\n".join(body)
    imports = {
        "launch": ["LaunchDescription"],
        "launch.actions": [
            "DeclareLaunchArgument",
            "GroupAction",
            "IncludeLaunchDescription",
            "SetLaunchConfiguration",
            "Shutdown",
        ],
        "launch.conditions": ["IfCondition", "UnlessCondition"],
        "launch.launch_description_sources": ["AnyLaunchDescriptionSource"],
        "launch.substitutions": [
            "AnonName",
            "Command",
            "EnvironmentVariable",
            "LaunchConfiguration",
            "ThisLaunchFileDir",
        ],
        "launch_ros.actions": ["Node", "PushRosNamespace"],
        "launch_ros.parameter_descriptions": ["ParameterValue"],
        "launch_ros.substitutions": ["FindPackageShare"],
    }
    head = [f'"""{HEADER.format(source=source)}"""', ""]
    for module, names in imports.items():
        used = [n for n in names if n == "LaunchDescription" or f"{n}(" in text]
        if used:
            head.append(f"from {module} import {', '.join(used)}")
    return (
        "\n".join(head)
        + "\n\n\ndef generate_launch_description():\n    return LaunchDescription([\n"
        + text
        + ("\n" if text else "")
        + "    ])\n"
    )


def used_packages(actions: list[Action]) -> set[str]:
    """Packages the converted file starts or looks up (xacro where it runs it)."""
    from pkgforge.migrate.roslaunch import nodes, token_lists

    found = {p[1] for parts in token_lists(actions) for p in parts if p[0] == "find"}
    for node in nodes(actions):
        found.add(node.package)
        if any(param.kind == "description" for param in node.params):
            found.add("xacro")
    return found
