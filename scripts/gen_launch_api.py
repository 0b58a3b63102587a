#!/usr/bin/env python3
"""Generate src/pkgforge/launch/api_names.json from the real ROS 2 launch sources.

    scripts/gen_launch_api.py [UPSTREAM_DIR]   (default: ../shared/upstream/ros2-launch)

For each distro folder (humble, jazzy) it reads, with `ast` only (nothing is imported
or copied), every module of launch, launch_xml, launch_yaml and launch_ros and writes:
the modules and, per module, its public names (what `from MODULE import NAME` finds in
ROS: the module's own classes, functions and assignments, and what it imports from the
same packages), the modules it imports at its top (so that importing it sets the same
submodule attributes as in ROS), and for classes and functions their signatures
(parameter name, kind, default when it is a literal) and each class's bases. The launch
worker builds its stand-in modules from this file (pkgforge/launch/api.py).
"""

from __future__ import annotations

import ast
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUTPUT = ROOT / "src" / "pkgforge" / "launch" / "api_names.json"
DISTROS = ("humble", "jazzy")
# (folder under the distro, top-level package)
PACKAGES = (
    ("launch/launch", "launch"),
    ("launch/launch_xml", "launch_xml"),
    ("launch/launch_yaml", "launch_yaml"),
    ("launch_ros/launch_ros", "launch_ros"),
)
OWN = {top for _, top in PACKAGES}
NO_DEFAULT = "<required>"
NOT_LITERAL = "<expression>"


def module_files(base: Path, top: str) -> dict[str, Path]:
    out = {}
    for path in sorted((base / top).rglob("*.py")):
        relative = path.relative_to(base).with_suffix("")
        parts = list(relative.parts)
        if any(p in ("test", "tests", "examples") for p in parts) or parts[-1] == "conftest":
            continue
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def absolute(module: str, is_package: bool, level: int, name: str | None) -> str:
    if level == 0:
        return name or ""
    parts = module.split(".")
    if not is_package:
        parts = parts[:-1]
    if level > 1:
        parts = parts[: len(parts) - (level - 1)]
    return ".".join(parts + ([name] if name else []))


def default_of(node: ast.expr | None):
    if node is None:
        return NO_DEFAULT
    try:
        value = ast.literal_eval(node)
    except (ValueError, SyntaxError, TypeError):
        return NOT_LITERAL
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    if isinstance(value, (tuple, list)) and all(isinstance(v, (str, int, float, bool)) for v in value):
        return {"literal": list(value), "type": type(value).__name__}
    return NOT_LITERAL


