"""The write and signal guard of the launch worker and of every Python process it starts.

Launch files and xacro are user code, and verify must never change the user's
files. The install tree the worker sees is pkgforge's own temporary copy (see
tree.py); this guard is the second layer, an audit hook (`sys.addaudithook`)
installed before any user code runs:

- a write-type operation (open for writing, remove, rename, mkdir, chmod, chown,
  truncate, utime, symlink, link, rmtree ...) on a path outside pkgforge's
  temporary folder (PKGFORGE_SANDBOX) is refused with PermissionError and
  recorded; so is one that changes an installed file of the tree as pkgforge
  made it (launch files run side by side in one tree, and the checks read it
  after them); files a launch file creates in the tree are its own to change;
  a write through a symlink inside the folder that points out of it (one a
  launch file made) first replaces the link with a private copy
  (copy-on-write), then proceeds;
- a signal (os.kill, os.killpg) to a process that is neither the worker nor one
  of its descendants is refused the same way: a launch file cannot kill pkgforge.

Child Python processes (a launch file's `subprocess.run(['xacro', ..., '-o', p])`)
get the same guard: guard_site/ is first on their PYTHONPATH and its
sitecustomize loads this file. Standard library only, so any Python 3 can load it.
Refusals are appended as JSON lines to the log of the process that evaluates the
request (PKGFORGE_SANDBOX_LOG, in its own folder), which it reads after the request and
reports.

An audit hook is not a security boundary (ctypes calls libc directly, a shell or
`python -I` has no hook, and the launch file can change the guard's own state): the
kernel is (landlock.py, namespaces.py). The guard's part is to say, at the launch
file's line, what it tried, and to give a Python write through a link a private copy.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import threading
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the guard runs in any Python 3 (guard_site/): typing only for mypy
    from collections.abc import Callable
    from typing import TypedDict

    from pkgforge.sandbox.protocol import GuardRecord

    Locator = Callable[[], "tuple[str | None, int | None] | None"]
    Handler = Callable[..., None]  # an audit event's arguments, as the event gives them

    class _State(TypedDict, total=False):
        root: str | None  # the real path of PKGFORGE_SANDBOX (else of the process's own folder)
        roots: list[str]  # the real paths of every folder it may write: that, and its own folder
        log: str | None  # the log of refusals (PKGFORGE_SANDBOX_LOG)
        tmp_upper: str | None  # the private /tmp overlay's upper folder (PKGFORGE_SANDBOX_TMP)
        root_pid: int | None  # the worker's pid
        locator: Locator | None
        spawned_at: tuple[str | None, int | None]  # where the running child was started
        pending: list[GuardRecord]
        sealed: int | None
        coverage: str | None  # coverage.py's data file when it measures this process


SANDBOX_VARIABLE = "PKGFORGE_SANDBOX"
OWN_VARIABLE = "PKGFORGE_SANDBOX_OWN"  # the folder of the process evaluating one request
# when /tmp is the process's private overlay (namespaces.private_tmp): the overlay's upper folder
TMP_VARIABLE = "PKGFORGE_SANDBOX_TMP"
LOG_VARIABLE = "PKGFORGE_SANDBOX_LOG"
ROOT_PID_VARIABLE = "PKGFORGE_SANDBOX_PID"
# entries of SANDBOX/install not changed since this time (ns) are the install tree pkgforge made
SEALED_VARIABLE = "PKGFORGE_SANDBOX_SEALED"
LOG_NAME = ".refused"  # in the evaluating process's own folder (without one: -<pid> in the tree)
MARKER = "pkgforge refused"
# devices a launch file may open for writing (its prints, /dev/null redirections)
ALLOWED_DEVICES = ("/dev/null", "/dev/zero", "/dev/stdout", "/dev/stderr", "/dev/tty", "/dev/full")
WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_APPEND
SPAWN_EVENTS = {"subprocess.Popen", "os.system", "os.posix_spawn", "os.exec", "os.spawn", "os.startfile"}

_state: _State = {
    "root": None,
    "roots": [],
    "log": None,
    "root_pid": None,
    "locator": None,
    "spawned_at": (None, None),
    "pending": [],
}
_busy = threading.local()


def writable_roots(root: str | None = None) -> list[str]:
    """The folders a sandboxed process may write: pkgforge's temporary tree ($PKGFORGE_SANDBOX,
    or `root`) and its own folder ($PKGFORGE_SANDBOX_OWN), those that are set."""
    found = [root or os.environ.get(SANDBOX_VARIABLE), os.environ.get(OWN_VARIABLE)]
    return [os.path.realpath(folder) for folder in found if folder]


def kernel_writable(root: str | None = None) -> list[str]:
    """What the kernel lets a sandboxed process write (landlock.restrict): writable_roots, and /tmp
    when it is the process's private overlay (the guard still refuses changing a file that was there)."""
    return writable_roots(root) + (["/tmp"] if os.environ.get(TMP_VARIABLE) else [])


