"""Issue 35: what a launch file or a xacro model does can change nothing of the user's, signal nothing of
pkgforge's, forge no result and hang nothing; the kernel enforces it where it can, and says where not.

Each test is one of the cases an outside campaign reproduced on the guard alone (a Python audit
hook): a shell child, `python -I`, ctypes, a xacro expression, a forged reply, a process tree
left behind. Each runs the real `pkgforge verify` on a real package, with HOME and an "elsewhere"
folder of the test's own, and compares every file of the workspace, HOME and elsewhere (kind,
mode, content, and the times of the files a case aims at) before and after.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import sys
import time
import uuid
from pathlib import Path

import pytest
from conftest import line_of, run_pkgforge
from test_processes import MARKER, left_behind
from test_sandbox import fingerprint

from pkgforge.sandbox import landlock, namespaces

LAUNCH_HEAD = """\
import ctypes, os, signal, socket, sqlite3, subprocess, sys, time
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription

SRC = {src!r}
HOME = {home!r}
ELSEWHERE = {elsewhere!r}
MARK = {mark!r}


def attempt(action):
    try:
        action()
    except Exception:
        pass

"""


@pytest.fixture
def setting(tmp_path, template_package):
    """(workspace, package, home, elsewhere): a clean package, and folders of the user's outside it."""
    workspace = tmp_path / "ws"
    package = workspace / "src" / "rob_description"
    shutil.copytree(template_package, package)
    home, elsewhere = tmp_path / "home", tmp_path / "elsewhere"
    for folder in (home, elsewhere):
        folder.mkdir()
        (folder / "keep.txt").write_text("mine\n")
    return workspace, package, home, elsewhere


def hostile(setting, body: str, name: str = "hostile.launch.py") -> Path:
    workspace, package, home, elsewhere = setting
    path = package / "launch" / name
    path.write_text(
        LAUNCH_HEAD.format(src=str(package), home=str(home), elsewhere=str(elsewhere), mark=str(workspace))
        + "def generate_launch_description():\n"
        + "".join(f"    {line}\n" for line in body.strip("\n").splitlines())
        + "    return LaunchDescription([])\n"
    )
    return path


def everything(setting) -> dict:
    workspace, _, home, elsewhere = setting
    return {
        "workspace": fingerprint(workspace, skip=("build",)),
        "home": fingerprint(home),
        "elsewhere": fingerprint(elsewhere),
        "times": {p: os.stat(p).st_mtime_ns for p in sorted(map(str, workspace.rglob("*")))},
    }


def verify(setting, *args: str, env: dict | None = None) -> tuple[int, dict, str]:
    """`pkgforge verify --format json` in the workspace, as the user: (status, report, stderr)."""
    workspace, _, home, _ = setting
    environment = dict(os.environ, HOME=str(home), **(env or {}))
    result = run_pkgforge(
        "verify",
        workspace,
        "--no-cache",
        "--format",
        "json",
        *args,
        cwd=workspace,
        env=environment,
        timeout=150,
    )
    assert "Traceback" not in result.stderr, result.stderr
    assert result.returncode in (0, 1), (result.returncode, result.stdout, result.stderr)
    return result.returncode, json.loads(result.stdout), result.stderr


def unchanged(setting, body: str, *args: str, env: dict | None = None) -> tuple[int, dict, Path]:
    """Run `body` in a launch file under verify; nothing of the user's may change."""
    launch = hostile(setting, body)
    before = everything(setting)
    status, report, _ = verify(setting, *args, env=env)
    assert everything(setting) == before
    return status, report, launch


# --- writes outside the sandbox ------------------------------------------------------------------


