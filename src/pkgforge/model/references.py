"""Static references: the packages and share paths a package's own files name, with lines.

Read without running anything, and always through a parser: XML (URDF,
xacro, SDF, launch XML) through lxml with comments and processing
instructions removed, YAML (launch YAML, RViz configs) through the YAML
composer, Python through `ast`. What a comment says is never a use.
Inside the values the parsers give (attribute values, element text, YAML
scalars): `package://pkg/...`, `$(find pkg)/...`, `$(find-pkg-share pkg)/...`,
launch `pkg` attributes and keys, RViz plugin classes; in Python launch files
the literal arguments of FindPackageShare, get_package_share_directory,
Node(package=...), PathJoinSubstitution and os.path.join, with names bound to
literals followed through the file.
"""

from __future__ import annotations

import ast
import dataclasses
import re
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.model.source import SourceFile, parse_python

if TYPE_CHECKING:  # both imported where they are used: most files need neither
    import yaml
    from lxml import etree

PACKAGE_NAME = r"[A-Za-z][A-Za-z0-9_]*"
# what ament accepts in practice (example-robot-data is a real, installed package name)
INSTALLED_NAME = r"[A-Za-z][A-Za-z0-9_\-]*"
TEXT_PATTERNS = [
    (re.compile(rf"package://({INSTALLED_NAME})(/[^\"'\s<>]*)?"), "package://"),
    (re.compile(rf"\$\(find\s+({INSTALLED_NAME})\)(/[^\"'\s<>)$]*)?"), "$(find)"),
    (re.compile(rf"\$\(find-pkg-share\s+({PACKAGE_NAME})\)(/[^\"'\s<>)$]*)?"), "$(find-pkg-share)"),
    (re.compile(rf"\$\(find-pkg-prefix\s+({PACKAGE_NAME})\)"), "$(find-pkg-prefix)"),
]
# inside launch XML/YAML values: xacro run by $(command) or found by $(find-exec)
VALUE_PATTERNS = [
    (re.compile(r"\$\(command\s+'?(xacro)\b"), "$(command xacro)"),
    (re.compile(r"\$\(find-exec\s+(xacro)\)"), "$(find-exec)"),
]
PACKAGE_ONLY = re.compile(PACKAGE_NAME)

SHARE_LOOKUPS = {"FindPackageShare", "get_package_share_directory", "get_package_share_path"}
PREFIX_LOOKUPS = {"FindPackagePrefix", "get_package_prefix"}
NODE_ACTIONS = {"Node", "ComposableNode", "LifecycleNode", "ExecutableInPackage", "ComposableNodeContainer"}
PATH_JOINS = {"PathJoinSubstitution", "os.path.join", "join", "path.join"}
STDLIB = set(sys.stdlib_module_names)


@dataclass(frozen=True)
class Reference:
    package: str
    relative: str | None  # a path inside the package's share folder, when one is named
    path: Path  # the file that names it
    line: int
    column: int | None
    via: str
    # a model's reference inside <xacro:if>/<xacro:unless>: that element's condition as written
    # ("if ${gazebo}"), the innermost one; None when xacro always reads it
    condition: str | None = None
    # a Python launch file's action given a condition= that does not hold with the declared
    # defaults (Node(..., condition=IfCondition(db)), db's default false): that argument as
    # written; what a file that could not be evaluated runs only with other settings
    launch_condition: str | None = None
    # a Python file's use inside an if/else branch of one of its functions: the branch as
    # written ("if LDS_MODEL == 'LDS-02'"); in a file that could not be evaluated, which branch
    # runs is unknown (turtlebot3's robot.launch.py picks a lidar driver by $LDS_MODEL)
    python_branch: str | None = None


def launch_kind(path: Path) -> str | None:
    """py | xml | yaml for launch files (by name, or by being in a launch/ folder); None for
    a file that is no launch file."""
    name = path.name
    for kind in ("py", "xml", "yaml"):
        if name.endswith((f".launch.{kind}", f"_launch.{kind}")):
            return kind
    if path.parent.name == "launch" and path.suffix in (".py", ".xml", ".yaml", ".yml"):
        return launch_format(name)
    return None


