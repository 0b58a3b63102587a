"""Issue 34: no false error from what pkgforge cannot read statically.

1. An ament_python package whose setup.py computes data_files (a helper with a loop over
   os.walk, as real description packages write it) is evaluated as colcon evaluates it
   (setuptools' setup(), stopped before any command, in the sandbox), so its install is predicted
   and another package's lookup into its share folder finds what it installs. When setup.py cannot
   run here, its install is unknown, never empty: lookups into it are infos, not file errors, and
   its own launch files and models are still evaluated, against its source.
2. A path with command-line flags (`world.sdf -r` as ros_gz_sim's gz_args) is split as its
   consumer splits it before its file part is checked.
"""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import pytest
from conftest import MAINTAINER, line_of, run_pkgforge, verify_report
from ros_prefix import make_prefix

# a helper of several statements over os.walk: what the static reader cannot evaluate
SETUP_PY = """\
import os

from setuptools import setup

package_name = 'arm_description'
IMPORTS


def share_files(folders):
    \"\"\"(destination, files) for every file below each folder, subfolders kept.\"\"\"
    out = []
    for folder in folders:
        for root, _, files in os.walk(folder):
            if files:
                out.append((os.path.join('share', package_name, root), [os.path.join(root, f) for f in files]))
    return out


setup(
    name=package_name,
    version='0.0.0',
    packages=[],
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ] + share_files(FOLDERS),
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='Test Maintainer',
    maintainer_email='test@example.com',
    description='an arm',
    license='Apache-2.0',
)
"""
FOLDERS = "['launch', 'meshes', 'rviz', 'urdf']"

# another package's launch file that processes the first one's model with xacro's module
ROBOT_LAUNCH = """\
import os

import xacro
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    doc = xacro.process_file(
        os.path.join(get_package_share_directory('arm_description'), 'urdf', 'MODEL')
    )
    return LaunchDescription([
        Node(
            package='robot_state_publisher',
            executable='robot_state_publisher',
            parameters=[{'robot_description': doc.toxml()}],
        ),
    ])
"""


@pytest.fixture(scope="module")
def template(tmp_path_factory) -> Path:
    """arm_description (ament_python) and arm_bringup (ament_cmake, depending on it), made once."""
    workspace = tmp_path_factory.mktemp("template")
    (workspace / "src").mkdir()
    for name, options in (("arm_description", ["--build-type", "ament_python"]), ("arm_bringup", [])):
        result = run_pkgforge("new", name, *MAINTAINER, *options, cwd=workspace)
        assert result.returncode == 0, result.stderr
    manifest = workspace / "src" / "arm_bringup" / "package.xml"
    manifest.write_text(
        manifest.read_text().replace(
            "<exec_depend>rviz2</exec_depend>",
            "<exec_depend>rviz2</exec_depend>\n  <exec_depend>arm_description</exec_depend>",
        )
    )
    cmake = workspace / "src" / "arm_bringup" / "CMakeLists.txt"
    cmake.write_text(
        cmake.read_text().replace(
            "DIRECTORY launch meshes rviz urdf", "DIRECTORY launch meshes rviz urdf worlds"
        )
    )
    (workspace / "src" / "arm_bringup" / "worlds").mkdir()
    (workspace / "src" / "arm_bringup" / "worlds" / "world.sdf").write_text(
        '<?xml version="1.0"?>\n<sdf version="1.8"><world name="w"/></sdf>\n'
    )
    return workspace


def workspace_of(
    template: Path, tmp_path: Path, *, imports: str = "", folders: str = FOLDERS, model: str = ""
) -> Path:
    workspace = tmp_path / "ws"
    shutil.copytree(template, workspace)
    description = workspace / "src" / "arm_description"
    (description / "setup.py").write_text(SETUP_PY.replace("IMPORTS", imports).replace("FOLDERS", folders))
    launch = ROBOT_LAUNCH.replace("MODEL", model or "arm_description.urdf.xacro")
    (workspace / "src" / "arm_bringup" / "launch" / "robot.launch.py").write_text(launch)
    return workspace


def found(report: dict) -> list[tuple[str, str, str, int | None]]:
    return sorted((d["code"], d["severity"], d["path"], d["line"]) for d in report["diagnostics"])


def by_code(report: dict, code: str) -> list[dict]:
    return [d for d in report["diagnostics"] if d["code"] == code]


def fingerprint(folder: Path) -> dict[str, str]:
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and "build" not in p.relative_to(folder).parts
    }


