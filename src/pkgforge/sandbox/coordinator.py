"""A launch worker's coordinator: one fresh, confined process per request, and the one reply it gives.

A worker is forked by the fork server (zygote.py) for one thread of the parent
(launch/resolve.py), which writes requests on its stdin and reads replies on its stdout.
No user code ever runs in the coordinator. For each request it:
1. reads the request line (byte by byte: nothing after it is in memory yet), makes the
   request's own folder and a pipe for its reply, and forks the process that evaluates it
   (worker.answer), which confines itself and then runs the launch file or xacro;
2. reads the request's token line, which the evaluating process therefore never holds;
3. waits for that process to end, not for the pipe to close (what it started may hold the
   pipe open): until its time limit (--launch-timeout, plus what it waited for a busy CPU,
   plus a grace), then kills it;
4. kills everything it left (in a PID namespace one kill(-1) ends all; otherwise the
   coordinator is a child subreaper and kills the tree below it);
5. reads what came on the pipe: exactly one JSON line is the reply; none is a crash; more
   than one means the launch file wrote on the channel itself, and the reply cannot be
   trusted;
6. writes the reply with the request and the token to the parent, and removes the folder.

Before its first request the coordinator enters the namespaces the fork server's probe found
(namespaces.py): then it is the first process of its own PID namespace, and the process it
was forked as only waits for it. Its first line to the parent says what confines each
request's process (protocol.Hello).
"""

from __future__ import annotations

import json
import os
import select
import signal
import sys
import tempfile
import time
from typing import Any, NoReturn

from pkgforge.sandbox import landlock, namespaces, processes, warmup, worker
from pkgforge.sandbox.confinement import probe
from pkgforge.sandbox.protocol import Confinement, Hello, WorkerLimits, WorkerRequest
from pkgforge.walk import remove_tree

KILL_GRACE = 2.0  # seconds past the time limit before a process that did not stop is killed
WORK_VARIABLE = "PKGFORGE_WORK"  # where each request's own folder is made (the parent's, per run)
# bytes of one reply: a process writing more is stopped (a reply is parsed into ~20 times its size:
# this bounds pkgforge's own memory; the records of real launch files stay far below it)
MAX_REPLY = 32 * 2**20
PR_SET_PDEATHSIG = 1

Reply = dict[str, Any]


def main(confinement: Confinement | None = None) -> None:
    """The coordinator on stdin (requests) and stdout (replies); returns when stdin closes.
    `confinement`: what the fork server's probe found (else probed here)."""
    confinement = probe() if confinement is None else confinement
    # Ctrl-C is pkgforge's to handle (it kills every worker); and no process of the same user
    # reads this one's descriptors or memory through /proc (the request sent ahead, its token)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    processes.not_dumpable()
    limits = worker.read_limits()
    if limits.get("parent"):
        processes.die_with_parent(int(limits["parent"]))
    work = os.environ.get(WORK_VARIABLE) or tempfile.mkdtemp(prefix="pkgforge-work-")
    from pkgforge.sandbox import guard

    applied = _enter(confinement, [*guard.writable_roots(), work])
    limits["parent"] = os.getpid()  # each request's process dies with this one
    landlock.abi_version()  # (loads the C library once, here, for every request's process)
    engine = worker.prepare()
    hello: Hello = {"hello": applied}
    _send(hello)
    prepared: set[str] = set()
    while True:
        line = _read_line(0)
        if line is None:
            return
        request: WorkerRequest = json.loads(line)
        _prepare_for(request, engine, work, prepared)
        own = tempfile.mkdtemp(prefix="request-", dir=work)
        reply_read, reply_write = os.pipe()
        child = os.fork()
        if child == 0:
            os.close(reply_read)
            worker.answer(request, engine, limits, reply_write, own, applied)
        os.close(reply_write)
        token = _read_line(0)  # read only now: the process that evaluates never holds it
        reply = _collect(child, reply_read, limits, applied)
        remove_tree(own)
        reply["request"] = request
        reply["token"] = (token or b"").decode(errors="replace")
        _send(reply)


def _prepare_for(request: WorkerRequest, engine: worker.Engine, work: str, prepared: set[str]) -> None:
    """What every process of the request's kind would import and cache, made once here before the
    first one is forked: the scaffold evaluated for launch files and models (warmup.py), setuptools
    for setup.py files. (A coordinator that answers only setup.py files warms no launch engine.)"""
    kind = "setup" if "setup" in request else "launch"
    if kind in prepared:
        return
    if kind == "setup":
        worker.prepare_setup()
    else:
        warmup.run(engine, work)
    import gc

    gc.freeze()  # (and left alone by the collector of each forked process)
    prepared.add(kind)


