"""Stop 26's false errors and misses found on real workspaces (xarm_ros2, crane_plus, husarion
ugv, spot_ros2, turtlebot3, a fourth campaign on ten repositories), each reduced to the smallest
packages that show it, verified with the real pkgforge, colcon discovery and xacro."""

from __future__ import annotations

from pathlib import Path

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
