"""What runs in the fresh process forked for one launch file or robot model (sandbox/coordinator.py).

Launch files and xacro are user code. Each request gets a process of its own, forked by the
worker's coordinator, that never evaluates anything else. Before any user code runs it:
- holds no descriptor of pkgforge's: stdin is a pipe nobody writes, stdout and stderr are
  /dev/null, and the only other descriptor is the pipe its one reply goes out on;
- works in a folder of its own (its current folder and TMPDIR), removed after it;
- limits itself (PKGFORGE_WORKER_LIMITS): address space (--worker-memory), open files, and
  CPU time and wall time (--launch-timeout); a breach raises inside the launch file, so it is
  reported at the line that was running, naming the limit and the option that raises it;
- installs the Python guard (guard.py, also in every Python process it starts), which reports
  each refused write or signal at its line;
- drops every capability (in the namespaces of namespaces.py), then restricts itself with
  Landlock (landlock.py): the kernel refuses writes outside pkgforge's temporary folders and
  signals outside the process's own tree, for it and for everything it starts.
"""

from __future__ import annotations

import json
import math
import os
import signal
import sys
import traceback
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any, NoReturn, cast

from pkgforge.sandbox.protocol import (
    Confinement,
    ErrorRecord,
    LimitKind,
    ModelReply,
    SetupReply,
    WorkerLimits,
    WorkerRequest,
)

if TYPE_CHECKING:
    from pkgforge.launch.branches import BranchBudget
    from pkgforge.launch.records import LaunchResultDict

    WorkerReply = LaunchResultDict | ModelReply | SetupReply
    from pkgforge.sandbox.processes import LoadAllowance

API_AMENT = Path(__file__).resolve().parent.parent / "launch" / "api_ament"
OPEN_FILES = 1024  # the usual `ulimit -n`: what a launch file gets under ros2 launch too
# bytes a request's process may write in all (its folder, its views of the tree and /tmp) when
# --worker-memory is unlimited; else that (the tmpfs holding them is memory too)
PRIVATE_FOLDER_SIZE = 2 * 2**30
# the extra argument combinations start and run only until this share of --launch-timeout
BRANCH_SHARE = 0.7


class TimeLimit(BaseException):
    """Raised in the launch file's code when its wall time runs out (BaseException: an
    `except Exception` in the launch file does not swallow it)."""


class CPULimit(BaseException):
    """Raised in the launch file's code when its CPU time runs out (SIGXCPU)."""


def _install_api() -> None:
    """Serve pkgforge's launch, launch_ros, launch_xml and launch_yaml (the real names of the
    target distro, PKGFORGE_LAUNCH_DISTRO) before anything on the path."""
    from pkgforge.launch import api

    api.install()
    try:
        import ament_index_python.packages  # noqa: F401  (the real one, from the ament extra or ROS)
    except ImportError:
        sys.path.insert(0, str(API_AMENT))


# --- limits ---------------------------------------------------------------------------------


def read_limits() -> WorkerLimits:
    try:
        limits: WorkerLimits = json.loads(os.environ.pop("PKGFORGE_WORKER_LIMITS", "{}"))
        return limits
    except ValueError:
        return {}


def _apply_limits(limits: WorkerLimits) -> None:
    """Process-wide limits and the parent-death signal, before any user code runs."""
    import resource

    from pkgforge.sandbox.processes import die_with_parent

    if limits.get("parent"):
        die_with_parent(int(limits["parent"]))
    _set(resource.RLIMIT_CORE, 0)
    memory = limits.get("memory")
    if memory:
        _set(resource.RLIMIT_AS, int(memory))
    _set(resource.RLIMIT_NOFILE, OPEN_FILES)

    def on_alarm(signum: int, frame: FrameType | None) -> None:
        # the time it waited for a busy CPU is not its own: the limit grows by it (to a bound)
        more = _allowance.more() if _allowance is not None else 0.0
        if more:
            signal.setitimer(signal.ITIMER_REAL, more)
            return
        raise TimeLimit()

    def on_xcpu(signum: int, frame: FrameType | None) -> None:
        raise CPULimit()

    signal.signal(signal.SIGALRM, on_alarm)
    signal.signal(signal.SIGXCPU, on_xcpu)


# this request's LoadAllowance (processes.py), stopped while the extra argument combinations run
# (their own budget) and between requests; None before the first request with a time limit
_allowance: LoadAllowance | None = None


