"""One fixer per check name: from a Diagnostic (its location and fix data) to text edits.

A fixer reads the files it edits through the FileSet (each file read once),
finds the construct at the diagnostic's line and column, and returns the edits
that fix it, computed against the text as read. It raises Unfixable with a
short reason when the construct is not one it can edit without guessing.
"""

from __future__ import annotations

import ast
import json
import posixpath
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.diagnostics import Diagnostic
from pkgforge.fix.edits import Edit, FileSet, NotOffered, SourceText, Unfixable
from pkgforge.model.source import parse_python

if TYPE_CHECKING:  # imported where used: `pkgforge fix` loads only what its fixers need
    import yaml
    from lxml import etree

    from pkgforge.model.cmake import CMakeModel
    from pkgforge.model.cmake_syntax import Argument, Command
    from pkgforge.model.package import PackageModel
    from pkgforge.model.setup_py import SetupPyModel

DEPENDENCY_ORDER = (
    "buildtool_depend",
    "buildtool_export_depend",
    "build_depend",
    "build_export_depend",
    "depend",
    "exec_depend",
    "run_depend",
    "test_depend",
    "doc_depend",
)
# format 1 (catkin) manifests know no exec_depend: run_depend is the run-time tag there
FORMAT_1_TAGS = {"exec_depend": "run_depend", "build_export_depend": "run_depend"}
ROBOT_DESCRIPTION_TOPIC = "/robot_description"
JSP_PACKAGES = ("joint_state_publisher", "joint_state_publisher_gui")


@dataclass
class Fix:
    """What one diagnostic's fix does: edits per file, and a few words for the report."""

    description: str
    edits: dict[Path, list[Edit]] = field(default_factory=dict)
    # a dependency it declares: (the package.xml, the name), so a run adds no cycle (run.py)
    declares: tuple[Path, str] | None = None

    def add(self, path: Path, edit: Edit) -> None:
        self.edits.setdefault(Path(path), []).append(edit)


class FixContext:
    """What fixers share: the files read, and package models loaded again in this process."""

    def __init__(self, files: FileSet):
        self.files = files
        self._models: dict[Path, PackageModel] = {}

    def model(self, path: Path) -> PackageModel:
        from pkgforge.model.package import load_package

        path = Path(path)
        if path not in self._models:
            self._models[path] = load_package(path)
        return self._models[path]


Fixer = Callable[[Diagnostic, FixContext], Fix]
FIXERS: dict[str, Fixer] = {}


def fixer(*names: str) -> Callable[[Fixer], Fixer]:
    def decorate(function: Fixer) -> Fixer:
        for name in names:
            FIXERS[name] = function
        return function

    return decorate


# --- package.xml: a dependency tag ---------------------------------------------------------------


def insert_dependency(source: SourceText, tag: str, name: str) -> tuple[Edit, str]:
    """The edit that declares `name` with `tag` in package.xml: beside the siblings of the same
    kind (in alphabetical order where they are), with the file's indentation and line ending.

    Generic over the kind, so any check that finds an undeclared dependency can use it
    (missing-exec-depend: exec_depend; find-package-undeclared: build_depend). Returns the
    edit and the tag written (format 1 manifests get run_depend for exec_depend)."""
    from lxml import etree

    parser = etree.XMLParser(resolve_entities=False, no_network=True, remove_comments=False)
    try:
        root = etree.fromstring(source.text.encode("utf-8"), parser)
    except etree.XMLSyntaxError as exc:
        raise Unfixable(f"package.xml is not well-formed XML: {exc.msg}") from exc
    try:
        manifest_format = int(root.get("format", "1"))
    except ValueError:
        raise Unfixable("package.xml's format attribute is not a number") from None
    if manifest_format < 2:
        tag = FORMAT_1_TAGS.get(tag, tag)
    if not re.fullmatch(r"[A-Za-z0-9_.\-]+", name):
        raise Unfixable(f"'{name}' is not a package name pkgforge writes into package.xml")
    elements = [e for e in root if isinstance(e.tag, str)]
    dependencies = [e for e in elements if e.tag in DEPENDENCY_ORDER]
    for element in dependencies:
        if (element.text or "").strip() == name and element.tag in (tag, "depend"):
            raise Unfixable(
                f"<{element.tag}>{name}</{element.tag}> is already declared at line {element.sourceline}"
            )
    new = f"<{tag}>{name}</{tag}>"
    eol = source.eol
    same = [e for e in dependencies if e.tag == tag]
    if same:
        names = [(e.text or "").strip() for e in same]
        ordered = names == sorted(names, key=str.lower)
        following = (
            next((e for e, n in zip(same, names, strict=False) if n.lower() > name.lower()), None)
            if ordered
            else None
        )
        if following is not None and _starts_line(source, following):
            line = _element_line(following)
            return Edit(
                source.line_start(line), source.line_start(line), source.indentation(line) + new + eol, name
            ), tag
        anchor = same[-1]
        return _after_element(source, anchor, new, name), tag
    rank = DEPENDENCY_ORDER.index(tag) if tag in DEPENDENCY_ORDER else len(DEPENDENCY_ORDER)
    earlier = [e for e in dependencies if DEPENDENCY_ORDER.index(e.tag) < rank]
    if earlier:
        return _after_element(source, earlier[-1], new, name), tag
    later = [e for e in dependencies if _starts_line(source, e)]
    for anchor in later + [e for e in elements if e.tag == "export" and _starts_line(source, e)]:
        line = _element_line(anchor)
        return Edit(
            source.line_start(line), source.line_start(line), source.indentation(line) + new + eol, name
        ), tag
    # no dependency and no <export>: before </package>, indented as <name>
    close = source.text.rfind("</package>")
    if close < 0 or not source.is_blank_before(close):
        raise Unfixable("no place in package.xml to put the dependency beside others")
    named = next((e for e in elements if e.tag == "name"), None)
    indent = source.indentation(_element_line(named)) if named is not None else "  "
    start = source.line_start(source.line_of(close))
    return Edit(start, start, indent + new + eol, name), tag


