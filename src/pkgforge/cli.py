"""Command line: parse options, call the library, map errors to exit codes."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, TypeVar

if sys.argv and os.path.basename(sys.argv[0]) == "pkgforge":  # the console script, before click loads:
    from pkgforge.sandbox.processes import install_signal_handlers  # a Ctrl-C while starting exits 130 too

    install_signal_handlers()

import click  # noqa: E402

from pkgforge import __version__  # noqa: E402
from pkgforge.errors import PkgforgeError  # noqa: E402
from pkgforge.model.distros import DISTROS, NEWEST_LTS, default_distro
from pkgforge.report import COLOR_CHOICES, FORMATS  # noqa: E402
from pkgforge.scaffold.kinds import BUILD_TYPES, CI_SYSTEMS, LAUNCH_FORMATS

if TYPE_CHECKING:
    from pkgforge.sandbox.zygote import Zygote
    from pkgforge.scaffold.notes import Notes
    from pkgforge.verify.pipeline import VerifyResult

    # click 8.2 made ParamType generic (value, input); click 8.1 (which pyproject allows) is not
    _SizeType = click.ParamType[int | None, object]
else:
    _SizeType = click.ParamType

_Command = TypeVar("_Command", bound=Callable[..., Any])

CONTEXT_SETTINGS = {"help_option_names": ["-h", "--help"], "max_content_width": 100}


# --debug (or PKGFORGE_DEBUG=1): show the traceback of an internal error
DEBUG = {"on": bool(os.environ.get("PKGFORGE_DEBUG"))}


def fail(error: PkgforgeError) -> NoReturn:
    click.echo("pkgforge: error: " + "\n".join(error.lines()), err=True)
    sys.exit(error.exit_code)


def _report_note() -> str:
    shown = "" if DEBUG["on"] else ", with the traceback that `pkgforge --debug ...` prints"
    return f" to pkgforge's maintainers (pkgforge {__version__}{shown})"


def internal_error(what: str, trace: str) -> NoReturn:
    """An unexpected exception inside pkgforge: exit 2, the traceback only under --debug."""
    from pkgforge.report import printable

    click.echo(f"pkgforge: internal error: {printable(what)}; please report it{_report_note()}", err=True)
    if DEBUG["on"]:
        click.echo(trace.rstrip(), err=True)
    sys.exit(2)


def _exit_now(status: int) -> NoReturn:
    """Exit with `status` as the interpreter would, without its teardown of every module and
    object: the streams flushed and the exit handlers run (temporary folders, coverage data)."""
    import atexit

    for stream in (sys.stdout, sys.stderr):
        try:
            if stream is not None:  # None: started with that descriptor closed (`>&-`)
                stream.flush()
        except (OSError, ValueError):
            pass
    atexit._run_exitfuncs()
    os._exit(status)


class _Group(click.Group):
    def main(self, args: Sequence[str] | None = None, *rest: Any, **kwargs: Any) -> Any:
        from pkgforge.sandbox.processes import Interrupted, install_signal_handlers

        if args is None:
            # the command line itself (not a caller passing arguments, as tests do): Ctrl-C,
            # SIGTERM, SIGHUP kill every process pkgforge started, and exit 128 + signal
            install_signal_handlers()
        try:
            return super().main(args, *rest, **kwargs)
        except Interrupted as stop:
            # unwound (every child killed, temporary trees removed): skip the interpreter's slow
            # teardown of every module, so Ctrl-C returns the prompt at once
            _exit_now(128 + stop.signum)  # its exit status (stop.code)
        except SystemExit as done:
            if args is None and (done.code is None or isinstance(done.code, int)):
                # the command has ended (its output written, its files closed, its processes and
                # temporary trees gone): the interpreter's teardown would only free every object
                # one by one, ~10 ms of a pre-commit run and ~50 ms at 800 packages
                _exit_now(done.code or 0)
            raise

    def invoke(self, ctx: click.Context) -> Any:
        """Every command's errors end as one line and exit 2: a PkgforgeError as it says, an
        OSError located at its file, anything else as an internal error (traceback under --debug)."""
        import traceback

        from pkgforge.errors import describe_os_error

        try:
            return super().invoke(ctx)
        except (
            click.exceptions.ClickException,
            click.exceptions.Exit,
            click.exceptions.Abort,
            SystemExit,
            KeyboardInterrupt,
        ):
            raise
        except PkgforgeError as error:
            fail(error)
        except BrokenPipeError:  # `pkgforge verify | head`: the reader left; no message to anyone
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            sys.exit(1)
        except OSError as exc:
            click.echo(f"pkgforge: error: {describe_os_error(exc)}", err=True)
            if DEBUG["on"]:
                click.echo(traceback.format_exc().rstrip(), err=True)
            sys.exit(2)
        except RecursionError as exc:
            internal_error(f"RecursionError: {exc} (input nested too deep)", traceback.format_exc())
        except Exception as exc:  # noqa: BLE001 - a bug in pkgforge: never a bare traceback
            internal_error(f"{type(exc).__name__}: {exc}", traceback.format_exc())


@click.group(cls=_Group, context_settings=CONTEXT_SETTINGS)
@click.version_option(__version__, "--version", prog_name="pkgforge")
@click.option("--debug", is_flag=True, help="On an internal error, print its traceback.")
def main(debug: bool) -> None:
    """Scaffold, build and verify ROS 2 robot description packages."""
    if debug:
        DEBUG["on"] = True


class MemorySize(_SizeType):
    """A size such as 2G or 512M (bytes), or `unlimited`."""

    name = "SIZE"
    minimum = 256 * 2**20

    def convert(self, value: object, param: click.Parameter | None, ctx: click.Context | None) -> int | None:
        from pkgforge.sandbox.processes import format_size, parse_size

        if isinstance(value, int) or value is None:
            return value
        if str(value).strip().lower() in ("unlimited", "none"):
            return None
        try:
            size = parse_size(str(value))
        except ValueError as exc:
            self.fail(str(exc), param, ctx)
        if size < self.minimum:
            self.fail(
                f"{value} is below the {format_size(self.minimum)} a launch worker needs to start", param, ctx
            )
        return size


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("name", required=False)
@click.option(
    "--distro",
    type=click.Choice(list(DISTROS)),
    default=default_distro,
    show_default=f"ROS_DISTRO, else {NEWEST_LTS}",
    help="ROS 2 distribution the package targets.",
)
@click.option(
    "--build-type",
    type=click.Choice(BUILD_TYPES),
    default="ament_cmake",
    show_default=True,
    help="Package build type.",
)
@click.option(
    "--launch-format",
    type=click.Choice(LAUNCH_FORMATS),
    default="py",
    show_default=True,
    help="Format of launch/display.launch.*.",
)
@click.option(
    "--destination",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Folder to create the package in [default: ./src in a workspace root, else .].",
)
@click.option("--maintainer-name", default=None, help="[default: git config user.name]")
@click.option("--maintainer-email", default=None, help="[default: git config user.email]")
@click.option(
    "--license",
    "license_",
    default="Apache-2.0",
    show_default=True,
    help="License identifier for package.xml.",
)
@click.option("--description", default="", help="package.xml description.")
@click.option(
    "--force",
    count=True,
    help="Write into an existing package folder: add missing generated files; files that "
    "differ from what pkgforge writes are listed and refused unless given twice "
    "(--force --force). Other files stay.",
)
@click.option(
    "--ci",
    type=click.Choice(CI_SYSTEMS),
    multiple=True,
    help="Add a CI workflow that builds and verifies the package on ros:<distro>. Repeatable.",
)
@click.option(
    "--from-urdf",
    "from_urdf",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    metavar="FILE",
    help="Bring in this .urdf/.urdf.xacro (a CAD export) with every mesh and "
    "texture it names, instead of the example robot; then verify.",
)
@click.option(
    "--mesh-uri",
    type=click.Choice(["package", "find"]),
    default="package",
    show_default=True,
    help="With --from-urdf: rewrite mesh URIs as package://NAME/meshes/... or "
    "file://$(find NAME)/meshes/....",
)
@click.option(
    "--add-root-link",
    is_flag=True,
    help="With --from-urdf: add a massless root link above a root link with an inertia, which KDL "
    "ignores (PF604); models are otherwise copied byte for byte.",
)
@click.option(
    "--sim",
    type=click.Choice(["gz"]),
    default=None,
    help="Add what Gazebo and ros2_control need for the target distro: worlds/empty.sdf, "
    "launch/sim.launch.py (ros_gz_sim, the clock bridge, the spawners), <ros2_control> with "
    "gz_ros2_control (ign_ros2_control on humble) and config/controllers.yaml.",
)
def new(
    name: str | None,
    distro: str,
    build_type: str,
    launch_format: str,
    destination: Path | None,
    maintainer_name: str | None,
    maintainer_email: str | None,
    license_: str,
    description: str,
    force: int,
    ci: tuple[str, ...],
    from_urdf: Path | None,
    mesh_uri: str,
    add_root_link: bool,
    sim: str | None,
) -> None:
    """Create a robot description package NAME that builds and shows in RViz2 (with --from-urdf,
    NAME defaults to the model's package name, made valid)."""
    from pkgforge.scaffold.package import create_package, default_destination, make_spec

    name_note = None
    if name is None:
        if from_urdf is None:
            raise click.UsageError("Missing argument 'NAME' (it may be left out with --from-urdf only).")
        from pkgforge.scaffold.from_urdf import default_name

        try:
            name, name_note = default_name(from_urdf)
        except PkgforgeError as error:
            fail(error)

    options: dict[str, Any] = dict(  # make_spec's keyword arguments
        name=name,
        distro=distro,
        build_type=build_type,
        launch_format=launch_format,
        maintainer_name=maintainer_name,
        maintainer_email=maintainer_email,
        license=license_,
        description=description,
        ci=tuple(dict.fromkeys(ci)),
        # the distro given on the command line is recorded in the package (pkgforge.toml)
        record_distro=click.get_current_context().get_parameter_source("distro")
        == click.core.ParameterSource.COMMANDLINE,
    )
    if sim is not None:
        if from_urdf is not None:
            fail(
                PkgforgeError(
                    "--sim gz writes the example robot's ros2_control and controllers: not with --from-urdf"
                )
            )
        options["sim"] = sim
    notes: Notes | None = None
    try:
        if from_urdf is not None:
            from pkgforge.scaffold.from_urdf import new_from_urdf

            created, notes, imported = new_from_urdf(
                options,
                from_urdf,
                destination or default_destination(Path.cwd()),
                force=force,
                uri_style=mesh_uri,
                add_root_link=add_root_link,
                name_note=name_note,
            )
            spec = make_spec(**options)
        else:
            spec = make_spec(**options)
            created = create_package(spec, destination or default_destination(Path.cwd()), force=force)
    except PkgforgeError as error:
        fail(error)
    shown = os.path.relpath(created.path)
    click.echo(f"created {spec.build_type} package '{spec.name}' for ROS 2 {spec.distro.name} in {shown}/")
    for relative in created.files:
        mark = (
            " (replaced)"
            if relative in created.overwritten
            else " (unchanged)"
            if relative in created.unchanged
            else ""
        )
        click.echo(f"  {relative}{mark}")
    from pkgforge.workspace import locate

    # the workspace the package landed in: `pkgforge build` run here would look elsewhere
    root = locate(created.path).root
    build = "pkgforge build" if root == Path.cwd().resolve() else f"pkgforge build {os.path.relpath(root)}"
    install = "install" if root == Path.cwd().resolve() else os.path.relpath(root / "install")
    steps = [
        (build, "# colcon build into install/"),
        (f"pkgforge verify {shown}", ""),
        (f"source {install}/setup.bash", "# the built package on this shell's paths (after ROS 2's own)"),
        (f"ros2 launch {spec.name} display.launch.{spec.launch_format}", ""),
    ]
    width = max(len(command) for command, comment in steps if comment) + 2
    click.echo("next:")
    for command, comment in steps:
        click.echo(f"  {command:<{width}}{comment}".rstrip())
    if notes is not None:
        click.echo(
            f"imported {from_urdf} with {imported.meshes} mesh(es); {len(imported.files)} file(s) "
            "in urdf/ and meshes/"
        )
        finish_with_verify(created.path, notes, spec.distro.name)


def finish_with_verify(package: Path, notes: Notes, distro: str) -> NoReturn:
    """`migrate` and `new --from-urdf`: what changed, then verify's report on the result; verify's exit status."""
    from pkgforge.report import render
    from pkgforge.verify.config import Selection
    from pkgforge.verify.pipeline import VerifyOptions
    from pkgforge.verify.pipeline import verify as run_verify

    click.echo(notes.render(Path.cwd()), nl=False)
    click.echo(f"verify {os.path.relpath(package)}:")
    try:
        result = run_verify(package, VerifyOptions(Selection(), distro=distro))  # the target's launch API
    except PkgforgeError as error:
        fail(error)
    click.echo(render("text", result), nl=False)
    report_internal_errors(result)
    sys.exit(result.exit_code(False))


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("path", type=click.Path(path_type=Path))
@click.option(
    "--destination",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Folder to create the ROS 2 package in [default: beside PATH, as NAME, or NAME_ros2 "
    "when NAME exists]. Never overwritten.",
)
@click.option(
    "--launch-format",
    type=click.Choice(LAUNCH_FORMATS),
    default="py",
    show_default=True,
    help="Format of the converted launch files.",
)
@click.option(
    "--distro",
    type=click.Choice(list(DISTROS)),
    default=default_distro,
    show_default=f"ROS_DISTRO, else {NEWEST_LTS}",
    help="ROS 2 distribution the package targets.",
)
@click.option(
    "--gazebo",
    is_flag=True,
    help="Convert Gazebo Classic (gazebo_ros empty_world.launch, spawn_model) to Gazebo with "
    "ros_gz_sim instead of leaving it out.",
)
@click.option(
    "--name",
    default=None,
    help="Name of the ROS 2 package [default: the source's; when that breaks REP 144 (an exporter's "
    "Arm_2_description), the valid name close to it]. Every package://, $(find) follows.",
)
@click.option(
    "--maintainer-name", default=None, help="For a maintainer without one [default: git config user.name]"
)
@click.option(
    "--maintainer-email", default=None, help="For a maintainer without one [default: git config user.email]"
)
@click.option(
    "--add-root-link",
    is_flag=True,
    help="Add a massless root link above a root link with an inertia, which KDL ignores (PF604); "
    "models are otherwise copied byte for byte.",
)
def migrate(
    path: Path,
    destination: Path | None,
    launch_format: str,
    distro: str,
    gazebo: bool,
    name: str | None,
    maintainer_name: str | None,
    maintainer_email: str | None,
    add_root_link: bool,
) -> None:
    """Convert the ROS 1 catkin description package at PATH to a ROS 2 package; then verify it."""
    from pkgforge.migrate.package import migrate as run_migrate
    from pkgforge.scaffold.notes import Notes

    try:
        created, notes, source = run_migrate(
            path,
            destination,
            launch_format=launch_format,
            distro=distro,
            gazebo=gazebo,
            notes_factory=Notes,
            name=name,
            maintainer_name=maintainer_name,
            maintainer_email=maintainer_email,
            add_root_link=add_root_link,
        )
    except PkgforgeError as error:
        fail(error)
    click.echo(f"migrated {os.path.relpath(source)} to ROS 2 {distro} in {os.path.relpath(created.path)}/")
    for relative in created.files:
        click.echo(f"  {relative}")
    finish_with_verify(created.path, notes, distro)


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("path", type=click.Path(path_type=Path), default=".")
@click.option(
    "--build-base",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Build folder [default: build/ in the workspace root].",
)
@click.option(
    "--install-base",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
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
    click.echo(f"built {len(result.packages)} package(s) into {os.path.relpath(result.install_base)}/")


def color_option(function: _Command) -> _Command:
    """--color, for every command whose output can be coloured."""
    return click.option(
        "--color",
        "color",
        type=click.Choice(COLOR_CHOICES),
        default="auto",
        show_default=True,
        help="Colour the text report: auto (a terminal, unless NO_COLOR is set or "
        "FORCE_COLOR is), always or never.",
    )(function)


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
@click.option(
    "--output",
    "-o",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the report to this file instead of standard output.",
)
@click.option(
    "--junit-xml",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Also write a JUnit XML report here (for CI test reports).",
)
@click.option(
    "--select",
    multiple=True,
    metavar="CHECKS",
    help="Run only these checks: codes, code prefixes (PF2) or names; comma-separated.",
)
@click.option(
    "--ignore",
    multiple=True,
    metavar="CHECKS",
    help="Skip these checks: codes, code prefixes or names; comma-separated.",
)
@click.option("--strict", is_flag=True, help="Treat warnings as errors (exit 1 on any warning).")
@click.option(
    "--statistics",
    is_flag=True,
    help="Print one line per check code with its count instead of the diagnostics (text report).",
)
@click.option(
    "--quiet", "-q", is_flag=True, help="Print the findings and the summary line only: no hints, no progress."
)
@color_option
@click.option(
    "--jobs",
    "-j",
    type=click.IntRange(1),
    default=None,
    help="Packages verified at once [default: the number of cores].",
)
@click.option(
    "--build",
    "build_tree",
    is_flag=True,
    help="Resolve against a real colcon build into build/pkgforge-verify/ "
    "[default: the tree predicted from the install rules].",
)
@click.option(
    "--install-base",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Resolve against an existing install folder from your own colcon build "
    "(merged or isolated); nothing is rebuilt.",
)
@click.option(
    "--launch-arg",
    "launch_args",
    multiple=True,
    metavar="NAME:=VALUE",
    help="A launch argument's value for every launch file. Repeatable.",
)
@click.option(
    "--launch-timeout",
    type=click.FloatRange(0.5),
    default=10.0,
    show_default=True,
    help="Seconds one launch file may take to load and resolve.",
)
@click.option(
    "--worker-memory",
    type=MemorySize(),
    default="2G",
    show_default=True,
    help="Memory (address space) each launch worker may use, e.g. 4G or 512M, or unlimited.",
)
@click.option(
    "--launch-engine",
    type=click.Choice(["auto", "ros", "builtin"]),
    default="auto",
    show_default=True,
    help="Evaluate launch files with a ROS 2 distro's own launch libraries (ros), pkgforge's "
    "built-in engine (builtin), or ros where a distro is found (auto).",
)
@click.option(
    "--ros-prefix",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="The ROS 2 distro whose launch libraries to use (e.g. /opt/ros/jazzy) "
    "[default: the sourced one, else the only one in /opt/ros].",
)
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
@click.option(
    "--explain-launch",
    "explain_launch",
    type=click.Path(path_type=Path),
    default=None,
    metavar="FILE",
    help="Print how FILE resolves in the install tree, then exit.",
)
@click.option(
    "--explain-model",
    "explain_model",
    type=click.Path(path_type=Path),
    default=None,
    metavar="FILE",
    help="Print the model's link/joint tree with its meshes, then exit (xacro arguments from --launch-arg).",
)
@click.option(
    "--explain-sandbox",
    "explain_sandbox",
    is_flag=True,
    help="Print what confines the launch files and xacro verify runs on this machine, then exit.",
)
@click.option(
    "--artifacts",
    "artifacts_dir",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
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
    arguments = {}
    for text in launch_args:
        name, sep, value = text.partition(":=")
        if not sep or not name:
            fail(PkgforgeError(f"--launch-arg '{text}' is not NAME:=VALUE"))
        arguments[name] = value
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
@click.option(
    "--launch-arg",
    "launch_args",
    multiple=True,
    metavar="NAME:=VALUE",
    help="A launch argument's value (xacro arguments of a model file). Repeatable.",
)
@click.option(
    "--launch-timeout",
    type=click.FloatRange(0.5),
    default=10.0,
    show_default=True,
    help="Seconds one launch file or model may take to process.",
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
        options = VerifyOptions(
            launch_timeout=launch_timeout, launch_arguments=_launch_arguments(launch_args)
        )
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


def report_internal_errors(result: VerifyResult) -> None:
    """A check that crashed: its diagnostic is in the report; say so on stderr (exit 2 follows)."""
    from pkgforge.report import printable

    for error in result.internal_errors:
        summary, _, trace = error.partition("\n")
        click.echo(
            f"pkgforge: internal error {printable(summary)}; please report it{_report_note()}", err=True
        )
        if DEBUG["on"]:
            click.echo(trace.rstrip(), err=True)


@main.command("verify-files", context_settings=CONTEXT_SETTINGS)
@click.argument("files", nargs=-1, type=click.Path(path_type=Path))
@click.option("--strict", is_flag=True, help="Treat warnings as errors.")
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
        folder = file.resolve().parent
        while folder != folder.parent and not (folder / "package.xml").is_file():
            folder = folder.parent
        if (folder / "package.xml").is_file() and folder not in packages:
            packages.append(folder)
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


def _launch_arguments(launch_args: Sequence[str]) -> dict[str, str]:
    arguments: dict[str, str] = {}
    for text in launch_args:
        name, sep, value = text.partition(":=")
        if not sep or not name:
            fail(PkgforgeError(f"--launch-arg '{text}' is not NAME:=VALUE"))
        arguments[name] = value
    return arguments


def _fix_targets(paths: Sequence[Path]) -> list[Path]:
    """What to fix: each PATH as given; a file stands for the package that holds it."""
    targets: list[Path] = []
    for path in paths or (Path("."),):
        if path.is_file():
            folder = path.resolve().parent
            while folder != folder.parent and not (folder / "package.xml").is_file():
                folder = folder.parent
            if not (folder / "package.xml").is_file():
                continue  # a staged file outside any package
            path = folder
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
            launch_arguments=_launch_arguments(launch_args),
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
@click.option(
    "--select",
    multiple=True,
    metavar="CHECKS",
    help="Run (and fix) only these checks: codes, code prefixes (PF2) or names; comma-separated.",
)
@click.option(
    "--ignore",
    multiple=True,
    metavar="CHECKS",
    help="Skip these checks: codes, code prefixes or names; comma-separated.",
)
@click.option("--strict", is_flag=True, help="Exit 1 on any warning that remains.")
@color_option
@click.option(
    "--jobs",
    "-j",
    type=click.IntRange(1),
    default=None,
    help="Packages and launch files processed at once [default: the number of cores].",
)
@click.option(
    "--launch-arg",
    "launch_args",
    multiple=True,
    metavar="NAME:=VALUE",
    help="A launch argument's value for every launch file. Repeatable.",
)
@click.option(
    "--launch-timeout",
    type=click.FloatRange(0.5),
    default=10.0,
    show_default=True,
    help="Seconds one launch file may take to load and resolve.",
)
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
