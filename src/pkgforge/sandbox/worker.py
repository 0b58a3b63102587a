"""What runs in the fresh process forked for one launch file or robot model (sandbox/coordinator.py).

What a request means (a launch file evaluated by an engine, a xacro model, a setup.py) is the
`Evaluator`'s, given by the process's entry (pkgforge/evaluation): this module only confines the
process, runs the evaluator under the limits and writes its one reply.

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
from collections.abc import Mapping
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any, NoReturn, Protocol

from pkgforge.sandbox.protocol import (
    Confinement,
    LimitKind,
    WorkerLimits,
    WorkerRequest,
)

if TYPE_CHECKING:
    from pkgforge.sandbox.processes import LoadAllowance

# a reply as plain data: a launch file's records (launch/records.as_dict), a ModelReply or a SetupReply
WorkerReply = dict[str, Any]
OPEN_FILES = 1024  # the usual `ulimit -n`: what a launch file gets under ros2 launch too
# bytes a request's process may write in all (its folder, its views of the tree and /tmp) when
# --worker-memory is unlimited; else that (the tmpfs holding them is memory too)
PRIVATE_FOLDER_SIZE = 2 * 2**30


class TimeLimit(BaseException):
    """Raised in the launch file's code when its wall time runs out (BaseException: an
    `except Exception` in the launch file does not swallow it)."""


class CPULimit(BaseException):
    """Raised in the launch file's code when its CPU time runs out (SIGXCPU)."""


class Evaluator(Protocol):
    """What the requests mean, given by the process's entry (pkgforge.evaluation.requests): the
    sandbox forks, confines and limits; the evaluator imports, warms and evaluates."""

    def preload(self) -> None:
        """In the fork server, once: imports every worker forked from it starts with."""

    def prepare(self) -> None:
        """In a coordinator, once, before any request (no user code runs here)."""

    def warm(self, kind: str, work: str) -> None:
        """In a coordinator, before its first request of `kind` ("launch" or "setup"): what each
        such request's process would make lazily, made once (in `work`, the coordinator's folder)."""

    def evaluate(self, request: WorkerRequest, limits: WorkerLimits) -> WorkerReply:
        """The request's reply, in the confined process, with the limits armed."""

    def failed(self, request: WorkerRequest, error: BaseException) -> WorkerReply:
        """The reply when evaluate() raised (a limit hit while visiting): located where it can be."""

    def locate(self) -> tuple[str | None, int | None]:
        """Where the user's code being evaluated is now (the guard's refusals name it)."""


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


def stop_allowance() -> None:
    if _allowance is not None:
        _allowance.stop()


def disarm() -> None:
    import resource

    stop_allowance()
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
        if id(record) != id(result.get("error")):
            continue  # an entity's error is shown with its type already
        if breach[0] == "time":
            result["status"] = "timeout"
        elif breach[0] == "memory":
            # xacro's own words say where (which expression): keep them
            prefix = f"{original}: " if original and not original.startswith("MemoryError") else ""
            record["message"] = f"{prefix}MemoryError: {breach[1]}"


def subject(request: WorkerRequest) -> str:
    """The file a request evaluates."""
    if "file" in request:
        return request["file"]
    return request["model"] if "model" in request else request["setup"]


def _install_guard(own: str, evaluator: Evaluator) -> bool:
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

    guard.set_locator(evaluator.locate)
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


def answer(
    request: WorkerRequest,
    evaluator: Evaluator,
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
        guarded = _install_guard(own, evaluator)
        _apply_limits(limits)
        _confine(confinement)
        result = _evaluate(request, evaluator, limits, guarded)
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


def _evaluate(
    request: WorkerRequest, evaluator: Evaluator, limits: WorkerLimits, guarded: bool
) -> WorkerReply:
    """The request's reply, as plain data, with the limit a breach hit named in it."""
    result: WorkerReply
    try:
        try:
            _arm(limits)
            result = evaluator.evaluate(request, limits)
        finally:
            disarm()
    except BaseException as error:  # noqa: BLE001 - the reply must always come
        result = evaluator.failed(request, error)
    _mark_limits(result, limits)
    if "branching" in result and isinstance(result["branching"], dict):
        result["branching"]["limit"] = limits.get("timeout")
    if guarded:
        _refusals(result, request)
    return result
