"""The launch files a migration generates are evaluated before they are written: each one that does
not run on the target distro (pkgforge's launch evaluation, the engine verify uses) is left out."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.diagnostics import Severity
from pkgforge.errors import PkgforgeError

if TYPE_CHECKING:
    from pkgforge.scaffold.package import PackageSpec

# what "does not run" means: the file raises (or cannot be imported or parsed), hands a node its
# arguments as a string, which launch_ros refuses when the node is started, or reads a file that
# exists nowhere (the exporter's display.launch naming <package>.urdf beside the model it wrote
# as <robot>.xacro: xacro, or the node given it, fails at start as it did under ROS 1)
UNLOADABLE = ("PF301", "PF313")
MISSING_FILE = "PF303"


def _reason(code: str, message: str, distro: str) -> str:
    shown = message if len(message) <= 160 else message[:159] + "…"
    if code == MISSING_FILE:
        return f"it reads a file that exists nowhere: {shown}"
    return f"it does not load on {distro} ({shown})"


def unloadable(spec: PackageSpec, files: Mapping[str, bytes], modes: Mapping[str, int]) -> dict[str, str]:
    """Each launch file of the package (relative path) that does not run, with the first reason.

    The package is written into a temporary folder and verified there with the launch checks only
    (no cache): the files are evaluated as the final package's will be, in the sandboxed workers."""
    from pkgforge.scaffold.package import create_package, render_files
    from pkgforge.verify.config import Selection
    from pkgforge.verify.options import VerifyOptions
    from pkgforge.verify.pipeline import verify

    staging = Path(tempfile.mkdtemp(prefix="pkgforge-migrate-"))
    try:
        rendered = render_files(spec)
        manifests = {name: rendered[name] for name in ("package.xml", "CMakeLists.txt")}
        created = create_package(spec, staging, files={**files, **manifests}, modes=modes)
        options = VerifyOptions(
            Selection(select=[*UNLOADABLE, MISSING_FILE]), use_cache=False, distro=spec.distro.name
        )
        try:
            result = verify(created.path, options)
        except PkgforgeError:
            return {}  # nothing to judge the files by here: verify's own run afterwards says why
        failed: dict[str, str] = {}
        for diagnostic in result.diagnostics:
            relative = Path(os.path.relpath(diagnostic.path, created.path)).as_posix()
            fails = diagnostic.code in UNLOADABLE or (
                diagnostic.code == MISSING_FILE and diagnostic.severity == Severity.ERROR
            )  # a warning: the path of one argument choice only, which the user gives then
            if fails and relative in spec.launch_files and relative not in failed:
                failed[relative] = _reason(diagnostic.code, diagnostic.message, spec.distro.name)
        return failed
    finally:
        shutil.rmtree(staging, ignore_errors=True)
