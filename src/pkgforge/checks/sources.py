"""Where a rule's facts come from: the upstream repository, branch and commit it was read from.

The simulation and control checks (issue 31) judge a package by what a distro's Gazebo,
ros_gz and ros2_control really ship; model/data/simulation.json holds those facts with the
commit of each branch scripts/update-sim-data read. `pkgforge rule` and docs/checks.md show the
sources under each rule, so a reader can check a verdict against the code it came from.
"""

from __future__ import annotations

from collections.abc import Callable

from pkgforge.model.simulation import data


def _short(commit: str) -> str:
    return commit[:10]


def _branches(key: str, title: str, label: dict[str, str] | None = None) -> str:
    """`title` at each branch the data read for `key` (one entry per branch, the distros or
    Gazebo releases that use it named)."""
    users: dict[tuple[str, str], list[str]] = {}
    for name, facts in data()[key].items():
        users.setdefault((facts["branch"], facts["commit"]), []).append((label or {}).get(name, name))
    listed = ", ".join(
        f"{branch}@{_short(commit)} ({', '.join(names)})" for (branch, commit), names in users.items()
    )
    return f"{title}: {listed}"


def _gz_sim() -> str:
    releases = {name: name.capitalize() for name in data()["gazebo"]}
    return _branches("gazebo", "gazebosim/gz-sim (gz_add_system names, SystemLoader's prefixes)", releases)


def _classic() -> str:
    classic, ros1 = data()["classic"], data()["ros1_classic"]
    return (
        f"ros-simulation/gazebo_ros_pkgs: {classic['branch']}@{_short(classic['commit'])} (Gazebo "
        f"Classic's plugins), {ros1['branch']}@{_short(ros1['commit'])} (ROS 1's)"
    )


def _gz_ros2_control() -> str:
    return _branches(
        "gz_ros2_control", "ros-controls/gz_ros2_control (the plugins, gz_system.cpp's interfaces)"
    )


def _ros2_control(what: str) -> str:
    return _branches("control", f"ros-controls/ros2_control ({what})")


def _ros2_controllers() -> str:
    return _branches("controllers", "ros-controls/ros2_controllers (each controller's type and parameters)")


ROS_GZ = "gazebosim/ros_gz: humble and jazzy branches, ros_gz_sim/launch/gz_sim.launch.py.in"
SDFORMAT = "gazebosim/sdformat (the <sdf version> root, versions 1.0 to 1.12) read through tinyxml2"
GZ_COMMON = "gazebosim/gz-common (SystemPaths: model:// on the resource path, file:// and relative URIs)"
MUJOCO = "google-deepmind/mujoco (PyPI mujoco, its URDF importer and mj_step)"
RCL = "ros2/rcl: rcl_yaml_param_parser (what every distro's nodes read a parameters file with)"

# code → what the rule's facts are read from (functions: the data file names the commits)
SOURCES: dict[str, Callable[[], tuple[str, ...]]] = {
    "PF420": lambda: (SDFORMAT,),
    "PF421": lambda: (GZ_COMMON, ROS_GZ),
    "PF422": lambda: (ROS_GZ, GZ_COMMON),
    "PF611": lambda: ("gazebosim/gz-physics#851 (DART refuses a moment below 1e-15)", MUJOCO),
    "PF612": lambda: (MUJOCO,),
    "PF613": lambda: (MUJOCO,),
    "PF614": lambda: (MUJOCO,),
    "PF701": lambda: (_gz_sim(), _classic(), _gz_ros2_control()),
    "PF702": lambda: (_ros2_control("hardware_interface's component_parser"),),
    "PF703": lambda: (_gz_ros2_control(),),
    "PF704": lambda: (_gz_ros2_control(), "ros/rosdistro (each distro's released packages)"),
    "PF705": lambda: (RCL,),
    "PF706": lambda: (_ros2_controllers(),),
    "PF707": lambda: (_ros2_controllers(),),
    "PF708": lambda: (_ros2_control("controller_manager's spawner"),),
    "PF709": lambda: (_ros2_control("controller_manager.cpp: the description parameter or topic"),),
}


def sources(code: str) -> tuple[str, ...]:
    """What the rule `code` is read from; empty for a rule whose facts are pkgforge's own."""
    found = SOURCES.get(code)
    return found() if found is not None else ()
