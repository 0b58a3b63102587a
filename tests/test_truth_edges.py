"""The edges of stop 23's false-error fixes (tests/test_realworld.py has the fixes themselves):
what a real defect next to each of them still is, found by a second reader of the change. Each
test runs the real pkgforge on a copy of a realworld fixture changed in one place."""

from __future__ import annotations

import shutil
from pathlib import Path

from conftest import FIXTURES, edit, line_of, run_pkgforge, verify_report

from pkgforge.model import references
from pkgforge.model.source import SourceFile

REALWORLD = FIXTURES / "realworld"


def copied(tmp_path: Path, name: str) -> Path:
    shutil.copytree(REALWORLD / name, tmp_path / "src" / name)
    return tmp_path / "src" / name


def errors(report: dict, package: str) -> list[tuple[str, str, int | None]]:
    return sorted(
        (d["name"], d["path"].removeprefix(f"src/{package}/"), d["line"])
        for d in report["diagnostics"]
        if d["package"] == package and d["severity"] == "error"
    )


def test_a_model_broken_whatever_it_is_given_stays_an_error(tmp_path):
    # fed to xacro only under a setting other than the defaults, and no other run of it worked
    package = copied(tmp_path, "choice_model_description")
    launch = package / "launch" / "display.launch.py"
    edit(
        launch,
        "from launch.actions import",
        "from launch.conditions import LaunchConfigurationEquals\nfrom launch.actions import",
    )
    edit(
        launch,
        "            executable='robot_state_publisher',",
        "            executable='robot_state_publisher',\n            condition=LaunchConfigurationEquals('robot_type', 'small'),",
    )
    _, report = verify_report(tmp_path, "--no-cache")
    # at the include whose filename the arguments build (issue 30: every finding at its line)
    include = line_of(package / "urdf" / "robot.urdf.xacro", "<xacro:include")
    assert errors(report, "choice_model_description") == [("xacro-error", "urdf/robot.urdf.xacro", include)]


def test_a_misspelt_module_next_to_a_folder_on_sys_path_is_a_load_error(tmp_path):
    package = copied(tmp_path, "driver_options_bringup")
    launch = package / "launch" / "camera.launch.py"
    edit(launch, "import rs_launch  # noqa: E402", "from launch_ros.actionz import Node  # noqa: E402")
    edit(launch, "rs_launch.declare_configurable_parameters(rs_launch.configurable_parameters)", "[]")
    _, report = verify_report(tmp_path, "--no-cache")
    assert ("launch-load-error", "launch/camera.launch.py", line_of(launch, "launch_ros.actionz")) in errors(
        report, "driver_options_bringup"
    )


def test_a_misspelt_program_run_while_loading_is_a_load_error(tmp_path):
    package = copied(tmp_path, "driver_options_bringup")
    launch = package / "launch" / "components.launch.py"
    edit(launch, "['ros2', 'component', 'types']", "['xacr0', '--version']")
    _, report = verify_report(tmp_path, "--no-cache")
    assert ("launch-load-error", "launch/components.launch.py", line_of(launch, "xacr0")) in errors(
        report, "driver_options_bringup"
    )


def test_a_package_without_a_model_of_its_own_keeps_its_find_errors(tmp_path):
    # its model files are for other packages to include: what they find, their users need
    package = copied(tmp_path, "gazebo_option_description")
    (package / "urdf" / "robot.urdf.xacro").unlink()
    _, report = verify_report(tmp_path, "--no-cache")
    accessory = package / "urdf" / "accessories" / "lidar_mount.urdf.xacro"
    assert errors(report, "gazebo_option_description") == [
        ("missing-exec-depend", "urdf/accessories/lidar_mount.urdf.xacro", line_of(accessory, "$(find")),
    ]


def test_a_template_name_in_the_parents_own_launch_file_is_still_unknown(tmp_path):
    package = copied(tmp_path, "template_kit")
    (package / "launch").mkdir()
    shutil.copy(package / "project_bringup" / "launch" / "project_bringup.launch.py", package / "launch")
    edit(
        package / "CMakeLists.txt",
        "install(DIRECTORY project_bringup",
        "install(DIRECTORY launch project_bringup",
    )
    _, report = verify_report(tmp_path, "--no-cache")
    launch = package / "launch" / "project_bringup.launch.py"
    assert errors(report, "template_kit") == [
        (
            "unknown-package",
            "launch/project_bringup.launch.py",
            line_of(launch, "FindPackageShare('project_bringup')"),
        )
    ]


