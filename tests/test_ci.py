"""pkgforge in CI: the colcon verb, generated workflows, pre-commit, the README recipe, the cache."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from importlib import resources
from pathlib import Path

import jsonschema
import pytest
import yaml
from conftest import MAINTAINER, SCRIPTS, colcon, edit, hand_made_install, line_of, run_command, run_pkgforge
from lxml import etree
from test_launch import jazzy_package, plain_colcon_build

REPO = Path(__file__).resolve().parent.parent
JUNIT_XSD = Path(__file__).parent / "schemas" / "junit.xsd"


@pytest.fixture(scope="module")
def built_workspace(tmp_path_factory) -> Path:
    """Three packages made by pkgforge new and one broken one, built by a plain colcon build."""
    workspace = tmp_path_factory.mktemp("ci")
    for name in ("a_description", "b_description", "c_description"):
        assert run_pkgforge("new", name, *MAINTAINER, "--destination", "src", cwd=workspace).returncode == 0
    broken = jazzy_package(workspace)
    edit(broken / "CMakeLists.txt", "launch urdf meshes rviz", "launch urdf meshes")
    plain_colcon_build(workspace)
    return workspace


@pytest.mark.slow
def test_colcon_verify_names_only_the_broken_package(built_workspace, tmp_path):
    junit = tmp_path / "junit.xml"
    result = colcon("verify", "--junit-xml", str(junit), cwd=built_workspace)
    assert result.returncode == 1, result.stdout + result.stderr
    located = re.findall(r"^(src/[^/]+)/\S+: PF\d{3} \[error\]", result.stdout, re.M)
    assert located and set(located) == {"src/small_turtle"}
    assert (
        result.stdout.splitlines()[-1]
        == "1 error, 0 warnings, 0 infos in 4 packages; launch: built-in engine (lyrical, the newest LTS)"
    )
    etree.XMLSchema(etree.parse(str(JUNIT_XSD))).assertValid(etree.parse(str(junit)))
    suites = etree.parse(str(junit)).getroot()
    assert sorted(s.get("name") for s in suites) == [
        "a_description",
        "b_description",
        "c_description",
        "small_turtle",
    ]


@pytest.mark.slow
def test_colcon_verify_skip_the_broken_package(built_workspace):
    result = colcon("verify", "--packages-skip", "small_turtle", cwd=built_workspace)
    assert result.returncode == 0, result.stdout + result.stderr
    assert (
        result.stdout.splitlines()[-1]
        == "0 errors, 0 warnings, 0 infos in 3 packages; launch: built-in engine (lyrical, the newest LTS)"
    )


@pytest.mark.slow
def test_colcon_verify_worker_memory(built_workspace):
    """The limit itself is tested through `pkgforge verify` (test_processes.py); same code path."""
    result = colcon(
        "verify", "--worker-memory", "512M", "--packages-select", "a_description", cwd=built_workspace
    )
    assert result.returncode == 0, result.stdout + result.stderr
    bad = colcon("verify", "--worker-memory", "lots", cwd=built_workspace)
    assert bad.returncode != 0 and "not a size such as 2G or 512M" in bad.stderr


def test_colcon_verify_distro_as_pkgforge_verify(tmp_path):
    """--distro: the same target distro as `pkgforge verify --distro`, before ROS_DISTRO."""
    import os

    assert (
        run_pkgforge("new", "rob_description", *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode
        == 0
    )
    package = tmp_path / "src" / "rob_description"
    manifest = package / "package.xml"
    edit(
        manifest,
        "  <exec_depend>joint_state_publisher</exec_depend>\n",
        "  <exec_depend>gazebo_ros</exec_depend>\n  <exec_depend>joint_state_publisher</exec_depend>\n",
    )
    hand_made_install(package)
    env = dict(os.environ, ROS_DISTRO="humble")  # gazebo_ros is released for humble, not jazzy

    def run(*command):
        return run_command(list(command), cwd=tmp_path, env=env)

    result = run(str(SCRIPTS / "colcon"), "verify", "--distro", "jazzy", "--format", "json")
    assert result.returncode == 1, result.stdout + result.stderr
    (diagnostic,) = [d for d in json.loads(result.stdout)["diagnostics"] if d["severity"] == "error"]
    assert (diagnostic["code"], diagnostic["path"], diagnostic["line"]) == (
        "PF108",
        "src/rob_description/package.xml",
        line_of(manifest, "<exec_depend>gazebo_ros<"),
    )
    assert "'gazebo_ros' is not released for jazzy (released for humble)" in diagnostic["message"]
    same = run(
        str(SCRIPTS / "pkgforge"),
        "verify",
        ".",
        "--install-base",
        "install",
        "--distro",
        "jazzy",
        "--format",
        "json",
        "--no-cache",
    )
    assert json.loads(same.stdout)["diagnostics"] == json.loads(result.stdout)["diagnostics"]
    # without --distro, ROS_DISTRO (humble) is the target: no error
    assert run(str(SCRIPTS / "colcon"), "verify").returncode == 0
    bad = run(str(SCRIPTS / "colcon"), "verify", "--distro", "jazy")
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.splitlines()[-1].endswith(
        "error: argument --distro: invalid choice: 'jazy' (choose from "
        "'humble', 'jazzy', 'kilted', 'lyrical', 'rolling')"
    )


def test_colcon_lists_the_verb(tmp_path):
    result = colcon("--help", cwd=tmp_path)
    assert re.search(r"^\s+verify\s+Check packages against their install tree", result.stdout, re.M)


# --- generated workflows ---------------------------------------------------------------------


def vendored_schema(name: str) -> dict:
    check_jsonschema = pytest.importorskip("check_jsonschema")
    return json.loads(
        resources.files(check_jsonschema).joinpath(f"builtin_schemas/vendor/{name}.json").read_text()
    )


@pytest.mark.parametrize("distro", ["humble", "jazzy"])
def test_github_workflow(tmp_path, distro):
    assert (
        run_pkgforge("new", "rob", *MAINTAINER, "--ci", "github", "--distro", distro, cwd=tmp_path).returncode
        == 0
    )
    workflow = yaml.safe_load((tmp_path / "rob" / ".github" / "workflows" / "pkgforge.yml").read_text())
    jsonschema.validate(workflow, vendored_schema("github-workflows"))
    job = workflow["jobs"]["verify"]
    assert job["container"] == f"ros:{distro}"
    runs = "\n".join(step.get("run", "") for step in job["steps"])
    assert f"source /opt/ros/{distro}/setup.bash" in runs
    assert "pkgforge build ." in runs
    assert "pkgforge verify . --install-base install --format github --junit-xml pkgforge-junit.xml" in runs
    assert any(step.get("uses", "").startswith("actions/upload-artifact") for step in job["steps"])
    assert (
        "--artifacts pkgforge-view" in runs and 'pkgforge-view/summary.md >> "$GITHUB_STEP_SUMMARY"' in runs
    )
    assert {"name": "pkgforge-view", "path": "pkgforge-view", "if-no-files-found": "ignore"} in [
        step.get("with") for step in job["steps"]
    ]


@pytest.mark.parametrize("distro", ["kilted", "lyrical", "rolling"])
def test_gitlab_pipeline(tmp_path, distro):
    assert (
        run_pkgforge("new", "rob", *MAINTAINER, "--ci", "gitlab", "--distro", distro, cwd=tmp_path).returncode
        == 0
    )
    pipeline = yaml.safe_load((tmp_path / "rob" / ".gitlab-ci.yml").read_text())
    jsonschema.validate(pipeline, vendored_schema("gitlab-ci"))
    job = pipeline["pkgforge"]
    assert job["image"] == f"ros:{distro}"
    script = "\n".join(job["script"])
    assert f". /opt/ros/{distro}/setup.sh" in script and "pkgforge build ." in script
    assert "pkgforge verify . --install-base install --junit-xml" in script
    assert job["artifacts"]["reports"]["junit"] == "pkgforge-junit.xml"
    assert '--artifacts "$CI_PROJECT_DIR/pkgforge-view"' in script
    assert job["artifacts"]["paths"] == ["pkgforge-view/"]


def test_generated_ci_installs_this_distribution_pinned(tmp_path):
    """`pip install pkgforge` would install an unrelated PyPI project: every generated CI file
    installs this project's own distribution, pinned to the version that wrote it."""
    try:
        import tomllib
    except ImportError:  # Python 3.10
        import tomli as tomllib

    from pkgforge import DISTRIBUTION, __version__

    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    assert (project["name"], project["version"]) == (DISTRIBUTION, __version__)
    assert DISTRIBUTION != "pkgforge"
    result = run_pkgforge("new", "rob", *MAINTAINER, "--ci", "github", "--ci", "gitlab", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    workflow = yaml.safe_load((tmp_path / "rob" / ".github" / "workflows" / "pkgforge.yml").read_text())
    pipeline = yaml.safe_load((tmp_path / "rob" / ".gitlab-ci.yml").read_text())
    lines = [
        line for step in workflow["jobs"]["verify"]["steps"] for line in step.get("run", "").splitlines()
    ]
    lines += pipeline["pkgforge"]["before_script"] + pipeline["pkgforge"]["script"]
    installs = [line for line in lines if "pip install" in line]
    # with the view extra: --artifacts renders the robot's pictures
    expected = f"/opt/pkgforge/bin/pip install '{DISTRIBUTION}[view]=={__version__}'"
    assert installs == [expected, expected]
    # the README shows the same lines, and no bare `pkgforge` install
    readme = (REPO / "README.md").read_text()
    assert expected in readme
    assert not re.search(r"pip install '?pkgforge\b", readme)


# --- pre-commit ------------------------------------------------------------------------------


def test_pre_commit_hook_definition():
    hooks = yaml.safe_load((REPO / ".pre-commit-hooks.yaml").read_text())
    hook = next(h for h in hooks if h["id"] == "pkgforge-verify")  # pkgforge-fix beside it: test_fix.py
    assert hook["id"] == "pkgforge-verify" and hook["language"] == "python" and hook["pass_filenames"]
    assert hook["entry"] == "pkgforge verify-files"
    assert re.search(hook["files"], "src/rob/launch/display.launch.py")
    assert re.search(hook["files"], "package.xml")


def test_verify_files_checks_only_the_touched_packages(tmp_path):
    broken = jazzy_package(tmp_path)
    edit(broken / "CMakeLists.txt", "launch urdf meshes rviz", "launch urdf meshes")
    assert (
        run_pkgforge("new", "good_description", *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode
        == 0
    )
    clean = run_pkgforge("verify-files", "src/good_description/package.xml", "README.md", cwd=tmp_path)
    assert clean.returncode == 0 and clean.stdout == ""
    dirty = run_pkgforge("verify-files", "src/small_turtle/launch/display.launch.py", cwd=tmp_path)
    assert dirty.returncode == 1
    assert dirty.stdout.startswith("src/small_turtle/launch/display.launch.py:14: PF302 [error]")


# --- the README's plain-shell recipe, end to end ---------------------------------------------


@pytest.mark.slow
def test_readme_plain_shell_recipe(tmp_path):
    readme = (REPO / "README.md").read_text()
    block = re.search(r"### Plain shell.*?```sh\n(.*?)```", readme, re.S).group(1)
    lines = [line for line in block.splitlines() if line.strip()]
    assert lines[0].startswith("python3 -m venv .venv && .venv/bin/pip install 'ros-pkgforge[ament]'")
    for name in ("a_description", "b_description"):
        assert run_pkgforge("new", name, *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode == 0
    # the install line is what this test environment already did; the rest runs as written
    (tmp_path / ".venv").symlink_to(Path(sys.prefix))
    for line in lines[1:]:
        result = subprocess.run(
            ["bash", "-c", line], cwd=tmp_path, capture_output=True, text=True, timeout=600
        )
        assert result.returncode == 0, f"{line}\n{result.stdout}{result.stderr}"
    etree.XMLSchema(etree.parse(str(JUNIT_XSD))).assertValid(
        etree.parse(str(tmp_path / "pkgforge-junit.xml"))
    )


# --- the cache -------------------------------------------------------------------------------


def entries(workspace: Path) -> dict[str, int]:
    folder = workspace / "build" / "pkgforge-cache"
    return {p.name: p.stat().st_mtime_ns for p in folder.glob("*.json") if p.name != "digests.json"}


def verify_json(workspace: Path, *args: str) -> tuple[int, list]:
    result = run_pkgforge("verify", "--format", "json", *args, cwd=workspace)
    assert result.returncode in (0, 1), result.stderr
    return result.returncode, sorted(
        (d["code"], d["path"], d["line"]) for d in json.loads(result.stdout)["diagnostics"]
    )


def test_cache_reuses_unchanged_packages_and_sees_every_change(tmp_path):
    package = jazzy_package(tmp_path)
    assert (
        run_pkgforge("new", "other_description", *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode
        == 0
    )
    first = verify_json(tmp_path)
    stored = entries(tmp_path)
    assert first == (0, []) and len(stored) == 2
    assert verify_json(tmp_path) == first
    assert entries(tmp_path) == stored  # nothing re-verified, nothing rewritten

    cmake = package / "CMakeLists.txt"
    edit(cmake, "launch urdf meshes rviz", "launch urdf meshes")
    launch = package / "launch" / "display.launch.py"
    assert verify_json(tmp_path) == (
        1,
        [("PF302", "src/small_turtle/launch/display.launch.py", line_of(launch, "rviz_config_path ="))],
    )
    changed = entries(tmp_path)
    assert [name for name in changed if changed[name] != stored[name]] != []
    assert sum(changed[name] != stored[name] for name in changed) == 1  # only small_turtle again


def test_unchanged_workspace_is_answered_whole_and_an_edit_keeping_size_and_mtime_is_seen(tmp_path):
    """The workspace entry (one fingerprint of every file's size, mtime, ctime and mode) answers an
    unchanged re-run; an edit that keeps the file's size and puts its mtime back still changes its
    ctime, so the next run verifies again and reports what the edit broke."""
    package = jazzy_package(tmp_path)
    assert (
        run_pkgforge("new", "other_description", *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode
        == 0
    )
    assert verify_json(tmp_path) == (0, [])
    whole = tmp_path / "build" / "pkgforge-cache" / "workspace.whole"
    assert whole.is_file()
    stored = entries(tmp_path)
    assert verify_json(tmp_path) == (0, [])
    assert entries(tmp_path) == stored

    cmake = package / "CMakeLists.txt"
    before = cmake.stat()
    text = cmake.read_text()
    assert "launch urdf meshes rviz" in text
    cmake.write_text(text.replace("launch urdf meshes rviz", "launch urdf meshes     "))
    os.utime(cmake, ns=(before.st_atime_ns, before.st_mtime_ns))
    assert (cmake.stat().st_size, cmake.stat().st_mtime_ns) == (before.st_size, before.st_mtime_ns)
    launch = package / "launch" / "display.launch.py"
    broken = (
        1,
        [("PF302", "src/small_turtle/launch/display.launch.py", line_of(launch, "rviz_config_path ="))],
    )
    assert verify_json(tmp_path) == broken
    assert verify_json(tmp_path) == broken  # answered whole again, with the new result


def test_cache_follows_files_of_other_packages(tmp_path):
    """A model including a file of another package is re-verified when that file changes."""
    for name in ("base_description", "rob_description"):
        assert run_pkgforge("new", name, *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode == 0
    rob = tmp_path / "src" / "rob_description"
    edit(
        rob / "urdf" / "rob_description.urdf.xacro",
        '  <xacro:include filename="$(find rob_description)/urdf/macros.xacro"/>\n',
        '  <xacro:include filename="$(find rob_description)/urdf/macros.xacro"/>\n'
        '  <xacro:include filename="$(find base_description)/urdf/extra.xacro"/>\n',
    )
    edit(
        rob / "package.xml",
        "  <exec_depend>joint_state_publisher</exec_depend>\n",
        "  <exec_depend>base_description</exec_depend>\n  <exec_depend>joint_state_publisher</exec_depend>\n",
    )
    extra = tmp_path / "src" / "base_description" / "urdf" / "extra.xacro"
    extra.write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>\n')
    assert verify_json(tmp_path) == (0, [])
    extra.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="gone.xacro"/>\n</robot>\n'
    )
    status, found = verify_json(tmp_path)
    assert status == 1 and ("PF308", "src/base_description/urdf/extra.xacro", 2) in found


def test_two_runs_at_once_agree_and_leave_a_valid_cache(tmp_path):
    for name in ("a_description", "b_description", "c_description"):
        assert run_pkgforge("new", name, *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode == 0
    broken = jazzy_package(tmp_path)
    edit(broken / "CMakeLists.txt", "launch urdf meshes rviz", "launch urdf meshes")
    command = [sys.executable, "-m", "pkgforge", "verify", "--format", "json"]
    runs = [
        subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    outputs = [run.communicate(timeout=300) for run in runs]
    reports = [json.loads(out) for out, _ in outputs]
    assert [run.returncode for run in runs] == [1, 1]
    assert reports[0] == reports[1]
    for path in (tmp_path / "build" / "pkgforge-cache").glob("*.json"):
        json.loads(path.read_text())  # every entry whole
    assert verify_json(tmp_path)[1] == sorted(
        (d["code"], d["path"], d["line"]) for d in reports[0]["diagnostics"]
    )


def test_colcon_verify_names_its_options_as_pkgforge_verify_does():
    """Issue 30: every option `colcon verify` shares with `pkgforge verify` has the same name
    (--format, --select, --ignore, not --pkgforge-format ...)."""
    import re

    def options(*command: str) -> set[str]:
        result = run_command([*command, "--help"])
        assert result.returncode == 0, result.stderr
        return set(re.findall(r"(?<![\w-])--[a-z][a-z-]+", result.stdout))

    colcon_verify = options(str(SCRIPTS / "colcon"), "verify")
    pkgforge_verify = options(str(SCRIPTS / "pkgforge"), "verify")
    ours = colcon_verify - {
        o for o in colcon_verify if o.startswith(("--packages-", "--base-paths", "--paths"))
    }
    ours -= {"--help", "--log-base", "--log-level"}
    assert not {o for o in ours if o.startswith("--pkgforge-")}, ours
    assert ours - pkgforge_verify == set(), ours - pkgforge_verify
    assert {"--format", "--select", "--ignore", "--distro", "--junit-xml"} <= ours