def _element_line(element: etree._Element) -> int:
    if element.sourceline is None:  # lxml sets it on every element it parses
        raise Unfixable(f"<{_tag(element)}> has no line in package.xml")
    return element.sourceline


def _tag(element: etree._Element) -> str:
    """The element's tag: a str for every element lxml parses (the stubs allow bytes and QName)."""
    tag = element.tag
    if not isinstance(tag, str):
        raise Unfixable("an element of package.xml has no plain tag name")
    return tag


def _start_tag_offset(source: SourceText, element: etree._Element) -> int:
    line = _element_line(element)
    tag = _tag(element)
    text = source.line_text(line)
    previous = [
        e
        for e in element.itersiblings(preceding=True)
        if getattr(e, "sourceline", None) == line and e.tag == tag
    ]
    matches = [m.start() for m in re.finditer(rf"<{re.escape(tag)}(?=[\s/>])", text)]
    if len(matches) <= len(previous):
        raise Unfixable(f"cannot find <{tag}> at package.xml:{line}")
    return source.line_start(line) + matches[len(previous)]


def _starts_line(source: SourceText, element: etree._Element) -> bool:
    try:
        return source.is_blank_before(_start_tag_offset(source, element))
    except Unfixable:
        return False


def _after_element(source: SourceText, element: etree._Element, new: str, order: str) -> Edit:
    """A new line holding `new` after the line where element ends, indented as element's line."""
    start = _start_tag_offset(source, element)
    closing = f"</{_tag(element)}>"
    end = source.text.find(closing, start)
    self_closing = source.text.find("/>", start)
    if end < 0 or (0 <= self_closing < source.text.find(">", start) + 1):
        end = source.text.find(">", start)
    else:
        end += len(closing)
    last_line = source.line_of(end)
    offset = source.line_end(last_line)
    indent = source.indentation(_element_line(element)) if source.is_blank_before(start) else ""
    prefix = "" if source.text[:offset].endswith("\n") else source.eol  # the last line had no ending
    return Edit(offset, offset, prefix + indent + new + source.eol, order)


def _manifest_for(diagnostic: Diagnostic) -> Path:
    data = diagnostic.fix or {}
    if data.get("manifest"):
        return Path(data["manifest"])
    folder = Path(diagnostic.path)
    folder = folder if folder.is_dir() else folder.parent
    while folder != folder.parent and not (folder / "package.xml").is_file():
        folder = folder.parent
    if not (folder / "package.xml").is_file():
        raise Unfixable("no package.xml above the file")
    return folder / "package.xml"


