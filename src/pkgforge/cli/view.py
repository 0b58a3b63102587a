"""`pkgforge view`: each robot model verify processes, rendered headless as PNG and SVG."""

from __future__ import annotations

from pathlib import Path

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, launch_arguments, main
from pkgforge.cli.options import launch_options
from pkgforge.errors import PkgforgeError


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("target", default=".", metavar="[PATH|PACKAGE|MODEL]")
@click.option(
    "-o",
    "--output",
    "out",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("pkgforge-view"),
    show_default=True,
    help="Folder for the images.",
)
@click.option(
    "--joint",
    "joints",
    multiple=True,
    metavar="NAME:=VALUE",
    help="A joint position (radians or metres) instead of zero. Repeatable.",
)
@launch_options(
    arg_help="A launch argument's value (xacro arguments of a model file). Repeatable.",
    timeout_help="Seconds one launch file or model may take to process.",
)
@click.option("--no-frame", is_flag=True, help="Do not draw the root link's frame.")
def view(
    target: str,
    out: Path,
    joints: tuple[str, ...],
    launch_args: tuple[str, ...],
    launch_timeout: float,
    no_frame: bool,
) -> None:
    """Render each robot model verify processes: four views (front, side, top, iso) as PNG and the
    kinematic tree as SVG, headless (no display, no GPU).

    TARGET is a package or workspace folder, a package name, or one .urdf/.xacro file
    (in a workspace package, or installed in a ROS prefix's share/<package>/).
    """
    from pkgforge.verify.pipeline import VerifyOptions
    from pkgforge.view import Artifacts, parse_joints
    from pkgforge.view.command import run_view

    try:
        artifacts = Artifacts(out, parse_joints(joints), frame=not no_frame)
        if artifacts.missing:
            raise PkgforgeError(artifacts.missing)
        options = VerifyOptions(launch_timeout=launch_timeout, launch_arguments=launch_arguments(launch_args))
        run_view(target, artifacts, options)
        artifacts.finish()
    except PkgforgeError as error:
        fail(error)
    from pkgforge.report import printable

    for problem in artifacts.problems:
        click.echo(f"pkgforge: warning: {printable(problem)}", err=True)
    if not artifacts.entries:
        fail(
            PkgforgeError(
                f"no robot model to render under {target} (verify says why: pkgforge verify {target})"
            )
        )
    for entry in artifacts.entries:
        files = [i["file"] for i in entry["images"]] + [entry["tree"]]
        click.echo(printable(f"{entry['model']}: {', '.join(str(out / f) for f in files)}"))
