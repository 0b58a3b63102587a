"""What differs between the ROS 2 distributions pkgforge writes packages for."""

from __future__ import annotations

import os
from dataclasses import dataclass


@dataclass(frozen=True)
class Distro:
    name: str
    # launch_ros gained the `type` attribute of <param> in the XML/YAML
    # frontends after Humble; Humble rejects nothing but ignores it, so we only
    # write it where it is understood.
    frontend_param_type: bool
    docker_image: str
    lts: bool
    ubuntu: str  # the Ubuntu release of its ros:<distro> image
    # launch's XML/YAML frontends read a node's on_exit="shutdown" after Humble (Humble refuses
    # the attribute: "Unexpected attribute(s) found in `node`")
    frontend_on_exit: bool = True


# every active ROS 2 distro, oldest first (the released packages of each: distro_data)
DISTROS: dict[str, Distro] = {
    d.name: d
    for d in (
        Distro(
            "humble",
            frontend_param_type=False,
            docker_image="ros:humble",
            lts=True,
            ubuntu="22.04 jammy",
            frontend_on_exit=False,
        ),
        Distro("jazzy", frontend_param_type=True, docker_image="ros:jazzy", lts=True, ubuntu="24.04 noble"),
        Distro(
            "kilted", frontend_param_type=True, docker_image="ros:kilted", lts=False, ubuntu="24.04 noble"
        ),
        Distro(
            "lyrical", frontend_param_type=True, docker_image="ros:lyrical", lts=True, ubuntu="26.04 resolute"
        ),
        Distro(
            "rolling",
            frontend_param_type=True,
            docker_image="ros:rolling",
            lts=False,
            ubuntu="26.04 resolute",
        ),
    )
}

# the newest long-term-support release
NEWEST_LTS = [d.name for d in DISTROS.values() if d.lts][-1]
DEFAULT_DISTRO = NEWEST_LTS


def default_distro() -> str:
    """ROS_DISTRO when it names an active distro (a sourced ROS), else the newest LTS."""
    environment = os.environ.get("ROS_DISTRO", "")
    return environment if environment in DISTROS else NEWEST_LTS
