"""`colcon verify`: pkgforge's checks as a colcon verb, after `colcon build`.

Takes colcon's own package selection (--packages-select, --packages-skip,
--packages-up-to, --base-paths, ...) and checks the selected packages against
the install tree colcon built (--install-base, merged or isolated).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from colcon_core.package_selection import add_arguments as add_packages_arguments
from colcon_core.package_selection import get_package_descriptors, select_package_decorators
from colcon_core.plugin_system import satisfies_version
from colcon_core.topological_order import topological_order_packages
from colcon_core.verb import VerbExtensionPoint

from pkgforge.cli.limits import LAUNCH_ENGINES, parse_worker_memory
from pkgforge.model.distros import DISTROS
from pkgforge.report import COLOR_CHOICES, FORMATS
from pkgforge.sandbox.processes import DEFAULT_WORKER_MEMORY


class VerifyVerb(VerbExtensionPoint):  # type: ignore[misc]  # colcon_core has no type information
    """Check packages against their install tree: install rules, launch files, models, RViz configs."""

    def __init__(self) -> None:  # noqa: D107
        super().__init__()
        satisfies_version(VerbExtensionPoint.EXTENSION_POINT_VERSION, "^1.0")

    def add_arguments(self, *, parser: argparse.ArgumentParser) -> None:  # noqa: D102
        # no --build-base: verify reads only the install tree colcon built (it declared one and
        # ignored it; an option that does nothing misleads)
        parser.add_argument(
            "--install-base",
            default="install",
            help="The install tree to check, merged or isolated (default: install)",
        )
        add_packages_arguments(parser)
        parser.add_argument(
            "--junit-xml",
            metavar="PATH",
            default=None,
            help="Also write a JUnit XML report (one testsuite per package)",
        )
        # the options' names are `pkgforge verify`'s; the --pkgforge-* names they had first still work
        parser.add_argument(
            "--format",
            choices=FORMATS,
            default="text",
            help="Output format on standard output (default: text)",
        )
        parser.add_argument("--pkgforge-format", dest="format", choices=FORMATS, help=argparse.SUPPRESS)
        parser.add_argument("--strict", action="store_true", help="Treat warnings as errors")
        parser.add_argument(
            "--color",
            choices=COLOR_CHOICES,
            default="auto",
            help="Colour the text report: auto (a terminal, unless NO_COLOR is set or FORCE_COLOR "
            "is), always or never (default: auto)",
        )
        for name, what in (("select", "Run only these checks"), ("ignore", "Skip these checks")):
            parser.add_argument(
                f"--{name}",
                action="append",
                default=[],
                metavar="CHECKS",
                help=f"{what} (codes, prefixes or names; comma-separated)",
            )
            parser.add_argument(f"--pkgforge-{name}", dest=name, action="append", help=argparse.SUPPRESS)
        parser.add_argument(
            "--launch-timeout",
            type=float,
            default=10.0,
            help="Seconds one launch file may take (default: 10)",
        )
        parser.add_argument(
            "--worker-memory",
            type=_memory,
            default=DEFAULT_WORKER_MEMORY,
            metavar="SIZE",
            help="Memory each launch worker may use, e.g. 4G or 512M, or unlimited (default: 2G)",
        )
        parser.add_argument(
            "--launch-engine",
            choices=LAUNCH_ENGINES,
            default="auto",
            help="Evaluate launch files with the ROS 2 distro's launch libraries (ros), "
            "pkgforge's built-in engine (builtin), or ros where found (default: auto)",
        )
        parser.add_argument(
            "--ros-prefix",
            default=None,
            metavar="DIR",
            help="The ROS 2 distro whose launch libraries to use (e.g. /opt/ros/jazzy)",
        )
        parser.add_argument(
            "--distro",
            choices=list(DISTROS),
            default=None,
            help="The ROS 2 distro the packages target (default: ROS_DISTRO, pkgforge.toml "
            "[verify] distro, the package's CI file, else every active distro)",
        )

    def main(self, *, context: Any) -> int:  # noqa: D102  (colcon's CommandContext)
        from pkgforge.errors import PkgforgeError
        from pkgforge.report import render
        from pkgforge.verify.config import Selection, load_config, split_keys
        from pkgforge.verify.discovery import PackageTarget, _load
        from pkgforge.verify.pipeline import VerifyOptions, run
        from pkgforge.workspace import Workspace

        args = context.args
        descriptors = get_package_descriptors(args)
        decorators = topological_order_packages(descriptors, recursive_categories=("run",))
        select_package_decorators(args, decorators)
        ros = [d for d in decorators if str(d.descriptor.type).startswith("ros.")]
        targets = [
            PackageTarget(Path(d.descriptor.path).resolve(), d.descriptor.name, str(d.descriptor.type), True)
            for d in ros
        ]
        selected = {Path(d.descriptor.path).resolve() for d in ros if d.selected}
        root = Path.cwd()
        selection = Selection(split_keys(args.select), split_keys(args.ignore))
        options = VerifyOptions(
            selection,
            strict=args.strict,
            mode="install-base",
            install_base=Path(args.install_base),
            launch_timeout=args.launch_timeout,
            worker_memory=args.worker_memory,
            launch_engine=args.launch_engine,
            ros_prefix=Path(args.ros_prefix) if args.ros_prefix else None,
            distro=args.distro,
        )
        try:
            options.engine()
            config = load_config(root, selection)
            models = {t.path: _load(t) for t in targets}
            chosen = [t for t in targets if t.path in selected]
            if not chosen:
                print("colcon verify: no package selected", file=sys.stderr)
                return 0
            result = run(
                root,
                Workspace(root, root),
                config,
                chosen,
                models,
                {t.name: t.path for t in targets},
                options,
            )
        except PkgforgeError as error:
            # 2, as `pkgforge verify`: could not run (colcon turns a returned string into 1)
            print("colcon verify: " + "\n".join(error.lines()), file=sys.stderr)
            return 2
        from pkgforge.report import use_color

        color = args.format == "text" and use_color(args.color, sys.stdout)
        sys.stdout.write(render(args.format, result, color=color, strict=args.strict))
        if args.junit_xml:
            Path(args.junit_xml).parent.mkdir(parents=True, exist_ok=True)
            Path(args.junit_xml).write_text(render("junit", result, strict=args.strict), encoding="utf-8")
        return result.exit_code(args.strict)


def _memory(text: str) -> int | None:
    """--worker-memory, as `pkgforge verify` reads it."""
    try:
        return parse_worker_memory(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
