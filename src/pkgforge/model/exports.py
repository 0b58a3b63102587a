"""What a binary install of a core ROS 2 package brings with it.

The data ships in the wheel as data/exports.json, written by scripts/update-exports from the
package.xml files of the core repositories (ament_cmake, ament_lint, rclcpp, rcl, rosidl,
common_interfaces, geometry2, ros2_control, ...) for humble, jazzy and rolling: each package's
run-time exports (<depend>, <build_export_depend>, <buildtool_export_depend>, <exec_depend>).
A package the user declares for the build arrives with the closure of these, so a
find_package() of one of them builds on a clean machine (ament_cmake brings
ament_cmake_python). Packages outside those repositories are not in the table: for them no
closure is known, and nothing is assumed.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Iterable
from pathlib import Path

DATA_FILE = Path(__file__).parent / "data" / "exports.json"
# a distro the table does not have is answered with the newest it has
NEWEST = "rolling"


@functools.cache
def _exports() -> dict[str, dict[str, list[str]]]:
    data: dict[str, dict[str, list[str]]] = json.loads(DATA_FILE.read_text(encoding="utf-8"))["exports"]
    return data


def brought_by(name: str, declared: Iterable[str], distros: Iterable[str]) -> str | None:
    """The declared package whose binary install brings `name` along in every one of `distros`
    (all the table has when none are given), else None."""
    table = _exports()
    targets = [d if d in table else NEWEST for d in distros] or sorted(table)
    candidates = sorted(set(declared))
    for candidate in candidates:
        if all(name in _closure(candidate, distro) for distro in set(targets)):
            return candidate
    return None


@functools.cache
def _closure(package: str, distro: str) -> frozenset[str]:
    """Every package a binary install of `package` brings along in `distro` (itself left out)."""
    exports = _exports()[distro]
    seen: set[str] = set()
    todo = list(exports.get(package, []))
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo.extend(exports.get(name, []))
    return frozenset(seen)
