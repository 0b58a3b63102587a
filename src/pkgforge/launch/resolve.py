"""Resolving every launch file of the verified packages, in worker subprocesses.

The parent hands each worker a batch of files, one at a time, and waits for
each reply no longer than the time limit; a worker that runs past it (a loop,
a hang) or dies (os._exit) is killed and replaced, and the file is reported.
"""

from __future__ import annotations

import json
import os
import queue
import secrets
import subprocess
import sys
import tempfile
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any, cast

from pkgforge.launch.engines import BUILTIN, LaunchEngine
from pkgforge.launch.records import ITEM_KINDS as ITEM_KINDS  # (imported from here too)
from pkgforge.launch.records import LaunchFile as LaunchFile
from pkgforge.launch.records import LaunchResultDict, Resolution, resolution_from_reply
from pkgforge.model.package import PackageModel
from pkgforge.model.references import launch_kind
from pkgforge.sandbox import processes
from pkgforge.sandbox.coordinator import KILL_GRACE, MAX_REPLY, WORK_VARIABLE, death_message, timeout_reply
from pkgforge.sandbox.protocol import Confinement, Hello, LaunchRequest, WorkerRequest
from pkgforge.sandbox.zygote import START_TIMEOUT, ForkedProcess, Zygote, worker_environment
from pkgforge.tree import PREFIX as TREE_PREFIX
from pkgforge.tree import InstallTree
from pkgforge.walk import remove_tree, walk

DEFAULT_TIMEOUT = 10.0
DEFAULT_WORKER_MEMORY = processes.DEFAULT_WORKER_MEMORY
AHEAD_LIMIT = 16384  # bytes of a request sent ahead to a busy worker: a quarter of a Linux pipe
STOP_GRACE = 2.0  # seconds an idle worker has to end after its stdin closed, before it is killed
TOKEN_BYTES = 16  # a request's token: random, so that nothing can write a reply that carries it
MAX_REPLY_LINE = MAX_REPLY  # characters of one reply line (the coordinator already stops a longer one)
# a result that depends on the machine's load or limits, never cached
MACHINE_DEPENDENT = ("timeout", "crashed")

# what crosses the worker's pipe: one JSON object per line (a launch file's LaunchResultDict, or a
# model's reply: robot_models.py), the parent's own when the worker timed out or crashed
Reply = dict[str, Any]


def _died() -> Reply:
    """The parent's own answer for a request its worker could not take or never answered."""
    return {"status": "crashed", "error": {"message": "the launch worker died", "line": None}}


def find_launch_files(
    tree: InstallTree, models: list[PackageModel]
) -> tuple[list[LaunchFile], list[LaunchFile]]:
    """(launch files, ROS 1 .launch files) installed by the given packages."""
    found: list[LaunchFile] = []
    ros1: list[LaunchFile] = []
    for model in models:
        share = tree.share(model.share_name)
        if share is None or not share.is_dir():
            continue
        # links followed only inside the share folder or back into the package's source
        # (--symlink-install), each folder once: a link cycle is not an endless walk
        for root, dirs, files in walk(
            share, follow_links=True, inside=(model.path,), limits=model.walk_limits
        ):
            dirs[:] = sorted(
                d for d in dirs if d not in ("test", "tests", "__pycache__") and not d.startswith(".")
            )
            for name in sorted(files):
                installed = Path(root) / name
                if name.endswith(".launch") and not name.endswith((".launch.py", ".launch.xml")):
                    ros1.append(LaunchFile(model.name, installed, source_of(installed, tree, model)))
                    continue
                if name.startswith("test_") or not _is_launch_file(installed):
                    continue
                found.append(LaunchFile(model.name, installed, source_of(installed, tree, model)))
    return found, ros1


def _is_launch_file(path: Path) -> bool:
    kind = launch_kind(path)
    if kind is None:
        return False
    if path.name.endswith((f".launch.{kind}", f"_launch.{kind}")):
        return True
    from pkgforge.model.source import read_head

    try:  # (NotRegularFile is an OSError: a FIFO or /dev/zero is never read)
        head = read_head(path, 65536)[0].decode(errors="replace")
    except OSError:
        return False
    if kind == "py":
        return "generate_launch_description" in head
    return "<launch" in head if kind == "xml" else head.lstrip().startswith("launch:")


