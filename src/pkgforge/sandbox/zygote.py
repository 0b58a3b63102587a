"""Launch workers forked from one process that has imported them already (a fork server).

A fresh worker interpreter imports about 120 modules (the launch stand-ins,
lxml, xacro, yaml, the evaluator) before its first file: a quarter of the
workers' time on a workspace of scaffolded packages. The fork server
(`python -m pkgforge.sandbox.worker --fork-server`) imports them once, then
forks one child per worker the parent asks for. A child is what
`python -m pkgforge.sandbox.worker` would be, started the same way: its own
session, the parent's pipes on stdin and stdout, stderr on /dev/null, the
environment the parent gives it; then worker.main() runs in it as in a fresh
interpreter (the guard, the limits, the subreaper, the parent-death signal:
its parent is the server, which itself dies with pkgforge). Nothing of a
launch file runs in the server: it only imports, forks and reports exits.

The parent side (`Zygote`) starts the server (ensure(), from the main thread) and hands
each child's pipes over a Unix socket (SCM_RIGHTS); the server reports every
child's exit status, so `ForkedProcess` answers poll() and wait() as a
subprocess.Popen does.
"""

from __future__ import annotations

import json
import os
import queue
import signal
import socket
import subprocess
import sys
import threading
import time
from typing import TYPE_CHECKING

from pkgforge.sandbox.protocol import Confinement, Exited, Forked, ForkReply, ForkRequest, WorkerLimits

if TYPE_CHECKING:
    from pkgforge.launch.engines import LaunchEngine  # not imported at run time: the server starts first

LIMITS_VARIABLE = "PKGFORGE_WORKER_LIMITS"
# what the server's probe found the kernel allows (confinement.probe), for every worker it forks
_CONFINEMENT: Confinement | None = None
START_TIMEOUT = 60.0  # seconds for the server to fork a child (it imports first)


# --- the server -----------------------------------------------------------------------------


def serve(channel: int) -> None:
    """The fork server's loop on the socket `channel`; returns when the parent closes it."""
    import selectors

    from pkgforge.sandbox.processes import die_with_parent

    parent = os.getppid()
    die_with_parent(parent)
    from pkgforge.sandbox.processes import not_dumpable

    not_dumpable()  # (its socket to pkgforge is nothing a launch file may reach through /proc)
    # as in a worker: no byte code written, also for what the preload imports (xacro and
    # ament_index_python may come from the user's PYTHONPATH: a sourced overlay's folders)
    sys.dont_write_bytecode = True
    from pkgforge.sandbox import worker
    from pkgforge.sandbox.confinement import probe

    worker.preload()
    global _CONFINEMENT
    _CONFINEMENT = probe()  # once per run; each worker applies it (sandbox/coordinator.py)
    import gc

    gc.freeze()  # what the preload made stays on shared pages in every forked worker
    sock = socket.socket(fileno=channel)
    wake_read, wake_write = os.pipe()
    os.set_blocking(wake_write, False)
    signal.set_wakeup_fd(wake_write)
    signal.signal(signal.SIGCHLD, lambda *_: None)
    selector = selectors.DefaultSelector()
    selector.register(sock, selectors.EVENT_READ)
    selector.register(wake_read, selectors.EVENT_READ)
    while True:
        for key, _ in selector.select():
            if key.fileobj is wake_read:
                os.read(wake_read, 4096)
                continue
            try:
                message, fds, _, _ = socket.recv_fds(sock, 1 << 20, 2)
            except OSError:
                message, fds = b"", []
            if not message:
                return  # the parent is done (its children were stopped before)
            pid = os.fork()
            if pid == 0:
                _child(json.loads(message), fds, sock, (wake_read, wake_write))
            for fd in fds:
                os.close(fd)
            forked: Forked = {"pid": pid}
            sock.send(json.dumps(forked).encode())
        _report_exits(sock)


def _report_exits(sock: socket.socket) -> None:
    while True:
        try:
            pid, status = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return
        exited: Exited = {"exit": pid, "code": os.waitstatus_to_exitcode(status)}
        sock.send(json.dumps(exited).encode())


