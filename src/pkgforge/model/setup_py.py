"""setup.py `data_files` read from the AST, without running setup.py.

Evaluates literals, names assigned at module level, `+`, f-strings,
os.path.join, glob()/glob.glob(), os.walk() comprehensions, calls of the
module's own one-line functions (`def f(x): return ...`), and module-level
`for` loops that append/extend/+= a list. `[options.data_files]` of setup.cfg
counts when setup() passes no data_files (setuptools' own precedence).
Anything else is Unknown and reported, never guessed.
"""

from __future__ import annotations

import ast
import configparser
import fnmatch
import glob as globmodule
import os
import posixpath
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pkgforge.model.source import SourceFile, parse_python
from pkgforge.walk import walk

# a value setup.py computes (str, int, bool, None, list, tuple): the user's data, checked where used
Value = Any


# evaluations one inside another (an operand, an element, a call of the file's own function): no
# setup.py nests 100 deep, and one that calls itself without end would raise RecursionError
MAX_EVAL_DEPTH = 100


class Unevaluable(Exception):
    def __init__(self, node: ast.AST, why: str):
        super().__init__(why)
        self.node, self.why = node, why


@dataclass(frozen=True)
class DataFilesEntry:
    destination: str
    files: tuple[str, ...]  # relative to the package folder
    line: int
    path: Path | None = None  # the file that names it, when not setup.py (setup.cfg)


@dataclass
class SetupPyModel:
    source: SourceFile
    entries: list[DataFilesEntry] = field(default_factory=list)
    # (line, why) for each part pkgforge could not evaluate
    unknown: list[tuple[int, str]] = field(default_factory=list)
    syntax_error: tuple[int, str] | None = None
    has_setup_call: bool = False
    name: str | None = None
    # the Python packages (dotted names) and top-level modules setup() installs, when evaluated:
    # `packages=` (a list, or find_packages() with its where/include/exclude), `py_modules=`
    python_packages: list[str] = field(default_factory=list)
    py_modules: list[str] = field(default_factory=list)
    # package_data={'pkg': ['*.yaml']}: the files it adds to the packages, (where it installs them
    # below site-packages, the file relative to the package folder): beside the modules
    package_data: list[tuple[str, str]] = field(default_factory=list)
    packages_line: int | None = None
    # setup(package_dir=...): where the packages' folders are ('' the root), when evaluated
    package_dir: dict[str, str] = field(default_factory=dict)
    # entry_points={'console_scripts': [...]} as setup() got them (evaluated setup.py only)
    entry_points: dict[str, list[str]] = field(default_factory=dict)
    setup_line: int | None = None  # the setup() call's
    # the line of setup()'s data_files= (its computed entries are located there)
    data_files_line: int | None = None
    # packages=, py_modules= or package_data= that the static reader could not evaluate
    partial: bool = False
    # read by running setup.py as colcon does (setup_eval.py), not from its text
    evaluated: bool = False
    # (line, why) when running setup.py failed: the static reading above stands
    evaluation_error: tuple[int | None, str] | None = None
    # that failure was a limit or a crash: this machine's, not the file's (never cached)
    evaluation_unstable: bool = False


def load_setup_py(source: SourceFile, package_path: Path) -> SetupPyModel:
    model = SetupPyModel(source)
    if source.text is None:
        model.syntax_error = (source.problem_line or 1, source.problem or "unreadable")
        return model
    try:
        tree = parse_python(source.text, filename=str(source.path))
    except SyntaxError as exc:
        model.syntax_error = (exc.lineno or 1, exc.msg)
        return model
    evaluator = _Evaluator(package_path)
    for statement in tree.body:
        if isinstance(statement, ast.FunctionDef):
            evaluator.functions[statement.name] = statement
    evaluator.run(tree.body)
    setup_call = next(
        (
            node
            for node in ast.walk(tree)
            if isinstance(node, ast.Call) and _call_name(node.func) in ("setup", "setuptools.setup")
        ),
        None,
    )
    if setup_call is None:
        return model
    model.has_setup_call = True
    model.setup_line = setup_call.lineno
    keywords = {kw.arg: kw.value for kw in setup_call.keywords if kw.arg}
    if "name" in keywords:
        try:
            model.name = evaluator.eval(keywords["name"])
        except Unevaluable:
            pass
    _read_python_packages(model, keywords, evaluator)
    data_files = keywords.get("data_files")
    model.data_files_line = data_files.lineno if data_files is not None else None
    if data_files is None:
        _read_setup_cfg(model, package_path)
        return model
    if not isinstance(data_files, (ast.List, ast.Tuple)):
        # a list built before setup(): its entries, at the line of data_files=
        try:
            value = evaluator.eval(data_files)
            if not isinstance(value, (list, tuple)):
                raise Unevaluable(data_files, "data_files is not a list")
            elements: list[ast.expr] = [ast.Constant(entry, lineno=data_files.lineno) for entry in value]
        except Unevaluable as exc:
            model.unknown.append((getattr(exc.node, "lineno", data_files.lineno), exc.why))
            return model
    else:
        elements = data_files.elts
    for element in elements:
        try:
            values = (
                evaluator.eval(element.value)
                if isinstance(element, ast.Starred)
                else [evaluator.eval(element)]
            )
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