def source_of(installed: Path, tree: InstallTree, model: PackageModel | None) -> Path | None:
    """The source file in `model`'s package that an installed file came from (by the layout,
    else by name); None when the file belongs to another package or has no source."""
    located = tree.locate(str(installed))
    if located is None or model is None or located[0] not in (model.name, model.share_name):
        return None
    package, relative, _ = located
    entry = model.layout.files.get(f"share/{package}/{relative}")
    if entry is not None and entry.source is not None:
        return entry.source
    candidate = model.path / relative
    return candidate if os.path.isfile(candidate) else None  # no PermissionError


@dataclass(frozen=True)
class WorkerLimits:
    """What one launch worker may use: wall and CPU time per file, address space, open files."""

    timeout: float = DEFAULT_TIMEOUT
    memory: int | None = DEFAULT_WORKER_MEMORY  # bytes; None: no limit

    def environment(self) -> str:
        return json.dumps({"timeout": self.timeout, "memory": self.memory, "parent": os.getpid()})


class _Worker:
    """One worker subprocess (its coordinator, sandbox/coordinator.py, forks a fresh confined
    process per request), in its own session; stopping it kills everything below it too
    (processes.kill_tree), including detached children."""

    def __init__(self, env: dict[str, str], limits: WorkerLimits | None = None, zygote: Zygote | None = None):
        self.env = env
        self.limits = limits or WorkerLimits()
        self.zygote = zygote
        self.process: subprocess.Popen[str] | ForkedProcess | None = None
        self.replies: queue.Queue[str | None] = queue.Queue()
        # the token and request of each request it has and has not answered, oldest first
        self.tokens: deque[tuple[str, WorkerRequest]] = deque()
        self.confinement: Confinement | None = None  # what its coordinator said confines each request

    @property
    def in_flight(self) -> int:
        return len(self.tokens)

    def start(self) -> subprocess.Popen[str] | ForkedProcess:
        if processes.cancelled.is_set():
            raise _Cancelled()
        env = dict(self.env, PKGFORGE_WORKER_LIMITS=self.limits.environment())
        process: subprocess.Popen[str] | ForkedProcess
        if self.zygote is not None:  # forked after its imports: the same worker, started sooner
            process = self.zygote.spawn(env)
        else:
            process = subprocess.Popen(
                [sys.executable, "-m", "pkgforge.evaluation"],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                env=env,
                text=True,
                errors="replace",
                start_new_session=True,
            )
        self.process = process
        self.replies = queue.Queue()
        self.tokens.clear()
        threading.Thread(target=self._read, args=(_pipe(process.stdout), self.replies), daemon=True).start()
        self.confinement = self._hello()
        if self.zygote is not None:
            self.zygote.confined(self.confinement)
        return process

    def _hello(self) -> Confinement:
        """The coordinator's first line: what confines the processes it forks."""
        try:
            line = self.replies.get(timeout=START_TIMEOUT)
            if line is None:
                raise ValueError("no line")
            hello: Hello = json.loads(line)
            return hello["hello"]
        except (queue.Empty, ValueError, TypeError, KeyError) as error:
            self.stop()
            raise OSError(
                f"the launch worker ({sys.executable}) did not start ({type(error).__name__})"
            ) from None

    @staticmethod
    def _read(stdout: IO[str], replies: queue.Queue[str | None]) -> None:
        try:
            for line in stdout:
                replies.put(line)
        except (OSError, ValueError):
            pass
        replies.put(None)

    def send(self, request: WorkerRequest) -> Reply | None:
        """Hand the worker a request when it has none (one started first when there is none);
        the reply (crashed) when it cannot take it, else None: `receive` gives the answer."""
        process = self.process
        if process is None or process.poll() is not None:
            try:
                process = self.start()
            except OSError as exc:  # an answer too: never a thread's traceback
                return {
                    "status": "crashed",
                    "error": {
                        "message": f"cannot start the launch worker {exc.filename or sys.executable}: "
                        f"{exc.strerror or exc}",
                        "line": None,
                    },
                }
        if not self._write(process, request):
            self.stop()
            return _died()
        return None

    def send_ahead(self, request: WorkerRequest) -> bool:
        """Queue a request behind the one the worker is on, so that it starts it the moment it
        answered (not when the parent's thread gets round to sending it); False when the worker
        cannot take it now (the caller sends it again later)."""
        process = self.process
        # the worker is busy: a write that fills the pipe would block this thread before it starts
        # watching the worker's time (a hung worker would then hang pkgforge). One request at most
        # waits in the pipe, so a small one never blocks; a larger one waits for an idle worker
        if len(json.dumps(request).encode()) + TOKEN_BYTES * 2 + 2 > AHEAD_LIMIT:
            return False
        return process is not None and process.poll() is None and self._write(process, request)

    def _write(self, process: subprocess.Popen[str] | ForkedProcess, request: WorkerRequest) -> bool:
        """The request line, then its token line (protocol.Envelope); in flight once written."""
        token = secrets.token_hex(TOKEN_BYTES)
        try:
            stdin = _pipe(process.stdin)
            stdin.write(json.dumps(request) + "\n" + token + "\n")
            stdin.flush()
        except (BrokenPipeError, OSError):
            return False
        self.tokens.append((token, request))
        return True

    def receive(self, timeout: float) -> Reply:
        """The answer to the oldest request the worker has: its reply, or the parent's own when
        the worker died or its reply does not carry the request's token (it is stopped then, with
        any request queued behind). The coordinator stops a request's process at its time limit;
        past BACKSTOP times that (what a busy CPU may add, and a grace) the worker itself is stuck."""
        process = self.process
        if process is None:
            return _died()
        deadline = time.monotonic() + (timeout + KILL_GRACE) * processes.MAX_LOAD_FACTOR + KILL_GRACE
        expected = self.tokens.popleft() if self.tokens else None
        try:
            line = self.replies.get(timeout=max(0.1, deadline - time.monotonic()))
        except queue.Empty:
            self.stop()
            return timeout_reply(timeout)
        if line is None:
            try:  # its replies closed: it is ending (or closed them and goes on: killed below)
                code = process.wait(timeout=1.0)
            except subprocess.TimeoutExpired:
                code = None
            self.stop()
            return {"status": "crashed", "error": {"message": _death(code, self.limits), "line": None}}
        if len(line) > MAX_REPLY_LINE:
            self.stop()
            return malformed_reply(f"a line of {len(line) // 2**20} MiB")
        try:
            reply: object = json.loads(line)
        except (ValueError, RecursionError):
            reply = None
        if (
            not isinstance(reply, dict)
            or expected is None
            or reply.pop("token", None) != expected[0]
            or reply.get("request") != expected[1]
        ):
            self.stop()
            return {
                "status": "crashed",
                "error": {
                    "message": "the launch worker's answer does not carry its request's token: something "
                    "else wrote on its channel, and no result of it can be trusted",
                    "line": None,
                    "type": "ForgedResult",
                },
            }
        return reply

    def stop(self, *, polite: bool = False) -> None:
        """End the worker and every process below it, and reap them.

        `polite` (the worker answered and waits for its next request): what it started is killed,
        its stdin closed, and it ends as it would after its last request (coverage.py writes its
        data then); killed after STOP_GRACE seconds all the same. Otherwise, or when it has a
        request still to answer (it would start on that first), it is killed at once.
        """
        process, self.process = self.process, None
        in_flight = self.in_flight
        self.tokens.clear()
        if process is None:
            return
        killed: set[int] = set()
        if polite and not in_flight and process.poll() is None and not processes.cancelled.is_set():
            try:
                if process.stdin is not None:
                    process.stdin.close()
                process.wait(timeout=STOP_GRACE)
            except (OSError, subprocess.TimeoutExpired):
                pass
        # (a worker that died already left its processes to pkgforge: run_requests kills those)
        if process.poll() is None:
            killed |= processes.kill_tree({process.pid})
        process.wait()
        processes.reap(killed, keep={process.pid})
        for stream in (process.stdin, process.stdout):
            try:
                if stream is not None:
                    stream.close()
            except OSError:
                pass


