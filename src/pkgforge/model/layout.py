"""The predicted install tree: which source file lands where under the install prefix."""

from __future__ import annotations

import fnmatch
import os
import posixpath
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from pkgforge.model.cmake import BINARY_DIR, INSTALL_PREFIX, PYTHON_SITE, CMakeModel, InstallRule, Unknown
from pkgforge.model.cmake_syntax import Argument
from pkgforge.model.setup_py import SetupPyModel, package_folder
from pkgforge.walk import WalkLimit, walk

INDEX_MARKER = "share/ament_index/resource_index/packages/{name}"


@dataclass(frozen=True)
class InstalledFile:
    destination: str  # posix path relative to the install prefix
    source: Path | None  # None for files the build generates (the ament index marker)
    rule_path: Path | None
    rule_line: int | None


@dataclass(frozen=True)
class MissingSource:
    """An install rule names a source that does not exist."""

    text: str
    mode: str  # DIRECTORY | FILES | PROGRAMS | data_files
    path: Path
    line: int
    column: int | None


@dataclass(frozen=True)
class RuleDestination:
    """Where a rule installs, for install-wrong-destination."""

    destination: str | None  # normalized, relative to the prefix; None when outside it
    raw: str
    sources: tuple[str, ...]
    path: Path
    line: int
    column: int | None


@dataclass
class InstallLayout:
    # False when the build file could not be read: then nothing is known to be
    # missing from the tree, and checks that need the tree stand down
    known: bool = True
    files: dict[str, InstalledFile] = field(default_factory=dict)
    missing: list[MissingSource] = field(default_factory=list)
    destinations: list[RuleDestination] = field(default_factory=list)
    # (path, line, why) for rules whose effect pkgforge cannot know
    unknown: list[tuple[Path, int, str]] = field(default_factory=list)
    # of those, the ones that may install files (not programs, not targets): (path, line, their
    # destination when known, else None). A file a launch file finds missing may come from one
    may_install: list[tuple[Path, int, str | None]] = field(default_factory=list)
    # the rules that install folders, for fix hints: (path, line, installed top-level folders)
    directory_rules: list[tuple[Path, int, tuple[str, ...], str]] = field(default_factory=list)
    # where a walk of an installed folder stopped (too deep, too many files)
    walk_limits: list[WalkLimit] = field(default_factory=list)

    def add(
        self, destination: str, source: Path | None, rule_path: Path | None, rule_line: int | None
    ) -> None:
        self.files.setdefault(destination, InstalledFile(destination, source, rule_path, rule_line))

    def installed_sources(self) -> set[Path]:
        return {f.source for f in self.files.values() if f.source is not None}

    def exists(self, destination: str) -> bool:
        destination = posixpath.normpath(destination)
        if destination in self.files:
            return True
        prefix = destination.rstrip("/") + "/"
        return any(key.startswith(prefix) for key in self.files)


def _normalize_destination(value: str) -> str | None:
    """Relative to the install prefix, or None when the destination is outside it."""
    value = value.replace("\\", "/")
    if value.startswith(INSTALL_PREFIX):
        value = value[len(INSTALL_PREFIX) :].lstrip("/")
    elif value.startswith("/"):
        return None
    value = posixpath.normpath(value) if value else "."
    if value.startswith(".."):
        return None
    return "" if value == "." else value


def _matches(pattern_kind: str, pattern: str, name: str, full: str) -> bool:
    if pattern_kind == "PATTERN":
        return fnmatch.fnmatchcase(name, pattern)
    try:
        return re.search(pattern, full) is not None
    except re.error:
        return False


def _directory_files(source: Path, rule: InstallRule, limits: list[WalkLimit]) -> Iterator[tuple[Path, str]]:
    """(file, path relative to source) that install(DIRECTORY) copies, honouring patterns."""
    excludes = [p for p in rule.patterns if p.exclude]
    includes = [p for p in rule.patterns if not p.exclude]
    top = str(source)
    for root, dirs, files in walk(top, limits=limits):
        relative_root = os.path.relpath(root, top)
        if excludes:
            dirs[:] = [
                d for d in dirs if not any(_matches(p.kind, p.value, d, f"{root}/{d}") for p in excludes)
            ]
        dirs.sort()
        for name in sorted(files):
            full = f"{root}/{name}"
            if excludes and any(_matches(p.kind, p.value, name, full) for p in excludes):
                continue
            if rule.files_matching and not any(_matches(p.kind, p.value, name, full) for p in includes):
                continue
            yield Path(full), name if relative_root == "." else f"{relative_root}/{name}"


def layout_from_cmake(cmake: CMakeModel, package_path: Path, share_name: str) -> InstallLayout:
    layout = InstallLayout(known=not cmake.syntax_errors and not cmake.unreadable)
    for rule in cmake.install_rules:
        _apply_rule(layout, rule)
    if cmake.ament_package_command is not None:
        ament = cmake.ament_package_command
        layout.add(f"share/{share_name}/package.xml", package_path / "package.xml", ament.path, ament.line)
        layout.add(INDEX_MARKER.format(name=share_name), None, ament.path, ament.line)
    return layout


