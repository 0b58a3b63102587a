"""Attacks a second reader made on issue 35's sandbox, each a defect of its first version, now held.

Numbers are those of the review: 1 a launch file rewriting another package's installed files in the
shared tree; 2 chmod/utime where only Landlock stands (refused, or announced as weaker); 3 root
keeping its capabilities without namespaces; 4 a Unix socket or a TCP port of an agent outside;
5 a malformed result stopping the whole run; 6 folders nested past Python's recursion breaking the
clean-up; 7 the next request's token read through /proc and a request swapped.
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import tempfile
import threading
import time
from pathlib import Path

import pytest
from conftest import new_package, run_pkgforge

REPLY_FD = """
def _reply_fd():
    stdin = os.readlink("/proc/self/fd/0")
    for fd in os.listdir("/proc/self/fd"):
        try:
            target = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            continue
        if target.startswith("pipe:") and target != stdin:
            return int(fd)
"""


def _workspace(tmp_path: Path, *names: str) -> Path:
    workspace = tmp_path / "ws"
    (workspace / "src").mkdir(parents=True)
    for name in names:
        new_package(workspace, name)
    return workspace


def _launch(workspace: Path, package: str, text: str) -> None:
    (workspace / "src" / package / "launch" / "display.launch.py").write_text(text)


def _verify(workspace: Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    return run_pkgforge(
        "verify", "--no-cache", "--format", "json", "-j", "1", *args, cwd=workspace, env=env, timeout=600
    )


def _codes(result: subprocess.CompletedProcess) -> list[tuple[str, str]]:
    report = json.loads(result.stdout)
    return [(d["code"], str(d.get("path"))) for d in report["diagnostics"]]


TAMPER = r'''
import os, subprocess
from launch import LaunchDescription
SCRIPT = r"""
for f in $(find "$T" -path '*share/beta/urdf/beta.urdf.xacro'); do
  ts=$(stat -c '%y' "$f")
  printf 'xxx' | dd of="$f" bs=1 seek=$(grep -bo 'arm.stl' "$f" | head -1 | cut -d: -f1) conv=notrunc 2>/dev/null
  touch -d "$ts" "$f"
done
"""
def generate_launch_description():
    subprocess.run(["sh", "-c", SCRIPT], env=dict(os.environ, T=os.environ["PKGFORGE_SANDBOX"]))
    return LaunchDescription([])
'''


def test_1_a_launch_file_cannot_change_another_packages_installed_files(tmp_path):
    """alpha's launch file rewrites beta's installed model in the shared tree (same inode, size and
    mtime, so tree.restore() does not see it): beta, untouched, gets a false PF402 (cached too)."""
    workspace = _workspace(tmp_path, "alpha", "beta")
    _launch(workspace, "alpha", TAMPER)
    result = _verify(workspace)
    assert result.returncode in (0, 1), result.stderr
    assert not [code for code, file in _codes(result) if "beta" in file and code != "PF107"]


FORGED = (
    "import os\n"
    + REPLY_FD
    + "def generate_launch_description():\n"
    + '    os.write(_reply_fd(), b\'{"status": "bogus"}\\n\')\n'
    + "    os._exit(0)\n"
)


def test_5_a_malformed_result_is_a_load_error_of_that_file(tmp_path):
    """One reply line of an unknown shape (written by the launch file, then os._exit): verify
    stops with `internal error` (exit 2) and no report for any package."""
    workspace = _workspace(tmp_path, "alpha", "beta")
    _launch(workspace, "alpha", FORGED)
    result = _verify(workspace)
    assert result.returncode == 1, result.stderr
    assert ("PF301", "src/alpha/launch/display.launch.py") in _codes(result)


DEEP = """
import subprocess, sys
from launch import LaunchDescription
NEST = (
    "import os\\nopen('MARK', 'w').close()\\nfd = os.open('.', os.O_RDONLY)\\nfor _ in range(3000):\\n"
    "    os.mkdir('d', dir_fd=fd)\\n    inner = os.open('d', os.O_RDONLY, dir_fd=fd)\\n"
    "    os.close(fd)\\n    fd = inner\\n"
)
def generate_launch_description():
    subprocess.run([sys.executable, "-I", "-c", NEST])  # (-I: no guard, so the loop is quick)
    return LaunchDescription([])