def install(root: str | None = None) -> bool:
    """Install the guard for the temporary folder `root` (default: $PKGFORGE_SANDBOX) and the
    process's own folder ($PKGFORGE_SANDBOX_OWN); idempotent."""
    if _state["root"] is not None:
        return True
    roots = writable_roots(root)
    if not roots:
        return False
    _state["root"], _state["roots"] = roots[0], roots
    _state["log"] = os.environ.get(LOG_VARIABLE)
    _state["tmp_upper"] = os.environ.get(TMP_VARIABLE)
    sealed = os.environ.get(SEALED_VARIABLE, "")
    _state["sealed"] = int(sealed) if sealed.isdigit() else None
    pid = os.environ.get(ROOT_PID_VARIABLE)
    if not pid or not pid.isdigit():
        pid = str(os.getpid())
        os.environ[ROOT_PID_VARIABLE] = pid  # the worker: its children inherit it
    _state["root_pid"] = int(pid)
    _state["coverage"] = _coverage_data()
    sys.dont_write_bytecode = True  # byte code of a user module would land beside its source
    sys.addaudithook(_hook)
    return True


def _coverage_data() -> str | None:
    """The data file of coverage.py when it measures this process (scripts/coverage): its own
    writes there at exit are not the launch file's, and no launch file runs in pkgforge's users'
    runs under coverage."""
    coverage = sys.modules.get("coverage")
    current = getattr(getattr(coverage, "Coverage", None), "current", None)
    measuring = current() if callable(current) else None
    return os.path.abspath(measuring.config.data_file) if measuring is not None else None


def log_path() -> str:
    """The log of the evaluating process this process belongs to (it, or a process below it)."""
    return _state.get("log") or os.path.join(_state["root"] or "", f"{LOG_NAME}-{_state['root_pid']}")


def set_locator(locator: Locator) -> None:
    """A callable → (file, line) of the user code running now (the worker's launch file frames)."""
    _state["locator"] = locator


def take() -> list[GuardRecord]:
    """What was refused or overwritten since the last call, by this process and its children."""
    _collect()
    records, _state["pending"] = _state["pending"], []
    _state["spawned_at"] = (None, None)
    unique: dict[tuple[str, str, str, str | None, int | None], GuardRecord] = {}
    for record in records:
        unique.setdefault(
            (record["kind"], record["operation"], record["path"], record.get("file"), record.get("line")),
            record,
        )
    return list(unique.values())


def _collect() -> None:
    """Move the log's records to the pending list; a child's are placed where it was started."""
    path = log_path()
    _busy.active = True
    try:
        with open(path, "r+", encoding="utf-8") as log:
            lines = log.read().splitlines()
            log.seek(0)
            log.truncate()
    except OSError:
        lines = []
    finally:
        _busy.active = False
    for line in lines:
        try:
            record: GuardRecord = json.loads(line)
        except ValueError:
            continue
        if record.get("file") is None and record.get("pid") != os.getpid():
            record["file"], record["line"] = _state["spawned_at"]
            record["child"] = True
        _state["pending"].append(record)


# --- the hook ---------------------------------------------------------------------------------


def _hook(event: str, args: tuple[Any, ...]) -> None:
    handler = _HANDLERS.get(event)
    if handler is None:
        locator = _state["locator"]
        if event in SPAWN_EVENTS and locator is not None and not getattr(_busy, "active", False):
            _collect()  # what the previous child did belongs to where it was started
            _busy.active = True
            try:
                where = locator()
                _state["spawned_at"] = where if where and where[0] else (None, None)
            finally:
                _busy.active = False
        return
    if getattr(_busy, "active", False):
        return  # the guard's own file work (copy-on-write, the log)
    _busy.active = True
    try:
        handler(*args)
    finally:
        _busy.active = False


def _path(value: object, dir_fd: object = None) -> str | None:
    """An absolute path for an audited path argument; None for a file descriptor."""
    if isinstance(value, int):
        return None
    return _absolute(value, dir_fd)


