"""Text edits on a user's files: located by line and column, applied bottom-up, written atomically.

A file is read once (its exact bytes kept); every fixer computes its edits
against that text; the edits of one file are applied from the bottom up, the
result is parsed again, and only then written: into a temporary file beside it,
renamed over it with its mode kept, and only if the file on disk still holds
the bytes that were read.
"""

from __future__ import annotations

import ast
import difflib
import os
import stat
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from pkgforge.model.source import read_regular

BOM = "\ufeff"


class Unfixable(Exception):
    """This finding has no automatic fix here; the message says why (shown to the user)."""


class NotOffered(Unfixable):
    """The check left this finding without a fix on purpose (its hint says what to decide): it
    stays among what remains, with no `not fixed` line."""


@dataclass(frozen=True)
class Edit:
    start: int  # character offsets into the file's text (after any BOM)
    end: int
    text: str
    order: str = ""  # among insertions at one offset: ascending order in the result


class SourceText:
    """One file as read: exact bytes, the text, line starts, line ending, indentation unit."""

    def __init__(self, path: Path):
        self.path = path
        self.data = read_regular(path)  # OSError (a FIFO, a device too): the caller says it cannot read
        try:
            text = self.data.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise Unfixable(f"{path.name} is not UTF-8 text") from exc
        self.bom = BOM if text.startswith(BOM) else ""
        self.text = text[len(self.bom) :]
        self.starts = [0]
        for index, char in enumerate(self.text):
            if char == "\n":
                self.starts.append(index + 1)

    # --- positions ----------------------------------------------------------------------------

    @property
    def eol(self) -> str:
        """The file's own line ending: CRLF when most lines end so, else LF."""
        crlf = self.text.count("\r\n")
        return "\r\n" if crlf and crlf * 2 >= self.text.count("\n") else "\n"

    def line_start(self, line: int) -> int:
        """Offset of the first character of a 1-based line."""
        if line < 1 or line > len(self.starts):
            raise Unfixable(f"{self.path.name} has no line {line}")
        return self.starts[line - 1]

    def line_end(self, line: int) -> int:
        """Offset just past the line's ending (the next line's start, or the end of the text)."""
        return self.starts[line] if line < len(self.starts) else len(self.text)

    def line_text(self, line: int) -> str:
        """The line without its ending."""
        return self.text[self.line_start(line) : self.line_end(line)].rstrip("\r\n")

    def offset(self, line: int, column: int) -> int:
        """Offset of a 1-based line and 1-based column (in characters)."""
        return self.line_start(line) + column - 1

    def offset_utf8(self, line: int, byte_column: int) -> int:
        """Offset of a 1-based line and a 0-based UTF-8 byte column (Python's ast)."""
        start = self.line_start(line)
        raw = self.line_text(line).encode("utf-8")[:byte_column]
        return start + len(raw.decode("utf-8", errors="ignore"))

    def line_of(self, offset: int) -> int:
        import bisect

        return bisect.bisect_right(self.starts, offset)

    def indentation(self, line: int) -> str:
        text = self.line_text(line)
        return text[: len(text) - len(text.lstrip(" \t"))]

    def is_blank_before(self, offset: int) -> bool:
        """Only spaces or tabs between the start of offset's line and offset."""
        start = self.starts[self.line_of(offset) - 1]
        return self.text[start:offset].strip(" \t") == ""


def apply(text: str, edits: list[Edit]) -> str:
    """The text with the edits applied from the bottom up (edits must not overlap)."""
    for edit in sorted(edits, key=lambda e: (e.start, e.end, e.order), reverse=True):
        text = text[: edit.start] + edit.text + text[edit.end :]
    return text


# --- parsing again ----------------------------------------------------------------------------


def parse_problem(path: Path, text: str) -> str | None:
    """Why the text does not parse as the kind of file path is, or None."""
    name = path.name
    try:
        if name.endswith((".xml", ".urdf", ".xacro", ".sdf")) or name == "package.xml":
            from lxml import etree

            parser = etree.XMLParser(resolve_entities=False, no_network=True)
            etree.fromstring(text.encode("utf-8"), parser)
        elif name.endswith(".py"):
            ast.parse(text, filename=str(path))
        elif name == "CMakeLists.txt" or name.endswith(".cmake"):
            from pkgforge.model.cmake_syntax import parse

            parse(text, path)
        elif name.endswith((".rviz", ".yaml", ".yml")):
            from pkgforge.model.yamlnodes import compose

            compose(text)
    except Exception as exc:  # any parser's failure means: do not write
        return f"{type(exc).__name__}: {exc}".splitlines()[0]
    return None


