"""Output formats for verify results: one module each, one `render(result, ...)` function."""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

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


# What a report must not print as it is: C0 controls (a newline would start a line a CI runner
# reads as its own, ESC a sequence that retitles or clears the terminal), DEL, C1 controls (CSI,
# OSC and NEL in one character), lone surrogates (a file name's bytes that are not UTF-8, which a
# UTF-8 stream refuses to write) and U+FFFE/U+FFFF (XML 1.0 forbids them, and lxml raises)
_UNPRINTABLE = re.compile("[\x00-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")
_NAMED_ESCAPES = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def printable(text: str) -> str:
    """text safe to print on one line of a terminal, a CI log or an XML report: each control
    character written visibly as Python writes it in a string (`\\n`, `\\t`, `\\x1b`, `\\x85`), a
    byte that was not UTF-8 as `\\xe9`, so that a name stays recognisable and cannot act.
    A backslash is kept as it is (Windows paths and regular expressions read as written)."""
    if _UNPRINTABLE.search(text) is None:
        return text
    return _UNPRINTABLE.sub(_escape, text)


def _escape(match: re.Match[str]) -> str:
    character = match.group(0)
    code = ord(character)
    if character in _NAMED_ESCAPES:
        return _NAMED_ESCAPES[character]
    if 0xDC80 <= code <= 0xDCFF:  # os.fsdecode's stand-in for the byte code - 0xDC00
        return f"\\x{code - 0xDC00:02x}"
    return f"\\x{code:02x}" if code <= 0xFF else f"\\u{code:04x}"


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
