"""What each request a launch worker receives means: a launch file evaluated by the launch engine
of the run (pkgforge's built-in stand-in, or a ROS distro's own libraries), a robot model run
through xacro, or a setup.py run as colcon reads it.

The sandbox (pkgforge.sandbox) forks one fresh, confined process per request and gives it to
`RequestEvaluator`; this module sits above the launch engines, the model loader and the setup.py
evaluator it dispatches to, so that the sandbox below imports none of them.
"""

from __future__ import annotations

import os
import signal
import sys
import traceback
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any, cast

from pkgforge.sandbox import worker
from pkgforge.sandbox.protocol import ErrorRecord, WorkerLimits, WorkerRequest
from pkgforge.sandbox.worker import WorkerReply

if TYPE_CHECKING:
    from pkgforge.launch.branches import BranchBudget

API_AMENT = Path(__file__).resolve().parent.parent / "launch" / "api_ament"
# the extra argument combinations start and run only until this share of --launch-timeout
BRANCH_SHARE = 0.7


def _install_api() -> None:
    """Serve pkgforge's launch, launch_ros, launch_xml and launch_yaml (the real names of the
    target distro, PKGFORGE_LAUNCH_DISTRO) before anything on the path."""
    from pkgforge.launch import api

    api.install()
    try:
        import ament_index_python.packages  # noqa: F401  (the real one, from the ament extra or ROS)
    except ImportError:
        sys.path.insert(0, str(API_AMENT))


def _budget(limits: WorkerLimits) -> BranchBudget | None:
    """How long this request's argument combinations past the defaults may run (records.BranchBudget):
    until BRANCH_SHARE of the time limit, leaving the rest for the reply. The defaults have the
    whole limit: a file that finishes them is never an error for want of time for the others."""
    import time

    from pkgforge.launch.branches import BranchBudget

    timeout = limits.get("timeout")
    if not timeout:
        return None

    def limit(seconds: float) -> None:
        worker.stop_allowance()  # the branches' budget is wall time as it comes: what does not fit is said
        remaining, _ = signal.getitimer(signal.ITIMER_REAL)
        if remaining <= 0 or seconds < remaining:
            signal.setitimer(signal.ITIMER_REAL, max(seconds, 0.001))

    return BranchBudget(
        time.monotonic() + BRANCH_SHARE * float(timeout),
        (worker.TimeLimit, worker.CPULimit),
        limit,
        worker.disarm,
    )


def _located(request: WorkerRequest, error: BaseException) -> ErrorRecord:
    """An error that escaped evaluate() (a limit hit while visiting), at the launch file's line."""
    record: ErrorRecord = {
        "stage": "worker",
        "type": type(error).__name__,
        "message": str(error),
        "file": worker.subject(request),
        "line": None,
    }
    if "file" in request:
        from pkgforge.launch.place import LAUNCH_FILES

        frames = [f for f in traceback.extract_tb(error.__traceback__) if f.filename in LAUNCH_FILES]
        if frames:
            record["file"], record["line"] = frames[-1].filename, frames[-1].lineno
    return record


def _launch_reply(reply: Mapping[str, Any]) -> WorkerReply:
    """An engine's reply (plain data, launch/records.as_dict) as the protocol's type."""
    return cast(WorkerReply, reply)


def preload() -> None:
    """Import ahead what main() imports, with no other effect: the fork server (zygote.py) runs
    this once, and every worker forked from it starts with these modules loaded."""
    import resource  # noqa: F401
    import tempfile  # noqa: F401

    from pkgforge.launch import records  # noqa: F401
    from pkgforge.sandbox import (
        guard,  # noqa: F401
        processes,  # noqa: F401
    )

    if os.environ.get("PKGFORGE_LAUNCH_ENGINE", "builtin") != "ros":
        from pkgforge.launch import api

        api._distro_data()  # the list of launch names: read once, not by every worker
    try:
        import ament_index_python.packages  # noqa: F401
    except ImportError:
        pass  # main() puts pkgforge's stand-in on the path
    import xacro  # noqa: F401
    import yaml  # noqa: F401

    from pkgforge.evaluation import warmup
    from pkgforge.launch import evaluate  # noqa: F401
    from pkgforge.urdf import robot  # noqa: F401

    warmup.render()  # the scaffold each worker evaluates once before its first request


def _tree_python_first() -> None:
    """The install tree's Python folders first on sys.path, as PYTHONPATH puts them in a sourced
    shell (after the engine's distro: an overlay before its underlay); a forked worker's sys.path
    was made before the tree existed."""
    from pkgforge.build.toolchain import TREE_PYTHONPATH

    folders = [f for f in os.environ.get(TREE_PYTHONPATH, "").split(os.pathsep) if f]
    for folder in reversed(folders):
        if folder in sys.path:
            sys.path.remove(folder)
        sys.path.insert(0, folder)


