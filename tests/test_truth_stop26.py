"""Stop 26's false errors and misses found on real workspaces (xarm_ros2, crane_plus, husarion
ugv, spot_ros2, turtlebot3, a fourth campaign on ten repositories), each reduced to the smallest
packages that show it, verified with the real pkgforge, colcon discovery and xacro."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import line_of, verify_report
from test_truth_audit import finding_cmake, found, package
from test_truth_edges import write_package

HELPER_SETUP = """from setuptools import find_packages, setup

package_name = 'audit_helpers'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
)
"""

HELPER_MANIFEST = """<?xml version="1.0"?>
<package format="3">
  <name>audit_helpers</name>
  <version>0.1.0</version>
  <description>launch helpers</description>
  <maintainer email="test@example.com">Test Maintainer</maintainer>
  <license>Apache-2.0</license>
  <exec_depend>launch</exec_depend>
  <export><build_type>ament_python</build_type></export>
</package>
"""

USING_LAUNCH = """from launch import LaunchDescription
from launch_ros.actions import Node

from audit_helpers.names import VIEWER


def generate_launch_description():
    return LaunchDescription([Node(package=VIEWER, executable=VIEWER)])
"""


def helpers_package(tmp_path: Path) -> Path:
    folder = tmp_path / "src" / "audit_helpers"
    write_package(
        folder,
        {
            "package.xml": HELPER_MANIFEST,
            "setup.py": HELPER_SETUP,
            "resource/audit_helpers": "",
            "audit_helpers/__init__.py": "",
            "audit_helpers/names.py": "VIEWER = 'rviz2'\n",
            "test/__init__.py": "",
            "test/test_names.py": "def test_nothing():\n    pass\n",
        },
    )
    return folder


def test_a_launch_file_imports_a_workspace_python_package_and_is_evaluated(tmp_path):
    # husarion_ugv_utils, uf_ros_lib, spot_common: ament_python packages of the same workspace
    # whose modules launch files import. A sourced install puts them on PYTHONPATH; the tree did
    # not, so the files were "importing a package not installed here", checked statically only
    helpers_package(tmp_path)
    folder = package(
        tmp_path, "audit_user", ["launch_ros", "audit_helpers"], {"launch/a.launch.py": USING_LAUNCH}
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF311") == []
    # what only evaluation sees: the node's package comes from the helper module
    launch = folder / "launch" / "a.launch.py"
    assert [(s, p, line) for s, p, line, _ in found(report, "PF305")] == [
        ("error", "src/audit_user/launch/a.launch.py", line_of(launch, "Node(package=VIEWER"))
    ]


def test_setup_py_packages_land_in_the_predicted_tree(tmp_path):
    from pkgforge.model.layout import layout_from_setup_py
    from pkgforge.model.setup_py import load_setup_py
    from pkgforge.model.source import read_source

    folder = helpers_package(tmp_path)
    setup_py = load_setup_py(read_source(folder / "setup.py"), folder)
    assert setup_py.python_packages == ["audit_helpers"]  # test/ excluded as setuptools does
    layout = layout_from_setup_py(setup_py, folder)
    assert sorted(d for d in layout.files if d.startswith("lib/")) == [
        "lib/python3/site-packages/audit_helpers/__init__.py",
        "lib/python3/site-packages/audit_helpers/names.py",
    ]


ENVIRONMENT_LAUNCH = """import os

from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    model = os.environ['AUDIT_ROBOT_MODEL']
    return LaunchDescription([
        Node(package='rviz2', executable='rviz2', arguments=[model]),
    ])
"""


def test_a_file_stopped_by_an_unset_variable_is_still_checked_statically(tmp_path):
    # turtlebot3_gazebo's robot_state_publisher.launch.py reads TURTLEBOT3_MODEL first: the rest
    # of the file went unchecked, and crane_plus's undeclared ros_gz_sim with it
    folder = package(tmp_path, "audit_env", ["launch_ros"], {"launch/a.launch.py": ENVIRONMENT_LAUNCH})
    _, report = verify_report(tmp_path, "--no-cache")
    launch = folder / "launch" / "a.launch.py"
    assert [(s, line) for s, _, line, _ in found(report, "PF305")] == [
        ("error", line_of(launch, "Node(package='rviz2'"))
    ]
    assert found(report, "PF317") == [
        (
            "info",
            "src/audit_env/launch/a.launch.py",
            line_of(launch, "os.environ['AUDIT_ROBOT_MODEL']"),
            "a.launch.py stops loading: environment variable AUDIT_ROBOT_MODEL is not set here; what "
            "depends on it is not checked; the rest checked statically",
        )
    ]


OPTIONAL_RVIZ_LAUNCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('rviz', default_value='false'),
        Node(package='robot_state_publisher', executable='robot_state_publisher'),
        Node(package='rviz2', executable='rviz2', condition=IfCondition(LaunchConfiguration('rviz'))),
        Node(package='joy', executable='joy_node', condition=IfCondition('true')),
    ])
"""


def test_a_node_started_only_with_a_setting_other_than_the_defaults_is_a_warning(tmp_path):
    # kobuki_description, gz_ros2_control_demos (gui:=true), linorobot2: RViz only on request;
    # a headless robot leaves rviz2 out on purpose (unknown-package already says so)
    folder = package(
        tmp_path,
        "audit_headless",
        ["launch_ros", "robot_state_publisher"],
        {"launch/a.launch.py": OPTIONAL_RVIZ_LAUNCH},
    )
    launch = folder / "launch" / "a.launch.py"
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF305") == [
        (
            "warning",
            "src/audit_headless/launch/a.launch.py",
            line_of(launch, "package='rviz2'"),
            "Node package 'rviz2' is used at run time but package.xml does not declare it (only with rviz:=true)",
        ),
        (  # started with the defaults: an error as before
            "error",
            "src/audit_headless/launch/a.launch.py",
            line_of(launch, "package='joy'"),
            "Node package 'joy' is used at run time but package.xml does not declare it",
        ),
    ]
    hints = [d["hint"] for d in report["diagnostics"] if d["code"] == "PF305"]
    assert (
        hints[0] == "add <exec_depend>rviz2</exec_depend> if the package's users launch it with that setting"
    )


CAMERA_MODEL = """<?xml version="1.0"?>
<robot name="audit" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find orbbec_description)/urdf/femto_bolt.urdf.xacro"/>
  <link name="base_link"/>
</robot>
"""

XACRO_LIBRARY_LAUNCH = """import os

import xacro
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import OpaqueFunction
from launch_ros.actions import Node


def setup(context):
    path = os.path.join(get_package_share_directory('{package}'), 'urdf', 'robot.urdf.xacro')
    urdf = xacro.process_file(path).toxml()
    return [Node(package='robot_state_publisher', executable='robot_state_publisher',
                 parameters=[{{'robot_description': urdf}}])]


def generate_launch_description():
    return LaunchDescription([OpaqueFunction(function=setup)])
"""


def test_the_xacro_library_on_a_model_including_a_declared_package_not_installed_here(tmp_path):
    # acl-robotgroup's mobile_manipulator: xacro.process_file() in an OpaqueFunction on a model
    # including orbbec_description (declared, released, not installed here) was a PF301 error,
    # while Command(['xacro ', ...]) on the same model was model-unevaluated's info
    folder = package(
        tmp_path,
        "audit_camera",
        ["launch_ros", "robot_state_publisher", "xacro", "orbbec_description"],
        {
            "launch/a.launch.py": XACRO_LIBRARY_LAUNCH.format(package="audit_camera"),
            "urdf/robot.urdf.xacro": CAMERA_MODEL,
        },
    )
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert found(report, "PF301") == []
    model = folder / "urdf" / "robot.urdf.xacro"
    assert found(report, "PF407") == [
        (
            "info",
            "src/audit_camera/urdf/robot.urdf.xacro",
            line_of(model, "xacro:include"),
            "robot.urdf.xacro includes urdf/femto_bolt.urdf.xacro of orbbec_description, a declared "
            "package not installed here; the model is not checked",
        )
    ]
    assert report["summary"]["errors"] == 0


MOVE_GROUP_LAUNCH = """from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([Node(package='moveit_ros_move_group', executable='move_group')])
"""


def test_a_declared_package_that_brings_a_use_along_is_not_unused(tmp_path):
    # moveit2_tutorials: moveit declared, moveit_ros_move_group used. missing-exec-depend names
    # moveit as what installs it; unused-exec-depend said nothing used moveit
    folder = package(
        tmp_path, "audit_moveit", ["launch_ros", "moveit", "joy"], {"launch/a.launch.py": MOVE_GROUP_LAUNCH}
    )
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert [(s, m) for s, _, _, m in found(report, "PF305")] == [
        (
            "warning",
            "Node package 'moveit_ros_move_group' is used at run time but package.xml does not declare it; "
            "moveit, which it declares, brings it along",
        )
    ]
    manifest = folder / "package.xml"
    assert found(report, "PF107") == [
        (
            "info",
            "src/audit_moveit/package.xml",
            line_of(manifest, "<exec_depend>joy<"),
            "nothing in audit_moveit uses exec_depend 'joy'",
        )
    ]


# --- CI distros: a matrix of several branches -------------------------------------------------

