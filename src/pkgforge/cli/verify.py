"""`pkgforge verify`: the package(s) at PATH checked against their install tree."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, launch_arguments, main, report_internal_errors
from pkgforge.cli.fix import run_fix_command
from pkgforge.cli.options import (
    check_selection,
    color_option,
    jobs_option,
    launch_options,
    path_option,
    sandbox_options,
    strict_option,
)
from pkgforge.errors import PkgforgeError
from pkgforge.model.distros import DISTROS
from pkgforge.report import FORMATS

if TYPE_CHECKING:
    from pkgforge.sandbox.zygote import Zygote


def _fork_server_first(
    launch_engine: str, ros_prefix: Path | None, target_distro: str | None
) -> Zygote | None:
    """The launch workers' fork server, started before verify imports anything more when no
    cached answer can spare it (--no-cache, launch files to evaluate): its ~0.1 s of imports then
    run beside verify's own, and one package's launch files wait less for it (~15 ms)."""
    from pkgforge.launch.engines import choose
    from pkgforge.sandbox.zygote import start_zygote

    try:
        return start_zygote(choose(launch_engine, ros_prefix, distro=target_distro))
    except PkgforgeError:
        return None  # verify chooses the engine again and says why


def _into_meta(ctx: click.Context, param: click.Parameter, value: bool) -> None:
    """verify's --fix options: kept in the context, not in verify()'s signature."""
    if param.name:  # an option's name (fix, unsafe_fixes)
        ctx.meta[param.name] = value


def _explain_sandbox(launch_engine: str, ros_prefix: Path | None, target_distro: str | None) -> None:
    """verify --explain-sandbox: a worker started as verify starts one says what confines it."""
    from pkgforge.launch.resolve import confinement_here
    from pkgforge.sandbox.confinement import describe
    from pkgforge.verify.pipeline import VerifyOptions

    engine = VerifyOptions(launch_engine=launch_engine, ros_prefix=ros_prefix, distro=target_distro).engine()
    try:
        confinement = confinement_here(engine)
    except OSError as error:
        fail(PkgforgeError(f"no launch worker could be started here: {error}"))
    click.echo("\n".join(describe(confinement)))


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("path", type=click.Path(path_type=Path), default=".")
@click.option(
    "--format", "fmt", type=click.Choice(FORMATS), default="text", show_default=True, help="Output format."
)
@path_option("--output", "-o", kind="file", help="Write the report to this file instead of standard output.")
@path_option("--junit-xml", kind="file", help="Also write a JUnit XML report here (for CI test reports).")
@check_selection("Run only these checks: codes, code prefixes (PF2) or names; comma-separated.")
@strict_option("Treat warnings as errors (exit 1 on any warning).")
@click.option(
    "--statistics",
    is_flag=True,
    help="Print one line per check code with its count instead of the diagnostics (text report).",
)
@click.option(
    "--quiet", "-q", is_flag=True, help="Print the findings and the summary line only: no hints, no progress."
)
@color_option
@jobs_option("Packages verified")
@click.option(
    "--build",
    "build_tree",
    is_flag=True,
    help="Resolve against a real colcon build into build/pkgforge-verify/ "
    "[default: the tree predicted from the install rules].",
)
@path_option(
    "--install-base",
    kind="folder",
    help="Resolve against an existing install folder from your own colcon build "
    "(merged or isolated); nothing is rebuilt.",
)
@launch_options()
@sandbox_options
@click.option(
    "--no-cache",
    is_flag=True,
    help="Verify every package again instead of reusing results of unchanged ones "
    "(cache: build/pkgforge-cache/, safe to delete).",
)
@click.option(
    "--simulate",
    is_flag=True,
    help="Also drop-test each robot model in MuJoCo (base fixed, joints limp, gravity, 2 s; "
    "needs pip install 'ros-pkgforge[simulate]'), in a separate limited process per model.",
)
@click.option(
    "--distro",
    "target_distro",
    type=click.Choice(list(DISTROS)),
    default=None,
    help="The ROS 2 distro the packages target [default: ROS_DISTRO, pkgforge.toml "
    "[verify] distro, the package's CI file, else every active distro].",
)
@path_option(
    "--explain-launch",
    "explain_launch",
    metavar="FILE",
    help="Print how FILE resolves in the install tree, then exit.",
)
@path_option(
    "--explain-model",
    "explain_model",
    metavar="FILE",
    help="Print the model's link/joint tree with its meshes, then exit (xacro arguments from --launch-arg).",
)
@click.option(
    "--explain-sandbox",
    "explain_sandbox",
    is_flag=True,
    help="Print what confines the launch files and xacro verify runs on this machine, then exit.",
)
@path_option(
    "--artifacts",
    "artifacts_dir",
    kind="folder",
    metavar="DIR",
    help="Also write pictures of every processed robot model into DIR (four "
    "views, kinematic tree SVG, summary.md), as `pkgforge view` does.",
)
@click.option(
    "--fix",
    is_flag=True,
    expose_value=False,
    callback=_into_meta,
    help="Apply the fixes of what verify finds: the same as `pkgforge fix PATH`.",
)
@click.option(
    "--unsafe-fixes",
    is_flag=True,
    expose_value=False,
    callback=_into_meta,
    help="With --fix: also apply the fixes marked unsafe.",
)
def verify(
    path: Path,
    fmt: str,
    output: Path | None,
    junit_xml: Path | None,
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    strict: bool,
    statistics: bool,
    quiet: bool,
    color: str,
    jobs: int | None,
    build_tree: bool,
    install_base: Path | None,
    launch_args: tuple[str, ...],
    launch_timeout: float,
    worker_memory: int | None,
    launch_engine: str,
    ros_prefix: Path | None,
    no_cache: bool,
    simulate: bool,
    target_distro: str | None,
    explain_launch: Path | None,
    explain_model: Path | None,
    explain_sandbox: bool,
    artifacts_dir: Path | None,
) -> None:
    """Check the package(s) at PATH against their install tree.

    PATH is a package, a workspace root or its src/. Exit status: 0 no errors,
    1 errors found (or warnings with --strict), 2 verify could not run.
    """
    context = click.get_current_context()
    if explain_sandbox:
        _explain_sandbox(launch_engine, ros_prefix, target_distro)
        return
    if simulate:
        from pkgforge.simulate import available

        if not available():
            raise click.UsageError("--simulate needs MuJoCo: pip install 'ros-pkgforge[simulate]'")
    fork_server = None
    if no_cache and not (build_tree or select or explain_launch or explain_model or context.meta.get("fix")):
        fork_server = _fork_server_first(launch_engine, ros_prefix, target_distro)
        if fork_server is not None:
            context.call_on_close(fork_server.close)  # however verify ends
    from pkgforge.report import render
    from pkgforge.verify.config import Selection, split_keys
    from pkgforge.verify.pipeline import VerifyOptions
    from pkgforge.verify.pipeline import verify as run_verify

    if build_tree and install_base is not None:
        fail(PkgforgeError("--build and --install-base exclude each other: build, or read an existing tree"))
    if statistics and fmt != "text":
        fail(PkgforgeError(f"--statistics prints a text report: drop --format {fmt}"))
    meta = click.get_current_context().meta
    apply_fixes, unsafe_fixes = meta.get("fix", False), meta.get("unsafe_fixes", False)
    if unsafe_fixes and not apply_fixes:
        fail(PkgforgeError("--unsafe-fixes goes with --fix"))
    if apply_fixes:
        others = [
            name
            for name, given in (
                ("--build", build_tree),
                ("--install-base", install_base is not None),
                ("--format", fmt != "text"),
                ("--output", output is not None),
                ("--junit-xml", junit_xml is not None),
                ("--explain-launch", explain_launch is not None),
                ("--explain-model", explain_model is not None),
            )
            if given
        ]
        if others:
            fail(PkgforgeError(f"--fix runs verify's default mode and prints text: drop {', '.join(others)}"))
        run_fix_command(
            (path,),
            select=select,
            ignore=ignore,
            unsafe_fixes=unsafe_fixes,
            diff=False,
            strict=strict,
            jobs=jobs,
            launch_args=launch_args,
            launch_timeout=launch_timeout,
            color=color,
        )
    arguments = launch_arguments(launch_args)
    mode = "build" if build_tree else "install-base" if install_base is not None else "predicted"
    options = VerifyOptions(
        Selection(split_keys(select), split_keys(ignore)),
        jobs=jobs,
        strict=strict,
        mode=mode,
        install_base=install_base,
        launch_timeout=launch_timeout,
        launch_arguments=arguments,
        use_cache=not no_cache,
        worker_memory=worker_memory,
        simulate=simulate,
        distro=target_distro,
        launch_engine=launch_engine,
        ros_prefix=ros_prefix,
        progress=not quiet,
    )
    try:
        if explain_launch is not None:
            from pkgforge.verify.explain import explain_launch_file

            click.echo(explain_launch_file(path, explain_launch, options), nl=False)
            return
        if explain_model is not None:
            from pkgforge.verify.explain import explain_model_file

            click.echo(explain_model_file(path, explain_model, options), nl=False)
            return
        artifacts = None
        if artifacts_dir is not None:
            from pkgforge.view import Artifacts

            # the pictures come from the models this run processes: no cached results
            artifacts = Artifacts(artifacts_dir)
            options.on_models, options.use_cache = artifacts, False
            if artifacts.missing:
                click.echo(
                    f"pkgforge: --artifacts writes the kinematic trees only; {artifacts.missing}", err=True
                )
        result = run_verify(path, options, fork_server)
        if artifacts is not None:
            artifacts.finish()
    except PkgforgeError as error:
        fail(error)
    from pkgforge.report import use_color

    colored = fmt == "text" and output is None and use_color(color, sys.stdout)
    if fmt == "text":
        from pkgforge.report.text import render as render_text

        text = render_text(result, color=colored, strict=strict, quiet=quiet, statistics=statistics)
    else:
        text = render(fmt, result, color=colored, strict=strict)
    if output is not None:
        try:
            output.write_text(text, encoding="utf-8")
        except OSError as exc:
            fail(PkgforgeError(f"cannot write {output}: {exc.strerror}"))
        if fmt != "text" and not quiet:
            from pkgforge.report.text import summary

            click.echo(summary(result), err=True)
    else:
        click.echo(text, nl=False, color=colored)
    if junit_xml is not None:
        try:
            junit_xml.parent.mkdir(parents=True, exist_ok=True)
            junit_xml.write_text(render("junit", result, strict=strict), encoding="utf-8")
        except OSError as exc:
            fail(PkgforgeError(f"cannot write {junit_xml}: {exc.strerror}"))
    report_internal_errors(result)
    sys.exit(result.exit_code(strict))
