"""`pkgforge fix` (and `verify --fix`): verify, apply the fixes of what it finds, report what remains."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, launch_arguments, main, package_of
from pkgforge.cli.options import check_selection, color_option, jobs_option, launch_options, strict_option
from pkgforge.errors import PkgforgeError


def _fix_targets(paths: Sequence[Path]) -> list[Path]:
    """What to fix: each PATH as given; a file stands for the package that holds it."""
    targets: list[Path] = []
    for path in paths or (Path("."),):
        if path.is_file():
            package = package_of(path)
            if package is None:
                continue  # a staged file outside any package
            path = package
        if path not in targets:
            targets.append(path)
    return targets


def run_fix_command(
    paths: Sequence[Path],
    *,
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    unsafe_fixes: bool,
    diff: bool,
    strict: bool,
    jobs: int | None,
    launch_args: Sequence[str],
    launch_timeout: float,
    color: str = "auto",
) -> NoReturn:
    """`pkgforge fix` and `pkgforge verify --fix`: fix, then report what was fixed and what remains."""
    from pkgforge.fix.report import diff_summary, render_fix
    from pkgforge.fix.run import FixOptions, run_fix
    from pkgforge.report import use_color
    from pkgforge.verify.config import Selection, split_keys
    from pkgforge.verify.pipeline import VerifyOptions

    options = FixOptions(
        VerifyOptions(
            Selection(split_keys(select), split_keys(ignore)),
            jobs=jobs,
            strict=strict,
            launch_timeout=launch_timeout,
            launch_arguments=launch_arguments(launch_args),
        ),
        unsafe=unsafe_fixes,
        diff=diff,
    )
    status = 0
    for target in _fix_targets(paths):
        try:
            run = run_fix(target, options)
        except PkgforgeError as error:
            fail(error)
        run.result.root = Path.cwd()  # paths as the user's shell shows them
        shown = use_color(color, sys.stderr if diff else sys.stdout)
        report, diff_text = render_fix(run, strict=strict, color=shown)
        if diff:  # the diff alone on stdout, a line of counts on stderr (ruff's --diff)
            click.echo(diff_text, nl=False)
            click.echo(diff_summary(run), nl=False, err=True)
        else:
            click.echo(report, nl=False, color=shown)
        status = max(status, run.exit_code(strict))
    sys.exit(status)


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("paths", nargs=-1, type=click.Path(path_type=Path))
@click.option("--diff", is_flag=True, help="Print the fixes as a unified diff; write nothing.")
@click.option(
    "--unsafe-fixes", is_flag=True, help="Also apply the fixes marked unsafe (`pkgforge checks` shows which)."
)
@check_selection("Run (and fix) only these checks: codes, code prefixes (PF2) or names; comma-separated.")
@strict_option("Exit 1 on any warning that remains.")
@color_option
@jobs_option("Packages and launch files processed")
@launch_options()
def fix(
    paths: tuple[Path, ...],
    diff: bool,
    unsafe_fixes: bool,
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    strict: bool,
    color: str,
    jobs: int | None,
    launch_args: tuple[str, ...],
    launch_timeout: float,
) -> None:
    """Verify PATH (default mode), apply the fixes of what it finds, and report what remains.

    PATH is a package, a workspace root or its src/, or files (each stands for its package;
    what the pre-commit hook passes). Exit status: 0 no errors remain, 1 errors remain or a
    file could not be written, 2 fix could not run.
    """
    run_fix_command(
        paths,
        select=select,
        ignore=ignore,
        unsafe_fixes=unsafe_fixes,
        diff=diff,
        strict=strict,
        jobs=jobs,
        launch_args=launch_args,
        launch_timeout=launch_timeout,
        color=color,
    )