def launch_format(name: str) -> str:
    """py | yaml | xml: how to read a file already known to be a launch file (an included one
    too), by its extension; any other extension is read as XML, as launch's frontend does."""
    name = name.lower()
    if name.endswith(".py"):
        return "py"
    if name.endswith((".yaml", ".yml")):
        return "yaml"
    return "xml"


def scan(source: SourceFile) -> list[Reference]:
    text = source.text
    if text is None:
        return []
    kind = launch_kind(source.path)
    if kind == "py":
        return _scan_python(source, text)
    if source.path.suffix == ".py":  # the package's own modules and scripts: what they import
        return [r for r in _scan_python(source, text) if r.via == "import"]
    locate = _Locator(text)
    if source.path.suffix == ".rviz":
        found = _scan_rviz(source, text, locate)
    elif kind == "yaml":
        found = _scan_yaml(source, text, locate)
    elif source.path.suffix in (".yaml", ".yml"):
        found = _scan_config_yaml(source, text, locate)
    else:
        found = _scan_xml(source, text, locate, launch=kind == "xml")
    found.sort(key=lambda r: (r.line, r.column or 0))
    return found


class _Locator:
    """The line and column of a value a parser found, searched from the line the parser names
    (lxml gives an element's first line; an attribute may stand on a later one)."""

    def __init__(self, text: str):
        self.lines = text.splitlines()

    def __call__(self, needle: str, line: int) -> tuple[int, int | None]:
        for number in range(max(line, 1), min(len(self.lines), line + 200) + 1):
            column = self.lines[number - 1].find(needle)
            if column >= 0:
                return number, column + 1
        return line, None


def _in_value(
    text: str, patterns: list[tuple[re.Pattern[str], str]], path: Path, line: int, locate: _Locator
) -> list[Reference]:
    """References inside one parsed value (an attribute, an element's text, a YAML scalar)."""
    found: list[Reference] = []
    for pattern, via in patterns:
        for match in pattern.finditer(text):
            relative = (
                match.group(2).lstrip("/")
                if match.lastindex and match.lastindex >= 2 and match.group(2)
                else None
            )
            where = locate(match.group(0), line)
            column = where[1] + (match.start(1) - match.start(0)) if where[1] else None
            found.append(Reference(match.group(1), relative, path, where[0], column, via))
    return found


def _scan_xml(source: SourceFile, text: str, locate: _Locator, *, launch: bool) -> list[Reference]:
    from lxml import etree

    parser = etree.XMLParser(
        remove_comments=True, remove_pis=True, resolve_entities=False, no_network=True, huge_tree=False
    )
    try:
        root = etree.fromstring(text.encode("utf-8"), parser)
    except (etree.XMLSyntaxError, ValueError):
        return []  # urdf-invalid, xacro-error or the launch load error reports the file
    patterns = TEXT_PATTERNS + (VALUE_PATTERNS if launch else [])
    found: list[Reference] = []
    # the file's own <xacro:arg name default>: a condition on one of them is decided at the
    # defaults. Read once, and only for a file with a reference inside a condition (few are)
    arg_defaults: dict[str, str] | None = None

    def defaults() -> dict[str, str]:
        nonlocal arg_defaults
        if arg_defaults is None:
            arg_defaults = {
                e.get("name", ""): e.get("default", "")
                for e in root.iter()
                if isinstance(e.tag, str) and _xacro_kind(e) == "arg" and e.get("default") is not None
            }
        return arg_defaults

    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        line = element.sourceline or 1
        here: list[Reference] = []
        for name, value in element.attrib.items():
            if launch and name == "pkg" and PACKAGE_ONLY.fullmatch(value.strip()):
                where = locate(f"{name}=", line)
                here.append(Reference(value.strip(), None, source.path, where[0], where[1], "node pkg"))
            here += _in_value(value, patterns, source.path, line, locate)
        if element.text and element.text.strip():
            here += _in_value(element.text, patterns, source.path, line, locate)
        if element.tag == "plugin":
            here += _plugin_uses(element, source.path, locate)
        if here and not launch and (condition := _xacro_condition(element, defaults)) is not None:
            here = [dataclasses.replace(r, condition=condition) for r in here]
        found += here
    return found


