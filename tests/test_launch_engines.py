"""`pkgforge verify --launch-engine ros|builtin` end to end, with the real launch libraries of
humble and jazzy laid out as a ROS prefix (tests/ros_prefix.py)."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path

import pytest
from conftest import FIXTURES, MAINTAINER, copy_fixture, line_of, new_package, run_pkgforge, verify_report
from ros_prefix import DISTROS, make_prefix


@pytest.fixture(scope="module")
def prefixes(tmp_path_factory) -> dict[str, Path]:
    base = tmp_path_factory.mktemp("ros")
    out = {}
    for distro in DISTROS:
        prefix, reason = make_prefix(distro, base)
        if prefix is None:
            print(f"real launch engine tests skipped: {reason}")
            pytest.skip(f"no real ROS 2 launch library for {distro}: {reason}")
        out[distro] = prefix
    return out


def _workspace(base: Path, name: str) -> Path:
    """fixtures: seed000, seed001 and small_turtle's launch file in every format; patterns: issue
    10's patterns of real packages (pattern_bot); or the conformance package."""
    workspace = base / name
    (workspace / "src").mkdir(parents=True)
    if name == "patterns":
        copy_fixture("launch_patterns/pattern_bot", workspace)
    elif name == "fixtures":
        copy_fixture("seed000/rob_description", workspace)
        turtle = copy_fixture("seed001/small_turtle", workspace)
        for launch in sorted((FIXTURES / "launch").iterdir()):
            shutil.copy(launch, turtle / "launch" / f"formats_{launch.name}")
    else:
        package = workspace / "src" / "launch_conformance"
        shutil.copytree(FIXTURES / "launch_conformance", package)
        (package / "launch").mkdir()
        for launch in list(package.iterdir()):
            if ".launch." in launch.name:
                launch.rename(package / "launch" / launch.name)
    return workspace


@pytest.fixture(scope="module")
def reports(tmp_path_factory, prefixes) -> dict:
    """(workspace, engine) → the JSON report of `pkgforge verify`; each run once."""
    base = tmp_path_factory.mktemp("engines")
    out = {}
    for name in ("fixtures", "patterns", "conformance"):
        workspace = _workspace(base, name)
        for distro in DISTROS:  # each engine told the same target distro
            out[name, "builtin", distro] = verify_report(
                workspace, "--no-cache", "--distro", distro, "--launch-engine", "builtin"
            )[1]
            out[name, distro] = verify_report(
                workspace,
                "--no-cache",
                "--distro",
                distro,
                "--launch-engine",
                "ros",
                "--ros-prefix",
                str(prefixes[distro]),
            )[1]
        out[name] = workspace
    return out


def _diagnostics(report: dict) -> list[tuple]:
    return sorted((d["code"], d["path"], d["line"], d["message"]) for d in report["diagnostics"])


@pytest.mark.parametrize("name", ["fixtures", "patterns", "conformance"])
@pytest.mark.parametrize("distro", DISTROS)
def test_both_engines_report_the_same_diagnostics(reports, name, distro):
    builtin, ros = reports[name, "builtin", distro], reports[name, distro]
    assert (builtin["launch"]["engine"], builtin["launch"]["distro"], builtin["launch"]["from"]) == (
        "builtin",
        distro,
        "--distro",
    )
    assert ros["launch"] == {"engine": "ros", "distro": distro}
    assert _diagnostics(builtin), "the fixtures have findings to compare"
    assert _diagnostics(ros) == _diagnostics(builtin)


def test_the_real_engine_reports_what_only_ros_refuses(reports):
    """jazzy's launch_ros refuses a parameter it parses as YAML into a dict: the node fails, at its line."""
    launch = reports["conformance"] / "src" / "launch_conformance" / "launch" / "py_file_content.launch.py"
    found = [
        (d["code"], d["path"], d["line"])
        for d in reports["conformance", "jazzy"]["diagnostics"]
        if d["path"].endswith("py_file_content.launch.py")
    ]
    assert found == [
        ("PF301", "src/launch_conformance/launch/py_file_content.launch.py", line_of(launch, "Node(package="))
    ]


def _snapshot(*folders: Path) -> dict[str, str]:
    """Every file and folder under the folders, with a digest of each file's content."""
    out = {}
    for folder in folders:
        for root, dirs, files in os.walk(folder):
            for name in dirs:
                out[os.path.join(root, name)] = "dir"
            for name in files:
                path = os.path.join(root, name)
                with open(path, "rb") as handle:
                    out[path] = hashlib.sha1(handle.read()).hexdigest()
    return out