def _fd_or_path(value: object, dir_fd: object = None) -> str | None:
    """As _path, and a file descriptor (os.fchmod, os.utime(fd)) as the file it is open on."""
    if isinstance(value, int) and not isinstance(value, bool):
        try:
            target = os.readlink(f"/proc/self/fd/{value}")
        except OSError:
            return None
        return target if os.path.isabs(target) else None  # (pipe:[...], socket:[...]: no file)
    return _absolute(value, dir_fd)


def _absolute(value: object, dir_fd: object) -> str | None:
    if not isinstance(value, (str, bytes, os.PathLike)):
        return None
    try:
        path = os.fsdecode(value)
    except TypeError:
        return None
    if not os.path.isabs(path):
        try:
            base = os.getcwd()
        except OSError:
            base = "/"
        if isinstance(dir_fd, int) and dir_fd >= 0:
            try:
                base = os.readlink(f"/proc/self/fd/{dir_fd}")
            except OSError:
                pass
        path = os.path.join(base, path)
    return os.path.normpath(path)


def _inside(real: str) -> bool:
    return any(real == root or real.startswith(f"{root}{os.sep}") for root in _state["roots"])


def _private_tmp(location: str, exists: bool) -> bool:
    """A path of /tmp where it is the process's private overlay that is the process's own: written
    by it, or new in /tmp itself or in a folder it made there. Anything else under /tmp (a file of the
    user's, a new file in the user's workspace kept in /tmp) is still refused."""
    upper = _state.get("tmp_upper")
    if not upper or not location.startswith("/tmp/"):
        return False
    relative = location[len("/tmp/") :]
    if exists:
        return os.path.lexists(os.path.join(upper, relative))
    folder = os.path.dirname(relative)
    return folder == "" or os.path.isdir(os.path.join(upper, folder))


def _location(path: str) -> str:
    """Where the entry itself is (its folder's real path, its own name): links not followed."""
    folder, name = os.path.split(path)
    return os.path.join(os.path.realpath(folder), name)


def _check(
    path: str | None, operation: str, *, follow: bool, creates: bool = False, needs: bool = False
) -> None:
    """Allow the operation on `path`, copy a linked file first, or refuse. An operation the
    system itself fails (creating what exists, removing what does not) changes nothing: allowed."""
    if path is not None and path.startswith(("/dev/fd/", "/proc/self/fd/")):
        path = _reopened(path)  # a descriptor opened again: the file it is open on
    if (
        path is None
        or path in ALLOWED_DEVICES
        or path.startswith(_state.get("coverage") or "\0")  # never a path prefix when unset
    ):
        return
    location = _location(path)
    exists = os.path.lexists(location)
    if creates and exists or needs and not exists:
        return
    if not _inside(location) and not _private_tmp(location, exists):
        _refuse(operation, path)
    if exists and _installed(location):
        _refuse(
            operation,
            location,
            "verify keeps the installed files as the install rules made them "
            "(other launch files and the checks read them)",
            kind="installed",
        )
    if follow and os.path.islink(location):
        real = os.path.realpath(location)
        if not _inside(real):
            _copy_on_write(location, real)


def _reopened(path: str) -> str | None:
    """The file a /proc/self/fd/N or /dev/fd/N path reopens; None for a pipe or socket (or a
    descriptor that is not open), which is no file of the user's."""
    try:
        target = os.readlink(f"/proc/self/fd/{path.rsplit('/', 1)[1]}")
    except (OSError, IndexError):
        return None
    return target if os.path.isabs(target) else None


def _installed(location: str) -> bool:
    """An entry of the install tree as pkgforge made it (not one a launch file made since)."""
    sealed = _state.get("sealed")
    if not sealed or not location.startswith(os.path.join(_state["root"] or "", "install") + os.sep):
        return False
    try:
        return os.lstat(location).st_mtime_ns <= sealed
    except OSError:
        return False


def _copy_on_write(link: str, target: str) -> None:
    """Replace a link out of the temporary folder by a private copy of what it points to."""
    temporary = f"{link}.pkgforge-copy-{os.getpid()}"
    try:
        if os.path.isfile(target):
            shutil.copyfile(target, temporary)
            os.replace(temporary, link)
        elif not os.path.exists(target):
            os.unlink(link)  # a dangling link: the write creates a file here, not there
        else:
            _refuse("write through a link to", link)
    except OSError:
        try:
            os.unlink(temporary)
        except OSError:
            pass
        _refuse("write through a link to", link)