def test_a_shell_writes_nothing_of_the_users(setting):
    """Case 1: os.system appending to the package's manifest, touching $HOME, writing elsewhere and
    changing a mode: no Python in the shell, so the guard never saw it; the kernel refuses it."""
    status, report, _ = unchanged(
        setting,
        """
os.system(f"echo x >> {SRC}/package.xml; touch {HOME}/f; echo x >> {ELSEWHERE}/keep.txt; "
          f"chmod 600 {SRC}/CMakeLists.txt; touch -d 2001-01-01 {SRC}/launch/display.launch.py")
""",
    )
    assert status == 0, report


def test_a_careless_redirection_does_not_land_in_the_users_folder(setting):
    """Case 2: `xacro m.xacro > generated.urdf` in the current folder: the request's own folder, not
    the folder verify was started in."""
    workspace, package, _, _ = setting
    status, report, _ = unchanged(
        setting,
        """
share = get_package_share_directory("rob_description")
subprocess.run(f"xacro {share}/urdf/rob_description.urdf.xacro > generated.urdf", shell=True)
subprocess.run("echo x > made_here.txt", shell=True)
""",
    )
    assert not list(workspace.rglob("generated.urdf")) and not list(workspace.rglob("made_here.txt"))
    assert status == 0, report


def test_a_shell_cannot_append_to_a_large_mesh_through_its_link(setting):
    """Case 3: a mesh over 1 MiB is a link into the user's package in pkgforge's tree; a shell
    appending to it would change the user's file (only Python writes got a private copy)."""
    from pkgforge.tree import LINK_THRESHOLD

    _, package, _, _ = setting
    (package / "meshes" / "big.stl").write_bytes(b"\0" * (LINK_THRESHOLD + 1))
    unchanged(
        setting,
        """
share = get_package_share_directory("rob_description")
os.system(f"echo x >> {share}/meshes/big.stl; truncate -s 0 {share}/meshes/arm.stl")
""",
    )


def test_pure_python_ways_around_the_audit_hook_change_nothing(setting):
    """Case 4: a read-only descriptor reopened for writing (/proc/self/fd, /dev/fd), fchmod and utime
    on a descriptor, os.open with dir_fd, sqlite3, a Unix socket bound to a path, and the guard's
    own state set by the launch file before writing."""
    status, report, launch = unchanged(
        setting,
        """
fd = os.open(f"{SRC}/package.xml", os.O_RDONLY)
attempt(lambda: open(f"/proc/self/fd/{fd}", "a").write("x"))  # op:proc
attempt(lambda: open(f"/dev/fd/{fd}", "a").write("x"))  # op:devfd
attempt(lambda: os.fchmod(fd, 0o777))  # op:fchmod
attempt(lambda: os.utime(fd, (0, 0)))  # op:futime
folder = os.open(SRC, os.O_RDONLY)
attempt(lambda: os.write(os.open("CMakeLists.txt", os.O_WRONLY | os.O_APPEND, dir_fd=folder), b"x"))
attempt(lambda: sqlite3.connect(f"{HOME}/db.sqlite").execute("create table t (x)"))
attempt(lambda: socket.socket(socket.AF_UNIX).bind(f"{ELSEWHERE}/sock"))
import pkgforge.sandbox.guard as guard
guard._state["roots"] = ["/"]
attempt(lambda: open(f"{SRC}/package.xml", "w").write("gone"))
attempt(lambda: open(f"{HOME}/after-guard.txt", "w").write("x"))
""",
    )
    found = {(d["code"], d["line"]) for d in report["diagnostics"] if d["path"].endswith("hostile.launch.py")}
    # (writes of one file with the same message are one diagnostic naming their lines: issue 30)
    found |= {
        (d["code"], int(line))
        for d in report["diagnostics"]
        if d["path"].endswith("hostile.launch.py")
        for line in re.findall(r"^line (\d+): ", d["detail"] or "", re.M)
    }
    # the guard still says, at its line, what it saw (the kernel refused the rest silently)
    for operation in ("proc", "devfd", "fchmod", "futime"):
        assert ("PF316", line_of(launch, f"# op:{operation}")) in found, (operation, report["diagnostics"])


