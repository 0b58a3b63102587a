"""A read-only view of the file system and a process namespace of its own, for a launch worker.

Where the kernel lets an unprivileged process make a user namespace (most do; Ubuntu's
AppArmor policy and some containers do not), the worker (sandbox/coordinator.py) enters:
- a user namespace, mapping only its own user and group (nothing gained: a process there
  has capabilities only over what that namespace owns);
- a mount namespace in which every mount is read-only except pkgforge's temporary folders:
  no write, and no chmod, chown, utime or xattr either (which Landlock leaves out), by any
  program;
- a PID namespace whose first process is the worker's coordinator: a process started in it
  sees no process outside (it cannot name pkgforge to signal it), and when the coordinator
  kills everything there (kill(-1)) nothing escapes, however it forked and detached.

Processes that run user code drop every capability and can never regain one (drop_privileges).
The namespace calls go through ctypes (os.unshare is Python 3.12+).
"""

from __future__ import annotations

import ctypes
import functools
import os
import signal
import sys
from collections.abc import Iterable
from typing import TypedDict

CLONE_NEWNS = 0x00020000
CLONE_NEWUSER = 0x10000000
CLONE_NEWPID = 0x20000000
CLONE_NEWNET = 0x40000000
MS_BIND = 1 << 12
MS_REC = 1 << 14
MS_PRIVATE = 1 << 18
MS_NOSUID = 1 << 1
MS_NODEV = 1 << 2
MS_NOEXEC = 1 << 3
SYS_MOUNT_SETATTR = 442  # the same on every architecture (asm-generic), Linux 5.12
AT_FDCWD = -100
AT_RECURSIVE = 0x8000
MOUNT_ATTR_RDONLY = 1
PR_CAPBSET_DROP = 24
PR_CAP_AMBIENT = 47
PR_CAP_AMBIENT_CLEAR_ALL = 4
CAPABILITY_VERSION_3 = 0x20080522
PROBE_FAILED = 71  # a probe's exit status when the step it tried failed


class _MountAttr(ctypes.Structure):
    _fields_ = [
        ("attr_set", ctypes.c_uint64),
        ("attr_clr", ctypes.c_uint64),
        ("propagation", ctypes.c_uint64),
        ("userns_fd", ctypes.c_uint64),
    ]


class _CapHeader(ctypes.Structure):
    _fields_ = [("version", ctypes.c_uint32), ("pid", ctypes.c_int)]


class _CapData(ctypes.Structure):
    _fields_ = [
        ("effective", ctypes.c_uint32),
        ("permitted", ctypes.c_uint32),
        ("inheritable", ctypes.c_uint32),
    ]


class NamespaceSupport(TypedDict):
    """What probe() found this kernel allows an unprivileged pkgforge to make."""

    view: bool  # a user and mount namespace with a read-only view
    pid: bool  # and in it a PID namespace with its own /proc
    why: str  # why not, when one is missing


def _libc() -> ctypes.CDLL:
    if not sys.platform.startswith("linux"):
        raise OSError(0, "not Linux")
    return _cdll()


@functools.cache
def _cdll() -> ctypes.CDLL:
    return ctypes.CDLL(None, use_errno=True)  # once: a CDLL costs a dlopen


def _check(status: int, call: str) -> None:
    if status != 0:
        errno = ctypes.get_errno()
        raise OSError(errno, f"{call}: {os.strerror(errno)}")


def _write(path: str, text: str) -> None:
    fd = os.open(path, os.O_WRONLY | os.O_CLOEXEC)
    try:
        os.write(fd, text.encode())
    finally:
        os.close(fd)