def test_an_added_repos_file_is_seen_by_a_cached_run(tmp_path):
    copied(tmp_path, "source_deps_description")
    first = verify_report(tmp_path, "--distro", "jazzy")[1]
    assert [d["name"] for d in first["diagnostics"] if d["severity"] == "error"] == ["package-not-in-distro"]
    (tmp_path / "src" / "deps.repos").write_text(
        "repositories:\n  create_driver:\n    type: git\n    url: https://example.com/c.git\n    version: main\n"
    )
    second = verify_report(tmp_path, "--distro", "jazzy")[1]
    assert [d for d in second["diagnostics"] if d["severity"] == "error"] == []


def test_a_repos_file_past_the_parsers_depth_is_no_internal_error(tmp_path):
    copied(tmp_path, "source_deps_description")
    (tmp_path / "src" / "deep.repos").write_text("[" * 20000)
    result = run_pkgforge("verify", tmp_path, "--no-cache", "--distro", "jazzy", cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "internal error" not in result.stdout + result.stderr


def test_a_launch_argument_larger_than_a_pipe_share_is_evaluated(tmp_path):
    # requests sent ahead to a busy worker stay small; a larger one waits for it to be idle
    copied(tmp_path, "choice_model_description")
    copied(tmp_path, "driver_options_bringup")
    _, report = verify_report(tmp_path, "--no-cache", "--launch-arg", "note:=" + "x" * 40000)
    assert errors(report, "choice_model_description") == []


def test_a_xacro_condition_that_holds_at_the_defaults_is_no_condition(tmp_path):
    text = (
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="sim" default="true"/>\n'
        '  <xacro:arg name="gz" default="false"/>\n'
        '  <xacro:if value="$(arg sim)"><a f="$(find p_sim)/x"/></xacro:if>\n'
        '  <xacro:unless value="$(arg gz)"><a f="$(find p_not_gz)/x"/></xacro:unless>\n'
        '  <xacro:if value="true"><a f="$(find p_true)/x"/></xacro:if>\n'
        '  <xacro:if value="$(arg gz)"><a f="$(find p_gz)/x"/></xacro:if>\n'
        '  <xacro:if value="${x}"><a f="$(find p_property)/x"/></xacro:if>\n'
        '  <xacro:if value="$(arg sim)"><xacro:if value="$(arg gz)"><a f="$(find p_both)/x"/></xacro:if></xacro:if>\n'
        "</robot>\n"
    )
    path = tmp_path / "robot.urdf.xacro"
    path.write_text(text)
    found = {r.package: r.condition for r in references.scan(SourceFile(path, text))}
    assert found == {
        "p_sim": None,
        "p_not_gz": None,
        "p_true": None,
        "p_gz": "if $(arg gz)",
        "p_property": "if ${x}",
        "p_both": "if $(arg gz)",
    }


BRINGUP_CMAKE = """cmake_minimum_required(VERSION 3.10)
project(choice_bringup NONE)
find_package(ament_cmake REQUIRED)
install(DIRECTORY launch DESTINATION share/${PROJECT_NAME})
ament_package()
"""


def manifest(name: str, description: str, exec_depends: list[str]) -> str:
    """A format-3 ament_cmake package.xml with these run-time dependencies."""
    depends = "".join(f"  <exec_depend>{d}</exec_depend>\n" for d in exec_depends)
    return f"""<?xml version="1.0"?>
<package format="3">
  <name>{name}</name>
  <version>0.1.0</version>
  <description>{description}</description>
  <maintainer email="test@example.com">Test Maintainer</maintainer>
  <license>Apache-2.0</license>
  <buildtool_depend>ament_cmake</buildtool_depend>
{depends}  <export><build_type>ament_cmake</build_type></export>
</package>
"""


BRINGUP_XML = manifest(
    "choice_bringup",
    "includes choice_model_description's display launch",
    ["choice_model_description", "launch", "launch_ros"],
)
BRINGUP_LAUNCH = """from launch import LaunchDescription
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import PathJoinSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    display = PathJoinSubstitution([FindPackageShare('choice_model_description'), 'launch', 'display.launch.py'])
    return LaunchDescription([
        IncludeLaunchDescription(PythonLaunchDescriptionSource([display])),
    ])
"""


def write_package(folder: Path, files: dict[str, str]) -> None:
    """A package made of these files (relative path → text)."""
    for relative, text in files.items():
        (folder / relative).parent.mkdir(parents=True, exist_ok=True)
        (folder / relative).write_text(text)


def model_and_bringup(tmp_path: Path, old: str, new: str) -> Path:
    """choice_model_description with `old` changed to `new` in its arm, and choice_bringup, which
    includes its display launch file (that runs xacro on the model); the bringup's launch file."""
    edit(copied(tmp_path, "choice_model_description") / "urdf" / "arms" / "big_7.xacro", old, new)
    bringup = tmp_path / "src" / "choice_bringup"
    write_package(
        bringup,
        {
            "CMakeLists.txt": BRINGUP_CMAKE,
            "package.xml": BRINGUP_XML,
            "launch/bringup.launch.py": BRINGUP_LAUNCH,
        },
    )
    return bringup / "launch" / "bringup.launch.py"


def test_a_model_another_packages_launch_runs_is_found_once_at_its_own_line(tmp_path):
    # arduinobot_bringup includes arduinobot_description's launch file, which runs xacro: the
    # bringup's diagnostics on that model pointed into pkgforge's temporary install tree
    launch = model_and_bringup(
        tmp_path,
        "    </link>",
        "    </link>\n"
        '    <joint name="j1" type="fixed"><parent link="base_link"/><child link="link1"/></joint>\n'
        '    <link name="link1"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>',
    )
    _, report = verify_report(tmp_path, "--no-cache")
    # both packages verified: the finding is at the link's line in the description's model, said
    # once (one cause, one finding); the bringup's include line stands for a model of a package not
    # verified here
    placed = sorted(
        (d["package"], d["path"].split("/")[1])
        for d in report["diagnostics"]
        if d["name"] == "collision-without-inertial"
    )
    assert placed == [("choice_model_description", "choice_model_description")]
    assert launch.is_file()


def test_a_test_subdirectory_find_package_hints_test_depend(tmp_path):
    # gz_ros2_control_tests: add_subdirectory(tests) under if(BUILD_TESTING), the package found
    # there declared only as <exec_depend>: the build gets it as a <test_depend>
    package = copied(tmp_path, "choice_model_description")
    edit(
        package / "CMakeLists.txt",
        "ament_package()",
        "if(BUILD_TESTING)\n  add_subdirectory(tests)\nendif()\nament_package()",
    )
    (package / "tests").mkdir()
    (package / "tests" / "CMakeLists.txt").write_text("find_package(launch_testing_ament_cmake REQUIRED)\n")
    edit(
        package / "package.xml",
        "  <exec_depend>xacro</exec_depend>",
        "  <exec_depend>xacro</exec_depend>\n  <exec_depend>launch_testing_ament_cmake</exec_depend>",
    )
    _, report = verify_report(tmp_path, "--no-cache")
    (found,) = [d for d in report["diagnostics"] if d["name"] == "find-package-undeclared"]
    assert (found["path"], found["line"]) == ("src/choice_model_description/tests/CMakeLists.txt", 1)
    assert found["hint"].startswith("add <test_depend>launch_testing_ament_cmake</test_depend>")


FLAGS_XML = manifest(
    "flags_description",
    "flags written True/False, and a model given its xacro arguments in Python",
    ["ament_index_python", "launch", "launch_ros", "robot_state_publisher", "xacro"],
)
# andino's rosbag_record.launch.py: default_value='True' and PythonExpression(['not ', flag])
FLAGS_RECORD = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, LogInfo
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration, PythonExpression


def generate_launch_description():
    mcap = LaunchConfiguration('mcap_format')
    return LaunchDescription([
        DeclareLaunchArgument('mcap_format', default_value='True'),
        LogInfo(msg='sqlite3', condition=IfCondition(PythonExpression(['not ', mcap]))),
    ])
"""
# andino's spawn_robot.launch.py: xacro.process_file(path, mappings={...}) in the launch file
FLAGS_SPAWN = """import os

import xacro
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    path = os.path.join(get_package_share_directory('flags_description'), 'urdf', 'robot.urdf.xacro')
    description = xacro.process_file(path, mappings={'wheels': 'four'}).toxml()
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[{'robot_description': description}]),
    ])