def _read_python_packages(model: SetupPyModel, keywords: dict[str, ast.expr], evaluator: _Evaluator) -> None:
    """`packages=` and `py_modules=` of setup(), when pkgforge can evaluate them: what a launch
    file of the workspace imports from this package (`package_dir=` moves them: left alone)."""
    if "package_dir" in keywords:
        model.partial = True  # (setup_eval.py's evaluation reads it)
        return
    for keyword, into in (("packages", model.python_packages), ("py_modules", model.py_modules)):
        node = keywords.get(keyword)
        if node is None:
            continue
        try:
            value = evaluator.eval(node)
        except (Unevaluable, TypeError, ValueError):
            model.partial = True
            continue
        if isinstance(value, (list, tuple)) and all(isinstance(v, str) and _DOTTED.match(v) for v in value):
            into.extend(value)
            model.packages_line = model.packages_line or node.lineno
    data = keywords.get("package_data")
    if data is not None and not isinstance(data, ast.Dict):
        model.partial = True
    if isinstance(data, ast.Dict):
        for key, patterns in zip(data.keys, data.values, strict=True):
            try:
                name = evaluator.eval(key) if key is not None else None
                globs = evaluator.eval(patterns)
            except (Unevaluable, TypeError, ValueError):
                model.partial = True
                continue
            if not isinstance(name, str) or not isinstance(globs, (list, tuple)):
                continue
            model.package_data += package_data_files(
                evaluator.package_path,
                model.python_packages,
                {},
                name,
                [g for g in globs if isinstance(g, str)],
            )


def package_data_files(
    package_path: Path, packages: list[str], package_dir: dict[str, str], name: str, patterns: list[str]
) -> list[tuple[str, str]]:
    """(installed below site-packages, file relative to the package folder) for each file
    package_data's patterns for package `name` ('' or '*': every package) match: setuptools globs
    them in each package's folder and installs them beside its modules."""
    out: list[tuple[str, str]] = []
    for dotted in packages if name in ("", "*") else [name]:
        folder = package_path / package_folder(dotted, package_dir)
        for pattern in patterns:
            found = globmodule.glob(str(folder / pattern), recursive=True)
            out += sorted(
                (
                    posixpath.join(dotted.replace(".", "/"), os.path.relpath(f, folder)),
                    os.path.relpath(f, package_path),
                )
                for f in found
                if os.path.isfile(f)
            )
    return out


