"""The options several commands take, each declared once: a decorator (or a factory of one, where
a command words its help in its own terms) that `verify`, `fix`, `view`, `new` and `migrate`
stack."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from pkgforge.cli.limits import LAUNCH_ENGINES, parse_worker_memory
from pkgforge.model.distros import DISTROS, NEWEST_LTS, default_distro
from pkgforge.report import COLOR_CHOICES
from pkgforge.scaffold.kinds import LAUNCH_FORMATS

if TYPE_CHECKING:
    # click 8.2 made ParamType generic (value, input); click 8.1 (which pyproject allows) is not
    _SizeType = click.ParamType[int | None, object]
else:
    _SizeType = click.ParamType

_Command = TypeVar("_Command", bound=Callable[..., Any])


class MemorySize(_SizeType):
    """A size such as 2G or 512M (bytes), or `unlimited`."""

    name = "SIZE"

    def convert(self, value: object, param: click.Parameter | None, ctx: click.Context | None) -> int | None:
        if isinstance(value, int) or value is None:
            return value
        try:
            return parse_worker_memory(str(value))
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


def stacked(*decorators: Callable[[Any], Any]) -> Callable[[_Command], _Command]:
    """One decorator of several, applied as if written one above the other in this order (the
    order `--help` lists the options in)."""

    def apply(function: _Command) -> _Command:
        for decorator in reversed(decorators):
            function = decorator(function)
        return function

    return apply


def path_option(
    *names: str, kind: str = "any", help: str, metavar: str | None = None
) -> Callable[[_Command], _Command]:
    """An option naming a path, None when not given: a "file", a "folder", or "any" path."""
    accepts = click.Path(file_okay=kind != "folder", dir_okay=kind != "file", path_type=Path)
    return click.option(*names, type=accepts, default=None, metavar=metavar, help=help)


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


def check_selection(select_help: str) -> Callable[[_Command], _Command]:
    """--select and --ignore: which checks run."""
    return stacked(
        click.option("--select", multiple=True, metavar="CHECKS", help=select_help),
        click.option(
            "--ignore",
            multiple=True,
            metavar="CHECKS",
            help="Skip these checks: codes, code prefixes or names; comma-separated.",
        ),
    )


def strict_option(help: str) -> Callable[[_Command], _Command]:
    """--strict: warnings count as errors in the exit status."""
    return click.option("--strict", is_flag=True, help=help)


def jobs_option(what: str) -> Callable[[_Command], _Command]:
    """--jobs/-j: how many of `what` at once."""
    return click.option(
        "--jobs",
        "-j",
        type=click.IntRange(1),
        default=None,
        help=f"{what} at once [default: the number of cores].",
    )


def launch_options(
    arg_help: str = "A launch argument's value for every launch file. Repeatable.",
    timeout_help: str = "Seconds one launch file may take to load and resolve.",
) -> Callable[[_Command], _Command]:
    """--launch-arg NAME:=VALUE (repeatable) and --launch-timeout: how launch files are evaluated."""
    return stacked(
        click.option("--launch-arg", "launch_args", multiple=True, metavar="NAME:=VALUE", help=arg_help),
        click.option(
            "--launch-timeout", type=click.FloatRange(0.5), default=10.0, show_default=True, help=timeout_help
        ),
    )


def sandbox_options(function: _Command) -> _Command:
    """--worker-memory, --launch-engine and --ros-prefix: what evaluates launch files, within what."""
    return stacked(
        click.option(
            "--worker-memory",
            type=MemorySize(),
            default="2G",
            show_default=True,
            help="Memory (address space) each launch worker may use, e.g. 4G or 512M, or unlimited.",
        ),
        click.option(
            "--launch-engine",
            type=click.Choice(list(LAUNCH_ENGINES)),
            default="auto",
            show_default=True,
            help="Evaluate launch files with a ROS 2 distro's own launch libraries (ros), pkgforge's "
            "built-in engine (builtin), or ros where a distro is found (auto).",
        ),
        path_option(
            "--ros-prefix",
            kind="folder",
            help="The ROS 2 distro whose launch libraries to use (e.g. /opt/ros/jazzy) "
            "[default: the sourced one, else the only one in /opt/ros].",
        ),
    )(function)


def destination_option(help: str) -> Callable[[_Command], _Command]:
    """--destination: the folder a new package is written in."""
    return path_option("--destination", kind="folder", help=help)


def launch_format_option(help: str) -> Callable[[_Command], _Command]:
    """--launch-format: the format launch files are written in."""
    return click.option(
        "--launch-format", type=click.Choice(LAUNCH_FORMATS), default="py", show_default=True, help=help
    )


def distro_option(function: _Command) -> _Command:
    """--distro of a package written: the ROS 2 distribution it targets."""
    return click.option(
        "--distro",
        type=click.Choice(list(DISTROS)),
        default=default_distro,
        show_default=f"ROS_DISTRO, else {NEWEST_LTS}",
        help="ROS 2 distribution the package targets.",
    )(function)


def maintainer_options(when: str = "") -> Callable[[_Command], _Command]:
    """--maintainer-name and --maintainer-email of a package written, `when` they apply."""
    return stacked(
        click.option("--maintainer-name", default=None, help=f"{when}[default: git config user.name]"),
        click.option("--maintainer-email", default=None, help=f"{when}[default: git config user.email]"),
    )


def add_root_link_option(help: str) -> Callable[[_Command], _Command]:
    """--add-root-link: a massless root link above a root link with an inertia (PF604)."""
    return click.option("--add-root-link", is_flag=True, help=help)