"""
FLAGS_MODEL = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="flags">
  <!-- no xacro:arg: the caller must give it (andino_gz_classic.xacro's use_gazebo_ros_control) -->
  <link name="base_$(arg wheels)">
    <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
  </link>
</robot>
"""


def test_true_false_flags_and_xacro_arguments_given_in_python(tmp_path):
    cmake = BRINGUP_CMAKE.replace("choice_bringup", "flags_description")
    write_package(
        tmp_path / "src" / "flags_description",
        {
            "CMakeLists.txt": cmake.replace("DIRECTORY launch", "DIRECTORY launch urdf"),
            "package.xml": FLAGS_XML,
            "launch/record.launch.py": FLAGS_RECORD,
            "launch/spawn.launch.py": FLAGS_SPAWN,
            "urdf/robot.urdf.xacro": FLAGS_MODEL,
        },
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "flags_description") == []


def test_another_packages_model_names_no_mesh_package_for_this_one(tmp_path):
    # andino_navigation runs andino_gz_classic's model, whose meshes are andino_description's:
    # the model's own package must declare them, and its own verification says so
    model_and_bringup(
        tmp_path,
        '<geometry><box size="0.1 0.1 0.1"/></geometry>',
        '<geometry><mesh filename="package://velodyne_description/meshes/VLP16_base_1.dae"/></geometry>',
    )
    _, report = verify_report(tmp_path, "--no-cache")
    undeclared = [
        (d["package"], d["message"]) for d in report["diagnostics"] if d["name"] == "missing-exec-depend"
    ]
    assert [p for p, m in undeclared if "velodyne_description" in m] == ["choice_model_description"]


