"""The fixers of package.xml, CMakeLists.txt, setup.py and models: from a Diagnostic (its
location and fix data) to text edits (registry.py: one fixer per check name).

A fixer reads the files it edits through the FileSet (each file read once),
finds the construct at the diagnostic's line and column, and returns the edits
that fix it, computed against the text as read. It raises Unfixable with a
short reason when the construct is not one it can edit without guessing.
"""

from __future__ import annotations

import ast
import posixpath
import re
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.diagnostics import Diagnostic
from pkgforge.fix.edits import Edit, NotOffered, SourceText, Unfixable, node_end_line, node_span
from pkgforge.fix.registry import Fix, FixContext, fixer, given
from pkgforge.model.source import parse_python

if TYPE_CHECKING:  # imported where used: `pkgforge fix` loads only what its fixers need
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


@fixer("project-name-mismatch")
def fix_project_name(diagnostic: Diagnostic, ctx: FixContext) -> Fix:
    name = given(diagnostic, "name", "the finding does not name the package")
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
    start, end = node_span(source, element)
    end_line = node_end_line(element)
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