# moveit2_tutorials' ci.yaml (main): the package's build, rolling only
ROLLING_BUILD = """name: CI
on:
  pull_request:
    branches: [main]
  push:
    branches: [main]
jobs:
  default:
    strategy:
      matrix:
        env:
          - IMAGE: rolling-source
    env:
      DOCKER_IMAGE: moveit/moveit2:${{ matrix.env.IMAGE }}
      ROS_DISTRO: rolling
    runs-on: ubuntu-latest
    steps:
      - uses: actions/checkout@v4
      - uses: ros-industrial/industrial_ci@master
        env: ${{ matrix.env }}
"""

# moveit2_tutorials' deploy.yml, the same on main and humble: the pages of each branch, each
# built in its distro's container
DOCS_OF_EACH_BRANCH = """name: Website
on:
  push:
    branches: [main, humble]
jobs:
  upload_site_artifacts:
    strategy:
      matrix:
        include:
          - container: 'moveit/moveit2:rolling-source'
            branch: 'main'
            rosdistro: 'rolling'
          - container: 'moveit/moveit2:humble-source'
            branch: 'humble'
            rosdistro: 'humble'
    runs-on: ubuntu-latest
    container:
      image: ${{ matrix.container }}
    steps:
      - uses: actions/checkout@v4
      - run: |
          source /opt/ros/${{ matrix.rosdistro }}/setup.bash
          make generate_api_artifacts BRANCH=${{ matrix.branch }}
"""

# a build of the package itself on humble and rolling (industrial_ci)
HUMBLE_AND_ROLLING_BUILD = """name: CI
on: [push, pull_request]
jobs:
  industrial_ci:
    strategy:
      matrix:
        env:
          - {ROS_DISTRO: humble, ROS_REPO: main}
          - {ROS_DISTRO: rolling, ROS_REPO: main}
    runs-on: ubuntu-latest
    steps:
      - uses: actions/checkout@v4
      - uses: ros-industrial/industrial_ci@master
        env: ${{ matrix.env }}
"""


def workflows(folder: Path, files: dict[str, str]) -> None:
    (folder / ".github" / "workflows").mkdir(parents=True)
    for name, text in files.items():
        (folder / ".github" / "workflows" / name).write_text(text)


def test_a_docs_matrix_of_each_branch_targets_no_distro(tmp_path):
    # moveit2_tutorials on main: its build is rolling only, deploy.yml's humble row builds the
    # humble branch's pages; moveit_py (jazzy on) was "not released for humble", an error
    folder = package(tmp_path, "audit_tutorials", ["moveit_py"], {})
    workflows(folder, {"ci.yaml": ROLLING_BUILD, "deploy.yml": DOCS_OF_EACH_BRANCH})
    _, report = verify_report(tmp_path, "--no-cache")
    assert report["diagnostics"] == []


def test_a_build_on_humble_keeps_its_package_not_in_distro_error(tmp_path):
    # the package's own build runs humble: moveit_py is not there, whatever deploy.yml holds
    folder = package(tmp_path, "audit_tutorials", ["moveit_py"], {})
    workflows(folder, {"ci.yaml": HUMBLE_AND_ROLLING_BUILD, "deploy.yml": DOCS_OF_EACH_BRANCH})
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(d["code"], d["severity"], d["path"], d["line"]) for d in report["diagnostics"]] == [
        ("PF108", "error", "src/audit_tutorials/package.xml", line_of(folder / "package.xml", "moveit_py"))
    ]
    assert report["diagnostics"][0]["message"] == (
        "<exec_depend>moveit_py</exec_depend>: 'moveit_py' is not released for humble "
        "(released for jazzy, kilted, lyrical, rolling)"
    )


def test_which_matrix_keys_name_a_branch_of_this_repository(tmp_path):
    from pkgforge.model.distro_data import ci_distros

    def distros(name: str, text: str) -> tuple[str, ...]:
        folder = tmp_path / name
        workflows(folder, {"ci.yml": text})
        return ci_distros(folder)

    checkout = "    steps:\n      - uses: actions/checkout@v4\n        with:\n"
    # the branch checked out is the distro's (humble, jazzy branches): not this checkout's distros
    each_branch = "    strategy:\n      matrix:\n        ros_distro: [humble, jazzy]\n"
    assert (
        distros("a", "jobs:\n  b:\n" + each_branch + checkout + "          ref: ${{ matrix.ros_distro }}\n")
        == ()
    )
    # another repository's branch: this package is built on both distros
    upstream = "          repository: org/dependency\n          ref: ${{ matrix.ros_distro }}\n"
    assert distros("b", "jobs:\n  b:\n" + each_branch + checkout + upstream) == ("humble", "jazzy")
    # one branch: what it is built for
    one = "    strategy:\n      matrix:\n        branch: [main]\n        ros_distro: [humble, jazzy]\n"
    assert distros("c", "jobs:\n  b:\n" + one) == ("humble", "jazzy")


def test_a_package_name_ending_in_an_underscore_is_a_warning(tmp_path):
    # ros2_learning's composition_: colcon builds it, REP 144 does not forbid it; `new` refuses it
    from conftest import run_pkgforge

    folder = package(tmp_path, "audit_name_", [], {})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF102") == [
        (
            "warning",
            "src/audit_name_/package.xml",
            line_of(folder / "package.xml", "<name>"),
            "package name: 'audit_name_' ends with '_', which REP 144 means as a separator between words",
        )
    ]
    made = run_pkgforge(
        "new", "rob_", "--maintainer-name", "A", "--maintainer-email", "a@example.com", cwd=tmp_path
    )
    assert made.returncode != 0 and "ends with '_'" in made.stderr and "Traceback" not in made.stderr
    assert not (tmp_path / "rob_").exists()


STEERING_MODEL = """<?xml version="1.0"?>
<robot name="steer">
  <link name="base_link"/>
  <joint name="base_joint" type="fixed"><parent link="base_link"/><child link="chassis"/></joint>
  <link name="chassis">
    <inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  </link>
  <link name="knuckle">
    <inertial><mass value="0.1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <joint name="steering_joint" type="revolute">
    <parent link="chassis"/><child link="knuckle"/><axis xyz="0 0 1"/>
    <limit effort="10" lower="-1" upper="1" velocity="3"/>
  </joint>
  <link name="wheel">
    <inertial><mass value="1"/><inertia ixx="0.05" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.09"/></inertial>
  </link>
  <joint name="wheel_joint" type="continuous">
    <parent link="knuckle"/><child link="wheel"/><axis xyz="0 1 0"/>
  </joint>
  <link name="flag">
    <inertial><mass value="0.1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <joint name="flag_joint" type="continuous">
    <parent link="chassis"/><child link="flag"/><axis xyz="0 0 1"/>
  </joint>
</robot>
"""


def test_a_point_mass_a_moving_joint_carries_with_a_wheel_below_is_a_warning(tmp_path):
    # gz_ros2_control_demos' ackermann steering knuckles: gz-sim takes a zero inertia (the wheel
    # below carries the joint); a point mass alone on a moving joint is still no rigid body
    folder = package(tmp_path, "audit_steer", [], {"urdf/steer.urdf": STEERING_MODEL})
    model = folder / "urdf" / "steer.urdf"
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, line, m.split(":")[0]) for s, _, line, m in found(report, "PF602")] == [
        ("warning", line_of(model, '<link name="knuckle">') + 1, "link 'knuckle'"),
        ("error", line_of(model, '<link name="flag">') + 1, "link 'flag'"),
    ]


LIDAR_LAUNCH = """import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    lidar = os.environ['AUDIT_LDS_MODEL']
    if lidar == 'LDS-01':
        driver = os.path.join(get_package_share_directory('hls_lfcd_lds_driver'), 'launch')
    elif lidar == 'LDS-02':
        driver = os.path.join(get_package_share_directory('ld08_driver'), 'launch')
    return LaunchDescription([Node(package='rviz2', executable='rviz2', arguments=[driver])])
"""


def test_a_use_in_a_python_branch_of_a_file_checked_statically_is_a_warning(tmp_path):
    # turtlebot3_bringup's robot.launch.py: the lidar driver by $LDS_MODEL; unset here, the file
    # is checked statically and which branch runs is unknown. What every branch reaches stays
    folder = package(tmp_path, "audit_lidar", ["launch_ros"], {"launch/a.launch.py": LIDAR_LAUNCH})
    launch = folder / "launch" / "a.launch.py"
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF305") == [
        (
            "warning",
            "src/audit_lidar/launch/a.launch.py",
            line_of(launch, "'hls_lfcd_lds_driver'"),
            "os.path.join 'hls_lfcd_lds_driver' is used only in the branch `if lidar == "
            "'LDS-01'` of a launch file not evaluated here, but package.xml does not declare it",
        ),
        (
            "warning",
            "src/audit_lidar/launch/a.launch.py",
            line_of(launch, "'ld08_driver'"),
            "os.path.join 'ld08_driver' is used only in the branch `if lidar == 'LDS-02'` "
            "of a launch file not evaluated here, but package.xml does not declare it",
        ),
        (
            "error",
            "src/audit_lidar/launch/a.launch.py",
            line_of(launch, "Node(package='rviz2'"),
            "Node 'rviz2' is used at run time but package.xml does not declare it",
        ),
    ]