def package_folder(dotted: str, package_dir: dict[str, str]) -> str:
    """The folder of a package, relative to the package's root, as setuptools' build_py finds it:
    package_dir of the package, or of its nearest parent with the rest of the name below it,
    or of '' (the root)."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        base = package_dir.get(".".join(parts[:cut]))
        if base is not None:
            return posixpath.join(base, *parts[cut:])
    return posixpath.join(package_dir.get("", ""), *parts)


def evaluated_model(static: SetupPyModel, values: Mapping[str, Any], package_path: Path) -> SetupPyModel:
    """The model of what setup() got when setup.py ran (setup_eval.py): its data_files, packages,
    py_modules, package_data and entry_points. An entry the static reader read too keeps its line
    (and file: setup.cfg); a computed one is at the static reader's unread element, when only one
    was unread, else at data_files= (the setup() line without one)."""
    model = SetupPyModel(
        static.source,
        has_setup_call=True,
        name=values.get("name") if isinstance(values.get("name"), str) else static.name,
        evaluated=True,
        data_files_line=static.data_files_line,
        setup_line=static.setup_line,
    )
    known = {(e.destination, e.files): e for e in static.entries}
    unread = sorted({line for line, _ in static.unknown})
    line = unread[0] if len(unread) == 1 else static.data_files_line or static.setup_line or 1
    for item in values.get("data_files") or []:
        files: tuple[str, ...]
        if isinstance(item, str):  # a lone file: install_data copies it into the prefix itself
            destination, files = "", (item,)
        else:
            destination, files = str(item[0]), tuple(str(f) for f in item[1])
        same = known.get((destination, files))
        model.entries.append(
            DataFilesEntry(destination, files, same.line if same else line, same.path if same else None)
        )
    model.package_dir = {str(k): str(v) for k, v in (values.get("package_dir") or {}).items()}
    model.python_packages = [p for p in values.get("packages") or [] if _DOTTED.match(p)]
    model.py_modules = [m for m in values.get("py_modules") or [] if _DOTTED.match(m)]
    model.packages_line = static.packages_line or line
    for name, patterns in (values.get("package_data") or {}).items():
        model.package_data += package_data_files(
            package_path, model.python_packages, model.package_dir, name, list(patterns)
        )
    model.entry_points = {
        str(k): [str(v) for v in lines] for k, lines in (values.get("entry_points") or {}).items()
    }
    return model


_DOTTED = re.compile(r"^[A-Za-z_]\w*(\.[A-Za-z_]\w*)*$")


def find_packages(where: Path, include: tuple[str, ...] = ("*",), exclude: tuple[str, ...] = ()) -> list[str]:
    """setuptools.find_packages(where, exclude, include): the folders under `where` holding an
    __init__.py, as dotted names, a folder that is not a package not searched further."""
    exclude = (*exclude, "ez_setup", "*__pycache__")
    found: list[str] = []
    stack = [(where, "")]
    while stack:
        folder, dotted = stack.pop()
        try:
            entries = sorted(os.scandir(folder), key=lambda e: e.name)
        except OSError:
            continue
        for entry in entries:
            if (
                "." in entry.name
                or not entry.is_dir()
                or not os.path.isfile(os.path.join(entry.path, "__init__.py"))
            ):
                continue
            name = f"{dotted}.{entry.name}" if dotted else entry.name
            if any(fnmatch.fnmatchcase(name, p) for p in include) and not any(
                fnmatch.fnmatchcase(name, p) for p in exclude
            ):
                found.append(name)
            if f"{name}*" in exclude or f"{name}.*" in exclude:
                continue
            if len(found) < 1000:  # bounded: a package tree of a launch helper, not a walk of the disk
                stack.append((Path(entry.path), name))
    return sorted(found)


def _call_name(func: ast.AST) -> str:
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute):
        return f"{_call_name(func.value)}.{func.attr}"
    return ""


class _Failed(ast.AST):
    """Where and why a module-level name could not be evaluated."""

    def __init__(self, lineno: int, why: str):
        super().__init__()
        self.lineno, self.why = lineno, why


class _Evaluator:
    def __init__(self, package_path: Path):
        self.package_path = package_path
        self.names: dict[str, Value] = {}
        self.functions: dict[str, ast.FunctionDef] = {}
        self.failed: dict[str, _Failed] = {}  # name → why its value is unknown
        self.depth = 0  # evaluations under way, one inside the other

    # --- statements (module level) -----------------------------------------------------------

    def run(self, statements: list[ast.stmt]) -> None:
        for statement in statements:
            self.statement(statement)

    def fail(self, name: str, line: int, why: str) -> None:
        self.names.pop(name, None)
        self.failed.setdefault(name, _Failed(line, why))

    def statement(self, statement: ast.stmt) -> None:
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
            target = statement.targets[0]
            try:
                value = self.eval(statement.value)
                if isinstance(target, ast.Name):
                    self.names[target.id] = value
                    self.failed.pop(target.id, None)
                else:
                    _bind(target, value, self.names, statement)
            except Unevaluable as exc:
                for name in _assigned_names(target):
                    self.fail(name, getattr(exc.node, "lineno", statement.lineno), exc.why)
        elif (
            isinstance(statement, ast.AugAssign)
            and isinstance(statement.target, ast.Name)
            and isinstance(statement.op, ast.Add)
        ):
            name = statement.target.id
            try:
                current = self.eval(statement.target)
                added = self.eval(statement.value)
                if isinstance(current, list) and isinstance(added, (list, tuple)):
                    self.names[name] = current + list(added)
                elif type(current) is type(added) and isinstance(current, (str, tuple)):
                    self.names[name] = current + added
                else:
                    raise Unevaluable(statement, "'+=' of different types")
            except Unevaluable as exc:
                self.fail(name, getattr(exc.node, "lineno", statement.lineno), exc.why)
        elif (
            isinstance(statement, ast.Expr)
            and isinstance(statement.value, ast.Call)
            and isinstance(statement.value.func, ast.Attribute)
            and isinstance(statement.value.func.value, ast.Name)
            and statement.value.func.attr in ("append", "extend")
        ):
            call, method = statement.value, statement.value.func
            name = statement.value.func.value.id
            if name not in self.names and name not in self.failed:
                return  # a list pkgforge does not track
            try:
                current = self.eval(method.value)
                if not isinstance(current, list) or len(call.args) != 1 or call.keywords:
                    raise Unevaluable(call, f"{name}.{method.attr}() of something not a list")
                value = self.eval(call.args[0])
                self.names[name] = current + ([value] if method.attr == "append" else list(value))
            except Unevaluable as exc:
                self.fail(name, getattr(exc.node, "lineno", statement.lineno), exc.why)
            except TypeError:
                self.fail(name, statement.lineno, f"{name}.extend() of something not a list")
        elif isinstance(statement, ast.For) and not statement.orelse:
            try:
                items = list(self.eval(statement.iter))
            except (Unevaluable, TypeError) as exc:
                why = exc.why if isinstance(exc, Unevaluable) else "the loop's items are not a list"
                for name in _changed_names(statement.body) | _assigned_names(statement.target):
                    self.fail(name, statement.lineno, f"changed in a loop over something unknown ({why})")
                return
            for item in items:
                try:
                    _bind(statement.target, item, self.names, statement)
                except Unevaluable as exc:
                    for name in _changed_names(statement.body):
                        self.fail(name, statement.lineno, exc.why)
                    return
                self.run(statement.body)
        elif isinstance(statement, (ast.If, ast.For, ast.While, ast.Try, ast.With)):
            kind = type(statement).__name__.lower()
            for name in _changed_names([statement]):
                self.fail(name, statement.lineno, f"changed inside a {kind} statement pkgforge does not run")

    def eval(self, node: ast.AST, scope: dict[str, Value] | None = None) -> Value:
        self.depth += 1
        try:
            if self.depth > MAX_EVAL_DEPTH:  # (each level is a few Python calls here)
                raise Unevaluable(
                    node,
                    f"evaluating it goes more than {MAX_EVAL_DEPTH} levels deep (an expression nested "
                    "that deep, or a function that calls itself): pkgforge evaluates no deeper",
                )
            return self._value(node, scope or {})
        finally:
            self.depth -= 1

    def _value(self, node: ast.AST, scope: dict[str, Value]) -> Value:
        if isinstance(node, ast.Constant) and isinstance(
            node.value, (str, int, bool, type(None), tuple, list)
        ):
            return node.value
        if isinstance(node, ast.Name):
            if node.id in scope:
                return scope[node.id]
            if node.id in self.names:
                return self.names[node.id]
            if node.id in self.failed:
                failed = self.failed[node.id]
                raise Unevaluable(failed, f"'{node.id}': {failed.why}")
            raise Unevaluable(node, f"'{node.id}' is not a literal pkgforge can see")
        if isinstance(node, ast.JoinedStr):
            return "".join(
                str(self.eval(v.value if isinstance(v, ast.FormattedValue) else v, scope))
                for v in node.values
            )
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
            left, right = self.eval(node.left, scope), self.eval(node.right, scope)
            if type(left) is not type(right) and not (
                isinstance(left, (list, tuple)) and isinstance(right, (list, tuple))
            ):
                raise Unevaluable(node, "'+' of different types")
            return list(left) + list(right) if isinstance(left, (list, tuple)) else left + right
        if isinstance(node, (ast.List, ast.Tuple)):
            out: list[Value] = []
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

    def call(self, node: ast.Call, scope: dict[str, Value]) -> Value:
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
            return [
                (os.path.relpath(root, self.package_path), dirs, files)
                for root, dirs, files in walk(self.package_path / args[0])
            ]  # bounded, no recursion
        if name in ("find_packages", "setuptools.find_packages"):
            where = kwargs.get("where", args[0] if args else ".")
            exclude = kwargs.get("exclude", args[1] if len(args) > 1 else ())
            include = kwargs.get("include", args[2] if len(args) > 2 else ("*",))
            if not (isinstance(where, str) and all(isinstance(p, str) for p in (*exclude, *include))):
                raise Unevaluable(node, "find_packages() with arguments that are not text")
            return find_packages(self.package_path / where, tuple(include), tuple(exclude))
        if name in self.functions:
            return self.local_function(self.functions[name], node, args)
        raise Unevaluable(node, f"{name or 'this'}() is not evaluated")

    def local_function(self, function: ast.FunctionDef, node: ast.Call, args: list[Value]) -> Value:
        body = [
            s for s in function.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))
        ]
        if len(body) != 1 or not isinstance(body[0], ast.Return) or body[0].value is None:
            raise Unevaluable(node, f"{function.name}() is more than one return statement")
        params = [a.arg for a in function.args.args]
        if len(params) != len(args):
            raise Unevaluable(node, f"{function.name}() called with other arguments than it takes")
        return self.eval(body[0].value, dict(zip(params, args, strict=False)))

    def comprehension(self, node: ast.ListComp, scope: dict[str, Value]) -> list[Value]:
        results: list[Value] = []

        def loop(index: int, bound: dict[str, Value]) -> None:
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


def _bind(target: ast.AST, value: Value, scope: dict[str, Value], node: ast.AST) -> None:
    if isinstance(target, ast.Name):
        scope[target.id] = value
    elif isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) == len(value):
        for element, item in zip(target.elts, value, strict=False):
            _bind(element, item, scope, node)
    else:
        raise Unevaluable(node, "a loop target pkgforge cannot unpack")


def _assigned_names(target: ast.AST) -> set[str]:
    return {node.id for node in ast.walk(target) if isinstance(node, ast.Name)}


def _changed_names(statements: list[ast.stmt]) -> set[str]:
    """Names that statements assign, or append/extend to."""
    names: set[str] = set()
    for statement in statements:
        for node in ast.walk(statement):
            if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign)):
                for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                    names |= _assigned_names(target)
            elif (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and isinstance(node.func.value, ast.Name)
                and node.func.attr in ("append", "extend", "insert")
            ):
                names.add(node.func.value.id)
    return names


class _CaseKeeping(configparser.ConfigParser):
    """A ConfigParser whose keys (data_files destinations) keep their case."""

    def optionxform(self, optionstr: str) -> str:
        return optionstr


def _read_setup_cfg(model: SetupPyModel, package_path: Path) -> None:
    """[options.data_files] of setup.cfg: `destination = file, glob ...`, globs as setuptools expands."""
    path = package_path / "setup.cfg"
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return
    parser = _CaseKeeping(interpolation=None)
    try:
        parser.read_string(text, source=str(path))
    except configparser.Error:
        return  # setuptools reports a broken setup.cfg when colcon builds
    if not parser.has_section("options.data_files"):
        return
    # the line of each key in the section, for diagnostics (configparser keeps none)
    lines: dict[str, int] = {}
    section = None
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if stripped.startswith("[") and stripped.endswith("]"):
            section = stripped[1:-1].strip()
        elif section == "options.data_files" and "=" in stripped and not line[:1].isspace():
            lines.setdefault(stripped.split("=", 1)[0].strip(), number)
    for destination, value in parser.items("options.data_files"):
        files: list[str] = []
        for item in value.replace(",", "\n").splitlines():
            item = item.strip()
            if not item:
                continue
            if any(c in item for c in "*?["):
                found = globmodule.glob(str(package_path / item), recursive=True)
                files += sorted(os.path.relpath(f, package_path) for f in found if os.path.isfile(f))
            else:
                files.append(item)
        model.entries.append(DataFilesEntry(destination, tuple(files), lines.get(destination, 1), path))