@fixer("missing-exec-depend", "find-package-undeclared", "ros2-control-hardware-unavailable")
def fix_dependency(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    data = diagnostic.fix or {}
    name, tag = data.get("dependency"), data.get("tag")
    if name is None and diagnostic.name == "find-package-undeclared":
        name = _find_package_name(diagnostic, ctx)
        tag = "buildtool_depend" if name.startswith("ament_cmake") else "build_depend"
    if not name or not tag:
        raise NotOffered("the check gives this finding no fix")
    manifest = _manifest_for(diagnostic)
    source = ctx.files.get(manifest)
    if name is not None and diagnostic.name == "find-package-undeclared":
        _refuse_other_declaration(source, name)
    edit, written = insert_dependency(source, tag, name)
    fix = Fix(f"declared <{written}>{name}</{written}> in package.xml", declares=(manifest, name))
    fix.add(manifest, edit)
    return fix


@fixer("duplicate-dependency")
def fix_duplicate_dependency(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    """Delete the repeated declaration at the finding's line: its own line when nothing else
    stands on it, else the element with the spaces before it."""
    data = diagnostic.fix or {}
    tag, name, line = data.get("tag"), data.get("dependency"), data.get("line")
    if not tag or not name or not isinstance(line, int):
        raise NotOffered("the check gives this finding no fix")
    source = ctx.files.get(diagnostic.path)
    pattern = re.compile(rf"<{re.escape(tag)}(?:\s[^<>]*)?>\s*{re.escape(name)}\s*</{re.escape(tag)}\s*>")
    matches = list(pattern.finditer(source.line_text(line)))
    if len(matches) != 1:
        raise Unfixable(f"cannot find one <{tag}>{name}</{tag}> on package.xml:{line}")
    start = source.line_start(line) + matches[0].start()
    fix = Fix(f"deleted the repeated <{tag}>{name}</{tag}> from package.xml")
    fix.add(diagnostic.path, _delete_span(source, start, start + len(matches[0].group(0))))
    return fix


def _find_package_name(diagnostic: Diagnostic, ctx: FixContext) -> str:
    """The package a find_package() at the diagnostic's location names."""
    source = ctx.files.get(diagnostic.path)
    command = _cmake_command_at(source, diagnostic.line, diagnostic.column, "find_package")
    if not command.args or command.args[0].kind == "bracket" or "$" in command.args[0].text:
        raise Unfixable("find_package() does not name its package literally")
    return command.args[0].text


def _refuse_other_declaration(source: SourceText, name: str) -> None:
    for match in re.finditer(r"<(\w+)>\s*" + re.escape(name) + r"\s*</\1>", source.text):
        if match.group(1) in DEPENDENCY_ORDER:
            raise Unfixable(
                f"{name} is declared as <{match.group(1)}> already: which tag it needs is "
                "for you to decide (<depend> covers build and run time)"
            )


# --- CMake ----------------------------------------------------------------------------------------


def _cmake_commands(source: SourceText) -> list[Command]:
    from pkgforge.model.cmake_syntax import CMakeSyntaxError, parse

    try:
        return parse(source.text, source.path)
    except CMakeSyntaxError as exc:
        raise Unfixable(f"{source.path.name} does not parse: {exc.message}") from exc


def _cmake_command_at(
    source: SourceText, line: int | None, column: int | None, name: str | None = None
) -> Command:
    """The command that starts at (line, column), or that holds an argument there."""
    if line is None:
        raise Unfixable("the finding has no line")
    for command in _cmake_commands(source):
        if name is not None and command.name != name:
            continue
        if command.line == line and (column is None or command.column == column):
            return command
        if any(a.line == line and (column is None or a.column == column) for a in command.args):
            return command
    raise Unfixable(f"no {name + '()' if name else 'command'} at {source.path.name}:{line}")


def _argument_span(source: SourceText, argument: Argument) -> tuple[int, int]:
    start = source.offset(argument.line, argument.column)
    if argument.kind == "unquoted":
        end = start + len(argument.text)
    elif argument.kind == "quoted" and "\\\n" not in source.text[start : start + len(argument.text) + 2]:
        end = start + len(argument.text) + 2
    else:
        raise Unfixable("a bracket argument is not edited")
    return start, end


def _command_end(source: SourceText, command: Command) -> int:
    """Offset just past the command's closing parenthesis."""
    from pkgforge.model import cmake_syntax

    scanner = cmake_syntax._Scanner(source.text, source.path)
    start = source.offset(command.line, command.column)
    scanner.advance_to(source.text.index("(", start) + 1)
    cmake_syntax._arguments(scanner, command.name, command.line)
    return scanner.pos


def _delete_span(source: SourceText, start: int, end: int) -> Edit:
    """Delete [start, end): whole lines when nothing else stands on them, else with the space before."""
    first, last = source.line_of(start), source.line_of(max(start, end - 1))
    before = source.text[source.line_start(first) : start]
    after = source.text[end : source.line_end(last)]
    if before.strip(" \t") == "" and after.strip(" \t\r\n") == "":
        return Edit(source.line_start(first), source.line_end(last), "")
    spaces = len(before) - len(before.rstrip(" \t"))
    if spaces and before.strip(" \t"):
        return Edit(start - spaces, end, "")
    trailing = len(after) - len(after.lstrip(" \t"))
    return Edit(start, end + trailing, "")


def _given(diagnostic: Diagnostic, key: str, missing: str) -> str:
    """The text the finding's fix data holds under `key`; Unfixable(missing) when there is none."""
    value = (diagnostic.fix or {}).get(key)
    if not isinstance(value, str) or not value:
        raise Unfixable(missing)
    return value


@fixer("project-name-mismatch")
def fix_project_name(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    name = _given(diagnostic, "name", "the finding does not name the package")
    source = ctx.files.get(diagnostic.path)
    command = _cmake_command_at(source, diagnostic.line, diagnostic.column, "project")
    if not command.args:
        raise Unfixable("project() has no argument")
    argument = command.args[0]
    if "$" in argument.text or "\\" in argument.text:
        raise Unfixable("project()'s name comes from a variable: set the variable instead")
    start, end = _argument_span(source, argument)
    text = name if argument.kind == "unquoted" else f'"{name}"'
    fix = Fix(f"project({argument.text}) → project({name})")
    fix.add(source.path, Edit(start, end, text))
    return fix


@fixer("install-missing-directory")
def fix_install_missing_directory(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    folder = (diagnostic.fix or {}).get("folder")
    source = ctx.files.get(diagnostic.path)
    command = _cmake_command_at(source, diagnostic.line, diagnostic.column, "install")
    target = next(
        (a for a in command.args if a.line == diagnostic.line and a.column == diagnostic.column), None
    )
    if target is None or target.text != folder:
        raise Unfixable(f"'{folder}' is not at {source.path.name}:{diagnostic.line}:{diagnostic.column}")
    sources = _install_sources(command)
    base = source.path.parent
    missing = [a for a in sources if "$" not in a.text and not (base / a.text).is_dir()]
    fix = Fix(f"removed '{folder}' from install(DIRECTORY ...)")
    if len(missing) == len(sources):  # nothing would be left to install: the rule goes
        start = source.offset(command.line, command.column)
        fix.add(source.path, _delete_span(source, start, _command_end(source, command)))
        fix.description = f"removed install(DIRECTORY {' '.join(a.text for a in sources)} ...): none exists"
        return fix
    start, end = _argument_span(source, target)
    fix.add(source.path, _delete_span(source, start, end))
    return fix


def _install_sources(command: Command) -> list[Argument]:
    from pkgforge.model.cmake import INSTALL_KEYWORDS

    out: list[Argument] = []
    for argument in command.args[1:]:
        if argument.kind == "unquoted" and argument.text in INSTALL_KEYWORDS:
            break
        out.append(argument)
    return out


# --- installing a folder -------------------------------------------------------------------------


@fixer("directory-not-installed", "uninstalled-reference", "mesh-not-found")
def fix_install_folder(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    data = diagnostic.fix or {}
    folder, package = data.get("install_folder"), data.get("package_path")
    if not folder or not package:
        raise Unfixable("no folder to install")
    if not re.fullmatch(r"[A-Za-z0-9_.\-]+", folder):
        raise Unfixable(f"'{folder}' is not a folder name pkgforge writes into an install rule")
    model = ctx.model(Path(package))
    if model.setup_py is not None:
        return _install_in_setup_py(model, model.setup_py, folder, ctx)
    if model.cmake is None:
        raise Unfixable("the package has neither CMakeLists.txt nor setup.py")
    return _install_in_cmake(model, model.cmake, folder, ctx)


def _install_in_cmake(model: PackageModel, cmake: CMakeModel, folder: str, ctx: FixContext) -> Fix:
    from pkgforge.model.layout import _normalize_destination

    share = f"share/{model.share_name}"
    candidates = [
        r
        for r in cmake.install_rules
        if r.mode == "DIRECTORY"
        and isinstance(r.destination, str)
        and _normalize_destination(r.destination) == share
        and not r.patterns
        and not r.files_matching
        and Path(r.base_dir) == model.path
        and not r.conditional
    ]
    fix = Fix(f"installed {folder}/ to share/{model.share_name}")
    for rule in candidates:
        source = ctx.files.get(rule.path)
        command = _cmake_command_at(source, rule.line, rule.command.column, "install")
        sources = _install_sources(command)
        if not sources or any(a.kind != "unquoted" for a in sources):
            continue
        if any(a.text.rstrip("/") == folder for a in sources):
            raise Unfixable(f"{folder} is in the install rule at {source.path.name}:{rule.line} already")
        fix.add(source.path, _add_to_list(source, command, sources, folder))
        fix.description = f"added {folder} to install(DIRECTORY ...) at {source.path.name}:{rule.line}"
        return fix
    # no rule to extend: a new one after the last install rule of CMakeLists.txt
    source = ctx.files.get(model.path / "CMakeLists.txt")
    commands = _cmake_commands(source)
    depth = 0
    last_install: Command | None = None
    ament: Command | None = None
    for command in commands:
        if command.name == "if":
            depth += 1
        elif command.name == "endif":
            depth = max(0, depth - 1)
        elif command.name in ("function", "macro"):
            depth += 1
        elif command.name in ("endfunction", "endmacro"):
            depth = max(0, depth - 1)
        elif depth == 0 and command.name == "install":
            last_install = command
        elif depth == 0 and command.name == "ament_package" and ament is None:
            ament = command
    new = f"install(DIRECTORY {folder} DESTINATION share/${{PROJECT_NAME}})"
    if last_install is not None:
        end = _command_end(source, last_install)
        offset = source.line_end(source.line_of(end))
        prefix = "" if source.text[:offset].endswith("\n") else source.eol
        fix.add(
            source.path,
            Edit(offset, offset, prefix + source.indentation(last_install.line) + new + source.eol),
        )
    elif ament is not None and source.is_blank_before(source.offset(ament.line, ament.column)):
        start = source.line_start(ament.line)
        fix.add(
            source.path, Edit(start, start, source.indentation(ament.line) + new + source.eol + source.eol)
        )
    else:
        raise Unfixable("no install rule or ament_package() in CMakeLists.txt to put the rule beside")
    fix.description = f"added {new} to CMakeLists.txt"
    return fix


def _add_to_list(source: SourceText, command: Command, arguments: list[Argument], item: str) -> Edit:
    """Insert `item` among `arguments` (alphabetically where they are), keeping their layout."""
    names = [a.text.rstrip("/") for a in arguments]
    ordered = names == sorted(names)
    one_per_line = (
        len({a.line for a in arguments}) == len(arguments)
        and len(arguments) > 1
        and all(source.is_blank_before(source.offset(a.line, a.column)) for a in arguments)
    )
    following = (
        next((a for a, n in zip(arguments, names, strict=False) if n > item), None) if ordered else None
    )
    if following is not None:
        start = source.offset(following.line, following.column)
        if one_per_line:
            line_start = source.line_start(following.line)
            return Edit(line_start, line_start, source.indentation(following.line) + item + source.eol, item)
        return Edit(start, start, item + " ", item)
    last = arguments[-1]
    _, end = _argument_span(source, last)
    if one_per_line:
        offset = source.line_end(last.line)
        return Edit(offset, offset, source.indentation(last.line) + item + source.eol, item)
    return Edit(end, end, " " + item, item)


GLOB_TEMPLATE = re.compile(
    r"""^(glob\.)?glob\(\s*(?:(?:os\.path\.|path\.)?join\(\s*(['"])@\2\s*,\s*(['"])(\*|\*\*|\*\.\*)\3\s*\)"""
    r"""|(['"])@/(\*|\*\*|\*\.\*|\*\*/\*)\5)\s*(,\s*recursive\s*=\s*True\s*)?\)$"""
)


def _install_in_setup_py(model: PackageModel, setup_py: SetupPyModel, folder: str, ctx: FixContext) -> Fix:
    """A data_files entry for `folder`, written as the entries for the other folders are:
    (destination, glob('folder/*')) tuples, or *helper('folder') calls."""
    source = ctx.files.get(setup_py.source.path)
    try:
        tree = parse_python(source.text)
    except SyntaxError as exc:
        raise Unfixable(f"setup.py does not parse: {exc.msg}") from exc
    call = next(
        (
            n
            for n in ast.walk(tree)
            if isinstance(n, ast.Call) and getattr(n.func, "id", getattr(n.func, "attr", None)) == "setup"
        ),
        None,
    )
    data_files = next((k.value for k in (call.keywords if call else []) if k.arg == "data_files"), None)
    if not isinstance(data_files, ast.List):
        raise Unfixable("setup.py's data_files is not a list written out in setup()")
    installed = {f for _, _, folders, _ in model.layout.directory_rules for f in folders}
    # (element, folder it installs, its text with that folder replaced by the new one)
    templates: list[tuple[ast.expr, str, str]] = []
    for element in data_files.elts:
        text = ast.get_source_segment(source.text, element) or ""
        for existing in sorted(installed):
            pattern = re.compile(rf"(?<=['\"/]){re.escape(existing)}(?=['\"/])")
            if isinstance(element, ast.Tuple) and len(element.elts) == 2:
                files_text = ast.get_source_segment(source.text, element.elts[1]) or ""
                usable = bool(GLOB_TEMPLATE.match(pattern.sub("@", files_text)))
            elif isinstance(element, ast.Starred) and isinstance(element.value, ast.Call):
                arguments = element.value.args
                usable = (
                    len(arguments) == 1
                    and isinstance(arguments[0], ast.Constant)
                    and arguments[0].value == existing
                    and not element.value.keywords
                )
            else:
                usable = False
            if usable:
                templates.append((element, existing, pattern.sub(folder, text)))
                break
    if not templates:
        raise Unfixable(
            "no data_files entry of the form (destination, glob('folder/*')) to follow; "
            f"add (os.path.join('share', package_name, '{folder}'), glob('{folder}/*'))"
        )
    names = [name for _, name, _ in templates]
    following = next((t for t in templates if t[1] > folder), None) if names == sorted(names) else None
    fix = Fix(f"added {folder} to data_files in setup.py")
    if following is not None:
        element, _, new = following
        start = source.offset_utf8(element.lineno, element.col_offset)
        if source.is_blank_before(start):
            line_start = source.line_start(element.lineno)
            fix.add(
                source.path,
                Edit(
                    line_start,
                    line_start,
                    source.indentation(element.lineno) + new + "," + source.eol,
                    folder,
                ),
            )
        else:
            fix.add(source.path, Edit(start, start, new + ", ", folder))
        fix.description += f":{element.lineno}"
        return fix
    element, _, new = templates[-1]
    start, end = _span(source, element)
    end_line = _end_line(element)
    rest = source.text[end : source.line_end(end_line)]
    comma = rest.lstrip(" \t").startswith(",")
    fix.description += f":{end_line + 1}"
    if source.is_blank_before(start):
        indent = source.indentation(element.lineno)
        offset = source.line_end(end_line)
        if comma:
            fix.add(source.path, Edit(offset, offset, indent + new + "," + source.eol, folder))
        else:
            fix.add(source.path, Edit(end, end, ",", folder))
            fix.add(source.path, Edit(offset, offset, indent + new + source.eol, folder))
    else:
        fix.add(source.path, Edit(end, end, ", " + new, folder))
    return fix


# --- RViz -------------------------------------------------------------------------------------------


def _yaml(source: SourceText) -> yaml.Node | None:  # None: an empty file
    import yaml

    from pkgforge.model.yamlnodes import compose

    try:
        return compose(source.text)
    except yaml.YAMLError as exc:  # (past the reader's bounds too)
        raise Unfixable(f"{source.path.name} is not valid YAML") from exc


def _mapping(node: yaml.Node | None) -> dict[str, tuple[yaml.Node, yaml.Node]]:
    import yaml

    if not isinstance(node, yaml.MappingNode):
        return {}
    return {key.value: (key, value) for key, value in node.value if isinstance(key, yaml.ScalarNode)}


def _plain(value: str) -> str:
    return value if re.fullmatch(r"[A-Za-z_/][A-Za-z0-9_./\-]*", value) else json.dumps(value)


def _replace_scalar(node: yaml.Node, value: str) -> Edit:
    import yaml

    if not isinstance(node, yaml.ScalarNode):
        raise Unfixable("the value is not a plain scalar")
    if node.start_mark.index == node.end_mark.index:  # `Key:` with nothing after it
        return Edit(node.start_mark.index, node.end_mark.index, " " + _plain(value))
    return Edit(node.start_mark.index, node.end_mark.index, _plain(value))


def _find_display(node: yaml.Node | None, line: int) -> yaml.MappingNode | None:
    """The mapping whose Class value stands at `line` (a display, possibly in a group), the first
    in the file's order."""
    import yaml

    todo = [node]
    while todo:  # (no recursion: the config nests as deep as the reader lets it)
        current = todo.pop()
        if isinstance(current, yaml.MappingNode):
            entries = _mapping(current)
            if "Class" in entries and entries["Class"][1].start_mark.line + 1 == line:
                return current
            todo += reversed([value for _, value in current.value])
        elif isinstance(current, yaml.SequenceNode):
            todo += reversed(current.value)
    return None


def _insert_key(source: SourceText, mapping: yaml.MappingNode, key: str, lines: list[str]) -> Edit:
    """New `key` lines in a block mapping, in alphabetical order where RViz keeps its keys."""
    entries = list(mapping.value)
    column = entries[0][0].start_mark.column
    indent = source.text[source.line_start(entries[0][0].start_mark.line + 1) :][:column]
    indent = indent if indent.strip(" ") == "" else " " * column
    text = "".join(indent + line + source.eol for line in lines)
    previous = [(k, v) for k, v in entries if str(k.value) < key]
    if previous:
        value = previous[-1][1]
        end = value.end_mark
        offset = end.index if end.column == 0 else source.line_end(end.line + 1)
        return Edit(offset, offset, text, key)
    first = entries[0][0]
    if source.is_blank_before(first.start_mark.index):
        start = source.line_start(first.start_mark.line + 1)
        return Edit(start, start, text, key)
    value = entries[0][1]
    offset = value.end_mark.index if value.end_mark.column == 0 else source.line_end(value.end_mark.line + 1)
    return Edit(offset, offset, text, key)


@fixer("rviz-no-description")
def fix_rviz_description(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    import yaml

    line = (diagnostic.fix or {}).get("display_line")
    source = ctx.files.get(diagnostic.path)
    display = _find_display(_yaml(source), line) if line else None
    if display is None:
        raise Unfixable("cannot find the RobotModel display")
    entries = _mapping(display)
    fix = Fix(f"RobotModel: Description Source Topic, Description Topic {ROBOT_DESCRIPTION_TOPIC}")
    if "Description Source" in entries:
        value = entries["Description Source"][1]
        if getattr(value, "value", None) != "Topic":
            fix.add(source.path, _replace_scalar(value, "Topic"))
    else:
        fix.add(
            source.path, _insert_key(source, display, "Description Source", ["Description Source: Topic"])
        )
    if "Description Topic" in entries:
        value = entries["Description Topic"][1]
        if isinstance(value, yaml.MappingNode):
            inner = _mapping(value)
            if "Value" in inner:
                fix.add(source.path, _replace_scalar(inner["Value"][1], ROBOT_DESCRIPTION_TOPIC))
            else:
                fix.add(
                    source.path, _insert_key(source, value, "Value", [f"Value: {ROBOT_DESCRIPTION_TOPIC}"])
                )
        else:
            fix.add(source.path, _replace_scalar(value, ROBOT_DESCRIPTION_TOPIC))
    else:
        fix.add(
            source.path,
            _insert_key(
                source,
                display,
                "Description Topic",
                [
                    "Description Topic:",
                    "  Depth: 5",
                    "  Durability Policy: Transient Local",
                    "  History Policy: Keep Last",
                    "  Reliability Policy: Reliable",
                    f"  Value: {ROBOT_DESCRIPTION_TOPIC}",
                ],
            ),
        )
    return fix


@fixer("rviz-fixed-frame-unknown")
def fix_fixed_frame(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    frame = _given(diagnostic, "frame", "the model's root link is not known")
    source = ctx.files.get(diagnostic.path)
    manager = _mapping(_yaml(source)).get("Visualization Manager")
    options = _mapping(manager[1]).get("Global Options") if manager else None
    fixed = _mapping(options[1]).get("Fixed Frame") if options else None
    if fixed is None:
        raise Unfixable("no Global Options: Fixed Frame to change")
    fix = Fix(f"Fixed Frame {getattr(fixed[1], 'value', '?')} → {frame} (the model's root link)")
    fix.add(source.path, _replace_scalar(fixed[1], frame))
    return fix


@fixer("rviz-ros1-config")
def fix_rviz1_config(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    """The whole config converted as `pkgforge migrate` converts one (unsafe: the file is written
    anew, its comments and RViz 1's window layout are not kept, classes RViz 2 lacks are left out)."""
    from pkgforge.errors import PkgforgeError
    from pkgforge.migrate.notes import Notes
    from pkgforge.migrate.rviz1 import convert

    source = ctx.files.get(diagnostic.path)
    notes = Notes(diagnostic.package)
    try:
        converted = convert(source.text, source.path, notes, set(), None, by="pkgforge fix")
    except PkgforgeError as exc:
        raise Unfixable(str(exc).split(": ", 1)[-1]) from exc
    renamed = sum(1 for d in notes.diagnostics if d.name == "migrate-renamed")
    dropped = sum(1 for d in notes.diagnostics if d.name == "migrate-dropped")
    fix = Fix(
        f"converted to RViz 2: {renamed} class(es) renamed"
        + (f", {dropped} without an RViz 2 class left out" if dropped else "")
    )
    fix.add(source.path, Edit(0, len(source.text), converted.replace("\n", source.eol)))
    return fix


# --- models ------------------------------------------------------------------------------------------


@fixer("mesh-case-mismatch")
def fix_mesh_case(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    data = diagnostic.fix or {}
    uri, real = data.get("uri"), data.get("real_name")
    if not uri or not real or "/" in real:
        raise Unfixable("the finding does not say the file's real name")
    source = ctx.files.get(diagnostic.path)
    wrong = posixpath.basename(uri)
    fixed_uri = uri[: len(uri) - len(wrong)] + real
    fix = Fix(f"{uri} → {fixed_uri}")
    exact = [m.start() for m in re.finditer(re.escape(uri) + r"(?=[\"'<\s])", source.text)]
    for start in exact:
        fix.add(source.path, Edit(start, start + len(uri), fixed_uri))
    if not exact and diagnostic.line:
        # the URI is built by xacro (package://$(arg ...)/...): its file name part is on the line
        line_start = source.line_start(diagnostic.line)
        hits = [
            m.start()
            for m in re.finditer(
                r"(?<=/)" + re.escape(wrong) + r"(?=[\"'])", source.line_text(diagnostic.line)
            )
        ]
        if len(hits) == 1:
            fix.add(source.path, Edit(line_start + hits[0], line_start + hits[0] + len(wrong), real))
    if not fix.edits:
        raise Unfixable(
            f"{uri} is not written literally in {source.path.name}: write {real} where it is built"
        )
    return fix


# --- Python launch files ------------------------------------------------------------------------------


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


_Located = ast.expr | ast.stmt | ast.keyword  # the nodes ast.parse gives positions


def _end_line(node: _Located) -> int:
    # ast.parse sets the end of every node; nodes built by hand may lack it
    return node.end_lineno if node.end_lineno is not None else node.lineno


def _span(source: SourceText, node: _Located) -> tuple[int, int]:
    end_column = node.end_col_offset if node.end_col_offset is not None else node.col_offset
    return (
        source.offset_utf8(node.lineno, node.col_offset),
        source.offset_utf8(_end_line(node), end_column),
    )


def _containing_calls(tree: ast.AST, line: int, name: str) -> list[ast.Call]:
    calls = [
        n
        for n in ast.walk(tree)
        if isinstance(n, ast.Call) and _call_name(n) == name and n.lineno <= line <= _end_line(n)
    ]
    return sorted(calls, key=lambda n: (_end_line(n) - n.lineno, -n.lineno))


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
        _, end = _span(source, parent.args[-1] if not parent.keywords else parent.keywords[-1].value)
        fix.add(source.path, Edit(end, end, ", value_type=str"))
        return fix
    start, end = _span(source, command)
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
        n for n in ast.walk(tree) if isinstance(n, (ast.Dict, ast.Call)) and n.lineno <= line <= _end_line(n)
    ]
    inner = sorted(around, key=lambda n: _end_line(n) - n.lineno)[:1]
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
        offset = source.line_end(_end_line(last))
        prefix = "" if source.text[:offset].endswith("\n") else source.eol
        return Edit(offset, offset, prefix + line + source.eol, "0")
    first = tree.body[0] if tree.body else None
    if (
        first is not None
        and isinstance(first, ast.Expr)
        and isinstance(getattr(first, "value", None), ast.Constant)
    ):
        offset = source.line_end(_end_line(first))
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
        start, end = _span(source, arguments)
        rest = source.text[end : source.line_end(_end_line(arguments))]
        alone = source.is_blank_before(start) and re.fullmatch(r"\s*,?\s*(#.*)?\s*", rest)
        previous = siblings[index - 1] if index > 0 else None
        following = siblings[index + 1] if index + 1 < len(siblings) else None
        if alone:  # the keyword has its own line(s): they go
            start, end = source.line_start(arguments.lineno), source.line_end(_end_line(arguments))
        elif previous is not None and _end_line(previous) == arguments.lineno:
            start = _span(source, previous)[1]  # `, arguments=[...]`: what follows keeps its place
        elif following is not None and following.lineno == _end_line(arguments):
            end = _span(source, following)[0]  # `arguments=[...], ` up to the next argument
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