def _set(kind: int, value: int) -> None:
    import resource

    try:
        _, hard = resource.getrlimit(kind)
        if hard != resource.RLIM_INFINITY:
            value = min(value, hard)
        resource.setrlimit(kind, (value, value))
    except (ValueError, OSError):
        pass


def _arm(limits: WorkerLimits) -> None:
    """This request's wall-time alarm and CPU-time soft limit (the CPU limit counts the whole
    process, so it is set to what was used so far plus this request's share)."""
    import resource

    from pkgforge.sandbox.processes import LoadAllowance

    timeout = limits.get("timeout")
    if not timeout:
        return
    global _allowance
    _allowance = LoadAllowance(float(timeout))
    signal.setitimer(signal.ITIMER_REAL, float(timeout))
    usage = resource.getrusage(resource.RUSAGE_SELF)
    soft = int(usage.ru_utime + usage.ru_stime) + math.ceil(float(timeout))
    try:
        _, hard = resource.getrlimit(resource.RLIMIT_CPU)
        if hard == resource.RLIM_INFINITY or soft < hard:
            resource.setrlimit(resource.RLIMIT_CPU, (soft, hard))
    except (ValueError, OSError):
        pass


def _budget(limits: WorkerLimits) -> BranchBudget | None:
    """How long this request's argument combinations past the defaults may run (branches.BranchBudget):
    until BRANCH_SHARE of the time limit, leaving the rest for the reply. The defaults have the
    whole limit: a file that finishes them is never an error for want of time for the others."""
    import time

    from pkgforge.launch.branches import BranchBudget

    timeout = limits.get("timeout")
    if not timeout:
        return None

    def limit(seconds: float) -> None:
        _stop_allowance()  # the branches' budget is wall time as it comes: what does not fit is said
        remaining, _ = signal.getitimer(signal.ITIMER_REAL)
        if remaining <= 0 or seconds < remaining:
            signal.setitimer(signal.ITIMER_REAL, max(seconds, 0.001))

    return BranchBudget(
        time.monotonic() + BRANCH_SHARE * float(timeout), (TimeLimit, CPULimit), limit, _disarm
    )


def _stop_allowance() -> None:
    if _allowance is not None:
        _allowance.stop()


def _disarm() -> None:
    import resource

    _stop_allowance()
    signal.setitimer(signal.ITIMER_REAL, 0)
    try:
        _, hard = resource.getrlimit(resource.RLIMIT_CPU)
        resource.setrlimit(resource.RLIMIT_CPU, (hard, hard))
    except (ValueError, OSError):
        pass


def _limit_message(error: Mapping[str, Any], limits: WorkerLimits) -> tuple[LimitKind, str] | None:
    """(limit, message) when an error record is a limit breach."""
    from pkgforge.sandbox.processes import format_size

    kind, message = error.get("type"), str(error.get("message", ""))
    timeout = limits.get("timeout") or 0.0
    if kind == "TimeLimit":
        granted = _allowance.granted if _allowance is not None else 0.0
        busy = f" and {granted:.1f} s more it waited for a busy CPU" if granted else ""
        return "time", (
            f"still running after the {timeout:g} s limit{busy} (an endless loop, or waiting "
            "for something); raise it with --launch-timeout"
        )
    if kind == "CPULimit":
        return "cpu", f"used more than the {timeout:g} s CPU time limit; raise it with --launch-timeout"
    if kind == "MemoryError" or message.startswith("MemoryError"):
        memory = limits.get("memory")
        size = format_size(int(memory)) if memory else "available"
        return "memory", (
            f"the launch worker's {size} memory limit was hit; "
            "raise it with --worker-memory (e.g. --worker-memory 4G)"
        )
    if "[Errno 24]" in message:
        return "files", (
            f"too many open files: the launch worker's limit of {OPEN_FILES} open files "
            "(the usual `ulimit -n`, as under ros2 launch) was hit; close the files it opens"
        )
    return None


def _mark_limits(result: WorkerReply, limits: WorkerLimits) -> None:
    """Name the limit a breach hit (the parent never caches such a result)."""
    records = [result.get("error")] + list(result.get("errors", []))
    for record in records:
        if not isinstance(record, dict):
            continue
        breach = _limit_message(record, limits)
        if breach is None:
            continue
        original = str(record.get("message", ""))
        record["limit"], record["message"] = breach
        if record is not result.get("error"):
            continue  # an entity's error is shown with its type already
        if breach[0] == "time":
            result["status"] = "timeout"
        elif breach[0] == "memory":
            # xacro's own words say where (which expression): keep them
            prefix = f"{original}: " if original and not original.startswith("MemoryError") else ""
            record["message"] = f"{prefix}MemoryError: {breach[1]}"