def test_a_file_an_unevaluated_includer_names_failing_on_its_own_is_a_warning(tmp_path):
    # xarm_ros2's mbot_moveit_gazebo.launch.py imports uf_ros_lib, which imports
    # launch_param_builder (declared, not installed here): the includer is checked statically,
    # so whether _robot_on_mbot_gazebo.launch.py loads through it is unknown
    from test_truth_audit import INCLUDED_ONLY_LAUNCH, INCLUDER_LAUNCH

    includer = "from launch_param_builder import ParameterBuilder\n" + INCLUDER_LAUNCH.replace(
        "audit_alone", "audit_unknown"
    )
    folder = package(
        tmp_path,
        "audit_unknown",
        ["launch", "launch_ros", "robot_state_publisher", "launch_param_builder"],
        {"launch/_inner.launch.py": INCLUDED_ONLY_LAUNCH, "launch/outer.launch.py": includer},
    )
    inner, outer = folder / "launch" / "_inner.launch.py", folder / "launch" / "outer.launch.py"
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert found(report, "PF301") == [
        (
            "warning",
            "src/audit_unknown/launch/_inner.launch.py",
            line_of(inner, "OpaqueFunction(function=launch_setup)"),
            "OpaqueFunction failed: KeyError: 'robot_description' (launched on its own; "
            f"outer.launch.py:{line_of(outer, '_inner.launch.py')} includes it and could not be "
            "evaluated here: whether it loads there is not known)",
        )
    ]
    assert [s for s, *_ in found(report, "PF311")] == ["info"]  # the includer, checked statically


ROBOT_WITH_SIM_BRANCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def launch_setup(context, *args, **kwargs):
    sim = LaunchConfiguration('use_sim_time').perform(context) == 'true'
    if sim:
        params = {'use_sim_time': True}
    else:
        params = {'port': serial_port}  # never defined: the real robot's path is broken
    return [Node(package='robot_state_publisher', executable='robot_state_publisher', parameters=[params])]


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('use_sim_time', default_value='false'),
        OpaqueFunction(function=launch_setup),
    ])
"""

SIM_INCLUDER = """from launch import LaunchDescription
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import PathJoinSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    return LaunchDescription([IncludeLaunchDescription(
        PythonLaunchDescriptionSource(PathJoinSubstitution([FindPackageShare('audit_bot'), 'launch', 'robot.launch.py'])),
        launch_arguments=ARGUMENTS.items(),
    )])
"""

RAISING_INNER = """from launch import LaunchDescription


def generate_launch_description():
    table = {'a': 1}
    return LaunchDescription([]) if table['b'] else None
"""


def test_an_includer_giving_a_declared_argument_does_not_excuse_the_default_branch(tmp_path):
    # a reader's case: sim.launch.py gives use_sim_time:=true, which robot.launch.py declares
    # (default false); launched with its defaults it crashes on the real robot: still an error
    files = {
        "launch/robot.launch.py": ROBOT_WITH_SIM_BRANCH,
        "launch/sim.launch.py": SIM_INCLUDER.replace("ARGUMENTS", "{'use_sim_time': 'true'}"),
    }
    folder = package(tmp_path, "audit_bot", ["launch_ros", "robot_state_publisher"], files)
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, line, m) for s, _, line, m in found(report, "PF301")] == [
        (
            "error",
            line_of(folder / "launch" / "robot.launch.py", "OpaqueFunction(function=launch_setup)"),
            "OpaqueFunction failed: NameError: name 'serial_port' is not defined (only with use_sim_time:=false)",
        )
    ]


def test_a_file_failing_through_its_includer_at_the_include_stays_an_error(tmp_path):
    # a reader's case: the include fails (recorded at the includer's line), not inside the file
    files = {
        "launch/robot.launch.py": RAISING_INNER,
        "launch/sim.launch.py": SIM_INCLUDER.replace("ARGUMENTS", "{'unrelated': 'x'}"),
    }
    folder = package(tmp_path, "audit_bot", ["launch_ros"], files)
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, p, line) for s, p, line, _ in found(report, "PF301")] == [
        (
            "error",
            "src/audit_bot/launch/robot.launch.py",
            line_of(folder / "launch" / "robot.launch.py", "table['b']"),
        ),
        (
            "error",
            "src/audit_bot/launch/sim.launch.py",
            line_of(folder / "launch" / "sim.launch.py", "IncludeLaunchDescription("),
        ),
    ]


def test_a_workspace_modules_own_missing_import_leaves_the_file_unevaluated(tmp_path):
    # a reader's case: the helper module imports cv2 (its package declares python3-opencv, which
    # rosdep installs there); not installed here, the launch file is checked statically as before
    folder = helpers_package(tmp_path)
    (folder / "audit_helpers" / "names.py").write_text("import cv2  # noqa: F401\n\nVIEWER = 'rviz2'\n")
    user = package(
        tmp_path, "audit_user", ["launch_ros", "audit_helpers", "rviz2"], {"launch/a.launch.py": USING_LAUNCH}
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF301") == []
    assert [(s, line) for s, _, line, _ in found(report, "PF311")] == [
        ("info", line_of(user / "launch" / "a.launch.py", "from audit_helpers.names import VIEWER"))
    ]


def test_package_data_lands_beside_the_modules_and_evaluation_uses_count(tmp_path):
    # a reader's cases: the module reads robots.yaml beside its __file__ (package_data); the node's
    # package comes from the module, so only evaluation sees rviz2 used (no unused-exec-depend)
    folder = helpers_package(tmp_path)
    setup = (folder / "setup.py").read_text()
    (folder / "setup.py").write_text(
        setup.replace("    data_files=[", "    package_data={'audit_helpers': ['*.yaml']},\n    data_files=[")
    )
    (folder / "audit_helpers" / "robots.yaml").write_text("viewer: rviz2\n")
    (folder / "audit_helpers" / "names.py").write_text(
        "import os\n\nwith open(os.path.join(os.path.dirname(__file__), 'robots.yaml')) as f:\n"
        "    VIEWER = f.read().split(':')[1].strip()\n"
    )
    package(
        tmp_path, "audit_user", ["launch_ros", "audit_helpers", "rviz2"], {"launch/a.launch.py": USING_LAUNCH}
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [d for d in report["diagnostics"] if d["package"] == "audit_user"] == []


def test_dotted_py_modules_install_in_their_folder(tmp_path):
    from pkgforge.model.layout import layout_from_setup_py
    from pkgforge.model.setup_py import load_setup_py
    from pkgforge.model.source import read_source

    folder = tmp_path / "pkg"
    write_package(
        folder,
        {
            "setup.py": "from setuptools import setup\nsetup(name='pkg', py_modules=['tools.names', 'top'])\n",
            "tools/names.py": "",
            "top.py": "",
        },
    )
    layout = layout_from_setup_py(load_setup_py(read_source(folder / "setup.py"), folder), folder)
    assert sorted(layout.files) == [
        "lib/python3/site-packages/tools/names.py",
        "lib/python3/site-packages/top.py",
    ]


DEPENDENCY_BRANCH_MATRIX = """name: CI
on: [push, pull_request]
jobs:
  build:
    runs-on: ubuntu-latest
    strategy:
      matrix:
        include:
          - ros_distro: humble
            branch: humble
          - ros_distro: jazzy
            branch: jazzy
    steps:
      - uses: actions/checkout@v4
      - uses: ros-tooling/action-ros-ci@v0.3
        with:
          target-ros2-distro: ${{ matrix.ros_distro }}
          vcs-repo-file-url: https://raw.githubusercontent.com/example/deps/${{ matrix.branch }}/deps.repos
"""


def test_a_matrix_branch_of_the_dependencies_keeps_the_distros(tmp_path):
    # a reader's case: `branch` names the dependencies' .repos branch, not a branch of this
    # repository (its triggers name none): the code here is built on humble and on jazzy
    folder = package(tmp_path, "audit_ci", ["gazebo_ros"], {})
    workflows(folder, {"ci.yml": DEPENDENCY_BRANCH_MATRIX})
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(d["code"], d["severity"], d["line"]) for d in report["diagnostics"]] == [
        ("PF108", "error", line_of(folder / "package.xml", "gazebo_ros"))
    ]


SIM_ONLY_LAUNCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('sim', default_value='false'),
        Node(package='ros_gz_bridge', executable='parameter_bridge', condition=IfCondition(LaunchConfiguration('sim'))),
    ])
"""


def test_a_simulator_needed_only_with_a_setting_stays_an_error(tmp_path):
    # a reader's case: sim:=true is a supported mode; its undeclared ros_gz_bridge fails there
    # on a fresh machine. Only viewers (rviz2, rqt, jsp_gui) are left out on purpose
    folder = package(tmp_path, "audit_sim", ["launch_ros"], {"launch/a.launch.py": SIM_ONLY_LAUNCH})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF305") == [
        (
            "error",
            "src/audit_sim/launch/a.launch.py",
            line_of(folder / "launch" / "a.launch.py", "package='ros_gz_bridge'"),
            "Node package 'ros_gz_bridge' is used at run time but package.xml does not declare it (only with sim:=true)",
        )
    ]


ZERO_VELOCITY_ARM = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base_link"/>
  <link name="upper">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="0"/>
  </joint>
