"""launch_ros.substitutions: FindPackage*, ExecutableInPackage, and every package lookup here.

Real: launch_ros/substitutions/find_package.py, executable_in_package.py. A package not
found here is recorded and stands in as an empty one, unless the launch file catches the
failure (a try around the lookup: probing for an optional package).
"""

from __future__ import annotations

import os
import sys
from types import FrameType

from pkgforge.launch.builtin.launch.errors import PackageNotFoundError
from pkgforge.launch.builtin.launch.execute_process import PREPARING
from pkgforge.launch.builtin.launch.launch_context import MISSING_PACKAGE_ROOT, RECORDER, LaunchContext
from pkgforge.launch.builtin.launch.substitution import (
    SomeSubstitutionsType,
    Substitution,
    normalize,
    perform_substitutions,
)
from pkgforge.launch.place import LAUNCH_FILES, here
from pkgforge.launch.records import PackageLookupRecordDict

# launch_ros substitutions


def lookup_package(
    package: str, via: str, where: object | tuple[str | None, int | None], kind: str = "share"
) -> str:
    """A package's share (or prefix) folder, the lookup recorded. A package not found here is
    recorded as such and stands in as an empty package (a path that exists nowhere), so the
    rest of the file is still evaluated."""
    from ament_index_python.packages import PackageNotFoundError as AmentNotFound
    from ament_index_python.packages import get_package_prefix

    item: PackageLookupRecordDict = {"name": package, "via": via}
    guarded = False
    if isinstance(where, tuple):
        item["file"], item["line"] = where
        guarded = _guarded(*where) or _guarded_on_stack()
        where = None
    known = RECORDER.prefix_cache  # one search of the prefixes per package and file (a file asks ~9 times)
    if package not in known:
        try:
            known[package] = getattr(get_package_prefix, "_pkgforge_real", get_package_prefix)(package)
        except (AmentNotFound, PackageNotFoundError, ValueError) as error:
            known[package] = error
    try:
        found = known[package]
        if isinstance(found, BaseException):
            raise type(found)(*found.args)
        prefix = found
    except (AmentNotFound, PackageNotFoundError, ValueError):
        if guarded:
            raise  # the launch file catches it: probing for an optional package
        RECORDER.add("packages", {**item, "found": False}, where)
        prefix = os.path.join(MISSING_PACKAGE_ROOT, package)
    else:
        RECORDER.add("packages", item, where)
    return prefix if kind == "prefix" else os.path.join(prefix, "share", package)


_GUARDS: dict[str, list[tuple[int, int]]] = {}
CATCHING = {"PackageNotFoundError", "KeyError", "LookupError", "Exception", "BaseException"}


def _guarded_on_stack() -> bool:
    """Whether any launch file's frame on the stack stands inside a try that catches a failed
    lookup: a helper (`def share_of(p): return get_package_share_directory(p)`) called inside the
    try of its caller raises to that try in ROS, as here."""
    frame: FrameType | None = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_filename in LAUNCH_FILES and _guarded(frame.f_code.co_filename, frame.f_lineno):
            return True
        frame = frame.f_back
    return False


def _guarded(file: str | None, line: int | None) -> bool:
    """Whether the launch file's line is inside a try whose handlers catch a failed lookup."""
    import ast

    if file is None or line is None:
        return False
    if file not in _GUARDS:
        spans: list[tuple[int, int]] = []
        tree: ast.Module | None
        try:
            with open(file, encoding="utf-8") as handle:
                tree = ast.parse(handle.read())
        except (OSError, SyntaxError, ValueError):
            tree = None
        for node in ast.walk(tree) if tree is not None else []:
            if isinstance(node, ast.Try) and node.body:
                names: set[str] = set()
                for handler in node.handlers:
                    if handler.type is None:
                        names.add("BaseException")
                    for part in ast.walk(handler.type) if handler.type is not None else []:
                        if isinstance(part, (ast.Name, ast.Attribute)):
                            names.add(part.id if isinstance(part, ast.Name) else part.attr)
                if names & CATCHING:
                    spans.append((node.body[0].lineno, node.body[-1].end_lineno or node.body[-1].lineno))
        _GUARDS[file] = spans
    return any(start <= line <= end for start, end in _GUARDS[file])


class FindPackage(Substitution):
    _performing = False

    def __init__(self, package: SomeSubstitutionsType) -> None:
        super().__init__()
        self.package = normalize(package)

    def perform(self, context: LaunchContext) -> str:
        self._performing = True
        try:
            return self.find(perform_substitutions(context, self.package))
        finally:
            self._performing = False

    def find(self, package_name: str) -> str:
        raise NotImplementedError()

    def _place_of_lookup(self) -> FindPackage | tuple[str | None, int | None]:
        # performed: the object's place; called directly by the launch file: that call's place
        return self if self._performing else here()


class FindPackagePrefix(FindPackage):
    def find(self, package_name: str) -> str:
        return lookup_package(package_name, "FindPackagePrefix", self._place_of_lookup(), "prefix")


class FindPackageShare(FindPackage):
    def find(self, package_name: str) -> str:
        return lookup_package(package_name, "FindPackageShare", self._place_of_lookup())


class ExecutableInPackage(Substitution):
    def __init__(self, executable: SomeSubstitutionsType, package: SomeSubstitutionsType) -> None:
        super().__init__()
        self.executable, self.package = normalize(executable), normalize(package)

    def perform(self, context: LaunchContext) -> str:
        return executable_in_package(
            self,
            perform_substitutions(context, self.executable),
            perform_substitutions(context, self.package),
        )


def executable_in_package(owner: object, executable: str, package: str) -> str:
    """`ExecutableInPackage.perform` of both engines: the package's prefix looked up (recorded; a
    package not found here stands in as an empty one) and the executable in its lib/<package>
    folder, found there or not. launch_ros refuses an executable that is not there; verify does
    not: a predicted install tree holds no build products, so an executable missing from it says
    nothing about the real install (the package's build installs it)."""
    import shutil

    if PREPARING[0]:  # the node's own package, looked up and recorded by its visit already
        prefix = _quiet_prefix(package)
    else:
        prefix = lookup_package(package, "ExecutableInPackage", owner, "prefix")
    libexec = os.path.join(prefix, "lib", package)
    found = shutil.which(executable, path=libexec) if os.path.isdir(libexec) else None
    return found or os.path.join(libexec, executable)


def _quiet_prefix(package: str) -> str:
    """A package's prefix as lookup_package finds it (its stand-in when not found), unrecorded."""
    from ament_index_python.packages import PackageNotFoundError as AmentNotFound
    from ament_index_python.packages import get_package_prefix

    known = RECORDER.prefix_cache
    if package not in known:
        try:
            known[package] = getattr(get_package_prefix, "_pkgforge_real", get_package_prefix)(package)
        except (AmentNotFound, PackageNotFoundError, ValueError) as error:
            known[package] = error
    found = known[package]
    return os.path.join(MISSING_PACKAGE_ROOT, package) if isinstance(found, BaseException) else found
