"""What Gazebo and ros2_control offer on each ROS 2 distro, read from data/simulation.json.

scripts/update-sim-data writes that file from the sources (gz-sim's ign-gazebo6, gz-sim8, gz-sim9
and gz-sim10 branches; gazebo_ros_pkgs' ros2 branch (and noetic-devel: ROS 1's plugins); gz_ros2_control's humble and jazzy branches;
ros2_control's and ros2_controllers' humble, jazzy, kilted and master branches), naming each
branch's commit. The checks in checks/simulation.py ask the questions below.
"""

from __future__ import annotations

import functools
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

DATA_FILE = Path(__file__).parent / "data" / "simulation.json"

# Gazebo Classic plugins a gz-sim system replaces (gz-sim's systems, by the Classic library's name)
CLASSIC_REPLACEMENTS = {
    "libgazebo_ros_diff_drive.so": "gz-sim-diff-drive-system",
    "libgazebo_ros_joint_state_publisher.so": "gz-sim-joint-state-publisher-system",
    "libgazebo_ros_planar_move.so": "gz-sim-velocity-control-system",
    "libgazebo_ros_p3d.so": "gz-sim-odometry-publisher-system",
    "libgazebo_ros_imu_sensor.so": "gz-sim-imu-system",
    "libgazebo_ros_ray_sensor.so": "gz-sim-sensors-system",
    "libgazebo_ros_camera.so": "gz-sim-sensors-system",
    "libgazebo_ros_gps_sensor.so": "gz-sim-navsat-system",
    "libgazebo_ros_ft_sensor.so": "gz-sim-forcetorque-system",
    "libgazebo_ros_bumper.so": "gz-sim-contact-system",
    "libgazebo_ros_ackermann_drive.so": "gz-sim-ackermann-steering-system",
    "libgazebo_ros_joint_pose_trajectory.so": "gz-sim-joint-position-controller-system",
    "libgazebo_ros2_control.so": "gz_ros2_control-system",
}
# ROS 1's Classic plugins that ROS 2's gazebo_plugins ships under another name (the ROS 2 port
# of gazebo_ros_pkgs merged the laser plugins into ray_sensor, the cameras into camera, ...)
ROS1_CLASSIC_RENAMED = {
    "libgazebo_ros_control.so": "libgazebo_ros2_control.so",
    "libgazebo_ros_laser.so": "libgazebo_ros_ray_sensor.so",
    "libgazebo_ros_gpu_laser.so": "libgazebo_ros_ray_sensor.so",
    "libgazebo_ros_block_laser.so": "libgazebo_ros_ray_sensor.so",
    "libgazebo_ros_range.so": "libgazebo_ros_ray_sensor.so",
    "libgazebo_ros_imu.so": "libgazebo_ros_imu_sensor.so",
    "libgazebo_ros_depth_camera.so": "libgazebo_ros_camera.so",
    "libgazebo_ros_openni_kinect.so": "libgazebo_ros_camera.so",
    "libgazebo_ros_multicamera.so": "libgazebo_ros_camera.so",
    "libgazebo_ros_skid_steer_drive.so": "libgazebo_ros_diff_drive.so",
}
# the Classic ros2_control plugin (ros-controls/gazebo_ros2_control, released for Humble only)
CLASSIC_CONTROL = "libgazebo_ros2_control.so"
# the hardware plugins of the Gazebo ros2_control integrations, by the package that ships them
GAZEBO_HARDWARE = {
    "gz_ros2_control": "gz_ros2_control/GazeboSimSystem",
    "ign_ros2_control": "ign_ros2_control/IgnitionSystem",
    "gazebo_ros2_control": "gazebo_ros2_control/GazeboSystem",
}
# the joint interfaces gz_ros2_control's and gazebo_ros2_control's systems export (gz_system.cpp)
GAZEBO_INTERFACES = ("position", "velocity", "effort")
# a gz-sim system's library name: [lib](gz-sim|ignition-gazebo)[N]-<system>-system[.so]
GZ_SYSTEM = re.compile(r"^(?:lib)?(gz-sim|ignition-gazebo)(\d*)-(.+)-system(?:\.so)?$")
GZ_CONTROL = re.compile(r"^(?:lib)?(gz|ign)_ros2_control-system(?:\.so)?$")


def gz_names(distro: str) -> dict[str, str]:
    """The names the distro's Gazebo and its ros2_control plugin answer to (Humble: Fortress
    and ign_ros2_control, gz_ros2_control's humble branch; later: gz-sim and gz_ros2_control;
    the bridge's message names: ros_gz's humble README ignition.msgs, jazzy gz.msgs). What
    `new --sim gz` writes, what `migrate --gazebo` converts Gazebo Classic to, and the resource
    variable PF422 (and its fix) names."""
    if distro == "humble":
        return {
            "system": "ignition-gazebo",
            "control": "ign_ros2_control",
            "plugin": "ign_ros2_control-system",
            "plugin_name": "ign_ros2_control::IgnitionROS2ControlPlugin",
            "hardware": "ign_ros2_control/IgnitionSystem",
            "msgs": "ignition.msgs",
            "namespace": "ignition::gazebo",
            "resource": "IGN_GAZEBO_RESOURCE_PATH",
        }
    return {
        "system": "gz-sim",
        "control": "gz_ros2_control",
        "plugin": "gz_ros2_control-system",
        "plugin_name": "gz_ros2_control::GazeboSimROS2ControlPlugin",
        "hardware": "gz_ros2_control/GazeboSimSystem",
        "msgs": "gz.msgs",
        "namespace": "gz::sim",
        "resource": "GZ_SIM_RESOURCE_PATH",
    }


