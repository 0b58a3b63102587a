"""Which launch engine evaluates launch files: the built-in one, or a ROS 2 distro's own libraries.

Parent side: nothing here imports `launch`. `--launch-engine auto` (the default) takes the
real libraries where a distro is installed: `--ros-prefix DIR`, else a sourced environment
(AMENT_PREFIX_PATH or PYTHONPATH holding `launch` and `launch_ros`), else the single
/opt/ros/<distro>; without one, the built-in engine. `--launch-engine ros` insists.
"""

from __future__ import annotations

import glob
import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from pkgforge.build.toolchain import python_paths
from pkgforge.errors import PkgforgeError

ENGINE_ENV = "PKGFORGE_LAUNCH_ENGINE"
PREFIX_ENV = "PKGFORGE_ROS_PREFIX"
DISTRO_ENV = "PKGFORGE_ROS_DISTRO"
BUILTIN_DISTRO_ENV = "PKGFORGE_LAUNCH_DISTRO"  # the distro whose API the built-in engine follows (api.py)
CHOICES = ("auto", "ros", "builtin")
# pure-Python modules the real launch imports; Debian's ROS packages put them here
SYSTEM_PYTHON = "/usr/lib/python3/dist-packages"
LAUNCH_REQUIREMENTS = {"lark": "lark", "osrf_pycommon": "osrf-pycommon", "yaml": "PyYAML"}
KNOWN_DISTROS = ("humble", "iron", "jazzy", "kilted", "rolling")