def _child(request: ForkRequest, fds: list[int], sock: socket.socket, wake: tuple[int, int]) -> None:
    """In the forked child: become a worker (its coordinator) as `python -m pkgforge.sandbox.worker`
    would. Never returns."""
    code = 1
    try:
        signal.set_wakeup_fd(-1)
        signal.signal(signal.SIGCHLD, signal.SIG_DFL)
        sock.close()
        for fd in wake:
            os.close(fd)
        os.setsid()
        stdin, stdout = fds
        os.dup2(stdin, 0)
        os.dup2(stdout, 1)
        os.close(stdin)
        os.close(stdout)
        env = dict(request["env"])
        limits: WorkerLimits = json.loads(env.get(LIMITS_VARIABLE) or "{}")
        limits["parent"] = os.getppid()  # dies with the server, which dies with pkgforge
        env[LIMITS_VARIABLE] = json.dumps(limits)
        os.environ.clear()
        os.environ.update(env)
        sys.stdin = open(0, encoding="utf-8", errors="replace", closefd=False)
        from pkgforge.sandbox import coordinator

        coordinator.main(_CONFINEMENT)
        code = 0
    except SystemExit as stop:
        code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
    except BaseException:  # noqa: BLE001 - a worker's own failure: the parent sees its exit
        code = 1
    finally:
        try:
            import atexit

            atexit._run_exitfuncs()  # what the interpreter would run at exit (the ros engine's scratch)
        finally:
            os._exit(code)


# --- the parent's side ----------------------------------------------------------------------


class _Server:
    """One running fork server: its process, its socket, the replies and exits it reported."""

    def __init__(self, env: dict[str, str]):
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        try:
            self.process = subprocess.Popen(
                [sys.executable, "-m", "pkgforge.sandbox.worker", "--fork-server", str(theirs.fileno())],
                pass_fds=[theirs.fileno()],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                env={k: v for k, v in env.items() if k != LIMITS_VARIABLE},
                start_new_session=True,
            )
        except BaseException:
            ours.close()
            raise
        finally:
            theirs.close()
        self.sock = ours
        self.forks: queue.Queue[Forked | None] = queue.Queue()
        self.exits: dict[int, int] = {}
        self.changed = threading.Condition()
        self.gone = False
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        while True:
            try:
                data = self.sock.recv(1 << 16)
            except OSError:
                data = b""
            if not data:
                break
            message: ForkReply = json.loads(data)
            if "exit" in message:
                with self.changed:
                    self.exits[message["exit"]] = message["code"]
                    self.changed.notify_all()
            else:
                self.forks.put(message)
        with self.changed:
            self.gone = True
            self.changed.notify_all()
        self.forks.put(None)

    def fork(self, env: dict[str, str]) -> ForkedProcess:
        """A new child with `env`, piped to this process; OSError when none came."""
        stdin_read, stdin_write = os.pipe()
        stdout_read, stdout_write = os.pipe()
        reply, cause = None, ""
        try:
            request: ForkRequest = {"env": env}
            socket.send_fds(self.sock, [json.dumps(request).encode()], [stdin_read, stdout_write])
            reply = self.forks.get(timeout=START_TIMEOUT)
        except (OSError, queue.Empty) as error:
            cause = f": {error}" if str(error) else ""
        finally:
            os.close(stdin_read)
            os.close(stdout_write)
        if not reply or "pid" not in reply:
            os.close(stdin_write)
            os.close(stdout_read)
            raise OSError(f"the launch workers' fork server ({sys.executable}) did not start a worker{cause}")
        return ForkedProcess(self, reply["pid"], stdin_write, stdout_read)

    def exit_code(self, pid: int, timeout: float | None) -> int | None:
        """The child's exit status (negative: the signal), waiting up to `timeout` seconds."""
        deadline = None if timeout is None else time.monotonic() + timeout
        with self.changed:
            while pid not in self.exits:
                if self.gone:  # the server died: its children came to pkgforge (the subreaper)
                    return _collect_orphan(pid)
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return None
                self.changed.wait(0.5 if left is None else min(left, 0.5))
            return self.exits[pid]

    def stop(self) -> None:
        try:
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        try:
            self.process.wait(timeout=2.0)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.sock.close()