def enter_view(writable: Iterable[str]) -> None:
    """Enter a new user, mount and network namespace where everything is read-only but `writable`
    (and where there is no network).
    Raises OSError; the process is then in whatever state the failing step left it (the caller
    goes on without the view: nothing was made read-only, or everything but `writable` was)."""
    libc = _libc()
    uid, gid = os.geteuid(), os.getegid()
    _check(libc.unshare(CLONE_NEWUSER | CLONE_NEWNS), "unshare(user, mount)")
    # no network: nothing on the user's machine (a local server, an agent's port) reachable
    _check(libc.unshare(CLONE_NEWNET), "unshare(network)")
    _write("/proc/self/setgroups", "deny")
    _write("/proc/self/uid_map", f"{uid} {uid} 1")
    _write("/proc/self/gid_map", f"{gid} {gid} 1")
    # changes here stay here (a shared mount would carry them back out)
    _check(libc.mount(b"none", b"/", None, MS_REC | MS_PRIVATE, None), "mount(private)")
    folders = [os.fsencode(os.path.realpath(f)) for f in writable if os.path.isdir(f)]
    for folder in folders:
        _check(libc.mount(folder, folder, None, MS_BIND | MS_REC, None), "mount(bind)")
    _set_readonly(libc, b"/", True)
    for folder in folders:
        _set_readonly(libc, folder, False)


def _set_readonly(libc: ctypes.CDLL, path: bytes, readonly: bool) -> None:
    attr = _MountAttr(MOUNT_ATTR_RDONLY, 0, 0, 0) if readonly else _MountAttr(0, MOUNT_ATTR_RDONLY, 0, 0)
    status = libc.syscall(
        SYS_MOUNT_SETATTR,
        AT_FDCWD,
        path,
        AT_RECURSIVE,
        ctypes.byref(attr),
        ctypes.c_size_t(ctypes.sizeof(attr)),
    )
    _check(status, "mount_setattr")


def private_mounts(own: str, tree: str | None, size: int) -> str:
    """What a request's process sees in a mount namespace of its own (needs enter_view's user
    namespace), so that nothing it writes reaches anything shared, and what it writes is bounded:
    - its folder `own`: a tmpfs of `size` bytes, holding every write below;
    - pkgforge's temporary tree `tree`: an overlay, its writes kept in `own` (another launch
      file never sees them, and the tree the checks read stays as pkgforge made it);
    - /tmp: an overlay likewise (a launch file writing /tmp/robot.urdf, then reading it back,
      works as under ros2 launch; the user's /tmp is never written);
    - /run: an empty tmpfs (the session bus, docker's and systemd's sockets are out of reach),
      unless `own` or `tree` is below it.
    → the /tmp overlay's upper folder (what the process wrote there)."""
    libc = _libc()
    _check(libc.unshare(CLONE_NEWNS), "unshare(mount)")
    own_bytes = os.fsencode(own)
    _check(
        libc.mount(b"tmpfs", own_bytes, b"tmpfs", MS_NOSUID | MS_NODEV, f"size={size},mode=700".encode()),
        "mount(tmpfs)",
    )
    _overlay(libc, "/tmp", own, "tmp")
    if tree is not None and os.path.isdir(tree):
        _overlay(libc, tree, own, "tree")
    below_run = [f for f in (own, tree or "") if f == "/run" or f.startswith("/run/")]
    if os.path.isdir("/run") and not below_run:
        _check(
            libc.mount(b"tmpfs", b"/run", b"tmpfs", MS_NOSUID | MS_NODEV, b"size=1m,mode=755"), "mount(/run)"
        )
    return os.path.join(own, ".tmp-upper")


def _overlay(libc: ctypes.CDLL, folder: str, own: str, name: str) -> None:
    """`folder` as an overlay whose writes go to own/.NAME-upper."""
    upper, work = os.path.join(own, f".{name}-upper"), os.path.join(own, f".{name}-work")
    os.mkdir(upper)
    os.mkdir(work)
    options = f"lowerdir={folder},upperdir={upper},workdir={work}".encode()
    _check(libc.mount(b"overlay", os.fsencode(folder), b"overlay", 0, options), f"mount(overlay {folder})")


def new_pid_namespace() -> None:
    """The next process this one forks is the first (pid 1) of a new PID namespace (needs the
    user namespace of enter_view). Irreversible: every later child goes there too."""
    _check(_libc().unshare(CLONE_NEWPID), "unshare(pid)")