def test_a_path_join_that_starts_a_longer_name_is_no_missing_file(tmp_path):
    # interbotix: default_value=[PathJoinSubstitution([share, 'config', 'motor_specs_']),
    # LaunchConfiguration('robot_model'), '.yaml']: the join alone names no file
    package = copied(tmp_path, "choice_model_description")
    launch = package / "launch" / "display.launch.py"
    edit(
        launch,
        "        DeclareLaunchArgument('dof', default_value='7'),",
        "        DeclareLaunchArgument('dof', default_value='7'),\n"
        "        DeclareLaunchArgument('arm_file', default_value=[PathJoinSubstitution(\n"
        "            [FindPackageShare('choice_model_description'), 'urdf', 'arms', 'big_']), '7.xacro']),",
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [d for d in report["diagnostics"] if d["name"] == "missing-file"] == []


def test_a_scheduled_build_of_another_branch_targets_no_distro(tmp_path):
    # Universal_Robots_ROS2_Driver on main: humble-binary-main.yml runs on a schedule only and
    # checks out the humble branch (ref_for_scheduled_build); main itself is built for rolling
    from pkgforge.model.distro_data import ci_distros

    workflows = tmp_path / ".github" / "workflows"
    workflows.mkdir(parents=True)
    (workflows / "humble-binary-main.yml").write_text(
        "on:\n  workflow_dispatch:\n  schedule:\n    - cron: '03 5 * * *'\n"
        "jobs:\n  humble:\n    uses: ./.github/workflows/reusable_ici.yml\n"
        "    with:\n      ros_distro: humble\n      ref_for_scheduled_build: humble\n"
    )
    (workflows / "rolling-binary-main.yml").write_text(
        "on:\n  push:\n    branches: [main]\n  schedule:\n    - cron: '13 4 * * *'\n"
        "jobs:\n  rolling:\n    uses: ./.github/workflows/reusable_ici.yml\n"
        "    with:\n      ros_distro: rolling\n      ref_for_scheduled_build: main\n"
    )
    assert ci_distros(tmp_path) == ("rolling",)


SHUTDOWN_AND_SDF = """import os

from launch import LaunchDescription
from launch.actions import OpaqueFunction, RegisterEventHandler
from launch.event_handlers import OnShutdown
from launch.substitutions import Command, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    world = '/nonexistent-pkgforge-test/world.sdf'  # written by a process at run time
    sdf = PathJoinSubstitution([FindPackageShare('choice_model_description'), 'urdf', 'robot.sdf.xacro'])
    return LaunchDescription([
        Node(package='ros_gz_sim', executable='create', arguments=['-string', Command(['xacro ', sdf])]),
        RegisterEventHandler(OnShutdown(on_shutdown=[OpaqueFunction(function=lambda _: os.remove(world))])),
    ])
"""


SDF_MODEL = """<?xml version="1.0"?>
<sdf version="1.8" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <model name="m"><link name="base"/></model>
</sdf>
"""


def test_a_shutdown_function_and_an_sdf_through_xacro_are_no_errors(tmp_path):
    # nav2_minimal_tb4_sim: an OnShutdown OpaqueFunction removes a file a process wrote; nav2's
    # gz_waffle.sdf.xacro is an SDF model spawned in Gazebo, not a URDF
    package = copied(tmp_path, "choice_model_description")
    write_package(package, {"launch/gazebo.launch.py": SHUTDOWN_AND_SDF, "urdf/robot.sdf.xacro": SDF_MODEL})
    edit(
        package / "package.xml",
        "  <exec_depend>xacro</exec_depend>",
        "  <exec_depend>xacro</exec_depend>\n  <exec_depend>ros_gz_sim</exec_depend>",
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [e for e in errors(report, "choice_model_description") if e[1] != "urdf/robot.urdf.xacro"] == []


def test_a_python_library_declared_by_its_rosdep_key_is_not_installed_here(tmp_path):
    # usb_cam: camera.launch.py imports pydantic, declared as <exec_depend>python3-pydantic
    package = copied(tmp_path, "driver_options_bringup")
    for name in ("declared", "undeclared"):
        module = f"{name}_vendor_sdk"
        (package / "launch" / f"{name}.launch.py").write_text(
            f"import {module}  # noqa: F401\nfrom launch import LaunchDescription\n\n\n"
            "def generate_launch_description():\n    return LaunchDescription([])\n"
        )
    edit(
        package / "package.xml",
        "  <exec_depend>launch</exec_depend>",
        "  <exec_depend>launch</exec_depend>\n  <exec_depend>python3-declared-vendor-sdk</exec_depend>",
    )
    _, report = verify_report(tmp_path, "--no-cache")
    found = {(d["name"], d["path"].rsplit("/", 1)[-1]) for d in report["diagnostics"]}
    assert ("launch-unevaluated", "declared.launch.py") in found
    assert ("launch-load-error", "undeclared.launch.py") in found


def test_a_repos_file_at_the_root_of_a_repository_of_package_groups(tmp_path):
    # c3pzero: c3pzero.repos at the repository root, packages two folders below (c300/c300_bringup)
    target = tmp_path / "src" / "robot_repo" / "group" / "source_deps_description"
    shutil.copytree(REALWORLD / "source_deps_description", target)
    (tmp_path / "src" / "robot_repo" / "robot.repos").write_text(
        "repositories:\n  create_driver:\n    type: git\n    url: https://example.com/c.git\n    version: main\n"
    )
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert errors(report, "source_deps_description") == []


SRDF_MODEL = """<?xml version="1.0"?>
<robot name="choice" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <group name="gripper"><link name="finger"/></group>
</robot>
"""
MOVEIT_LAUNCH = """<launch>
  <node pkg="robot_state_publisher" exec="robot_state_publisher">
    <param name="robot_description_semantic"
           value="$(command 'xacro $(find-pkg-share choice_model_description)/urdf/robot.srdf.xacro')"/>
  </node>
</launch>
"""


def test_semantic_descriptions_and_undeclared_namespace_prefixes_are_no_invalid_urdf(tmp_path):
    # c3pzero_moveit_config's c3pzero.srdf.xacro (<robot>, no links); c300's xacro output with
    # gz:expressed_in and no xmlns:gz (tinyxml2, urdfdom's parser, knows no namespaces)
    package = copied(tmp_path, "choice_model_description")
    # c3pzero_moveit_config's demo.launch.xml: robot_description_semantic from xacro on it
    write_package(package, {"launch/moveit.launch.xml": MOVEIT_LAUNCH, "urdf/robot.srdf.xacro": SRDF_MODEL})
    # declared on the root of a file included inside an <xacro:if> (c300.urdf.xacro's gazebo
    # part): xacro leaves that declaration out of its output
    (package / "urdf" / "arms" / "gazebo.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" xmlns:gz="http://gazebosim.org/schema">\n'
        '  <gazebo><sensor name="imu"><pose gz:expressed_in="base_link">0 0 0 0 0 0</pose></sensor></gazebo>\n'
        "</robot>\n"
    )
    edit(
        package / "urdf" / "robot.urdf.xacro",
        "  <xacro:arm/>",
        '  <xacro:arm/>\n  <xacro:if value="true"><xacro:include filename="arms/gazebo.xacro"/></xacro:if>',
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [d for d in report["diagnostics"] if d["name"] == "urdf-invalid"] == []


def test_an_included_file_reading_the_robots_variable_is_no_load_error_of_the_includer(tmp_path):
    # turtlebot3_gazebo: empty_world.launch.py includes robot_state_publisher.launch.py, which
    # reads os.environ['TURTLEBOT3_MODEL'] (the robot's setup sets it)
    package = copied(tmp_path, "driver_options_bringup")
    launch = package / "launch"
    (launch / "model.launch.py").write_text(
        "import os\n\nfrom launch import LaunchDescription\n\n\ndef generate_launch_description():\n"
        "    model = os.environ['PKGFORGE_TEST_ROBOT_MODEL']\n    return LaunchDescription([])\n"
    )
    (launch / "world.launch.py").write_text(
        "import os\n\nfrom launch import LaunchDescription\nfrom launch.actions import IncludeLaunchDescription\n"
        "from launch.launch_description_sources import PythonLaunchDescriptionSource\n\n\n"
        "def generate_launch_description():\n"
        "    model = os.path.join(os.path.dirname(__file__), 'model.launch.py')\n"
        "    return LaunchDescription([IncludeLaunchDescription(PythonLaunchDescriptionSource(model))])\n"
    )
    _, report = verify_report(tmp_path, "--no-cache")
    found = {(d["name"], d["path"].rsplit("/", 1)[-1]) for d in report["diagnostics"]}
    assert ("launch-environment-unset", "model.launch.py") in found
    assert not {f for f in found if f[1] == "world.launch.py"}


STAND_IN_LAUNCH = """import os

import yaml
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription


def load_yaml(package_name, file_path):
    absolute_file_path = os.path.join(get_package_share_directory(package_name), file_path)
    try:
        with open(absolute_file_path) as file:
            return yaml.safe_load(file)
    except EnvironmentError:
        return None


def generate_launch_description():
    pipeline = {'move_group': {'planning_plugin': 'ompl_interface/OMPLPlanner'}}
    pipeline['move_group'].update(load_yaml('LOOKED_UP', 'config/ompl_planning.yaml'))
    return LaunchDescription([])
"""


def stand_in_package(tmp_path: Path, looked_up: str, exec_depends: list[str]) -> Path:
    """A package whose launch file reads a YAML file of `looked_up` the way doosan-robot2's
    dsr_moveit2.launch.py does (its own try returns None); the launch file."""
    folder = tmp_path / "src" / "stand_in_bringup"
    write_package(
        folder,
        {
            "CMakeLists.txt": BRINGUP_CMAKE.replace("choice_bringup", "stand_in_bringup"),
            "package.xml": manifest("stand_in_bringup", "reads another package's YAML", exec_depends),
            "launch/moveit.launch.py": STAND_IN_LAUNCH.replace("LOOKED_UP", looked_up),
        },
    )
    return folder / "launch" / "moveit.launch.py"


def test_a_load_failure_after_a_package_not_found_is_that_lookups_error(tmp_path):
    # doosan-robot2: moveit_config_m1013 is COLCON_IGNOREd; in ROS get_package_share_directory
    # raises PackageNotFoundError at the lookup; the stand-in folder let loading go on to a
    # TypeError (dict.update(None)) reported as PF301 at a line with nothing wrong on it
    launch = stand_in_package(tmp_path, "pkgforge_test_absent_config", ["launch", "python3-yaml"])
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "stand_in_bringup") == [
        (
            "unknown-package",
            "launch/moveit.launch.py",
            line_of(launch, "get_package_share_directory(package_name)"),
        )
    ]


def test_a_load_failure_with_every_package_found_stays_a_load_error(tmp_path):
    # the same file, its package found (the YAML file is not there): the TypeError is its own
    launch = stand_in_package(tmp_path, "stand_in_bringup", ["launch", "python3-yaml"])
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "stand_in_bringup") == [
        ("launch-load-error", "launch/moveit.launch.py", line_of(launch, ".update(load_yaml("))
    ]


def test_a_package_looked_up_in_an_ignored_folder_is_named_in_the_hint(tmp_path):
    # doosan-robot2's moveit_config_m1013 holds a COLCON_IGNORE: "not in the workspace" for colcon
    launch = stand_in_package(tmp_path, "pkgforge_test_absent_config", ["launch", "python3-yaml"])
    ignored = tmp_path / "src" / "configs" / "absent_config"
    write_package(
        ignored,
        {
            "package.xml": manifest("pkgforge_test_absent_config", "ignored", []),
            "CMakeLists.txt": BRINGUP_CMAKE,
        },
    )
    (tmp_path / "src" / "configs" / "COLCON_IGNORE").write_text("")
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "stand_in_bringup") == [
        (
            "unknown-package",
            "launch/moveit.launch.py",
            line_of(launch, "get_package_share_directory(package_name)"),
        )
    ]
    (unknown,) = [d for d in report["diagnostics"] if d["name"] == "unknown-package"]
    assert unknown["hint"] == (
        "its folder configs/absent_config is inside configs, which holds a COLCON_IGNORE, so colcon "
        "does not build it: delete that file to build it, or drop the lookup"
    )