def _collect_orphan(pid: int) -> int:
    try:
        _, status = os.waitpid(pid, 0)
        return os.waitstatus_to_exitcode(status)
    except ChildProcessError:
        return -signal.SIGKILL


class Zygote:
    """The fork server of one verify run (started again should it die); workers come from spawn()."""

    def __init__(self) -> None:
        self._server: _Server | None = None
        self._lock = threading.Lock()
        self._confinements: list[Confinement] = []

    def confined(self, confinement: Confinement) -> None:
        """What a worker's coordinator said confines the processes it forks (its hello)."""
        with self._lock:
            if confinement not in self._confinements:
                self._confinements.append(confinement)

    @property
    def confinement(self) -> Confinement | None:
        """The weakest confinement any worker of this run had; None when no worker ran."""
        with self._lock:
            found = list(self._confinements)
        if not found:
            return None
        return min(
            found,
            key=lambda c: (c["landlock"] > 0 or c["view"], c["signals"] or c["pid"], c["view"], c["pid"]),
        )

    @property
    def pid(self) -> int | None:
        return self._server.process.pid if self._server is not None else None

    def ensure(self, env: dict[str, str]) -> None:
        """Start the server unless it runs. From the thread that lives longest (the main one): the
        server's parent-death signal fires when the thread that started it ends."""
        with self._lock:
            if self._server is not None and self._server.gone:
                self._server.stop()
                self._server = None
            if self._server is None:
                self._server = _Server(env)

    def spawn(self, env: dict[str, str]) -> ForkedProcess:
        """A new worker with `env`, its stdin and stdout piped here (as subprocess.Popen would);
        OSError when none can be had."""
        with self._lock:
            if self._server is None or self._server.gone:
                raise OSError(f"the launch workers' fork server ({sys.executable}) is not running")
            return self._server.fork(env)

    def close(self) -> None:
        """End the server (its workers were stopped already)."""
        with self._lock:
            server, self._server = self._server, None
        if server is not None:
            server.stop()


def worker_environment(env: dict[str, str], engine: LaunchEngine) -> dict[str, str]:
    """A launch worker's environment: `env` (the tree's) with the real xacro and python3 first on
    PATH, and the engine's (launch.engines.LaunchEngine) variables."""
    env = dict(env)
    env["PATH"] = os.path.dirname(sys.executable) + os.pathsep + env.get("PATH", "")
    return engine.environment(env)


def start_zygote(engine: LaunchEngine) -> Zygote:
    """The run's fork server, started now (from the main thread), so that its imports overlap
    discovery and model loading; the tree's variables come with each worker. (Here, not in
    resolve.py: importing the resolver and the model layer first would delay the start ~0.15 s.)"""
    zygote = Zygote()
    try:
        zygote.ensure(worker_environment(dict(os.environ), engine))
    except OSError:
        pass  # run_requests tries again, and each worker says why it could not start
    return zygote


def _ended(pid: int) -> bool:
    """Whether the process has exited (a zombie, or gone)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as handle:
            stat = handle.read()
    except OSError:
        return True
    return stat[stat.rfind(b")") + 2 :][:1] in (b"Z", b"X")


class ForkedProcess:
    """A worker forked by the server, with the part of subprocess.Popen the pool uses."""

    def __init__(self, server: _Server, pid: int, stdin: int, stdout: int):
        self.server, self.pid = server, pid
        self.returncode: int | None = None
        self.stdin = open(stdin, "w", encoding="utf-8", errors="replace")
        self.stdout = open(stdout, encoding="utf-8", errors="replace")

    def poll(self) -> int | None:
        if self.returncode is None:
            self.returncode = self.server.exit_code(self.pid, 0)
            if self.returncode is None and _ended(self.pid):
                self.returncode = self.server.exit_code(self.pid, 5.0)
        return self.returncode

    def wait(self, timeout: float | None = None) -> int:
        if self.returncode is None:
            self.returncode = self.server.exit_code(self.pid, timeout)
            if self.returncode is None:  # only with a timeout: without one it waits for the exit
                raise subprocess.TimeoutExpired(f"launch worker {self.pid}", timeout or 0.0)
        return self.returncode