def _xacro_kind(element: etree._Element) -> str:
    """'if' for <xacro:if>, and so on; '' for an element that is not xacro's. xacro goes by the
    prefix, whatever namespace it is bound to (files use both http://www.ros.org/wiki/xacro and
    http://wiki.ros.org/xacro); unbound, lxml keeps the prefix in the tag."""
    tag = element.tag
    if not isinstance(tag, str):
        return ""
    if element.prefix == "xacro":
        return tag.rpartition("}")[2]
    return tag.removeprefix("xacro:") if tag.startswith("xacro:") else ""


ARG_REFERENCE = re.compile(r"^\$\(arg\s+([\w-]+)\)$")
XACRO_TRUE, XACRO_FALSE = ("true", "1"), ("false", "0")


def _xacro_condition(element: etree._Element, arg_defaults: Callable[[], dict[str, str]]) -> str | None:
    """The condition of an <xacro:if>/<xacro:unless> around `element` that does not hold at the
    file's defaults (or cannot be decided), as written: xacro reads what is inside only when it
    holds (franka's $(find franka_gazebo_bringup) under <xacro:if value="${gazebo}">). None when
    every one around it holds with the defaults: xacro reads it then."""
    for ancestor in element.iterancestors():
        kind = _xacro_kind(ancestor)
        if kind not in ("if", "unless"):
            continue
        value = (ancestor.get("value") or "").strip()
        argument = ARG_REFERENCE.match(value)
        decided = ((arg_defaults().get(argument.group(1)) or "") if argument else value).strip().lower()
        if decided in (XACRO_TRUE if kind == "if" else XACRO_FALSE):
            continue  # holds at the defaults
        return f"{kind} {value}".strip()
    return None


# Gazebo plugin libraries whose file name is not their package's name
PLUGIN_LIBRARIES = {
    "libgazebo_ros2_control": "gazebo_ros2_control",
    "libgazebo_ros_": "gazebo_plugins",
    "libgz_ros2_control": "gz_ros2_control",
    "gz_ros2_control": "gz_ros2_control",
    "libign_ros2_control": "ign_ros2_control",
    "ign_ros2_control": "ign_ros2_control",
}


def _plugin_uses(element: etree._Element, path: Path, locate: _Locator) -> list[Reference]:
    """<plugin>pkg/Class</plugin> (ros2_control hardware) and <plugin filename="lib...so">
    (Gazebo): the package that provides the plugin."""
    found: list[Reference] = []
    line = element.sourceline or 1
    text = (element.text or "").strip()
    if "/" in text and PACKAGE_ONLY.fullmatch(text.split("/")[0]):
        where = locate(text, line)
        found.append(Reference(text.split("/")[0], None, path, where[0], where[1], "plugin"))
    filename = (element.get("filename") or "").strip()
    if filename:
        stem = filename.split("/")[-1].removesuffix(".so").removesuffix("-system")
        package = next(
            (p for prefix, p in PLUGIN_LIBRARIES.items() if stem.startswith(prefix)), stem.removeprefix("lib")
        )
        if PACKAGE_ONLY.fullmatch(package):
            where = locate(filename, line)
            found.append(Reference(package, None, path, where[0], where[1], "plugin"))
    return found


