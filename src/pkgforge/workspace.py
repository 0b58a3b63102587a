"""Finding packages the way colcon does: colcon-core discovery and identification."""

from __future__ import annotations

import logging
import re
import sys
from collections import OrderedDict
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pkgforge.errors import PkgforgeError


@dataclass(frozen=True)
class Workspace:
    """Where a PATH given on the command line sits.

    `root` is where build/, install/ and log/ go (the folder holding src/, as
    colcon uses); `base_path` is what discovery crawls; `package` is set when
    PATH is one package inside a workspace, so only it (and what it needs) is
    processed.
    """

    root: Path
    base_path: Path
    package_path: Path | None = None


def locate(path: Path) -> Workspace:
    path = path.resolve()
    if not path.exists():
        raise PkgforgeError(f"{path} does not exist")
    if not path.is_dir():
        raise PkgforgeError(f"{path} is not a folder (give a package, a workspace or its src/)")
    if (path / "src").is_dir() and not (path / "package.xml").exists():
        return Workspace(root=path, base_path=path / "src")
    if path.name == "src" and not (path / "package.xml").exists():
        return Workspace(root=path.parent, base_path=path)
    for ancestor in path.parents:
        if ancestor.name == "src":
            return Workspace(
                root=ancestor.parent,
                base_path=ancestor,
                package_path=path if (path / "package.xml").exists() else None,
            )
    return Workspace(
        root=path if not (path / "package.xml").exists() else path.parent,
        base_path=path,
        package_path=path if (path / "package.xml").exists() else None,
    )


def discover(
    base_path: Path, *, augment: bool = True, ros_only: bool = False, unreadable: list[Path] | None = None
) -> list[Any]:
    """colcon PackageDescriptors under base_path (COLCON_IGNORE, AMENT_IGNORE honoured).

    `augment`: with colcon's augmentation (the dependencies; build.py orders by them; names,
    types and paths never change there). `ros_only`: identify with colcon's ignore and ROS
    extensions alone (colcon-python-setup-py imports setuptools: ~0.3 CPU s and ~10 MiB) when
    that gives what all of them would: every folder the ROS extension leaves to the lower
    priorities is watched, and when one holds a CMakeLists.txt or setup.py (what colcon's cmake
    and python extensions look for) discovery runs again with every extension. `unreadable`: gets
    the folders whose setup.py colcon could not run (each said on stderr in one line)."""
    import argparse
    import logging

    from colcon_core.package_discovery import add_package_discovery_arguments, discover_packages

    import pkgforge.model.catkin  # noqa: F401  (before colcon's ROS extension imports catkin_pkg)

    parser = argparse.ArgumentParser(add_help=False)
    add_package_discovery_arguments(parser)
    args = parser.parse_args(["--base-paths", str(base_path)])
    # colcon logs (with tracebacks) the manifests it rejects; pkgforge finds
    # those folders itself and reports each problem with its line instead
    logging.getLogger("colcon").setLevel(logging.CRITICAL + 1)
    try:
        descriptors = None
        undecided = _Undecided()
        groups = _ros_identification(undecided) if ros_only else None
        if groups is not None:
            descriptors = discover_packages(args, groups)
            if undecided.folders:
                descriptors = None  # colcon's other extensions might identify those: ask them all
        if descriptors is None:
            from colcon_core.package_identification import get_package_identification_extensions

            # colcon's python extension runs each setup.py it meets in a Python of its own whose
            # traceback, when the file fails (an import not installed), would reach the terminal
            # raw: pkgforge says it in one located line instead
            with _setup_py_failures() as failures:
                descriptors = discover_packages(args, get_package_identification_extensions())
            for folder, failure in failures:
                print(f"pkgforge: warning: {failure}", file=sys.stderr)
                if unreadable is not None:
                    unreadable.append(Path(folder))
        if augment:  # augmentation is where colcon-ros fills in the manifest's dependencies
            from colcon_core.package_augmentation import augment_packages

            augment_packages(descriptors)
    except Exception as exc:  # colcon raises plain exceptions for bad manifests
        raise PkgforgeError(f"package discovery under {base_path} failed: {exc}") from exc
    return sorted(descriptors, key=lambda d: (d.name or "", str(d.path)))