def signature(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list:
    """[[name, kind, default], ...]; kind as inspect.Parameter's, default NO_DEFAULT when required."""
    args = function.args
    out = []
    positional = args.posonlyargs + args.args
    defaults = [None] * (len(positional) - len(args.defaults)) + list(args.defaults)
    for index, (arg, default) in enumerate(zip(positional, defaults, strict=False)):
        kind = "POSITIONAL_ONLY" if index < len(args.posonlyargs) else "POSITIONAL_OR_KEYWORD"
        out.append([arg.arg, kind, default_of(default)])
    if args.vararg:
        out.append([args.vararg.arg, "VAR_POSITIONAL", NO_DEFAULT])
    for arg, default in zip(args.kwonlyargs, args.kw_defaults, strict=False):
        out.append([arg.arg, "KEYWORD_ONLY", default_of(default)])
    if args.kwarg:
        out.append([args.kwarg.arg, "VAR_KEYWORD", NO_DEFAULT])
    return out


def dotted(node: ast.expr) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        base = dotted(node.value)
        return f"{base}.{node.attr}" if base else None
    if isinstance(node, ast.Subscript):  # Generic[T]
        return dotted(node.value)
    return None


def read_module(name: str, path: Path, known: set[str], exposed: dict) -> dict:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    is_package = path.name == "__init__.py"
    names: dict[str, dict] = {}
    imports: list[str] = []
    local: dict[str, str] = {}  # a name bound by an import → the absolute dotted thing it names

    def note_import(module: str) -> None:
        if module.split(".")[0] in OWN and module not in imports and module != name:
            imports.append(module)

    def walk(body: list[ast.stmt]) -> None:
        for statement in body:
            if isinstance(statement, ast.ImportFrom):
                source = absolute(name, is_package, statement.level, statement.module)
                if source.split(".")[0] in OWN:
                    note_import(source)
                for alias in statement.names:
                    if alias.name == "*":
                        continue
                    bound = alias.asname or alias.name
                    target = f"{source}.{alias.name}"
                    local[bound] = target
                    if target in known:
                        note_import(target)
                        names[bound] = {"kind": "module", "module": target}
                    elif source.split(".")[0] in OWN:
                        names[bound] = {"kind": "alias", "target": target}
                    else:
                        names[bound] = {"kind": "external", "module": source, "attr": alias.name}
            elif isinstance(statement, ast.Import):
                for alias in statement.names:
                    if alias.name.split(".")[0] in OWN:
                        note_import(alias.name)
                    bound = alias.asname or alias.name.split(".")[0]
                    local[bound] = alias.asname and alias.name or bound
                    kind = "module" if local[bound] in known else "external-module"
                    names[bound] = {"kind": kind, "module": local[bound]}
            elif isinstance(statement, ast.ClassDef):
                for decorator in statement.decorator_list:
                    if (
                        isinstance(decorator, ast.Call)
                        and dotted(decorator.func) in ("expose_action", "expose_substitution")
                        and decorator.args
                        and isinstance(decorator.args[0], ast.Constant)
                    ):
                        kind = "actions" if dotted(decorator.func) == "expose_action" else "substitutions"
                        exposed[kind][decorator.args[0].value] = f"{name}.{statement.name}"
                bases = []
                for base in statement.bases:
                    text = dotted(base)
                    if text is None:
                        continue
                    head, _, rest = text.partition(".")
                    resolved = local.get(head, f"{name}.{head}" if head in names else head)
                    bases.append(f"{resolved}.{rest}" if rest else resolved)
                methods = {}
                for item in statement.body:
                    if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and (
                        not item.name.startswith("_") or item.name == "__init__"
                    ):
                        decorators = {dotted(d) for d in item.decorator_list}
                        kind = (
                            "property"
                            if "property" in decorators
                            else "staticmethod"
                            if "staticmethod" in decorators
                            else "classmethod"
                            if "classmethod" in decorators
                            else "method"
                        )
                        if kind == "property" and item.name in methods:
                            continue
                        methods[item.name] = {"kind": kind, "signature": signature(item)}
                names[statement.name] = {
                    "kind": "class",
                    "bases": bases,
                    "methods": methods,
                    "line": statement.lineno,
                }
            elif isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef)):
                names[statement.name] = {
                    "kind": "function",
                    "signature": signature(statement),
                    "line": statement.lineno,
                }
            elif isinstance(statement, (ast.Assign, ast.AnnAssign)):
                targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
                for target in targets:
                    for node in ast.walk(target):
                        if isinstance(node, ast.Name):
                            entry = {"kind": "value", "line": statement.lineno}
                            value = statement.value
                            if isinstance(value, ast.Name) and value.id in names:
                                bound = names[value.id]
                                entry = (
                                    dict(bound)
                                    if bound["kind"] != "class" and bound["kind"] != "function"
                                    else {"kind": "alias", "target": f"{name}.{value.id}"}
                                )
                                if value.id == node.id:  # `X = X`: a re-export
                                    entry = dict(bound)
                            names[node.id] = entry
            elif isinstance(statement, ast.If) and (
                "TYPE_CHECKING" in ast.unparse(statement.test) or ast.unparse(statement.test) == "False"
            ):
                walk(statement.orelse)  # the body is only for type checkers: never run
            elif isinstance(statement, (ast.If, ast.Try)):
                walk(statement.body)
                for handler in getattr(statement, "handlers", []):
                    walk(handler.body)
                walk(statement.orelse)
                walk(getattr(statement, "finalbody", []))

    walk(tree.body)
    exported = None
    if "__all__" in names:
        for statement in tree.body:
            if isinstance(statement, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "__all__" for t in statement.targets
            ):
                try:
                    exported = list(ast.literal_eval(statement.value))
                except ValueError:
                    exported = None
        names.pop("__all__")
    # every module-level name is importable in ROS, private ones included; keep what a launch
    # file could reasonably name: public names, and all classes/functions
    kept = {
        k: v
        for k, v in names.items()
        if not k.startswith("__") and (not k.startswith("_") or v["kind"] in ("class", "function"))
    }
    return {"package": is_package, "all": exported, "imports": imports, "names": kept}


def generate(upstream: Path) -> dict:
    data = {"generated_by": "scripts/gen_launch_api.py", "distros": {}}
    for distro in DISTROS:
        modules = {}
        sources = (upstream / distro / "SOURCES").read_text().split()
        files = {}
        for folder, top in PACKAGES:
            files.update(module_files(upstream / distro / folder, top))
        exposed: dict = {"actions": {}, "substitutions": {}}
        for module, path in files.items():
            modules[module] = read_module(module, path, set(files), exposed)
        # a submodule is an attribute of its package once imported
        for module in modules:
            parent, _, child = module.rpartition(".")
            if parent in modules:
                modules[parent].setdefault("submodules", []).append(child)
        data["distros"][distro] = {
            "sources": " ".join(sources),
            "modules": dict(sorted(modules.items())),
            "frontend": {k: dict(sorted(v.items())) for k, v in exposed.items()},
        }
    return data


def main(argv: list[str]) -> int:
    candidates = [ROOT.parent / "shared", ROOT.parent.parent / "shared"]  # main checkout, worktree
    upstream = (
        Path(argv[1])
        if len(argv) > 1
        else next(
            (c / "upstream" / "ros2-launch" for c in candidates if (c / "upstream").is_dir()), candidates[0]
        )
    )
    if not (upstream / "jazzy").is_dir():
        print(f"gen_launch_api: no {upstream}/jazzy; give the ros2-launch sources folder", file=sys.stderr)
        return 2
    data = generate(upstream)
    # one module a line: small, and a regeneration diffs by module
    lines = []
    for distro, content in data["distros"].items():
        lines.append(f' "{distro}": {{"sources": {json.dumps(content["sources"])},')
        lines.append(f'  "frontend": {json.dumps(content["frontend"], sort_keys=True)},')
        lines.append('  "modules": {')
        entries = [
            f"  {json.dumps(m)}: {json.dumps(v, sort_keys=True, separators=(',', ':'))}"
            for m, v in content["modules"].items()
        ]
        lines.append(",\n".join(entries))
        lines.append(" }},")
    lines[-1] = " }}"
    text = '{"generated_by": "scripts/gen_launch_api.py", "distros": {\n' + "\n".join(lines) + "\n}}\n"
    json.loads(text)
    OUTPUT.write_text(text)
    counts = {d: len(v["modules"]) for d, v in data["distros"].items()}
    print(f"wrote {OUTPUT.relative_to(ROOT)}: modules per distro {counts}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