MOVEIT_CONFIG = "moveit_resources_panda_moveit_config"  # released in every distro, not installed here


def test_a_load_failure_after_reading_a_declared_package_not_installed_here_is_unevaluated(tmp_path):
    # the MoveIt tutorials' load_yaml: the YAML file of a declared moveit config package, not
    # installed here, read as None, then dict.update(None): a TypeError that ROS never raises
    launch = stand_in_package(tmp_path, MOVEIT_CONFIG, ["launch", "python3-yaml", MOVEIT_CONFIG])
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "stand_in_bringup") == []
    (unevaluated,) = [d for d in report["diagnostics"] if d["code"] == "PF311"]
    assert (unevaluated["path"], unevaluated["line"]) == (
        "src/stand_in_bringup/launch/moveit.launch.py",
        line_of(launch, ".update(load_yaml("),
    )
    assert unevaluated["message"] == (
        f"moveit.launch.py reads files of {MOVEIT_CONFIG} while loading, a package not installed "
        "here; checked statically instead"
    )


def test_a_direct_read_of_a_declared_package_not_installed_here_is_unevaluated(tmp_path):
    launch = stand_in_package(tmp_path, MOVEIT_CONFIG, ["launch", "python3-yaml", MOVEIT_CONFIG])
    edit(launch, "    except EnvironmentError:\n        return None\n", "    finally:\n        pass\n")
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "stand_in_bringup") == []
    assert [(d["code"], d["line"]) for d in report["diagnostics"] if d["code"] == "PF311"] == [
        ("PF311", line_of(launch, "with open(absolute_file_path)"))
    ]