def _enter(confinement: Confinement, writable: list[str]) -> Confinement:
    """Enter what the probe found usable: the read-only view, then (first process of a new PID
    namespace) a /proc of its own; else become a child subreaper. → what is in force."""
    applied: Confinement = {**confinement, "why": list(confinement["why"])}
    if applied["view"]:
        try:
            namespaces.enter_view(writable)
        except OSError as error:
            applied["view"] = applied["pid"] = False
            applied["network"] = applied["landlock"] >= landlock.NET_ABI
            applied["why"].append(f"namespaces: {error}")
    applied["pid"] = applied["pid"] and applied["view"]
    if applied["pid"]:
        try:
            namespaces.new_pid_namespace()
        except OSError as error:
            applied["pid"] = False
            applied["why"].append(f"PID namespace: {error}")
        else:
            first = os.fork()
            if first != 0:
                _wait_for_coordinator(first)
            _prctl_death_signal()  # (its parent is outside the namespace: no getppid() check)
            try:
                namespaces.mount_proc()
            except OSError as error:  # still its own PID namespace: kill_all holds; /proc shows more
                applied["why"].append(f"PID namespace without its own /proc: {error}")
    if not applied["pid"]:
        processes.become_subreaper()
    return applied


def _wait_for_coordinator(first: int) -> NoReturn:
    """The process the worker was forked as, once the coordinator runs in the PID namespace: it
    holds nothing and only waits, so that the worker ends when the coordinator does."""
    code = 1
    try:
        for fd in (0, 1):
            os.close(fd)
        while True:
            try:
                _, status = os.waitpid(first, 0)
                code = os.waitstatus_to_exitcode(status)
                break
            except InterruptedError:
                continue
    finally:
        os._exit(code if code >= 0 else 128 - code)


def _prctl_death_signal() -> None:
    processes._prctl(PR_SET_PDEATHSIG, signal.SIGKILL)


def _read_line(fd: int) -> bytes | None:
    """One line from `fd`, read a byte at a time (nothing past it is read); None at the end."""
    line = bytearray()
    while True:
        try:
            byte = os.read(fd, 1)
        except InterruptedError:
            continue
        if not byte:
            return bytes(line) if line else None
        if byte == b"\n":
            return bytes(line)
        line += byte


def _send(message: object) -> None:
    data = (json.dumps(message, default=str) + "\n").encode()
    view = memoryview(data)
    while view:
        view = view[os.write(1, view) :]


# --- one request's process ------------------------------------------------------------------


def _collect(child: int, replies: int, limits: WorkerLimits, confinement: Confinement) -> Reply:
    """Wait for the request's process to end (at most its time limit, and then kill it), end what
    it left, and read its reply."""
    timeout = limits.get("timeout")
    allowance = processes.LoadAllowance(float(timeout), child) if timeout else None
    deadline = time.monotonic() + float(timeout) + KILL_GRACE if timeout else None
    exited = _pidfd(child)
    received = bytearray()
    os.set_blocking(replies, False)
    poller = select.poll()
    poller.register(replies, select.POLLIN)
    if exited is not None:
        poller.register(exited, select.POLLIN)
    timed_out = too_big = ended = False
    reading = True
    while not ended:
        wait = None if deadline is None else deadline - time.monotonic()
        if wait is not None and wait <= 0:
            more = allowance.more() if allowance is not None else 0.0
            if more and allowance is not None and _own_load(child) >= allowance.granted:
                more = 0.0  # it waited for its own processes (a fork bomb), not for a busy machine
            if more and deadline is not None:
                deadline = time.monotonic() + more
                continue
            _kill(child)
            timed_out = True
            break
        if exited is None:  # no pidfd (Linux < 5.3): look every few milliseconds
            wait = 0.005 if wait is None else min(wait, 0.005)
        for fd, _ in poller.poll(None if wait is None else max(1, int(wait * 1000))):
            if fd == replies and reading:
                reading = _drain(replies, received)
                if not reading:
                    poller.unregister(replies)
                if len(received) > MAX_REPLY:
                    _kill(child)
                    too_big = True
                    ended = True
            elif fd == exited:
                ended = True
        if exited is None and not ended:
            ended = _ended(child)
    status = _reap(child)
    if exited is not None:
        os.close(exited)
    _end_the_rest(confinement)
    if not too_big:
        _drain(replies, received)  # everything that could write is gone: up to the end now
    os.close(replies)
    if timed_out:
        return timeout_reply(float(timeout or 0.0), allowance.granted if allowance is not None else 0.0)
    return _reply(bytes(received), status, limits, too_big=too_big)


