"""Issue 11: no process outlives pkgforge; signals exit 128+N at once; worker limits are located
findings; a failed `verify --build` still reports; the cache keeps no machine-dependent answer.

Every test runs the real `pkgforge` on real launch files. Processes are found by a marker in
their environment (inherited from the pkgforge process the test starts), so other runs on the
same machine are never mistaken for ours.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest
from conftest import copy_fixture, line_of, run_pkgforge
from lxml import etree

MARKER = "PKGFORGE_TEST_MARKER"

# a launch file that starts a child, double-forks a setsid sleeper, then does `tail`
SPAWNING = """import os
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
"""


@pytest.fixture(scope="session")
def package(tmp_path_factory):
    """make(workspace, launch text, name): a package made by `pkgforge new` (once per session,
    then copied under other names) with the given display.launch.py."""
    workspace = tmp_path_factory.mktemp("template")
    result = run_pkgforge(
        "new", "tpl_pkg", "--maintainer-email", "t@example.com", "--destination", "src", cwd=workspace
    )
    assert result.returncode == 0, result.stderr
    template = workspace / "src" / "tpl_pkg"

    def make(workspace: Path, launch: str, name: str = "proc_pkg") -> Path:
        folder = workspace / "src" / name
        for source in sorted(template.rglob("*")):
            target = folder / str(source.relative_to(template)).replace("tpl_pkg", name)
            target.parent.mkdir(parents=True, exist_ok=True)
            if source.is_dir():
                target.mkdir(exist_ok=True)
            elif source.suffix == ".stl":
                shutil.copyfile(source, target)
            else:
                target.write_text(source.read_text().replace("tpl_pkg", name))
        (folder / "launch" / "display.launch.py").write_text(launch)
        return folder

    return make


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
    return subprocess.Popen(
        [sys.executable, "-m", "pkgforge", "verify", "--no-cache", *args],
        cwd=workspace,
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def wait_for(marker: str, text: str, process: subprocess.Popen, limit: float = 120) -> None:
    deadline = time.monotonic() + limit
    while not any(text in cmdline for _, cmdline in marked(marker)):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, f"{text} never started"
        time.sleep(0.05)


# --- signals ----------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["SIGINT", "SIGTERM", "SIGHUP"])
def test_signal_kills_every_process_and_exits_128_plus_signal(tmp_path, name, package):
    package(tmp_path, SPAWNING.format(tail="    time.sleep(600)"))
    marker = uuid.uuid4().hex
    process = start_verify(tmp_path, marker)
    wait_for(marker, "sleep 7772", process)
    assert any("pkgforge.evaluation" in cmdline for _, cmdline in marked(marker))
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


def test_double_forked_setsid_child_is_gone_after_verify(tmp_path, package):
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


# --- limits, and a worker that dies: one workspace, one verify ---------------------------------


def launch_file(body: str, imports: str = "") -> str:
    return (
        f"{imports}from launch import LaunchDescription\n\n\ndef generate_launch_description():\n{body}"
        "    return LaunchDescription([])\n"
    )


LIMITS = {
    "l_memory": launch_file("    everything = bytearray(6 * 2**30)\n"),
    "l_files": launch_file("    files = [open(__file__) for _ in range(5000)]\n"),
    # the limits a launch file finds when it starts
    "l_rlimits": launch_file(
        "    raise RuntimeError(repr([resource.getrlimit(getattr(resource, kind))[0]\n"
        "                             for kind in ('RLIMIT_AS', 'RLIMIT_NOFILE', 'RLIMIT_CPU')]))\n",
        "import resource\n\n",
    ),
    "l_wall": launch_file("    time.sleep(600)\n", "import time\n\n"),
    # reads its stdin: waits until the wall limit, as a sleep does, and never reads the request the
    # parent queued behind it in the same worker (another package's file, then wrongly timed out)
    "l_stdin": launch_file("    sys.stdin.readline()\n", "import sys\n\n"),
    "l_killed": launch_file("    os.kill(os.getpid(), signal.SIGKILL)\n", "import os\nimport signal\n\n"),
}
TIMEOUT = 4
# the CPU limit (SIGXCPU), verified on its own with a wall-time limit it cannot reach first: the
# file lowers its own soft limit to 1-2 s of CPU from now
CPU_BOUND = launch_file(
    "    used = resource.getrusage(resource.RUSAGE_SELF)\n"
    "    soft, hard = resource.getrlimit(resource.RLIMIT_CPU)\n"
    "    resource.setrlimit(resource.RLIMIT_CPU, (int(used.ru_utime + used.ru_stime) + 2, hard))\n"
    "    while True: sum(range(1000))\n",
    "import resource\n\n",
)


@pytest.fixture(scope="module")
def limits_workspace(tmp_path_factory, package) -> tuple[Path, dict[str, dict]]:
    """(workspace, package → its one error), verified once with --launch-timeout TIMEOUT."""
    workspace = tmp_path_factory.mktemp("limits")
    for name, launch in LIMITS.items():
        package(workspace, launch, name)
    result = run_pkgforge(
        "verify", "--format", "json", "--no-cache", "--launch-timeout", str(TIMEOUT), cwd=workspace
    )
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stderr
    errors: dict[str, list] = {}
    for diagnostic in json.loads(result.stdout)["diagnostics"]:
        if diagnostic["severity"] == "error":
            errors.setdefault(diagnostic["package"], []).append(diagnostic)
    assert sorted(errors) == sorted(LIMITS)
    assert all(len(found) == 1 for found in errors.values()), errors
    return workspace, {name: found[0] for name, found in errors.items()}


def at(workspace: Path, name: str, text: str) -> tuple[str, str, int]:
    launch = workspace / "src" / name / "launch" / "display.launch.py"
    return "PF301", f"src/{name}/launch/display.launch.py", line_of(launch, text)


def located(diagnostic: dict) -> tuple[str, str, int]:
    return diagnostic["code"], diagnostic["path"], diagnostic["line"]


def test_6_gib_allocation_is_a_located_memory_limit(limits_workspace):
    workspace, errors = limits_workspace
    assert located(errors["l_memory"]) == at(workspace, "l_memory", "bytearray")
    assert "2 GiB memory limit" in errors["l_memory"]["message"]
    assert "--worker-memory" in errors["l_memory"]["message"]


def test_worker_memory_option(limits_workspace):
    workspace, _ = limits_workspace
    result = run_pkgforge(
        "verify", "src/l_memory", "--format", "json", "--no-cache", "--worker-memory", "512M", cwd=workspace
    )
    assert result.returncode == 1
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert "512 MiB memory limit" in diagnostic["message"]
    bad = run_pkgforge("verify", "--worker-memory", "lots", cwd=workspace)
    assert bad.returncode == 2
    assert "Invalid value for '--worker-memory'" in bad.stderr and "2G or 512M" in bad.stderr


def test_open_files_limit_is_located(limits_workspace):
    workspace, errors = limits_workspace
    assert located(errors["l_files"]) == at(workspace, "l_files", "open(__file__)")
    assert "1024 open files" in errors["l_files"]["message"]


def test_limits_are_set_before_the_launch_file_runs(limits_workspace):
    _, errors = limits_workspace
    memory, files, cpu = json.loads(
        errors["l_rlimits"]["message"].rsplit("RuntimeError: ", 1)[1].replace("'", '"')
    )
    assert (memory, files) == (2 * 2**30, 1024)
    assert TIMEOUT <= cpu <= TIMEOUT + 2  # this file's share: the CPU time used so far + the time limit


def test_cpu_time_limit_is_located(tmp_path, package):
    package(tmp_path, CPU_BOUND)
    result = run_pkgforge("verify", "--format", "json", "--no-cache", "--launch-timeout", "120", cwd=tmp_path)
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert located(diagnostic) == at(tmp_path, "proc_pkg", "while True: sum")
    assert "CPU time limit" in diagnostic["message"] and "--launch-timeout" in diagnostic["message"]


def test_wall_time_limit_is_located(limits_workspace):
    workspace, errors = limits_workspace
    assert located(errors["l_wall"]) == at(workspace, "l_wall", "time.sleep(600)")
    assert f"still running after the {TIMEOUT} s limit" in errors["l_wall"]["message"]


def test_launch_file_reading_stdin_waits_for_the_wall_limit_and_takes_no_request(limits_workspace):
    workspace, errors = limits_workspace
    assert located(errors["l_stdin"]) == at(workspace, "l_stdin", "sys.stdin.readline()")
    assert f"still running after the {TIMEOUT} s limit" in errors["l_stdin"]["message"]


def test_worker_that_kills_itself_is_reported_and_pkgforge_goes_on(limits_workspace):
    _, errors = limits_workspace
    assert errors["l_killed"]["path"] == "src/l_killed/launch/display.launch.py"
    assert "SIGKILL" in errors["l_killed"]["message"]


# --- verify --build on a failing build ---------------------------------------------------------


@pytest.mark.triggers("PF902")
def test_failing_build_still_reports_everything(tmp_path):
    """Two packages that fail differently: each gets build-failed, the static checks still run,
    and every report file asked for is written."""
    copy_fixture("seed001/small_turtle", tmp_path)  # install(DIRECTORY worlds models) that do not exist
    rob = copy_fixture("seed000/rob_description", tmp_path)
    fatal = rob / "CMakeLists.txt"
    fatal.write_text(
        fatal.read_text().replace(
            "find_package(ament_cmake REQUIRED)",
            'find_package(ament_cmake REQUIRED)\nmessage(FATAL_ERROR "not today")',
        )
    )
    static = run_pkgforge("verify", "--format", "json", "--select", "PF1,PF2,PF9", cwd=tmp_path)
    result = run_pkgforge(
        "verify",
        "--build",
        "--format",
        "json",
        "--output",
        "report.json",
        "--junit-xml",
        "out/junit.xml",
        cwd=tmp_path,
    )
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stderr
    report = json.loads((tmp_path / "report.json").read_text())
    failed = {d["package"]: d for d in report["diagnostics"] if d["code"] == "PF902"}
    assert sorted(failed) == ["robot_description", "small_turtle"]
    # every static diagnostic is there
    static_found = {
        (d["code"], d["path"], d["line"], d["message"]) for d in json.loads(static.stdout)["diagnostics"]
    }
    assert static_found and static_found <= {
        (d["code"], d["path"], d["line"], d["message"]) for d in report["diagnostics"]
    }
    cmake = tmp_path / "src" / "small_turtle" / "CMakeLists.txt"
    assert ("PF201", "src/small_turtle/CMakeLists.txt", line_of(cmake, "worlds")) in {
        (d["code"], d["path"], d["line"]) for d in report["diagnostics"]
    }
    # located: at the CMake error in the package's own file, else at its build file
    assert (failed["robot_description"]["path"], failed["robot_description"]["line"]) == (
        "src/rob_description/CMakeLists.txt",
        line_of(fatal, "FATAL_ERROR"),
    )
    assert "not today" in failed["robot_description"]["message"]
    assert (failed["small_turtle"]["path"], failed["small_turtle"]["line"]) == (
        "src/small_turtle/CMakeLists.txt",
        None,
    )
    log = (
        tmp_path / "build" / "pkgforge-verify" / "log" / "latest_build" / "small_turtle" / "stdout_stderr.log"
    )
    # (the whole text is the detail when the message is cut to 300 characters: issue 30)
    assert (
        str(log) in (failed["small_turtle"]["detail"] or failed["small_turtle"]["message"]) and log.is_file()
    )
    assert "file INSTALL cannot find" in (
        failed["small_turtle"]["detail"] or failed["small_turtle"]["message"]
    )
    assert failed["small_turtle"]["name"] == "build-failed" and failed["small_turtle"]["severity"] == "error"
    junit = etree.parse(str(tmp_path / "out" / "junit.xml"))
    etree.XMLSchema(etree.parse(str(Path(__file__).parent / "schemas" / "junit.xsd"))).assertValid(junit)
    failures = junit.findall(".//testcase/failure/..")
    assert "PF902 build-failed" in {case.get("name") for case in failures}


# --- the cache --------------------------------------------------------------------------------

# each misbehaves only while the flag file exists: what the machine's state decides
FLAGGED = {
    "timeout": "    while os.path.exists(FLAG):\n        pass\n",
    "crash": "    if os.path.exists(FLAG):\n        os._exit(3)\n",
    "killed": "    if os.path.exists(FLAG):\n        os.kill(os.getpid(), 9)\n",
    "memory": "    if os.path.exists(FLAG):\n        bytearray(6 * 2**30)\n",
}


def test_machine_dependent_results_are_not_cached(tmp_path, package):
    flag = tmp_path / "flag"
    flag.touch()
    for case, body in FLAGGED.items():
        package(
            tmp_path,
            f"import os\n\nfrom launch import LaunchDescription\n\nFLAG = {str(flag)!r}\n\n\n"
            f"def generate_launch_description():\n{body}    return LaunchDescription([])\n",
            f"c_{case}",
        )
    package(tmp_path, launch_file(""), "c_clean")
    first = run_pkgforge("verify", "--format", "json", "--launch-timeout", "2", cwd=tmp_path)
    assert first.returncode == 1, first.stderr
    errors = sorted(d["package"] for d in json.loads(first.stdout)["diagnostics"] if d["severity"] == "error")
    assert errors == sorted(f"c_{case}" for case in FLAGGED)
    # only the clean package's result was kept
    assert [entry["report"]["name"] for entry in cache_entries(tmp_path)] == ["c_clean"]
    flag.unlink()  # the machine is fine again; no file of the packages changed
    second = run_pkgforge("verify", "--format", "json", "--launch-timeout", "2", cwd=tmp_path)
    assert second.returncode == 0, second.stdout
    assert not [d for d in json.loads(second.stdout)["diagnostics"] if d["severity"] == "error"]


def cache_entries(workspace: Path) -> list[dict]:
    return [
        json.loads(p.read_text())
        for p in (workspace / "build" / "pkgforge-cache").glob("*.json")
        if p.name != "digests.json"
    ]


def cache_entry(workspace: Path) -> dict:
    (entry,) = cache_entries(workspace)
    return entry


def test_file_mode_is_part_of_the_fingerprint(tmp_path, package):
    folder = package(tmp_path, launch_file(""))
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


# --- the time limit and argument combinations: the defaults decide, the others run while time remains

BRANCHING = """import time
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration

NAMES = ["use_sim", "use_rviz", "use_gui", "lidar", "camera", "imu"]


def on_branch(context):
    if any(LaunchConfiguration(name).perform(context) == "true" for name in NAMES):
{slow}
    return []


def generate_launch_description():
{load}    return LaunchDescription([DeclareLaunchArgument(name, default_value="false") for name in NAMES]
                             + [OpaqueFunction(function=on_branch)])
"""
COMBINATIONS = {
    # every combination past the defaults takes a second: some fit in the limit, the rest do not
    "b_slow": BRANCHING.format(slow="        time.sleep(1.0)  # slow", load=""),
    # a combination past the defaults never ends: stopped, and said, but no error
    "b_endless": BRANCHING.format(slow="        while True: pass  # endless", load=""),
    # the defaults never end: the time limit's error, at the line, as ever
    "b_load": BRANCHING.format(slow="        pass", load="    time.sleep(600)  # at load\n"),
}


@pytest.mark.triggers("PF318")
@pytest.mark.parametrize("engine", ["builtin", "ros"])
def test_combinations_past_the_defaults_never_make_a_time_error(tmp_path, package, engine):
    """Both engines branch through branches.evaluate_branches under the same budget."""
    options = ["--launch-engine", "builtin"]
    if engine == "ros":
        from ros_prefix import make_prefix

        prefix, reason = make_prefix("jazzy", tmp_path / "ros")
        if prefix is None:
            pytest.skip(f"no real ROS 2 launch library: {reason}")
        options = ["--launch-engine", "ros", "--ros-prefix", str(prefix)]
    for name, launch in COMBINATIONS.items():
        package(tmp_path, launch, name)
    result = run_pkgforge(
        "verify", "--format", "json", "--launch-timeout", str(TIMEOUT), *options, cwd=tmp_path
    )
    assert "Traceback" not in result.stderr
    found = {}
    for diagnostic in json.loads(result.stdout)["diagnostics"]:
        if diagnostic["code"] in ("PF301", "PF318"):
            found.setdefault(diagnostic["package"], []).append(diagnostic)
    path = "src/{0}/launch/display.launch.py".format
    launch = tmp_path / "src" / "{}" / "launch" / "display.launch.py"
    # the defaults never end: PF301 at the line it was running, nothing about combinations
    (load,) = found["b_load"]
    assert located(load) == (
        "PF301",
        path("b_load"),
        line_of(Path(str(launch).format("b_load")), "# at load"),
    )
    # a branch that never ends: the defaults' records stand, the branch is said (info) where it stopped
    (endless,) = found["b_endless"]
    assert located(endless) == (
        "PF318",
        path("b_endless"),
        line_of(Path(str(launch).format("b_endless")), "# endless"),
    )
    assert endless["severity"] == "info"
    # the defaults and MAX_BRANCHES (16) others, the first (every argument true) never ending
    assert f"1 of 17 argument combinations evaluated within the {TIMEOUT} s limit" in endless["message"]
    assert (
        "16 not checked" in endless["message"]
        and "use_sim:=true was stopped at this line" in endless["message"]
    )
    # slow branches: as many as fit, counted; no error
    (slow,) = found["b_slow"]
    assert slow["code"] == "PF318" and slow["path"] == path("b_slow")
    evaluated, planned = map(
        int, re.search(r"(\d+) of (\d+) argument combinations", slow["message"]).groups()
    )
    assert planned == 17 and 1 <= evaluated < planned
    assert f"{planned - evaluated} not checked" in slow["message"]
    assert result.returncode == 1  # b_load's error only
    assert not [
        d
        for d in json.loads(result.stdout)["diagnostics"]
        if d["severity"] == "error" and d["package"] != "b_load"
    ], result.stdout
    # machine-dependent (what fits depends on the machine's load): never cached
    assert not [
        entry
        for entry in cache_entries(tmp_path)
        if entry["report"]["name"] in ("b_slow", "b_endless", "b_load")
    ]


# a file that finishes, slowed by a busy machine: two competitors pinned to its CPU give it a third
# of it (at most), so its half second of CPU time takes 1.5 s or more of wall time, past the 1 s limit
CONTENDED = launch_file(
    """    cpu = min(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {cpu})
    for _ in range(2):
        if os.fork() == 0:
            end = time.monotonic() + 20
            while time.monotonic() < end:
                pass
            os._exit(0)
    start = time.process_time()
    while time.process_time() - start < 0.5:  # half a second of CPU time
        pass
""",
    "import os\nimport time\n\n",
)


def test_time_waiting_for_a_busy_cpu_does_not_count_against_the_limit(tmp_path, package):
    """The wall limit grows by what the worker waited for a CPU (Linux run_delay), to at most
    MAX_LOAD_FACTOR times it: a slow machine does not turn a finishing file into an error, while
    a sleep or a blocking call (no CPU wanted, no wait) still stops at the limit itself."""
    from pkgforge.sandbox.processes import run_delay

    if run_delay() is None:
        pytest.skip("this kernel does not report run_delay (/proc/self/task/*/schedstat)")
    package(tmp_path, CONTENDED, "contended")
    result = run_pkgforge("verify", "--format", "json", "--no-cache", "--launch-timeout", "1", cwd=tmp_path)
    assert "Traceback" not in result.stderr
    assert not [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "PF301"], result.stdout
