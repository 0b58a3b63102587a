"""`pkgforge build`: the workspace built with colcon (merged install)."""

from __future__ import annotations

import os
from pathlib import Path

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, main
from pkgforge.cli.options import path_option
from pkgforge.errors import PkgforgeError


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("path", type=click.Path(path_type=Path), default=".")
@path_option("--build-base", kind="folder", help="Build folder [default: build/ in the workspace root].")
@path_option(
    "--install-base",
    kind="folder",
    help="Install folder, merged layout [default: install/ in the workspace root].",
)
@click.option(
    "--packages-select",
    multiple=True,
    metavar="NAME",
    help="Build only these packages (and what they depend on). Repeatable.",
)
@click.option(
    "--build-tests",
    is_flag=True,
    help="Configure with BUILD_TESTING=ON (needs ament_lint_auto and the test tools).",
)
@click.option(
    "--no-stubs", is_flag=True, help="Do not stub declared build dependencies that are not installed here."
)
@click.option(
    "--parallel-workers",
    type=click.IntRange(1),
    default=None,
    help="Packages built at once [default: colcon's, the number of cores].",
)
@click.option(
    "--cmake-args",
    "cmake_args",
    multiple=True,
    metavar="ARG",
    help="Extra CMake argument, e.g. --cmake-args=-DFOO=1. Repeatable.",
)
def build(
    path: Path,
    build_base: Path | None,
    install_base: Path | None,
    packages_select: tuple[str, ...],
    build_tests: bool,
    no_stubs: bool,
    parallel_workers: int | None,
    cmake_args: tuple[str, ...],
) -> None:
    """Build the workspace or package at PATH with colcon (merged install)."""
    from pkgforge.build.colcon import default_options, run_build
    from pkgforge.workspace import locate

    try:
        workspace = locate(path)
        options = default_options(workspace, build_base, install_base)
        options.build_tests = build_tests
        options.stub_missing = not no_stubs
        options.packages_select = tuple(packages_select)
        options.parallel_workers = parallel_workers
        options.cmake_args = tuple(cmake_args)
        result = run_build(workspace, options)
    except PkgforgeError as error:
        fail(error)
    from pkgforge.report.text import counted

    click.echo(
        f"built {counted(len(result.packages), 'package')} into {os.path.relpath(result.install_base)}/"
    )
