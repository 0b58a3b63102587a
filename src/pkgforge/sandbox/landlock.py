"""Landlock: the kernel's own limit on what a process and everything it starts may write and signal.

A process that calls restrict() can from then on, and so can every process it starts
(whatever the program: a shell, a C program, Python started with -I), only:
- create, write, truncate, rename, link and remove files below the folders it was given
  (and write to the few devices named here, such as /dev/null); reading and running stays
  allowed everywhere;
- signal processes of its own domain (itself and what it started), and connect to abstract
  Unix sockets of its own domain, where the kernel has Landlock ABI 6 (Linux 6.12);
- bind or connect no TCP port (ABI 4, Linux 6.7): no local server or agent is reachable;
- never lift any of it again (there is no call to undo it), nor mount, nor ptrace a process
  outside its domain (so no /proc/<pid>/fd/N of pkgforge's either).

Landlock does not cover metadata (chmod, chown, utime, extended attributes): the read-only
mount view of namespaces.py does, where the kernel allows it, and the Python guard (guard.py)
refuses those a Python process attempts.

The three system calls are made through ctypes (their numbers are the same on every
architecture: they came after the tables were unified). The PyPI binding `landlock` is a
pre-release without the ABI 6 scopes; these are three calls and two structures.
"""

from __future__ import annotations

import ctypes
import functools
import os
import sys
from collections.abc import Iterable

SYS_LANDLOCK_CREATE_RULESET = 444
SYS_LANDLOCK_ADD_RULE = 445
SYS_LANDLOCK_RESTRICT_SELF = 446
CREATE_RULESET_VERSION = 1  # flag: ask for the ABI version instead of creating a ruleset
RULE_PATH_BENEATH = 1
PR_SET_NO_NEW_PRIVS = 38

# filesystem rights (uapi/linux/landlock.h), by the ABI that introduced them
WRITE_FILE = 1 << 1
REMOVE_DIR = 1 << 4
REMOVE_FILE = 1 << 5
MAKE_CHAR = 1 << 6
MAKE_DIR = 1 << 7
MAKE_REG = 1 << 8
MAKE_SOCK = 1 << 9
MAKE_FIFO = 1 << 10
MAKE_BLOCK = 1 << 11
MAKE_SYM = 1 << 12
REFER = 1 << 13  # ABI 2: rename and link across folders
TRUNCATE = 1 << 14  # ABI 3
WRITES_ABI1 = (
    WRITE_FILE
    | REMOVE_DIR
    | REMOVE_FILE
    | MAKE_CHAR
    | MAKE_DIR
    | MAKE_REG
    | MAKE_SOCK
    | MAKE_FIFO
    | MAKE_BLOCK
    | MAKE_SYM
)
# what a writable folder allows: all of that but device nodes (a block device made there is a
# way to the disk; nothing a launch file does needs one)
DEVICES = MAKE_CHAR | MAKE_BLOCK
# what may be done to a file (not a folder): a rule on a device names only these
FILE_WRITES = WRITE_FILE | TRUNCATE

# network rights (ABI 4): handled with no rule, no TCP port can be bound or connected to
NET_BIND_TCP = 1 << 0
NET_CONNECT_TCP = 1 << 1
NET_ABI = 4

SCOPE_ABSTRACT_UNIX_SOCKET = 1 << 0  # ABI 6
SCOPE_SIGNAL = 1 << 1  # ABI 6
SCOPES_ABI = 6

# devices a sandboxed process may open for writing (its prints, redirections to /dev/null)
WRITABLE_DEVICES = ("/dev/null", "/dev/zero", "/dev/full")


class _RulesetAttr(ctypes.Structure):
    _fields_ = [
        ("handled_access_fs", ctypes.c_uint64),
        ("handled_access_net", ctypes.c_uint64),  # ABI 4
        ("scoped", ctypes.c_uint64),  # ABI 6
    ]


class _PathBeneathAttr(ctypes.Structure):
    _pack_ = 1  # __attribute__((packed)) in the uapi header
    _fields_ = [("allowed_access", ctypes.c_uint64), ("parent_fd", ctypes.c_int32)]


class LandlockError(OSError):
    """A Landlock call failed (the process is then not restricted)."""


@functools.cache
def _libc() -> ctypes.CDLL | None:
    """The C library (once: a CDLL costs a dlopen), None off Linux."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(None, use_errno=True)
    except OSError:
        return None


def abi_version() -> int:
    """The kernel's Landlock ABI version; 0 when it has none (older than 5.13, or not enabled)."""
    libc = _libc()
    if libc is None:
        return 0
    version: int = libc.syscall(
        SYS_LANDLOCK_CREATE_RULESET, None, ctypes.c_size_t(0), ctypes.c_uint32(CREATE_RULESET_VERSION)
    )
    return max(version, 0)


def handled_writes(abi: int) -> int:
    """Every write-type right the kernel of this ABI knows (asking for more is EINVAL)."""
    rights = WRITES_ABI1
    if abi >= 2:
        rights |= REFER
    if abi >= 3:
        rights |= TRUNCATE
    return rights


def restrict(writable: Iterable[str], abi: int | None = None) -> int:
    """Restrict this process (and all it will start) to writing below `writable` and to the
    devices WRITABLE_DEVICES, and (ABI 6) to signalling and reaching abstract sockets of its own
    domain. Returns the ABI used; raises LandlockError when the kernel refuses (nothing applied)."""
    libc = _libc()
    abi = abi_version() if abi is None else abi
    if libc is None or abi < 1:
        raise LandlockError(0, "the kernel has no Landlock")
    rights = handled_writes(abi)
    scopes = SCOPE_SIGNAL | SCOPE_ABSTRACT_UNIX_SOCKET if abi >= SCOPES_ABI else 0
    # (an older kernel takes the whole structure too: it checks that the fields it lacks are 0)
    network = NET_BIND_TCP | NET_CONNECT_TCP if abi >= NET_ABI else 0
    attr = _RulesetAttr(rights, network, scopes)
    size = ctypes.c_size_t(ctypes.sizeof(_RulesetAttr))
    ruleset = libc.syscall(SYS_LANDLOCK_CREATE_RULESET, ctypes.byref(attr), size, 0)
    if ruleset < 0:
        _raise(ctypes.get_errno(), "landlock_create_ruleset")
    try:
        for folder in writable:
            _allow(libc, ruleset, folder, rights & ~DEVICES)
        for device in WRITABLE_DEVICES:
            if os.path.exists(device):
                _allow(libc, ruleset, device, rights & FILE_WRITES)
        if libc.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
            _raise(ctypes.get_errno(), "prctl(PR_SET_NO_NEW_PRIVS)")
        if libc.syscall(SYS_LANDLOCK_RESTRICT_SELF, ruleset, 0) != 0:
            _raise(ctypes.get_errno(), "landlock_restrict_self")
    finally:
        os.close(ruleset)
    return abi


def _allow(libc: ctypes.CDLL, ruleset: int, path: str, rights: int) -> None:
    fd = os.open(path, os.O_PATH | os.O_CLOEXEC)
    try:
        rule = _PathBeneathAttr(rights, fd)
        if libc.syscall(SYS_LANDLOCK_ADD_RULE, ruleset, RULE_PATH_BENEATH, ctypes.byref(rule), 0) != 0:
            _raise(ctypes.get_errno(), f"landlock_add_rule({path})")
    finally:
        os.close(fd)


def _raise(errno: int, call: str) -> None:
    raise LandlockError(errno, f"{call}: {os.strerror(errno)}")