@dataclass(frozen=True)
class LaunchEngine:
    name: Literal["builtin", "ros"] = "builtin"
    prefix: str | None = None  # "" : the sourced PYTHONPATH has the libraries
    distro: str | None = None
    how: str = "built-in"

    def environment(self, env: dict[str, str]) -> dict[str, str]:
        env = dict(env)
        env[ENGINE_ENV] = self.name
        env.pop(PREFIX_ENV, None)
        env.pop(DISTRO_ENV, None)
        if self.name == "builtin" and self.distro:
            env[BUILTIN_DISTRO_ENV] = self.distro
        # what a shell with ROS 2 sourced always has, and launch files read without a default
        # (linorobot2's EnvironmentVariable('ROS_DISTRO')); here ROS may not be sourced at all
        if self.distro:
            env.setdefault("ROS_DISTRO", self.distro)
        env.setdefault("ROS_VERSION", "2")
        env.setdefault("ROS_PYTHON_VERSION", "3")
        if self.name == "ros":
            env[PREFIX_ENV] = self.prefix or ""
            env[DISTRO_ENV] = self.distro or ""
            if self.prefix:
                # the distro's own packages (launch's grammar) before the placeholders of undeclared ones
                parts = [p for p in env.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
                if self.prefix not in parts:
                    phantom = env.get("PKGFORGE_PHANTOM_PREFIX")
                    at = parts.index(phantom) if phantom in parts else len(parts)
                    parts.insert(at, self.prefix)
                env["AMENT_PREFIX_PATH"] = os.pathsep.join(parts)
        return env

    @property
    def label(self) -> str:
        if self.name == "builtin":
            return "built-in" + (f" ({self.distro})" if self.distro else "")
        return f"ROS 2 {self.distro or '(distro unknown)'}" + (f" from {self.prefix}" if self.prefix else "")


BUILTIN = LaunchEngine()  # the distro from PKGFORGE_LAUNCH_DISTRO, else api.DEFAULT_DISTRO


def builtin(target: str | None = None, environ: Mapping[str, str] = os.environ) -> LaunchEngine:
    """The built-in engine held to the target distro's launch API: --distro, else ROS_DISTRO,
    else the default distro (distros.default_distro: the newest LTS)."""
    from pkgforge.model.distros import DISTROS, default_distro

    environment = environ.get("ROS_DISTRO", "")
    distro = target or (environment if environment in DISTROS else default_distro())
    return LaunchEngine("builtin", None, distro, "built-in")


def has_launch(prefix: str) -> bool:
    return any(
        os.path.isfile(os.path.join(folder, "launch", "__init__.py"))
        and os.path.isfile(os.path.join(folder, "launch_ros", "__init__.py"))
        for folder in python_paths(prefix)
    )


def _pythonpath_has_launch(environ: Mapping[str, str]) -> bool:
    for folder in environ.get("PYTHONPATH", "").split(os.pathsep):
        if (
            folder
            and os.path.isfile(os.path.join(folder, "launch", "__init__.py"))
            and os.path.isfile(os.path.join(folder, "launch_ros", "__init__.py"))
        ):
            return True
    return False


def distro_of(prefix: str | None, environ: Mapping[str, str] = os.environ) -> str | None:
    if prefix:
        name = os.path.basename(os.path.normpath(prefix))
        from pkgforge.model.distros import DISTROS

        if name in DISTROS or name in ("humble", "iron", "jazzy", "kilted", "rolling"):
            return name
    return environ.get("ROS_DISTRO") or None


def find_ros(
    ros_prefix: str | None = None, environ: Mapping[str, str] = os.environ
) -> tuple[str | None, str | None, str]:
    """(prefix, distro, how) of the ROS 2 launch libraries to use; prefix None when none found.
    A prefix of "" means: the sourced environment's PYTHONPATH already has them."""
    if ros_prefix:
        return (
            (ros_prefix if has_launch(ros_prefix) else None),
            distro_of(ros_prefix, environ),
            "--ros-prefix",
        )
    for prefix in environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if prefix and has_launch(prefix):
            return prefix, distro_of(prefix, environ), "sourced"
    if _pythonpath_has_launch(environ):
        return "", environ.get("ROS_DISTRO") or None, "sourced"
    candidates = [p for p in sorted(glob.glob("/opt/ros/*")) if has_launch(p)]
    if len(candidates) == 1:
        return candidates[0], distro_of(candidates[0], environ), "/opt/ros"
    return None, None, ("several distros in /opt/ros: choose one with --ros-prefix" if candidates else "none")


def missing_requirements(prefix: str | None) -> list[str]:
    """The PyPI names of what the real launch needs and neither this Python, the prefix nor
    the system's dist-packages has."""
    import importlib.util

    folders = python_paths(prefix) if prefix else []
    folders.append(SYSTEM_PYTHON)
    missing = []
    for module, name in LAUNCH_REQUIREMENTS.items():
        if importlib.util.find_spec(module) is not None:
            continue
        if not any(
            os.path.exists(os.path.join(f, module)) or os.path.exists(os.path.join(f, module + ".py"))
            for f in folders
        ):
            missing.append(name)
    return missing


def choose(
    option: str = "auto",
    ros_prefix: str | os.PathLike[str] | None = None,
    environ: Mapping[str, str] = os.environ,
    distro: str | None = None,
) -> LaunchEngine:
    """The engine for --launch-engine OPTION (--ros-prefix DIR); a clear error when ros cannot be had.
    `distro` (--distro) is the target the built-in engine follows; the real engine is its prefix's."""
    if option not in CHOICES:
        raise PkgforgeError(f"--launch-engine {option!r}: choose auto, ros or builtin")
    fallback = builtin(distro, environ)
    if option == "builtin":
        return fallback
    prefix_text = os.fspath(ros_prefix) if ros_prefix is not None else None
    if prefix_text is not None and not os.path.isdir(prefix_text):
        raise PkgforgeError(f"--ros-prefix {prefix_text}: no such folder")
    prefix, distro, how = find_ros(prefix_text, environ)
    missing = missing_requirements(prefix) if prefix is not None else []
    if missing:
        if option == "auto" and prefix_text is None:
            return fallback
        raise PkgforgeError(
            f"the ROS 2 launch libraries in {prefix or 'PYTHONPATH'} need "
            f"{', '.join(missing)}, which this Python cannot import: "
            f"pip install {' '.join(missing)} (or pkgforge[ros])"
        )
    if prefix is None:
        if prefix_text is not None:
            raise PkgforgeError(
                f"--ros-prefix {prefix_text} holds no ROS 2 launch libraries "
                "(lib/python3.*/site-packages/launch and launch_ros): pass a distro's "
                "install folder, e.g. /opt/ros/jazzy"
            )
        if option == "ros":
            raise PkgforgeError(
                "--launch-engine ros: no ROS 2 distro found (" + how + "); source one, "
                "pass --ros-prefix /opt/ros/<distro>, or use --launch-engine builtin"
            )
        return fallback
    return LaunchEngine("ros", os.path.abspath(prefix) if prefix else "", distro, how)
