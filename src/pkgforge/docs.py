"""docs/checks.md, generated from the check registry."""

from __future__ import annotations

from .checks.registry import all_checks

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


FIX_WORDS = {None: "none", "safe": "safe (`pkgforge fix`)",
             "unsafe": "unsafe (`pkgforge fix --unsafe-fixes`)"}


def checks_markdown() -> str:
    checks = all_checks()
    rows = [f"| {c.code} | [{c.name}](#{c.code.lower()}-{c.name}) | {c.severity.label} | {c.fix or '-'} | "
            f"{c.summary} |" for c in checks]
    sections = []
    for c in checks:
        sections.append(f"## {c.code} {c.name}\n\n"
                        f"**Severity:** {c.severity.label}. **Area:** {c.area}. "
                        f"**Automatic fix:** {FIX_WORDS[c.fix]}.\n\n"
                        f"{c.summary[0].upper()}{c.summary[1:]}. {c.explanation}\n\n"
                        f"**Fix:** {c.hint}.\n")
    return HEADER + "\n".join(rows) + "\n\n" + "\n".join(sections)