def test_the_real_engine_writes_nothing_of_the_users(tmp_path, prefixes):
    """Home, workspace and TMPDIR are as they were: logs and parameter files lived in pkgforge's
    temporary folders, which are gone."""
    workspace = _workspace(tmp_path, "fixtures")
    home, tmp = tmp_path / "home", tmp_path / "tmp"
    home.mkdir()
    tmp.mkdir()
    (home / ".bashrc").write_text("# a user's file\n")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "XDG_"))}
    env.update(HOME=str(home), TMPDIR=str(tmp))
    before = _snapshot(home, workspace, tmp)
    result = run_pkgforge(
        "verify",
        "--no-cache",
        "--launch-engine",
        "ros",
        "--ros-prefix",
        str(prefixes["jazzy"]),
        cwd=workspace,
        env=env,
    )
    assert result.returncode == 1, result.stdout + result.stderr  # the fixtures' findings
    assert result.stdout.splitlines()[-1].endswith("; launch: ROS 2 jazzy"), (
        result.stdout
    )  # the summary says so
    assert _snapshot(home, workspace, tmp) == before


def test_the_real_engine_reads_launch_yaml_within_pkgforge_s_bounds(tmp_path, prefixes):
    """issue 35: launch_yaml's yaml.safe_load is pkgforge's bounded reader in the worker too: an alias
    bomb, 50,000 nested brackets and an alias inside its own collection each name the bound and line"""
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "rob_description", "--launch-format", "yaml", "--distro", "jazzy")
    laughs = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"] + [
        f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 12)
    ]
    files = {
        "bomb.launch.yaml": "launch:\n- let:\n    name: laughs\n    value:\n"
        + "".join(f"      {line}\n" for line in laughs),
        "deep.launch.yaml": "launch:\n- let:\n    name: deep\n    value: "
        + "[" * 50_000
        + "]" * 50_000
        + "\n",
        "self.launch.yaml": "launch:\n- let: &l\n    name: x\n    value: [*l]\n",
    }
    for name, text in files.items():
        (package / "launch" / name).write_text(text)
    result = run_pkgforge(
        "verify", "--no-cache", "--format", "json", "--launch-engine", "ros", "--ros-prefix",
        str(prefixes["jazzy"]), cwd=tmp_path, timeout=240,
    )  # fmt: skip
    assert result.returncode == 1 and "Traceback" not in result.stderr, result.stdout + result.stderr
    messages = {  # the whole text: launch's "multiple exceptions" message runs past one line's 300
        d["path"].rsplit("/", 1)[-1]: d["detail"] or d["message"]
        for d in json.loads(result.stdout)["diagnostics"]
        if d["code"] == "PF301"
    }
    launch = package / "launch"
    for name, bound in [
        (
            "bomb.launch.yaml",
            f"its aliases expand to more than 1,000,000 nodes: pkgforge reads YAML up to that size (line {line_of(launch / 'bomb.launch.yaml', '&a5')})",
        ),
        ("deep.launch.yaml", "nested deeper than 500 levels: pkgforge reads YAML up to that depth (line 4)"),
        ("self.launch.yaml", "alias *l is inside the collection it names: expanding it never ends (line 4)"),
    ]:
        assert f"YAMLLimit: {bound}" in messages[name], messages


def test_engine_choice_errors_are_one_line(tmp_path):
    workspace = _workspace(tmp_path, "fixtures")
    env = {k: v for k, v in os.environ.items() if k not in ("AMENT_PREFIX_PATH", "PYTHONPATH")}
    result = run_pkgforge("verify", "--ros-prefix", str(tmp_path / "nowhere"), cwd=workspace, env=env)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [
        f"pkgforge: error: --ros-prefix {tmp_path / 'nowhere'}: no such folder"
    ]
    result = run_pkgforge("verify", "--ros-prefix", str(workspace), cwd=workspace, env=env)
    assert result.returncode == 2 and "holds no ROS 2 launch libraries" in result.stderr
    assert "Traceback" not in result.stderr


IRON_ON = """from launch import LaunchDescription
from launch.conditions import IfCondition
from launch.substitutions import EqualsSubstitution
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([Node(package="rviz2", executable="rviz2",
                                   condition=IfCondition(EqualsSubstitution("1", "1.0")))])
"""


