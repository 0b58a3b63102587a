"""What a check reports: a Diagnostic, located at a file and line, with a fix hint."""

from __future__ import annotations

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


@dataclass(frozen=True)
class Diagnostic:
    code: str
    name: str
    severity: Severity
    package: str
    path: Path  # absolute
    line: int | None
    column: int | None
    message: str
    hint: str
    # the finding's fix data (pkgforge fix); not part of any report
    fix: dict[str, Any] | None = field(default=None, compare=False, hash=False, repr=False)

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
