"""Issue 11: no process outlives pkgforge; signals exit 128+N at once; worker limits are located
findings; a failed `verify --build` still reports; the cache keeps no machine-dependent answer.

Every test runs the real `pkgforge` on real launch files. Processes are found by a marker in
their environment (inherited from the pkgforge process the test starts), so other runs on the
same machine are never mistaken for ours.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest
from lxml import etree

from conftest import copy_fixture, line_of, run_pkgforge

MARKER = "PKGFORGE_TEST_MARKER"

# a launch file that starts a child, double-forks a setsid sleeper, then does `tail`
SPAWNING = '''import os
import subprocess
import time

from launch import LaunchDescription


def generate_launch_description():
    subprocess.Popen(["sleep", "7771"])
    if os.fork() == 0:
        os.setsid()
        if os.fork() == 0:
            os.execvp("sleep", ["sleep", "7772"])
        os._exit(0)
{tail}
    return LaunchDescription([])
'''


def package(workspace: Path, launch: str, name: str = "proc_pkg") -> Path:
    result = run_pkgforge("new", name, "--maintainer-email", "t@example.com", "--destination", "src",
                          cwd=workspace)
    assert result.returncode == 0, result.stderr
    folder = workspace / "src" / name
    (folder / "launch" / "display.launch.py").write_text(launch)
    return folder


def marked(marker: str) -> list[tuple[int, str]]:
    """Live processes (not zombies) whose environment holds the marker."""
    found = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/environ", "rb") as handle:
                if f"{MARKER}={marker}".encode() not in handle.read():
                    continue
            with open(f"/proc/{pid}/stat", "rb") as handle:
                if handle.read().rsplit(b")", 1)[1].split()[0] == b"Z":
                    continue
            with open(f"/proc/{pid}/cmdline", "rb") as handle:
                found.append((int(pid), handle.read().replace(b"\0", b" ").decode(errors="replace")))
        except OSError:
            continue
    return found


def left_behind(marker: str, settle: float = 3.0) -> list[tuple[int, str]]:
    """What is still running after pkgforge ended (a short settle: a killed process takes a moment
    to disappear from /proc)."""
    deadline = time.monotonic() + settle
    while time.monotonic() < deadline:
        alive = marked(marker)
        if not alive:
            return []
        time.sleep(0.05)
    alive = marked(marker)
    for pid, _ in alive:  # do not leave them to the next test
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
    return alive


def start_verify(workspace: Path, marker: str, *args: str) -> subprocess.Popen:
    """`pkgforge verify` with its temporary files in workspace/tmp (to see that none is left)."""
    (workspace / "tmp").mkdir(exist_ok=True)
    env = dict(os.environ, **{MARKER: marker}, TMPDIR=str(workspace / "tmp"))
    return subprocess.Popen([sys.executable, "-m", "pkgforge", "verify", "--no-cache", *args], cwd=workspace,
                            env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


def wait_for(marker: str, text: str, process: subprocess.Popen, limit: float = 120) -> None:
    deadline = time.monotonic() + limit
    while not any(text in cmdline for _, cmdline in marked(marker)):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, f"{text} never started"
        time.sleep(0.05)


# --- signals ----------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["SIGINT", "SIGTERM", "SIGHUP"])
def test_signal_kills_every_process_and_exits_128_plus_signal(tmp_path, name):
    package(tmp_path, SPAWNING.format(tail="    time.sleep(600)"))
    marker = uuid.uuid4().hex
    process = start_verify(tmp_path, marker)
    wait_for(marker, "sleep 7772", process)
    assert any("pkgforge.launch.worker" in cmdline for _, cmdline in marked(marker))
    started = time.monotonic()
    process.send_signal(getattr(signal, name))
    out, err = process.communicate(timeout=60)
    elapsed = time.monotonic() - started
    print(f"{name}: pkgforge exited {process.returncode} {elapsed:.3f} s after the signal")
    assert process.returncode == 128 + getattr(signal, name), err
    assert "Traceback" not in err
    assert left_behind(marker) == []
    assert elapsed < 5  # generous: measured ~0.04 s (the issue asks for 1 s)
    assert list((tmp_path / "tmp").iterdir()) == []  # the temporary install tree is removed


def test_double_forked_setsid_child_is_gone_after_verify(tmp_path):
    folder = package(tmp_path, SPAWNING.format(tail="    time.sleep(0.5)"))
    marker = uuid.uuid4().hex
    process = start_verify(tmp_path, marker, "--format", "json")
    out, err = process.communicate(timeout=300)
    assert process.returncode in (0, 1), err
    assert "Traceback" not in err
    assert left_behind(marker) == []
    # the launch file itself was evaluated (an empty description: the model is checked on its own)
    assert not [d for d in json.loads(out)["diagnostics"] if d["code"] == "PF301"], out
    assert folder.is_dir()


def test_worker_that_kills_itself_is_reported_and_pkgforge_goes_on(tmp_path):
    launch = ("import os\nimport signal\n\n\ndef generate_launch_description():\n"
              "    os.kill(os.getpid(), signal.SIGKILL)\n")
    package(tmp_path, launch)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert (diagnostic["code"], diagnostic["path"]) == ("PF301", "src/proc_pkg/launch/display.launch.py")
    assert "SIGKILL" in diagnostic["message"]


# --- limits -----------------------------------------------------------------------------------

BIG_ALLOCATION = '''from launch import LaunchDescription


def generate_launch_description():
    everything = bytearray(6 * 2**30)
    return LaunchDescription([everything])
'''


def test_6_gib_allocation_is_a_located_memory_limit(tmp_path):
    folder = package(tmp_path, BIG_ALLOCATION)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stderr
    errors = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    (diagnostic,) = errors
    launch = folder / "launch" / "display.launch.py"
    assert (diagnostic["code"], diagnostic["path"], diagnostic["line"]) == \
        ("PF301", "src/proc_pkg/launch/display.launch.py", line_of(launch, "bytearray"))
    assert "2 GiB memory limit" in diagnostic["message"]
    assert "--worker-memory" in diagnostic["message"]


def test_worker_memory_option(tmp_path):
    package(tmp_path, BIG_ALLOCATION)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", "--worker-memory", "512M", cwd=tmp_path)
    assert result.returncode == 1
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert "512 MiB memory limit" in diagnostic["message"]
    bad = run_pkgforge("verify", "--worker-memory", "lots", cwd=tmp_path)
    assert bad.returncode == 2
    assert "Invalid value for '--worker-memory'" in bad.stderr and "2G or 512M" in bad.stderr


def test_open_files_limit_is_located(tmp_path):
    launch = ('from launch import LaunchDescription\n\n\ndef generate_launch_description():\n'
              '    files = [open(__file__) for _ in range(5000)]\n    return LaunchDescription([])\n')
    folder = package(tmp_path, launch)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", cwd=tmp_path)
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert (diagnostic["code"], diagnostic["line"]) == \
        ("PF301", line_of(folder / "launch" / "display.launch.py", "open(__file__)"))
    assert "1024 open files" in diagnostic["message"]


def test_limits_are_set_before_the_launch_file_runs(tmp_path):
    launch = ('import resource\n\n\ndef generate_launch_description():\n'
              '    raise RuntimeError(repr([resource.getrlimit(getattr(resource, kind))[0]\n'
              '                             for kind in ("RLIMIT_AS", "RLIMIT_NOFILE", "RLIMIT_CPU")]))\n')
    package(tmp_path, launch)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", "--launch-timeout", "7", cwd=tmp_path)
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    memory, files, cpu = json.loads(diagnostic["message"].rsplit("RuntimeError: ", 1)[1])
    assert (memory, files) == (2 * 2**30, 1024)
    assert 7 <= cpu <= 9  # this file's share: the CPU time used so far + the time limit


def test_cpu_time_limit_is_located(tmp_path):
    """The CPU limit (SIGXCPU) stops the launch file at the line it was running. Reaching it in a
    test without racing the wall-time limit: the file lowers its own soft limit to 1 s."""
    launch = ('import resource\n\n\ndef generate_launch_description():\n'
              '    used = resource.getrusage(resource.RUSAGE_SELF)\n'
              '    soft, hard = resource.getrlimit(resource.RLIMIT_CPU)\n'
              '    resource.setrlimit(resource.RLIMIT_CPU, (int(used.ru_utime + used.ru_stime) + 1, hard))\n'
              '    while True: sum(range(1000))\n')
    folder = package(tmp_path, launch)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", "--launch-timeout", "60", cwd=tmp_path)
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert (diagnostic["code"], diagnostic["line"]) == \
        ("PF301", line_of(folder / "launch" / "display.launch.py", "while True: sum"))
    assert "CPU time limit" in diagnostic["message"] and "--launch-timeout" in diagnostic["message"]


def test_wall_time_limit_is_located(tmp_path):
    launch = ('import time\n\nfrom launch import LaunchDescription\n\n\ndef generate_launch_description():\n'
              '    time.sleep(600)\n    return LaunchDescription([])\n')
    folder = package(tmp_path, launch)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", "--launch-timeout", "1", cwd=tmp_path)
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert (diagnostic["code"], diagnostic["line"]) == \
        ("PF301", line_of(folder / "launch" / "display.launch.py", "time.sleep(600)"))
    assert "still running after the 1 s limit" in diagnostic["message"]


def test_colcon_verify_worker_memory(tmp_path):
    from test_launch import SCRIPTS, plain_colcon_build

    package(tmp_path, BIG_ALLOCATION)
    plain_colcon_build(tmp_path)
    colcon = [str(SCRIPTS / "colcon"), "verify", "--pkgforge-format", "json"]
    result = subprocess.run([*colcon, "--worker-memory", "512M"], cwd=tmp_path, capture_output=True, text=True,
                            timeout=600, stdin=subprocess.DEVNULL)
    assert result.returncode == 1, result.stdout + result.stderr
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert diagnostic["code"] == "PF301" and "512 MiB memory limit" in diagnostic["message"]
    bad = subprocess.run([*colcon, "--worker-memory", "lots"], cwd=tmp_path, capture_output=True, text=True,
                         timeout=600, stdin=subprocess.DEVNULL)
    assert bad.returncode != 0 and "not a size such as 2G or 512M" in bad.stderr


# --- verify --build on a failing build ---------------------------------------------------------

def test_failing_build_still_reports_everything(tmp_path):
    copy_fixture("seed001/small_turtle", tmp_path)  # install(DIRECTORY worlds models) that do not exist
    result = run_pkgforge("verify", "--build", "--format", "json", "--output", "report.json",
                          "--junit-xml", "out/junit.xml", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stderr
    report = json.loads((tmp_path / "report.json").read_text())
    found = sorted((d["code"], d["path"], d["line"]) for d in report["diagnostics"])
    cmake = tmp_path / "src" / "small_turtle" / "CMakeLists.txt"
    assert found == [("PF201", "src/small_turtle/CMakeLists.txt", line_of(cmake, "worlds"))] * 2 + \
        [("PF902", "src/small_turtle/CMakeLists.txt", None)]
    (failed,) = [d for d in report["diagnostics"] if d["code"] == "PF902"]
    log = tmp_path / "build" / "pkgforge-verify" / "log" / "latest_build" / "small_turtle" / "stdout_stderr.log"
    assert str(log) in failed["message"] and log.is_file()
    assert 'file INSTALL cannot find' in failed["message"]
    assert failed["name"] == "build-failed" and failed["severity"] == "error"
    junit = etree.parse(str(tmp_path / "out" / "junit.xml"))
    etree.XMLSchema(etree.parse(str(Path(__file__).parent / "schemas" / "junit.xsd"))).assertValid(junit)
    failures = junit.findall(".//testcase/failure/..")
    assert "PF902 build-failed" in {case.get("name") for case in failures}


def test_failing_build_is_located_at_the_cmake_error(tmp_path):
    folder = copy_fixture("seed000/rob_description", tmp_path)
    cmake = folder / "CMakeLists.txt"
    text = cmake.read_text().replace("find_package(ament_cmake REQUIRED)",
                                     "find_package(ament_cmake REQUIRED)\nmessage(FATAL_ERROR \"not today\")")
    cmake.write_text(text)
    result = run_pkgforge("verify", "--build", "--format", "json", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    (failed,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "PF902"]
    assert (failed["path"], failed["line"]) == ("src/rob_description/CMakeLists.txt",
                                                line_of(cmake, "FATAL_ERROR"))
    assert "not today" in failed["message"]


# --- the cache --------------------------------------------------------------------------------

# each misbehaves only while the flag file exists: what the machine's state decides
FLAGGED = {
    "timeout": "    while os.path.exists(FLAG):\n        pass\n",
    "crash": "    if os.path.exists(FLAG):\n        os._exit(3)\n",
    "killed": "    if os.path.exists(FLAG):\n        os.kill(os.getpid(), 9)\n",
    "memory": "    if os.path.exists(FLAG):\n        bytearray(6 * 2**30)\n",
}


@pytest.mark.parametrize("case", sorted(FLAGGED))
def test_machine_dependent_results_are_not_cached(tmp_path, case):
    flag = tmp_path / "flag"
    flag.touch()
    launch = (f"import os\n\nfrom launch import LaunchDescription\n\nFLAG = {str(flag)!r}\n\n\n"
              f"def generate_launch_description():\n{FLAGGED[case]}    return LaunchDescription([])\n")
    package(tmp_path, launch)
    first = run_pkgforge("verify", "--format", "json", "--launch-timeout", "1", cwd=tmp_path)
    assert first.returncode == 1, first.stderr
    assert [d["code"] for d in json.loads(first.stdout)["diagnostics"] if d["severity"] == "error"] == ["PF301"]
    flag.unlink()  # the machine is fine again; no file of the package changed
    second = run_pkgforge("verify", "--format", "json", "--launch-timeout", "1", cwd=tmp_path)
    assert second.returncode == 0, second.stdout
    assert not [d for d in json.loads(second.stdout)["diagnostics"] if d["severity"] == "error"]


def test_a_clean_result_is_still_cached(tmp_path):
    package(tmp_path, "from launch import LaunchDescription\n\n\n"
                      "def generate_launch_description():\n    return LaunchDescription([])\n")
    first = run_pkgforge("verify", "--format", "json", cwd=tmp_path)
    assert first.returncode == 0, first.stdout + first.stderr
    assert cache_entry(tmp_path)["report"]["name"] == "proc_pkg"


def cache_entry(workspace: Path) -> dict:
    (entry,) = [p for p in (workspace / "build" / "pkgforge-cache").glob("*.json") if p.name != "digests.json"]
    return json.loads(entry.read_text())


def test_file_mode_is_part_of_the_fingerprint(tmp_path):
    folder = package(tmp_path, "")
    (folder / "launch" / "display.launch.py").unlink()
    first = run_pkgforge("verify", "--format", "json", cwd=tmp_path)
    assert first.returncode == 0, first.stdout + first.stderr
    key = cache_entry(tmp_path)["key"]
    mesh = next((folder / "meshes").iterdir(), None) or folder / "package.xml"
    mesh.chmod(0)
    try:
        second = run_pkgforge("verify", "--format", "json", cwd=tmp_path)
        fresh = run_pkgforge("verify", "--format", "json", "--no-cache", cwd=tmp_path)
    finally:
        mesh.chmod(0o644)
    assert cache_entry(tmp_path)["key"] != key  # seen: verified again, not replayed
    assert json.loads(second.stdout) == json.loads(fresh.stdout)
    assert second.returncode == fresh.returncode