def test_the_built_in_engine_follows_the_target_distro(tmp_path):
    """`verify --distro` is the built-in engine's distro: a name that exists from Iron on is an
    ImportError, as in ROS, under humble, and none under jazzy; the report says which distro ran."""
    workspace = tmp_path / "ws"
    (workspace / "src").mkdir(parents=True)
    package = new_package(workspace, "iron_bot", "--distro", "jazzy")
    launch = package / "launch" / "equals.launch.py"
    launch.write_text(IRON_ON)
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_DISTRO", "PKGFORGE_LAUNCH_DISTRO")}
    found = {}
    for distro in ("humble", "jazzy"):
        result = run_pkgforge(
            "verify",
            "--format",
            "json",
            "--distro",
            distro,
            "--launch-engine",
            "builtin",
            cwd=workspace,
            env=env,
        )
        assert "Traceback" not in result.stderr and result.returncode in (0, 1), result.stderr
        report = json.loads(result.stdout)
        assert report["launch"] == {
            "engine": "builtin",
            "distro": distro,
            "from": "--distro",
            "distros": [{"distro": distro, "from": "--distro", "packages": ["iron_bot"]}],
        }
        found[distro] = [
            (d["code"], d["path"], d["line"], d["message"])
            for d in report["diagnostics"]
            if d["path"].endswith("equals.launch.py")
        ]
    assert found["humble"] == [
        (
            "PF301",
            "src/iron_bot/launch/equals.launch.py",
            line_of(launch, "import EqualsSubstitution"),
            "loading equals.launch.py failed: ImportError: cannot import name "
            "'EqualsSubstitution' from 'launch.substitutions'",
        )
    ]
    assert found["jazzy"] == []


WORKFLOW_ON_AN_IMAGE = """\
on: [push]
jobs:
  build:
    runs-on: ubuntu-latest
    container: ros:{distro}-ros-base
    steps:
      - uses: actions/checkout@v4
"""

# ros-tooling's actions on a plain Ubuntu image: the distro is only action-ros-ci's input
WORKFLOW_OF_ACTION_ROS_CI = """\
on: [push, pull_request]
jobs:
  build:
    runs-on: ubuntu-latest
    container:
      image: ubuntu:jammy
    steps:
      - uses: ros-tooling/setup-ros@0.3.4
      - uses: ros-tooling/action-ros-ci@0.2.6
        with:
          target-ros2-distro: {distro}
"""


@pytest.mark.parametrize(
    "how", ["pkgforge.toml", "new --ci", "workflow image", "action-ros-ci", "new --distro"]
)
def test_the_project_s_own_files_choose_the_built_in_engine_s_distro(tmp_path, how):
    """Issue 30: the target distro written in the project (pkgforge.toml's [verify] distro, the CI
    file `new --ci` wrote, a workflow's ros:<distro> image or action-ros-ci's target-ros2-distro,
    the pkgforge.toml `new --distro` records) holds the built-in engine to that distro's launch API, as --distro does: a humble
    package's file that imports EqualsSubstitution fails; the summary line says where humble came
    from, and a run told --distro jazzy finds nothing."""
    workspace = tmp_path / "ws"
    (workspace / "src").mkdir(parents=True)
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_DISTRO", "PKGFORGE_LAUNCH_DISTRO")}
    options = {"new --ci": ["--distro", "humble", "--ci", "github"], "new --distro": ["--distro", "humble"]}
    result = run_pkgforge("new", "iron_bot", *MAINTAINER, *options.get(how, []), cwd=workspace, env=env)
    assert result.returncode == 0, result.stderr
    package = workspace / "src" / "iron_bot"
    if how == "new --ci":
        (package / "pkgforge.toml").unlink()  # the CI file alone says humble
    elif how == "pkgforge.toml":
        (workspace / "pkgforge.toml").write_text('[verify]\ndistro = "humble"\n')
    elif how in ("workflow image", "action-ros-ci"):
        workflow = WORKFLOW_ON_AN_IMAGE if how == "workflow image" else WORKFLOW_OF_ACTION_ROS_CI
        (package / ".github" / "workflows").mkdir(parents=True)
        (package / ".github" / "workflows" / "build.yml").write_text(workflow.format(distro="humble"))
    launch = package / "launch" / "equals.launch.py"
    launch.write_text(IRON_ON)
    source = "the CI files" if how in ("new --ci", "workflow image", "action-ros-ci") else "pkgforge.toml"
    text = run_pkgforge("verify", "--launch-engine", "builtin", "--no-cache", cwd=workspace, env=env)
    assert text.returncode == 1, text.stdout + text.stderr
    assert (
        f"src/iron_bot/launch/equals.launch.py:{line_of(launch, 'import EqualsSubstitution')}: PF301 [error] "
        "loading equals.launch.py failed: ImportError: cannot import name 'EqualsSubstitution' from "
        "'launch.substitutions' (launch-load-error)" in text.stdout.splitlines()
    )
    assert text.stdout.splitlines()[-1] == (
        f"1 error, 0 warnings, 0 infos in 1 package; launch: built-in engine (humble from {source})"
    )
    result = run_pkgforge("verify", "--format", "json", "--launch-engine", "builtin", cwd=workspace, env=env)
    report = json.loads(result.stdout)
    assert report["launch"] == {
        "engine": "builtin",
        "distro": "humble",
        "from": source,
        "distros": [{"distro": "humble", "from": source, "packages": ["iron_bot"]}],
    }
    told = run_pkgforge("verify", "--launch-engine", "builtin", "--distro", "jazzy", cwd=workspace, env=env)
    assert told.returncode == 0, told.stdout + told.stderr
    assert told.stdout.splitlines()[-1].endswith("launch: built-in engine (jazzy from --distro)")