def test_a_defect_of_its_own_after_reading_a_package_not_installed_here_stays_a_load_error(tmp_path):
    launch = stand_in_package(tmp_path, MOVEIT_CONFIG, ["launch", "python3-yaml", MOVEIT_CONFIG])
    edit(launch, "pipeline['move_group'].update(", "print(")  # the read's None used harmlessly
    edit(launch, "    return LaunchDescription([])", "    return LaunchDescriptio([])")
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "stand_in_bringup") == [
        ("launch-load-error", "launch/moveit.launch.py", line_of(launch, "LaunchDescriptio("))
    ]


def test_a_type_error_of_its_own_after_a_package_not_found_stays_a_load_error(tmp_path):
    # doosan's dsr_control2.launch.py: Node() without executable= is a TypeError about no None
    launch = stand_in_package(tmp_path, "pkgforge_test_absent_config", ["launch", "python3-yaml"])
    edit(launch, "pipeline['move_group'].update(", "print(")
    edit(launch, "    return LaunchDescription([])", "    return LaunchDescription([len(5)])")
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "stand_in_bringup") == [
        ("launch-load-error", "launch/moveit.launch.py", line_of(launch, "len(5)")),
        (
            "unknown-package",
            "launch/moveit.launch.py",
            line_of(launch, "get_package_share_directory(package_name)"),
        ),
    ]


