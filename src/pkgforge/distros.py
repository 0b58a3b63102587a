"""What differs between the ROS 2 distributions pkgforge writes packages for."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Distro:
    name: str
    # launch_ros gained the `type` attribute of <param> in the XML/YAML
    # frontends after Humble; Humble rejects nothing but ignores it, so we only
    # write it where it is understood.
    frontend_param_type: bool
    docker_image: str


DISTROS: dict[str, Distro] = {
    d.name: d
    for d in (
        Distro("humble", frontend_param_type=False, docker_image="ros:humble"),
        Distro("jazzy", frontend_param_type=True, docker_image="ros:jazzy"),
        Distro("kilted", frontend_param_type=True, docker_image="ros:kilted"),
        Distro("rolling", frontend_param_type=True, docker_image="ros:rolling"),
    )
}

DEFAULT_DISTRO = "jazzy"