def _record(kind: str, operation: str, path: str) -> None:
    record: GuardRecord = {"kind": kind, "pid": os.getpid(), "operation": operation, "path": path}
    locator = _state["locator"]
    if locator is not None:
        record["file"], record["line"] = locator() or (None, None)
    try:
        with open(log_path(), "a", encoding="utf-8") as log:
            log.write(json.dumps(record) + "\n")
    except OSError:
        pass


def _refuse(
    operation: str,
    path: str,
    reason: str = "verify never changes files outside its temporary install tree",
    kind: str = "refused",
) -> None:
    _record(kind, operation, path)
    raise PermissionError(1, f"{MARKER} to {operation} {path}: {reason}")


def _open(path: object, mode: object, flags: object) -> None:
    if isinstance(flags, int) and flags & WRITE_FLAGS or isinstance(mode, str) and set(mode) & set("wax+"):
        _check(_path(path), "write", follow=True)


def _truncate(path: object, *rest: object) -> None:
    _check(_fd_or_path(path), "truncate", follow=True)


def _two(operation: str, *, follow_source: bool = False) -> Handler:
    def handler(source: object, destination: object, *rest: object) -> None:
        source_fd = rest[0] if rest else None
        destination_fd = rest[1] if len(rest) > 1 else None
        if follow_source:  # a hard link to a file out of the folder would write through to it
            path = _path(source, source_fd)
            if path is not None and not _inside(os.path.realpath(path)):
                _refuse(operation, path)
        else:
            _check(_path(source, source_fd), operation, follow=False, needs=True)
        _check(_path(destination, destination_fd), operation, follow=False)

    return handler


def _one(operation: str, *, follow: bool, dir_fd: int | None = None, **when: bool) -> Handler:
    def handler(path: object, *rest: object) -> None:
        fd = rest[dir_fd - 1] if dir_fd is not None and len(rest) >= dir_fd else None
        _check(_fd_or_path(path, fd), operation, follow=follow, **when)

    return handler


def _symlink(source: object, destination: object, dir_fd: object = None, *rest: object) -> None:
    _check(_path(destination, dir_fd), "create a link at", follow=False, creates=True)


def _descendant(pid: int) -> bool:
    """The worker itself, or a process below it."""
    root = _state["root_pid"]
    for _ in range(128):
        if pid == root:
            return True
        if pid <= 1:
            return False
        try:
            with open(f"/proc/{pid}/stat", "rb") as stat:
                pid = int(stat.read().rsplit(b")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):
            return False
    return False


def _kill(pid: object, signal: object, *rest: object) -> None:
    if not isinstance(pid, int):
        return
    if pid == 0 or (pid > 0 and _descendant(pid)):
        return
    if pid < -1 and (-pid == os.getpgrp() or _descendant(-pid)):
        return
    _refuse_signal(pid, signal)


def _killpg(pgid: object, signal: object, *rest: object) -> None:
    if isinstance(pgid, int) and (pgid in (0, os.getpgrp()) or _descendant(pgid)):
        return
    _refuse_signal(-pgid if isinstance(pgid, int) else pgid, signal)


def _refuse_signal(pid: object, signal: object) -> None:
    _refuse(
        f"send signal {int(signal) if isinstance(signal, int) else signal} to",
        f"process {pid}",
        "it is not a process the launch file started",
    )


_HANDLERS: dict[str, Handler] = {
    "open": _open,
    "os.remove": _one("delete", follow=False, dir_fd=1, needs=True),
    "os.rmdir": _one("delete", follow=False, dir_fd=1, needs=True),
    "os.mkdir": _one("create a folder at", follow=False, dir_fd=2, creates=True),
    "os.mkfifo": _one("create a pipe at", follow=False, dir_fd=2),
    "os.mknod": _one("create a device at", follow=False, dir_fd=3),
    "os.chmod": _one("change the mode of", follow=True, dir_fd=2),
    "os.chown": _one("change the owner of", follow=True, dir_fd=3),
    "os.chflags": _one("change the flags of", follow=True),
    "os.truncate": _truncate,
    "os.utime": _one("change the times of", follow=True, dir_fd=3),
    "os.setxattr": _one("change the attributes of", follow=True),
    "os.removexattr": _one("change the attributes of", follow=True),
    "shutil.rmtree": _one("delete", follow=False, dir_fd=1, needs=True),
    "os.rename": _two("rename"),
    "os.link": _two("create a hard link to", follow_source=True),
    "os.symlink": _symlink,
    "os.kill": _kill,
    "os.killpg": _killpg,
}