</robot>
"""


def test_a_zero_velocity_where_only_moveit_reads_the_model_is_a_warning(tmp_path):
    # waveshare roarm: MoveIt reads velocity 0 as no limit (robot_model.cpp: velocity_bounded_ =
    # max_velocity_ > epsilon); only a simulator or ros2_control enforces it
    folder = package(tmp_path, "audit_arm", ["moveit_ros_move_group"], {"urdf/arm.urdf": ZERO_VELOCITY_ARM})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF605") == [
        (
            "warning",
            "src/audit_arm/urdf/arm.urdf",
            line_of(folder / "urdf" / "arm.urdf", "<limit"),
            "revolute joint 'j1': velocity=\"0\" (nothing here enforces it: MoveIt reads 0 as no limit and "
            "RViz ignores it; a simulator or ros2_control would stop the joint)",
        )
    ]


def test_a_point_mass_on_a_moving_link_where_gazebo_classic_is_used_stays_an_error(tmp_path):
    # a reader's case: ODE (Gazebo Classic) refuses a moving body without inertia
    package(tmp_path, "audit_steer", ["gazebo_ros2_control"], {"urdf/steer.urdf": STEERING_MODEL})
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "humble")
    # (one cause in one file, one diagnostic naming both links: issue 30)
    [(severity, _, _, message)] = found(report, "PF602")
    assert severity == "error" and message.startswith(
        "2 links have an inertia that is not positive definite (principal moments): knuckle ("
    )
    assert "), flag (" in message


# --- the docs.ros.org tutorials' launch files on a machine without ROS sourced ------------------
# (each for both engines: the built-in one and the real launch libraries, jazzy's)


def engine_reports(tmp_path: Path) -> dict[str, dict]:
    """The report of `pkgforge verify` by each engine (the ros engine where the real launch
    libraries are laid out: tests/ros_prefix.py)."""
    from ros_prefix import make_prefix

    prefix, _ = make_prefix("jazzy", tmp_path / "ros")
    reports = {}
    for engine in ("builtin", "ros"):
        if engine == "ros" and prefix is None:
            continue  # (no real launch library here: said by the engine tests too)
        extra = ["--ros-prefix", str(prefix)] if engine == "ros" else []
        _, reports[engine] = verify_report(
            tmp_path, "--no-cache", "--distro", "jazzy", "--launch-engine", engine, *extra
        )
    return reports


FIND_EXECUTABLE_LAUNCH = """from launch import LaunchDescription
from launch.actions import ExecuteProcess
from launch.substitutions import FindExecutable


def generate_launch_description():
    return LaunchDescription([
        ExecuteProcess(cmd=[[FindExecutable(name='ros2'), ' topic list']], shell=True),
        ExecuteProcess(cmd=[FindExecutable(name='python3'), '--version']),
    ])
"""


def test_a_program_find_executable_does_not_find_here_is_unevaluated_not_an_error(tmp_path):
    # the "Using event handlers" tutorial: ExecuteProcess(cmd=[[FindExecutable(name='ros2'),
    # ' service call ...']]). ros2 is on PATH wherever ROS is sourced, not on the machine that
    # checks: "SubstitutionFailure: executable 'ros2' not found on the PATH" was a PF301 error
    import shutil

    if shutil.which("ros2"):
        pytest.skip("ros2 is on PATH here")
    folder = package(tmp_path, "audit_findexec", ["ros2cli"], {"launch/a.launch.py": FIND_EXECUTABLE_LAUNCH})
    launch = folder / "launch" / "a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert found(report, "PF301") == [], engine
        assert found(report, "PF311") == [
            (
                "info",
                "src/audit_findexec/launch/a.launch.py",
                line_of(launch, "FindExecutable(name='ros2')"),
                "a.launch.py: ExecuteProcess finds ros2 on PATH (FindExecutable), a program not "
                "installed here; what it starts is not checked",
            )
        ], engine


ENVIRONMENT_SUBSTITUTION_LAUNCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, LogInfo, UnsetEnvironmentVariable
from launch.substitutions import EnvironmentVariable, FileContent, LaunchConfiguration


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('node_prefix', default_value=[EnvironmentVariable('AUDIT_OPERATOR'), '_']),
        LogInfo(msg=[LaunchConfiguration('node_prefix'), 'ok']),
        LogInfo(msg=EnvironmentVariable('AUDIT_SITE')),
        UnsetEnvironmentVariable('AUDIT_SITE'),
        LogInfo(msg=EnvironmentVariable('AUDIT_SITE')),
        LogInfo(msg=FileContent('/nonexistent-pkgforge-test/notes.txt')),
    ])
"""


def test_an_environment_variable_substitution_not_set_here_is_the_unset_variable_info(tmp_path, monkeypatch):
    # the tf2 tutorial's DeclareLaunchArgument('node_prefix', default_value=[EnvironmentVariable(
    # 'USER'), '_']) where USER is not set (a container, CI): "SubstitutionFailure: environment
    # variable 'USER' does not exist" was a PF301 error; os.environ['USER'] was PF317 already.
    # A variable set here that the file unsets itself, and any other SubstitutionFailure, stay errors
    monkeypatch.delenv("AUDIT_OPERATOR", raising=False)
    monkeypatch.setenv("AUDIT_SITE", "lab")
    folder = package(
        tmp_path, "audit_envsub", ["launch"], {"launch/a.launch.py": ENVIRONMENT_SUBSTITUTION_LAUNCH}
    )
    launch = folder / "launch" / "a.launch.py"
    path = "src/audit_envsub/launch/a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert found(report, "PF317") == [
            (
                "info",
                path,
                line_of(launch, "EnvironmentVariable('AUDIT_OPERATOR')"),
                "a.launch.py: DeclareLaunchArgument fails: environment variable AUDIT_OPERATOR is not "
                "set here (EnvironmentVariable without a default); what depends on it is not checked",
            )
        ], engine
        reads = [n for n, text in enumerate(launch.read_text().splitlines(), 1) if "'AUDIT_SITE'" in text]
        assert found(report, "PF301") == [
            (
                "error",
                path,
                reads[2],  # after the file's own UnsetEnvironmentVariable
                "LogInfo failed: SubstitutionFailure: environment variable 'AUDIT_SITE' does not exist",
            ),
            (
                "error",
                path,
                line_of(launch, "FileContent("),
                "LogInfo failed: SubstitutionFailure: File not found: /nonexistent-pkgforge-test/notes.txt",
            ),
        ], engine


SHUTDOWN_EVENT_LAUNCH = """from launch import LaunchDescription
from launch.actions import ExecuteProcess, LogInfo, RegisterEventHandler
from launch.event_handlers import OnProcessExit, OnShutdown
from launch.substitutions import LocalSubstitution


def generate_launch_description():
    sleeper = ExecuteProcess(cmd=['sleep', '1'])
    return LaunchDescription([
        sleeper,
        RegisterEventHandler(OnProcessExit(target_action=sleeper, on_exit=[LogInfo(
            msg=['exited: ', LocalSubstitution('event.process_name')])])),
        RegisterEventHandler(OnShutdown(on_shutdown=[LogInfo(
            msg=['Launch was asked to shutdown: ', LocalSubstitution('event.reason')])])),
    ])
"""


def test_an_event_handlers_entities_see_the_event(tmp_path):
    # the "Using event handlers" tutorial: OnShutdown's LogInfo of LocalSubstitution('event.reason').
    # launch puts the event in the locals before it visits a handler's entities; the built-in
    # engine did not ("NameError: name 'event' is not defined", a PF301 error), the ros engine
    # did not for OnProcessExit, and did not visit OnShutdown's entities at all
    folder = package(tmp_path, "audit_events", ["launch"], {"launch/a.launch.py": SHUTDOWN_EVENT_LAUNCH})
    launch = folder / "launch" / "a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert [d for d in report["diagnostics"] if d["path"].endswith(".py")] == [], engine
    # a misspelt attribute of the event is the file's own error, as launch says it when it happens
    launch.write_text(SHUTDOWN_EVENT_LAUNCH.replace("event.reason", "event.reasons"))
    for engine, report in engine_reports(tmp_path).items():
        assert found(report, "PF301") == [
            (
                "error",
                "src/audit_events/launch/a.launch.py",
                line_of(launch, "RegisterEventHandler(OnShutdown("),
                "LogInfo failed: AttributeError: 'Shutdown' object has no attribute 'reasons'",
            )
        ], engine


PATHLIB_XACRO_LAUNCH = """import os
from pathlib import Path

import xacro
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    path = Path(os.path.join(get_package_share_directory('audit_path'), 'urdf', 'robot.urdf.xacro'))
    document = xacro.process_file(path)
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[{'robot_description': document.toxml()}]),
    ])
"""


def test_the_xacro_library_given_a_pathlib_path_is_the_same_model(tmp_path):
    # jocacace/ROSConES: xacro.process_file(Path(...)) on a model including a declared package
    # not installed here was xacro-error's PF308 error; with a str path, model-unevaluated's info
    package(
        tmp_path,
        "audit_path",
        ["launch_ros", "robot_state_publisher", "xacro", "orbbec_description"],
        {"launch/a.launch.py": PATHLIB_XACRO_LAUNCH, "urdf/robot.urdf.xacro": CAMERA_MODEL},
    )
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert [(d["code"], d["severity"], d["path"]) for d in report["diagnostics"]] == [
        ("PF407", "info", "src/audit_path/urdf/robot.urdf.xacro")
    ]


