"""The fixers of simulation findings: an SDF <uri> into a home folder (PF421), a models folder
Gazebo is not told of (PF422), ros2_control_node given a description it ignores (PF709)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

from yaml import MappingNode

from pkgforge.diagnostics import Diagnostic
from pkgforge.fix.edits import Edit, NotOffered, SourceText, Unfixable, node_span
from pkgforge.fix.registry import Fix, FixContext, fixer, given
from pkgforge.model.cmake_syntax import Command

# PF422's hook: a file of the package, named in ament_environment_hooks() (ament_cmake_core's
# environment_hooks: a .in is configured with @ONLY, installed to share/<project>/environment and
# listed in the package's local_setup.dsv, which colcon's setup files read)
HOOK = "hooks/gz_resource_path.dsv.in"
HOOK_CALL = 'ament_environment_hooks("${CMAKE_CURRENT_SOURCE_DIR}/' + HOOK + '")'


@fixer("sdf-uri-unresolved")
def fix_sdf_home_uri(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    """A <uri> that is a path into a home folder, rewritten as the URI Gazebo finds the same model
    or mesh by once the package is installed (the check computes it from the install tree).

    Safe when the result is model://... and the models folder is on Gazebo's resource path: the
    path worked on its author's machine only, the model:// finds the installed copy of the same
    folder everywhere. Unsafe (the finding says so) when the folder is not on the resource path
    yet (the model:// alone would be found nowhere, the path at least on the author's machine:
    with --unsafe-fixes PF422's fix puts it there in the next pass) and for package://PKG/...
    (gz-common's FindFileURI drops the scheme and looks for PKG/... in each resource path folder:
    found only when the folder holding share/PKG is on it, which nothing of the package sets)."""
    fix_data = diagnostic.fix or {}
    if "uri" not in fix_data:
        raise NotOffered("not a path into a home folder")
    uri = given(diagnostic, "uri", "the finding names no URI")
    replacement = given(
        diagnostic,
        "replacement",
        "no model folder or mesh the package installs is at the end of that path: install it, "
        "then use model://NAME",
    )
    source = ctx.files.get(diagnostic.path)
    line = diagnostic.line or 0
    start = source.line_start(line)
    match = re.compile(r"<uri(\s[^>]*)?>(\s*)(.*?)\s*</uri>", re.S).search(source.text, start)
    if match is None or source.line_of(match.start()) != line:
        raise Unfixable(f"no <uri> element starts at {source.path.name}:{line}")
    if match.group(3) != uri:
        raise Unfixable(
            f"the <uri> at {source.path.name}:{line} is not the plain text {uri!r} (an entity, "
            "CDATA or a comment in it): edit it by hand"
        )
    fix = Fix(f"<uri> {uri} → {replacement}")
    fix.add(source.path, Edit(match.start(3), match.end(3), replacement))
    return fix


@fixer("gazebo-resource-path-unset")
def fix_resource_path(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    """An environment hook of the package that prepends share/<package>/models to the resource
    variable of each target distro's Gazebo, as ros_gz_sim_demos does (hooks/*.dsv.in named in
    ament_environment_hooks()), for ament_cmake packages.

    Safe: it sets a path where none was for a folder the package installs and its own worlds
    include from; whoever sources the workspace gets it, whichever way Gazebo is started (the
    <gazebo_ros gazebo_model_path> export works only through ros_gz_sim's gz_sim.launch.py, and
    only from ros_gz 0.244.14 on humble). A model of the same name elsewhere on the path is found
    after this one: the package's own worlds mean the package's own. ament_python: no fix. Its
    environment files are written by colcon's python build (colcon-ros' AmentPythonBuildTask), not
    from an ament_environment_hooks() list; a hook installed through setup.py's data_files is not
    one mechanical edit, and the alternative, an AppendEnvironmentVariable in the launch file that
    starts Gazebo, depends on which launch file the user starts: the reason says so."""
    folder = Path(
        given(
            diagnostic,
            "package",
            "the models folder is another package's: set its resource path there",
        )
    )
    build_type = given(diagnostic, "build_type", "the package's build type is unknown")
    if build_type != "ament_cmake":
        raise Unfixable(
            f"an {build_type} package has no environment hook of its own: add "
            "AppendEnvironmentVariable(...) for share/<package>/models to the launch file that starts Gazebo"
        )
    variables = (diagnostic.fix or {}).get("variables") or []
    if not isinstance(variables, list) or not all(isinstance(v, str) for v in variables):
        raise Unfixable("the finding names no resource variable")
    source = ctx.files.get(folder / "CMakeLists.txt")
    if HOOK in source.text:
        raise Unfixable(f"CMakeLists.txt names {HOOK} already; its hook does not set the path")
    ament = _top_level_ament_package(source)
    if not source.is_blank_before(source.offset(ament.line, ament.column)):
        raise Unfixable("ament_package() does not start its own line in CMakeLists.txt")
    line = ament.line
    while line > 1 and source.line_text(line - 1).lstrip().startswith("#"):
        line -= 1  # above the comment that goes with ament_package()
    start = source.line_start(line)
    fix = Fix(f"added {HOOK} (share/<package>/models on {' and '.join(variables)}) to CMakeLists.txt")
    indent = source.indentation(ament.line)
    comment = "# Gazebo finds model://NAME of share/<package>/models on its resource path only"
    fix.add(
        source.path,
        Edit(start, start, indent + comment + source.eol + indent + HOOK_CALL + source.eol + source.eol),
    )
    lines = [f"prepend-non-duplicate;{variable};share/@PROJECT_NAME@/models" for variable in variables]
    fix.create(folder / HOOK, "\n".join(lines) + "\n")
    return fix


def _top_level_ament_package(source: SourceText) -> Command:
    from pkgforge.fix.fixers import _cmake_commands

    depth = 0
    for command in _cmake_commands(source):
        if command.name in ("if", "function", "macro", "foreach", "while"):
            depth += 1
        elif command.name in ("endif", "endfunction", "endmacro", "endforeach", "endwhile"):
            depth = max(0, depth - 1)
        elif depth == 0 and command.name == "ament_package":
            return command
    raise Unfixable("CMakeLists.txt calls no ament_package() outside a block to put the hook before")


# --- PF709: ros2_control_node's robot_description parameter ---------------------------------------


@fixer("controller-description-delivery")
def fix_controller_description(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    """The robot_description parameter dropped from ros2_control_node, on targets that all read
    the /robot_description topic (ros2_control's jazzy branch and later: controller_manager.cpp
    subscribes to "robot_description", relative, so /robot_description in the root namespace, and
    never reads the parameter).

    Safe: the parameter is ignored there, so dropping it changes nothing the node does; whether
    robot_state_publisher publishes /robot_description is what decided the node's description
    before the fix and after it. (No remapping: ros2_control_demos' jazzy launch files have none;
    ~/robot_description was humble's topic.) Edited where the parameter is written as a literal
    in the node itself: an entry of a dict in parameters=[...] (or a list item that is a name
    bound once to such a dict of that key alone) in Python, a <param name="robot_description"
    .../> in XML, a `- name: robot_description` item of the node's block `param:` list of one-line
    name and value in YAML. A parameter file, a computed list or a flow-style list: by hand."""
    if (diagnostic.fix or {}).get("drop") is not True:
        raise NotOffered("the fix is a decision for the user (see the hint)")
    source = ctx.files.get(diagnostic.path)
    name = source.path.name
    if name.endswith(".py"):
        return _drop_python(source, diagnostic.line or 0)
    if name.endswith(".xml"):
        return _drop_xml(source, diagnostic.line or 0)
    if name.endswith((".yaml", ".yml")):
        return _drop_yaml(source, diagnostic.line or 0)
    raise Unfixable("only Python, XML and YAML launch files are edited: drop the parameter by hand")


def _drop_python(source: SourceText, line: int) -> Fix:
    from pkgforge.fix.launch_fixers import _containing_calls, _python

    tree = _python(source)
    for call in _containing_calls(tree, line, "Node"):
        keywords = {k.arg: k for k in call.keywords if k.arg}
        executable = keywords.get("executable")
        if executable is None or not (
            isinstance(executable.value, ast.Constant) and executable.value.value == "ros2_control_node"
        ):
            continue
        parameters = keywords.get("parameters")
        if parameters is None or not isinstance(parameters.value, (ast.List, ast.Tuple)):
            raise Unfixable("the node's parameters are not a list written in the Node(...): drop it by hand")
        elements = parameters.value.elts
        for index, element in enumerate(elements):
            if isinstance(element, ast.Dict):
                keys = [_key(k) for k in element.keys]
                if "robot_description" not in keys:
                    continue
                if len(keys) == 1:
                    return _dropped(source, _remove_item(source, elements, index), "the parameter dict")
                position = keys.index("robot_description")
                pairs = [_pair(source, k, v) for k, v in zip(element.keys, element.values, strict=True)]
                return _dropped(source, _remove_span(source, pairs, position), "its entry")
            if isinstance(element, ast.Name) and _bound_to_description(tree, element.id):
                return _dropped(source, _remove_item(source, elements, index), element.id)
        raise Unfixable(
            "robot_description is not a literal entry of the node's parameters=[...]: drop it by hand"
        )
    raise Unfixable(f"cannot find the ros2_control_node Node(...) at line {line}")


def _key(node: ast.expr | None) -> str | None:
    return node.value if isinstance(node, ast.Constant) and isinstance(node.value, str) else None


def _bound_to_description(tree: ast.Module, name: str) -> bool:
    """Whether `name` is bound once, to a dict literal whose one key is robot_description."""
    bindings = [
        node
        for node in ast.walk(tree)
        if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign, ast.NamedExpr))
        and name in {t.id for t in ast.walk(node) if isinstance(t, ast.Name) and isinstance(t.ctx, ast.Store)}
    ]
    if len(bindings) != 1 or not isinstance(bindings[0], ast.Assign):
        return False
    value = bindings[0].value
    return isinstance(value, ast.Dict) and [_key(k) for k in value.keys] == ["robot_description"]


def _pair(source: SourceText, key: ast.expr | None, value: ast.expr) -> tuple[int, int]:
    if key is None:
        raise Unfixable("the parameter dict unpacks another (**...): drop the parameter by hand")
    return node_span(source, key)[0], node_span(source, value)[1]


def _remove_item(source: SourceText, elements: list[ast.expr], index: int) -> Edit:
    return _remove_span(source, [node_span(source, e) for e in elements], index)


def _remove_span(source: SourceText, spans: list[tuple[int, int]], index: int) -> Edit:
    """Remove one item of a comma-separated sequence, with the comma and the space it owns: up to
    the next item's start, or (the last item) from the previous item's end, a trailing comma kept."""
    start, end = spans[index]
    if index + 1 < len(spans):
        following = spans[index + 1][0]
        between = source.text[end:following]
        if "\n" in between and source.is_blank_before(start):  # the item has its own line(s)
            return Edit(
                source.line_start(source.line_of(start)), source.line_start(source.line_of(following)), ""
            )
        return Edit(start, following, "")
    if index > 0:
        previous = spans[index - 1][1]
        if "\n" in source.text[previous:start] and source.is_blank_before(start):
            rest = source.text[end : source.line_end(source.line_of(end))]
            if re.fullmatch(r"\s*,?\s*", rest):  # `item,` alone on its line(s): the lines go
                return Edit(
                    source.line_start(source.line_of(start)), source.line_end(source.line_of(end)), ""
                )
        return Edit(previous, end, "")
    return Edit(start, end, "")  # the only item: the brackets stay, empty


def _dropped(source: SourceText, edit: Edit, what: str) -> Fix:
    fix = Fix(f"removed robot_description ({what}) from ros2_control_node's parameters")
    fix.add(source.path, edit)
    return fix


def _drop_xml(source: SourceText, line: int) -> Fix:
    from pkgforge.fix.fixers import _delete_span

    start = source.line_start(line)
    node = re.compile(r"<node\b[^>]*?(/?)>", re.S).search(source.text, start)
    if node is None or source.line_of(node.start()) != line:
        raise Unfixable(f"cannot find the ros2_control_node <node> at line {line}")
    if node.group(1) == "/":
        raise Unfixable("the <node> has no <param> children")
    close = source.text.find("</node>", node.end())
    body = source.text[node.end() : close] if close >= 0 else ""
    params = [
        m
        for m in re.finditer(r"<param\b[^>]*?/>", body, re.S)
        if re.search(r"""\bname\s*=\s*["']robot_description["']""", m.group(0))
    ]
    if len(params) != 1 or "<node" in body:
        raise Unfixable(
            'the node has no one <param name="robot_description" .../> of its own: edit it by hand'
        )
    fix = Fix('removed <param name="robot_description"> from ros2_control_node')
    offset = node.end()
    fix.add(source.path, _delete_span(source, offset + params[0].start(), offset + params[0].end()))
    return fix


def _drop_yaml(source: SourceText, line: int) -> Fix:
    """The node's `- name: robot_description` item, its lines removed (the `param:` key's too
    when it is the only item: an empty param is null, which launch's YAML parser refuses)."""
    import yaml

    from pkgforge.model.yamlnodes import compose

    try:
        root = compose(source.text)
    except yaml.YAMLError as exc:
        raise Unfixable(f"{source.path.name} does not parse: {exc}".splitlines()[0]) from exc
    node = _yaml_node_at(root, line)
    if node is None:
        raise Unfixable(f"cannot find the ros2_control_node node at line {line}")
    param = next(((k, v) for k, v in node.value if k.value == "param"), None)
    if param is None or not isinstance(param[1], yaml.SequenceNode) or param[1].flow_style:
        raise Unfixable("the node's param is not a block list (- name: ...): drop the parameter by hand")
    items = param[1].value
    index = next((i for i, item in enumerate(items) if _names_description(item)), None)
    if index is None:
        raise Unfixable("no `- name: robot_description` item of one-line name and value: drop it by hand")
    first = items[index].start_mark.line  # 0-based
    last = max(v.end_mark.line for _, v in items[index].value)
    if not source.line_text(first + 1).lstrip().startswith("- "):
        raise Unfixable("the robot_description item does not start its own line: drop it by hand")
    if len(items) == 1:  # the key goes too
        if param[0].start_mark.line + 1 != first:
            raise Unfixable("param: and its one item are not on consecutive lines: drop it by hand")
        first = param[0].start_mark.line
    fix = Fix("removed the robot_description item from ros2_control_node's param")
    fix.add(source.path, Edit(source.line_start(first + 1), source.line_end(last + 1), ""))
    return fix


def _yaml_node_at(root: object, line: int) -> MappingNode | None:
    """The mapping under a `node:` key whose list item starts at the 1-based line."""
    import yaml

    todo: list[object] = [root]
    while todo:
        current = todo.pop()
        if isinstance(current, yaml.MappingNode):
            for key, value in current.value:
                if (
                    key.value == "node"
                    and isinstance(value, yaml.MappingNode)
                    and key.start_mark.line + 1 <= line <= value.start_mark.line + 1
                    and any(k.value == "exec" and v.value == "ros2_control_node" for k, v in value.value)
                ):
                    return value
                todo.append(value)
        elif isinstance(current, yaml.SequenceNode):
            todo.extend(current.value)
    return None


def _names_description(item: object) -> bool:
    """A `name: robot_description` item whose every value is a scalar on one line."""
    import yaml

    if not isinstance(item, yaml.MappingNode):
        return False
    values = {k.value: v for k, v in item.value}
    return (
        set(values) == {"name", "value"}
        and all(
            isinstance(v, yaml.ScalarNode) and v.start_mark.line == v.end_mark.line for v in values.values()
        )
        and values["name"].value == "robot_description"
    )