"""


MARK = f"deep-{os.getpid()}-{time.time_ns()}"  # (other runs on this machine nest folders too)


def _deep_leftovers(before: set[str]) -> list[str]:
    return [
        os.path.join("/dev/shm", name)
        for name in set(os.listdir("/dev/shm")) - before
        if name.startswith("pkgforge-")
        and any(next(Path("/dev/shm", name).glob(f"{'*/' * depth}{MARK}"), None) for depth in range(4))
    ]


@pytest.mark.parametrize("disabled", ["", "namespaces"], ids=["view", "no-view"])
def test_6_deep_folders_in_the_requests_own_folder(tmp_path, disabled):
    """3000 nested folders in the request's own folder: shutil.rmtree (Python 3.11) raises
    RecursionError in the coordinator, then in pkgforge: internal error, and the folder stays in
    /dev/shm (a tree left so makes every later run's _sweep crash the same way)."""
    workspace = _workspace(tmp_path, "alpha")
    _launch(workspace, "alpha", DEEP.replace("MARK", MARK))
    before = set(os.listdir("/dev/shm")) if os.path.isdir("/dev/shm") else set()
    try:
        result = _verify(workspace, env=dict(os.environ, PKGFORGE_SANDBOX_DISABLE=disabled))
        left = _deep_leftovers(before) if os.path.isdir("/dev/shm") else []
        assert result.returncode in (0, 1), result.stderr
        assert not left
    finally:
        for path in _deep_leftovers(before) if os.path.isdir("/dev/shm") else []:
            subprocess.run(["rm", "-rf", path], check=False)  # (C rm: no recursion limit)


CAPABILITIES = """
from launch import LaunchDescription
def generate_launch_description():
    raise RuntimeError([line.strip() for line in open("/proc/self/status") if line.startswith("CapEff")][0])
"""


@pytest.mark.skipif(os.geteuid() != 0, reason="root only: a user's process has no capability to keep")
def test_3_no_capability_is_kept_without_namespaces(tmp_path):
    """Run as root where user namespaces are not available (PKGFORGE_SANDBOX_DISABLE=namespaces: a
    container's seccomp, Ubuntu's AppArmor): capabilities are dropped only in the view, so the
    request keeps CAP_MKNOD (Landlock lets it make a block device in its own folder and write the
    disk through it), CAP_SYS_BOOT, CAP_SYS_MODULE ..."""
    workspace = _workspace(tmp_path, "alpha")
    _launch(workspace, "alpha", CAPABILITIES)
    result = _verify(workspace, env=dict(os.environ, PKGFORGE_SANDBOX_DISABLE="namespaces"))
    messages = [d["message"] for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "PF301"]
    assert messages and "CapEff:\\t0000000000000000" in repr(messages[0]), messages


SOCKETS = """
import socket
from launch import LaunchDescription
def generate_launch_description():
    for family, address in ((socket.AF_UNIX, __UNIX__), (socket.AF_INET, ("127.0.0.1", __PORT__))):
        try:
            client = socket.socket(family, socket.SOCK_STREAM)
            client.connect(address)
            client.sendall(b"rm ~/precious")
        except OSError:
            pass
    return LaunchDescription([])
"""


def test_4_no_connection_to_an_agent_outside(tmp_path):
    """A pathname Unix socket outside /tmp (/run/user/$UID/bus, /var/run/docker.sock ...) and a
    localhost TCP port: the agent behind either (systemd --user, dockerd) writes what it is told."""
    folder = tempfile.mkdtemp(prefix="r35-agent-", dir="/dev/shm" if os.path.isdir("/dev/shm") else None)
    unix = socket.socket(socket.AF_UNIX)
    unix.bind(os.path.join(folder, "bus"))
    tcp = socket.socket()
    tcp.bind(("127.0.0.1", 0))
    heard: list[bytes] = []

    def serve(server: socket.socket) -> None:
        server.listen()
        try:
            while True:
                connection, _ = server.accept()
                heard.append(connection.recv(100))
                connection.close()
        except OSError:
            return

    for server in (unix, tcp):
        threading.Thread(target=serve, args=(server,), daemon=True).start()
    try:
        workspace = _workspace(tmp_path, "alpha")
        text = SOCKETS.replace("__UNIX__", repr(os.path.join(folder, "bus"))).replace(
            "__PORT__", str(tcp.getsockname()[1])
        )
        _launch(workspace, "alpha", text)
        result = _verify(workspace)
        assert result.returncode in (0, 1), result.stderr
        assert heard == []
    finally:
        unix.close()
        tcp.close()
        shutil.rmtree(folder, ignore_errors=True)


THIEF = r"""
import os, time, json, subprocess
from launch import LaunchDescription
def generate_launch_description():
    parent = os.getppid()
    pipe = os.open(f"/proc/{parent}/fd/0", os.O_RDONLY | os.O_NONBLOCK)
    time.sleep(0.5)
    try:
        request, token = os.read(pipe, 65536).decode().splitlines()[:2]
    except (BlockingIOError, ValueError):
        return LaunchDescription([])
    swapped = json.dumps({"file": os.path.join(os.path.dirname(__file__), "clean.launch.py"), "arguments": {}})
    subprocess.run(["sh", "-c", f"printf '%s\\n%s\\n' '{swapped}' '{token}' > /proc/{parent}/fd/0"])
    return LaunchDescription([])
"""
CLEAN = "from launch import LaunchDescription\ndef generate_launch_description():\n    return LaunchDescription([])\n"
BROKEN = "def generate_launch_description():\n    raise RuntimeError('beta is broken')\n"


def test_7_a_request_cannot_swap_the_next_request(tmp_path):
    """Without the kernel's protections (announced as `writes and signals refused only by the
    Python guard`), alpha's launch file reads the request sent ahead and its token from
    /proc/<coordinator>/fd/0 and puts back another file with that token: beta's error vanishes."""
    workspace = _workspace(tmp_path, "alpha", "beta")
    _launch(workspace, "alpha", THIEF)
    (workspace / "src" / "alpha" / "launch" / "clean.launch.py").write_text(CLEAN)
    _launch(workspace, "beta", BROKEN)
    result = _verify(workspace, env=dict(os.environ, PKGFORGE_SANDBOX_DISABLE="landlock,namespaces"))
    assert ("PF301", "src/beta/launch/display.launch.py") in _codes(result)


METADATA = """
import subprocess
from launch import LaunchDescription
def generate_launch_description():
    subprocess.run(["sh", "-c", "chmod 000 TARGET"])
    return LaunchDescription([])
"""


def test_2_metadata_changes_are_refused_or_announced_without_the_view(tmp_path):
    """Landlock without the read-only view (Ubuntu 24.04's AppArmor, containers): a shell's chmod of
    the user's file succeeds, and the summary does not say the sandbox is weaker."""
    workspace = _workspace(tmp_path, "alpha")
    target = workspace / "src" / "alpha" / "package.xml"
    _launch(workspace, "alpha", METADATA.replace("TARGET", str(target)))
    mode = target.stat().st_mode
    result = run_pkgforge(
        "verify", "--no-cache", cwd=workspace, env=dict(os.environ, PKGFORGE_SANDBOX_DISABLE="namespaces")
    )
    changed = target.stat().st_mode != mode
    target.chmod(mode)
    assert not changed or "sandbox weaker" in result.stdout, result.stdout
