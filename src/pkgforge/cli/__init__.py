"""Command line: parse options, call the library, map errors to exit codes.

`app` holds the click group and the error handling every command shares, `options` the options
several commands take (declared once); each command is a module of its own, registered on the
group when it is imported here. `colcon_verb` is `colcon verify`, the same checks as a colcon verb.
"""

from __future__ import annotations

import os
import sys

if sys.argv and os.path.basename(sys.argv[0]) == "pkgforge":  # the console script, before click loads:
    from pkgforge.sandbox.processes import install_signal_handlers  # a Ctrl-C while starting exits 130 too

    install_signal_handlers()

from pkgforge.cli import build, checks, fix, migrate, new, verify, verify_files, view  # noqa: E402, F401
from pkgforge.cli.app import main  # noqa: E402

__all__ = ["main"]