def test_packages_of_a_workspace_each_follow_their_own_distro(tmp_path):
    """Two packages, one recorded for humble and one for jazzy, in one workspace: each launch
    file is evaluated under its own package's launch API (the jazzy one's import loads)."""
    workspace = tmp_path / "ws"
    (workspace / "src").mkdir(parents=True)
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_DISTRO", "PKGFORGE_LAUNCH_DISTRO")}
    for name, distro in (("old_bot", "humble"), ("new_bot", "jazzy")):
        result = run_pkgforge("new", name, *MAINTAINER, "--distro", distro, cwd=workspace, env=env)
        assert result.returncode == 0, result.stderr
        (workspace / "src" / name / "launch" / "equals.launch.py").write_text(IRON_ON)
    result = run_pkgforge("verify", "--format", "json", "--launch-engine", "builtin", cwd=workspace, env=env)
    report = json.loads(result.stdout)
    assert [(d["code"], d["path"]) for d in report["diagnostics"]] == [
        ("PF301", "src/old_bot/launch/equals.launch.py")
    ]
    assert report["launch"]["distro"] is None
    assert report["launch"]["distros"] == [
        {"distro": "jazzy", "from": "pkgforge.toml", "packages": ["new_bot"]},
        {"distro": "humble", "from": "pkgforge.toml", "packages": ["old_bot"]},
    ]
    text = run_pkgforge("verify", "--launch-engine", "builtin", cwd=workspace, env=env)
    assert text.stdout.splitlines()[-1].endswith(
        "launch: built-in engine (jazzy from pkgforge.toml; humble from pkgforge.toml)"
    )


DISTRO_BRANCH_WORKFLOW = """\
on:
  pull_request:
    branches: [{branch}]
  push:
    branches: [{branch}]
  schedule:
    - cron: '03 1 * * MON-FRI'
jobs:
  binary:
    uses: ros-controls/ros2_control_ci/.github/workflows/reusable-industrial-ci-with-cache.yml@master
    strategy:
      matrix:
        ROS_DISTRO: [{distro}]
    with:
      ros_distro: ${{{{ matrix.ROS_DISTRO }}}}
      ref_for_scheduled_build: {branch}
"""


def test_a_workflow_of_another_distro_s_branch_does_not_choose_the_launch_api(tmp_path):
    """Issue 30 (truth campaign: ros2_control_demos on master keeps humble-binary-build.yml, which
    runs for the humble branch): with the checkout on master, the workflows for the branch named
    after humble say nothing of the code here; rolling's does. A workflow for a branch not named
    after a distro (realsense-ros' ros2-development, from which its ros2-master comes) still does."""
    import subprocess

    workspace = tmp_path / "ws"
    (workspace / "src").mkdir(parents=True)
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_DISTRO", "PKGFORGE_LAUNCH_DISTRO")}
    result = run_pkgforge("new", "demo_bot", *MAINTAINER, cwd=workspace, env=env)
    assert result.returncode == 0, result.stderr
    package = workspace / "src" / "demo_bot"
    (package / "launch" / "equals.launch.py").write_text(IRON_ON)
    workflows = package / ".github" / "workflows"
    workflows.mkdir(parents=True)
    (workflows / "humble-binary-build.yml").write_text(
        DISTRO_BRANCH_WORKFLOW.format(branch="humble", distro="humble")
    )
    (workflows / "rolling-binary-build.yml").write_text(
        DISTRO_BRANCH_WORKFLOW.format(branch="master", distro="rolling")
    )
    subprocess.run(["git", "init", "-q", "-b", "master", str(package)], check=True)

    def verify() -> str:
        result = run_pkgforge("verify", "--launch-engine", "builtin", "--no-cache", cwd=workspace, env=env)
        assert result.returncode in (0, 1), result.stderr
        return result.stdout

    said = verify()
    assert "PF301" not in said and said.splitlines()[-1].endswith("(rolling from the CI files)"), said
    (workflows / "rolling-binary-build.yml").unlink()
    (workflows / "main.yml").write_text(
        DISTRO_BRANCH_WORKFLOW.format(branch="ros2-development", distro="humble")
    )
    said = verify()
    assert "equals.launch.py" in said and said.splitlines()[-1].endswith("(humble from the CI files)"), said
