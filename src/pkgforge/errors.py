"""Errors the CLI turns into a clean message and an exit status, never a traceback."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pkgforge.printable import printable


class PkgforgeError(Exception):
    """A problem with the user's input or environment; exit status 2.

    One line each argument: PkgforgeError(line, line, ...) for several (printed one under the
    other), so that a newline inside a name in a line is escaped, not taken for the next line."""

    exit_code = 2

    def __str__(self) -> str:
        return "\n".join(map(str, self.args))

    def lines(self) -> list[str]:
        """What the error says, one printable line each (`pkgforge: error: ` goes before the first)."""

        return [printable(str(line)) for line in self.args] or [""]


class BuildFailed(PkgforgeError):
    """colcon ran and at least one package failed; exit status 1.

    `failures`: (package, its log file, the last lines of the log), one per failing
    package; empty when colcon stopped before any package ran.
    """

    exit_code = 1

    def __init__(
        self,
        message: str,
        failures: Sequence[tuple[str | None, Path | None, str]] | None = None,
        status: int | None = None,
    ) -> None:
        super().__init__(message)
        self.failures = list(failures or [])
        self.status = status


# what to do about the OSErrors a user can cause, by errno name
_OS_FIXES = {
    "EACCES": "check its permissions (ls -l) or run as its owner",
    "EPERM": "check its permissions (ls -l) or run as its owner",
    "EROFS": "the file system is read-only: choose another folder",
    "ENOSPC": "the disk is full: free some space",
    "EDQUOT": "the disk quota is used up: free some space",
    "ENAMETOOLONG": "use a shorter name or a shallower folder",
    "ELOOP": "a symbolic link points back to itself: fix or remove it",
    "ENOENT": "check the path",
    "ENOTDIR": "a part of the path is a file, not a folder",
    "EISDIR": "it is a folder where a file is expected",
    "EMFILE": "too many open files: raise the limit (ulimit -n)",
}


def describe_os_error(exc: OSError) -> str:
    """One located line for an OSError: the file, what went wrong, what to do (printable: the
    file's name may hold a newline or an escape sequence)."""
    import errno

    where = exc.filename if exc.filename is not None else None
    if exc.filename2 is not None:
        where = f"{exc.filename} -> {exc.filename2}"
    what = exc.strerror or str(exc)
    fix = _OS_FIXES.get(errno.errorcode.get(exc.errno or 0, ""), "")
    text = f"{where}: {what}" if where is not None else what
    return printable(f"{text}; {fix}" if fix else text)