def _own_load(child: int) -> float:
    """CPU seconds the request's other processes used: every process below the coordinator but the
    request's own (which it waited for: its children's times, as they ended)."""
    ticks = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
    total = 0
    for pid in processes.descendants(os.getpid()):
        try:
            with open(f"/proc/{pid}/stat", "rb") as handle:
                fields = handle.read().rsplit(b")", 1)[1].split()
        except (OSError, IndexError):
            continue
        # (after the name: state is field 0; utime, stime, cutime, cstime are 11 to 14)
        own, children = int(fields[11]) + int(fields[12]), int(fields[13]) + int(fields[14])
        total += children if pid == child else own
    return total / ticks


def _pidfd(pid: int) -> int | None:
    try:
        return os.pidfd_open(pid)
    except (AttributeError, OSError):
        return None


def _drain(fd: int, into: bytearray) -> bool:
    """Read what is there now; False at the end of the pipe."""
    while len(into) <= MAX_REPLY:
        try:
            data = os.read(fd, 1 << 16)
        except BlockingIOError:
            return True
        except InterruptedError:
            continue
        if not data:
            return False
        into += data
    return True


def _kill(pid: int) -> None:
    try:
        os.kill(pid, signal.SIGKILL)
    except OSError:
        pass


def _ended(pid: int) -> bool:
    """Whether the child has exited (its status left for _reap)."""
    try:
        return os.waitid(os.P_PID, pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is not None
    except ChildProcessError:
        return True


def _reap(pid: int) -> int | None:
    while True:
        try:
            _, status = os.waitpid(pid, 0)
            return os.waitstatus_to_exitcode(status)
        except InterruptedError:
            continue
        except ChildProcessError:
            return None


def _end_the_rest(confinement: Confinement) -> None:
    """Kill whatever the request's process started and left."""
    if confinement["pid"] or os.getpid() == 1:
        namespaces.kill_all()
        return
    for _ in range(1000):  # a child subreaper: whatever is left below it hangs on one of its children
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return  # nothing left
        if pid == 0:  # one still runs: stop and kill them all
            processes.reap(processes.kill_tree(processes.descendants(os.getpid())), timeout=2.0)


def _reply(received: bytes, status: int | None, limits: WorkerLimits, *, too_big: bool) -> Reply:
    """The one reply line the process wrote, or the coordinator's own when there is not exactly one."""
    if too_big:
        return _crashed(f"the process evaluating it wrote more than {MAX_REPLY // 2**20} MiB of result")
    lines = [line for line in received.split(b"\n") if line.strip()]
    if not lines:
        return _crashed(death_message(status, limits))
    if len(lines) > 1:
        return _crashed(
            f"the launch file wrote on the channel its result comes back on ({len(lines)} results "
            "instead of one): it writes to a file descriptor it did not open, and no result of it "
            "can be trusted",
            kind="ForgedResult",
        )
    try:
        reply: object = json.loads(lines[0])
    except (ValueError, RecursionError):
        return _crashed(
            "the process evaluating it wrote something that is not a result "
            "(it wrote to a file descriptor it does not own)"
        )
    if not isinstance(reply, dict):
        return _crashed("the launch worker gave no result")
    return reply


def _crashed(message: str, kind: str | None = None) -> Reply:
    error: dict[str, Any] = {"message": message, "line": None}
    if kind is not None:
        error["type"] = kind
    return {"status": "crashed", "error": error}


def timeout_reply(timeout: float, granted: float = 0.0) -> Reply:
    busy = f" and {granted:.1f} s more it waited for a busy CPU" if granted else ""
    return {
        "status": "timeout",
        "error": {
            "message": f"still running after the {timeout:g} s limit{busy} (an endless loop, or "
            "waiting for something); raise it with --launch-timeout",
            "line": None,
            "limit": "time",
        },
    }


def death_message(code: int | None, limits: WorkerLimits) -> str:
    """Why a process ended without a reply, from its exit status."""
    if code is not None and code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        cause = {
            "SIGKILL": "killed (SIGKILL: by the system's out-of-memory killer, or by the launch file)",
            "SIGXCPU": f"stopped at the {limits.get('timeout') or 0:g} s CPU time limit "
            "(raise it with --launch-timeout)",
            "SIGSEGV": "crashed (SIGSEGV in an extension module)",
        }.get(name, f"killed by {name}")
        return f"the process evaluating it was {cause}, without a result"
    return (
        f"the process evaluating it exited (status {code}) without a result "
        "(os._exit or a crash in an extension module)"
    )


if __name__ == "__main__":  # pragma: no cover - `python -m pkgforge.sandbox.worker` is the entry
    main()
    sys.exit(0)
