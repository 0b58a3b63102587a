"""setup.py `data_files` read from the AST, without running setup.py.

Evaluates literals, names assigned at module level, `+`, f-strings,
os.path.join, glob()/glob.glob(), os.walk() comprehensions, and calls of the
module's own one-line functions (`def f(x): return ...`). Anything else is
Unknown and reported, never guessed.
"""

from __future__ import annotations

import ast
import glob as globmodule
import os
from dataclasses import dataclass, field
from pathlib import Path

from .source import SourceFile


class Unevaluable(Exception):
    def __init__(self, node: ast.AST, why: str):
        super().__init__(why)
        self.node, self.why = node, why


@dataclass(frozen=True)
class DataFilesEntry:
    destination: str
    files: tuple[str, ...]  # relative to the package folder
    line: int


@dataclass
class SetupPyModel:
    source: SourceFile
    entries: list[DataFilesEntry] = field(default_factory=list)
    # (line, why) for each part pkgforge could not evaluate
    unknown: list[tuple[int, str]] = field(default_factory=list)
    syntax_error: tuple[int, str] | None = None
    has_setup_call: bool = False
    name: str | None = None


def load_setup_py(source: SourceFile, package_path: Path) -> SetupPyModel:
    model = SetupPyModel(source)
    if source.text is None:
        model.syntax_error = (source.problem_line or 1, source.problem or "unreadable")
        return model
    try:
        tree = ast.parse(source.text, filename=str(source.path))
    except SyntaxError as exc:
        model.syntax_error = (exc.lineno or 1, exc.msg)
        return model
    evaluator = _Evaluator(package_path)
    for statement in tree.body:
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1 \
                and isinstance(statement.targets[0], ast.Name):
            try:
                evaluator.names[statement.targets[0].id] = evaluator.eval(statement.value)
            except Unevaluable:
                evaluator.names.pop(statement.targets[0].id, None)
        elif isinstance(statement, ast.FunctionDef):
            evaluator.functions[statement.name] = statement
    setup_call = next((node for node in ast.walk(tree) if isinstance(node, ast.Call)
                       and _call_name(node.func) in ("setup", "setuptools.setup")), None)
    if setup_call is None:
        return model
    model.has_setup_call = True
    keywords = {kw.arg: kw.value for kw in setup_call.keywords if kw.arg}
    if "name" in keywords:
        try:
            model.name = evaluator.eval(keywords["name"])
        except Unevaluable:
            pass
    data_files = keywords.get("data_files")
    if data_files is None:
        return model
    elements = data_files.elts if isinstance(data_files, (ast.List, ast.Tuple)) else [data_files]
    for element in elements:
        try:
            values = evaluator.eval(element.value) if isinstance(element, ast.Starred) \
                else [evaluator.eval(element)]
            for value in values:
                destination, files = value
                if not isinstance(destination, str) or not all(isinstance(f, str) for f in files):
                    raise Unevaluable(element, "an entry is not (str, [str, ...])")
                model.entries.append(DataFilesEntry(destination, tuple(files), element.lineno))
        except Unevaluable as exc:
            model.unknown.append((getattr(exc.node, "lineno", element.lineno), exc.why))
        except (TypeError, ValueError):
            model.unknown.append((element.lineno, "an entry is not (destination, [files])"))
    return model


def _call_name(func: ast.AST) -> str:
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute):
        return f"{_call_name(func.value)}.{func.attr}"
    return ""


class _Evaluator:
    def __init__(self, package_path: Path):
        self.package_path = package_path
        self.names: dict[str, object] = {}
        self.functions: dict[str, ast.FunctionDef] = {}

    def eval(self, node: ast.AST, scope: dict | None = None):
        scope = scope or {}
        if isinstance(node, ast.Constant) and isinstance(node.value, (str, int, bool, type(None))):
            return node.value
        if isinstance(node, ast.Name):
            if node.id in scope:
                return scope[node.id]
            if node.id in self.names:
                return self.names[node.id]
            raise Unevaluable(node, f"'{node.id}' is not a literal pkgforge can see")
        if isinstance(node, ast.JoinedStr):
            return "".join(str(self.eval(v.value if isinstance(v, ast.FormattedValue) else v, scope))
                           for v in node.values)
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
            left, right = self.eval(node.left, scope), self.eval(node.right, scope)
            if type(left) is not type(right) and not (isinstance(left, (list, tuple))
                                                      and isinstance(right, (list, tuple))):
                raise Unevaluable(node, "'+' of different types")
            return list(left) + list(right) if isinstance(left, (list, tuple)) else left + right
        if isinstance(node, (ast.List, ast.Tuple)):
            out = []
            for element in node.elts:
                if isinstance(element, ast.Starred):
                    out.extend(self.eval(element.value, scope))
                else:
                    out.append(self.eval(element, scope))
            return out if isinstance(node, ast.List) else tuple(out)
        if isinstance(node, ast.ListComp):
            return self.comprehension(node, scope)
        if isinstance(node, ast.Call):
            return self.call(node, scope)
        raise Unevaluable(node, f"{type(node).__name__} expressions are not evaluated")

    def call(self, node: ast.Call, scope: dict):
        name = _call_name(node.func)
        args = [self.eval(a, scope) for a in node.args]
        kwargs = {kw.arg: self.eval(kw.value, scope) for kw in node.keywords if kw.arg}
        if name in ("os.path.join", "path.join"):
            return os.path.join(*args)
        if name in ("glob", "glob.glob"):
            pattern = args[0]
            recursive = bool(kwargs.get("recursive", False))
            found = globmodule.glob(str(self.package_path / pattern), recursive=recursive)
            return sorted(os.path.relpath(f, self.package_path) for f in found)
        if name == "os.walk":
            return [(os.path.relpath(root, self.package_path), dirs, files)
                    for root, dirs, files in os.walk(self.package_path / args[0])]
        if name in self.functions:
            return self.local_function(self.functions[name], node, args)
        raise Unevaluable(node, f"{name or 'this'}() is not evaluated")

    def local_function(self, function: ast.FunctionDef, node: ast.Call, args: list):
        body = [s for s in function.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
        if len(body) != 1 or not isinstance(body[0], ast.Return) or body[0].value is None:
            raise Unevaluable(node, f"{function.name}() is more than one return statement")
        params = [a.arg for a in function.args.args]
        if len(params) != len(args):
            raise Unevaluable(node, f"{function.name}() called with other arguments than it takes")
        return self.eval(body[0].value, dict(zip(params, args)))

    def comprehension(self, node: ast.ListComp, scope: dict):
        results: list = []

        def loop(index: int, bound: dict):
            if index == len(node.generators):
                results.append(self.eval(node.elt, bound))
                return
            generator = node.generators[index]
            for item in self.eval(generator.iter, bound):
                inner = dict(bound)
                _bind(generator.target, item, inner, node)
                if all(self.eval(condition, inner) for condition in generator.ifs):
                    loop(index + 1, inner)

        loop(0, dict(scope))
        return results


def _bind(target: ast.AST, value, scope: dict, node: ast.AST) -> None:
    if isinstance(target, ast.Name):
        scope[target.id] = value
    elif isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == len(value):
        for element, item in zip(target.elts, value):
            _bind(element, item, scope, node)
    else:
        raise Unevaluable(node, "a loop target pkgforge cannot unpack")