BOTH_READ_THE_FILE_LAUNCH = """import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    urdf = os.path.join(get_package_share_directory('audit_arm'), 'urdf', 'arm.urdf')
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher', arguments=[urdf]),
        Node(package='joint_state_publisher_gui', executable='joint_state_publisher_gui', arguments=[urdf]),
    ])
"""


def test_jsp_given_the_plain_file_robot_state_publisher_reads_on_its_command_line(tmp_path):
    # waveshare roarm's display.launch.py: both read arm.urdf from argv (robot_state_publisher.cpp
    # reads argv[1]; joint_state_publisher's urdf_file argument): no jsp-model-argument error,
    # only rsp-model-argument's advice
    model = ZERO_VELOCITY_ARM.replace('velocity="0"', 'velocity="1"')
    package(
        tmp_path,
        "audit_arm",
        ["launch_ros", "robot_state_publisher", "joint_state_publisher_gui"],
        {"launch/a.launch.py": BOTH_READ_THE_FILE_LAUNCH, "urdf/arm.urdf": model},
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(d["code"], d["severity"]) for d in report["diagnostics"]] == [("PF314", "warning")]


NODE_ONLY_LAUNCH = """from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([Node(package='robot_state_publisher', executable='robot_state_publisher')])
"""


def test_a_launch_use_declared_only_as_test_depend_is_a_warning(tmp_path):
    # doosan-robot2's dsr_tests: launch files its pytest starts, their packages <test_depend>
    folder = package(
        tmp_path,
        "audit_tests",
        [],
        {"launch/a.launch.py": NODE_ONLY_LAUNCH},
        test_depend=["robot_state_publisher"],
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF305") == [
        (
            "warning",
            "src/audit_tests/launch/a.launch.py",
            line_of(folder / "launch" / "a.launch.py", "Node(package="),
            "Node package 'robot_state_publisher' is used at run time but package.xml declares it only as <test_depend>",
        )
    ]


def test_a_finding_in_another_packages_file_a_model_includes_has_the_include_line(tmp_path):
    # waveshare roarm_moveit's config model includes roarm_description's URDF: its findings on
    # that model had no line at all
    arm = ZERO_VELOCITY_ARM.replace('effort="10"', 'effort="0"').replace('velocity="0"', 'velocity="1"')
    package(tmp_path, "audit_arm_description", [], {"urdf/arm.urdf": arm})
    wrapper = (
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm">\n'
        '  <xacro:include filename="$(find audit_arm_description)/urdf/arm.urdf"/>\n'
        '  <link name="world"/>\n'
        '  <joint name="world_joint" type="fixed"><parent link="world"/><child link="base_link"/></joint>\n</robot>\n'
    )
    folder = package(
        tmp_path, "audit_arm_config", ["audit_arm_description"], {"urdf/arm_config.urdf.xacro": wrapper}
    )
    assert (folder / "urdf" / "arm_config.urdf.xacro").is_file()
    _, report = verify_report(tmp_path, "--no-cache")
    # both packages verified: the finding is at the arm's own line, once (one cause, one finding);
    # the include line stands for a file of a package not verified here
    assert [(s, p) for s, p, _, _ in found(report, "PF605")] == [
        ("warning", "src/audit_arm_description/urdf/arm.urdf")
    ]


# --- a path that is only part of the name a substitution list builds ---------------------------

SUFFIX_LAUNCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import Command, FindExecutable, LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    description = Command([
        PathJoinSubstitution([FindExecutable(name='xacro')]), ' ',
        PathJoinSubstitution([FindPackageShare('audit_suffix'), 'xacro', LaunchConfiguration('model')]),
        '.urdf.xacro',
        ' tool:=', LaunchConfiguration('tool'),
    ])
    return LaunchDescription([
        DeclareLaunchArgument('model', default_value='arm'),
        DeclareLaunchArgument('tool', default_value='true'),
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[{'robot_description': ParameterValue(description, value_type=str)}]),
    ])
"""

# the flag (a point mass on a moving joint: PF602) is there only with the launch file's tool:=true
TOOL_MODEL = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="tool" default="false"/>
  <link name="base_link">
    <inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  </link>
  <xacro:if value="$(arg tool)">
    <link name="flag">
      <inertial><mass value="0.1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
    </link>
    <joint name="flag_joint" type="continuous">
      <parent link="base_link"/><child link="flag"/><axis xyz="0 0 1"/>
    </joint>
  </xacro:if>
</robot>
"""


def suffix_reports(tmp_path: Path, launch: str) -> tuple[Path, dict[str, dict]]:
    """The package with this launch file and xacro/arm.urdf.xacro, and its reports."""
    files = {"launch/a.launch.py": launch, "xacro/arm.urdf.xacro": TOOL_MODEL}
    folder = package(tmp_path, "audit_suffix", ["launch_ros", "robot_state_publisher", "xacro"], files)
    return folder, engine_reports(tmp_path)


def test_a_path_joined_to_its_suffix_in_a_command_is_that_file(tmp_path):
    # doosan-robot2: Command([xacro, ' ', PathJoinSubstitution([share, 'xacro', model]),
    # '.urdf.xacro', ...]) joins its parts into one line before splitting it: xacro gets
    # .../xacro/arm.urdf.xacro. share/.../xacro/arm alone was a PF303 error in 11 launch files
    _, reports = suffix_reports(tmp_path, SUFFIX_LAUNCH)
    for engine, report in reports.items():
        assert found(report, "PF303") == [], engine
        assert found(report, "PF302") == [], engine
        # the model xacro processed is the joined name, with the launch file's tool:=true (the
        # flag's line: PF602's own test says where in the link)
        assert [(s, p, m.split(":")[0]) for s, p, _, m in found(report, "PF602")] == [
            ("error", "src/audit_suffix/xacro/arm.urdf.xacro", "link 'flag'")
        ], engine


def test_a_typo_in_the_suffix_joined_to_a_path_is_the_missing_file(tmp_path):
    launch = SUFFIX_LAUNCH.replace("'.urdf.xacro'", "'.urdf.xacroo'")
    folder, reports = suffix_reports(tmp_path, launch)
    file = folder / "launch" / "a.launch.py"
    for engine, report in reports.items():
        assert [(s, line, m.split(" does not exist")[0]) for s, _, line, m in found(report, "PF303")] == [
            ("error", line_of(file, "description = Command(["), "share/audit_suffix/xacro/arm.urdf.xacroo")
        ], engine


LIST_LAUNCH = """from launch import LaunchDescription
from launch.actions import ExecuteProcess, SetEnvironmentVariable
from launch.substitutions import PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    share = FindPackageShare('audit_lists')
    return LaunchDescription([
        Node(package='rviz2', executable='rviz2',
             arguments=['-d', [PathJoinSubstitution([share, 'config', 'view']), '.rviz']]),
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[[PathJoinSubstitution([share, 'config', 'state']), '_params.yaml'],
                         {'limits': [PathJoinSubstitution([share, 'config', 'limits']), '.yaml']}]),
        ExecuteProcess(cmd=['cat', [PathJoinSubstitution([share, 'config', 'notes']), '.txtt']]),
        SetEnvironmentVariable('GZ_SIM_RESOURCE_PATH', [PathJoinSubstitution([share, 'models']), ':', '/opt']),
    ])
"""


def test_a_path_joined_to_its_suffix_in_a_list_of_substitutions_is_that_file(tmp_path):
    # launch concatenates a list of substitutions into one string: a Node argument, a parameter
    # file and a parameter value name the joined files, which are there; a command's word with
    # a typo is still missing; a path before ':' (a search path) is a whole name of its own
    files = {
        "launch/a.launch.py": LIST_LAUNCH,
        "config/view.rviz": "Visualization Manager:\n  Displays: []\n",
        "config/state_params.yaml": "robot_state_publisher:\n  ros__parameters:\n    publish_frequency: 20.0\n",
        "config/limits.yaml": "a: 1\n",
        "config/notes.txt": "notes\n",
    }
    folder = package(tmp_path, "audit_lists", ["launch_ros", "robot_state_publisher", "rviz2"], files)
    file = folder / "launch" / "a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert [(s, line, m.split(" does not exist")[0]) for s, _, line, m in found(report, "PF303")] == [
            ("error", line_of(file, "'notes'"), "share/audit_lists/config/notes.txtt"),
            ("error", line_of(file, "'models'"), "share/audit_lists/models"),
        ], engine
        assert found(report, "PF302") == [], engine


def test_a_path_before_a_substitution_with_no_value_names_no_file_of_its_own(tmp_path):
    # the suffix an argument with no default: the launch stops there, and where the name ends is
    # not known, so share/.../xacro/arm alone is no missing file (the argument is said: PF309)
    launch = SUFFIX_LAUNCH.replace("'.urdf.xacro',", "LaunchConfiguration('suffix'),").replace(
        "DeclareLaunchArgument('model', default_value='arm'),",
        "DeclareLaunchArgument('model', default_value='arm'), DeclareLaunchArgument('suffix'),",
    )
    assert "DeclareLaunchArgument('suffix')" in launch
    folder, reports = suffix_reports(tmp_path, launch)
    file = folder / "launch" / "a.launch.py"
    for engine, report in reports.items():
        assert found(report, "PF303") == [], engine
        assert [(s, line) for s, _, line, _ in found(report, "PF309")] == [
            ("info", line_of(file, "DeclareLaunchArgument('suffix')"))
        ], engine