# --- 1. setup.py evaluated ------------------------------------------------------------------------


def test_computed_data_files_are_installed_as_setuptools_computes_them(template, tmp_path):
    """Before: PF206 for the helper, and arm_bringup's lookup of the model a false xacro-error."""
    workspace = workspace_of(template, tmp_path)
    status, report = verify_report(workspace, "--no-cache")
    assert status == 0, report["diagnostics"]
    assert found(report) == []


def test_the_evaluated_package_s_own_launch_files_and_models_are_checked(template, tmp_path):
    """Its launch file is installed (the helper installs launch/), so it is evaluated: its defect
    is found. Before, nothing of the package was evaluated and this was missed."""
    workspace = workspace_of(template, tmp_path)
    launch = workspace / "src" / "arm_description" / "launch" / "display.launch.py"
    launch.write_text(launch.read_text().replace("'display.rviz'", "'missing.rviz'"))
    status, report = verify_report(workspace, "--no-cache")
    assert status == 1
    assert [(d["code"], d["path"], d["line"]) for d in report["diagnostics"]] == [
        ("PF303", "src/arm_description/launch/display.launch.py", line_of(launch, "missing.rviz"))
    ]


def test_computed_data_files_that_leave_urdf_out_are_still_an_error(template, tmp_path):
    """The nearest case that must still be reported: the helper really installs no urdf/."""
    workspace = workspace_of(template, tmp_path, folders="['launch', 'meshes', 'rviz']")
    status, report = verify_report(workspace, "--no-cache")
    assert status == 1
    launch = workspace / "src" / "arm_bringup" / "launch" / "robot.launch.py"
    xacro = by_code(report, "PF308")
    assert [(d["severity"], d["path"], d["line"]) for d in xacro] == [
        ("error", "src/arm_bringup/launch/robot.launch.py", line_of(launch, "xacro.process_file"))
    ]
    assert "arm_description.urdf.xacro" in xacro[0]["message"]
    # the package's own launch file refers to urdf/, which its data_files leave out
    display = workspace / "src" / "arm_description" / "launch" / "display.launch.py"
    assert [(d["severity"], d["path"], d["line"]) for d in by_code(report, "PF302")] == [
        ("error", "src/arm_description/launch/display.launch.py", line_of(display, "urdf/arm_description"))
    ]
    assert not by_code(report, "PF206")


@pytest.mark.triggers("PF206", "PF319")
def test_a_setup_py_that_cannot_run_here_leaves_its_package_unknown_not_empty(template, tmp_path):
    """setup.py imports a module this machine lacks: the failure is said at its line (PF206), and
    the package's install is unknown: another package's lookup of a file its source has works, and
    of a file it does not have is an info naming the package, never a file error."""
    workspace = workspace_of(template, tmp_path, imports="import not_installed_here")
    setup_py = workspace / "src" / "arm_description" / "setup.py"
    status, report = verify_report(workspace, "--no-cache")
    assert status == 0, report["diagnostics"]
    failure = [d for d in by_code(report, "PF206") if "could not be evaluated" in d["message"]]
    assert [(d["severity"], d["path"], d["line"]) for d in failure] == [
        ("info", "src/arm_description/setup.py", line_of(setup_py, "import not_installed_here"))
    ]
    assert "ModuleNotFoundError: No module named 'not_installed_here'" in failure[0]["message"]
    assert not by_code(report, "PF319") and not by_code(report, "PF308")

    # a file the package's source does not have: not known to be missing (its install is unknown)
    launch = workspace / "src" / "arm_bringup" / "launch" / "robot.launch.py"
    launch.write_text(launch.read_text().replace("arm_description.urdf.xacro", "other.urdf.xacro"))
    status, report = verify_report(workspace, "--no-cache")
    assert status == 0, report["diagnostics"]
    unknown = by_code(report, "PF319")
    assert [(d["severity"], d["path"], d["line"]) for d in unknown] == [
        ("info", "src/arm_bringup/launch/robot.launch.py", line_of(launch, "xacro.process_file"))
    ]
    assert "share/arm_description/urdf/other.urdf.xacro" in unknown[0]["message"]
    assert (
        f"arm_description's install cannot be predicted (setup.py:{line_of(setup_py, '] + share_files')})"
        in (unknown[0]["message"])
    )