def _scan_config_yaml(source: SourceFile, text: str, locate: _Locator) -> list[Reference]:
    """ros2_control and pluginlib YAML: `type: joint_trajectory_controller/JointTrajectoryController`,
    `plugin: "nav2_..::.."`: the package each class comes from; parameters of the
    controller_manager node (`controller_manager: {ros__parameters: ...}`) use controller_manager."""
    import yaml

    from pkgforge.model.yamlnodes import compose_all

    found: list[Reference] = []
    try:
        documents = compose_all(text)
    except yaml.YAMLError:
        return found
    for document in documents:
        if isinstance(document, yaml.MappingNode):
            for key_node, value_node in document.value:
                if (
                    getattr(key_node, "value", None) == "controller_manager"
                    and isinstance(value_node, yaml.MappingNode)
                    and any(getattr(k, "value", None) == "ros__parameters" for k, _ in value_node.value)
                ):
                    line = key_node.start_mark.line + 1
                    found.append(
                        Reference(
                            "controller_manager",
                            None,
                            source.path,
                            line,
                            key_node.start_mark.column + 1,
                            "plugin",
                        )
                    )
    for key, value, line in _yaml_scalars(text):
        if key not in ("type", "plugin", "plugin_name", "plugins"):
            continue
        value = value.strip()
        package = value.split("/")[0] if "/" in value else value.split("::")[0] if "::" in value else None
        if package and PACKAGE_ONLY.fullmatch(package):
            where = locate(value, line)
            found.append(Reference(package, None, source.path, where[0], where[1], "plugin"))
    return found


def _yaml_scalars(text: str) -> Iterator[tuple[str | None, str, int]]:
    """(key or None, scalar value, line) for every scalar of every YAML document."""
    import yaml

    from pkgforge.model.yamlnodes import compose_all

    try:
        documents = compose_all(text)
    except yaml.YAMLError:
        return
    todo: list[tuple[str | None, yaml.Node]] = [
        (None, document) for document in documents if document is not None
    ]
    while todo:
        key, node = todo.pop()
        if isinstance(node, yaml.ScalarNode):
            yield key, node.value, node.start_mark.line + 1
        elif isinstance(node, yaml.SequenceNode):
            todo += [(key, child) for child in node.value]
        elif isinstance(node, yaml.MappingNode):
            for key_node, value_node in node.value:
                name = key_node.value if isinstance(key_node, yaml.ScalarNode) else None
                todo.append((name, value_node))


def _scan_yaml(source: SourceFile, text: str, locate: _Locator) -> list[Reference]:
    found: list[Reference] = []
    for key, value, line in _yaml_scalars(text):
        if key == "pkg" and PACKAGE_ONLY.fullmatch(value.strip()):
            where = locate(value.strip(), line)
            found.append(Reference(value.strip(), None, source.path, where[0], where[1], "node pkg"))
        found += _in_value(value, TEXT_PATTERNS + VALUE_PATTERNS, source.path, line, locate)
    return found


def _scan_rviz(source: SourceFile, text: str, locate: _Locator) -> list[Reference]:
    found: list[Reference] = []
    for key, value, line in _yaml_scalars(text):
        if key == "Class" and "/" in value:
            package = value.split("/")[0].strip()
            if PACKAGE_ONLY.fullmatch(package):
                where = locate(value, line)
                found.append(Reference(package, None, source.path, where[0], where[1], "rviz plugin"))
    return found