def bringup_with(tmp_path: Path, launch_text: str, exec_depends: list[str]) -> Path:
    """A package whose one launch file is `launch_text`; the launch file."""
    folder = tmp_path / "src" / "edge_bringup"
    write_package(
        folder,
        {
            "CMakeLists.txt": BRINGUP_CMAKE.replace("choice_bringup", "edge_bringup"),
            "package.xml": manifest("edge_bringup", "one launch file", exec_depends),
            "launch/edge.launch.py": launch_text,
        },
    )
    return folder / "launch" / "edge.launch.py"


def test_a_none_of_its_own_after_looking_up_a_package_not_installed_here_stays_a_load_error(tmp_path):
    # looked up, never read: the AttributeError is the file's (a second reader's case)
    launch = bringup_with(
        tmp_path,
        "from ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\n\nROBOTS = {'panda': 'panda.urdf'}\n\n\n"
        "def generate_launch_description():\n"
        f"    config = get_package_share_directory('{MOVEIT_CONFIG}')\n"
        "    urdf = ROBOTS.get('pandaa').upper()\n"
        "    return LaunchDescription([])\n",
        ["launch", MOVEIT_CONFIG],
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "edge_bringup") == [
        ("launch-load-error", "launch/edge.launch.py", line_of(launch, ".upper()"))
    ]