@dataclass
class Engine:
    """The launch engine a coordinator prepared once (before forking), for its requests."""

    name: str  # builtin | ros
    distro: str | None
    setup_error: str | None = None  # the ros engine's libraries could not be imported: said per file


def prepare_setup() -> None:
    """In the coordinator, before the first setup.py request: setuptools imported once (~0.2 CPU s,
    pkgforge's own dependency, no user code), so that each setup.py's process forks with it."""
    import importlib

    try:
        importlib.import_module("setuptools")
    except Exception:  # noqa: BLE001 - each request's process then says why, at setup.py
        pass


def prepare() -> Engine:
    """In the coordinator, once, before any request: the engine's imports and the tree's Python
    folders, so that each request's fresh process starts with them (no user code runs here)."""
    engine = Engine(
        os.environ.get("PKGFORGE_LAUNCH_ENGINE", "builtin"), os.environ.get("PKGFORGE_ROS_DISTRO") or None
    )
    if engine.name == "ros":
        try:
            import ament_index_python.packages  # noqa: F401
        except ImportError:
            sys.path.append(str(API_AMENT))
        from pkgforge.launch import ros_engine

        try:
            ros_engine.setup(os.environ.get("PKGFORGE_ROS_PREFIX") or None)
        except BaseException as error:  # noqa: BLE001 - said for every file, never a traceback
            engine.setup_error = (
                f"the ROS 2 launch libraries could not be imported: {type(error).__name__}: {error}"
            )
    else:
        _install_api()
    _tree_python_first()
    from pkgforge.launch import evaluate  # noqa: F401
    from pkgforge.urdf import robot  # noqa: F401

    return engine


def _evaluate(request: WorkerRequest, engine: Engine, limits: WorkerLimits) -> WorkerReply:
    """The request's reply, as plain data (a launch file's records, a model's structure, a
    setup.py's values)."""
    from pkgforge.urdf.robot import process_model

    budget = _budget(limits)
    if "model" in request:
        return cast(WorkerReply, process_model(request["model"], request.get("mappings", {})))
    if "setup" in request:
        from pkgforge.model.setup_eval import run_setup_py

        return cast(WorkerReply, run_setup_py(request["setup"]))
    return _evaluate_launch(engine, request["file"], request.get("arguments", {}), budget)


def _evaluate_launch(
    engine: Engine, path: str, arguments: dict[str, str], budget: BranchBudget | None
) -> WorkerReply:
    """One launch file's records, through the run's engine."""
    if engine.name == "ros":
        from pkgforge.launch import ros_engine

        if engine.setup_error is not None:
            return _launch_reply(ros_engine.error_reply(path, engine.setup_error, engine.distro))
        return _launch_reply(ros_engine.evaluate(path, arguments, engine.distro, budget))
    from pkgforge.launch.evaluate import evaluate

    return _launch_reply(evaluate(path, arguments, budget))


class RequestEvaluator:
    """The sandbox's Evaluator (sandbox/worker.py) for pkgforge's three kinds of request."""

    def __init__(self) -> None:
        self.engine: Engine | None = None

    def preload(self) -> None:
        preload()

    def prepare(self) -> None:
        self.engine = prepare()

    def warm(self, kind: str, work: str) -> None:
        if kind == "setup":
            prepare_setup()
        elif self.engine is not None:
            from pkgforge.evaluation import warmup

            engine = self.engine
            warmup.run(work, lambda path: _evaluate_launch(engine, path, {}, None))

    def evaluate(self, request: WorkerRequest, limits: WorkerLimits) -> WorkerReply:
        assert self.engine is not None, "prepare() runs first"
        return _evaluate(request, self.engine, limits)

    def failed(self, request: WorkerRequest, error: BaseException) -> WorkerReply:
        result: dict[str, Any] = {"status": "load-error", "error": _located(request, error)}
        if "file" in request:  # what failed before it (a limit hit while visiting) is reported too
            from pkgforge.launch.builtin.launch.launch_context import RECORDER
            from pkgforge.launch.records import as_dict

            result["errors"] = [cast(ErrorRecord, as_dict(e)) for e in RECORDER.errors]
        return result

    def locate(self) -> tuple[str | None, int | None]:
        from pkgforge.launch.place import here

        file, line = here()
        if file is None:  # a construct being visited (a Command running): where it was written
            frame: FrameType | None = sys._getframe(1)
            while frame is not None and file is None:
                owner = frame.f_locals.get("self")
                file, line = getattr(owner, "_file", None), getattr(owner, "_line", None)
                frame = frame.f_back
        return file, line
