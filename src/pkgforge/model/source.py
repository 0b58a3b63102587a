"""Reading a package's files once: text, lines, and `pkgforge: ignore=` suppressions.

Every file of the user's that pkgforge reads in its own process goes through `read_regular`
(or `read_head`): only a regular file is opened (a FIFO would block the read for ever, a link
to /dev/zero or /dev/urandom would never end), and never more than a limit.
"""

from __future__ import annotations

import ast
import errno
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO

# Larger files are listed (they still install) but not read: a 50 MB mesh
# exported as ASCII must not stall a pre-commit hook.
MAX_READ_BYTES = 8 * 1024 * 1024

SUPPRESSION = re.compile(r"pkgforge:\s*ignore\s*=\s*([A-Za-z0-9_\-]+(?:\s*,\s*[A-Za-z0-9_\-]+)*)")
# what a file that is not a regular one is, by its mode's type bits
KINDS = {
    stat.S_IFIFO: "a FIFO (named pipe)",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
    stat.S_IFDIR: "a folder",
}
# (O_NONBLOCK: a FIFO swapped in after the check opens at once instead of waiting for a writer;
# O_NOCTTY: a terminal never becomes pkgforge's)
OPEN_FLAGS = os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC


class NotRegularFile(OSError):
    """A path pkgforge would read that is no regular file (nor a link to one): never read.
    Its strerror says what it is, in one line."""


class FileTooLarge(OSError):
    """A regular file over the limit it is read with."""

    def __init__(self, path: str, size: int, limit: int):
        super().__init__(
            errno.EFBIG,
            f"{size / 1e6:.1f} MB is over pkgforge's {limit // (1024 * 1024)} MB limit for reading a file",
            path,
        )
        self.size = size


def not_regular(path: str | os.PathLike[str], mode: int) -> NotRegularFile:
    """The refusal of `path`, whose mode (links followed) is not a regular file's."""
    kind = KINDS.get(stat.S_IFMT(mode), "not a regular file")
    # a link names where it ends (through an install tree's link to the source, and on)
    what = f"a link to {os.path.realpath(path)}, {kind}" if os.path.islink(path) else kind
    return NotRegularFile(errno.EINVAL, f"{what}: pkgforge reads only regular files", os.fspath(path))


def open_regular(path: str | os.PathLike[str]) -> tuple[int, os.stat_result]:
    """A descriptor open for reading on the regular file at `path` (links followed), and its
    status; NotRegularFile (before anything is opened: opening some devices does something) for
    anything else."""
    info = os.stat(path)
    if not stat.S_ISREG(info.st_mode):
        raise not_regular(path, info.st_mode)
    handle = os.open(path, OPEN_FLAGS)
    try:
        info = os.fstat(handle)  # what was opened: the path may have been swapped meanwhile
        if not stat.S_ISREG(info.st_mode):
            raise not_regular(path, info.st_mode)
    except BaseException:
        os.close(handle)
        raise
    return handle, info


def read_regular(path: str | os.PathLike[str], limit: int = MAX_READ_BYTES) -> bytes:
    """The bytes of the regular file at `path`: NotRegularFile for anything else, FileTooLarge
    over `limit` (by its size, or by what a read gives: a file that grows, or /proc's size 0)."""
    handle, info = open_regular(path)
    with open(handle, "rb", closefd=True) as stream:
        if info.st_size > limit:
            raise FileTooLarge(os.fspath(path), info.st_size, limit)
        data = _read_up_to(stream, info.st_size, limit + 1)
    if len(data) > limit:
        raise FileTooLarge(os.fspath(path), len(data), limit)
    return data


def read_head(path: str | os.PathLike[str], limit: int) -> tuple[bytes, int]:
    """At most the first `limit` bytes of the regular file at `path`, and its size;
    NotRegularFile for anything else."""
    handle, info = open_regular(path)
    with open(handle, "rb", closefd=True) as stream:
        return _read_up_to(stream, info.st_size, limit), info.st_size


def _read_up_to(stream: BinaryIO, size: int, most: int) -> bytes:
    """At most `most` bytes of a file whose size is `size`. (A read of n bytes allocates n first:
    the size, and one byte more to see the end; more only when the file grew, or its size is
    not known ahead, as /proc's are not.)"""
    data = stream.read(min(size + 1, most))
    if size < len(data) < most:
        data += stream.read(most - len(data))
    return data


def parse_python(text: str, filename: str = "<unknown>") -> ast.Module:
    """ast.parse(text). A text nested too deep for CPython's parser (`1+1+…` 3000 times: a
    RecursionError or MemoryError building the tree; compiling it fails the same way, so Python
    cannot run it either) is a SyntaxError saying so."""
    try:
        return ast.parse(text, filename=filename)
    except (RecursionError, MemoryError):
        raise SyntaxError(
            "nested too deep for Python's parser (it ran out of stack): Python cannot run it either",
            (filename, _longest_statement(text), None, None),
        ) from None


def _longest_statement(text: str) -> int | None:
    """The first line of the statement of the most tokens: where the parser's stack runs out (it
    gives no line), found without building a tree."""
    import io
    import tokenize

    best, best_count, start, count = None, 0, None, 0
    try:
        for token in tokenize.generate_tokens(io.StringIO(text).readline):
            if token.type in (tokenize.NL, tokenize.COMMENT, tokenize.INDENT, tokenize.DEDENT):
                continue  # (blank lines and comments between statements are none of theirs)
            if start is None:
                start = token.start[0]
            count += 1
            if token.type in (tokenize.NEWLINE, tokenize.ENDMARKER):
                if count > best_count:
                    best, best_count = start, count
                start, count = None, 0
    except (tokenize.TokenError, SyntaxError):
        pass
    if start is not None and count > best_count:  # a statement the tokenizer stopped in
        best = start
    return best


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
        data = read_regular(path)
    except (NotRegularFile, FileTooLarge) as exc:
        return SourceFile(path, None, exc.strerror)
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
