"""ruff/mypy style: `path:line:col: CODE [severity] message (name)`, then `hint:`; paths as the
shell reaches them (relative to the current folder, else absolute), so a terminal opens them."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from pkgforge.diagnostics import Diagnostic, Severity
from pkgforge.report import from_here, printable

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

COLORS = {Severity.ERROR: "red", Severity.WARNING: "yellow", Severity.INFO: "cyan"}


def location(diagnostic: Diagnostic, shown: Callable[[Path], str] = from_here) -> str:
    """`path:line:col`, the path printable (a file's name may hold any character but / and NUL)."""
    parts = [printable(shown(diagnostic.path))]
    if diagnostic.line is not None:
        parts.append(str(diagnostic.line))
        if diagnostic.column is not None:
            parts.append(str(diagnostic.column))
    return ":".join(parts)


def counted(number: int, noun: str) -> str:
    """`1 error`, `2 errors`, `0 packages`."""
    return f"{number} {noun}" + ("" if number == 1 else "s")


def summary(result: VerifyResult) -> str:
    return printable(  # the distro may come from $ROS_DISTRO as it is
        f"{counted(result.count(Severity.ERROR), 'error')}, {counted(result.count(Severity.WARNING), 'warning')}, "
        f"{counted(result.count(Severity.INFO), 'info')} in {counted(len(result.reports), 'package')}"
        + engine_note(result)
        + sandbox_note(result)
    )


def sandbox_note(result: VerifyResult) -> str:
    """Said only when the kernel did not enforce what verify promises (sandbox/confinement.py)."""
    from pkgforge.sandbox.confinement import weaker

    note = weaker(result.sandbox) if result.sandbox is not None else None
    return f"; {note}" if note else ""


def engine_note(result: VerifyResult) -> str:
    """Which launch engine evaluated the launch files; for the built-in one, the distro whose
    launch API it followed and where that came from (`humble from pkgforge.toml`)."""
    from pkgforge.verify.distros import NEWEST_LTS_SOURCE

    if result.engine != "ros":
        chosen = result.launch_distros
        if chosen:
            said = [
                f"{distro}, {source}" if source == NEWEST_LTS_SOURCE else f"{distro} from {source}"
                for distro, source in chosen
            ]
            return f"; launch: built-in engine ({'; '.join(said)})"
        return "; launch: built-in engine" + (f" ({result.distro})" if result.distro else "")
    return f"; launch: ROS 2 {result.distro or '(distro unknown)'}"


def render(
    result: VerifyResult,
    *,
    color: bool = False,
    strict: bool = False,
    quiet: bool = False,
    statistics: bool = False,
) -> str:
    """The report: each diagnostic and its hint (`quiet`: without the hints), then the summary;
    `statistics`: one line per code with its count instead of the diagnostics (ruff's)."""

    def style(text: str, **kwargs: Any) -> str:
        return click.style(text, **kwargs) if color else text

    if statistics:
        return "\n".join([*statistics_lines(result), summary(result)]) + "\n"
    lines = []
    for diagnostic in result.diagnostics:
        severity = style(f"[{diagnostic.severity.label}]", fg=COLORS[diagnostic.severity], bold=True)
        lines.append(
            f"{style(location(diagnostic), bold=True)}: "
            f"{style(diagnostic.code, bold=True)} {severity} {printable(diagnostic.message)} "
            f"({diagnostic.name})"
        )
        if not quiet:
            lines.append(f"    hint: {printable(diagnostic.hint)}")
    lines.append(summary(result))
    return "\n".join(lines) + "\n"


def statistics_lines(result: VerifyResult) -> list[str]:
    """`count  CODE  name [severity]` per code, the most frequent first (a code found at several
    severities, e.g. after [severity] or a finding's own, lists them)."""
    counts: dict[tuple[str, str], list[Severity]] = {}
    for diagnostic in result.diagnostics:
        counts.setdefault((diagnostic.code, diagnostic.name), []).append(diagnostic.severity)
    width = len(str(max((len(found) for found in counts.values()), default=0)))
    lines = []
    for (code, name), found in sorted(counts.items(), key=lambda item: (-len(item[1]), item[0])):
        levels = ", ".join(level.label for level in sorted(set(found), reverse=True))
        lines.append(f"{len(found):>{width}}  {code}  {name} [{levels}]")
    return lines
