"""No new Unix socket: the one door Landlock and the read-only view leave open.

Connecting to a Unix socket by its path needs no write access to the file system: a launch file
of the user's could reach docker's, systemd's or an ssh or gpg agent's socket, wherever it lies,
and have it act with the user's rights. A seccomp filter makes socket(AF_UNIX, ...) fail with
EACCES for the process and everything it starts (it cannot be lifted). socketpair() stays
allowed: asyncio and multiprocessing make their own connected pairs with it, which reach nothing.

The filter is classic BPF through ctypes (prctl PR_SET_SECCOMP), for the architectures whose
system call numbers it knows (x86_64 with its x32 numbers, i386, aarch64); elsewhere it is not
installed and applies() says so.
"""

from __future__ import annotations

import ctypes
import functools
import os
import platform

PR_SET_SECCOMP = 22
SECCOMP_MODE_FILTER = 2
SECCOMP_RET_ALLOW = 0x7FFF0000
SECCOMP_RET_ERRNO = 0x00050000
AF_UNIX = 1
EACCES = 13
X32_BIT = 0x40000000

# BPF opcodes
LD_W_ABS = 0x20  # BPF_LD | BPF_W | BPF_ABS
JEQ_K = 0x15  # BPF_JMP | BPF_JEQ | BPF_K
AND_K = 0x54  # BPF_ALU | BPF_AND | BPF_K
RET_K = 0x06  # BPF_RET | BPF_K

# struct seccomp_data: nr (0), arch (4), instruction_pointer (8), args[6] (16, 24, ...)
NR, ARCH, ARG0 = 0, 4, 16

# (audit architecture, socket's number, socketcall's number or None) by machine
ARCHITECTURES = {
    "x86_64": (0xC000003E, 41, None),
    "aarch64": (0xC00000B7, 198, None),
    "i686": (0x40000003, 359, 102),
}
I386 = (0x40000003, 359, 102)  # 32-bit programs a 64-bit x86 process may run


class _Instruction(ctypes.Structure):
    _fields_ = [
        ("code", ctypes.c_uint16),
        ("jt", ctypes.c_uint8),
        ("jf", ctypes.c_uint8),
        ("k", ctypes.c_uint32),
    ]


class _Program(ctypes.Structure):
    _fields_ = [("len", ctypes.c_uint16), ("filter", ctypes.POINTER(_Instruction))]


def applies() -> bool:
    """Whether this machine's architecture is one the filter knows."""
    return platform.machine() in ARCHITECTURES


def _program() -> list[tuple[int, int, int, int]]:
    """The filter: on the native architecture (and i386 beside x86_64), socket(AF_UNIX) → EACCES,
    and i386's socketcall (whose arguments it cannot see) → EACCES; everything else allowed."""
    native = ARCHITECTURES[platform.machine()]
    deny = (RET_K, 0, 0, SECCOMP_RET_ERRNO | EACCES)
    allow = (RET_K, 0, 0, SECCOMP_RET_ALLOW)
    blocks: list[list[tuple[int, int, int, int]]] = []
    for arch, socket, socketcall in [native] + ([I386] if native[0] == 0xC000003E else []):
        body: list[tuple[int, int, int, int]] = [(LD_W_ABS, 0, 0, NR)]
        if arch == 0xC000003E:
            body.append((AND_K, 0, 0, ~X32_BIT & 0xFFFFFFFF))  # x32's numbers are x86_64's with that bit
        if socketcall is not None:
            body += [(JEQ_K, 0, 1, socketcall), deny]
        body += [(JEQ_K, 0, 3, socket), (LD_W_ABS, 0, 0, ARG0), (JEQ_K, 0, 1, AF_UNIX), deny, allow]
        blocks.append([(LD_W_ABS, 0, 0, ARCH), (JEQ_K, 0, len(body), arch), *body])
    return [instruction for block in blocks for instruction in block] + [allow]


def install() -> None:
    """Install the filter on this process (and all it will start); OSError when the kernel refuses
    (needs no_new_privs, which landlock.restrict sets, or CAP_SYS_ADMIN)."""
    if not applies():
        raise OSError(0, f"no seccomp filter for {platform.machine()}")
    instructions = _program()
    array = (_Instruction * len(instructions))(*[_Instruction(*i) for i in instructions])
    program = _Program(len(instructions), array)
    libc = _libc()
    libc.prctl(38, 1, 0, 0, 0)  # PR_SET_NO_NEW_PRIVS: what a filter needs without privileges
    if libc.prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, ctypes.byref(program), 0, 0) != 0:
        errno = ctypes.get_errno()
        raise OSError(errno, f"prctl(PR_SET_SECCOMP): {os.strerror(errno)}")


@functools.cache
def _libc() -> ctypes.CDLL:
    return ctypes.CDLL(None, use_errno=True)
