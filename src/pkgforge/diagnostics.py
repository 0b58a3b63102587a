"""What a check reports: a Diagnostic, located at a file and line, with a fix hint."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from enum import IntEnum
from pathlib import Path
from typing import Any


class Severity(IntEnum):
    INFO = 1
    WARNING = 2
    ERROR = 3

    @property
    def label(self) -> str:
        return self.name.lower()

    @classmethod
    def parse(cls, text: str) -> Severity:
        return cls[text.upper()]


@dataclass(frozen=True)
class Group:
    """One finding of a cause that may repeat on many items of one file (velocity="0" on each
    joint of a model): verify shows the findings of one check, file, severity and `cause` as one
    diagnostic that names the items (grouped after suppressions: verify/grouping.py).

    `many` is that diagnostic's message, with `{count}` and `{items}` in it
    ('{count} joints have velocity="0": {items}'); `item` names this finding's item in that list
    ("j1", or "j1 (1.57 > -1.57)" when the items differ in more than their names)."""

    cause: str
    item: str
    many: str


@dataclass(frozen=True)
class Finding:
    """What a check function yields; the registry adds code, name and default severity."""

    message: str
    path: Path
    line: int | None = None
    column: int | None = None
    hint: str | None = None  # None: the check's own hint
    severity: Severity | None = None  # None: the check's default
    # what `pkgforge fix` needs to fix it (plain data, e.g. {"dependency": "xacro"}); None: no fix.
    # {"unsafe": True, ...}: this finding's fix is unsafe (--unsafe-fixes) whatever the check's kind
    fix: dict[str, Any] | None = field(default=None, compare=False, hash=False)
    # the full text behind a message kept to one short line (an error's whole output, every
    # argument combination): the JSON report's `detail`
    detail: str | None = None
    group: Group | None = field(default=None, compare=False, hash=False)


# A message is one line of at most this many characters (a terminal's two lines, a CI
# annotation's title): what is longer goes to `detail`, which the JSON report holds.
MESSAGE_LIMIT = 300
CUT_NOTE = " (full text: --format json)"
GAP = " ... "


def one_line(message: str, detail: str | None = None) -> tuple[str, str | None]:
    """(message, detail) with the message on one line of at most MESSAGE_LIMIT characters: its
    line breaks (and the blanks around them) become one space, and a longer message keeps its
    beginning and its end (what an error says after the URDF it quotes), cut at word boundaries
    and noted; the whole text is kept in detail (before the finding's own detail)."""
    flat = flattened(message)
    if len(flat) <= MESSAGE_LIMIT:
        return flat, detail if flat == message else _both(message, detail)
    room = MESSAGE_LIMIT - len(CUT_NOTE) - len(GAP)
    head_room = room * 3 // 5
    tail_room = room - head_room
    cut = flat.rfind(" ", head_room * 2 // 3, head_room + 1)
    head = flat[: cut if cut > 0 else head_room].rstrip(" ,;:(")
    start = len(flat) - tail_room
    space = flat.find(" ", start, start + tail_room // 3)
    tail = flat[space + 1 if space >= 0 else start :]
    return head + GAP + tail + CUT_NOTE, _both(message, detail)


# a line break that lays text out: with blanks around it (indentation), or several in a row
_LAYOUT_BREAK = re.compile(r"[ \t]*(\r\n|\r|\n)[ \t\r\n]*")


def flattened(text: str) -> str:
    """text on one line: each line break that lays it out (the blanks around it, blank lines) one
    space; a lone break between two characters, as a file's name may hold one, the two characters
    \\n (what the reports print for it: `printable`), so the name stays recognisable."""
    if "\n" not in text and "\r" not in text:
        return text

    def join(match: re.Match[str]) -> str:
        edge = match.start() == 0 or match.end() == len(text)
        if match.group(0) == match.group(1) and not edge:
            return match.group(1).replace("\r", "\\r").replace("\n", "\\n")
        return " "

    return _LAYOUT_BREAK.sub(join, text).strip()


def _both(message: str, detail: str | None) -> str:
    return message if not detail or detail == message else f"{message}\n{detail}"


@dataclass(frozen=True)
class Diagnostic:
    code: str
    name: str
    severity: Severity
    package: str
    path: Path  # absolute
    line: int | None
    column: int | None
    message: str  # one line, at most MESSAGE_LIMIT characters
    hint: str
    # the finding's fix data (pkgforge fix); not part of any report
    fix: dict[str, Any] | None = field(default=None, compare=False, hash=False, repr=False)
    detail: str | None = None  # the full text a short message stands for (JSON report)
    # the finding's Group until verify groups the package's diagnostics; never cached or reported
    group: Group | None = field(default=None, compare=False, hash=False, repr=False)

    def sort_key(self) -> tuple[str, str, int, int, str, str]:
        return (self.package, str(self.path), self.line or 0, self.column or 0, self.code, self.message)


@dataclass
class PackageReport:
    """The diagnostics of one package, and what the reports say about the package."""

    name: str
    path: Path
    build_type: str
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # bugs in pkgforge met while checking the package ("summary\ntraceback"): verify exits 2
    internal_errors: list[str] = field(default_factory=list)
    # (the distro whose launch API the built-in engine followed for its launch files, where that
    # came from: --distro, ROS_DISTRO, pkgforge.toml, CI file, the newest LTS); None: no built-in engine
    launch_distro: tuple[str, str] | None = None
