"""A worker's coordinator evaluates pkgforge's own scaffold once before it forks any request's process.

Each request runs in a fresh process forked from the coordinator (sandbox/coordinator.py); whatever the
first evaluation in a process imports or caches lazily (the launch API's modules, xacro's and
lxml's machinery, the evaluator's tables) would otherwise be made again in every one of them.
Evaluating a launch file of each format and its model here first makes it once, in the process
they are all forked from: measured on scaffolded packages, about 12 → 5 CPU ms per request.

The files are what `pkgforge new` writes (rendered once, in the fork server's preload), in a
temporary prefix of the coordinator's own; nothing of the user's is read and nothing reported.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

PACKAGE = "pkgforge_warm_up"
FORMATS = ("py", "xml", "yaml")

# the scaffold's files, relative to the package folder (render(), in the fork server)
_FILES: dict[str, bytes] = {}


def render() -> None:
    """Render the scaffold once (jinja2): in the fork server, so no worker pays for it."""
    if _FILES:
        return
    from pkgforge.scaffold.package import make_spec, render_files

    for launch_format in FORMATS:
        spec = make_spec(
            PACKAGE,
            maintainer_name="pkgforge",
            maintainer_email="warm-up@example.com",
            launch_format=launch_format,
        )
        _FILES.update(render_files(spec))


def run(folder: str, evaluate_launch: Callable[[str], object]) -> None:
    """Evaluate each launch format (with `evaluate_launch`, the run's engine) and the model once, in
    a prefix made in `folder`; any failure is ignored (it only means less was warmed)."""
    if not _FILES:
        return
    prefix = tempfile.mkdtemp(prefix="warm-up-", dir=folder)
    before = os.environ.get("AMENT_PREFIX_PATH")
    try:
        share = Path(prefix, "share", PACKAGE)
        for relative, content in _FILES.items():
            target = share / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(content)
        index = Path(prefix, "share", "ament_index", "resource_index", "packages")
        index.mkdir(parents=True)
        (index / PACKAGE).write_bytes(b"")
        os.environ["AMENT_PREFIX_PATH"] = os.pathsep.join(filter(None, [prefix, before]))
        _evaluate_all(share, evaluate_launch)
    except Exception:  # noqa: BLE001 - warming is an optimisation: never a reason not to work
        pass
    finally:
        if before is None:
            os.environ.pop("AMENT_PREFIX_PATH", None)
        else:
            os.environ["AMENT_PREFIX_PATH"] = before
        shutil.rmtree(prefix, ignore_errors=True)


def _evaluate_all(share: Path, evaluate_launch: Callable[[str], object]) -> None:
    from pkgforge.urdf.robot import process_model

    for launch in sorted((share / "launch").iterdir()):
        evaluate_launch(str(launch))
    for model in sorted((share / "urdf").glob("*.urdf.xacro")):
        process_model(str(model), {})
