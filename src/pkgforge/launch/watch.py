"""What a launch file reads and runs, watched for both engines: xacro, ament_index, packages not found.

Audit hooks and wrappers installed once per worker: a read under a package not found here is
recorded (what fails after it is that lookup's consequence), xacro reads are the model's own,
and ament_index's lookups go through the built-in engine's lookup_package (recorded).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from typing import Any

from pkgforge.launch.builtin.launch.command import running_xacro
from pkgforge.launch.builtin.launch.launch_context import MISSING_PACKAGE_ROOT, RECORDER
from pkgforge.launch.builtin.launch_ros.substitutions import lookup_package
from pkgforge.launch.place import LAUNCH_FILES, here

# what reading a file (or a folder) is to Python's audit hooks
READ_EVENTS = frozenset({"open", "os.listdir", "os.scandir", "glob.glob"})
_READS_WATCHED: list[bool] = []


def watch_stand_in_reads() -> None:
    """Note every path the launch file opens or lists in a package's stand-in (not found here) or
    phantom share folder (declared, not installed here): an audit hook, once per process (a hook
    cannot be removed; it notes into the recorder of the file being evaluated)."""
    if _READS_WATCHED:
        return
    _READS_WATCHED.append(True)
    roots = [MISSING_PACKAGE_ROOT + os.sep]
    phantom = os.environ.get("PKGFORGE_PHANTOM_PREFIX")
    if phantom:
        roots.append(os.path.join(phantom, "share") + os.sep)
    prefixes = tuple(roots)
    index = tuple(os.path.join(root, "ament_index") + os.sep for root in roots)

    def note(event: str, args: tuple[Any, ...]) -> None:
        if event not in READ_EVENTS or not args or not isinstance(args[0], str):
            return
        # (the package lookups' own reads of the ament index are not the file's)
        if args[0].startswith(prefixes) and not args[0].startswith(index):
            RECORDER.stand_in_reads.append(args[0])

    sys.addaudithook(note)


def watch_xacro() -> None:
    """Record models a Python launch file processes with the xacro module itself (seed 000's style)."""
    import xacro

    if getattr(xacro, "_pkgforge_watched", False):
        return
    real_parse, real_process_file = xacro.parse, xacro.process_file

    def note(path: object, via: str, mappings: object = None) -> None:
        # only a call from the launch file itself: xacro calls parse() for every include too
        caller = sys._getframe(2).f_code.co_filename
        if caller not in LAUNCH_FILES:
            return
        if isinstance(path, os.PathLike):  # xacro opens a pathlib.Path as it opens a str
            path = os.fspath(path)
        if not running_xacro() and isinstance(path, str) and os.path.isabs(path):
            file, line = here()
            # the xacro arguments it gives (andino's spawn_robot: use_gazebo_ros_control), so the
            # model is checked as the file processes it, not failing for want of them
            given = (
                {str(k): str(v) for k, v in mappings.items() if isinstance(v, (str, int, float, bool))}
                if isinstance(mappings, dict)
                else {}
            )
            RECORDER.add(
                "commands",
                {
                    "command": ["xacro", path, *(f"{k}:={v}" for k, v in sorted(given.items()))],
                    "ok": True,
                    "message": "",
                    "model": path,
                    "mappings": given,
                    "via": via,
                    "file": file,
                    "line": line,
                },
            )
            RECORDER.add("packages", {"name": "xacro", "via": via, "file": file, "line": line})

    def parse(inp: Any, filename: str | None = None, **kwargs: Any) -> Any:
        note(filename or getattr(inp, "name", None), "xacro.parse")
        return real_parse(inp, filename, **kwargs)

    def process_file(input_file_name: str, **kwargs: Any) -> Any:
        note(input_file_name, "xacro.process_file", kwargs.get("mappings"))
        return real_process_file(input_file_name, **kwargs)

    xacro._pkgforge_real_process_file = real_process_file  # Command(['xacro', ...]) records itself
    xacro.parse, xacro.process_file = parse, process_file
    xacro._pkgforge_watched = True


def watch_ament() -> None:
    """A launch file's own ament_index lookups are recorded; a package not found here is
    reported and stands in as an empty package, so the rest of the file is still checked
    (lookups by xacro or by the launch API itself are left alone)."""
    try:
        import ament_index_python
        import ament_index_python.packages as packages
    except ImportError:
        return
    if getattr(packages, "_pkgforge_watched", False):
        return

    def from_launch_file() -> bool:
        return sys._getframe(2).f_code.co_filename in LAUNCH_FILES

    real_prefix = packages.get_package_prefix
    real_share = packages.get_package_share_directory
    real_share_path: Callable[..., Any] | None = getattr(packages, "get_package_share_path", None)

    def get_package_prefix(package_name: str) -> str:
        if from_launch_file():
            return lookup_package(package_name, "get_package_prefix", here(), "prefix")
        return real_prefix(package_name)

    def get_package_share_directory(package_name: str, *args: Any, **kwargs: Any) -> str:
        if from_launch_file():
            return lookup_package(package_name, "get_package_share_directory", here())
        return real_share(package_name, *args, **kwargs)

    def get_package_share_path(package_name: str, *args: Any, **kwargs: Any) -> Any:
        import pathlib

        if from_launch_file():
            return pathlib.Path(lookup_package(package_name, "get_package_share_path", here()))
        assert real_share_path is not None  # patched in only where the module has it
        return real_share_path(package_name, *args, **kwargs)

    get_package_prefix.__dict__["_pkgforge_real"] = real_prefix  # lookup_package calls it
    patched: dict[str, Callable[..., Any]] = {
        "get_package_prefix": get_package_prefix,
        "get_package_share_directory": get_package_share_directory,
    }
    if real_share_path is not None:
        patched["get_package_share_path"] = get_package_share_path
    for module in (packages, ament_index_python):
        for name, function in patched.items():
            if hasattr(module, name):
                setattr(module, name, function)
    vars(packages)["_pkgforge_watched"] = True