# colcon's log line for an identification extension that raised (colcon_core.package_identification)
EXTENSION_FAILED = re.compile(r"Exception in package identification extension '(\w+)' in '([^']+)'")
# the setup.py's own frames: run_setup exec()s its text, which Python names "<string>"
SETUP_FRAME = re.compile(r'File "<string>", line (\d+)')


class _Recorder(logging.Handler):
    """The folders whose setup.py colcon's python extensions failed to run, from colcon's log."""

    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.folders: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        found = EXTENSION_FAILED.search(record.getMessage())
        if found and found.group(1).startswith("python") and found.group(2) not in self.folders:
            self.folders.append(found.group(2))


@contextmanager
def _setup_py_failures() -> Iterator[list[tuple[str, str]]]:
    """While colcon identifies packages: its log records which setup.py files failed, and what
    the Pythons running them wrote on the standard error (file descriptor 2, which they inherit)
    is kept; after, one line per failed setup.py (its file, the line it failed at, the error),
    and anything else they wrote passed on as it was."""
    import os
    import tempfile

    colcon = logging.getLogger("colcon")
    recorder = _Recorder()
    level, handlers, propagate = colcon.level, colcon.handlers[:], colcon.propagate
    colcon.setLevel(logging.ERROR)
    colcon.handlers, colcon.propagate = [recorder], False
    failures: list[tuple[str, str]] = []  # (folder, what to say)
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with tempfile.TemporaryFile() as captured:
            os.dup2(captured.fileno(), 2)
            try:
                yield failures
            finally:
                sys.stderr.flush()
                os.dup2(saved, 2)
                captured.seek(0)
                written = captured.read().decode("utf-8", errors="replace")
            failures += _described(recorder.folders, written)
            if not failures and written:
                sys.stderr.write(written)  # not a setup.py's failure: what it is, as it came
    finally:
        os.close(saved)
        colcon.setLevel(level)
        colcon.handlers, colcon.propagate = handlers, propagate


def _described(folders: list[str], written: str) -> list[tuple[str, str]]:
    """One line per folder whose setup.py failed, with the error of its traceback (in the order
    colcon ran them) where each has one."""
    import os

    tracebacks = [
        t for t in re.split(r"^(?=Traceback \(most recent call last\):)", written, flags=re.M) if t.strip()
    ]
    tracebacks = [t for t in tracebacks if t.startswith("Traceback")]
    lines = []
    for index, folder in enumerate(folders):
        setup_py = os.path.relpath(os.path.join(folder, "setup.py"))
        error, line = "it failed", ""
        if len(tracebacks) == len(folders):
            text = tracebacks[index].rstrip().splitlines()
            error = text[-1].strip() if text else error
            frames = SETUP_FRAME.findall(tracebacks[index])
            line = f":{frames[-1]}" if len(frames) > 1 else ""  # (the first is colcon's own -c code)
        lines.append(
            (
                folder,
                f"{setup_py}{line}: colcon could not run it to read the package's name ({error}), so it "
                "skips the folder: install what it imports, or put a COLCON_IGNORE file beside it if it is no package",
            )
        )
    return lines


# the files that keep colcon out of a folder and everything below it (colcon's ignore extension)
IGNORE_MARKERS = ("COLCON_IGNORE", "AMENT_IGNORE", "CATKIN_IGNORE")

# what colcon's cmake, python and python_setup_py identification extensions look for in a folder
BUILD_FILES = ("CMakeLists.txt", "setup.py")


class _Undecided:
    """Ranked below the ROS extension, so it sees exactly the folders colcon would hand to its
    cmake and python extensions; notes those where they could find a package. Identifies nothing."""

    PACKAGE_IDENTIFICATION_NAME = "pkgforge_undecided"

    def __init__(self) -> None:
        self.folders: list[str] = []

    def identify(self, desc: Any) -> None:  # colcon's PackageDescriptor (untyped)
        import os

        if any(os.path.isfile(os.path.join(str(desc.path), name)) for name in BUILD_FILES):
            self.folders.append(str(desc.path))