# --- writing ----------------------------------------------------------------------------------


@dataclass
class Outcome:
    path: Path
    written: bool
    problem: str | None = None  # why nothing was written


def unified_diff(path: Path, before: str, after: str, shown: str) -> str:
    lines = difflib.unified_diff(
        before.splitlines(keepends=True), after.splitlines(keepends=True), f"a/{shown}", f"b/{shown}"
    )
    out = []
    for line in lines:
        out.append(line if line.endswith("\n") else line + "\n\\ No newline at end of file\n")
    return "".join(out)


def write_atomically(source: SourceText, new_text: str) -> Outcome:
    """Write new_text over source.path if the file still holds what was read; never half-written.

    A symbolic link stays one: the file it points to is written."""
    path = Path(os.path.realpath(source.path))
    try:
        current = read_regular(path)
    except OSError as exc:
        return Outcome(source.path, False, f"cannot read it again: {exc.strerror or exc}")
    if current != source.data:
        return Outcome(source.path, False, "it changed since pkgforge read it; run pkgforge fix again")
    try:
        info = path.stat()
    except OSError as exc:
        return Outcome(source.path, False, f"cannot stat it: {exc.strerror or exc}")
    if not os.access(path, os.W_OK) or not (info.st_mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH)):
        return Outcome(source.path, False, "it is read-only")
    data = (source.bom + new_text).encode("utf-8")
    temporary = None
    try:
        handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".pkgforge-fix")
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, stat.S_IMODE(info.st_mode))
        if read_regular(path) != source.data:  # changed while the new text was being written
            raise _Changed()
        os.replace(temporary, path)
        temporary = None
    except _Changed:
        return Outcome(source.path, False, "it changed since pkgforge read it; run pkgforge fix again")
    except OSError as exc:
        return Outcome(source.path, False, f"cannot write it: {exc.strerror or exc}")
    finally:
        if temporary is not None:
            try:
                os.unlink(temporary)
            except OSError:
                pass
    return Outcome(source.path, True)


def create_exclusively(path: Path, text: str) -> Outcome:
    """Write a new file (its folder made if missing) where no file is; never over one. Its text is
    written beside it first and linked into place, so no half-written file is ever seen."""
    path = Path(path)
    temporary = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".pkgforge-fix")
        with os.fdopen(handle, "wb") as stream:
            stream.write(text.encode("utf-8"))
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, 0o644)
        os.link(temporary, path)  # refuses an existing file, where a rename would replace it
    except FileExistsError:
        return Outcome(path, False, "it was created since pkgforge looked; run pkgforge fix again")
    except OSError as exc:
        return Outcome(path, False, f"cannot create it: {exc.strerror or exc}")
    finally:
        if temporary is not None:
            try:
                os.unlink(temporary)
            except OSError:
                pass
    return Outcome(path, True)


class _Changed(Exception):
    pass


@dataclass
class FileSet:
    """The files fixers read, each read once."""

    files: dict[Path, SourceText] = field(default_factory=dict)
    unreadable: dict[Path, str] = field(default_factory=dict)

    def get(self, path: Path) -> SourceText:
        path = Path(path)
        if path in self.unreadable:
            raise Unfixable(self.unreadable[path])
        if path not in self.files:
            try:
                self.files[path] = SourceText(path)
            except OSError as exc:
                self.unreadable[path] = f"cannot read {path.name}: {exc.strerror or exc}"
                raise Unfixable(self.unreadable[path]) from exc
            except Unfixable as exc:
                self.unreadable[path] = str(exc)
                raise
        return self.files[path]


Located = ast.expr | ast.stmt | ast.keyword  # the nodes ast.parse gives positions


def node_end_line(node: Located) -> int:
    # ast.parse sets the end of every node; nodes built by hand may lack it
    return node.end_lineno if node.end_lineno is not None else node.lineno


def node_span(source: SourceText, node: Located) -> tuple[int, int]:
    end_column = node.end_col_offset if node.end_col_offset is not None else node.col_offset
    return (
        source.offset_utf8(node.lineno, node.col_offset),
        source.offset_utf8(node_end_line(node), end_column),
    )
