"""The fixers of Python and XML launch files: robot_description as a string, the
joint_state_publisher's model argument."""

from __future__ import annotations

import ast
import re

from pkgforge.diagnostics import Diagnostic
from pkgforge.fix.edits import Edit, SourceText, Unfixable, node_end_line, node_span
from pkgforge.fix.registry import Fix, FixContext, fixer
from pkgforge.model.source import parse_python

JSP_PACKAGES = ("joint_state_publisher", "joint_state_publisher_gui")


def _python(source: SourceText) -> ast.Module:
    try:
        return parse_python(source.text)
    except SyntaxError as exc:
        raise Unfixable(f"{source.path.name} does not parse: {exc.msg}") from exc


def _call_name(node: ast.expr) -> str:
    func = node.func if isinstance(node, ast.Call) else node
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute):
        return func.attr
    return ""


def _containing_calls(tree: ast.AST, line: int, name: str) -> list[ast.Call]:
    calls = [
        n
        for n in ast.walk(tree)
        if isinstance(n, ast.Call) and _call_name(n) == name and n.lineno <= line <= node_end_line(n)
    ]
    return sorted(calls, key=lambda n: (node_end_line(n) - n.lineno, -n.lineno))


def _parents(tree: ast.AST) -> dict[ast.AST, ast.AST]:
    return {child: parent for parent in ast.walk(tree) for child in ast.iter_child_nodes(parent)}