@functools.lru_cache(maxsize=1)
def data() -> dict[str, Any]:
    loaded: dict[str, Any] = json.loads(DATA_FILE.read_text(encoding="utf-8"))
    return loaded


def gazebo_of(distro: str) -> str | None:
    """The Gazebo release the distro's ros_gz is built against (fortress, harmonic, ...)."""
    found: str | None = data()["distro_gazebo"].get(distro)
    return found


def gazebo_branch(gazebo: str) -> str:
    branch: str = data()["gazebo"][gazebo]["branch"]
    return branch


@dataclass(frozen=True)
class PluginVerdict:
    """Why a plugin library does not load on a distro, and what does."""

    reason: str
    replacement: str | None


def plugin_verdict(filename: str, distro: str, released: frozenset[str]) -> PluginVerdict | None:
    """None when the distro's simulator ships `filename` (or it is none of the libraries pkgforge
    knows: a package's own plugin), else why not. `released`: the distro's released packages."""
    name = filename.rsplit("/", 1)[-1]
    classic = set(data()["classic"]["libraries"]) | {CLASSIC_CONTROL}
    if name in classic or f"lib{name}.so" in classic:
        package = "gazebo_ros2_control" if CLASSIC_CONTROL in (name, f"lib{name}.so") else "gazebo_plugins"
        if package in released:
            return None
        library = name if name.endswith(".so") else f"lib{name}.so"
        return PluginVerdict(
            f"Gazebo Classic's {name} ({package}) is not released for {distro}",
            CLASSIC_REPLACEMENTS.get(library),
        )
    ros1 = _ros1_verdict(name, distro, released, classic)
    if ros1 is not None:
        return ros1
    control = GZ_CONTROL.match(name)
    if control:
        package = f"{control.group(1)}_ros2_control"
        if package in released:
            return None
        other = "gz_ros2_control" if package == "ign_ros2_control" else "ign_ros2_control"
        return PluginVerdict(
            f"{package} is not released for {distro}",
            f"{other}-system" if other in released else None,
        )
    return _system_verdict(name, distro)


def _ros1_verdict(
    name: str, distro: str, released: frozenset[str], classic: set[str]
) -> PluginVerdict | None:
    """ROS 1's Classic plugins (gazebo_ros_pkgs' noetic-devel) that no ROS 2 gazebo_plugins ships
    by that name: libgazebo_ros_control.so and the laser plugins load in no Gazebo of any ROS 2
    distro. The replacement: the ROS 2 Classic name where the distro releases Classic, else gz's."""
    library = name if name.endswith(".so") else f"lib{name}.so"
    if library in classic or library not in data()["ros1_classic"]["libraries"]:
        return None
    renamed = ROS1_CLASSIC_RENAMED.get(library)
    on_classic = (
        renamed is not None
        and ("gazebo_ros2_control" if renamed == CLASSIC_CONTROL else "gazebo_plugins") in released
    )
    return PluginVerdict(
        f"{library} is ROS 1's Gazebo Classic plugin (gazebo_ros_pkgs' noetic-devel): no ROS 2 distro ships it",
        renamed if on_classic else CLASSIC_REPLACEMENTS.get(renamed or library),
    )


def _system_verdict(name: str, distro: str) -> PluginVerdict | None:
    system = GZ_SYSTEM.match(name)
    gazebo = gazebo_of(distro)
    if system is None or gazebo is None:
        return None
    prefix, version, short = system.groups()
    facts = data()["gazebo"][gazebo]
    title = gazebo.capitalize()
    if prefix not in facts["prefixes"]:
        return PluginVerdict(
            f"Gazebo {title} ({facts['branch']}) loads no '{prefix}-' library", f"gz-sim-{short}-system"
        )
    if version and version != facts["branch"].rsplit("sim", 1)[-1].rsplit("gazebo", 1)[-1]:
        return PluginVerdict(
            f"Gazebo {title} ({facts['branch']}) installs no version {version} of it",
            f"{facts['prefixes'][0]}-{short}-system",
        )
    if short not in facts["systems"]:
        return PluginVerdict(f"Gazebo {title} ({facts['branch']}) has no '{short}' system", None)
    return None


def controller_types(distro: str) -> dict[str, dict[str, Any]]:
    """ros2_controllers' controller types on the distro's branch: type → {package, joints}."""
    types: dict[str, dict[str, Any]] = data()["controllers"][distro]["types"]
    return types


def controller_packages() -> frozenset[str]:
    """Every package ros2_controllers ships a controller from (on some branch), by type prefix."""
    return frozenset(t.split("/", 1)[0] for d in data()["controllers"].values() for t in d["types"])


def controllers_branch(distro: str) -> str:
    branch: str = data()["controllers"][distro]["branch"]
    return branch
