"""How findings reach the person (issue 30, part A): paths a terminal and a CI service open, every
finding at its file and line, one short line per message (the rest in the JSON's `detail`), one
diagnostic per cause and file, and the report options (--statistics, -q, per-file ignores)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from conftest import FIXTURES, MAINTAINER, edit, line_of, new_package, run_pkgforge, verify_report

TEMPORARY = re.compile(r"pkgforge-tree-")
RVIZ_OUT = ("launch meshes rviz urdf", "launch meshes urdf")  # the scaffold's install line without rviz


def diagnostics(report: dict, code: str) -> list[tuple[str, str, int | None, str]]:
    return [
        (d["severity"], d["path"], d["line"], d["message"])
        for d in report["diagnostics"]
        if d["code"] == code
    ]


def scaffold(workspace: Path) -> Path:
    """`pkgforge new rob_description` in the workspace's src/."""
    (workspace / "src").mkdir(exist_ok=True)
    return new_package(workspace, "rob_description")


# --- where a finding is ---------------------------------------------------------------------


def test_text_report_paths_are_relative_to_the_current_folder_else_absolute(tmp_path):
    """`pkgforge verify src/rob` prints src/rob/launch/..., as ruff and gcc do, so the terminal
    opens it; from a folder the file is not under, the absolute path."""
    package = scaffold(tmp_path)
    edit(package / "CMakeLists.txt", *RVIZ_OUT)
    launch = package / "launch" / "display.launch.py"
    line = line_of(launch, "'rviz', 'display.rviz'")
    result = run_pkgforge("verify", "src/rob_description", "--no-cache", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    assert f"src/rob_description/launch/display.launch.py:{line}:" in result.stdout
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    result = run_pkgforge("verify", tmp_path / "src" / "rob_description", "--no-cache", cwd=elsewhere)
    assert result.stdout.startswith(f"{launch}:{line}:"), result.stdout


def _ci_commands(text: str) -> list[str]:
    """A CI script's commands as this machine runs them: this pkgforge, no apt, pip or ROS setup."""
    skipped = ("apt-get", "pip install", "python3 -m venv", "source /opt/ros", ". /opt/ros")
    lines = [line for line in text.replace("\\\n", " ").splitlines() if line.strip()]
    python = f"{sys.executable} -m pkgforge"
    return [
        line.replace("/opt/pkgforge/bin/pkgforge", python)
        for line in lines
        if not any(word in line for word in skipped)
    ]


def _repository(tmp_path: Path) -> tuple[Path, set[str]]:
    """A package made by `new --ci github --ci gitlab`, with a defect, committed in its own git
    repository: (the repository, the files git tracks)."""
    result = run_pkgforge("new", "rob", *MAINTAINER, "--ci", "github", "--ci", "gitlab", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    repository = tmp_path / "rob"
    edit(repository / "CMakeLists.txt", *RVIZ_OUT)
    git = ["git", "-c", "user.name=t", "-c", "user.email=t@example.com", "-C", str(repository)]
    for command in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "rob"]):
        subprocess.run([*git, *command], check=True, capture_output=True)
    tracked = subprocess.run([*git, "ls-files"], check=True, capture_output=True, text=True).stdout.split()
    return repository, set(tracked)