@fixer("robot-description-not-string")
def fix_robot_description(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    source = ctx.files.get(diagnostic.path)
    if not source.path.name.endswith(".py"):
        raise Unfixable("only Python launch files are edited")
    tree = _python(source)
    parents = _parents(tree)
    command = _robot_description_command(tree, diagnostic.line or 0)
    if command is None:
        raise Unfixable("cannot find the Command() that makes robot_description")
    fix = Fix("robot_description: ParameterValue(Command(...), value_type=str)")
    parent = parents.get(command)
    if isinstance(parent, ast.Call) and _call_name(parent) == "ParameterValue" and command in parent.args:
        if any(k.arg == "value_type" for k in parent.keywords):
            raise Unfixable("ParameterValue already has a value_type: make it str")
        _, end = node_span(source, parent.args[-1] if not parent.keywords else parent.keywords[-1].value)
        fix.add(source.path, Edit(end, end, ", value_type=str"))
        return fix
    start, end = node_span(source, command)
    fix.add(source.path, Edit(start, start, "ParameterValue("))
    fix.add(source.path, Edit(end, end, ", value_type=str)"))
    import_edit = _import_edit(source, tree, "launch_ros.parameter_descriptions", "ParameterValue")
    if import_edit is not None:
        fix.add(source.path, import_edit)
    return fix


def _robot_description_command(tree: ast.Module, line: int) -> ast.Call | None:
    calls = _containing_calls(tree, line, "Command")
    if calls:
        return calls[0]
    # the line of the node or the dict: follow 'robot_description': <Command or a name bound to one>
    around = [
        n
        for n in ast.walk(tree)
        if isinstance(n, (ast.Dict, ast.Call)) and n.lineno <= line <= node_end_line(n)
    ]
    inner = sorted(around, key=lambda n: node_end_line(n) - n.lineno)[:1]
    dicts = [n for n in ast.walk(inner[0]) if isinstance(n, ast.Dict)] if inner else []
    for node in dicts:
        for key, value in zip(node.keys, node.values, strict=False):
            if isinstance(key, ast.Constant) and key.value == "robot_description":
                if isinstance(value, ast.Call) and _call_name(value) == "Command":
                    return value
                if isinstance(value, ast.Name):
                    bound = [
                        n.value
                        for n in ast.walk(tree)
                        if isinstance(n, ast.Assign)
                        and any(isinstance(t, ast.Name) and t.id == value.id for t in n.targets)
                        and isinstance(n.value, ast.Call)
                        and _call_name(n.value) == "Command"
                    ]
                    if len(bound) == 1:
                        return bound[0]
    return None


def _import_edit(source: SourceText, tree: ast.Module, module: str, name: str) -> Edit | None:
    """The import of `name` from `module`, after the module's last top-level import; None if bound."""
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and any((a.asname or a.name) == name for a in node.names):
            return None
        if isinstance(node, (ast.Assign, ast.FunctionDef, ast.ClassDef)) and name in {
            getattr(t, "id", None) for t in getattr(node, "targets", [])
        } | {getattr(node, "name", None)}:
            return None
    imports = [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]
    line = f"from {module} import {name}"
    if imports:
        last = imports[-1]
        offset = source.line_end(node_end_line(last))
        prefix = "" if source.text[:offset].endswith("\n") else source.eol
        return Edit(offset, offset, prefix + line + source.eol, "0")
    first = tree.body[0] if tree.body else None
    if (
        first is not None
        and isinstance(first, ast.Expr)
        and isinstance(getattr(first, "value", None), ast.Constant)
    ):
        offset = source.line_end(node_end_line(first))
        return Edit(offset, offset, line + source.eol, "0")
    return Edit(0, 0, line + source.eol, "0")


@fixer("jsp-model-argument")
def fix_jsp_argument(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    source = ctx.files.get(diagnostic.path)
    name = source.path.name
    if name.endswith(".py"):
        return _jsp_python(source, diagnostic.line or 0)
    if name.endswith(".xml"):
        return _jsp_xml(source, diagnostic.line or 0)
    raise Unfixable("only Python and XML launch files are edited")


def _jsp_python(source: SourceText, line: int) -> Fix:
    tree = _python(source)
    for call in _containing_calls(tree, line, "Node"):
        keywords = {k.arg: k for k in call.keywords if k.arg}
        given = keywords.get("package")
        if (
            given is None
            or not isinstance(given.value, ast.Constant)
            or given.value.value not in JSP_PACKAGES
        ):
            continue
        package = given.value.value
        arguments = keywords.get("arguments")
        if arguments is None:
            raise Unfixable("the node's arguments are not given as arguments=[...]")
        if isinstance(arguments.value, (ast.List, ast.Tuple)) and len(arguments.value.elts) > 1:
            raise Unfixable("arguments=[...] holds more than the model: remove the model by hand")
        siblings = list(call.args) + [k for k in call.keywords]
        siblings.sort(key=lambda n: (n.lineno, n.col_offset))
        index = siblings.index(arguments)
        start, end = node_span(source, arguments)
        rest = source.text[end : source.line_end(node_end_line(arguments))]
        alone = source.is_blank_before(start) and re.fullmatch(r"\s*,?\s*(#.*)?\s*", rest)
        previous = siblings[index - 1] if index > 0 else None
        following = siblings[index + 1] if index + 1 < len(siblings) else None
        if alone:  # the keyword has its own line(s): they go
            start, end = source.line_start(arguments.lineno), source.line_end(node_end_line(arguments))
        elif previous is not None and node_end_line(previous) == arguments.lineno:
            start = node_span(source, previous)[1]  # `, arguments=[...]`: what follows keeps its place
        elif following is not None and following.lineno == node_end_line(arguments):
            end = node_span(source, following)[0]  # `arguments=[...], ` up to the next argument
        else:
            end += len(rest) - len(rest.lstrip(" \t,"))
        fix = Fix(f"removed arguments=... from the {package} node")
        fix.add(source.path, Edit(start, end, ""))
        return fix
    raise Unfixable(f"cannot find the joint_state_publisher Node(...) at line {line}")


def _jsp_xml(source: SourceText, line: int) -> Fix:
    start = source.line_start(line)
    match = re.compile(r"<node\b[^>]*>", re.S).search(source.text, start)
    package = re.search(r"""\bpkg\s*=\s*["']([^"']*)["']""", match.group(0)) if match else None
    if (
        match is None
        or source.line_of(match.start()) != line
        or package is None
        or package.group(1) not in JSP_PACKAGES
    ):
        raise Unfixable(f"cannot find the joint_state_publisher <node> at line {line}")
    package_name = package.group(1)
    attribute = re.search(r"""\s+args\s*=\s*("[^"]*"|'[^']*')""", match.group(0))
    if attribute is None:
        raise Unfixable("the node has no args attribute")
    fix = Fix(f"removed args=... from the {package_name} node")
    fix.add(source.path, Edit(match.start() + attribute.start(), match.start() + attribute.end(), ""))
    return fix
