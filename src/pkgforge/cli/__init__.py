"""Command line: parse options, call the library, map errors to exit codes.

`app` holds the click group and the error handling every command shares, `options` the options
several commands take (declared once); each command is a module of its own, registered on the
group when `main` is first asked for. `colcon_verb` is `colcon verify`, the same checks as a colcon
verb: colcon imports it on every run (`colcon build` too), so importing this package loads neither
click nor the commands; `main` does (PEP 562).
"""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING

if sys.argv and os.path.basename(sys.argv[0]) == "pkgforge":  # the console script, before click loads:
    from pkgforge.sandbox.processes import install_signal_handlers  # a Ctrl-C while starting exits 130 too

    install_signal_handlers()

if TYPE_CHECKING:
    from pkgforge.cli.app import main

__all__ = ["main"]

COMMANDS = ("new", "migrate", "build", "verify", "verify_files", "fix", "view", "checks")


def __getattr__(name: str) -> object:
    """`main`, the `pkgforge` group with every command registered on it."""
    if name != "main":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    for command in COMMANDS:
        importlib.import_module(f"{__name__}.{command}")
    from pkgforge.cli.app import main

    globals()["main"] = main
    return main
