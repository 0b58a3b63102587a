"""docs/checks.md, generated from the check registry."""

from __future__ import annotations

from pkgforge.checks.registry import Check, all_checks

# where the catalogue lives, relative to the repository root (and in the sdist); SARIF's helpUri
# points at a check's anchor in it. pkgforge has no public documentation site to point at.
DOCS_PATH = "docs/checks.md"

HEADER = """# pkgforge checks

Generated from the check registry by `pkgforge checks --format markdown`; do not edit.
Select or ignore checks by code (`PF101`), code prefix (`PF1`) or name (`manifest-invalid`) with
`--select`/`--ignore`, in `pkgforge.toml`, or on the line before with
`# pkgforge: ignore=NAME` (CMake, Python) or `<!-- pkgforge: ignore=NAME -->` (XML).
The fix column says what `pkgforge fix` does: `safe` fixes are applied by default, `unsafe` ones
(they may change more than the defect) only with `--unsafe-fixes`; `-` has no automatic fix.

| code | name | severity | fix | what |
| --- | --- | --- | --- | --- |
"""


FIX_WORDS = {
    None: "none",
    "safe": "safe (`pkgforge fix`)",
    "unsafe": "unsafe (`pkgforge fix --unsafe-fixes`)",
}


def checks_markdown() -> str:
    checks = all_checks()
    rows = [
        f"| {c.code} | [{c.name}](#{c.anchor}) | {c.severity.label} | {c.fix or '-'} | {c.summary} |"
        for c in checks
    ]
    sections = []
    for c in checks:
        sections.append(
            f"## {c.code} {c.name}\n\n"
            f"**Severity:** {c.severity.label}. **Area:** {c.area}. "
            f"**Automatic fix:** {FIX_WORDS[c.fix]}.\n\n"
            f"{c.summary[0].upper()}{c.summary[1:]}. {c.explanation}\n\n"
            f"**Fix:** {c.hint}.\n" + _examples_markdown(c)
        )
    return HEADER + "\n".join(rows) + "\n\n" + "\n".join(sections)


def help_uri(check: Check) -> str:
    """The check's section in the catalogue (a stable relative reference: pkgforge has no site)."""
    return f"{DOCS_PATH}#{check.anchor}"


def _fence(snippet: str) -> str:
    return "```\n" + snippet.strip("\n") + "\n```\n"


def _examples_markdown(check: Check) -> str:
    if not check.bad:
        return ""
    text = "\n**Example:**\n\n" + _fence(check.bad)
    if check.good:
        text += "\n**Fixed:**\n\n" + _fence(check.good)
    return text


def _indent(snippet: str) -> str:
    return "\n".join("    " + line if line else "" for line in snippet.strip("\n").splitlines())


def rule_text(check: Check) -> str:
    """`pkgforge rule CODE|NAME`: one check, as `ruff rule` or `catkin_lint --help-problem` show one."""
    import textwrap

    lines = [
        f"{check.code} {check.name} ({check.severity.label}, area {check.area})",
        "",
        textwrap.fill(f"{check.summary[0].upper()}{check.summary[1:]}. {check.explanation}", 88),
    ]
    if check.bad:
        lines += ["", "Example:", "", _indent(check.bad)]
    if check.good:
        lines += ["", "Fixed:", "", _indent(check.good)]
    lines += [
        "",
        textwrap.fill(f"Fix: {check.hint}.", 88),
        f"Automatic fix: {FIX_WORDS[check.fix]}.",
        f"Documentation: {help_uri(check)}",
    ]
    return "\n".join(lines) + "\n"
