"""The `pkgforge` click group and what every command shares: errors mapped to one line and an
exit status, the report of a check that crashed, verify run on what `new` and `migrate` wrote."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import click

from pkgforge import __version__
from pkgforge.errors import PkgforgeError

if TYPE_CHECKING:
    from pkgforge.scaffold.notes import Notes
    from pkgforge.verify.pipeline import VerifyResult

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


def launch_arguments(launch_args: Sequence[str]) -> dict[str, str]:
    """--launch-arg NAME:=VALUE, each; a malformed one ends the command."""
    arguments: dict[str, str] = {}
    for text in launch_args:
        name, sep, value = text.partition(":=")
        if not sep or not name:
            fail(PkgforgeError(f"--launch-arg '{text}' is not NAME:=VALUE"))
        arguments[name] = value
    return arguments


def package_of(file: Path) -> Path | None:
    """The package folder that holds `file` (the nearest package.xml above it), if any."""
    folder = file.resolve().parent
    while folder != folder.parent and not (folder / "package.xml").is_file():
        folder = folder.parent
    return folder if (folder / "package.xml").is_file() else None