def test_an_unknown_package_s_own_models_are_still_evaluated_against_its_source(template, tmp_path):
    """setup.py cannot run here, yet the package's model is processed from its source: its defect
    is an error, at its line."""
    workspace = workspace_of(template, tmp_path, imports="import not_installed_here")
    model = workspace / "src" / "arm_description" / "urdf" / "arm_description.urdf.xacro"
    model.write_text(
        model.read_text().replace("</robot>", '  <link name="${undefined_property}"/>\n</robot>')
    )
    status, report = verify_report(workspace, "--no-cache")
    assert status == 1
    errors = [d for d in report["diagnostics"] if d["severity"] == "error"]
    assert {(d["code"], d["path"]) for d in errors} >= {
        ("PF308", "src/arm_description/urdf/arm_description.urdf.xacro")
    }
    assert all("undefined_property" in d["message"] for d in errors if d["code"] == "PF308")


def test_evaluating_setup_py_writes_nothing(template, tmp_path):
    """A setup.py that writes a file while it runs: refused (verify writes nothing of the user's),
    and the refusal is where its evaluation stopped."""
    workspace = workspace_of(
        template,
        tmp_path,
        imports="open(os.path.join(os.path.dirname(__file__) or '.', 'made.txt'), 'w').write('x')",
    )
    setup_py = workspace / "src" / "arm_description" / "setup.py"
    before = fingerprint(workspace)
    status, report = verify_report(workspace, "--no-cache")
    assert fingerprint(workspace) == before
    assert not (workspace / "src" / "arm_description" / "made.txt").exists()
    failure = [d for d in by_code(report, "PF206") if "could not be evaluated" in d["message"]]
    assert [(d["path"], d["line"]) for d in failure] == [
        ("src/arm_description/setup.py", line_of(setup_py, "made.txt"))
    ]
    assert "PermissionError" in failure[0]["message"]
    assert status == 0, report["diagnostics"]


def test_a_literal_setup_py_is_not_run(template, tmp_path):
    """The fast path: a setup.py the static reader reads whole is never run (a module it imports
    that is missing here does not matter)."""
    workspace = workspace_of(template, tmp_path)
    scaffold = (template / "src" / "arm_description" / "setup.py").read_text()  # (pkgforge new's)
    (workspace / "src" / "arm_description" / "setup.py").write_text("import not_installed_here\n" + scaffold)
    status, report = verify_report(workspace, "--no-cache")
    assert status == 0 and found(report) == []


# --- 2. command lines split as their consumer splits them ------------------------------------------------

SIM_LAUNCH = """\
from launch import LaunchDescription
from launch.actions import ExecuteProcess, IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import PathJoinSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    share = FindPackageShare('arm_bringup')
    gz = IncludeLaunchDescription(
        PythonLaunchDescriptionSource(
            PathJoinSubstitution([FindPackageShare('ros_gz_sim'), 'launch', 'gz_sim.launch.py'])
        ),
        launch_arguments={'gz_args': PathJoinSubstitution([share, 'worlds', 'GZ_WORLD'])}.items(),
    )
    shell = ExecuteProcess(
        cmd=['gz', 'sim', PathJoinSubstitution([share, 'worlds', 'SHELL_WORLD'])], shell=True
    )
    return LaunchDescription([gz, shell])
"""


@pytest.fixture(scope="module")
def engines(tmp_path_factory) -> list[list[str]]:
    """The built-in engine, and the real launch libraries (jazzy) when this machine has them."""
    out = [["--launch-engine", "builtin", "--distro", "jazzy"]]
    prefix, _ = make_prefix("jazzy", tmp_path_factory.mktemp("ros"))
    if prefix is not None:
        out.append(["--launch-engine", "ros", "--distro", "jazzy", "--ros-prefix", str(prefix)])
    return out


def sim_workspace(template: Path, tmp_path: Path, gz_world: str, shell_world: str) -> tuple[Path, Path]:
    workspace = workspace_of(template, tmp_path)
    launch = workspace / "src" / "arm_bringup" / "launch" / "sim.launch.py"
    launch.write_text(SIM_LAUNCH.replace("GZ_WORLD", gz_world).replace("SHELL_WORLD", shell_world))
    manifest = workspace / "src" / "arm_bringup" / "package.xml"
    manifest.write_text(
        manifest.read_text().replace(
            "<exec_depend>rviz2</exec_depend>",
            "<exec_depend>rviz2</exec_depend>\n  <exec_depend>ros_gz_sim</exec_depend>",
        )
    )
    return workspace, launch