def _apply_rule(layout: InstallLayout, rule: InstallRule) -> None:
    dest_arg: Argument | None = rule.destination_arg
    column = dest_arg.column if dest_arg else None
    installs_files = rule.mode in ("DIRECTORY", "FILES")  # (PROGRAMS go to lib/, TARGETS are built)
    if rule.destination is None:
        layout.unknown.append((rule.path, rule.line, "install() without DESTINATION"))
        if installs_files:
            layout.may_install.append((rule.path, rule.line, None))
        return
    if isinstance(rule.destination, Unknown):
        line = dest_arg.line if dest_arg else rule.line
        layout.unknown.append((rule.path, line, f"DESTINATION depends on {rule.destination.why}"))
        if installs_files:
            layout.may_install.append((rule.path, line, None))
        return
    destination = _normalize_destination(rule.destination)
    known_sources = tuple(s for s, _ in rule.sources if isinstance(s, str))
    layout.destinations.append(
        RuleDestination(
            destination,
            rule.destination,
            known_sources,
            rule.path,
            dest_arg.line if dest_arg else rule.line,
            column,
        )
    )
    if destination is None:
        return
    installed_dirs = []
    for value, arg in rule.sources:
        if isinstance(value, Unknown):
            layout.unknown.append((rule.path, arg.line, f"a source depends on {value.why}"))
            if installs_files and destination is not None:
                layout.may_install.append((rule.path, arg.line, destination))
            continue
        if value.startswith(BINARY_DIR):
            continue  # generated at build time; not in the source tree
        source = Path(os.path.normpath(value if os.path.isabs(value) else rule.base_dir / value))
        if rule.mode == "DIRECTORY":
            if not source.is_dir():
                if not rule.optional:
                    layout.missing.append(MissingSource(value, rule.mode, rule.path, arg.line, arg.column))
                continue
            into = destination if value.endswith("/") else posixpath.join(destination, source.name)
            # as written: a trailing slash (contents, not the folder) matters to the fix hints
            installed_dirs.append(source.name if not value.endswith("/") else value.rstrip("/") + "/")
            for full, relative in _directory_files(source, rule, layout.walk_limits):
                layout.add(posixpath.normpath(posixpath.join(into, relative)), full, rule.path, rule.line)
        else:
            if not source.is_file():
                if not rule.optional:
                    layout.missing.append(MissingSource(value, rule.mode, rule.path, arg.line, arg.column))
                continue
            name = rule.rename or source.name
            layout.add(posixpath.normpath(posixpath.join(destination, name)), source, rule.path, rule.line)
    if installed_dirs:
        layout.directory_rules.append((rule.path, rule.line, tuple(installed_dirs), destination))


def layout_from_setup_py(setup_py: SetupPyModel, package_path: Path) -> InstallLayout:
    layout = InstallLayout(known=setup_py.syntax_error is None and setup_py.has_setup_call)
    path = setup_py.source.path
    for line, why in setup_py.unknown:
        layout.unknown.append((path, line, why))
        layout.may_install.append((path, line, None))  # data_files: anywhere under the prefix
    _add_python_modules(layout, setup_py, package_path)
    for entry in setup_py.entries:
        path = entry.path or setup_py.source.path
        destination = _normalize_destination(entry.destination)
        layout.destinations.append(
            RuleDestination(destination, entry.destination, entry.files, path, entry.line, None)
        )
        if destination is None:
            continue
        folders = set()
        for relative in entry.files:
            source = Path(os.path.normpath(package_path / relative))
            if not source.is_file():
                # setuptools fails on a listed folder or a missing file alike
                layout.missing.append(MissingSource(relative, "data_files", path, entry.line, None))
                continue
            folders.add(Path(relative).parts[0] if len(Path(relative).parts) > 1 else "")
            layout.add(posixpath.join(destination, source.name), source, path, entry.line)
        top = tuple(sorted(f for f in folders if f))
        if top:
            layout.directory_rules.append((path, entry.line, top, destination))
    return layout


def _add_python_modules(layout: InstallLayout, setup_py: SetupPyModel, package_path: Path) -> None:
    """The .py files of setup()'s packages and py_modules, where setuptools installs them
    (lib/pythonX.Y/site-packages: one folder for any version here), so that a launch file of the
    workspace imports them from the tree as from a sourced install."""
    line = setup_py.packages_line
    for dotted in setup_py.python_packages:
        installed = dotted.replace(".", "/")
        folder = package_path / package_folder(dotted, setup_py.package_dir)  # (package_dir: elsewhere)
        try:
            names = sorted(e.name for e in os.scandir(folder) if e.name.endswith(".py"))
        except OSError:
            continue
        for name in names:
            source = folder / name
            if source.is_file():
                layout.add(f"{PYTHON_SITE}/{installed}/{name}", source, setup_py.source.path, line)
    for module in setup_py.py_modules:
        package, _, last = module.rpartition(".")  # (a.b: a/b.py, as setuptools installs it)
        where = package_folder(package, setup_py.package_dir) if package else setup_py.package_dir.get("", "")
        source = package_path / where / f"{last}.py"
        if source.is_file():
            layout.add(f"{PYTHON_SITE}/{module.replace('.', '/')}.py", source, setup_py.source.path, line)
    for installed, relative in setup_py.package_data:
        layout.add(f"{PYTHON_SITE}/{installed}", package_path / relative, setup_py.source.path, line)