def test_python_without_the_guard_writes_nothing(setting):
    """Case 5: `python -I`, `python -S` and a child with an empty environment load no guard."""
    unchanged(
        setting,
        """
code = f"open({HOME!r} + '/f', 'w').write('x'); open({SRC!r} + '/package.xml', 'a').write('x')"
for flags in (["-I"], ["-S"], []):
    subprocess.run([sys.executable, *flags, "-c", code], env={} if not flags else None)
""",
    )


def test_a_xacro_expression_that_escapes_xacros_eval_writes_nothing(setting):
    """Case 6: a model alone, no launch file: xacro's restricted eval reaches Popen through
    object's subclasses and runs a shell that writes HOME."""
    workspace, package, home, _ = setting
    payload = (
        "[c for c in python.vars(python.type)['__subclasses__'](python.type(0).mro()[-1]) "
        f"if 'Popen' in python.repr(c)][0]('touch {home}/escaped; echo x >> {package}/package.xml', "
        "shell=True).wait() and 'escaped'"
    )
    (package / "urdf" / "escape.urdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="escape">\n'
        f'  <link name="${{{payload}}}"/>\n</robot>\n'
    )
    before = everything(setting)
    status, report, _ = verify(setting)
    assert everything(setting) == before
    assert not (home / "escaped").exists()


# --- signals, forged results, the report ------------------------------------------------------------


def test_a_detached_child_cannot_kill_pkgforge(setting):
    """Case 7: a setsid child with no guard SIGKILLs every process whose command line names this
    workspace (pkgforge's own); pkgforge reports as usual."""
    status, report, _ = unchanged(
        setting,
        """
code = (
    "import os\\n"
    "for p in os.listdir('/proc'):\\n"
    "    try:\\n"
    "        if p.isdigit() and MARK in open(f'/proc/{p}/cmdline', 'rb').read().decode(errors='replace'):\\n"
    "            os.kill(int(p), 9)\\n"
    "    except OSError:\\n"
    "        pass\\n"
).replace("MARK", repr(MARK))
subprocess.run([sys.executable, "-I", "-c", code], start_new_session=True)
""",
    )
    assert report["summary"]["packages"] == 1


def test_a_forged_reply_on_an_inherited_descriptor_is_not_taken(setting):
    """Case 8: the launch file writes a reply saying it loaded, to every descriptor it has, then
    fails: it is an error, not clean."""
    status, report, launch = unchanged(
        setting,
        """
forged = json_reply = b'{"status": "ok", "nodes": [], "token": "0"}\\n'
for fd in range(3, 256):
    attempt(lambda: os.write(fd, forged))
raise RuntimeError("the real failure")
""",
    )
    assert status == 1, report
    (error,) = [d for d in report["diagnostics"] if d["code"] == "PF301"]
    assert error["path"] == "src/rob_description/launch/hostile.launch.py"
    assert "no result of it can be trusted" in error["message"], error


def test_a_child_cannot_write_into_pkgforges_report(setting):
    """Case 9: a child without the guard writes into /proc/<pkgforge>/fd/1: the JSON report stays
    pkgforge's own."""
    status, report, _ = unchanged(
        setting,
        """
code = (
    "import os\\n"
    "for p in os.listdir('/proc'):\\n"
    "    try:\\n"
    "        if p.isdigit() and MARK in open(f'/proc/{p}/cmdline', 'rb').read().decode(errors='replace'):\\n"
    "            open(f'/proc/{p}/fd/1', 'w').write('FORGED')\\n"
    "    except OSError:\\n"
    "        pass\\n"
).replace("MARK", repr(MARK))
subprocess.run([sys.executable, "-I", "-c", code], start_new_session=True)
""",
    )
    assert "FORGED" not in json.dumps(report)


