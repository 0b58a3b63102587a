"""`pkgforge checks` and `pkgforge rule`: the registry of checks, listed and explained."""

from __future__ import annotations

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, main
from pkgforge.errors import PkgforgeError


@main.command(context_settings=CONTEXT_SETTINGS)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "markdown"]),
    default="text",
    show_default=True,
    help="markdown writes docs/checks.md.",
)
def checks(fmt: str) -> None:
    """List every check: code, name, default severity and what it finds."""
    from pkgforge.checks.catalogue import checks_markdown
    from pkgforge.checks.registry import all_checks

    if fmt == "markdown":
        click.echo(checks_markdown(), nl=False)
        return
    for check in all_checks():
        fix = check.fix or "-"
        click.echo(f"{check.code}  {check.name:<28} {check.severity.label:<8} {fix:<6} {check.summary}")


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("check")
def rule(check: str) -> None:
    """Explain one check, by code (PF302) or name (uninstalled-reference): why, an example, the fix."""
    from pkgforge.checks.catalogue import rule_text
    from pkgforge.checks.registry import close_checks, find_check

    found = find_check(check)
    if found is None:
        close = close_checks(check)
        also = f" (did you mean {', '.join(close)}?)" if close else ""
        fail(PkgforgeError(f"no check is coded or named '{check}'{also}; `pkgforge checks` lists them"))
    click.echo(rule_text(found), nl=False)