@pytest.mark.slow
def test_generated_github_workflow_annotates_paths_of_the_repository(tmp_path):
    """The workflow checks the repository out into src/rob of the workspace it verifies: GitHub
    matches an annotation's file against the repository's paths, so file= is launch/..., not
    src/rob/launch/... (and SARIF's artifact is relative to that repository too)."""
    repository, tracked = _repository(tmp_path)
    workspace = tmp_path / "github"
    shutil.copytree(repository, workspace / "src" / "rob", symlinks=True)  # actions/checkout, path: src/rob
    workflow = yaml.safe_load((repository / ".github" / "workflows" / "pkgforge.yml").read_text())
    steps = {step.get("name"): step for step in workflow["jobs"]["verify"]["steps"]}
    assert workflow["jobs"]["verify"]["steps"][0]["with"]["path"] == "src/rob"
    printed = ""
    for name in ("Build", "Verify"):
        for command in _ci_commands(steps[name]["run"]):
            done = subprocess.run(
                ["bash", "-c", command], cwd=workspace, capture_output=True, text=True, timeout=600
            )
            assert "Traceback" not in done.stderr, done.stderr
            printed += done.stdout
    annotations = re.findall(r"^::(error|warning|notice) file=([^,]+),line=(\d+)", printed, re.M)
    assert annotations, printed
    assert {file for _, file, _ in annotations} <= tracked, annotations
    line = line_of(repository / "launch" / "display.launch.py", "'rviz', 'display.rviz'")
    assert ("error", "launch/display.launch.py", str(line)) in annotations
    junit = (workspace / "pkgforge-junit.xml").read_text()
    assert f"launch/display.launch.py:{line}:" in junit and "src/rob/launch" not in junit
    sarif = run_pkgforge("verify", ".", "--install-base", "install", "--format", "sarif", cwd=workspace)
    run = json.loads(sarif.stdout)["runs"][0]
    places = [r["locations"][0]["physicalLocation"]["artifactLocation"] for r in run["results"]]
    assert {p["uri"] for p in places} <= tracked
    assert {run["originalUriBaseIds"][p["uriBaseId"]]["uri"] for p in places} == {
        (workspace / "src" / "rob").as_uri() + "/"
    }


@pytest.mark.slow
def test_generated_gitlab_pipeline_reports_paths_of_the_repository(tmp_path):
    """The pipeline copies the clone into /tmp/ws/src/rob: GitLab's code quality report and the
    JUnit report name the files as the repository has them."""
    repository, tracked = _repository(tmp_path)
    job = yaml.safe_load((repository / ".gitlab-ci.yml").read_text())["pkgforge"]
    scratch = tmp_path / "ws"
    # (a job's lines run in one shell, in the clone: $CI_PROJECT_DIR)
    script = "\n".join(_ci_commands("\n".join(job["before_script"] + job["script"])))
    assert "cd /tmp/ws" in script
    env = dict(os.environ, CI_PROJECT_DIR=str(repository))
    done = subprocess.run(
        ["bash", "-ec", script.replace("/tmp/ws", str(scratch))],
        cwd=repository,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert "Traceback" not in done.stderr and done.returncode == 1, done.stdout + done.stderr
    issues = json.loads((repository / "gl-code-quality-report.json").read_text())
    paths = {issue["location"]["path"] for issue in issues}
    assert paths and paths <= tracked, paths
    assert "launch/display.launch.py" in paths
    assert "src/rob/" not in (repository / "pkgforge-junit.xml").read_text()


def test_a_model_finding_in_a_xacro_macro_is_at_the_macros_line(tmp_path):
    """A link named by a template (`${prefix}_finger`, made by a macro) is found at the line that
    writes it, not at the model without a line."""
    package = scaffold(tmp_path)
    model = package / "urdf" / "gripper.urdf.xacro"
    model.write_text(GRIPPER)
    _, report = verify_report(tmp_path, "--no-cache")
    assert diagnostics(report, "PF601") == [
        (
            "error",
            "src/rob_description/urdf/gripper.urdf.xacro",
            line_of(model, 'name="${prefix}_finger"'),
            "link 'left_finger' has mass 0.0",
        )
    ]


def test_a_model_finding_reached_by_several_packages_launch_files_is_one_at_its_line(tmp_path):
    """husky: husky_description's link without <inertial> was said four times, once by each
    package whose launch file runs xacro on that model (at each launch line); it is one cause,
    at the link's line, said once, by the package whose file that is."""
    description = scaffold(tmp_path)
    bringup = new_package(tmp_path, "rob_bringup")
    model = description / "urdf" / "rob_description.urdf.xacro"
    edit(model, '<xacro:box_inertial x="${arm_width}" y="${arm_width}" z="${arm_length}" mass="0.2"/>', "")
    edit(
        bringup / "launch" / "display.launch.py",
        "FindPackageShare('rob_bringup')",
        "FindPackageShare('rob_description')",
    )
    launch = bringup / "launch" / "display.launch.py"
    edit(launch, "'urdf/rob_bringup.urdf.xacro'", "'urdf/rob_description.urdf.xacro'")
    # (with an argument of its own: a model of its own, not the one the description package shows)
    edit(launch, "LaunchConfiguration('model')])", "LaunchConfiguration('model'), ' name:=rob'])")
    edit(
        bringup / "package.xml",
        "<exec_depend>",
        "<exec_depend>rob_description</exec_depend>\n  <exec_depend>",
    )
    _, report = verify_report(tmp_path, "--no-cache")
    found = [(d["package"], d["path"], d["line"]) for d in report["diagnostics"] if d["code"] == "PF603"]
    assert found == [
        (
            "rob_description",
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, '<link name="arm_link">'),
        )
    ]


