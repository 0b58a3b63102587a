"""Verify never changes the user's files: the copied install tree and the worker's guard.

A hostile launch file writes, truncates, deletes, renames and chmods the user's
files, runs `xacro -o` over them, writes through a child process and signals
pkgforge itself; each attempt must be refused, reported where it stands, and
the workspace (and the install base built by `pkgforge build`) must hash the
same before and after `pkgforge verify`, in all three modes.
"""

from __future__ import annotations

import hashlib
import os
import stat
from pathlib import Path

import pytest
from conftest import line_of, new_package, run_pkgforge, verify_report

HOSTILE = """\
import os, shutil, signal, subprocess, sys, tempfile
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription

SRC = {src!r}
INSTALL = {install!r}


def attempt(action):
    try:
        action()
    except OSError:
        pass


def generate_launch_description():
    share = get_package_share_directory("victim")
    attempt(lambda: open(os.path.join(SRC, "package.xml"), "w").write("gone"))  # op:write
    attempt(lambda: os.truncate(os.path.join(SRC, "CMakeLists.txt"), 0))  # op:truncate
    attempt(lambda: os.remove(os.path.join(SRC, "rviz", "display.rviz")))  # op:delete
    attempt(lambda: os.rename(os.path.join(SRC, "urdf", "macros.xacro"), os.path.join(SRC, "m.xacro")))  # op:rename
    attempt(lambda: os.chmod(os.path.join(SRC, "meshes", "arm.stl"), 0))  # op:chmod
    attempt(lambda: shutil.rmtree(os.path.join(SRC, "meshes")))  # op:rmtree
    attempt(lambda: open(os.path.join(INSTALL, "share", "victim", "package.xml"), "a").write("x"))  # op:install
    attempt(lambda: open(os.path.join(share, "urdf", "macros.xacro"), "w").write("<robot/>"))  # op:share
    subprocess.run([sys.executable, "-c", "open(%r, 'w').write('x')" % os.path.join(SRC, "package.xml")])  # op:child
    subprocess.run(["xacro", os.path.join(share, "urdf", "victim.urdf.xacro"),  # op:xacro
                    "-o", os.path.join(SRC, "urdf", "victim.urdf.xacro")])
    attempt(lambda: os.kill(os.getppid(), signal.SIGKILL))  # op:kill
    # what a launch file may do: files of its own, in a temporary folder or beside its installed ones
    with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as own:
        own.write("<robot name='r'/>")
    subprocess.run(["xacro", os.path.join(share, "urdf", "victim.urdf.xacro"),
                    "-o", os.path.join(share, "urdf", "generated.urdf")], check=True)
    return LaunchDescription([])
"""

STOPPING = """\
import os
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription


def generate_launch_description():
    urdf = os.path.join(get_package_share_directory("victim"), "urdf", "victim.urdf.xacro")
    open(urdf, "w").write("<robot/>")  # the tutorial pattern, aimed at the model itself
    return LaunchDescription([])
"""

OPERATIONS = (
    "write",
    "truncate",
    "delete",
    "rename",
    "chmod",
    "rmtree",
    "install",
    "share",
    "child",
    "xacro",
    "kill",
)


def fingerprint(folder: Path, skip: tuple[str, ...] = ()) -> dict[str, tuple]:
    """Every entry under folder: kind, mode and content (links by their text), not following links."""
    out = {}
    for root, dirs, files in os.walk(folder):
        relative_root = os.path.relpath(root, folder)
        dirs[:] = [d for d in dirs if os.path.normpath(os.path.join(relative_root, d)) not in skip]
        for name in dirs + files:
            path = os.path.join(root, name)
            info = os.lstat(path)
            if stat.S_ISLNK(info.st_mode):
                content = os.readlink(path)
            elif stat.S_ISREG(info.st_mode):
                content = hashlib.sha256(Path(path).read_bytes()).hexdigest()
            else:
                content = None
            out[os.path.relpath(path, folder)] = (
                stat.S_IFMT(info.st_mode),
                stat.S_IMODE(info.st_mode),
                content,
            )
    return out


@pytest.fixture(scope="module")
def hostile_workspace(tmp_path_factory) -> Path:
    workspace = tmp_path_factory.mktemp("sandbox")
    (workspace / "src").mkdir()
    package = new_package(workspace, "victim")
    (package / "launch" / "hostile.launch.py").write_text(
        HOSTILE.format(src=str(package), install=str(workspace / "install"))
    )
    (package / "launch" / "stopping.launch.py").write_text(STOPPING)
    result = run_pkgforge("build", cwd=workspace)
    assert result.returncode == 0, result.stdout + result.stderr
    return workspace


