"""`verify --build`: a package colcon could not build."""

from __future__ import annotations

import re
from pathlib import Path

from pkgforge.checks.facts import FileFacts
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding

TAIL_LINES = 15
CMAKE_ERROR = re.compile(r"CMake Error at (.+?):(\d+)")
PYTHON_FRAME = re.compile(r'File "(.+?)", line (\d+)')
# where the log's story starts: the first error, else its last lines are shown
ERROR_LINE = re.compile(
    r"CMake Error|Traceback \(most recent call last\)|\berror:|^error\b|Error:", re.IGNORECASE
)


# verify/pipeline.py reports it from the build's outcome (no check function reads a context)
register(
    "PF902",
    "build-failed",
    "error",
    area="run",
    bad=("# CMakeLists.txt\nfind_package(ament_cmake REQUIRED)\nadd_subdirectory(missing)  # CMake Error"),
    good=("# CMakeLists.txt\nfind_package(ament_cmake REQUIRED)"),
    summary="colcon could not build the package (`verify --build`)",
    explanation="Nothing it would install exists, so its launch files, models and RViz configs "
    "were not checked against a built tree; every check that needs no tree still ran.",
    hint="fix the error in the log tail (the whole log is at the path named), or run `pkgforge verify` "
    "without --build to check the rest against the tree predicted from the install rules",
)(None)


def build_failed_finding(
    package_path: Path,
    build_type: str,
    log: Path | None,
    tail: str,
    status: int | None = None,
    dependency: str | None = None,
    *,
    files: FileFacts,
) -> Finding:
    """The failure at the first CMake or Python error in the package's own files, else at its
    build file; the message ends with the last lines of colcon's log. `files`: what exists, read
    by the verify pipeline (a check touches no file itself)."""
    from pkgforge.build.colcon import HINT_SEPARATOR, SETUP_PY_UNREADABLE

    if tail.startswith(SETUP_PY_UNREADABLE):  # colcon could not run setup.py: one located line
        place, _, said = tail.removeprefix(SETUP_PY_UNREADABLE).partition(": ")
        file, _, number = place.rpartition(":") if place.rpartition(":")[2].isdigit() else (place, "", "")
        message, _, hint = said.partition(HINT_SEPARATOR)
        return Finding(message, Path(file), int(number) if number else None, hint=hint or None)
    lines = [line for line in tail.splitlines() if line.strip()]
    first_error = next((i for i, line in enumerate(lines) if ERROR_LINE.search(line)), None)
    lines = lines[first_error : first_error + TAIL_LINES] if first_error is not None else lines[-TAIL_LINES:]
    where: tuple[Path, int | None] | None = None if dependency else _located(files, package_path, tail)
    if where is None:
        name = "setup.py" if build_type == "ament_python" else "CMakeLists.txt"
        where = (
            package_path / name if files.is_file(package_path / name) else package_path / "package.xml",
            None,
        )
    if log is None:
        head = f"colcon build stopped (status {status}) before building it"
    elif dependency:
        head = f"colcon build failed on {dependency}, which it needs; from {dependency}'s log {log}:"
    else:
        head = f"colcon build failed; from its log {log}:"
    return Finding("\n".join([head, *("  " + line for line in lines)]), *where)


def _located(files: FileFacts, package_path: Path, tail: str) -> tuple[Path, int] | None:
    for pattern in (CMAKE_ERROR, PYTHON_FRAME):
        for match in pattern.finditer(tail):
            path = Path(match.group(1).strip())
            if not path.is_absolute():
                path = package_path / path
            real = files.real(path)
            if real is None or not real.is_relative_to(package_path):
                continue
            path = real
            if files.is_file(path):
                return path, int(match.group(2))
    return None