def test_a_tree_of_sleeping_children_neither_hangs_verify_nor_outlives_it(setting, monkeypatch):
    """Case 10: sixteen launch files each fork a tree of children that sleep for ten minutes
    holding whatever the launch file held, some detaching (setsid) a moment later; verify ends
    each time (the old worker waited for its pipe to close: a hang about one run in five here),
    and none of them is left."""
    workspace, package, _, _ = setting
    marker = uuid.uuid4().hex
    monkeypatch.setenv(MARKER, marker)
    for index in range(16):
        hostile(
            setting,
            """
for _ in range(4):
    if os.fork() == 0:
        for _ in range(3):
            if os.fork() == 0:
                time.sleep(0.2)
                if os.fork() == 0:
                    os.setsid()
                    time.sleep(600)
                    os._exit(0)
                time.sleep(600)
                os._exit(0)
        time.sleep(600)
        os._exit(0)
""",
            name=f"sleepers{index}.launch.py",
        )
    for disabled in ("", "namespaces"):  # a PID namespace's kill(-1), or the subreaper's kill_tree
        started = time.monotonic()
        status, report, _ = verify(setting, env={"PKGFORGE_SANDBOX_DISABLE": disabled})
        assert time.monotonic() - started < 120
        assert status == 0, report
        assert left_behind(marker) == []


# --- what the kernel enforces, and says ---------------------------------------------------------------


BYPASS = """
libc = ctypes.CDLL(None, use_errno=True)  # below Python's audit hooks: only the kernel sees it
fd = libc.open(f"{TARGET}".encode(), os.O_WRONLY | os.O_APPEND)
if fd < 0:
    raise OSError(ctypes.get_errno(), "kernel refused the write")
libc.write(fd, b"written", 7)
"""


@pytest.fixture
def outside_tmp():
    """A folder of the user's outside /tmp (in /dev/shm), with keep.txt in it; removed after."""
    import tempfile

    if not os.access("/dev/shm", os.W_OK):
        pytest.skip("no writable /dev/shm")
    folder = Path(tempfile.mkdtemp(prefix="pkgforge-test-", dir="/dev/shm"))
    (folder / "keep.txt").write_text("mine\n")
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


def expected_confinement() -> dict:
    abi = landlock.abi_version()
    support = namespaces.probe()
    return {"landlock": abi, "signals": abi >= 6, "view": support["view"], "pid": support["pid"]}


@pytest.mark.parametrize(
    "disabled", ["", "landlock", "namespaces", "landlock,namespaces"], ids=["all", "view", "landlock", "none"]
)
def test_the_kernel_refuses_a_write_python_never_sees(setting, disabled, outside_tmp):
    """A write through libc in the launch file: refused by Landlock (EACCES) or the read-only view
    (EROFS), whichever is active; with neither, the write happens (so this test can fail) and the
    summary says the sandbox is weaker. The JSON says which protections were active."""
    target = outside_tmp / "keep.txt"  # (under /tmp the read-only view has a private overlay)
    launch = hostile(setting, BYPASS.replace("{TARGET}", str(target)))
    status, report, _ = verify(setting, env={"PKGFORGE_SANDBOX_DISABLE": disabled})
    expected = expected_confinement()
    if "landlock" in disabled:
        expected.update(landlock=0, signals=False)
    if "namespaces" in disabled:
        expected.update(view=False, pid=False)
    assert {k: report["sandbox"][k] for k in expected} == expected, report["sandbox"]
    kernel = expected["landlock"] > 0 or expected["view"]
    weaker = not (kernel and expected["view"] and (expected["signals"] or expected["pid"]))
    text = run_pkgforge(
        "verify", "--no-cache", cwd=setting[0], env=dict(os.environ, PKGFORGE_SANDBOX_DISABLE=disabled)
    )
    assert ("; sandbox weaker: " in text.stdout.splitlines()[-1]) == weaker, text.stdout
    if kernel:
        (error,) = [d for d in report["diagnostics"] if d["code"] == "PF301"]
        assert error["line"] == line_of(launch, "raise OSError"), error
        errno = 30 if expected["view"] else 13  # the read-only view (EROFS) is met before Landlock (EACCES)
        assert f"[Errno {errno}]" in error["message"], error
        assert target.read_text() == "mine\n"
    else:
        assert target.read_text().startswith("mine\nwritten")
        assert "sandbox weaker: writes, chmod/utime, signals refused only by the Python guard" in text.stdout