def _ros_identification(below: _Undecided | None = None) -> OrderedDict[int, OrderedDict[str, Any]] | None:
    """colcon's ignore and ROS identification extensions, grouped by priority as colcon groups
    them (and `below`, ranked under them); None unless the installed identification extensions
    are the known six and no COLCON_EXTENSION_BLOCKLIST is set."""
    import os

    if os.environ.get("COLCON_EXTENSION_BLOCKLIST") or _identification_names() != IDENTIFICATION:
        return None
    from colcon_core.package_identification.ignore import IgnorePackageIdentification
    from colcon_ros.package_identification.ignore import IgnorePackageIdentification as IgnoreAmentInstall
    from colcon_ros.package_identification.ros import RosPackageIdentification

    groups = OrderedDict(
        [
            (
                1000,
                OrderedDict(
                    [
                        ("ignore", IgnorePackageIdentification()),
                        ("ignore_ament_install", IgnoreAmentInstall()),
                    ]
                ),
            ),
            (150, OrderedDict([("ros", RosPackageIdentification())])),
        ]
    )
    for group in groups.values():
        for name, extension in group.items():
            extension.PACKAGE_IDENTIFICATION_NAME = name
    if below is not None:
        groups[0] = OrderedDict([(below.PACKAGE_IDENTIFICATION_NAME, below)])
    return groups


# colcon's identification extensions as installed with pkgforge: those above priority 150 only
# ignore a folder, `ros` identifies a package.xml, and what ranks below never runs once it has
IDENTIFICATION = {"cmake", "ignore", "ignore_ament_install", "python", "python_setup_py", "ros"}


def identify_folder(folder: Path) -> Any:
    """colcon's descriptor of one package folder from its ignore and ROS extensions alone (what
    colcon's discovery of that folder decides when the ROS extension identifies it), without
    loading every extension (colcon-python-setup-py imports setuptools: ~1 CPU s); None when
    that is not certain (another colcon extension installed, an extension blocklist, a folder
    colcon ignores or whose manifest the ROS extension rejects): discover() decides then."""
    import logging

    import pkgforge.model.catkin  # noqa: F401  (before colcon's ROS extension imports catkin_pkg)

    groups = _ros_identification()
    if groups is None:
        return None
    from colcon_core.package_identification import IgnoreLocationException, identify

    logging.getLogger("colcon").setLevel(logging.CRITICAL + 1)  # as discover(): pkgforge reports it
    try:
        descriptor = identify(groups, str(folder))
    except IgnoreLocationException:
        return None
    except Exception:  # colcon raises plain exceptions for bad manifests: discover() says it
        return None
    return descriptor if descriptor and str(descriptor.type).startswith("ros.") else None


IDENTIFICATION_GROUP = "colcon_core.package_identification"


def _identification_names() -> set[str]:
    """The names of colcon's identification entry points in every distribution on sys.path.

    importlib.metadata.entry_points() builds a Distribution for each of the ~100 installed and
    reads them all (~45 ms, a tenth of checking one package); this reads only the entry_points.txt
    files of the dist-info and egg-info folders. It sees every distribution entry_points() sees
    (and shadowed copies too, which can only add names: then discover() decides, as for any
    other name); with a path entry it cannot list (a zip, an egg), importlib.metadata answers."""
    import os
    import sys

    names: set[str] = set()
    for entry in sys.path:
        if entry.lower().endswith(".egg"):  # an egg's EGG-INFO: importlib.metadata's rules
            from importlib.metadata import entry_points

            return {e.name for e in entry_points(group=IDENTIFICATION_GROUP)}
        try:
            folders = [n for n in os.listdir(entry or ".") if n.endswith((".dist-info", ".egg-info"))]
        except NotADirectoryError:
            from importlib.metadata import entry_points

            return {e.name for e in entry_points(group=IDENTIFICATION_GROUP)}
        except OSError:
            continue  # a path entry that is gone: importlib.metadata finds nothing there either
        for folder in folders:
            try:
                with open(os.path.join(entry or ".", folder, "entry_points.txt"), encoding="utf-8") as handle:
                    text = handle.read()
            except (OSError, UnicodeDecodeError):
                continue
            if IDENTIFICATION_GROUP in text:
                names |= _section_names(text, IDENTIFICATION_GROUP)
    return names


def _section_names(text: str, section: str) -> set[str]:
    """The keys of one [section] of an entry_points.txt (an ini file: `name = module:attr`)."""
    names, inside = set(), False
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("["):
            inside = line == f"[{section}]"
        elif inside and "=" in line and not line.startswith(("#", ";")):
            names.add(line.split("=", 1)[0].strip())
    return names