def _located(request: WorkerRequest, error: BaseException) -> ErrorRecord:
    """An error that escaped evaluate() (a limit hit while visiting), at the launch file's line."""
    record: ErrorRecord = {
        "stage": "worker",
        "type": type(error).__name__,
        "message": str(error),
        "file": _subject(request),
        "line": None,
    }
    if "file" in request:
        from pkgforge.launch.place import LAUNCH_FILES

        frames = [f for f in traceback.extract_tb(error.__traceback__) if f.filename in LAUNCH_FILES]
        if frames:
            record["file"], record["line"] = frames[-1].filename, frames[-1].lineno
    return record


def _subject(request: WorkerRequest) -> str:
    """The file a request evaluates."""
    if "file" in request:
        return request["file"]
    return request["model"] if "model" in request else request["setup"]


def _install_guard(own: str) -> bool:
    """The guard, for pkgforge's temporary install tree and this process's own folder `own`; the
    processes it starts get it through PYTHONPATH."""
    from pkgforge.sandbox import guard

    os.environ[guard.OWN_VARIABLE] = own
    os.environ[guard.LOG_VARIABLE] = os.path.join(own, guard.LOG_NAME)
    os.environ[guard.ROOT_PID_VARIABLE] = str(os.getpid())
    if not guard.install():
        return False
    temporary = os.path.join(own, "tmp")
    os.makedirs(temporary, exist_ok=True)
    # tempfile in a launch file (and in its children) writes inside its own folder
    os.environ["TMPDIR"] = temporary
    import tempfile

    tempfile.tempdir = None
    os.environ["PYTHONDONTWRITEBYTECODE"] = "1"
    site = str(Path(guard.__file__).resolve().parent / "guard_site")
    os.environ["PYTHONPATH"] = site + (
        os.pathsep + os.environ["PYTHONPATH"] if os.environ.get("PYTHONPATH") else ""
    )

    def where() -> tuple[str | None, int | None]:
        from pkgforge.launch.place import here

        file, line = here()
        if file is None:  # a construct being visited (a Command running): where it was written
            frame: FrameType | None = sys._getframe(1)
            while frame is not None and file is None:
                owner = frame.f_locals.get("self")
                file, line = getattr(owner, "_file", None), getattr(owner, "_line", None)
                frame = frame.f_back
        return file, line

    guard.set_locator(where)
    return True


def _refusals(result: WorkerReply, request: WorkerRequest) -> None:
    """What the guard refused, or saw overwritten in the tree, while answering: located records."""
    from pkgforge.sandbox import guard

    for record in guard.take():
        if "file" not in request:
            # pkgforge's own xacro run on a model: no launch file to blame; a setup.py that
            # writes fails on the refusal, and that failure is its evaluation's answer
            continue
        if record["kind"] == "installed":
            kind = "TreeWrite"
        else:
            kind = "RefusedSignal" if record["operation"].startswith("send signal") else "RefusedWrite"
        via = " (in a process it started)" if record.get("child") else ""
        result.setdefault("errors", []).append(
            {
                "stage": "sandbox",
                "type": kind,
                "message": f"{record['operation']}: {record['path']}{via}",
                "file": record.get("file") or request.get("file"),
                "line": record.get("line"),
            }
        )


def _launch_reply(reply: Mapping[str, Any]) -> LaunchResultDict:
    """An engine's reply (plain data, launch/records.as_dict) as the protocol's type."""
    return cast("LaunchResultDict", reply)


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

    from pkgforge.launch import evaluate  # noqa: F401
    from pkgforge.sandbox import warmup
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


def answer(
    request: WorkerRequest,
    engine: Engine,
    limits: WorkerLimits,
    reply_fd: int,
    own: str,
    confinement: Confinement,
) -> NoReturn:
    """The fresh process of one request: confine it, evaluate, write the one reply line on
    `reply_fd`, exit. Never returns; never runs anything else."""
    code = 0
    try:
        _isolate(reply_fd)
        _private_mounts(own, confinement, limits)
        os.chdir(own)  # (after: `own` may now be a tmpfs of its own)
        guarded = _install_guard(own)
        _apply_limits(limits)
        _confine(confinement)
        result = _evaluate(request, engine, limits, guarded)
        _write_all(reply_fd, (json.dumps(result, default=str) + "\n").encode())
    except BaseException:  # noqa: BLE001 - no reply: the coordinator says the process died
        code = 1
    finally:
        os._exit(code)


