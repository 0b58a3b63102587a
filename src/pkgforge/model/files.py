"""The files of a package: a walk light enough for the cache's fast path (no XML, no colcon)."""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from pathlib import Path

from pkgforge.model.source import read_regular
from pkgforge.walk import WalkLimit, walk

NAME_ELEMENT = re.compile(r"<name>\s*([^<\s]+)\s*</name>")

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


def vcs_repos_files(package_folders: Iterable[Path], base: Path | None = None) -> list[Path]:
    """The vcs .repos (and wstool .rosinstall) files in the packages' own folders and in every folder above them up to the
    workspace's `base` (where packages are found) and the one above it (rosbot_ros keeps
    rosbot_hardware.repos in a package, c3pzero its c3pzero.repos at the root of a repository of
    package groups, a workspace in src/ or beside it), sorted: what `vcs import` brings in from
    source. Without `base`: up to the folder the packages share."""
    packages = {p.resolve() for p in package_folders}
    if not packages:
        return []
    top = base.resolve() if base is not None else Path(os.path.commonpath([str(p) for p in packages]))
    folders = {top, top.parent}
    for package in packages:
        folders.add(package)
        folders.update(p for p in package.parents if p.is_relative_to(top))
    found: set[Path] = set()
    for folder in folders:
        try:
            with os.scandir(folder) as entries:
                found.update(
                    Path(e.path)
                    for e in entries
                    if e.name.endswith((".repos", ".rosinstall")) and e.is_file(follow_symlinks=False)
                )
        except OSError:
            continue
    return sorted(found)


def manifest_text(folder: Path) -> str | None:
    """A package's package.xml as text (None: unreadable, too large, or no regular file)."""
    try:  # (a str path, not a Path per file: a third of the time for 200 packages)
        return read_regular(os.path.join(folder, "package.xml")).decode("utf-8", errors="replace")
    except OSError:
        return None


def quick_name(folder: Path, text: str | None = "") -> str:
    """The package name read without parsing the manifest (before colcon has identified anything,
    and for packages colcon never sees: one nested in another). `text`: the package.xml already
    read (None: unreadable)."""
    if text == "":
        text = manifest_text(folder)
    match = NAME_ELEMENT.search(text) if text is not None else None
    return match.group(1) if match else folder.name
