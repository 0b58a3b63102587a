"""Child processes pkgforge starts, and everything they start: none outlives a run.

On Linux pkgforge makes itself a child subreaper (prctl PR_SET_CHILD_SUBREAPER),
and so does each launch worker: a process a launch file double-forks and
detaches with setsid is re-parented to the worker (or, should the worker have
died, to pkgforge) instead of to init, so it stays in the process tree read from
/proc. A tree is stopped (SIGSTOP, until no new process appears: a stopped
process cannot fork), then killed (SIGKILL) and reaped.

SIGINT, SIGTERM and SIGHUP kill every descendant at once and unwind the run
(temporary trees are removed) with exit status 128 + the signal number.
"""

from __future__ import annotations

import ctypes
import functools
import os
import re
import signal
import sys
import threading
import time
from collections.abc import Set as AbstractSet
from types import FrameType

PR_SET_PDEATHSIG = 1
PR_SET_CHILD_SUBREAPER = 36
HANDLED_SIGNALS = ("SIGINT", "SIGTERM", "SIGHUP")
DEFAULT_WORKER_MEMORY = 2 * 2**30  # bytes of address space per launch worker (--worker-memory)

# set when a signal asked pkgforge to stop: no new worker starts after it
cancelled = threading.Event()


class Interrupted(SystemExit):
    """pkgforge was asked to stop by a signal; exits with 128 + the signal number."""

    def __init__(self, signum: int):
        super().__init__(128 + signum)
        self.signum = signum


def _prctl(option: int, value: int) -> bool:
    if not sys.platform.startswith("linux"):
        return False
    try:
        status: int = _libc().prctl(option, value, 0, 0, 0)  # ctypes: C int
        return status == 0
    except (OSError, AttributeError):
        return False


@functools.cache
def _libc() -> ctypes.CDLL:
    return ctypes.CDLL(None, use_errno=True)  # once: a CDLL costs a dlopen


PR_SET_DUMPABLE = 4


def not_dumpable() -> bool:
    """No process without CAP_SYS_PTRACE may read this one's /proc/<pid>/fd, mem or environ, even
    of the same user (a launch file's process, whose capabilities are dropped). Reset at exec."""
    return _prctl(PR_SET_DUMPABLE, 0)


def become_subreaper() -> bool:
    """Orphaned descendants are re-parented to this process, not to init (Linux 3.4+)."""
    return _prctl(PR_SET_CHILD_SUBREAPER, 1)


def die_with_parent(parent: int) -> None:
    """SIGKILL this process when its parent dies (even by SIGKILL), on Linux."""
    if _prctl(PR_SET_PDEATHSIG, signal.SIGKILL) and os.getppid() != parent:
        os._exit(1)  # the parent died before the request was made


# --- the process tree -----------------------------------------------------------------------

_STAT = re.compile(rb"\) \S+ (\d+)")


def _children_map() -> dict[int, list[int]]:
    children: dict[int, list[int]] = {}
    try:
        names = os.listdir("/proc")
    except OSError:
        return children
    for name in names:
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat", "rb") as handle:
                stat = handle.read()
        except OSError:
            continue
        match = _STAT.search(stat, stat.rfind(b")"))
        if match:
            children.setdefault(int(match.group(1)), []).append(int(name))
    return children


def descendants(*roots: int) -> set[int]:
    """Every live process below the roots (not the roots themselves)."""
    children = _children_map()
    found: set[int] = set()
    todo = list(roots)
    while todo:
        for child in children.get(todo.pop(), []):
            if child not in found:
                found.add(child)
                todo.append(child)
    return found


def _signal(pid: int, signum: int) -> None:
    try:
        os.kill(pid, signum)
    except (ProcessLookupError, PermissionError):
        pass


def kill_tree(
    roots: AbstractSet[int], *, below: AbstractSet[int] = frozenset(), skip: AbstractSet[int] = frozenset()
) -> set[int]:
    """Stop, then kill, the `roots` and every process below them and below `below`.

    Processes are stopped until the tree stops growing (a stopped process cannot
    fork or reap), so none escapes by forking while the tree is read. `skip`
    (pkgforge itself) is never signalled. Returns the pids killed.
    """
    stopped: set[int] = set()
    for _ in range(200):
        tree = (set(roots) | descendants(*roots, *below)) - set(skip) - {os.getpid()}
        new = tree - stopped
        if not new:
            break
        for pid in new:
            _signal(pid, signal.SIGSTOP)
        stopped |= new
    for pid in stopped:
        _signal(pid, signal.SIGKILL)
    return stopped


