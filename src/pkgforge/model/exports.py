"""What a binary install of a core ROS 2 package brings with it.

The data ships in the wheel as data/exports.json, written by scripts/update-exports from the
package.xml files of the core repositories (ament_cmake, ament_lint, rclcpp, rcl, rosidl,
common_interfaces, geometry2, ros2_control, ...) and of those robot bringup packages use
(launch_ros, xacro, robot_state_publisher, rviz, ros2_controllers, ros_gz, navigation2, moveit2,
...) for humble, jazzy and rolling: each package's run-time exports (<depend>,
<build_export_depend>, <buildtool_export_depend>, <exec_depend>). A package the user declares
arrives with the closure of these, so a find_package() of one of them builds on a clean machine
(ament_cmake brings ament_cmake_python) and a node of one of them starts (navigation2 brings
nav2_bt_navigator). Packages outside those repositories are not in the table: for them no
closure is known, and nothing is assumed.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Iterable, Mapping
from pathlib import Path

DATA_FILE = Path(__file__).parent / "data" / "exports.json"
# a distro the table does not have is answered with the newest it has
NEWEST = "rolling"


@functools.cache
def _exports() -> dict[str, dict[str, list[str]]]:
    data: dict[str, dict[str, list[str]]] = json.loads(DATA_FILE.read_text(encoding="utf-8"))["exports"]
    return data


def brought_by(
    name: str,
    declared: Iterable[str],
    distros: Iterable[str],
    workspace: Mapping[str, Iterable[str]] | None = None,
) -> str | None:
    """The declared package whose install brings `name` along in every one of `distros` (all the
    table has when none are given), else None. `workspace`: the run-time exports of the
    workspace's own packages (built from source, they bring theirs as a binary does: xarm_api's
    <depend>xarm_sdk</depend>), followed before the table."""
    table = _exports()
    targets = [d if d in table else NEWEST for d in distros] or sorted(table)
    candidates = sorted(set(declared))
    for candidate in candidates:
        if all(name in _closure_with(candidate, distro, workspace) for distro in set(targets)):
            return candidate
    return None


# closures through a workspace's exports, per workspace mapping (kept alive here, so its id stays
# its own): a run asks for the same closures once per package and check
_WORKSPACE_CLOSURES: dict[int, tuple[Mapping[str, Iterable[str]], dict[tuple[str, str], frozenset[str]]]] = {}


def _closure_with(package: str, distro: str, workspace: Mapping[str, Iterable[str]] | None) -> frozenset[str]:
    if not workspace:
        return _closure(package, distro)
    memo = _WORKSPACE_CLOSURES.setdefault(id(workspace), (workspace, {}))[1]
    key = (package, distro)
    if key not in memo:
        memo[key] = _walk_closure(package, distro, workspace)
    return memo[key]


def _walk_closure(package: str, distro: str, workspace: Mapping[str, Iterable[str]]) -> frozenset[str]:
    exports = _exports()[distro]
    seen: set[str] = set()
    todo = list(workspace.get(package, exports.get(package, [])))
    while todo:
        current = todo.pop()
        if current not in seen:
            seen.add(current)
            todo.extend(workspace.get(current, exports.get(current, [])))
    return frozenset(seen)


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