def mount_proc() -> None:
    """In the first process of a new PID namespace: a /proc that shows only that namespace."""
    libc = _libc()
    _check(libc.mount(b"proc", b"/proc", b"proc", MS_NOSUID | MS_NODEV | MS_NOEXEC, None), "mount(proc)")


def kill_all() -> None:
    """From the first process of a PID namespace: kill every other process in it, and reap them."""
    try:
        os.kill(-1, signal.SIGKILL)
    except OSError:
        pass
    while True:
        try:
            os.waitpid(-1, 0)
        except ChildProcessError:
            return
        except InterruptedError:
            continue


def drop_privileges() -> None:
    """No capability now or after any exec (empty bounding, ambient and current sets): what a
    user namespace granted this process is gone for it and for everything it starts."""
    libc = _libc()
    try:
        with open("/proc/sys/kernel/cap_last_cap") as handle:
            last = int(handle.read())
    except (OSError, ValueError):
        last = 63
    for capability in range(last + 1):
        libc.prctl(PR_CAPBSET_DROP, capability, 0, 0, 0)  # (fails harmlessly for an unknown one)
    libc.prctl(PR_CAP_AMBIENT, PR_CAP_AMBIENT_CLEAR_ALL, 0, 0, 0)
    header = _CapHeader(CAPABILITY_VERSION_3, 0)
    data = (_CapData * 2)()
    _check(libc.capset(ctypes.byref(header), data), "capset")


def probe() -> NamespaceSupport:
    """Try, in throwaway processes, what enter_view and a PID namespace with its own /proc
    need; nothing of this process changes."""
    if not sys.platform.startswith("linux") or not hasattr(os, "fork"):
        return {"view": False, "pid": False, "why": "not Linux"}
    import tempfile

    read_end, write_end = os.pipe()
    with tempfile.TemporaryDirectory(prefix="pkgforge-probe-") as folder:
        child = os.fork()
        if child == 0:  # pragma: no cover - in the throwaway child
            os.close(read_end)
            _probe_child(write_end, folder)
        os.close(write_end)
        with os.fdopen(read_end, "rb") as answer:
            text = answer.read(4096).decode(errors="replace")
        os.waitpid(child, 0)
        if os.path.exists(f"{folder}-not"):  # a view that did not hold left this
            os.unlink(f"{folder}-not")
    step, _, why = text.partition(":")
    if step == "ok":
        return {"view": True, "pid": True, "why": ""}
    if step == "pid":
        return {"view": True, "pid": False, "why": f"no PID namespace: {why}"}
    return {"view": False, "pid": False, "why": f"no user namespace: {why or 'unknown'}"}


def _probe_child(answer: int, folder: str) -> None:  # pragma: no cover - in the throwaway child
    """Report 'ok', or the first step that failed ('view:why', 'pid:why'); never returns. The view
    is made as a worker makes it, with `folder` writable: a file is written there, and nothing
    can be written beside it."""
    try:
        try:
            enter_view([folder])
            with open(os.path.join(folder, "written"), "w") as handle:
                handle.write("ok")
            try:
                open(os.path.join(os.path.dirname(folder), f"{os.path.basename(folder)}-not"), "w").close()
            except OSError:
                pass
            else:
                raise OSError(0, "a file outside the writable folder could be written")
        except OSError as error:
            os.write(answer, f"view:{error.strerror or error}".encode())
            return
        try:
            new_pid_namespace()
            first = os.fork()
            if first == 0:
                try:
                    mount_proc()
                    os._exit(0 if os.getpid() == 1 and os.listdir("/proc/1") else PROBE_FAILED)
                except BaseException:  # noqa: BLE001 - any failure: no usable PID namespace
                    os._exit(PROBE_FAILED)
            _, status = os.waitpid(first, 0)
            if os.waitstatus_to_exitcode(status) != 0:
                raise OSError(0, "its /proc cannot be mounted")
        except OSError as error:
            os.write(answer, f"pid:{error.strerror or error}".encode())
            return
        os.write(answer, b"ok:")
    finally:
        os._exit(0)