def _scan_python(source: SourceFile, text: str) -> list[Reference]:
    try:
        tree = parse_python(text, filename=str(source.path))
    except SyntaxError:
        return []
    found: list[Reference] = []
    nodes = list(ast.walk(tree))  # walked once: the bindings and the calls both look at every node
    bindings = _literal_bindings(nodes)
    wrappers = _lookup_wrappers(nodes)
    defaults, configurations = _argument_defaults(nodes)

    def off_at_defaults(condition: ast.AST) -> bool:
        """IfCondition(LaunchConfiguration('db')) with db's declared default false (Unless with
        true): the action does not run with the defaults."""
        if not isinstance(condition, ast.Call) or not condition.args:
            return False
        kind = _name(condition.func).split(".")[-1]
        argument = condition.args[0]
        if isinstance(argument, ast.Name):
            argument = configurations.get(argument.id, argument)
        if not (
            isinstance(argument, ast.Call)
            and _name(argument.func).split(".")[-1] == "LaunchConfiguration"
            and argument.args
        ):
            return False
        default = defaults.get(literal(argument.args[0]) or "")
        if default is None:
            return False
        return (kind, default.lower()) in {
            ("IfCondition", "false"),
            ("IfCondition", "0"),
            ("UnlessCondition", "true"),
            ("UnlessCondition", "1"),
        }

    def literal(node: ast.AST) -> str | None:
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            return node.value
        bound = bindings.get(node.id) if isinstance(node, ast.Name) else None
        return bound if isinstance(bound, str) else None

    def share_of(node: ast.AST) -> str | None:
        """The package whose share folder `node` evaluates to, if it is a lookup."""
        bound = bindings.get(node.id) if isinstance(node, ast.Name) else None
        if isinstance(bound, ast.Call):
            node = bound
        if isinstance(node, ast.Call) and _name(node.func).split(".")[-1] in SHARE_LOOKUPS and node.args:
            return literal(node.args[0])
        return None

    for node in nodes:
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            if isinstance(node, ast.ImportFrom) and node.level:
                continue  # a relative import names no package
            modules = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
            for module in modules:
                top = module.split(".")[0]
                if top and top not in STDLIB:
                    found.append(
                        Reference(top, None, source.path, node.lineno, node.col_offset + 1, "import")
                    )
            continue
        if not isinstance(node, ast.Call):
            continue
        name = _name(node.func).split(".")[-1] if not _name(node.func).startswith("os.") else _name(node.func)
        position = (node.lineno, node.col_offset + 1)
        if name in SHARE_LOOKUPS | PREFIX_LOOKUPS and node.args:
            package = literal(node.args[0])
            if package:
                found.append(Reference(package, None, source.path, *position, name))
        elif name in wrappers:
            # load_yaml('moveit_resources_panda_moveit_config', 'config/kinematics.yaml'): the
            # file's own function hands that argument to get_package_share_directory
            index, parameter, lookup = wrappers[name]
            given = node.args[index] if index < len(node.args) else None
            given = next((k.value for k in node.keywords if k.arg == parameter), given)
            package = literal(given) if given is not None else None
            if package:
                found.append(Reference(package, None, source.path, *position, lookup))
        elif name in NODE_ACTIONS:
            condition = next(
                (
                    ast.unparse(k.value)
                    for k in node.keywords
                    if k.arg == "condition" and off_at_defaults(k.value)
                ),
                None,
            )
            for keyword in node.keywords:
                if keyword.arg == "package" and (package := literal(keyword.value)):
                    found.append(
                        Reference(package, None, source.path, *position, name, launch_condition=condition)
                    )
        elif name in PATH_JOINS:
            parts = (
                node.args[0].elts
                if name == "PathJoinSubstitution"
                and node.args
                and isinstance(node.args[0], (ast.List, ast.Tuple))
                else node.args
            )
            if parts:
                package = share_of(parts[0])
                literals = [literal(p) for p in parts[1:]]
                rest = [r for r in literals if r is not None]
                if package and rest and len(rest) == len(literals):
                    first = parts[1]
                    found.append(
                        Reference(
                            package,
                            "/".join(r.strip("/") for r in rest),
                            source.path,
                            first.lineno,
                            first.col_offset + 1,
                            name,
                        )
                    )
        elif name == "Command" and node.args:
            first = (
                node.args[0].elts[0]
                if isinstance(node.args[0], (ast.List, ast.Tuple)) and node.args[0].elts
                else node.args[0]
            )
            command = literal(first)
            if command and command.split() and command.split()[0] == "xacro":
                found.append(Reference("xacro", None, source.path, *position, "Command xacro"))
        elif name == "FindExecutable":
            for keyword in node.keywords:
                if keyword.arg == "name" and literal(keyword.value) == "xacro":
                    found.append(Reference("xacro", None, source.path, *position, "FindExecutable"))
    branches = _python_branches(nodes)
    return [
        dataclasses.replace(r, python_branch=branches.get((r.line, r.column))) if r.via != "import" else r
        for r in found
    ]