@pytest.mark.slow
@pytest.mark.parametrize(
    "mode", [[], ["--build"], ["--install-base", "install"]], ids=["predicted", "build", "install-base"]
)
@pytest.mark.triggers("PF316")
def test_verify_changes_nothing_of_the_users(hostile_workspace, mode):
    workspace = hostile_workspace
    package = workspace / "src" / "victim"
    mine = ("build",)  # pkgforge's own: its cache, and the --build tree
    before = fingerprint(workspace, skip=mine)
    assert fingerprint(workspace / "install")  # the install base is hashed too
    status, report = verify_report(workspace, "--no-cache", *mode)
    assert fingerprint(workspace, skip=mine) == before
    assert status == 0, report  # warnings only: the guard kept everything
    hostile = package / "launch" / "hostile.launch.py"
    found = {(d["code"], d["path"], d["line"]) for d in report["diagnostics"]}
    for operation in OPERATIONS:
        line = line_of(hostile, f"# op:{operation}")
        assert ("PF316", "src/victim/launch/hostile.launch.py", line) in found, (operation, report)
    by_line = {
        d["line"]: d["message"]
        for d in report["diagnostics"]
        if d["code"] == "PF316" and d["path"].endswith("hostile.launch.py")
    }
    assert "pkgforge refused it and kept the file unchanged" in by_line[line_of(hostile, "# op:write")]
    assert str(package / "package.xml") in by_line[line_of(hostile, "# op:write")]
    assert "through a process it starts" in by_line[line_of(hostile, "# op:child")]
    assert "installed share/victim/urdf/macros.xacro" in by_line[line_of(hostile, "# op:share")]
    assert "send signal 9" in by_line[line_of(hostile, "# op:kill")]
    # what the launch file may do is not reported, and it ran to its end
    assert not {d["line"] for d in report["diagnostics"] if d["path"].endswith("hostile.launch.py")} - {
        line_of(hostile, f"# op:{operation}") for operation in OPERATIONS
    }
    # the tutorial pattern aimed at the model: refused, located, and the model still checks clean
    stopping = package / "launch" / "stopping.launch.py"
    (stop,) = [d for d in report["diagnostics"] if d["path"].endswith("stopping.launch.py")]
    assert (stop["code"], stop["line"]) == ("PF316", line_of(stopping, "open(urdf"))
    assert "loading stopped there" in stop["message"]
    assert not [d for d in report["diagnostics"] if d["path"].endswith(".xacro")]


def test_the_tree_holds_copies_not_links_to_the_source(tmp_path):
    """The predicted tree: small files are copies (writing one cannot reach src/); a large mesh
    stays a link, and the guard copies it before a write."""
    from pkgforge.model.package import load_package
    from pkgforge.tree import LINK_THRESHOLD, predicted_tree

    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "copied")
    big = package / "meshes" / "big.stl"
    big.write_bytes(b"\0" * (LINK_THRESHOLD + 1))
    model = load_package(package)
    tree = predicted_tree([model])
    try:
        share = tree.share("copied")
        assert not (share / "urdf" / "copied.urdf.xacro").is_symlink()
        assert (share / "urdf" / "copied.urdf.xacro").read_bytes() == (
            package / "urdf" / "copied.urdf.xacro"
        ).read_bytes()
        assert (share / "meshes" / "big.stl").is_symlink()
        assert tree.origin(str(share / "package.xml")) == str((package / "package.xml").resolve())
        from pkgforge.launch.resolve import source_of

        assert (
            source_of(share / "urdf" / "copied.urdf.xacro", tree, model)
            == package / "urdf" / "copied.urdf.xacro"
        )
    finally:
        tree.close()
    assert not Path(tree.root).exists()


def test_the_guard_reaches_child_python_processes(tmp_path):
    """A Python process started with the worker's environment (guard_site on PYTHONPATH) gets the
    guard before its first line: writes outside the folder and signals to its parent are refused
    and logged; files of its own inside the folder are written."""
    import json
    import signal
    import subprocess
    import sys

    import pkgforge.sandbox.guard as guard

    sandbox, user = tmp_path / "sandbox", tmp_path / "user.txt"
    sandbox.mkdir()
    user.write_text("mine\n")
    site = Path(guard.__file__).parent / "guard_site"
    env = dict(os.environ, PYTHONPATH=str(site), PKGFORGE_SANDBOX=str(sandbox))
    env.pop(guard.ROOT_PID_VARIABLE, None)
    script = (
        f"import os, signal\n"
        f"open({str(sandbox / 'own.txt')!r}, 'w').write('ok')\n"
        f"for action in (lambda: open({str(user)!r}, 'w'), lambda: os.remove({str(user)!r}),\n"
        f"               lambda: os.kill(os.getppid(), signal.{signal.Signals.SIGTERM.name})):\n"
        f"    try:\n        action()\n    except PermissionError as error:\n        print(error)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.count("pkgforge refused") == 3, result.stdout
    assert user.read_text() == "mine\n" and (sandbox / "own.txt").read_text() == "ok"
    (log,) = sandbox.glob(".refused-*")  # the process started without a worker: its own pid
    logged = [json.loads(line) for line in log.read_text().splitlines()]
    assert [(r["operation"], r["path"]) for r in logged] == [
        ("write", str(user)),
        ("delete", str(user)),
        (f"send signal {int(signal.SIGTERM)} to", f"process {os.getpid()}"),
    ]
