"""Output formats for verify results: one module each, one `render(result, ...)` function."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from pkgforge.printable import printable

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

COLOR_CHOICES = ("auto", "always", "never")


def use_color(choice: str | None, stream: TextIO) -> bool:
    """--color always/never as given; auto (or None): NO_COLOR set (and not empty) never,
    FORCE_COLOR set (not empty, 0 or false) always, else when the stream is a terminal."""
    if choice == "always":
        return True
    if choice == "never":
        return False
    if os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR", "").strip().lower() not in ("", "0", "false"):
        return True
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


FORMATS = ("text", "json", "junit", "sarif", "github", "gitlab")
__all__ = ["COLOR_CHOICES", "FORMATS", "printable", "relative", "render", "use_color"]


def relative(path: Path, root: Path) -> str:
    """A path relative to a folder (the JSON report's: the folder verify was given)."""
    return Path(os.path.relpath(path, root)).as_posix()


def from_here(path: Path) -> str:
    """A path as the user's shell reaches it, as ruff and gcc print one: relative to the current
    folder when it is inside it, else absolute (never ../../: a terminal opens what it shows)."""
    absolute = Path(os.path.abspath(path))
    try:
        here = Path(os.getcwd())
    except OSError:  # the current folder was removed
        return absolute.as_posix()
    try:
        return absolute.relative_to(here).as_posix()
    except ValueError:
        return absolute.as_posix()


class InRepository:
    """A file's path as CI services match it against the repository's files: relative to the
    root of the git repository that holds it (the nearest folder above it with a .git, as
    actions/checkout and GitLab's clone make it), else relative to `fallback`."""

    def __init__(self, fallback: Path):
        self.fallback = fallback
        self._known: dict[Path, Path | None] = {}

    def root(self, path: Path) -> Path | None:
        folder = Path(os.path.abspath(path)).parent
        trail = []
        while folder not in self._known:
            trail.append(folder)
            if (folder / ".git").exists():
                self._known[folder] = folder
                break
            if folder.parent == folder:
                self._known[folder] = None
                break
            folder = folder.parent
        found = self._known[folder]
        for seen in trail:
            self._known[seen] = found
        return found

    def __call__(self, path: Path) -> str:
        return relative(path, self.root(path) or self.fallback)


def render(fmt: str, result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    from importlib import import_module

    # only the chosen format's module: junit's lxml alone costs a re-run answered by the cache ~10 %
    if fmt not in FORMATS:
        raise KeyError(fmt)
    module = import_module(f".{MODULES.get(fmt, fmt)}", __name__)
    text: str = module.render(result, color=color, strict=strict)
    return text


MODULES = {"json": "json_report"}  # the format names whose module is named otherwise
