"""docs/checks.md, generated from the check registry."""

from __future__ import annotations

import functools

from pkgforge.checks.registry import Check, all_checks

# where the catalogue lives, relative to the repository root (and in the sdist); the wheel ships
# a copy as pkgforge/docs/checks.md (pyproject.toml's force-include)
DOCS_PATH = "docs/checks.md"
# the catalogue's URL, or the URL of the folder holding it (a fork's or a mirror's docs/)
DOCS_URL_ENV = "PKGFORGE_DOCS_URL"

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
            f"**Fix:** {c.hint}.\n" + _sources_markdown(c) + _examples_markdown(c)
        )
    return HEADER + "\n".join(rows) + "\n\n" + "\n".join(sections)


def help_uri(check: Check) -> str:
    """The URL of the check's section in the catalogue (`pkgforge rule`, SARIF's helpUri)."""
    return f"{docs_url()}#{check.anchor}"


def docs_url() -> str:
    """The catalogue's URL: PKGFORGE_DOCS_URL (the file's URL, or its folder's); else the
    distribution's `Documentation` project URL (pyproject.toml [project.urls]); else the
    catalogue of this pkgforge's own repository (an editable install's docs/checks.md) or its
    wheel's copy, as a file:// URL that opens where pkgforge is installed."""
    import os
    from pathlib import Path

    given = os.environ.get(DOCS_URL_ENV, "").strip()
    if given:
        return given if given.endswith(".md") else given.rstrip("/") + "/checks.md"
    published = _project_url("Documentation")
    if published:
        return published.rstrip("/") + "/checks.md" if not published.endswith(".md") else published
    package = Path(__file__).resolve().parent.parent
    for candidate in (package.parent.parent / DOCS_PATH, package / DOCS_PATH):
        if candidate.is_file():
            return candidate.as_uri()
    return DOCS_PATH  # a copy without its docs: the path every checkout and sdist has


@functools.lru_cache(maxsize=4)
def _project_url(label: str) -> str | None:
    from importlib import metadata

    try:
        urls: list[str] = [str(u) for u in metadata.metadata("ros-pkgforge").get_all("Project-URL") or []]
    except metadata.PackageNotFoundError:
        return None
    for entry in urls:
        name, _, url = entry.partition(",")
        if name.strip().lower() == label.lower() and url.strip():
            return url.strip()
    return None


def _fence(snippet: str) -> str:
    return "```\n" + snippet.strip("\n") + "\n```\n"


def _sources_markdown(check: Check) -> str:
    from pkgforge.checks.sources import sources

    read = sources(check.code)
    return "\n**Sources:**\n\n" + "".join(f"- {source}\n" for source in read) if read else ""


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
    ]
    from pkgforge.checks.sources import sources

    lines += [
        textwrap.fill(f"Source: {source}", 88, subsequent_indent="  ", break_on_hyphens=False)
        for source in sources(check.code)
    ]
    lines.append(f"Documentation: {help_uri(check)}")
    return "\n".join(lines) + "\n"