def _isolate(reply_fd: int) -> None:
    """No descriptor of pkgforge's: stdin a pipe nobody writes (input() waits until the wall
    limit, as before), stdout and stderr /dev/null, every other descriptor closed."""
    unwritten, keep_open = os.pipe()  # the write end stays open here, unwritten
    devnull = os.open(os.devnull, os.O_RDWR)
    os.dup2(unwritten, 0)
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    keep = {0, 1, 2, reply_fd, keep_open}
    for fd in _open_descriptors():
        if fd not in keep:
            try:
                os.close(fd)
            except OSError:
                pass
    sys.stdin = open(0, encoding="utf-8", errors="replace", closefd=False)
    sys.stdout = sys.stderr = open(os.devnull, "w")


def _open_descriptors() -> list[int]:
    try:
        return [int(name) for name in os.listdir("/proc/self/fd")]
    except OSError:
        return list(range(3, OPEN_FILES))


def _private_mounts(own: str, confinement: Confinement, limits: WorkerLimits) -> None:
    """In the read-only view: its own folder a bounded tmpfs, the tree and /tmp overlays whose
    writes stay there, /run empty (namespaces.private_mounts)."""
    if not confinement["view"]:
        return
    from pkgforge.sandbox import guard, namespaces

    size = int(limits.get("memory") or PRIVATE_FOLDER_SIZE)
    try:
        upper = namespaces.private_mounts(own, os.environ.get(guard.SANDBOX_VARIABLE), size)
    except OSError:
        return  # the shared tree, and /tmp read-only: such a write fails (the guard says where)
    os.environ[guard.TMP_VARIABLE] = upper


def _confine(confinement: Confinement) -> None:
    """What the kernel enforces from here on, for this process and everything it starts."""
    from pkgforge.sandbox import landlock, namespaces

    try:  # (also for root without a user namespace: mknod, raw disks, modules, the clock)
        namespaces.drop_privileges()
    except OSError:
        pass  # nothing to drop where the kernel has no capabilities to give
    if confinement["landlock"]:
        from pkgforge.sandbox import guard

        landlock.restrict(guard.kernel_writable(), confinement["landlock"])
    if confinement["sockets"]:
        from pkgforge.sandbox import seccomp

        seccomp.install()


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def _evaluate(request: WorkerRequest, engine: Engine, limits: WorkerLimits, guarded: bool) -> WorkerReply:
    """The request's reply, as plain data (a launch file's records, or a model's structure)."""
    from pkgforge.launch.evaluate import evaluate
    from pkgforge.urdf.robot import process_model

    result: WorkerReply
    try:
        try:
            _arm(limits)
            budget = _budget(limits)
            if "model" in request:
                result = process_model(request["model"], request.get("mappings", {}))
            elif "setup" in request:
                from pkgforge.model.setup_eval import run_setup_py

                result = run_setup_py(request["setup"])
            elif engine.name == "ros":
                from pkgforge.launch import ros_engine

                if engine.setup_error is not None:
                    result = _launch_reply(
                        ros_engine.error_reply(request["file"], engine.setup_error, engine.distro)
                    )
                else:
                    result = _launch_reply(
                        ros_engine.evaluate(
                            request["file"], request.get("arguments", {}), engine.distro, budget
                        )
                    )
            else:
                result = _launch_reply(evaluate(request["file"], request.get("arguments", {}), budget))
        finally:
            _disarm()
    except BaseException as error:  # noqa: BLE001 - the reply must always come
        result = {"status": "load-error", "error": _located(request, error)}
        if "file" in request:  # what failed before it (a limit hit while visiting) is reported too
            from pkgforge.launch.builtin.launch.launch_context import RECORDER
            from pkgforge.launch.records import as_dict

            result["errors"] = [cast(ErrorRecord, as_dict(e)) for e in RECORDER.errors]
    _mark_limits(result, limits)
    if "branching" in result and isinstance(result["branching"], dict):
        result["branching"]["limit"] = limits.get("timeout")
    if guarded:
        _refusals(result, request)
    return result


if __name__ == "__main__":
    if sys.argv[1:2] == ["--fork-server"]:  # workers forked after these imports (zygote.py)
        from pkgforge.sandbox.zygote import serve

        serve(int(sys.argv[2]))
        # nothing to flush or remove, and the interpreter's own exit with lxml, xacro and the
        # evaluator loaded takes ~60 ms that pkgforge would wait for (Zygote.close)
        os._exit(0)
    else:  # one worker on stdin and stdout, without a fork server
        from pkgforge.sandbox.coordinator import main

        main()
