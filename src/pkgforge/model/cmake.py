"""What a package's CMakeLists.txt means for its install tree.

Interprets the part of CMake that decides install rules: project(), set(),
list(APPEND), include() of the package's own files and GNUInstallDirs,
add_subdirectory(), foreach(). Both branches of an if() are taken (a rule in
either may run); function and macro bodies are not (they run only if called).
A value built from something unknown stays unknown: it is never guessed.
An if() whose condition holds only where an optional find_package() found its
package (`if(X_FOUND)`, `if(TARGET X::x)`, the else() of `if(NOT X_FOUND)`, the
rest of a file after `if(NOT X_FOUND) return() endif()`) gates what it holds:
the find_package() commands there are recorded with the packages they need.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from pkgforge.model.cmake_syntax import Argument, CMakeSyntaxError, Command, parse
from pkgforge.model.source import SourceFile, read_source

# Stand-ins for paths that are not in the source tree
INSTALL_PREFIX = "<install-prefix>"
BINARY_DIR = "<build-dir>"
# where ament_cmake_python installs modules (the real path names the Python version)
PYTHON_SITE = "lib/python3/site-packages"

VARIABLE = re.compile(r"\$\{([^${}]*)\}")
ENV_VARIABLE = re.compile(r"\$ENV\{[^}]*\}")
ESCAPES = {
    "n": "\n",
    "t": "\t",
    "r": "\r",
    ";": "\\;",
    "\\": "\\",
    '"': '"',
    " ": " ",
    "$": "$",
    "@": "@",
    "(": "(",
    ")": ")",
    "#": "#",
    "{": "{",
    "}": "}",
}

INSTALL_KEYWORDS = {
    "DESTINATION",
    "FILE_PERMISSIONS",
    "DIRECTORY_PERMISSIONS",
    "USE_SOURCE_PERMISSIONS",
    "OPTIONAL",
    "MESSAGE_NEVER",
    "CONFIGURATIONS",
    "COMPONENT",
    "EXCLUDE_FROM_ALL",
    "FILES_MATCHING",
    "PATTERN",
    "REGEX",
    "TYPE",
    "PERMISSIONS",
    "RENAME",
}
GNU_INSTALL_DIRS = {
    "CMAKE_INSTALL_BINDIR": "bin",
    "CMAKE_INSTALL_SBINDIR": "sbin",
    "CMAKE_INSTALL_LIBDIR": "lib",
    "CMAKE_INSTALL_INCLUDEDIR": "include",
    "CMAKE_INSTALL_DATAROOTDIR": "share",
    "CMAKE_INSTALL_DATADIR": "share",
    "CMAKE_INSTALL_LIBEXECDIR": "libexec",
}
MAX_INCLUDE_DEPTH = 16


class Unknown:
    """A value pkgforge cannot know without running CMake."""

    def __init__(self, why: str):
        self.why = why

    def __repr__(self) -> str:
        return f"Unknown({self.why})"


# a CMake scope's variables: their values, or why pkgforge cannot know one
Variables = dict[str, "str | Unknown"]


@dataclass(frozen=True)
class Pattern:
    kind: str  # PATTERN | REGEX
    value: str
    exclude: bool


@dataclass
class InstallRule:
    mode: str  # DIRECTORY | FILES | PROGRAMS
    command: Command
    base_dir: Path  # CMAKE_CURRENT_SOURCE_DIR where the rule stands
    sources: list[tuple[str | Unknown, Argument]] = field(default_factory=list)
    destination: str | Unknown | None = None
    destination_arg: Argument | None = None
    optional: bool = False
    files_matching: bool = False
    patterns: list[Pattern] = field(default_factory=list)
    rename: str | None = None
    conditional: bool = False  # inside an if()

    @property
    def path(self) -> Path:
        return self.command.path

    @property
    def line(self) -> int:
        return self.command.line


@dataclass
class CMakeModel:
    project_name: str | Unknown | None = None
    project_command: Command | None = None
    ament_package_command: Command | None = None
    install_rules: list[InstallRule] = field(default_factory=list)
    find_packages: list[tuple[str, Command]] = field(default_factory=list)
    # the find_package() commands inside if(BUILD_TESTING): what they find is a test dependency
    test_only: set[tuple[Path, int]] = field(default_factory=set)
    # the find_package() commands that run only where an optional find_package() (not REQUIRED)
    # found its package (tmr_ros2's tm_driver: if(moveit_ros_planning_interface_FOUND)): their
    # location → those optional finds, (name, command) by name
    gated: dict[tuple[Path, int], tuple[tuple[str, Command], ...]] = field(default_factory=dict)
    # ament_auto_find_build_dependencies(): every build dependency of package.xml is found
    auto_find_command: Command | None = None
    files: list[SourceFile] = field(default_factory=list)  # every CMake file read
    syntax_errors: list[CMakeSyntaxError] = field(default_factory=list)
    unreadable: list[SourceFile] = field(default_factory=list)


@dataclass
class _IfBlock:
    """An open if() while its commands run: what its branch taken now needs found."""

    testing: bool  # an if(BUILD_TESTING) still counted
    gate: frozenset[str]  # the optional finds the current branch runs only with
    earlier_false: frozenset[str]  # what every earlier condition being false needs found
    first_false: frozenset[str]  # what the first condition being false needs found
    first_branch: bool = True
    returns: bool = False  # a return() in the first branch: what follows needs first_false
    after: frozenset[str] = frozenset()  # gates of inner blocks' return() in the current branch


class _Interpreter:
    def __init__(self, package_path: Path, model: CMakeModel):
        self.package_path = package_path
        self.model = model
        self.depth = 0
        self.testing = 0  # how many enclosing if(BUILD_TESTING) blocks are open
        self.gate: frozenset[str] = frozenset()  # the optional finds what runs now needs
        # name → its find_package(); only those without REQUIRED (X_FOUND may be false)
        self.optional_finds: dict[str, Command] = {}
        self.required_finds: set[str] = set()

    def run_file(self, path: Path, variables: Variables) -> None:
        if self.depth > MAX_INCLUDE_DEPTH:
            return
        source = read_source(path)
        self.model.files.append(source)
        if source.text is None:
            self.model.unreadable.append(source)
            return
        try:
            commands = parse(source.text, path)
        except CMakeSyntaxError as error:
            self.model.syntax_errors.append(error)
            return
        self.depth += 1
        try:
            self.run(commands, variables, conditional=False)
        finally:
            self.depth -= 1

    def run(self, commands: list[Command], variables: Variables, *, conditional: bool) -> None:
        index = 0
        blocks: list[_IfBlock] = []  # the if() blocks open in these commands
        outer = self.gate  # what the caller's context needs (an include or a loop inside an if())
        rest: frozenset[str] = frozenset()  # what the rest needs after a top-level if(NOT X_FOUND) return()
        try:
            while index < len(commands):
                command = commands[index]
                name = command.name
                self.gate = outer | rest | frozenset().union(*(b.gate | b.after for b in blocks))
                if name in ("function", "macro"):
                    index = _block_end(commands, index, name, "end" + name) + 1
                    continue
                if name == "foreach":
                    end = _block_end(commands, index, "foreach", "endforeach")
                    self.foreach(command, commands[index + 1 : end], variables, conditional or bool(blocks))
                    index = end + 1
                    continue
                if name == "if":
                    words = [a.text for a in command.args]
                    when_true, when_false = self.condition(command.args)
                    blocks.append(
                        _IfBlock(
                            bool(words) and words[0] == "BUILD_TESTING", when_true, when_false, when_false
                        )
                    )
                    self.testing += blocks[-1].testing
                elif name in ("else", "elseif") and blocks:
                    block = blocks[-1]
                    if block.testing:  # the other branch of if(BUILD_TESTING)
                        block.testing = False
                        self.testing -= 1
                    when_true, when_false = (
                        self.condition(command.args) if name == "elseif" else (frozenset(),) * 2
                    )
                    block.gate = block.earlier_false | when_true
                    block.earlier_false |= when_false
                    block.first_branch, block.after = False, frozenset()
                elif name == "endif":
                    if blocks:
                        block = blocks.pop()
                        self.testing -= block.testing
                        if block.returns:  # if(NOT X_FOUND) return() endif(): what follows needs X
                            if blocks:
                                blocks[-1].after |= block.first_false
                            else:
                                rest |= block.first_false
                elif name == "return":
                    if blocks and blocks[-1].first_branch:
                        blocks[-1].returns = True
                else:
                    self.command(command, variables, conditional or bool(blocks))
                index += 1
        finally:
            self.testing -= sum(b.testing for b in blocks)  # an if() never closed in this file
            self.gate = outer

    def condition(self, args: tuple[Argument, ...]) -> tuple[frozenset[str], frozenset[str]]:
        """The optional finds an if() condition needs found when it holds, and when it does not."""
        optional = {
            name: command for name, command in self.optional_finds.items() if name not in self.required_finds
        }
        if not optional:
            return frozenset(), frozenset()
        return _needs_found(list(args), optional)

    def foreach(self, command: Command, body: list[Command], variables: Variables, conditional: bool) -> None:
        values = self.expand_args(command.args, variables)
        if not values or isinstance(values[0], Unknown):
            return
        loop_var, items = values[0], values[1:]
        if items and items[0] in ("IN",):
            items = items[1:]
        if items and items[0] in ("ITEMS", "LISTS"):
            keyword, rest = items[0], items[1:]
            items = rest
            if keyword == "LISTS":
                items = [
                    part
                    for name in rest
                    for part in _split_list(variables.get(name, "") if isinstance(name, str) else "")
                ]
        if any(isinstance(item, Unknown) for item in items) or (items and items[0] == "RANGE"):
            return
        for item in items:
            scope = dict(variables)
            scope[loop_var] = item
            self.run(body, scope, conditional=conditional)

    def command(self, command: Command, variables: Variables, conditional: bool) -> None:
        name = command.name
        if name == "project":
            values = self.expand_args(command.args, variables)
            if values:
                self.model.project_name = values[0]
                self.model.project_command = command
                if isinstance(values[0], str):
                    variables["PROJECT_NAME"] = values[0]
                    variables["CMAKE_PROJECT_NAME"] = values[0]
                    variables[f"{values[0]}_SOURCE_DIR"] = variables["CMAKE_CURRENT_SOURCE_DIR"]
                else:
                    variables["PROJECT_NAME"] = values[0]
        elif name == "set":
            self.set(command, variables)
        elif name == "list":
            values = self.expand_args(command.args, variables)
            if len(values) >= 2 and values[0] == "APPEND" and isinstance(values[1], str):
                current = variables.get(values[1], "")
                added = [v for v in values[2:] if not isinstance(v, Unknown)]
                if isinstance(current, Unknown) or len(added) < len(values) - 2:
                    variables[values[1]] = Unknown(f"list {values[1]}")
                else:
                    parts = [current] if current != "" else []
                    variables[values[1]] = ";".join(parts + added)
        elif name == "include":
            self.include(command, variables)
        elif name == "add_subdirectory":
            values = self.expand_args(command.args, variables)
            if values and isinstance(values[0], str):
                folder = _resolve(values[0], variables)
                if _inside(folder, self.package_path) and (folder / "CMakeLists.txt").is_file():
                    scope = dict(variables)
                    scope["CMAKE_CURRENT_SOURCE_DIR"] = str(folder)
                    scope["CMAKE_CURRENT_LIST_DIR"] = str(folder)
                    self.run_file(folder / "CMakeLists.txt", scope)
        elif name == "install":
            rule = self.install(command, variables)
            if rule is not None:
                rule.conditional = conditional
                self.model.install_rules.append(rule)
        elif name == "ament_package":
            self.model.ament_package_command = command
        elif name == "ament_auto_package":
            # ament_cmake_auto: install(DIRECTORY <dir> DESTINATION share/${PROJECT_NAME}) for each
            # folder after INSTALL_TO_SHARE, then ament_package()
            self.model.ament_package_command = command
            rule = self.auto_package(command, variables)
            if rule is not None:
                rule.conditional = conditional
                self.model.install_rules.append(rule)
        elif name == "ament_auto_find_build_dependencies":
            self.model.auto_find_command = command
        elif name in ("ament_python_install_package", "ament_python_install_module"):
            rule = self.python_install(command, variables)
            if rule is not None:
                self.model.install_rules.append(rule)
        elif name == "find_package":
            values = self.expand_args(command.args, variables)
            if values and isinstance(values[0], str):
                self.model.find_packages.append((values[0], command))
                if self.testing:
                    self.model.test_only.add((command.path, command.line))
                if self.gate:
                    self.model.gated[(command.path, command.line)] = tuple(
                        (gate, self.optional_finds[gate]) for gate in sorted(self.gate)
                    )
                if "REQUIRED" in values[1:]:
                    self.required_finds.add(values[0])
                else:
                    self.optional_finds.setdefault(values[0], command)

    def auto_package(self, command: Command, variables: Variables) -> InstallRule | None:
        rule = InstallRule("DIRECTORY", command, Path(str(variables["CMAKE_CURRENT_SOURCE_DIR"])))
        keywords = {"INSTALL_TO_SHARE", "INSTALL_TO_PATH", "USE_SCOPED_HEADER_INSTALL_DIR"}
        collecting = False
        for arg in command.args:
            for value in self.expand_list(arg, variables):
                if value in keywords:
                    collecting = value == "INSTALL_TO_SHARE"
                elif collecting:
                    rule.sources.append((value, arg))
        if not rule.sources:
            return None
        project = variables.get("PROJECT_NAME")
        rule.destination = f"share/{project}" if isinstance(project, str) else Unknown("${PROJECT_NAME}")
        return rule

    def python_install(self, command: Command, variables: Variables) -> InstallRule | None:
        """ament_cmake_python: the package folder (PACKAGE_DIR, else the name) or module file."""
        values = self.expand_args(command.args, variables)
        if not values or isinstance(values[0], Unknown):
            return None
        source: str | Unknown = values[0]
        if command.name == "ament_python_install_package":
            if "PACKAGE_DIR" in values[1:-1]:
                source = values[values.index("PACKAGE_DIR") + 1]
            mode = "DIRECTORY"
        else:
            mode = "FILES"
        rule = InstallRule(mode, command, Path(str(variables["CMAKE_CURRENT_SOURCE_DIR"])))
        rule.sources.append((source, command.args[0]))
        rule.destination = PYTHON_SITE
        return rule

    def set(self, command: Command, variables: Variables) -> None:
        values = self.expand_args(command.args, variables)
        if not values or isinstance(values[0], Unknown):
            return
        name, rest = values[0], values[1:]
        for stop in ("CACHE", "PARENT_SCOPE"):
            if stop in rest:
                rest = rest[: rest.index(stop)]
        known = [v for v in rest if not isinstance(v, Unknown)]
        if len(known) < len(rest):
            variables[name] = Unknown(f"variable {name}")
        else:
            variables[name] = ";".join(known)

    def include(self, command: Command, variables: Variables) -> None:
        values = self.expand_args(command.args, variables)
        if not values or isinstance(values[0], Unknown):
            return
        target = values[0]
        if target == "GNUInstallDirs":
            variables.update(GNU_INSTALL_DIRS)
            return
        if "/" not in target and not target.endswith(".cmake"):
            return  # a CMake module from elsewhere
        path = _resolve(target, variables)
        if _inside(path, self.package_path) and path.is_file():
            self.run_file(path, variables)

    def install(self, command: Command, variables: Variables) -> InstallRule | None:
        args = list(command.args)
        if not args:
            return None
        mode = self.expand(args[0], variables)
        if mode not in ("DIRECTORY", "FILES", "PROGRAMS"):
            return None  # TARGETS, EXPORT, SCRIPT, CODE: not resources
        rule = InstallRule(mode, command, Path(str(variables["CMAKE_CURRENT_SOURCE_DIR"])))
        expanded: list[tuple[str | Unknown, Argument]] = []
        for arg in args[1:]:
            for value in self.expand_list(arg, variables):
                expanded.append((value, arg))
        index = 0
        while index < len(expanded) and expanded[index][0] not in INSTALL_KEYWORDS:
            rule.sources.append(expanded[index])
            index += 1
        while index < len(expanded):
            keyword, arg = expanded[index]
            following = expanded[index + 1] if index + 1 < len(expanded) else None
            if keyword == "DESTINATION" and following:
                rule.destination, rule.destination_arg = following[0], following[1]
                index += 2
            elif keyword in ("PATTERN", "REGEX") and following:
                exclude = index + 2 < len(expanded) and expanded[index + 2][0] == "EXCLUDE"
                if isinstance(following[0], str):
                    rule.patterns.append(Pattern(keyword, following[0], exclude))
                index += 3 if exclude else 2
            elif keyword == "RENAME" and following:
                rule.rename = following[0] if isinstance(following[0], str) else None
                index += 2
            else:
                if keyword == "OPTIONAL":
                    rule.optional = True
                elif keyword == "FILES_MATCHING":
                    rule.files_matching = True
                index += 1
        return rule

    # --- evaluation of arguments ---------------------------------------------------------

    def expand(self, arg: Argument, variables: Variables) -> str | Unknown:
        if arg.kind == "bracket":
            return arg.text
        return _expand_text(arg.text, variables)

    def expand_list(self, arg: Argument, variables: Variables) -> list[str | Unknown]:
        value = self.expand(arg, variables)
        if isinstance(value, Unknown) or arg.kind != "unquoted":
            return [value]
        return [part for part in _split_list(value) if part != ""]

    def expand_args(self, args: tuple[Argument, ...], variables: Variables) -> list[str | Unknown]:
        return [value for arg in args for value in self.expand_list(arg, variables)]


def _expand_text(text: str, variables: Variables) -> str | Unknown:
    if ENV_VARIABLE.search(text):
        return Unknown("an environment variable")
    for _ in range(32):  # innermost ${} first, so ${A_${B}} works
        match = VARIABLE.search(text)
        if not match:
            break
        value = variables.get(match.group(1))
        if value is None:
            return Unknown(f"${{{match.group(1)}}}")
        if isinstance(value, Unknown):
            return value
        text = text[: match.start()] + value + text[match.end() :]
    return re.sub(r"\\(.)", lambda m: ESCAPES.get(m.group(1), m.group(1)), text)


def _split_list(value: str | Unknown) -> list[str | Unknown]:
    if isinstance(value, Unknown):
        return [value]
    parts: list[str | Unknown] = []
    current: list[str] = []
    index = 0
    while index < len(value):
        char = value[index]
        if char == "\\" and index + 1 < len(value) and value[index + 1] == ";":
            current.append(";")
            index += 2
            continue
        if char == ";":
            parts.append("".join(current))
            current = []
        else:
            current.append(char)
        index += 1
    parts.append("".join(current))
    return parts


# if() operators: unary ones take the next argument, binary ones the arguments either side
UNARY_TESTS = frozenset(
    {"EXISTS", "COMMAND", "DEFINED", "TARGET", "POLICY", "TEST", "IS_DIRECTORY", "IS_SYMLINK"}
    | {"IS_ABSOLUTE", "IS_READABLE", "IS_WRITABLE", "IS_EXECUTABLE"}
)
BINARY_TESTS = frozenset(
    {"EQUAL", "LESS", "GREATER", "LESS_EQUAL", "GREATER_EQUAL", "STREQUAL", "STRLESS", "STRGREATER"}
    | {"STRLESS_EQUAL", "STRGREATER_EQUAL", "VERSION_EQUAL", "VERSION_LESS", "VERSION_GREATER"}
    | {"VERSION_LESS_EQUAL", "VERSION_GREATER_EQUAL", "PATH_EQUAL", "MATCHES", "IN_LIST", "IS_NEWER_THAN"}
)
NO_NEED: tuple[frozenset[str], frozenset[str]] = (frozenset(), frozenset())
# parentheses in an if() condition read through (four calls a level); a condition nested deeper
# (none is) is read as needing nothing, as any condition pkgforge cannot read is
MAX_CONDITION_DEPTH = 64


class _NotACondition(Exception):
    pass


def _needs_found(args: list[Argument], optional: dict[str, Command]) -> tuple[frozenset[str], frozenset[str]]:
    """(needed when it holds, needed when it does not): the names of `optional` whose find must
    have found the package for the if() condition `args` to hold (`X_FOUND`, `${X_FOUND}`,
    `TARGET X::x`) or to fail (`NOT X_FOUND`), through NOT, AND, OR and parentheses as
    cmake-commands(7) gives their precedence. A condition read otherwise needs nothing."""
    by_lower = {name.lower(): name for name in optional}
    position = 0
    depth = 0  # parentheses open

    def word(offset: int = 0) -> str | None:
        index = position + offset
        if index >= len(args):
            return None
        return args[index].text if args[index].kind == "unquoted" else None

    def either() -> tuple[frozenset[str], frozenset[str]]:
        nonlocal position
        when_true, when_false = both()
        while word() == "OR":
            position += 1
            other_true, other_false = both()
            when_true, when_false = when_true & other_true, when_false | other_false
        return when_true, when_false

    def both() -> tuple[frozenset[str], frozenset[str]]:
        nonlocal position
        when_true, when_false = negation()
        while word() == "AND":
            position += 1
            other_true, other_false = negation()
            when_true, when_false = when_true | other_true, when_false & other_false
        return when_true, when_false

    def negation() -> tuple[frozenset[str], frozenset[str]]:
        nonlocal position
        flips = 0
        while word() == "NOT":  # (counted, not recursed: `NOT NOT … x` may be any length)
            position += 1
            flips += 1
        when_true, when_false = test()
        return (when_false, when_true) if flips % 2 else (when_true, when_false)

    def test() -> tuple[frozenset[str], frozenset[str]]:
        nonlocal position, depth
        if position >= len(args):
            raise _NotACondition
        if word() == "(":
            depth += 1
            if depth > MAX_CONDITION_DEPTH:  # read recursively: deeper is read as needing nothing
                raise _NotACondition
            position += 1
            found = either()
            if word() != ")":
                raise _NotACondition
            position += 1
            depth -= 1
            return found
        if word() in UNARY_TESTS:
            operator = word()
            position += 2
            if position > len(args):
                raise _NotACondition
            target = args[position - 1].text
            if operator == "TARGET" and "::" in target:  # an imported target: X's find made it
                name = by_lower.get(target.split("::")[0].lower())
                return (frozenset({name}), frozenset()) if name else NO_NEED
            return NO_NEED
        operand = args[position].text
        position += 1
        if word() in BINARY_TESTS:
            position += 2
            if position > len(args):
                raise _NotACondition
            return NO_NEED
        if word() not in (None, ")", "AND", "OR"):
            raise _NotACondition
        variable = operand[2:-1] if operand.startswith("${") and operand.endswith("}") else operand
        if variable.endswith("_FOUND"):
            name = by_lower.get(variable[: -len("_FOUND")].lower())
            if name is not None:
                return frozenset({name}), frozenset()
        return NO_NEED

    try:
        found = either()
    except _NotACondition:
        return NO_NEED
    return found if position == len(args) else NO_NEED


def _block_end(commands: list[Command], start: int, opener: str, closer: str) -> int:
    depth = 0
    for index in range(start, len(commands)):
        if commands[index].name == opener:
            depth += 1
        elif commands[index].name == closer:
            depth -= 1
            if depth == 0:
                return index
    return len(commands) - 1


def _resolve(value: str, variables: Variables) -> Path:
    path = Path(value)
    if not path.is_absolute():
        path = Path(str(variables["CMAKE_CURRENT_SOURCE_DIR"])) / path
    return Path(_normalize(str(path)))


def _normalize(path: str) -> str:
    import os.path

    return os.path.normpath(path)


def _inside(path: Path, folder: Path) -> bool:
    try:
        path.relative_to(folder)
        return True
    except ValueError:
        return False


def load_cmake(package_path: Path) -> CMakeModel:
    model = CMakeModel()
    variables: Variables = {
        "CMAKE_CURRENT_SOURCE_DIR": str(package_path),
        "CMAKE_CURRENT_LIST_DIR": str(package_path),
        "CMAKE_SOURCE_DIR": str(package_path),
        "PROJECT_SOURCE_DIR": str(package_path),
        "CMAKE_INSTALL_PREFIX": INSTALL_PREFIX,
        "CMAKE_CURRENT_BINARY_DIR": BINARY_DIR,
        "CMAKE_BINARY_DIR": BINARY_DIR,
        "PROJECT_BINARY_DIR": BINARY_DIR,
    }
    _Interpreter(package_path, model).run_file(package_path / "CMakeLists.txt", variables)
    return model
