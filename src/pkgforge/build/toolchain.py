"""The ament_cmake toolchain a build uses: a sourced ROS 2, or the PyPI wheels.

Nothing here requires the virtual environment to be activated: the
environment handed to colcon is built from this interpreter's own prefix.
"""

from __future__ import annotations

import glob
import os
import shutil
import sys
import sysconfig
from dataclasses import dataclass
from pathlib import Path

from pkgforge.errors import PkgforgeError

AMENT_CMAKE_CONFIG = Path("share/ament_cmake/cmake/ament_cmakeConfig.cmake")


@dataclass(frozen=True)
class Toolchain:
    origin: str  # "ros": a sourced distro; "wheels": pkgforge[ament] in this environment
    prefixes: tuple[Path, ...]  # CMake prefixes that provide ament_cmake and friends
    scripts_dir: Path  # this interpreter's bin/, for python3, xacro, cmake, ninja

    def environment(self, base: dict[str, str] | None = None) -> dict[str, str]:
        env = dict(os.environ if base is None else base)
        env["PATH"] = prepend_path(str(self.scripts_dir), env.get("PATH", ""))
        if self.origin == "wheels":
            for prefix in self.prefixes:
                env["CMAKE_PREFIX_PATH"] = prepend_path(str(prefix), env.get("CMAKE_PREFIX_PATH", ""))
        # colcon's default console output suits people and CI logs alike
        env.setdefault("PYTHONUNBUFFERED", "1")
        return env

    def cmake_generator_args(self, env: dict[str, str]) -> list[str]:
        """Ninja when make is missing (a machine without build-essential)."""
        if shutil.which("make", path=env["PATH"]) is None and shutil.which("ninja", path=env["PATH"]):
            return ["-G", "Ninja"]
        return []

    def find_cmake_config(self, name: str, env: dict[str, str]) -> bool:
        """Whether find_package(<name>) would find a config file in the prefixes."""
        for prefix in filter(None, env.get("CMAKE_PREFIX_PATH", "").split(os.pathsep)):
            for folder in (Path(prefix) / "share" / name / "cmake", Path(prefix) / "lib" / "cmake" / name):
                if (folder / f"{name}Config.cmake").exists() or (folder / f"{name}-config.cmake").exists():
                    return True
        return False


def prepend_path(entry: str, value: str) -> str:
    """entry first in an os.pathsep list, without duplicates or empty parts."""
    parts = [p for p in value.split(os.pathsep) if p and p != entry]
    return os.pathsep.join([entry, *parts])


# an install tree's Python folders (python_paths of its prefixes), for a launch worker forked
# after its own start, whose sys.path PYTHONPATH no longer changes (sandbox/worker.py)
TREE_PYTHONPATH = "PKGFORGE_TREE_PYTHONPATH"


def python_paths(prefix: str) -> list[str]:
    """The folders of a prefix (a ROS distro, an install tree) that hold Python packages (any
    Python version): what sourcing its setup script puts on PYTHONPATH."""
    patterns = (
        "lib/python3*/site-packages",
        "lib/python3*/dist-packages",
        "local/lib/python3*/dist-packages",
        "local/lib/python3*/site-packages",
        "lib/python3/dist-packages",
    )
    found: list[str] = []
    for pattern in patterns:
        for folder in sorted(glob.glob(os.path.join(prefix, pattern))):
            if folder not in found:
                found.append(folder)
    return found


def detect() -> Toolchain:
    scripts = Path(sysconfig.get_path("scripts"))
    for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
        if (Path(prefix) / AMENT_CMAKE_CONFIG).exists():
            return Toolchain("ros", (Path(prefix),), scripts)
    own = Path(sys.prefix)
    if (own / AMENT_CMAKE_CONFIG).exists():
        return Toolchain("wheels", (own,), scripts)
    raise PkgforgeError(
        "no ament_cmake found: install it with `pip install 'ros-pkgforge[ament]'` "
        "(ROS-free wheels) or source a ROS 2 distro (`source /opt/ros/<distro>/setup.bash`)"
    )


def require_cmake(env: dict[str, str]) -> None:
    if shutil.which("cmake", path=env["PATH"]) is None:
        raise PkgforgeError(
            "cmake not found: `pip install 'ros-pkgforge[ament]'` brings it, or `apt-get install cmake`"
        )
