"""What `pkgforge fix` prints: what it fixed, what it could not, and what remains, by code."""

from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING

from pkgforge.report import from_here, printable
from pkgforge.report.text import location, render

if TYPE_CHECKING:
    from pkgforge.fix.run import FixRun


def render_fix(run: FixRun, *, strict: bool = False, color: bool = False) -> tuple[str, str]:
    """(the report, the diff): with --diff the report goes to stderr, the diff to stdout."""
    lines: list[str] = []
    verb = "would fix" if _diff_mode(run) else "fixed"
    for applied in run.fixed:
        d = applied.diagnostic
        lines.append(f"{verb} {location(d)}: {d.code} {d.name}: {printable(applied.description)}")
    for outcome in run.failures:
        lines.append(printable(f"pkgforge: error: {from_here(outcome.path)} not written: {outcome.problem}"))
    for d, why in run.not_fixed:
        lines.append(f"not fixed {location(d)}: {d.code} {d.name}: {printable(why)}")
    if run.unsafe_available:
        counts = Counter(f"{d.code} {d.name}" for d in run.unsafe_available)
        lines.append(
            f"{len(run.unsafe_available)} unsafe fix(es) not applied (--unsafe-fixes applies them): "
            + ", ".join(f"{k} ×{n}" for k, n in sorted(counts.items()))
        )
    if run.fixed and not _diff_mode(run):
        lines.append(f"fixed {len(run.fixed)} problem(s) in {len(run.files_written)} file(s)")
    remaining = Counter((d.code, d.name, d.severity.label) for d in run.result.diagnostics)
    title = "found" if _diff_mode(run) else "remaining"
    if remaining:
        lines.append(f"{title}, by code:")
        for (code, name, severity), count in sorted(remaining.items()):
            lines.append(f"  {code} {name} [{severity}] ×{count}")
    text = "\n".join(lines) + ("\n" if lines else "")
    detail = render(run.result, color=color, strict=strict)
    return text + detail, run.diff


def _diff_mode(run: FixRun) -> bool:
    return run.diff_mode


def diff_summary(run: FixRun) -> str:
    """What `fix --diff` says on stderr beside the diff, as ruff does: one line of counts (the
    findings themselves are `pkgforge verify`'s report); empty when there is nothing to say."""
    files = sum(1 for line in run.diff.splitlines() if line.startswith("+++ "))
    parts = []
    if run.fixed:
        parts.append(f"would fix {len(run.fixed)} problem(s) in {files} file(s)")
    if run.unsafe_available:
        parts.append(f"{len(run.unsafe_available)} more with --unsafe-fixes")
    if run.failures:
        parts.append(f"{len(run.failures)} file(s) could not be fixed")
    return "; ".join(parts) + "\n" if parts else ""