def reap(pids: AbstractSet[int], *, timeout: float = 2.0, keep: AbstractSet[int] = frozenset()) -> None:
    """Collect the exit status of killed processes re-parented to this one (no zombies left).

    `keep`: children whose status their subprocess.Popen object collects.
    """
    pending = set(pids) - set(keep)
    deadline = time.monotonic() + timeout
    while pending and time.monotonic() < deadline:
        for pid in list(pending):
            try:
                done, _ = os.waitpid(pid, os.WNOHANG)
            except ChildProcessError:  # not (yet) this process's child: gone, or re-parented later
                if not os.path.exists(f"/proc/{pid}"):
                    pending.discard(pid)
                continue
            if done:
                pending.discard(pid)
        if pending:
            time.sleep(0.005)


def kill_descendants(*, except_for: AbstractSet[int] = frozenset()) -> None:
    """Kill and reap every process below this one (all workers, colcon, what they started)."""
    me = os.getpid()
    roots = descendants(me) - set(except_for)
    if roots:
        reap(kill_tree(roots, skip={me}), timeout=0.5)


# --- signals --------------------------------------------------------------------------------

_handling = False


def _on_signal(signum: int, frame: FrameType | None) -> None:
    global _handling
    cancelled.set()
    kill_descendants()
    if _handling:  # a second signal while unwinding: stop now
        os._exit(128 + signum)
    _handling = True
    raise Interrupted(signum)


def install_signal_handlers() -> None:
    """SIGINT, SIGTERM, SIGHUP: kill every descendant, unwind, exit 128 + signal (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        return
    become_subreaper()
    for name in HANDLED_SIGNALS:
        signum = getattr(signal, name, None)
        if signum is None:
            continue
        if name == "SIGHUP" and signal.getsignal(signum) == signal.SIG_IGN:
            continue  # started under nohup: keep ignoring it
        signal.signal(signum, _on_signal)


# --- sizes ----------------------------------------------------------------------------------

_SIZE = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([kmgt]?)(?:i?b)?\s*$", re.IGNORECASE)


# the launch wall-time limit grows with the time a worker waited for a busy CPU, to at most this many
# times --launch-timeout: a loaded machine slows a file down, it does not make it endless. Generous on
# purpose: what the wall limit is for (a sleep, input(), a socket) waits for no CPU and gets nothing,
# and an endless loop hits the CPU-time limit (the same seconds, whatever the load) anyway; the bound
# is only for a worker starved outright
MAX_LOAD_FACTOR = 10.0


def run_delay(pid: int | str = "self") -> float | None:
    """Seconds the threads of process `pid` were ready to run but waited for a CPU (Linux's
    schedstat run_delay): what a busy machine added to its wall time. None where not known."""
    total, found = 0, False
    try:
        tasks = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return None
    for task in tasks:
        try:
            with open(f"/proc/{pid}/task/{task}/schedstat") as handle:
                total += int(handle.read().split()[1])
                found = True
        except (OSError, ValueError, IndexError):
            continue  # a thread that ended meanwhile
    return total / 1e9 if found else None


class LoadAllowance:
    """How much more wall time a process gets because it waited for a CPU since `start`:
    `more()` grants what it waited beyond what was granted so far, up to (MAX_LOAD_FACTOR - 1)
    times the limit in all. A process that sleeps or blocks waits for no CPU, so it gets nothing."""

    def __init__(self, limit: float, pid: int | str = "self"):
        self.pid, self.cap, self.granted = pid, (MAX_LOAD_FACTOR - 1) * limit, 0.0
        self.start = run_delay(pid)

    def more(self, least: float = 0.05) -> float:
        now = run_delay(self.pid)
        if now is None or self.start is None:
            return 0.0
        extra = min(now - self.start, self.cap) - self.granted
        if extra < least:
            return 0.0
        self.granted += extra
        return extra

    def stop(self) -> None:
        """No more grants: `granted` stays what it is."""
        self.cap = self.granted


def parse_size(text: str) -> int:
    """'2G', '512M', '1.5GiB', '300000000' → bytes; ValueError otherwise."""
    match = _SIZE.match(text)
    if not match:
        raise ValueError(f"'{text}' is not a size such as 2G or 512M")
    factor = 1024 ** " kmgt".index(match.group(2).lower() or " ")
    return int(float(match.group(1)) * factor)


def format_size(size: int) -> str:
    for unit, factor in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if size >= factor:
            value = size / factor
            return f"{value:g} {unit}" if value == int(value) else f"{value:.1f} {unit}"
    return f"{size} bytes"