# --- find_package() behind an optional find_package (tmr_ros2's tm_driver) --------------------------

GATED_CMAKE = """cmake_minimum_required(VERSION 3.10)
project(audit_driver NONE)
find_package(ament_cmake REQUIRED)
find_package(moveit_ros_planning_interface QUIET)
if(moveit_ros_planning_interface_FOUND)
  find_package(trajectory_msgs REQUIRED)
  find_package(control_msgs REQUIRED)
endif()
if(NOT moveit_ros_planning_interface_FOUND)
  find_package(urdf REQUIRED)
else()
  find_package(rclcpp_action REQUIRED)
endif()
if(WITH_TF)
  find_package(tf2_ros REQUIRED)
endif()
find_package(control_msgs REQUIRED)
ament_package()
"""


def test_a_find_package_only_an_optional_find_lets_run_is_a_warning(tmp_path):
    # tm_driver: find_package(moveit_ros_planning_interface QUIET), then inside
    # if(moveit_ros_planning_interface_FOUND) trajectory_msgs, control_msgs, rclcpp_action REQUIRED:
    # a clean machine (rosdep installs what package.xml declares) never runs that branch
    folder = package(tmp_path, "audit_driver", [], {"CMakeLists.txt": GATED_CMAKE})
    cmakelists = folder / "CMakeLists.txt"
    _, report = verify_report(tmp_path, "--no-cache")
    gate = "(an if() on the optional find_package() at line 4), so a clean machine builds without it"
    assert found(report, "PF109") == [
        (
            "warning",
            "src/audit_driver/CMakeLists.txt",
            line_of(cmakelists, "find_package(moveit_ros_planning_interface QUIET)"),
            "find_package(moveit_ros_planning_interface) but package.xml does not declare "
            "moveit_ros_planning_interface for the build; it is optional (QUIET), so a clean machine "
            "builds without what needs it",
        ),
        (
            "warning",
            "src/audit_driver/CMakeLists.txt",
            line_of(cmakelists, "find_package(trajectory_msgs"),
            "find_package(trajectory_msgs) but package.xml does not declare trajectory_msgs for the "
            f"build; it is needed only where moveit_ros_planning_interface is found {gate}",
        ),
        # the branch a clean machine takes
        (
            "error",
            "src/audit_driver/CMakeLists.txt",
            line_of(cmakelists, "find_package(urdf"),
            "find_package(urdf) but package.xml does not declare urdf for the build",
        ),
        (
            "warning",
            "src/audit_driver/CMakeLists.txt",
            line_of(cmakelists, "find_package(rclcpp_action"),
            "find_package(rclcpp_action) but package.xml does not declare rclcpp_action for the "
            f"build; it is needed only where moveit_ros_planning_interface is found {gate}",
        ),
        # an if() on anything else may well hold there
        (
            "error",
            "src/audit_driver/CMakeLists.txt",
            line_of(cmakelists, "find_package(tf2_ros"),
            "find_package(tf2_ros) but package.xml does not declare tf2_ros for the build",
        ),
        # found inside the gate and again outside it: the clean machine fails at the second
        (
            "error",
            "src/audit_driver/CMakeLists.txt",
            GATED_CMAKE.splitlines().index("find_package(control_msgs REQUIRED)") + 1,
            "find_package(control_msgs) but package.xml does not declare control_msgs for the build",
        ),
    ]
    # rosdep installs what package.xml declares: where it declares the optional package (one that
    # brings no control_msgs along, as MoveIt would), the branch runs on a clean machine
    cmake = GATED_CMAKE.replace("moveit_ros_planning_interface", "point_cloud_transport")
    package(tmp_path, "audit_driver", [], {"CMakeLists.txt": cmake}, depend=["point_cloud_transport"])
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, p, line) for s, p, line, _ in found(report, "PF109")] == [
        ("error", "src/audit_driver/CMakeLists.txt", line_of(cmakelists, "find_package(trajectory_msgs")),
        ("error", "src/audit_driver/CMakeLists.txt", line_of(cmakelists, "find_package(control_msgs")),
        ("error", "src/audit_driver/CMakeLists.txt", line_of(cmakelists, "find_package(urdf")),
        ("error", "src/audit_driver/CMakeLists.txt", line_of(cmakelists, "find_package(rclcpp_action")),
        ("error", "src/audit_driver/CMakeLists.txt", line_of(cmakelists, "find_package(tf2_ros")),
    ]


def test_what_follows_a_return_without_an_optional_package_is_a_warning(tmp_path):
    # ros2/demos' demo_nodes_cpp_native: if(NOT rmw_fastrtps_cpp_FOUND) return() endif(); a clean
    # machine without it configures nothing after; a FATAL_ERROR instead of return() stops it there
    cmake = (
        "cmake_minimum_required(VERSION 3.10)\nproject(audit_native NONE)\nfind_package(ament_cmake REQUIRED)\n"
        "find_package(rmw_fastrtps_cpp QUIET)\nif(NOT rmw_fastrtps_cpp_FOUND)\n"
        '  message(STATUS "skipping")\n  return()\nendif()\nfind_package(tf2_ros REQUIRED)\nament_package()\n'
    )
    folder = package(tmp_path, "audit_native", [], {"CMakeLists.txt": cmake})
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, p, line) for s, p, line, _ in found(report, "PF109")][0] == (
        "warning",
        "src/audit_native/CMakeLists.txt",
        line_of(folder / "CMakeLists.txt", "find_package(rmw_fastrtps_cpp QUIET)"),
    )
    assert found(report, "PF109")[1:] == [
        (
            "warning",
            "src/audit_native/CMakeLists.txt",
            line_of(folder / "CMakeLists.txt", "find_package(tf2_ros"),
            "find_package(tf2_ros) but package.xml does not declare tf2_ros for the build; it is needed "
            "only where rmw_fastrtps_cpp is found (an if() on the optional find_package() at line 4), "
            "so a clean machine builds without it",
        )
    ]


# --- `pkgforge fix` and a dependency cycle (ROBOTIS ai_worker, doosan-robot2) ------------------------

SIM_LAUNCH = """from launch import LaunchDescription
from launch.substitutions import Command, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    model = PathJoinSubstitution([FindPackageShare('audit_description'), 'urdf', 'robot.urdf.xacro'])
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[{'robot_description': ParameterValue(Command(['xacro ', model]), value_type=str)}]),
    ])
"""

CONTROLLED_MODEL = """<?xml version="1.0"?>
<robot name="audit" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <link name="base_link"/>
  <gazebo>
    <plugin filename="gz_ros2_control-system" name="gz_ros2_control::GazeboSimROS2ControlPlugin">
      <parameters>$(find audit_bringup)/config/gz.yaml</parameters>
    </plugin>
  </gazebo>
</robot>
"""


def test_fix_declares_neither_side_of_a_mutual_use(tmp_path):
    # ffw_description's xacro finds ffw_bringup, whose launch file finds ffw_description: each
    # PF305 is true, but declaring both is a cycle colcon refuses; another fix still applies
    from conftest import run_pkgforge

    description = package(
        tmp_path, "audit_description", ["xacro"], {"urdf/robot.urdf.xacro": CONTROLLED_MODEL}
    )
    bringup = package(
        tmp_path,
        "audit_bringup",
        ["xacro", "robot_state_publisher"],
        {"launch/sim.launch.py": SIM_LAUNCH, "config/gz.yaml": "controller_manager: {}\n"},
    )
    viewer = package(
        tmp_path,
        "audit_viewer",
        [],
        {
            "launch/view.launch.py": USING_LAUNCH.replace(
                "from audit_helpers.names import VIEWER\n", "VIEWER = 'rviz2'\n"
            )
        },
    )
    manifests = {p: (p / "package.xml").read_text() for p in (description, bringup)}
    launch_line = line_of(bringup / "launch" / "sim.launch.py", "FindPackageShare('audit")
    model_line = line_of(description / "urdf" / "robot.urdf.xacro", "$(find")
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, p, line) for s, p, line, _ in found(report, "PF305")] == [
        ("error", "src/audit_bringup/launch/sim.launch.py", launch_line),
        ("error", "src/audit_description/urdf/robot.urdf.xacro", model_line),
        (
            "error",
            "src/audit_viewer/launch/view.launch.py",
            line_of(viewer / "launch" / "view.launch.py", "Node("),
        ),
    ]
    result = run_pkgforge("fix", ".", cwd=tmp_path)
    assert "Traceback" not in result.stdout + result.stderr
    assert result.returncode == 1  # the two errors remain
    assert {p: (p / "package.xml").read_text() for p in manifests} == manifests
    assert "<exec_depend>rviz2</exec_depend>" in (viewer / "package.xml").read_text()
    not_fixed = [line for line in result.stdout.splitlines() if line.startswith("not fixed")]
    assert not_fixed == [
        f"not fixed src/audit_bringup/launch/sim.launch.py:{launch_line}: PF305 missing-exec-depend: declaring "
        "audit_description here and, as another fix of this run would, audit_bringup in audit_description "
        "makes a cycle colcon refuses (audit_bringup → audit_description → audit_bringup): neither is "
        "applied; declare the dependency that is meant, and move the other use",
        f"not fixed src/audit_description/urdf/robot.urdf.xacro:{model_line}: PF305 missing-exec-depend: "
        "declaring audit_bringup here and, as another fix of this run would, audit_description in "
        "audit_bringup makes a cycle colcon refuses (audit_description → audit_bringup → "
        "audit_description): neither is applied; declare the dependency that is meant, and move the other use",
    ]
    # a second run changes nothing
    again = run_pkgforge("fix", ".", cwd=tmp_path)
    assert again.returncode == 1 and not [
        line for line in again.stdout.splitlines() if line.startswith("fixed")
    ]
    assert {p: (p / "package.xml").read_text() for p in manifests} == manifests


