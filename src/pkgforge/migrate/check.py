"""The launch files a migration generates are evaluated before they are written: each one that does
not load on the target distro (pkgforge's launch evaluation, the engine verify uses) is left out."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.errors import PkgforgeError

if TYPE_CHECKING:
    from pkgforge.scaffold.package import PackageSpec

# what "does not load" means: the file raises (or cannot be imported or parsed), or hands a node
# its arguments as a string, which launch_ros refuses when the node is started
UNLOADABLE = ("PF301", "PF313")


def unloadable(spec: PackageSpec, files: Mapping[str, bytes], modes: Mapping[str, int]) -> dict[str, str]:
    """Each launch file of the package (relative path) that does not load, with the first reason.

    The package is written into a temporary folder and verified there with the launch checks only
    (no cache): the files are evaluated as the final package's will be, in the sandboxed workers."""
    from pkgforge.scaffold.package import create_package, render_files
    from pkgforge.verify.config import Selection
    from pkgforge.verify.pipeline import VerifyOptions, verify

    staging = Path(tempfile.mkdtemp(prefix="pkgforge-migrate-"))
    try:
        rendered = render_files(spec)
        manifests = {name: rendered[name] for name in ("package.xml", "CMakeLists.txt")}
        created = create_package(spec, staging, files={**files, **manifests}, modes=modes)
        options = VerifyOptions(Selection(select=list(UNLOADABLE)), use_cache=False, distro=spec.distro.name)
        try:
            result = verify(created.path, options)
        except PkgforgeError:
            return {}  # nothing to judge the files by here: verify's own run afterwards says why
        failed: dict[str, str] = {}
        for diagnostic in result.diagnostics:
            relative = Path(os.path.relpath(diagnostic.path, created.path)).as_posix()
            if diagnostic.code in UNLOADABLE and relative in spec.launch_files and relative not in failed:
                failed[relative] = diagnostic.message
        return failed
    finally:
        shutil.rmtree(staging, ignore_errors=True)
