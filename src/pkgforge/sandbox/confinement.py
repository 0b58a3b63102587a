"""Which of the kernel's protections confine the processes that evaluate launch files and models.

probe() finds out once per run (in the fork server, before any worker: sandbox/zygote.py) by
trying each in throwaway processes; the coordinator of every worker applies what it found and
says so in its first line (protocol.Hello). `verify` prints a note when the sandbox is weaker
than Landlock with signal scoping, and `verify --explain-sandbox` lists every protection.
"""

from __future__ import annotations

import os
import sys

from pkgforge.sandbox import landlock, namespaces
from pkgforge.sandbox.protocol import Confinement

DISABLE_VARIABLE = "PKGFORGE_SANDBOX_DISABLE"  # comma-separated: landlock, namespaces, seccomp (tests)


def probe() -> Confinement:
    """What this kernel lets pkgforge use (tried in throwaway processes; nothing here changes)."""
    disabled = set(os.environ.get(DISABLE_VARIABLE, "").replace(" ", "").split(","))
    why: list[str] = []
    abi = 0 if "landlock" in disabled else landlock.abi_version()
    if "landlock" in disabled:
        why.append(f"Landlock: turned off ({DISABLE_VARIABLE})")
    elif abi == 0:
        why.append("Landlock: this kernel has none (Linux 5.13 or later with Landlock enabled has it)")
    elif not _restricts(abi):
        why.append("Landlock: the kernel refused a ruleset")
        abi = 0
    elif abi < landlock.SCOPES_ABI:
        why.append(f"Landlock ABI {abi}: no signal scoping (ABI 6, Linux 6.12)")
    if "namespaces" in disabled:
        support: namespaces.NamespaceSupport = {
            "view": False,
            "pid": False,
            "why": f"turned off ({DISABLE_VARIABLE})",
        }
    else:
        support = namespaces.probe()
    if support["why"]:
        why.append(f"namespaces: {support['why']}")
    return {
        "landlock": abi,
        "signals": abi >= landlock.SCOPES_ABI,
        "view": support["view"],
        "pid": support["pid"],
        "network": support["view"] or abi >= landlock.NET_ABI,
        "sockets": "seccomp" not in disabled and _filters(),
        "guard": True,
        "why": why,
    }


def _filters() -> bool:
    """Whether a process can install the seccomp filter (seccomp.py), tried in a throwaway one."""
    from pkgforge.sandbox import seccomp

    if not seccomp.applies() or not hasattr(os, "fork"):
        return False
    child = os.fork()
    if child == 0:  # pragma: no cover - in the throwaway child
        code = 1
        try:
            seccomp.install()
            import socket

            try:
                socket.socket(socket.AF_UNIX)
            except PermissionError:
                code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(child, 0)
    return os.waitstatus_to_exitcode(status) == 0


def _restricts(abi: int) -> bool:
    """Whether a process can restrict itself (a container's seccomp may refuse the calls)."""
    if not hasattr(os, "fork"):
        return False
    child = os.fork()
    if child == 0:  # pragma: no cover - in the throwaway child
        code = 1
        try:
            landlock.restrict([], abi)
            code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(child, 0)
    return os.waitstatus_to_exitcode(status) == 0


def unconfined() -> Confinement:
    """No kernel protection: the guard alone (not Linux, or no worker ran to say)."""
    return {
        "landlock": 0,
        "signals": False,
        "view": False,
        "pid": False,
        "network": False,
        "sockets": False,
        "guard": True,
        "why": [sys.platform],
    }


def weaker(confinement: Confinement) -> str | None:
    """A few words for verify's summary line when something verify promises is not kernel-enforced:
    writes (Landlock or the read-only view), chmod/chown/utime (only the view: Landlock does not cover
    them), signals (Landlock's scopes or the PID namespace). None when all three are."""
    held = {
        "writes": confinement["landlock"] > 0 or confinement["view"],
        "chmod/utime": confinement["view"],
        "signals": confinement["signals"] or confinement["pid"],
    }
    missing = [what for what, kernel in held.items() if not kernel]
    if not missing:
        return None
    return f"sandbox weaker: {', '.join(missing)} refused only by the Python guard (see --explain-sandbox)"


def describe(confinement: Confinement) -> list[str]:
    """verify --explain-sandbox: one line per protection, active or not."""

    def mark(active: bool) -> str:
        return "✓" if active else "✗"

    abi = confinement["landlock"]
    view = confinement["view"]
    lines = [
        f"{mark(abi > 0)} Landlock{f' ABI {abi}' if abi else ''}: the kernel refuses writes outside "
        "pkgforge's temporary folders, by the launch file and everything it starts",
        f"{mark(confinement['signals'])} Landlock scopes: signals and abstract Unix sockets only within "
        "the launch file's own processes",
        f"{mark(view)} read-only view (user and mount namespace): no write, chmod, chown or utime "
        "anywhere else, by any program; its writes to the tree and /tmp stay its own, in a tmpfs "
        "of --worker-memory",
        f"{mark(confinement['pid'])} PID namespace: no process outside can be seen or signalled; "
        "everything it started ends with it",
        f"{mark(confinement['network'])} no network: no TCP port (a local server, an agent) reachable"
        + ("; /run is empty (no session bus, no docker or systemd socket)" if view else ""),
        f"{mark(confinement['sockets'])} no new Unix socket (seccomp): no agent reachable by its "
        "socket's path (docker, ssh, gpg)",
        f"{mark(confinement['guard'])} Python guard (audit hook): each refused write or signal reported "
        "at its line (launch-writes-files, PF316)",
        "✓ one fresh process per launch file and per model, holding no descriptor of pkgforge's; its "
        "one result line taken once it ended, with a token it never held",
        "✓ limits: --worker-memory, --launch-timeout (CPU and wall time), 1024 open files",
    ]
    lines += [f"  not available: {why}" for why in confinement["why"]]
    note = weaker(confinement)
    if note is not None:
        lines.append(note)
    return lines