def test_a_lookup_in_a_helper_called_inside_a_try_is_caught_as_in_ros(tmp_path):
    # the helper's lookup raises to its caller's try in ROS: no unknown package, and the
    # IndexError after it is the file's own
    launch = bringup_with(
        tmp_path,
        "from ament_index_python.packages import PackageNotFoundError, get_package_share_directory\n"
        "from launch import LaunchDescription\n\n\ndef share_of(package):\n"
        "    return get_package_share_directory(package)\n\n\n"
        "def generate_launch_description():\n"
        "    try:\n        extra = share_of('pkgforge_test_optional_driver')\n"
        "    except PackageNotFoundError:\n        extra = None\n"
        "    worlds = [w for w in ('empty', 'house') if w == 'houses']\n"
        "    world = worlds[0]\n"
        "    return LaunchDescription([])\n",
        ["launch"],
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert errors(report, "edge_bringup") == [
        ("launch-load-error", "launch/edge.launch.py", line_of(launch, "worlds[0]"))
    ]


LOOKUP_LAUNCH = (
    "from ament_index_python.packages import get_package_share_directory\n"
    "from launch import LaunchDescription\n\n\ndef generate_launch_description():\n"
    "    share = get_package_share_directory('pkgforge_test_old_name')\n"
    "    return LaunchDescription([])\n"
)


def hint_of(report: dict) -> str:
    (unknown,) = [d for d in report["diagnostics"] if d["name"] == "unknown-package"]
    return str(unknown["hint"])


def test_colcons_own_install_folder_is_no_ignored_package(tmp_path):
    # a repository with no src/: an earlier colcon build left install/ (ignored by colcon) with
    # the old name's package.xml; deleting install/COLCON_IGNORE is no advice to give
    bringup_with(tmp_path, LOOKUP_LAUNCH, ["launch"])
    repository = tmp_path / "src"  # verified as the workspace: its packages and install/ side by side
    old = repository / "install" / "share" / "pkgforge_test_old_name"
    write_package(old, {"package.xml": manifest("pkgforge_test_old_name", "old", []), "CMakeLists.txt": ""})
    (repository / "install" / "COLCON_IGNORE").write_text("")
    (repository / "install" / ".colcon_install_layout").write_text("isolated\n")
    _, report = verify_report(repository, "--no-cache")
    assert hint_of(report) == "check the name against package.xml <name>"


def test_a_cached_run_sees_an_ignored_package_come_and_go(tmp_path):
    bringup_with(tmp_path, LOOKUP_LAUNCH, ["launch"])
    (tmp_path / "src" / "old" / "COLCON_IGNORE").parent.mkdir()
    (tmp_path / "src" / "old" / "COLCON_IGNORE").write_text("")
    assert hint_of(verify_report(tmp_path)[1]) == "check the name against package.xml <name>"
    write_package(
        tmp_path / "src" / "old" / "deep" / "pkg",
        {"package.xml": manifest("pkgforge_test_old_name", "old", []), "CMakeLists.txt": BRINGUP_CMAKE},
    )
    assert hint_of(verify_report(tmp_path)[1]).startswith(
        "its folder old/deep/pkg is inside old, which holds"
    )
    shutil.rmtree(tmp_path / "src" / "old" / "deep")
    assert hint_of(verify_report(tmp_path)[1]) == "check the name against package.xml <name>"