GRIPPER = """<?xml version="1.0"?>
<robot name="gripper" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="finger" params="prefix">
    <link name="${prefix}_finger">
      <inertial><mass value="0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    </link>
  </xacro:macro>
  <link name="palm"/>
  <xacro:finger prefix="left"/>
  <joint name="left_joint" type="fixed"><parent link="palm"/><child link="left_finger"/></joint>
</robot>
"""


PARTS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="load_arm" params="arm">
    <xacro:include filename="$(find rob_description)/urdf/arms/${arm}_macro.xacro"/>
  </xacro:macro>
</robot>
"""
TWIN = """<?xml version="1.0"?>
<robot name="twin" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find rob_description)/urdf/parts.xacro"/>
  <link name="base_link"/>
  <xacro:load_arm arm="absent"/>
</robot>
"""
CALL = """<?xml version="1.0"?>
<robot name="call" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm" params="prefix">
    <link name="${prefix}base"/>
  </xacro:macro>
  <xacro:arm
    prefix="a_"
    sim="true"/>
</robot>
"""


def test_a_xacro_error_is_at_the_line_of_its_culprit(tmp_path):
    """kortex: a macro call over several lines passing a parameter the macro does not declare (at
    that attribute's line); an include whose filename a macro builds from its parameters, in a
    file the model includes (at that include); xacro's errno text said once."""
    package = scaffold(tmp_path)
    urdf = package / "urdf"
    (urdf / "parts.xacro").write_text(PARTS)
    (urdf / "twin.urdf.xacro").write_text(TWIN)
    (urdf / "call.urdf.xacro").write_text(CALL)
    _, report = verify_report(tmp_path, "--no-cache", "--select", "PF308")
    assert diagnostics(report, "PF308") == [
        (
            "error",
            "src/rob_description/urdf/call.urdf.xacro",
            line_of(urdf / "call.urdf.xacro", 'sim="true"'),
            'xacro call.urdf.xacro: Invalid parameter "sim"',
        ),
        (
            "error",
            "src/rob_description/urdf/parts.xacro",
            line_of(urdf / "parts.xacro", "<xacro:include"),
            "xacro twin.urdf.xacro: No such file or directory: urdf/arms/absent_macro.xacro",
        ),
    ]


READS_ABSENT_FILE = """import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription


def generate_launch_description():
    path = os.path.join(get_package_share_directory('rob_description'), 'config', 'absent.yaml')
    with open(path) as handle:
        handle.read()
    return LaunchDescription([])
"""


@pytest.mark.slow
def test_no_path_of_pkgforges_tree_in_a_message_with_an_install_base(tmp_path):
    """With --install-base (what CI runs), a launch error naming a file of the install tree names
    the user's install folder, never pkgforge's /dev/shm/pkgforge-tree-... copy of it."""
    package = scaffold(tmp_path)
    (package / "launch" / "reads.launch.py").write_text(READS_ABSENT_FILE)
    assert run_pkgforge("build", ".", cwd=tmp_path).returncode == 0
    _, report = verify_report(tmp_path, "--install-base", "install", "--no-cache")
    found = diagnostics(report, "PF301")
    absent = tmp_path / "install" / "share" / "rob_description" / "config" / "absent.yaml"
    assert found == [
        (
            "error",
            "src/rob_description/launch/reads.launch.py",
            line_of(package / "launch" / "reads.launch.py", "with open"),
            f"loading reads.launch.py failed: FileNotFoundError: [Errno 2] No such file or directory: '{absent}'",
        )
    ]
    assert not TEMPORARY.search(json.dumps(report))


# --- how much there is to read --------------------------------------------------------------

LOUD_LAUNCH = """from launch import LaunchDescription


def generate_launch_description():
    lines = ['robot_description: <robot name="r"> ' + 'x' * 90 for _ in range(60)]
    raise RuntimeError('\\n'.join(lines))
    return LaunchDescription([])
"""


def test_a_long_multiline_error_is_one_short_line_with_the_whole_text_in_detail(tmp_path):
    package = scaffold(tmp_path)
    launch = package / "launch" / "loud.launch.py"
    launch.write_text(LOUD_LAUNCH)
    _, report = verify_report(tmp_path, "--no-cache")
    [diagnostic] = [d for d in report["diagnostics"] if d["code"] == "PF301"]
    assert (diagnostic["path"], diagnostic["line"]) == (
        "src/rob_description/launch/loud.launch.py",
        line_of(launch, "raise RuntimeError"),
    )
    message = diagnostic["message"]
    assert len(message) <= 300 and "\n" not in message, message
    assert message.startswith("loading loud.launch.py failed: RuntimeError: robot_description: <robot")
    # its beginning and its end, the middle left out and said so
    assert " ... " in message and message.endswith("x (full text: --format json)")
    assert diagnostic["detail"].count("x" * 90) == 60
    text = run_pkgforge("verify", ".", "--no-cache", cwd=tmp_path).stdout
    assert max(len(line) for line in text.splitlines()) < 400


def _arm(joints: int, ros2_control: list[str] = ()) -> str:
    links = "".join(
        f"""
  <link name="l{i}"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j{i}" type="revolute">
    <parent link="l{i - 1}"/><child link="l{i}"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="0"/>
  </joint>"""
        for i in range(1, joints + 1)
    )
    control = "".join(
        f'\n    <joint name="{name}"><command_interface name="position"/></joint>' for name in ros2_control
    )
    block = f'\n  <ros2_control name="arm" type="system">{control}\n  </ros2_control>' if ros2_control else ""
    return f'<?xml version="1.0"?>\n<robot name="arm">\n  <link name="l0"/>{links}{block}\n</robot>\n'


def limit_lines(model: Path) -> list[int]:
    return [n for n, line in enumerate(model.read_text().splitlines(), start=1) if "<limit " in line]


def test_velocity_zero_on_many_joints_is_one_diagnostic_naming_them(tmp_path):
    package = scaffold(tmp_path)
    model = package / "urdf" / "arm.urdf"
    model.write_text(_arm(6))
    _, report = verify_report(tmp_path, "--no-cache")
    lines = limit_lines(model)
    [(severity, path, line, message)] = diagnostics(report, "PF605")
    assert (severity, path, line) == ("warning", "src/rob_description/urdf/arm.urdf", lines[0])
    assert message == (
        '6 joints have velocity="0" (nothing here enforces it: MoveIt reads 0 as no limit and RViz '
        "ignores it; a simulator or ros2_control would stop them): j1, j2, j3, j4, j5, j6 "
        f"(lines {', '.join(map(str, lines))})"
    )
    [diagnostic] = [d for d in report["diagnostics"] if d["code"] == "PF605"]
    assert (
        diagnostic["detail"]
        .splitlines()[1]
        .startswith(f"line {lines[1]}: revolute joint 'j2': velocity=\"0\"")
    )


def test_velocity_zero_is_an_error_only_on_the_joints_something_enforces(tmp_path):
    """A <ros2_control> block holds the joints it names to their limits (an error, one for those
    joints); the others only a simulator would (a warning); a workspace that merely declares a
    simulator package enforces nothing on this model."""
    package = scaffold(tmp_path)
    edit(package / "package.xml", "<export>", "<exec_depend>gazebo_ros</exec_depend>\n  <export>")
    model = package / "urdf" / "arm.urdf"
    model.write_text(_arm(4, ros2_control=["j1", "j2"]))
    _, report = verify_report(tmp_path, "--no-cache", "--select", "PF605")
    lines = limit_lines(model)
    assert [(s, line, m.split(":")[0]) for s, _, line, m in diagnostics(report, "PF605")] == [
        (
            "error",
            lines[0],
            '2 joints have velocity="0", and <ros2_control> holds them to it (they cannot move)',
        ),
        ("warning", lines[2], '2 joints have velocity="0" (nothing here enforces it'),
    ]


def test_effort_zero_is_an_error_only_where_the_effort_is_commanded_or_simulated(tmp_path):
    """abb_ros2: position-controlled arms with effort="0" (as ROS-Industrial writes it) under a
    <ros2_control> of real or mock hardware: ros2_control's limiters clamp only an effort command,
    so nothing holds those joints to it (a warning); a joint whose effort is commanded, or that
    Gazebo's hardware simulates, cannot move (an error)."""
    package = scaffold(tmp_path)
    model = package / "urdf" / "arm.urdf"
    text = _arm(3, ros2_control=["j1", "j2", "j3"]).replace(
        'effort="10" velocity="0"', 'effort="0" velocity="1"'
    )
    text = text.replace(
        '<joint name="j3"><command_interface name="position"/>',
        '<joint name="j3"><command_interface name="effort"/>',
    )
    model.write_text(text)
    _, report = verify_report(tmp_path, "--no-cache", "--select", "PF605")
    lines = limit_lines(model)
    assert [(s, line, m.split(":")[0]) for s, _, line, m in diagnostics(report, "PF605")] == [
        ("warning", lines[0], '2 joints have effort="0" (nothing here enforces it'),
        ("error", lines[2], "revolute joint 'j3'"),
    ]
    model.write_text(
        text.replace(
            '<ros2_control name="arm" type="system">',
            '<ros2_control name="arm" type="system">\n    <hardware><plugin>gz_ros2_control/GazeboSimSystem</plugin></hardware>',
        )
    )
    _, report = verify_report(tmp_path, "--no-cache", "--select", "PF605")
    assert [(s, m.split(":")[0]) for s, _, _, m in diagnostics(report, "PF605")] == [
        ("error", '3 joints have effort="0", and <ros2_control> holds them to it (they cannot move)')
    ]


def test_a_missing_mesh_of_a_visual_and_a_collision_is_one_diagnostic(tmp_path):
    package = scaffold(tmp_path)
    model = package / "urdf" / "tool.urdf.xacro"
    model.write_text(TOOL)
    _, report = verify_report(tmp_path, "--no-cache")
    line = line_of(model, "package://rob_description/meshes/${name}.stl")
    assert diagnostics(report, "PF402") == [
        (
            "error",
            "src/rob_description/urdf/tool.urdf.xacro",
            line,
            "2 mesh files do not exist: package://rob_description/meshes/left.stl, "
            "package://rob_description/meshes/right.stl",
        )
    ]


TOOL = """<?xml version="1.0"?>
<robot name="tool" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="jaw" params="name">
    <link name="${name}">
      <visual><geometry><mesh filename="package://rob_description/meshes/${name}.stl"/></geometry></visual>
      <collision><geometry><mesh filename="package://rob_description/meshes/${name}.stl"/></geometry></collision>
      <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    </link>
  </xacro:macro>
  <link name="palm"/>
  <xacro:jaw name="left"/>
  <xacro:jaw name="right"/>
  <joint name="left_joint" type="fixed"><parent link="palm"/><child link="left"/></joint>
  <joint name="right_joint" type="fixed"><parent link="palm"/><child link="right"/></joint>
</robot>
"""

NODES_OF_ONE_PACKAGE = """from launch import LaunchDescription
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    share = FindPackageShare('no_such_package_xyz')
    return LaunchDescription([
        Node(package='no_such_package_xyz', executable='a', parameters=[share]),
        Node(package='no_such_package_xyz', executable='b'),
    ])
"""


def test_one_unknown_package_named_by_many_nodes_is_one_diagnostic(tmp_path):
    package = scaffold(tmp_path)
    launch = package / "launch" / "nodes.launch.py"
    launch.write_text(NODES_OF_ONE_PACKAGE)
    _, report = verify_report(tmp_path, "--no-cache")
    found = diagnostics(report, "PF304")
    assert len(found) == 1, found
    severity, path, line, message = found[0]
    assert (severity, path) == ("error", "src/rob_description/launch/nodes.launch.py")
    lines = [
        line_of(launch, "FindPackageShare('no"),
        line_of(launch, "executable='a'"),
        line_of(launch, "executable='b'"),
    ]
    assert line == lines[0]
    assert message == (
        "package 'no_such_package_xyz' (FindPackageShare, Node package) is not in the workspace, not "
        f"declared in package.xml and released in no ROS 2 distro (lines {', '.join(map(str, lines))})"
    )


# --- report options -------------------------------------------------------------------------


@pytest.fixture
def arm_workspace(tmp_path: Path) -> Path:
    """A package whose launch file misses its rviz folder (PF302) and whose model has a zero
    velocity (PF605) and a duplicated dependency (PF106)."""
    package = scaffold(tmp_path)
    edit(package / "CMakeLists.txt", *RVIZ_OUT)
    (package / "urdf" / "arm.urdf").write_text(_arm(2))
    edit(package / "package.xml", "<export>", "<exec_depend>xacro</exec_depend>\n  <export>")
    return tmp_path


def test_statistics_prints_one_line_per_code(arm_workspace):
    result = run_pkgforge("verify", ".", "--no-cache", "--statistics", cwd=arm_workspace)
    lines = result.stdout.splitlines()
    assert {re.split(r"\s+", line.strip())[1] for line in lines[:-1]} >= {"PF302", "PF605", "PF106"}
    assert all(re.fullmatch(r"\d+  PF\d{3}  [a-z0-9-]+ \[[a-z, ]+\]", line) for line in lines[:-1]), lines
    assert "hint:" not in result.stdout and lines[-1].startswith(("1 error", "2 error"))
    refused = run_pkgforge("verify", ".", "--statistics", "--format", "json", cwd=arm_workspace)
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1


def test_quiet_prints_the_findings_and_the_summary_only(arm_workspace):
    full = run_pkgforge("verify", ".", "--no-cache", cwd=arm_workspace).stdout.splitlines()
    quiet = run_pkgforge("verify", ".", "-q", cwd=arm_workspace).stdout.splitlines()
    assert quiet == [line for line in full if not line.startswith("    hint: ")]
    assert len(quiet) < len(full)


def test_per_file_ignores_silence_checks_in_the_files_a_glob_matches(arm_workspace):
    (arm_workspace / "pkgforge.toml").write_text(
        '[verify.per-file-ignores]\n"*.urdf" = ["joint-limit-invalid"]\n"src/*/launch/**" = ["PF3"]\n'
    )
    _, report = verify_report(arm_workspace, "--no-cache")
    codes = {d["code"] for d in report["diagnostics"]}
    assert "PF106" in codes and not codes & {"PF605", "PF302"}
    (arm_workspace / "pkgforge.toml").write_text(
        '[verify.per-file-ignores]\n"*.urdf" = ["joint-limit-invalidd"]\n'
    )
    result = run_pkgforge("verify", ".", cwd=arm_workspace)
    assert result.returncode == 2
    assert "pkgforge.toml:2: " in result.stderr and "(did you mean joint-limit-invalid" in result.stderr


@pytest.mark.parametrize("option", ["--select", "--ignore"])
def test_a_misspelt_check_name_gets_did_you_mean(arm_workspace, option):
    result = run_pkgforge("verify", ".", option, "uninstaled-reference", cwd=arm_workspace)
    assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
    assert "(did you mean uninstalled-reference" in result.stderr


def test_fix_diff_prints_the_diff_and_one_line_of_counts(arm_workspace):
    result = run_pkgforge("fix", ".", "--diff", cwd=arm_workspace)
    assert result.stdout.startswith("--- ") and "+++ " in result.stdout, result.stdout
    assert re.fullmatch(r"would fix \d+ problem\(s\) in \d+ file\(s\)(; .*)?\n", result.stderr), result.stderr


# --- every fixture ----------------------------------------------------------------------------


@pytest.mark.slow
def test_every_message_of_every_fixture_is_one_short_line_without_pkgforges_paths(tmp_path):
    """Over every package of tests/fixtures in one workspace: each message one line of at most 300
    characters, no message, hint or detail naming pkgforge's temporary tree."""
    for manifest in sorted(FIXTURES.rglob("package.xml")):
        folder = manifest.parent
        if any((parent / "package.xml").is_file() for parent in folder.parents if FIXTURES in parent.parents):
            continue  # a nested package: copied with the one holding it
        shutil.copytree(folder, tmp_path / "src" / folder.name)
    _, report = verify_report(tmp_path, "--no-cache")
    assert len(report["diagnostics"]) > 100
    for d in report["diagnostics"]:
        where = f"{d['path']}:{d['line']} {d['code']}"
        assert len(d["message"]) <= 300, where
        assert "\n" not in d["message"] and "\r" not in d["message"], where
        assert "\n" not in d["hint"], where
        for text in (d["message"], d["hint"], d["detail"] or "", d["path"]):
            assert not TEMPORARY.search(text), (where, text)