def test_gz_args_with_flags_is_split_as_gz_sim_splits_it(template, tmp_path, engines):
    """ros_gz_sim's gz_sim.launch.py gives gz_args to `gz sim` through a shell: the file is
    world.sdf, -r a flag. Before: PF303 'world.sdf -r does not exist'."""
    workspace, _ = sim_workspace(template, tmp_path, "world.sdf -r", "world.sdf -r -v 4")
    for engine in engines:
        status, report = verify_report(workspace, "--no-cache", *engine)
        assert status == 0 and found(report) == [], (engine, report["diagnostics"])


@pytest.mark.triggers("PF303")
def test_a_gz_args_world_that_does_not_exist_is_still_an_error(template, tmp_path, engines):
    """The nearest case that must still be reported: the file part, after the split, is missing."""
    workspace, launch = sim_workspace(template, tmp_path, "wrold.sdf -r", "world.sdf -r")
    for engine in engines:
        status, report = verify_report(workspace, "--no-cache", *engine)
        assert status == 1
        missing = by_code(report, "PF303")
        assert [(d["severity"], d["path"], d["line"]) for d in missing] == [
            ("error", "src/arm_bringup/launch/sim.launch.py", line_of(launch, "wrold.sdf"))
        ], engine
        assert missing[0]["message"].startswith("share/arm_bringup/worlds/wrold.sdf does not exist")


def test_a_process_without_a_shell_gets_the_path_as_one_word(template, tmp_path, engines):
    """ExecuteProcess without shell=True passes each cmd item as one argument: `world.sdf -r` is
    then one file name, which does not exist: still an error."""
    workspace, launch = sim_workspace(template, tmp_path, "world.sdf -r", "world.sdf -v 4")
    launch.write_text(launch.read_text().replace(", shell=True", ""))
    for engine in engines:
        status, report = verify_report(workspace, "--no-cache", *engine)
        assert status == 1
        assert [(d["code"], d["line"]) for d in report["diagnostics"]] == [
            ("PF303", line_of(launch, "cmd=['gz', 'sim'"))
        ], engine
        assert "world.sdf -v 4 does not exist" in report["diagnostics"][0]["message"]


# --- found by the truth campaign ----------------------------------------------------------------

XACRO_IN_A_SUBPROCESS = """\
import subprocess

from launch import LaunchDescription
from launch.actions import OpaqueFunction
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def launch_setup(context):
    model = FindPackageShare('arm_bringup').perform(context) + '/urdf/arm_on_base.urdf.xacro'
    run = subprocess.run(['xacro', model], capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f'xacro failed for {model}: {run.stderr}')
    return [Node(package='robot_state_publisher', executable='robot_state_publisher',
                 parameters=[{'robot_description': run.stdout}])]


def generate_launch_description():
    return LaunchDescription([OpaqueFunction(function=launch_setup)])
"""


@pytest.mark.triggers("PF407")
def test_xacro_run_by_an_action_on_a_declared_package_not_installed_here_is_no_error(template, tmp_path):
    """amiga_ros2_gazebo: an OpaqueFunction runs xacro in a subprocess and raises its stderr; the
    model includes a file of kortex_description, declared and not installed here. On the user's
    machine the file is there: model-unevaluated (info), not launch-load-error."""
    workspace = workspace_of(template, tmp_path)
    bringup = workspace / "src" / "arm_bringup"
    manifest = bringup / "package.xml"
    manifest.write_text(
        manifest.read_text().replace(
            "<exec_depend>rviz2</exec_depend>",
            "<exec_depend>rviz2</exec_depend>\n  <exec_depend>kortex_description</exec_depend>",
        )
    )
    (bringup / "urdf" / "arm_on_base.urdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm">\n'
        '  <xacro:include filename="$(find kortex_description)/robots/kortex_robot.xacro"/>\n'
        '  <link name="base_link"/>\n</robot>\n'
    )
    (bringup / "launch" / "arm.launch.py").write_text(XACRO_IN_A_SUBPROCESS)
    status, report = verify_report(workspace, "--no-cache")
    assert status == 0, report["diagnostics"]
    assert not by_code(report, "PF301")
    # one defect, one diagnostic: at the model's include (the model is installed, and processed)
    unevaluated = by_code(report, "PF407")
    model = bringup / "urdf" / "arm_on_base.urdf.xacro"
    assert [(d["severity"], d["path"], d["line"]) for d in unevaluated] == [
        ("info", "src/arm_bringup/urdf/arm_on_base.urdf.xacro", line_of(model, "kortex_robot.xacro"))
    ]
