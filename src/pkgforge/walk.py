"""The one directory walk pkgforge uses on anything the user controls.

Like os.walk (top-down, the caller may prune `dirs` in place) but:
- iterative: no Python recursion however deep the folders nest;
- a symlinked folder is entered only when asked to follow links, only when its
  real path stays inside the walk's top, and never twice (a link to `.` or to
  a parent is a cycle, not an endless walk);
- bounded: at most `max_depth` folders deep and `max_files` files; where a
  bound stops the walk (or a folder cannot be read), a WalkLimit says which
  folder and why, for the folder-not-walked diagnostic (PF903).
"""

from __future__ import annotations

import errno
import os
from collections.abc import Iterator
from dataclasses import dataclass

# Deeper nesting is an accident (a folder copied into itself); real packages stay under 15.
MAX_DEPTH = 64
# More files than any description package holds (example-robot-data has ~3000 in all).
MAX_FILES = 100_000


UNREADABLE_HINT = (
    "give the folder read and search permission (chmod a+rx); colcon build cannot install it either"
)


@dataclass(frozen=True)
class WalkLimit:
    path: str  # the folder where the walk stopped
    why: str  # one line: which bound, or why the folder cannot be read
    hint: str | None = None  # None: the check's own hint


def walk(
    top: str | os.PathLike[str],
    *,
    follow_links: bool = False,
    max_depth: int = MAX_DEPTH,
    max_files: int = MAX_FILES,
    limits: list[WalkLimit] | None = None,
    inside: tuple[str | os.PathLike[str], ...] = (),
) -> Iterator[tuple[str, list[str], list[str]]]:
    """(folder, sub-folder names, file names) for top and every folder under it.

    A followed link may lead into top or into one of the folders `inside`
    (an install tree's link back into its package's source, --symlink-install).

    An unreadable folder is skipped, and noted in `limits` too.
    """
    top = os.fspath(top)
    try:
        roots = [os.path.realpath(p) for p in (top, *inside)]
        top_stat = os.stat(top)
    except OSError:
        return
    seen = {(top_stat.st_dev, top_stat.st_ino)}
    stack = [(top, 0)]
    files_left = max_files
    while stack:
        folder, depth = stack.pop()
        dirs, files, links = [], [], set()
        try:
            with os.scandir(folder) as entries:
                for entry in entries:
                    try:
                        is_dir = entry.is_dir()
                    except OSError:
                        is_dir = False
                    if is_dir:
                        dirs.append(entry.name)
                        if entry.is_symlink():
                            links.add(entry.name)
                    else:
                        files.append(entry.name)
        except OSError as exc:
            if exc.errno != errno.ENOENT:  # gone meanwhile is no problem; unreadable is
                _note(limits, folder, f"cannot read this folder: {exc.strerror}", UNREADABLE_HINT)
            continue
        if len(files) > files_left:
            files = sorted(files)[:files_left]
            _note(limits, folder, f"more than {max_files} files: pkgforge did not look at the rest")
            files_left = 0
        else:
            files_left -= len(files)
        yield folder, dirs, files
        if files_left <= 0:
            if dirs or stack:
                _note(limits, folder, f"more than {max_files} files: pkgforge did not look at the rest")
            return
        if dirs and depth + 1 > max_depth:
            _note(
                limits,
                folder,
                f"folders nest more than {max_depth} deep below this one: pkgforge did not look inside",
            )
            continue
        below = []
        for name in dirs:
            path = os.path.join(folder, name)
            if name in links:
                if not follow_links:
                    continue
                real = os.path.realpath(path)
                if not any(real == root or real.startswith(root.rstrip(os.sep) + os.sep) for root in roots):
                    continue  # out of the tree
            try:
                status = os.stat(path)
            except OSError:
                continue
            key = (status.st_dev, status.st_ino)
            if key in seen:
                continue  # a link cycle, or a folder reached twice
            seen.add(key)
            below.append((path, depth + 1))
        stack.extend(reversed(below))


def _note(limits: list[WalkLimit] | None, folder: str, why: str, hint: str | None = None) -> None:
    if limits is not None:
        limit = WalkLimit(folder, why, hint)
        if limit not in limits:
            limits.append(limit)


def remove_tree(path: str | os.PathLike[str]) -> None:
    """Remove a folder pkgforge made (a temporary tree, a launch file's own folder) whatever a launch
    file left in it: nested past Python's recursion (shutil.rmtree recurses), or folders it made
    unreadable (chmod 0). GNU rm and chmod walk without recursion. Never raises."""
    import shutil
    import subprocess

    try:
        shutil.rmtree(path)
        return
    except FileNotFoundError:
        return
    except (OSError, RecursionError):
        pass
    text = os.fspath(path)
    for command in (["chmod", "-R", "u+rwx", "--", text], ["rm", "-rf", "--", text]):
        try:
            subprocess.run(
                command,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                timeout=120,
                check=False,
            )
        except (OSError, subprocess.SubprocessError):
            pass
