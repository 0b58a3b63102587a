"""The files of a package: a walk light enough for the cache's fast path (no XML, no colcon)."""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from pkgforge.walk import WalkLimit, walk

# Never part of what a package installs or refers to.
SKIPPED_DIRS = {"build", "install", "log", "__pycache__", "node_modules", "test", "tests"}


def walk_files(
    root: Path, limits: list[WalkLimit] | None = None, nested: list[Path] | None = None
) -> list[Path]:
    """Every file of the package, not descending into nested packages or build folders (the
    nested packages' folders, relative, go to `nested`)."""
    folders: list[str] = []
    files = [Path(name) for name in walk_file_names(root, limits, folders)]
    if nested is not None:
        nested += [Path(folder) for folder in folders]
    return files


def walk_file_names(
    root: Path, limits: list[WalkLimit] | None = None, nested: list[str] | None = None
) -> list[str]:
    """walk_files as relative path strings (the cache's fast path builds no Path objects)."""
    files = []
    top = str(root)
    cut = len(top.rstrip(os.sep)) + 1
    for current, dirs, names in walk(top, limits=limits):
        relative_dir = "." if current == top else current[cut:]  # (the walk joins below top: no relpath)
        keep = []
        for d in sorted(dirs):
            if d.startswith(".") or (current == top and d in SKIPPED_DIRS):
                continue
            sub = os.path.join(current, d)
            if os.path.exists(os.path.join(sub, "COLCON_IGNORE")):
                continue
            if os.path.exists(os.path.join(sub, "package.xml")):
                if nested is not None:
                    nested.append(d if relative_dir == "." else f"{relative_dir}/{d}")
                continue
            keep.append(d)
        dirs[:] = keep
        for name in sorted(names):
            if not name.startswith("."):
                files.append(name if relative_dir == "." else f"{relative_dir}/{name}")
    return files


def vcs_repos_files(package_folders: Iterable[Path]) -> list[Path]:
    """The vcs .repos files in the packages' own folders and beside them (where rosbot_ros keeps
    rosbot_hardware.repos; a workspace's src/), sorted: what `vcs import` brings in from source."""
    found: set[Path] = set()
    for folder in {f for p in package_folders for f in (p, p.parent)}:
        try:
            with os.scandir(folder) as entries:
                found.update(
                    Path(e.path)
                    for e in entries
                    if e.name.endswith(".repos") and e.is_file(follow_symlinks=False)
                )
        except OSError:
            continue
    return sorted(found)
