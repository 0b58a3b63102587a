"""`pkgforge verify-files`: the packages that hold the files pre-commit passes, each verified once."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import NoReturn

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, main, package_of, report_internal_errors
from pkgforge.cli.options import color_option, strict_option
from pkgforge.errors import PkgforgeError


@main.command("verify-files", context_settings=CONTEXT_SETTINGS)
@click.argument("files", nargs=-1, type=click.Path(path_type=Path))
@strict_option("Treat warnings as errors.")
@color_option
def verify_files(files: tuple[Path, ...], strict: bool, color: str) -> NoReturn:
    """Verify the packages that hold FILES (pre-commit passes the staged files).

    Each package found above a file is verified once, in the fast default mode.
    """
    from pkgforge.report import render, use_color
    from pkgforge.verify.config import Selection
    from pkgforge.verify.pipeline import VerifyOptions
    from pkgforge.verify.pipeline import verify as run_verify

    colored = use_color(color, sys.stdout)
    packages: list[Path] = []
    for file in files:
        package = package_of(file)
        if package is not None and package not in packages:
            packages.append(package)
    status = 0
    for package in packages:
        try:
            result = run_verify(package, VerifyOptions(Selection(), strict=strict))
        except PkgforgeError as error:
            fail(error)
        result.root = Path.cwd()  # paths as the repository shows them
        if result.diagnostics:
            click.echo(render("text", result, color=colored), nl=False, color=colored)
        report_internal_errors(result)
        status = max(status, result.exit_code(strict))
    sys.exit(status)
