"""A ROS-like prefix of the real launch libraries, laid out at test time from ../shared/upstream.

The upstream sources (ros2/launch and ros2/launch_ros, humble and jazzy) sit beside the
project's clone, never in it: this finds them by walking up from the checkout to a folder
that holds `shared/upstream` (or takes $PKGFORGE_UPSTREAM_LAUNCH), and symlinks the four
Python packages into `<tmp>/opt/ros/<distro>/lib/pythonX.Y/site-packages` with the entry
points their setup.py declare (launch_xml and launch_yaml are found through them).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DISTROS = ("humble", "jazzy")
PACKAGES = {  # package → (repository folder, folder holding setup.py, entry points)
    "launch": ("launch", "launch", ""),
    "launch_xml": ("launch", "launch_xml", "[launch.frontend.parser]\nxml = launch_xml:Parser\n"),
    "launch_yaml": ("launch", "launch_yaml", "[launch.frontend.parser]\nyaml = launch_yaml:Parser\n"),
    "launch_ros": (
        "launch_ros",
        "launch_ros",
        "[launch.frontend.launch_extension]\nlaunch_ros = launch_ros\n",
    ),
}


def upstream_root() -> tuple[Path | None, str]:
    """The ros2-launch folder with one subfolder per distro, and how it was found (or why not)."""
    variable = os.environ.get("PKGFORGE_UPSTREAM_LAUNCH")
    if variable:
        path = Path(variable)
        return (
            (path, f"$PKGFORGE_UPSTREAM_LAUNCH={variable}")
            if path.is_dir()
            else (None, f"$PKGFORGE_UPSTREAM_LAUNCH={variable} is not a folder")
        )
    here = Path(__file__).resolve()
    for parent in here.parents:
        candidate = parent / "shared" / "upstream" / "ros2-launch"
        if candidate.is_dir():
            return candidate, str(candidate)
    return None, (
        f"no shared/upstream/ros2-launch above {here.parent} and no $PKGFORGE_UPSTREAM_LAUNCH: "
        "the real launch libraries are not on this machine"
    )


def missing_requirements() -> str | None:
    for module in ("lark", "osrf_pycommon", "yaml", "ament_index_python"):
        try:
            __import__(module)
        except ImportError:
            return f"{module} is not installed (pip install -e '.[test]')"
    return None


def make_prefix(distro: str, base: Path) -> tuple[Path | None, str]:
    """(prefix, reason): <base>/opt/ros/<distro> laid out from upstream, or None and why not."""
    root, how = upstream_root()
    if root is None:
        return None, how
    source = root / distro
    if not source.is_dir():
        return None, f"{source} does not exist"
    problem = missing_requirements()
    if problem:
        return None, problem
    prefix = base / "opt" / "ros" / distro
    site = prefix / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / "site-packages"
    site.mkdir(parents=True, exist_ok=True)
    for package, (repository, project, entry_points) in PACKAGES.items():
        folder = source / repository / project / package
        if not (folder / "__init__.py").is_file():
            return None, f"{folder} has no __init__.py"
        link = site / package
        if not link.exists():
            link.symlink_to(folder, target_is_directory=True)
        info = site / f"{package}-0.0.0.egg-info"
        info.mkdir(exist_ok=True)
        (info / "PKG-INFO").write_text(f"Metadata-Version: 2.1\nName: {package}\nVersion: 0.0.0\n")
        (info / "entry_points.txt").write_text(entry_points)
        (info / "top_level.txt").write_text(package + "\n")
        index = prefix / "share" / "ament_index" / "resource_index" / "packages"
        index.mkdir(parents=True, exist_ok=True)
        (index / package).touch()
        (prefix / "share" / package).mkdir(exist_ok=True)
    grammar = prefix / "share" / "launch" / "frontend"
    grammar.mkdir(parents=True, exist_ok=True)
    for share in (source / "launch" / "launch" / "share" / "launch" / "frontend").iterdir():
        if not (grammar / share.name).exists():
            (grammar / share.name).symlink_to(share)
    return prefix, str(prefix)