def test_fix_declares_no_build_dependency_back_on_a_package_that_depends_on_this_one(tmp_path):
    # PF109's fix on a workspace package: audit_tools find_package()s audit_core, which exec_depends
    # audit_tools already; the build_depend would be a cycle colcon refuses
    from conftest import run_pkgforge

    core = package(tmp_path, "audit_core", ["audit_tools"], {})
    tools = package(
        tmp_path, "audit_tools", [], {"CMakeLists.txt": finding_cmake("audit_tools", "audit_core")}
    )
    before = (tools / "package.xml").read_text()
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF109") == [
        (
            "error",
            "src/audit_tools/CMakeLists.txt",
            line_of(tools / "CMakeLists.txt", "find_package(audit_core"),
            "find_package(audit_core) but package.xml does not declare audit_core for the build",
        )
    ]
    result = run_pkgforge("fix", ".", cwd=tmp_path)
    assert "Traceback" not in result.stdout + result.stderr
    assert result.returncode == 1
    assert (tools / "package.xml").read_text() == before
    assert (core / "package.xml").read_text().count("audit_tools") == 1
    find_line = line_of(tools / "CMakeLists.txt", "find_package(audit_core")
    assert [line for line in result.stdout.splitlines() if line.startswith("not fixed")] == [
        f"not fixed src/audit_tools/CMakeLists.txt:{find_line}:1: PF109 find-package-undeclared: audit_core "
        "depends on audit_tools (audit_tools → audit_core → audit_tools), so declaring it makes a cycle "
        "colcon refuses"
    ]


def test_a_program_find_executable_cannot_find_anywhere_stays_an_error(tmp_path):
    # a reader's case: a misspelt program fails everywhere, and a node's executable lives in
    # lib/<package>/, never on PATH: only the tools a sourced ROS puts on PATH (ros2, gz) are
    # "not installed here"
    launch = FIND_EXECUTABLE_LAUNCH.replace("'ros2'", "'pyhton3'").replace(
        "FindExecutable(name='python3')", "FindExecutable(name='robot_state_publisher')"
    )
    folder = package(tmp_path, "audit_typo", ["launch"], {"launch/a.launch.py": launch})
    written = folder / "launch" / "a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert [(s, line) for s, _, line, _ in found(report, "PF301")] == [
            ("error", line_of(written, "'pyhton3'")),
            ("error", line_of(written, "'robot_state_publisher'")),
        ], engine
        assert found(report, "PF311") == [], engine


def test_a_system_library_gate_gates_nothing(tmp_path):
    # a reader's case: find_package(Eigen3 QUIET) then if(Eigen3_FOUND) find_package(tf2_eigen
    # REQUIRED), eigen declared by its rosdep key: rosdep installs Eigen3, the branch runs, the
    # build fails without tf2_eigen. A CMake name is no ROS package name: no gate
    cmake = (
        "cmake_minimum_required(VERSION 3.10)\nproject(audit_gate NONE)\nfind_package(ament_cmake REQUIRED)\n"
        "find_package(Eigen3 QUIET)\nif(Eigen3_FOUND)\n  find_package(tf2_eigen REQUIRED)\nendif()\nament_package()\n"
    )
    folder = package(tmp_path, "audit_gate", [], {"CMakeLists.txt": cmake}, depend=["eigen"])
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert [(s, line) for s, _, line, _ in found(report, "PF109")] == [
        ("error", line_of(folder / "CMakeLists.txt", "find_package(tf2_eigen"))
    ]


def test_a_launch_use_declared_only_as_test_depend_outside_tests_stays_an_error(tmp_path):
    # a reader's case: a released binary brings no test dependencies; an ordinary package's
    # installed launch file fails after `apt install` (ros2/demos' lifecycle_py too)
    folder = package(
        tmp_path,
        "audit_bringup",
        [],
        {"launch/a.launch.py": NODE_ONLY_LAUNCH},
        test_depend=["robot_state_publisher"],
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF305") == [
        (
            "error",
            "src/audit_bringup/launch/a.launch.py",
            line_of(folder / "launch" / "a.launch.py", "Node(package="),
            "Node package 'robot_state_publisher' is used at run time but package.xml does not declare it; it "
            "declares it only as <test_depend>, which a released binary does not bring",
        )
    ]


def test_the_include_line_is_the_one_naming_that_package_and_path(tmp_path):
    # a reader's case: two includes of files with the same name, from two packages: the finding
    # in the arm's file points at the arm's include, not at the first one with that name
    arm = ZERO_VELOCITY_ARM.replace('effort="10"', 'effort="0"').replace('velocity="0"', 'velocity="1"')
    package(tmp_path, "audit_arm_description", [], {"urdf/arm.urdf": arm})
    gripper = '<?xml version="1.0"?>\n<robot name="g">\n  <!-- nothing yet -->\n</robot>\n'
    package(tmp_path, "audit_gripper_description", [], {"urdf/arm.urdf": gripper})
    wrapper = (
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm">\n'
        '  <!-- <xacro:include filename="$(find audit_arm_description)/urdf/arm.urdf"/> (old) -->\n'
        '  <xacro:include filename="$(find audit_gripper_description)/urdf/arm.urdf"/>\n'
        '  <xacro:include filename="$(find audit_arm_description)/urdf/arm.urdf"/>\n'
        '  <link name="world"/>\n'
        '  <joint name="world_joint" type="fixed"><parent link="world"/><child link="base_link"/></joint>\n</robot>\n'
    )
    deps = ["audit_arm_description", "audit_gripper_description"]
    folder = package(tmp_path, "audit_arm_config", deps, {"urdf/arm_config.urdf.xacro": wrapper})
    assert (folder / "urdf" / "arm_config.urdf.xacro").is_file()
    _, report = verify_report(tmp_path, "--no-cache")
    # both packages verified: the finding is at the arm's own line, once (one cause, one finding);
    # the include line stands for a file of a package not verified here
    assert [(s, p) for s, p, _, _ in found(report, "PF605")] == [
        ("warning", "src/audit_arm_description/urdf/arm.urdf")
    ]


LOG_SENTENCE_LAUNCH = """from launch import LaunchDescription
from launch.actions import LogInfo
from launch.substitutions import PathJoinSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    share = FindPackageShare('audit_log')
    return LaunchDescription([
        LogInfo(msg=['Loading the model ', PathJoinSubstitution([share, 'urdf', 'robot.urdf']), '.']),
        LogInfo(msg=['Loading ', PathJoinSubstitution([share, 'urdf', 'robot.urdf']), '...']),
    ])
"""


def test_a_full_stop_after_a_joined_path_is_no_part_of_its_name(tmp_path):
    # a reader's case: 'robot.urdf.' and 'robot.urdf...' were missing files (the built-in engine
    # only); a sentence's punctuation ends the name
    robot = '<?xml version="1.0"?>\n<robot name="r">\n  <link name="base_link"/>\n</robot>\n'
    package(
        tmp_path,
        "audit_log",
        ["launch"],
        {"launch/a.launch.py": LOG_SENTENCE_LAUNCH, "urdf/robot.urdf": robot},
    )
    for engine, report in engine_reports(tmp_path).items():
        assert found(report, "PF303") == [] and found(report, "PF302") == [], engine


RUN_TIME_EVENT_LAUNCH = """from launch import LaunchDescription
from launch.actions import ExecuteProcess, LogInfo, RegisterEventHandler
from launch.event_handlers import OnProcessExit, OnProcessStart
from launch.substitutions import LocalSubstitution


def generate_launch_description():
    sleeper = ExecuteProcess(cmd=['sleep', '1'], name='sleeper')
    return LaunchDescription([
        sleeper,
        RegisterEventHandler(OnProcessStart(target_action=sleeper, on_start=[LogInfo(
            msg=['cmd: ', LocalSubstitution('event.cmd[0]')])])),
        RegisterEventHandler(OnProcessExit(on_exit=[LogInfo(
            msg=['exited: ', LocalSubstitution("event.action.process_details['name']")])])),
    ])
"""


def test_an_event_handler_using_the_events_run_time_values_is_unchecked_not_an_error(tmp_path):
    # a reader's case: event.cmd[0] and event.action.process_details are real values at run
    # time; the stand-in event's empty ones made the file's valid code an IndexError and a
    # NoneType error (both engines)
    folder = package(tmp_path, "audit_events", ["launch"], {"launch/a.launch.py": RUN_TIME_EVENT_LAUNCH})
    launch = folder / "launch" / "a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert found(report, "PF301") == [], engine
        assert [(s, line) for s, _, line, _ in found(report, "PF311")] == [
            ("info", line_of(launch, "OnProcessStart(")),
            ("info", line_of(launch, "OnProcessExit(")),
        ], engine