def _pipe(stream: IO[str] | None) -> IO[str]:
    """A worker's stdin or stdout: always a pipe (subprocess.PIPE, or the fork server's)."""
    if stream is None:
        raise OSError("the launch worker has no pipe")
    return stream


class _Cancelled(Exception):
    """A signal asked pkgforge to stop: no new worker."""


def _death(code: int | None, limits: WorkerLimits) -> str:
    """Why the worker (its coordinator) ended without answering."""
    return death_message(code, {"timeout": limits.timeout}).replace(
        "the process evaluating it", "the launch worker"
    )


def run_requests(
    requests: Sequence[WorkerRequest],
    tree: InstallTree,
    *,
    jobs: int = 1,
    timeout: float = DEFAULT_TIMEOUT,
    on_done: Callable[[], object] | None = None,
    limits: WorkerLimits | None = None,
    engine: LaunchEngine = BUILTIN,
    zygote: Zygote | None = None,
    convert: Callable[[int, Reply], Any] | None = None,
) -> list[Any]:
    """Each request answered by a worker subprocess, in order; a hang or crash is an answer too.
    `convert(index, reply)`: what to keep of each reply, called as it comes (a reply's plain data
    is dropped at once instead of all of them living until the last worker ends: the peak memory).

    Workers are forked from `zygote` (the run's fork server; without one, a fork server for
    this call). Every worker, and everything the launch files started, is gone when this
    returns (or raises: a signal stops pkgforge, see processes.py).
    """
    if not requests:
        return []
    own = zygote is None
    if zygote is None:
        zygote = Zygote()
    limits = WorkerLimits(timeout, limits.memory if limits is not None else DEFAULT_WORKER_MEMORY)
    processes.become_subreaper()
    processes.not_dumpable()  # pkgforge's own descriptors: out of any launch file's reach
    before = processes.descendants(os.getpid())
    env = worker_environment(tree.environment(), engine)
    # the real engine's logs and temporary parameter files: removed here, however its workers end
    # inside the tree's sandbox when there is one: the worker's guard refuses writes anywhere else
    scratch = (
        tempfile.mkdtemp(prefix="pkgforge-launch-", dir=env.get("PKGFORGE_SANDBOX"))
        if engine.name == "ros"
        else None
    )
    if scratch is not None:
        env["PKGFORGE_SCRATCH"] = scratch
    # each request's own folder is made in here (beside the tree, not in it: the kernel lets a
    # request's process write the tree and its own folder, never another request's)
    sandbox = env.get("PKGFORGE_SANDBOX")
    own_folders = tempfile.mkdtemp(  # (named as a tree: removed by the next run if this one is killed)
        prefix=f"{TREE_PREFIX}{os.getpid()}-work-", dir=os.path.dirname(sandbox) if sandbox else None
    )
    env[WORK_VARIABLE] = own_folders
    work: queue.Queue[tuple[int, WorkerRequest]] = queue.Queue()
    for index, request in enumerate(requests):
        work.put((index, request))
    # a reply, or (its conversion,) once converted as it came
    replies: list[Any] = [None] * len(requests)

    def answered(index: int, reply: Reply) -> None:
        replies[index] = reply
        if convert is not None:
            replies[index] = (_converted(convert, index, reply),)
        if on_done is not None:
            on_done()

    def run() -> None:
        worker = _Worker(env, limits, zygote)
        # taken from `work`, not answered, and not with the current worker (a stopped worker's)
        backlog: deque[tuple[int, WorkerRequest]] = deque()
        sent: deque[tuple[int, WorkerRequest]] = deque()  # with the worker, oldest first

        def take() -> tuple[int, WorkerRequest] | None:
            if backlog:
                return backlog.popleft()
            try:
                return work.get_nowait()
            except queue.Empty:
                return None

        try:
            while not processes.cancelled.is_set():
                if not sent:
                    item = take()
                    if item is None:
                        return
                    failure = worker.send(item[1])
                    if failure is not None:
                        answered(item[0], failure)
                        continue
                    sent.append(item)
                # one request ahead: the worker goes on the moment it answered, instead of waiting
                # for this thread to read, convert, and send (measured: ~4 ms idle per file)
                ahead = take()
                if ahead is not None:
                    if worker.send_ahead(ahead[1]):
                        sent.append(ahead)
                    else:
                        backlog.appendleft(ahead)
                index, _ = sent.popleft()
                reply = worker.receive(timeout)
                if worker.process is None:  # stopped: what it had not answered goes to a fresh one
                    backlog.extendleft(reversed(sent))
                    sent.clear()
                answered(index, reply)
        except _Cancelled:
            return
        finally:
            worker.stop(polite=True)

    threads = [threading.Thread(target=run, daemon=True) for _ in range(max(1, min(jobs, len(requests))))]
    try:
        try:
            zygote.ensure(env)
        except OSError:
            pass  # each worker says it could not start
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    finally:
        if own:
            zygote.close()
        # anything a worker left that escaped its tree (re-parented here) is killed too
        leftover = processes.descendants(os.getpid()) - before - {zygote.pid}
        if leftover:
            processes.reap(processes.kill_tree(leftover, skip=before), timeout=0.5)
        if scratch is not None:
            remove_tree(scratch)
        remove_tree(own_folders)
    for index, reply in enumerate(replies):
        if reply is None:
            replies[index] = reply = {
                "status": "crashed",
                "error": {"message": "not evaluated (pkgforge was stopped)", "line": None},
            }
        if convert is not None:
            replies[index] = reply[0] if isinstance(reply, tuple) else _converted(convert, index, reply)
    return replies