def _python_branches(nodes: list[ast.AST]) -> dict[tuple[int, int | None], str]:
    """(line, column) of every node inside an if/elif/else branch of a function → that branch, the
    innermost, as written ("if LDS_MODEL == 'LDS-02'", "else of if use_sim")."""
    ifs: list[ast.If] = []
    for function in (n for n in nodes if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))):
        ifs += [
            n for n in ast.walk(function) if isinstance(n, ast.If) and not isinstance(n.test, ast.Constant)
        ]
    branches: dict[tuple[int, int | None], str] = {}
    # outer first (ast.walk is breadth first within a function; sorted by position across them):
    # an inner branch overwrites its outer one
    for branch in sorted(ifs, key=lambda n: (n.lineno, n.col_offset)):
        test = ast.unparse(branch.test)
        for body, text in ((branch.body, f"if {test}"), (branch.orelse, f"else of if {test}")):
            for statement in body:
                for node in ast.walk(statement):
                    if isinstance(node, (ast.expr, ast.stmt)):
                        branches[(node.lineno, node.col_offset + 1)] = text
    return branches


def _argument_defaults(nodes: list[ast.AST]) -> tuple[dict[str, str], dict[str, ast.Call]]:
    """The file's DeclareLaunchArgument literal defaults (name → default), and the names bound to
    a LaunchConfiguration (db_config = LaunchConfiguration('db'))."""
    defaults: dict[str, str] = {}
    configurations: dict[str, ast.Call] = {}
    for node in nodes:
        if isinstance(node, ast.Call) and _name(node.func).split(".")[-1] == "DeclareLaunchArgument":
            keywords = {k.arg: k.value for k in node.keywords}
            name = node.args[0] if node.args else keywords.get("name")
            default = node.args[1] if len(node.args) > 1 else keywords.get("default_value")
            if (
                isinstance(name, ast.Constant)
                and isinstance(name.value, str)
                and isinstance(default, ast.Constant)
                and isinstance(default.value, str)
            ):
                defaults[name.value] = default.value
        elif (
            isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and isinstance(node.targets[0], ast.Name)
            and isinstance(node.value, ast.Call)
            and _name(node.value.func).split(".")[-1] == "LaunchConfiguration"
        ):
            configurations[node.targets[0].id] = node.value
    return defaults, configurations


def _lookup_wrappers(nodes: list[ast.AST]) -> dict[str, tuple[int, str, str]]:
    """The file's functions that hand one of their parameters straight to a package lookup:
    name → (that parameter's position, its name, the lookup)."""
    wrappers: dict[str, tuple[int, str, str]] = {}
    for node in nodes:
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        parameters = [a.arg for a in [*node.args.posonlyargs, *node.args.args]]
        if parameters and parameters[0] in ("self", "cls"):
            parameters = parameters[1:]  # a method: its callers do not pass it
        for inner in ast.walk(node):
            if (
                isinstance(inner, ast.Call)
                and (lookup := _name(inner.func).split(".")[-1]) in SHARE_LOOKUPS | PREFIX_LOOKUPS
                and inner.args
                and isinstance(inner.args[0], ast.Name)
                and inner.args[0].id in parameters
            ):
                wrappers[node.name] = (parameters.index(inner.args[0].id), inner.args[0].id, lookup)
                break
    return wrappers


def _literal_bindings(nodes: list[ast.AST]) -> dict[str, object]:
    """name → str literal or lookup Call, from every simple assignment among the file's nodes."""
    bindings: dict[str, object] = {}
    for node in nodes:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            value = node.value
            if isinstance(value, ast.Constant) and isinstance(value.value, str):
                bindings[node.targets[0].id] = value.value
            elif isinstance(value, ast.Call) and _name(value.func).split(".")[-1] in SHARE_LOOKUPS:
                bindings[node.targets[0].id] = value
    return bindings


def _name(func: ast.AST) -> str:
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute):
        inner = _name(func.value)
        return f"{inner}.{func.attr}" if inner else func.attr
    return ""