STATIC_CONDITION_LAUNCH = """import os

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    model = os.environ['AUDIT_ROBOT_MODEL']
    return LaunchDescription([
        DeclareLaunchArgument('db', default_value='false'),
        Node(package='warehouse_ros_mongo', executable='mongo_wrapper_ros.py', condition=IfCondition(LaunchConfiguration('db')), arguments=[model]),
    ])
"""


def test_a_statically_checked_use_under_a_condition_names_it(tmp_path):
    # moveit2_tutorials' chomp_demo.launch.py (checked statically): warehouse_ros_mongo only with
    # db:=true; a database a supported setting needs stays an error, saying when it is needed
    folder = package(tmp_path, "audit_db", ["launch_ros"], {"launch/a.launch.py": STATIC_CONDITION_LAUNCH})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF305") == [
        (
            "error",
            "src/audit_db/launch/a.launch.py",
            line_of(folder / "launch" / "a.launch.py", "Node(package='warehouse_ros_mongo'"),
            "Node 'warehouse_ros_mongo' is used at run time but package.xml does not declare it "
            "(only with condition=IfCondition(LaunchConfiguration('db')))",
        )
    ]


DISTRO_BRANCH_LAUNCH = """import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription


def generate_launch_description():
    model = os.environ['AUDIT_ROBOT_MODEL']
    if os.environ.get('ROS_DISTRO') == 'humble':
        simulator = get_package_share_directory('gazebo_ros')
    else:
        simulator = get_package_share_directory('ros_gz_sim')
    return LaunchDescription([])
"""


def test_a_branch_on_ros_distro_in_a_file_checked_statically_is_taken_by_the_target(tmp_path):
    # a reader's case: which branch runs on $ROS_DISTRO is known for the target distro: the other
    # branch's package is no use there (gazebo_ros "not released for jazzy" was a PF108 error)
    folder = package(tmp_path, "audit_distro", ["launch"], {"launch/a.launch.py": DISTRO_BRANCH_LAUNCH})
    launch = folder / "launch" / "a.launch.py"
    for distro, used in (("jazzy", "ros_gz_sim"), ("humble", "gazebo_ros")):
        _, report = verify_report(tmp_path, "--no-cache", "--distro", distro)
        assert found(report, "PF108") == [], distro
        assert [(s, line) for s, _, line, _ in found(report, "PF305")] == [
            ("error", line_of(launch, f"'{used}'"))
        ], distro


HANDLER_OWN_BUG_LAUNCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess, RegisterEventHandler
from launch.event_handlers import OnProcessExit
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import Node


def generate_launch_description():
    second = PythonExpression(["'", LaunchConfiguration('names'), "'.split(',')[1]"])
    sleeper = ExecuteProcess(cmd=['sleep', '1'], name='sleeper')
    return LaunchDescription([
        DeclareLaunchArgument('names', default_value='robot1'),
        sleeper,
        RegisterEventHandler(OnProcessExit(target_action=sleeper, on_exit=[
            Node(package='demo_nodes_cpp', executable='talker', namespace=second)])),
    ])
"""


def test_a_handlers_own_bug_that_never_reads_the_event_stays_an_error(tmp_path):
    # a reader's case: 'robot1'.split(',')[1] fails whenever the event comes; the event is not read
    folder = package(
        tmp_path,
        "audit_handler",
        ["launch_ros", "demo_nodes_cpp"],
        {"launch/a.launch.py": HANDLER_OWN_BUG_LAUNCH},
    )
    launch = folder / "launch" / "a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert [(s, line) for s, _, line, _ in found(report, "PF301")] == [
            ("error", line_of(launch, "Node(package="))
        ], engine
        assert found(report, "PF311") == [], engine


def test_rviz2_rqt_and_gazebo_are_on_path_where_ros_is_sourced(tmp_path):
    # a reader's case: rviz2 installs to bin/ (install(TARGETS rviz2 DESTINATION bin)), as rqt and
    # Gazebo Classic's gazebo do: FindExecutable of them is PF311, as of ros2
    launch = FIND_EXECUTABLE_LAUNCH.replace("'ros2'", "'rviz2'").replace(
        "FindExecutable(name='python3')", "FindExecutable(name='gazebo')"
    )
    folder = package(tmp_path, "audit_viewer", ["launch"], {"launch/a.launch.py": launch})
    written = folder / "launch" / "a.launch.py"
    for engine, report in engine_reports(tmp_path).items():
        assert found(report, "PF301") == [], engine
        assert [(s, line) for s, _, line, _ in found(report, "PF311")] == [
            ("info", line_of(written, "'rviz2'")),
            ("info", line_of(written, "'gazebo'")),
        ], engine


def test_a_gate_on_a_system_library_no_declared_key_installs_is_a_warning(tmp_path):
    # a reader's case: find_package(CUDA QUIET) then if(CUDA_FOUND) ...: nothing declared installs
    # CUDA, so a clean machine skips the branch (Eigen3 with eigen declared is found: an error)
    cmake = (
        "cmake_minimum_required(VERSION 3.10)\nproject(audit_cuda NONE)\nfind_package(ament_cmake REQUIRED)\n"
        "find_package(CUDA QUIET)\nif(CUDA_FOUND)\n  find_package(tf2_eigen REQUIRED)\nendif()\nament_package()\n"
    )
    folder = package(tmp_path, "audit_cuda", [], {"CMakeLists.txt": cmake})
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert [(s, line) for s, _, line, _ in found(report, "PF109")] == [
        ("warning", line_of(folder / "CMakeLists.txt", "find_package(tf2_eigen"))
    ]


def test_a_dot_inside_a_joined_suffix_is_part_of_the_name(tmp_path):
    # a reader's case: ['cat', [PathJoin([share, 'urdf', 'robot']), '.urdf.']] names robot.urdf.,
    # which does not exist: only dots standing alone after the path are a sentence's punctuation
    launch = """from launch import LaunchDescription
from launch.actions import ExecuteProcess
from launch.substitutions import PathJoinSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    share = FindPackageShare('audit_dot')
    return LaunchDescription([
        ExecuteProcess(cmd=['cat', [PathJoinSubstitution([share, 'urdf', 'robot']), '.urdf.']]),
    ])
"""
    robot = '<?xml version="1.0"?>\n<robot name="r">\n  <link name="base_link"/>\n</robot>\n'
    package(tmp_path, "audit_dot", ["launch"], {"launch/a.launch.py": launch, "urdf/robot.urdf": robot})
    for engine, report in engine_reports(tmp_path).items():
        assert [(s, m.split(" does")[0]) for s, _, _, m in found(report, "PF303")] == [
            ("error", "share/audit_dot/urdf/robot.urdf.")
        ], engine


def test_an_include_with_a_comment_after_it_keeps_its_line(tmp_path):
    # a reader's case: '<xacro:include filename="$(find pkg)/urdf/arm.urdf"/> <!-- the arm -->'
    arm = ZERO_VELOCITY_ARM.replace('effort="10"', 'effort="0"').replace('velocity="0"', 'velocity="1"')
    package(tmp_path, "audit_arm_description", [], {"urdf/arm.urdf": arm})
    wrapper = (
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm">\n'
        '  <xacro:include filename="$(find audit_arm_description)/urdf/arm.urdf"/> <!-- the arm -->\n'
        '  <link name="world"/>\n'
        '  <joint name="world_joint" type="fixed"><parent link="world"/><child link="base_link"/></joint>\n</robot>\n'
    )
    folder = package(
        tmp_path, "audit_arm_config", ["audit_arm_description"], {"urdf/arm_config.urdf.xacro": wrapper}
    )
    assert (folder / "urdf" / "arm_config.urdf.xacro").is_file()
    _, report = verify_report(tmp_path, "--no-cache")
    # both packages verified: the finding is at the arm's own line, once (one cause, one finding);
    # the include line stands for a file of a package not verified here
    assert [(s, p) for s, p, _, _ in found(report, "PF605")] == [
        ("warning", "src/audit_arm_description/urdf/arm.urdf")
    ]


STR_CHOICES_LAUNCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import Command, FindExecutable, LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('robot_model', default_value='wxai', choices=('wxai')),
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[{'robot_description': ParameterValue(Command([
                 FindExecutable(name='xacro'), ' ',
                 PathJoinSubstitution([FindPackageShare('audit_choices'), 'urdf',
                                       LaunchConfiguration('robot_model')]), '.urdf.xacro']),
                 value_type=str)}]),
    ])
"""


def test_choices_given_as_one_string_are_that_word(tmp_path):
    # trossen_arm_description: choices=('wxai') is the str 'wxai'; launch's `value not in choices`
    # is then a substring test, which 'wxai' passes. Split into characters, the default "failed"
    # and w.urdf.xacro, x.urdf.xacro ... were missing files (both engines)
    robot = '<?xml version="1.0"?>\n<robot name="r">\n  <link name="base_link"/>\n</robot>\n'
    package(
        tmp_path,
        "audit_choices",
        ["launch_ros", "robot_state_publisher", "xacro"],
        {"launch/a.launch.py": STR_CHOICES_LAUNCH, "urdf/wxai.urdf.xacro": robot},
    )
    for engine, report in engine_reports(tmp_path).items():
        assert [d["code"] for d in report["diagnostics"] if d["severity"] == "error"] == [], engine
