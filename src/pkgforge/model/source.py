"""Reading a package's files once: text, lines, and `pkgforge: ignore=` suppressions."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

# Larger files are listed (they still install) but not read: a 50 MB mesh
# exported as ASCII must not stall a pre-commit hook.
MAX_READ_BYTES = 8 * 1024 * 1024

SUPPRESSION = re.compile(r"pkgforge:\s*ignore\s*=\s*([A-Za-z0-9_\-]+(?:\s*,\s*[A-Za-z0-9_\-]+)*)")


@dataclass
class SourceFile:
    path: Path
    text: str | None  # None when unreadable, too large or not UTF-8
    problem: str | None = None  # why text is None
    problem_line: int | None = None
    # line number → names/codes suppressed for the line after the comment
    suppressions: dict[int, set[str]] = field(default_factory=dict)

    def __getstate__(self) -> dict[str, Any]:
        # A model crosses from a worker process to the checks, which never read
        # file text (the loaders did): leave it behind, keeping "was readable".
        state = dict(self.__dict__)
        if state["text"] is not None:
            state["text"] = ""
        return state


def read_source(path: Path) -> SourceFile:
    try:
        size = path.stat().st_size
        if size > MAX_READ_BYTES:
            return SourceFile(
                path,
                None,
                f"{size / 1e6:.1f} MB is over pkgforge's "
                f"{MAX_READ_BYTES // (1024 * 1024)} MB limit for reading a file",
            )
        data = path.read_bytes()
    except OSError as exc:
        return SourceFile(path, None, f"cannot read: {exc.strerror or exc}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        return SourceFile(
            path, None, f"not valid UTF-8: byte 0x{data[exc.start]:02x} at line {line}", problem_line=line
        )
    if text.startswith("\ufeff"):
        text = text[1:]
    return SourceFile(path, text, suppressions=_suppressions(text))


def _suppressions(text: str) -> dict[int, set[str]]:
    found: dict[int, set[str]] = {}
    if "pkgforge:" not in text:
        return found
    for number, line in enumerate(text.splitlines(), start=1):
        match = SUPPRESSION.search(line)
        if match:
            names = {n.strip() for n in match.group(1).split(",") if n.strip()}
            # the comment covers its own line and the next one
            for covered in (number, number + 1):
                found.setdefault(covered, set()).update(names)
    return found