def _converted(convert: Callable[[int, Reply], Any], index: int, reply: Reply) -> Any:
    """What `convert` keeps of a reply. A reply it cannot read (an unknown status, a record of the
    wrong shape: only a process that wrote its own line on the result channel gives one, since the
    evaluator's own replies are well-formed) is that file's crash, never the whole run's."""
    try:
        return convert(index, reply)
    except (ValueError, TypeError, KeyError, AttributeError, RecursionError) as error:
        return convert(index, malformed_reply(f"{type(error).__name__}: {error}"))


def malformed_reply(why: str) -> Reply:
    return {
        "status": "crashed",
        "error": {
            "message": f"its result cannot be read ({why[:200]}): the launch file wrote on the channel "
            "its result comes back on, and no result of it can be trusted",
            "line": None,
            "type": "ForgedResult",
        },
    }


def resolve(
    launch_files: list[LaunchFile],
    tree: InstallTree,
    *,
    jobs: int = 1,
    timeout: float = DEFAULT_TIMEOUT,
    arguments: dict[str, str] | None = None,
    on_done: Callable[[], object] | None = None,
    limits: WorkerLimits | None = None,
    engine: LaunchEngine = BUILTIN,
    zygote: Zygote | None = None,
) -> list[Resolution]:
    requests: list[LaunchRequest] = [
        {"file": str(launch.installed), "arguments": arguments or {}} for launch in launch_files
    ]

    def convert(index: int, reply: Reply) -> Resolution:
        # JSON from the worker, or the parent's own timeout/crash reply: resolution_from_reply
        # refuses an unknown status, from_dict an unknown record key
        result = cast(LaunchResultDict, reply)
        result.setdefault("engine", engine.name)  # a timeout or a crash is the engine's too
        result.setdefault("distro", engine.distro)
        return _resolution(launch_files[index], result)

    return run_requests(
        requests,
        tree,
        jobs=jobs,
        timeout=timeout,
        on_done=on_done,
        limits=limits,
        engine=engine,
        zygote=zygote,
        convert=convert,
    )


def _resolution(launch: LaunchFile, reply: LaunchResultDict) -> Resolution:
    return resolution_from_reply(launch, reply)


def confinement_here(engine: LaunchEngine = BUILTIN) -> Confinement:
    """What confines a request's process on this machine: a worker started as verify starts one
    (over an empty temporary tree), asked for its hello, and stopped (verify --explain-sandbox)."""
    with tempfile.TemporaryDirectory(prefix="pkgforge-probe-") as folder:
        tree = os.path.join(folder, "tree")
        own_folders = os.path.join(folder, "work")
        os.mkdir(tree)
        os.mkdir(own_folders)
        env = worker_environment(dict(os.environ, PKGFORGE_SANDBOX=tree), engine)
        env[WORK_VARIABLE] = own_folders
        zygote = Zygote()
        try:
            zygote.ensure(env)
            worker = _Worker(env, WorkerLimits(), zygote)
            try:
                worker.start()
            finally:
                worker.stop()
        finally:
            zygote.close()
    confinement = zygote.confinement
    if confinement is None:
        raise OSError("no launch worker started")
    return confinement