def test_this_machine_enforces_writes_and_signals_in_the_kernel():
    """Where the kernel has Landlock ABI 6 (this CI's does), both are kernel-enforced."""
    if landlock.abi_version() < 6:
        pytest.skip(f"Landlock ABI {landlock.abi_version()} on this kernel")
    result = run_pkgforge("verify", "--explain-sandbox", cwd=Path.cwd())
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith(f"✓ Landlock ABI {landlock.abi_version()}:"), result.stdout
    assert lines[1].startswith("✓ Landlock scopes"), result.stdout
    assert "sandbox weaker" not in result.stdout


def test_explain_sandbox_says_what_is_missing():
    env = dict(os.environ, PKGFORGE_SANDBOX_DISABLE="landlock,namespaces")
    result = run_pkgforge("verify", "--explain-sandbox", cwd=Path.cwd(), env=env)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[0].startswith("✗ Landlock"), result.stdout
    assert "not available: Landlock: turned off (PKGFORGE_SANDBOX_DISABLE)" in result.stdout
    assert result.stdout.rstrip().endswith(
        "sandbox weaker: writes, chmod/utime, signals refused only by the Python guard (see --explain-sandbox)"
    )


def test_each_file_runs_in_a_fresh_process(setting):
    """No user code runs in a process that evaluates another file: what one launch file changes
    in its interpreter (the launch API itself) is gone for the next."""
    workspace, package, _, _ = setting
    hostile(setting, "import launch\nlaunch.LaunchDescription = None", name="a_poison.launch.py")
    status, report, _ = verify(setting, "--jobs", "1")
    assert status == 0, [d for d in report["diagnostics"] if d["severity"] == "error"]
    assert sys.platform != "linux" or report["sandbox"] is not None


TMP_ROUND_TRIP = """
share = get_package_share_directory("rob_description")
urdf = "/tmp/{name}.urdf"
subprocess.run(["xacro", f"{{share}}/urdf/rob_description.urdf.xacro", "-o", urdf])  # op:write
with open(urdf) as handle:  # op:read
    handle.read()
"""


@pytest.mark.parametrize("disabled", ["", "namespaces"], ids=["private-tmp", "no-view"])
def test_a_launch_file_writing_tmp_and_reading_it_back(setting, disabled):
    """The tutorial pattern `xacro -o /tmp/x.urdf`, then open() it: ros2 launch lets it write. In the
    read-only view /tmp is the file's own overlay (the user's /tmp untouched): clean. Without one,
    the write is refused and the failure that follows is a warning naming that refusal, not an error."""
    if disabled == "" and not namespaces.probe()["view"]:
        pytest.skip("no user namespaces here")
    name = f"pkgforge-test-{uuid.uuid4().hex}"
    launch = hostile(setting, TMP_ROUND_TRIP.format(name=name))
    status, report, _ = verify(setting, env={"PKGFORGE_SANDBOX_DISABLE": disabled})
    assert not Path(f"/tmp/{name}.urdf").exists()
    found = {(d["code"], d["severity"], d["line"]) for d in report["diagnostics"]}
    if disabled == "":
        assert status == 0 and not found, report["diagnostics"]
    else:
        assert status == 0, report["diagnostics"]
        assert found == {
            ("PF316", "warning", line_of(launch, "# op:write")),
            ("PF301", "warning", line_of(launch, "# op:read")),
        }, report["diagnostics"]
