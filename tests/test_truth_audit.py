"""Stop 25's audit of every error pkgforge gave on 46 real workspaces: each false error found,
reduced to the smallest package that shows it, and what pkgforge says now (the real pkgforge,
the real colcon discovery, the real xacro). The packages are written here, not copied."""

from __future__ import annotations

import json
from pathlib import Path

from conftest import at_least, line_of, verify_report
from test_truth_edges import BRINGUP_CMAKE, MOVEIT_CONFIG, manifest, write_package

from pkgforge.model.exports import brought_by


def package(
    tmp_path: Path, name: str, exec_depends: list[str], files: dict[str, str], **tags: list[str]
) -> Path:
    """A package `name` with these files (CMakeLists.txt and package.xml made unless given)."""
    folder = tmp_path / "src" / name
    text = manifest(name, "a package of the audit", exec_depends)
    for tag, names in tags.items():
        text = text.replace("  <export>", "".join(f"  <{tag}>{n}</{tag}>\n" for n in names) + "  <export>")
    folders = sorted({relative.split("/")[0] for relative in files if "/" in relative})
    cmake = BRINGUP_CMAKE.replace("choice_bringup", name)
    cmake = (
        cmake.replace("DIRECTORY launch", f"DIRECTORY {' '.join(folders)}")
        if folders
        else cmake.replace("install(DIRECTORY launch DESTINATION share/${PROJECT_NAME})\n", "")
    )
    made = {"CMakeLists.txt": cmake, "package.xml": text}
    write_package(folder, {**made, **files})
    return folder


def finding_cmake(project: str, *found: str) -> str:
    """An ament_cmake CMakeLists.txt that find_package()s these packages and installs nothing."""
    finds = "".join(f"find_package({name} REQUIRED)\n" for name in found)
    return (
        f"cmake_minimum_required(VERSION 3.10)\nproject({project} NONE)\nfind_package(ament_cmake REQUIRED)\n"
        f"{finds}ament_package()\n"
    )


def params_launch(package_name: str, relative: str) -> str:
    """A launch file starting a node of `package_name` with the parameter file `relative` of its share."""
    parts = ", ".join(repr(part) for part in relative.split("/"))
    return (
        "from launch import LaunchDescription\nfrom launch.substitutions import PathJoinSubstitution\n"
        "from launch_ros.actions import Node\nfrom launch_ros.substitutions import FindPackageShare\n\n\n"
        "def generate_launch_description():\n"
        f"    params = PathJoinSubstitution([FindPackageShare('{package_name}'), {parts}])\n"
        f"    return LaunchDescription([Node(package='{package_name}', executable='x', parameters=[params])])\n"
    )


def found(report: dict, code: str) -> list[tuple[str, str, int | None, str]]:
    return [
        (d["severity"], d["path"], d["line"], d["message"])
        for d in report["diagnostics"]
        if d["code"] == code
    ]


def test_a_find_package_a_declared_core_package_brings_is_a_warning(tmp_path):
    # clearpath_generator_common: find_package(ament_cmake_python) with only ament_cmake declared;
    # ros2/demos: find_package(rmw) with rclcpp declared. Both build on the build farm
    cmake = finding_cmake("audit_cpp", "ament_cmake_python", "rmw", "urdf")
    folder = package(tmp_path, "audit_cpp", [], {"CMakeLists.txt": cmake}, depend=["rclcpp"])
    cmakelists = folder / "CMakeLists.txt"
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, line) for s, _, line, _ in found(report, "PF109")] == [
        ("warning", line_of(cmakelists, "find_package(ament_cmake_python")),
        ("warning", line_of(cmakelists, "find_package(rmw")),
        ("error", line_of(cmakelists, "find_package(urdf")),  # nothing declared brings urdf
    ]
    messages = [m for _, _, _, m in found(report, "PF109")]
    assert messages[0].endswith("; ament_cmake, which it declares, brings it along, so it builds")
    assert messages[1].endswith("; rclcpp, which it declares, brings it along, so it builds")


def test_the_exports_table_against_the_core_packages_own_manifests():
    # read from ament_cmake's, rclcpp's, ament_lint_common's, ament_cmake_gmock's package.xml
    for name, declared in [
        ("ament_cmake_python", "ament_cmake"),
        ("ament_cmake", "ament_cmake_ros"),
        ("rmw", "rclcpp"),
        ("builtin_interfaces", "rclcpp"),
        ("ament_cmake_flake8", "ament_lint_common"),
        ("ament_cmake_gtest", "ament_cmake_gmock"),
    ]:
        for distro in ("humble", "jazzy", "rolling", "kilted"):
            assert brought_by(name, [declared], [distro]) == declared, (name, distro)
    assert brought_by("urdf", ["rclcpp", "ament_cmake"], []) is None
    assert brought_by("rclcpp", ["rmw"], []) is None  # a dependency, not a dependant


def test_a_find_package_declared_as_another_kind_is_a_warning(tmp_path):
    # lino linorobot2_gazebo: find_package of a package declared only as <exec_depend>
    cmake = finding_cmake("audit_kind", "urdf")
    folder = package(tmp_path, "audit_kind", ["urdf"], {"CMakeLists.txt": cmake})
    _, report = verify_report(tmp_path, "--no-cache")
    ((severity, _, line, message),) = found(report, "PF109")
    assert (severity, line) == ("warning", line_of(folder / "CMakeLists.txt", "find_package(urdf"))
    assert "`rosdep install` installs it, so it builds from source, but the release build" in message


NOT_EVALUATED = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from moveit_configs_utils import MoveItConfigsBuilder


def generate_launch_description():
    config = MoveItConfigsBuilder("audit").to_moveit_configs()
    return LaunchDescription([
        DeclareLaunchArgument("db", default_value="False"),
        Node(package="warehouse_ros_mongo", executable="mongo_wrapper_ros.py",
             condition=IfCondition(LaunchConfiguration("db"))),
    ])
"""


def test_a_node_under_a_condition_in_a_file_checked_statically_is_a_warning(tmp_path):
    # moveit_resources' demo.launch.py: warehouse_ros_mongo (humble only) runs only with db:=True,
    # and the file imports moveit_configs_utils (not installed here): checked statically
    folder = package(
        tmp_path,
        "audit_moveit",
        ["launch", "launch_ros", "moveit_configs_utils", "warehouse_ros_mongo"],
        {"launch/demo.launch.py": NOT_EVALUATED},
    )
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    launch = folder / "launch" / "demo.launch.py"
    node_uses = [f for f in found(report, "PF108") if f[1].endswith("demo.launch.py")]
    declared = [f for f in found(report, "PF108") if f[1].endswith("package.xml")]
    assert declared and all(s == "error" for s, *_ in declared)  # package.xml's declaration stays
    assert node_uses == []  # (a declared package's uses are its declaration's finding)
    assert launch.is_file()


def test_a_static_launch_use_under_a_condition_of_an_undeclared_package_is_a_warning(tmp_path):
    folder = package(
        tmp_path,
        "audit_moveit",
        ["launch", "launch_ros", "moveit_configs_utils"],
        {"launch/demo.launch.py": NOT_EVALUATED},
    )
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    launch = folder / "launch" / "demo.launch.py"
    ((severity, path, line, message),) = found(report, "PF108")
    assert (severity, path, line) == (
        "warning",
        "src/audit_moveit/launch/demo.launch.py",
        line_of(launch, 'Node(package="warehouse_ros_mongo"'),
    )
    assert message.endswith(
        '(only with condition=IfCondition(LaunchConfiguration("db")))'
    ) or message.endswith("(only with condition=IfCondition(LaunchConfiguration('db')))")


def test_a_file_uri_into_a_declared_package_not_installed_here_is_unchecked(tmp_path):
    # zed-ros2-wrapper: file://$(find zed_msgs)/meshes/zed.stl, zed_msgs declared, not installed here
    model = (
        '<?xml version="1.0"?>\n<robot name="audit" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base_link"><visual><geometry>\n'
        '    <mesh filename="file://$(find zed_msgs)/meshes/zed.stl"/>\n'
        "  </geometry></visual></link>\n</robot>\n"
    )
    package(tmp_path, "audit_zed", ["xacro", "zed_msgs"], {"urdf/robot.urdf.xacro": model})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF402") == []


def test_a_package_a_repos_repository_holds_is_no_distro_error(tmp_path):
    # c3pzero: c3pzero.repos imports piper_ros2, which holds piper_description
    folder = package(tmp_path, "audit_repos", ["piper_description"], {})
    (folder.parent / "audit.repos").write_text(
        "repositories:\n  piper_ros2:\n    type: git\n    url: https://github.com/example/piper_ros2.git\n"
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF108") == []
    (folder.parent / "audit.repos").unlink()  # without it, the name is unknown: an error
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, line) for s, _, line, _ in found(report, "PF108")] == [
        ("error", line_of(folder / "package.xml", "<exec_depend>piper_description"))
    ]


def test_a_dependency_back_on_a_package_that_depends_on_this_one_has_no_fix(tmp_path):
    # husky_description's xacro finds husky_control, which depends on husky_description:
    # declaring it is a cycle colcon refuses, so no safe fix adds it
    model = (
        '<?xml version="1.0"?>\n<robot name="audit" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base_link"/>\n'
        '  <gazebo><plugin filename="x.so" name="c"><parameters>$(find audit_control)/config/c.yaml'
        "</parameters></plugin></gazebo>\n</robot>\n"
    )
    description = package(tmp_path, "audit_description", ["xacro"], {"urdf/robot.urdf.xacro": model})
    package(tmp_path, "audit_control", ["audit_description"], {})
    _, report = verify_report(tmp_path, "--no-cache")
    (diagnostic,) = [
        d for d in report["diagnostics"] if d["code"] == "PF305" and d["package"] == "audit_description"
    ]
    assert (diagnostic["severity"], diagnostic["line"]) == (
        "warning",
        line_of(description / "urdf" / "robot.urdf.xacro", "$(find audit_control)"),
    )
    assert "declaring it here makes a cycle colcon refuses" in diagnostic["message"]
    assert diagnostic.get("fix") in (None, False)
    before = (description / "package.xml").read_text()
    from conftest import run_pkgforge

    run_pkgforge("fix", tmp_path, cwd=tmp_path)
    assert (description / "package.xml").read_text() == before


def test_the_audit_packages_report_is_json(tmp_path):
    # (the helper above writes valid packages: a clean one has no finding at all)
    package(tmp_path, "audit_clean", [], {})
    _, report = verify_report(tmp_path, "--no-cache")
    assert json.dumps(report) and [d for d in report["diagnostics"] if d["severity"] == "error"] == []


def test_an_imported_python_library_uses_its_rosdep_key(tmp_path):
    # the MoveIt tutorials' launch files `import yaml` and declare python3-yaml
    launch = "import cv2\nimport yaml\nfrom launch import LaunchDescription\n\n\ndef generate_launch_description():\n    return LaunchDescription([])\n"
    package(
        tmp_path,
        "audit_keys",
        ["launch", "python3-yaml", "python3-opencv", "python3-numpy"],
        {"launch/a.launch.py": launch},
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [m for _, _, _, m in found(report, "PF107")] == [
        "nothing in audit_keys uses exec_depend 'python3-numpy'"
    ]


def test_a_package_handed_to_the_files_own_lookup_function_is_a_use(tmp_path):
    # the MoveIt tutorials' load_yaml(package_name, file_path) calls get_package_share_directory
    # (package_name): load_yaml('moveit_resources_panda_moveit_config', ...) uses that package
    launch = (
        "import os\n\nfrom ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\n\n\n"
        "def load_file(package_name, file_path):\n"
        "    return os.path.join(get_package_share_directory(package_name), file_path)\n\n\n"
        "class Config:\n    def share(self, package):\n        return get_package_share_directory(package)\n\n\n"
        "def generate_launch_description():\n"
        "    load_file(file_path='config/a.yaml', package_name='moveit_resources_panda_moveit_config')\n"
        "    Config().share('moveit_resources_fanuc_moveit_config')\n"
        "    return LaunchDescription([])\n"
    )
    names = ["moveit_resources_panda_moveit_config", "moveit_resources_fanuc_moveit_config"]
    package(tmp_path, "audit_wrapper", ["launch", *names], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF107") == []


# --- a second reader's corrections of the audit's fixes --------------------------------------

PLAIN = '<?xml version="1.0"?>\n<robot name="audit"><link name="base_link"/></robot>\n'
XACRO = '<?xml version="1.0"?>\n<robot name="audit" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="base_link"/></robot>\n'


def jsp_launch(description: str, jsp_argument: str) -> str:
    return (
        "import os\nfrom ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\nfrom launch.substitutions import Command\n"
        "from launch_ros.actions import Node\nfrom launch_ros.parameter_descriptions import ParameterValue\n\n\n"
        "def generate_launch_description():\n"
        "    share = get_package_share_directory('audit_jsp')\n"
        f"    desc = {description}\n"
        "    return LaunchDescription([\n"
        "        Node(package='robot_state_publisher', executable='robot_state_publisher',\n"
        "             parameters=[{'robot_description': desc}]),\n"
        f"        Node(package='joint_state_publisher', executable='joint_state_publisher', arguments=[{jsp_argument}]),\n"
        "    ])\n"
    )


def test_jsp_given_a_plain_file_robot_state_publisher_does_not_get_stays_an_error(tmp_path):
    # robot_state_publisher runs xacro on robot.urdf.xacro; joint_state_publisher reads another,
    # plain file (a stale model), or a relative path it opens from wherever it is started
    xacro_run = (
        "ParameterValue(Command(['xacro ', os.path.join(share, 'urdf', 'robot.urdf.xacro')]), value_type=str)"
    )
    files = {
        "urdf/robot.urdf.xacro": XACRO,
        "urdf/plain.urdf": PLAIN,
        "launch/stale.launch.py": jsp_launch(xacro_run, "os.path.join(share, 'urdf', 'plain.urdf')"),
        "launch/relative.launch.py": jsp_launch(xacro_run, "'urdf/plain.urdf'"),
        "launch/same.launch.py": jsp_launch(
            "open(os.path.join(share, 'urdf', 'plain.urdf')).read()",
            "os.path.join(share, 'urdf', 'plain.urdf')",
        ),
    }
    package(
        tmp_path,
        "audit_jsp",
        ["launch", "launch_ros", "robot_state_publisher", "joint_state_publisher", "xacro"],
        files,
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert sorted((s, p.rsplit("/", 1)[-1]) for s, p, _, _ in found(report, "PF306")) == [
        ("error", "relative.launch.py"),
        ("error", "stale.launch.py"),
    ]  # same.launch.py: robot_state_publisher reads that very text


def test_a_repos_file_does_not_hide_a_typo_of_a_released_package(tmp_path):
    folder = package(tmp_path, "audit_typo", ["image_transprot"], {})
    (folder.parent / "deps.repos").write_text(
        "repositories:\n  image_common:\n    type: git\n    url: https://github.com/ros-perception/image_common.git\n"
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, line) for s, _, line, _ in found(report, "PF108")] == [
        ("error", line_of(folder / "package.xml", "<exec_depend>image_transprot"))
    ]


def test_a_node_whose_condition_holds_at_the_defaults_stays_an_error(tmp_path):
    launch = NOT_EVALUATED.replace("IfCondition", "UnlessCondition")  # db's default False: it runs
    package(
        tmp_path,
        "audit_moveit",
        ["launch", "launch_ros", "moveit_configs_utils"],
        {"launch/demo.launch.py": launch},
    )
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert [s for s, *_ in found(report, "PF108")] == ["error"]


def test_a_find_package_declared_only_as_doc_depend_stays_an_error(tmp_path):
    # rosdep's default dependency types are every kind but doc
    cmake = finding_cmake("audit_doc", "urdf")
    package(tmp_path, "audit_doc", [], {"CMakeLists.txt": cmake}, doc_depend=["urdf"])
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF109")] == ["error"]


def test_a_cycle_through_a_package_not_verified_has_no_fix_either(tmp_path):
    # cyc_description verified alone: cyc_control exec_depends cyc_middle, which test_depends on it
    model = PLAIN.replace(
        "<link",
        '<gazebo><plugin filename="x.so" name="c">$(find audit_control)/c.yaml</plugin></gazebo><link',
    )
    description = package(tmp_path, "audit_description", ["xacro"], {"urdf/robot.urdf.xacro": model})
    package(tmp_path, "audit_control", ["audit_middle"], {})
    package(tmp_path, "audit_middle", [], {}, test_depend=["audit_description"])
    _, report = verify_report(description, "--no-cache")
    assert [s for s, *_ in found(report, "PF305")] == ["warning"]
    before = (description / "package.xml").read_text()
    from conftest import run_pkgforge

    run_pkgforge("fix", description, cwd=description)
    assert (description / "package.xml").read_text() == before


# --- a fresh campaign on ten repositories never seen before (stop 25) -------------------------


def test_a_find_package_a_declared_workspace_package_brings_is_a_warning(tmp_path):
    # xarm_ros2: xarm_controller finds xarm_sdk, which its declared xarm_api <depend>s on
    cmake = finding_cmake("audit_controller", "audit_sdk")
    package(tmp_path, "audit_sdk", [], {})
    package(tmp_path, "audit_api", [], {}, depend=["audit_sdk"])
    package(tmp_path, "audit_controller", [], {"CMakeLists.txt": cmake}, depend=["audit_api"])
    _, report = verify_report(tmp_path, "--no-cache")
    ((severity, _, _, message),) = found(report, "PF109")
    assert severity == "warning" and message.endswith(
        "; audit_api, which it declares, brings it along, so it builds"
    )


def test_a_file_computed_data_files_install_is_found(tmp_path):
    # limo_ros2's voice_control: setup.py computes data_files; the old hint's glob broke the build.
    # It was a warning (an install rule pkgforge could not read may install it); setup.py is now
    # run as colcon reads it (issue 34), so what it installs is known: Plugins/ is installed
    setup = (
        "import os\nfrom glob import glob\nfrom setuptools import setup\n\n"
        "plugins = glob('Plugins/**/**.**')\n"
        "plugin_path = [(os.path.join('share', 'audit_py', os.path.dirname(c)), [c]) for c in plugins]\n"
        "setup(name='audit_py', version='0.1.0', packages=[],\n"
        "      data_files=[('share/ament_index/resource_index/packages', ['resource/audit_py']),\n"
        "                  ('share/audit_py', ['package.xml']), ('share/audit_py', glob('launch/*.launch.py')),\n"
        "                  *plugin_path])\n"
    )
    launch = (
        "import os\nfrom ament_index_python.packages import get_package_share_path\n"
        "from launch import LaunchDescription\nfrom launch.actions import DeclareLaunchArgument\n"
        "from launch.substitutions import LaunchConfiguration\nfrom launch_ros.actions import Node\n\n\n"
        "def generate_launch_description():\n"
        "    plugin_path = os.path.join(get_package_share_path('audit_py'), 'Plugins')\n"
        "    declare = DeclareLaunchArgument(name='plugin_path', default_value=plugin_path)\n"
        "    node = Node(package='audit_py', executable='voice',\n"
        "                parameters=[{'plugin_path': LaunchConfiguration('plugin_path', default=declare)}])\n"
        "    return LaunchDescription([declare, node])\n"
    )
    folder = tmp_path / "src" / "audit_py"
    text = manifest("audit_py", "python", ["launch", "launch_ros"]).replace("ament_cmake", "ament_python")
    write_package(
        folder,
        {
            "package.xml": text,
            "setup.py": setup,
            "resource/audit_py": "",
            "launch/a.launch.py": launch,
            "Plugins/test/one.py": "",
        },
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF302") == [] and found(report, "PF206") == []


def test_a_package_named_by_an_unset_variable_is_environment_unset(tmp_path):
    # dobot: get_package_share_directory(os.getenv('DOBOT_TYPE') + '_moveit') and a model path
    # 'urdf/None_robot.xacro' were PF304 and PF301 errors; with the variable set, none
    launch = (
        "import os\nfrom ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\n\n\ndef generate_launch_description():\n"
        "    robot = os.getenv('PKGFORGE_TEST_DOBOT_TYPE')\n"
        "    config = get_package_share_directory(f'{robot}_moveit')\n"
        "    model = open(os.path.join(get_package_share_directory('audit_env'), f'{robot}_robot.xacro')).read()\n"
        "    return LaunchDescription([])\n"
    )
    package(tmp_path, "audit_env", ["launch"], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    assert [d["code"] for d in report["diagnostics"] if d["severity"] == "error"] == []
    # warnings naming the variable (the None is not proven to come from it: a second reader's
    # case had an unrelated dict.get() give it), not silence and not errors
    said = sorted((d["code"], d["severity"]) for d in report["diagnostics"] if "None in it" in d["message"])
    assert said == [("PF301", "warning"), ("PF304", "warning")]
    assert all(
        "PKGFORGE_TEST_DOBOT_TYPE is not set here" in d["message"]
        for d in report["diagnostics"]
        if "None in it" in d["message"]
    )


def test_a_rosinstall_file_brings_its_repositories_from_source(tmp_path):
    # ROBOTIS-OP3: .robotis_op3.rosinstall lists robotis_controller_msgs (built from source)
    folder = package(tmp_path, "audit_op3", ["robotis_controller_msgs"], {})
    (folder.parent / ".audit.rosinstall").write_text(
        "- git: {local-name: robotis_controller_msgs , uri: 'https://github.com/ROBOTIS-GIT/ROBOTIS-Framework-msgs.git', version: master}\n"
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF108") == []


# --- a second reader's corrections of the fresh campaign's fixes ------------------------------


def test_a_commented_out_or_ros1_only_export_brings_nothing_along(tmp_path):
    cmake = finding_cmake("audit_controller", "audit_sdk")
    package(tmp_path, "audit_sdk", [], {})
    api = package(tmp_path, "audit_api", [], {})
    text = (api / "package.xml").read_text()
    (api / "package.xml").write_text(
        text.replace(
            "  <export>",
            '  <!-- <depend>audit_sdk</depend> -->\n  <depend condition="$ROS_VERSION == 1">audit_sdk</depend>\n  <export>',
        )
    )
    package(tmp_path, "audit_controller", [], {"CMakeLists.txt": cmake}, depend=["audit_api"])
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF109")] == ["error"]


def test_a_cached_run_sees_another_packages_dependency_change_kind(tmp_path):
    cmake = finding_cmake("audit_controller", "audit_sdk")
    package(tmp_path, "audit_sdk", [], {})
    api = package(tmp_path, "audit_api", [], {}, depend=["audit_sdk"])
    package(tmp_path, "audit_controller", [], {"CMakeLists.txt": cmake}, depend=["audit_api"])
    assert [s for s, *_ in found(verify_report(tmp_path)[1], "PF109")] == ["warning"]
    text = (api / "package.xml").read_text()
    (api / "package.xml").write_text(
        text.replace("<depend>audit_sdk</depend>", "<test_depend>audit_sdk</test_depend>")
    )
    assert [s for s, *_ in found(verify_report(tmp_path)[1], "PF109")] == ["error"]


def test_a_rule_that_installs_programs_cannot_install_a_missing_share_file(tmp_path):
    cmake = (
        "cmake_minimum_required(VERSION 3.10)\nproject(audit_programs NONE)\nfind_package(ament_cmake REQUIRED)\n"
        "install(DIRECTORY launch DESTINATION share/${PROJECT_NAME})\n"
        "install(PROGRAMS $ENV{EXTRA_SCRIPTS} DESTINATION lib/${PROJECT_NAME})\nament_package()\n"
    )
    launch = params_launch("audit_programs", "config/params.yaml")
    package(
        tmp_path,
        "audit_programs",
        ["launch", "launch_ros"],
        {"CMakeLists.txt": cmake, "launch/a.launch.py": launch, "config/params.yaml": "x: 1\n"},
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF302")] == ["error"]


# --- a second fresh campaign (ardupilot_gz, create3_sim, denso, Bumper-Bot, go2, neobotix, SO-ARM100,
# stretch_ros2) ------------------------------------------------------------------------------


def test_an_opaque_function_reading_a_declared_package_not_installed_here_is_unevaluated(tmp_path):
    # ardupilot_gz's launch_setup opens ardupilot_gazebo's model.sdf (declared, not installed here)
    launch = (
        "import os\nfrom ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\nfrom launch.actions import OpaqueFunction\n\n\n"
        "def setup(context):\n"
        f"    with open(os.path.join(get_package_share_directory('{MOVEIT_CONFIG}'), 'config', 'a.yaml')) as f:\n"
        "        f.read()\n"
        "    return []\n\n\n"
        "def generate_launch_description():\n    return LaunchDescription([OpaqueFunction(function=setup)])\n"
    )
    folder = package(tmp_path, "audit_opaque", ["launch", MOVEIT_CONFIG], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF301") == []
    ((severity, _, line, message),) = found(report, "PF311")
    assert (severity, line) == ("info", line_of(folder / "launch" / "a.launch.py", "OpaqueFunction(function"))
    assert message == (
        f"a.launch.py: OpaqueFunction reads files of {MOVEIT_CONFIG}, a package not installed here; "
        "what it starts is not checked"
    )


def test_a_build_export_depend_is_declared_for_run_time_too(tmp_path):
    # stretch_calibration: <build_export_depend>stretch_core</build_export_depend>, used by its launch
    launch = (
        "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n\n\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([Node(package='robot_state_publisher', executable='robot_state_publisher')])\n"
    )
    package(
        tmp_path,
        "audit_export",
        ["launch", "launch_ros"],
        {"launch/a.launch.py": launch},
        build_export_depend=["robot_state_publisher"],
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF305") == []


def test_a_long_path_in_an_action_failure_is_kept_whole():
    # ardupilot_gz: "No such file or directory: 'share/ardupilo.../'" named no file
    from pkgforge.checks.launch_load import _one_line

    path = "/dev/shm/pkgforge-tree-1/phantom/share/ardupilot_gazebo/models/iris_with_gimbal/model.sdf"
    assert _one_line(f"[Errno 2] No such file or directory: '{path}'").endswith(f"'{path}'")
    value = "x" * 100
    assert _one_line(f"cannot parse '{value}'") == f"cannot parse '{'x' * 60}...'"


def test_what_loading_records_holds_for_every_argument_setting(tmp_path):
    # denso, stretch, rox: a lookup at the top of generate_launch_description() was said to
    # happen "(only with sim:=true …)", the defaults, as if other settings skipped it (rviz2: what
    # nothing declared brings; robot_state_publisher brings tf2_ros, the lookup this had first)
    launch = (
        "from ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\nfrom launch.actions import DeclareLaunchArgument\n\n\n"
        "def generate_launch_description():\n"
        "    share = get_package_share_directory('rviz2')\n"
        "    return LaunchDescription([DeclareLaunchArgument('gui', default_value='true'),\n"
        "                              Node(package='robot_state_publisher', executable='robot_state_publisher')])\n"
    )
    launch = launch.replace("from launch.actions", "from launch_ros.actions import Node\nfrom launch.actions")
    package(
        tmp_path,
        "audit_load",
        ["launch", "launch_ros", "robot_state_publisher"],
        {"launch/a.launch.py": launch},
    )
    _, report = verify_report(tmp_path, "--no-cache")
    ((severity, _, _, message),) = found(report, "PF305")
    assert severity == "error" and message.endswith("is used at run time but package.xml does not declare it")


def test_an_empty_model_file_nothing_includes_is_no_robot(tmp_path):
    # rox_description's urdf/xacros/meca_wheel.xacro is 0 bytes in git: PF401 "Document is empty"
    package(
        tmp_path,
        "audit_empty",
        ["xacro"],
        {"urdf/robot.urdf": PLAIN, "urdf/xacros/empty.xacro": "", "urdf/xacros/blank.xacro": "\n  \n"},
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF401") == []


def test_a_display_of_an_rviz_config_no_launch_file_of_its_package_opens_stays_an_error(tmp_path):
    # (lowered for a while this stop: a second reader showed configs opened through ExecuteProcess,
    # a -d built from an argument, or another package's launch file; the package ships it)
    def config(plugin: str) -> str:
        return (
            "Panels: []\nVisualization Manager:\n  Class: ''\n  Displays:\n"
            f"    - Class: {plugin}\n      Enabled: true\n      Name: A\n  Global Options:\n    Fixed Frame: map\n"
        )

    launch = (
        "from launch import LaunchDescription\nfrom launch.substitutions import PathJoinSubstitution\n"
        "from launch_ros.actions import Node\nfrom launch_ros.substitutions import FindPackageShare\n\n\n"
        "def generate_launch_description():\n"
        "    rviz = PathJoinSubstitution([FindPackageShare('audit_rviz'), 'rviz', 'opened.rviz'])\n"
        "    return LaunchDescription([Node(package='rviz2', executable='rviz2', arguments=['-d', rviz])])\n"
    )
    package(
        tmp_path,
        "audit_rviz",
        ["launch", "launch_ros", "rviz2"],
        {
            "launch/a.launch.py": launch,
            "rviz/opened.rviz": config("nav2_rviz_plugins/ParticleCloud"),
            "rviz/unused.rviz": config("rviz_visual_tools/KeyTool"),
        },
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert sorted((s, p.rsplit("/", 1)[-1]) for s, p, _, _ in found(report, "PF305")) == [
        ("error", "opened.rviz"),
        ("error", "unused.rviz"),
    ]


# --- a second reader's corrections of the second campaign's fixes -----------------------------

LOADING_LAUNCH = (
    "from ament_index_python.packages import get_package_share_directory\n"
    "from launch import LaunchDescription\nfrom launch.actions import DeclareLaunchArgument\n"
    "from launch_ros.actions import Node\n\n\n"
    "def generate_launch_description():\n"
    "    share = get_package_share_directory('xacro')\n"
    "    typo = get_package_share_directory('audit_bto_typo')\n"
    "    return LaunchDescription([\n"
    "        DeclareLaunchArgument('use_sim', default_value='false'),\n"
    "        Node(package='audit_engines', executable='demo'),\n"
    "    ])\n"
)


def test_both_engines_say_loading_records_hold_for_every_setting(tmp_path):
    # the ros engine loads the file again for each other setting: those loads' records held
    # "only with use_sim:=true", and PF304 fell to a warning (the built-in engine: errors)
    from ros_prefix import make_prefix

    prefix, why = make_prefix("jazzy", tmp_path / "ros")
    package(tmp_path, "audit_engines", ["launch", "launch_ros"], {"launch/a.launch.py": LOADING_LAUNCH})
    said = {}
    for engine in ("builtin", "ros"):
        extra = ["--ros-prefix", str(prefix)] if engine == "ros" and prefix is not None else []
        if engine == "ros" and prefix is None:
            continue  # (no real launch library here: said by the engine tests too)
        _, report = verify_report(
            tmp_path, "--no-cache", "--distro", "jazzy", "--launch-engine", engine, *extra
        )
        said[engine] = sorted(
            (d["code"], d["severity"], d["message"])
            for d in report["diagnostics"]
            if d["code"] in ("PF304", "PF305")
        )
    assert [(code, severity) for code, severity, _ in said["builtin"]] == [
        ("PF304", "error"),
        ("PF305", "error"),
    ]
    assert all("only with" not in message for _, _, message in said["builtin"])
    if "ros" in said:
        assert said["ros"] == said["builtin"]


def test_an_actions_own_bug_after_another_action_read_a_package_not_installed_here_stays(tmp_path):
    launch = (
        "import os\nfrom ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\nfrom launch.actions import OpaqueFunction\n\n\n"
        "def read_params(context):\n"
        f"    path = os.path.join(get_package_share_directory('{MOVEIT_CONFIG}'), 'params.yaml')\n"
        "    try:\n        with open(path) as f:\n            f.read()\n    except OSError:\n        pass\n"
        "    return []\n\n\n"
        "def pick_robot(context):\n    robots = []\n    return [robots[0]]\n\n\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([OpaqueFunction(function=read_params), OpaqueFunction(function=pick_robot)])\n"
    )
    folder = package(tmp_path, "audit_two", ["launch", MOVEIT_CONFIG], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, line) for s, _, line, _ in found(report, "PF301")] == [
        ("error", line_of(folder / "launch" / "a.launch.py", "OpaqueFunction(function=read_params)"))
    ]


def test_another_packages_distro_condition_is_evaluated_for_the_target(tmp_path):
    cmake = finding_cmake("audit_c", "urdf")
    b = package(tmp_path, "audit_b", [], {})
    (b / "package.xml").write_text(
        (b / "package.xml")
        .read_text()
        .replace("  <export>", '  <depend condition="$ROS_DISTRO == humble">urdf</depend>\n  <export>')
    )
    c = package(tmp_path, "audit_c", [], {"CMakeLists.txt": cmake}, depend=["audit_b"])
    for where in (tmp_path, c):  # the workspace, and the package alone (audit_b not checked first)
        _, report = verify_report(where, "--no-cache", "--distro", "jazzy")
        assert [s for s, *_ in found(report, "PF109")] == ["error"]
        _, report = verify_report(where, "--no-cache", "--distro", "humble")
        assert [s for s, *_ in found(report, "PF109")] == ["warning"]


def test_an_unreadable_rule_installing_at_the_prefix_root_may_install_a_share_file(tmp_path):
    cmake = (
        "cmake_minimum_required(VERSION 3.10)\nproject(audit_root NONE)\nfind_package(ament_cmake REQUIRED)\n"
        "install(DIRECTORY launch DESTINATION share/${PROJECT_NAME})\n"
        "install(DIRECTORY ${EXTRA} DESTINATION .)\nament_package()\n"
    )
    launch = params_launch("audit_root", "config/x.yaml")
    package(
        tmp_path,
        "audit_root",
        ["launch", "launch_ros"],
        {"CMakeLists.txt": cmake, "launch/a.launch.py": launch, "config/x.yaml": "x: 1\n"},
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF302")] == ["warning"]


def test_a_manifest_with_a_defect_elsewhere_still_brings_its_dependencies(tmp_path):
    cmake = finding_cmake("audit_a", "urdf")
    b = package(tmp_path, "audit_b", [], {}, depend=["urdf"])
    (b / "package.xml").write_text(
        (b / "package.xml").read_text().replace("test@example.com", "test@example")
    )
    package(tmp_path, "audit_a", [], {"CMakeLists.txt": cmake}, depend=["audit_b"])
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF109")] == ["warning"]


def test_an_action_stopped_by_the_guards_refusal_is_no_load_error(tmp_path):
    # Automatic Addison's yahboom tutorial: an OpaqueFunction rewrites ros2_controllers.yaml in the
    # user's workspace; the guard refuses (PF316), and the PermissionError that ROS never raises
    # was a PF301 error too
    target = tmp_path / "elsewhere" / "ros2_controllers.yaml"
    target.parent.mkdir()
    target.write_text("a: 1\n")
    launch = (
        "from launch import LaunchDescription\nfrom launch.actions import OpaqueFunction\n\n\n"
        "def rewrite(context):\n"
        f"    with open({str(target)!r}, 'w') as f:\n"
        "        f.write('a: 2\\n')\n"
        "    return []\n\n\n"
        "def generate_launch_description():\n    return LaunchDescription([OpaqueFunction(function=rewrite)])\n"
    )
    package(tmp_path, "audit_guard", ["launch"], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF301") == []
    assert [s for s, *_ in found(report, "PF316")] == ["warning"]
    assert target.read_text() == "a: 1\n"


def test_gazebo_is_a_rosdep_key_on_humble(tmp_path):
    # a Gazebo Classic course for Humble: rosdep's base.yaml resolves 'gazebo' on Ubuntu jammy
    folder = package(tmp_path, "audit_gazebo", ["gazebo"], {})
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "humble")
    assert found(report, "PF108") == []
    _, report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy")
    assert [(s, line) for s, _, line, _ in found(report, "PF108")] == [
        ("error", line_of(folder / "package.xml", "<exec_depend>gazebo"))
    ]


def test_a_node_a_declared_package_brings_along_is_a_warning(tmp_path):
    # spot_ros2_control exec_depends spot_description, which exec_depends robot_state_publisher
    launch = (
        "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n\n\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([Node(package='robot_state_publisher', executable='robot_state_publisher')])\n"
    )
    package(tmp_path, "audit_desc", ["robot_state_publisher"], {})
    package(tmp_path, "audit_control", ["launch", "launch_ros", "audit_desc"], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    ((severity, _, _, message),) = found(report, "PF305")
    assert severity == "warning" and message.endswith("; audit_desc, which it declares, brings it along")


# --- a second reader's corrections of the third campaign's fixes ------------------------------


def test_a_provider_declared_under_a_condition_brings_nothing_for_sure(tmp_path):
    launch = (
        "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n\n\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([Node(package='robot_state_publisher', executable='robot_state_publisher')])\n"
    )
    package(tmp_path, "audit_prov", ["robot_state_publisher"], {})
    app = package(tmp_path, "audit_app", ["launch", "launch_ros"], {"launch/a.launch.py": launch})
    text = (app / "package.xml").read_text()
    (app / "package.xml").write_text(
        text.replace(
            "  <export>",
            '  <exec_depend condition="$ROS_DISTRO == humble">audit_prov</exec_depend>\n  <export>',
        )
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF305")] == ["error"]


def test_a_cycle_is_checked_before_what_a_package_brings_along(tmp_path):
    # the workspace's own controller_manager exec_depends app; app declares ros2_control (which
    # brings controller_manager): the fix would close a cycle
    launch = (
        "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n\n\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([Node(package='controller_manager', executable='ros2_control_node')])\n"
    )
    app = package(
        tmp_path, "audit_app", ["launch", "launch_ros", "ros2_control"], {"launch/a.launch.py": launch}
    )
    package(tmp_path, "controller_manager", ["audit_app"], {})
    _, report = verify_report(tmp_path, "--no-cache")
    (diagnostic,) = [d for d in report["diagnostics"] if d["code"] == "PF305" and d["package"] == "audit_app"]
    assert "makes a cycle colcon refuses" in diagnostic["message"]
    before = (app / "package.xml").read_text()
    from conftest import run_pkgforge

    run_pkgforge("fix", tmp_path, cwd=tmp_path)
    assert (app / "package.xml").read_text() == before


def test_a_read_while_loading_makes_an_actions_failure_a_warning(tmp_path):
    # worlds globbed from a package not installed here while loading, then worlds[0] in an
    # OpaqueFunction: maybe that read's consequence, maybe the action's own bug (a reader's
    # case: an unrelated names[0]): a PF301 warning that says so, neither an error nor an info
    launch = (
        "import glob\nimport os\nfrom ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\nfrom launch.actions import ExecuteProcess, OpaqueFunction\n\n\n"
        "def generate_launch_description():\n"
        f"    share = get_package_share_directory('{MOVEIT_CONFIG}')\n"
        "    worlds = sorted(glob.glob(os.path.join(share, 'worlds', '*.world')))\n\n"
        "    def setup(context):\n        return [ExecuteProcess(cmd=['gzserver', worlds[0]])]\n\n"
        "    return LaunchDescription([OpaqueFunction(function=setup)])\n"
    )
    package(tmp_path, "audit_glob", ["launch", MOVEIT_CONFIG], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    ((severity, _, _, message),) = found(report, "PF301")
    assert (
        severity == "warning" and f"(the file read files of {MOVEIT_CONFIG}, not installed here," in message
    )
    assert found(report, "PF311") == []


SIBLINGS = (
    "import glob\nimport os\nfrom ament_index_python.packages import get_package_share_directory\n"
    "from launch import LaunchDescription\nfrom launch.actions import ExecuteProcess, GroupAction, OpaqueFunction\n\n\n"
    "def generate_launch_description():\n"
    "    def a(context):\n"
    f"        return glob.glob(os.path.join(get_package_share_directory('{MOVEIT_CONFIG}'), 'w', '*'))\n\n"
    "    def b(context):\n"
    "        names = context.launch_configurations.get('names', '').split()\n"
    "        return [ExecuteProcess(cmd=['echo', names[0]])]\n\n"
    "    def setup(context):\n"
    "        return [OpaqueFunction(function=a), OpaqueFunction(function=b)]\n\n"
    "    return LaunchDescription([OpaqueFunction(function=setup)])\n"
)


def test_a_sibling_actions_read_does_not_excuse_an_actions_own_bug(tmp_path):
    folder = package(tmp_path, "audit_sib", ["launch", MOVEIT_CONFIG], {"launch/a.launch.py": SIBLINGS})
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, line) for s, _, line, _ in found(report, "PF301")] == [
        ("error", line_of(folder / "launch" / "a.launch.py", "return [OpaqueFunction(function=a)"))
    ]


def test_what_an_opaque_function_read_counts_for_what_it_returns_through_a_group(tmp_path):
    launch = SIBLINGS.replace(
        "    def a(context):\n"
        f"        return glob.glob(os.path.join(get_package_share_directory('{MOVEIT_CONFIG}'), 'w', '*'))\n\n",
        "",
    ).replace(
        "        return [OpaqueFunction(function=a), OpaqueFunction(function=b)]\n",
        f"        glob.glob(os.path.join(get_package_share_directory('{MOVEIT_CONFIG}'), 'w', '*'))\n"
        "        return [GroupAction([OpaqueFunction(function=b)])]\n",
    )
    package(tmp_path, "audit_group", ["launch", MOVEIT_CONFIG], {"launch/a.launch.py": launch})
    _, report = verify_report(tmp_path, "--no-cache")
    assert found(report, "PF301") == []
    assert [s for s, *_ in found(report, "PF311")] == ["info"]


def test_a_ros_version_condition_holds_on_every_distro(tmp_path):
    # <depend condition="$ROS_VERSION == 2">rclcpp</depend>: brings rmw along wherever ROS 2 is
    cmake = finding_cmake("audit_rv", "rmw")
    folder = package(tmp_path, "audit_rv", [], {"CMakeLists.txt": cmake})
    text = (folder / "package.xml").read_text()
    (folder / "package.xml").write_text(
        text.replace("  <export>", '  <depend condition="$ROS_VERSION == 2">rclcpp</depend>\n  <export>')
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF109")] == ["warning"]


def test_a_condition_on_a_variable_of_the_users_own_build_brings_nothing_for_sure(tmp_path):
    cmake = finding_cmake("audit_uv", "rmw")
    folder = package(tmp_path, "audit_uv", [], {"CMakeLists.txt": cmake})
    text = (folder / "package.xml").read_text()
    (folder / "package.xml").write_text(
        text.replace(
            "  <export>", '  <depend condition="$BUILD_TYPE == hardware">rclcpp</depend>\n  <export>'
        )
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF109")] == ["error"]


def test_an_included_files_reads_while_loading_count_as_loading_reads(tmp_path):
    sub = (
        "import glob\nimport os\nfrom ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\nfrom launch.actions import ExecuteProcess, OpaqueFunction\n\n\n"
        "def generate_launch_description():\n"
        f"    worlds = glob.glob(os.path.join(get_package_share_directory('{MOVEIT_CONFIG}'), 'w', '*'))\n\n"
        "    def setup(context):\n        return [ExecuteProcess(cmd=['gz', worlds[0]])]\n\n"
        "    return LaunchDescription([OpaqueFunction(function=setup)])\n"
    )
    top = (
        "import os\nfrom launch import LaunchDescription\nfrom launch.actions import IncludeLaunchDescription\n"
        "from launch.launch_description_sources import PythonLaunchDescriptionSource\n\n\n"
        "def generate_launch_description():\n"
        "    sub = os.path.join(os.path.dirname(__file__), 'sub.launch.py')\n"
        "    return LaunchDescription([IncludeLaunchDescription(PythonLaunchDescriptionSource(sub))])\n"
    )
    package(
        tmp_path,
        "audit_inc",
        ["launch", MOVEIT_CONFIG],
        {"launch/top.launch.py": top, "launch/sub.launch.py": sub},
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [s for s, *_ in found(report, "PF301")] == ["warning"]


def test_what_holds_on_every_target_distro_for_sure():
    # a comparison on a variable of the user's own build may be false; joined by `or` with one
    # that holds on ROS 2, the whole holds for sure (a reader's case: a false PF109 error)
    from pkgforge.model.manifest import Dependency

    def sure(condition: str, distros: tuple[str, ...]) -> bool:
        return Dependency("x", "depend", 1, condition).holds_on_every(distros)

    assert sure("$ROS_VERSION == 2 or $BUILD_TYPE == hardware", ())
    assert sure("hardware == $BUILD_TYPE or $ROS_VERSION == 2", ())
    assert not sure("$BUILD_TYPE == hardware", ("jazzy",))
    assert not sure("$ROS_VERSION == 2 and $BUILD_TYPE == hardware", ())
    assert sure("$ROS_VERSION == 2", ())
    assert not sure("$ROS_VERSION == 1", ("humble",))
    assert not sure("$ROS_DISTRO == humble", ())
    assert sure("$ROS_DISTRO == humble", ("humble",))
    assert not sure("$ROS_DISTRO == humble", ("humble", "jazzy"))


INCLUDED_ONLY_LAUNCH = """import yaml
from launch import LaunchDescription
from launch.actions import OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def launch_setup(context, *args, **kwargs):
    dump = LaunchConfiguration('config_dump', default='').perform(context)
    config = yaml.safe_load(dump) if dump else {}
    description = {'robot_description': config['robot_description']}
    return [Node(package='robot_state_publisher', executable='robot_state_publisher', parameters=[description])]


def generate_launch_description():
    return LaunchDescription([OpaqueFunction(function=launch_setup)])
"""

INCLUDER_LAUNCH = """import yaml
from launch import LaunchDescription
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import PathJoinSubstitution
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    dump = yaml.dump({'robot_description': '<robot name="r"><link name="base"/></robot>'})
    inner = IncludeLaunchDescription(
        PythonLaunchDescriptionSource(PathJoinSubstitution([FindPackageShare('audit_alone'), 'launch', '_inner.launch.py'])),
        launch_arguments={'config_dump': dump}.items(),
    )
    return LaunchDescription([inner])
"""


def test_a_file_made_to_be_included_failing_on_its_own_is_a_warning(tmp_path):
    # xarm_ros2's _robot_on_mbot_gazebo.launch.py reads moveit_config_dump, which only its
    # includer gives: launched alone it fails (ros2 launch too), through its includer it loads
    from ros_prefix import make_prefix

    prefix, _ = make_prefix("jazzy", tmp_path / "ros")
    folder = package(
        tmp_path,
        "audit_alone",
        ["launch", "launch_ros", "robot_state_publisher"],
        {"launch/_inner.launch.py": INCLUDED_ONLY_LAUNCH, "launch/outer.launch.py": INCLUDER_LAUNCH},
    )
    inner, outer = folder / "launch" / "_inner.launch.py", folder / "launch" / "outer.launch.py"
    for engine in ("builtin", "ros"):
        if engine == "ros" and prefix is None:
            continue  # (no real launch library here)
        extra = ["--ros-prefix", str(prefix)] if engine == "ros" else []
        _, report = verify_report(
            tmp_path, "--no-cache", "--distro", "jazzy", "--launch-engine", engine, *extra
        )
        assert found(report, "PF301") == [
            (
                "warning",
                "src/audit_alone/launch/_inner.launch.py",
                line_of(inner, "OpaqueFunction(function=launch_setup)"),
                "OpaqueFunction failed: KeyError: 'robot_description' (launched on its own; "
                f"outer.launch.py:{line_of(outer, 'IncludeLaunchDescription(')} includes it with "
                "config_dump and it loads there)",
            )
        ], engine
        hints = [d["hint"] for d in report["diagnostics"] if d["code"] == "PF301"]
        assert hints == [
            "launch it through outer.launch.py, or give its launch arguments defaults it runs with"
        ]


def test_a_file_made_to_be_included_failing_through_its_includer_too_stays_an_error(tmp_path):
    folder = package(
        tmp_path,
        "audit_alone",
        ["launch", "launch_ros", "robot_state_publisher"],
        {
            "launch/_inner.launch.py": INCLUDED_ONLY_LAUNCH,
            "launch/outer.launch.py": INCLUDER_LAUNCH.replace("{'robot_description':", "{'description':"),
        },
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(s, p, line) for s, p, line, _ in found(report, "PF301")] == [
        (
            "error",
            "src/audit_alone/launch/_inner.launch.py",
            line_of(folder / "launch" / "_inner.launch.py", "OpaqueFunction(function=launch_setup)"),
        )
    ]


# --- the exports table beyond the core: what bringup packages start (navigation2, urdf_launch) --


def nodes_launch(*packages: str) -> str:
    """A launch file starting one node of each of these packages, one per line."""
    nodes = "".join(f"        Node(package='{name}', executable='x'),\n" for name in packages)
    return (
        "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n\n\n"
        f"def generate_launch_description():\n    return LaunchDescription([\n{nodes}    ])\n"
    )


def test_the_exports_table_against_the_bringup_packages_own_manifests():
    # navigation2's, urdf_tutorial's, rviz2's, moveit's, ros_gz's package.xml: on every distro
    for name, declared in [
        ("nav2_bt_navigator", "navigation2"),
        ("nav2_controller", "navigation2"),
        ("nav2_rviz_plugins", "navigation2"),
        ("nav2_rviz_plugins", "nav2_bringup"),
        ("urdf_launch", "urdf_tutorial"),
        ("xacro", "urdf_launch"),
        ("rviz_common", "rviz2"),
        ("rviz_default_plugins", "rviz2"),
        ("moveit_ros_move_group", "moveit"),
        ("moveit_ros_planning", "moveit_ros_planning_interface"),
        ("ros_gz_bridge", "ros_gz"),
        ("ros_gz_sim", "ros_gz"),
        ("joint_state_publisher", "joint_state_publisher_gui"),
    ]:
        for distro in ("humble", "jazzy", "rolling", "kilted"):
            assert brought_by(name, [declared], [distro]) == declared, (name, distro)
    # Gazebo Classic's gazebo_ros_pkgs is part of humble only
    assert brought_by("gazebo_ros", ["gazebo_ros_pkgs"], ["humble"]) == "gazebo_ros_pkgs"
    assert brought_by("gazebo_ros", ["gazebo_ros_pkgs"], ["jazzy"]) is None
    assert brought_by("gazebo_ros", ["gazebo_ros_pkgs"], []) is None
    assert brought_by("robot_state_publisher", ["navigation2"], []) is None


def test_a_node_the_declared_navigation2_brings_is_a_warning(tmp_path):
    # andino_navigation, turtlebot4_navigation: navigation2 exec_depends every nav2_* package
    folder = package(
        tmp_path,
        "audit_nav",
        ["launch", "launch_ros", "navigation2"],
        {"launch/nav.launch.py": nodes_launch("nav2_bt_navigator")},
    )
    launch = folder / "launch" / "nav.launch.py"
    _, report = verify_report(tmp_path, "--no-cache")
    assert [(d["code"], d["severity"], d["path"], d["line"]) for d in at_least(report, "warning")] == [
        ("PF305", "warning", str(launch.relative_to(tmp_path)), line_of(launch, "nav2_bt_navigator"))
    ]
    ((_, _, _, message),) = found(report, "PF305")
    assert message == (
        "Node package 'nav2_bt_navigator' is used at run time but package.xml does not declare it; "
        "navigation2, which it declares, brings it along"
    )


def test_an_include_of_urdf_launch_with_urdf_tutorial_declared_is_no_error(tmp_path):
    # bme_gazebo_basics: urdf_launch's display.launch.py, which urdf_tutorial exec_depends on
    launch = (
        "from launch import LaunchDescription\nfrom launch.actions import IncludeLaunchDescription\n"
        "from launch.substitutions import PathJoinSubstitution\n"
        "from launch_ros.substitutions import FindPackageShare\n\n\n"
        "def generate_launch_description():\n"
        "    display = PathJoinSubstitution([FindPackageShare('urdf_launch'), 'launch', 'display.launch.py'])\n"
        "    return LaunchDescription([IncludeLaunchDescription(display)])\n"
    )
    folder = package(
        tmp_path, "audit_tutorial", ["launch", "launch_ros", "urdf_tutorial"], {"launch/a.launch.py": launch}
    )
    _, report = verify_report(tmp_path, "--no-cache")
    assert [d for d in report["diagnostics"] if d["severity"] == "error"] == []
    ((severity, _, line, message),) = found(report, "PF305")
    assert (severity, line) == (
        "warning",
        line_of(folder / "launch" / "a.launch.py", "FindPackageShare('urdf_launch')"),
    )
    assert message.endswith("; urdf_tutorial, which it declares, brings it along")


def test_a_node_nothing_declared_brings_stays_an_error(tmp_path):
    # navigation2 brings nav2_* but not robot_state_publisher; gazebo_ros_pkgs (Gazebo Classic)
    # brings gazebo_ros on humble, the one distro it is part of, so not on every active distro
    folder = package(
        tmp_path,
        "audit_none",
        ["launch", "launch_ros", "navigation2", "gazebo_ros_pkgs"],
        {"launch/a.launch.py": nodes_launch("nav2_controller", "robot_state_publisher", "gazebo_ros")},
    )
    launch = folder / "launch" / "a.launch.py"

    def pf305(*args: str) -> list[tuple[str, int | None]]:
        return [
            (s, line) for s, _, line, _ in found(verify_report(tmp_path, "--no-cache", *args)[1], "PF305")
        ]

    nav2, rsp, gazebo = (
        line_of(launch, name) for name in ("nav2_controller", "robot_state_publisher", "gazebo_ros")
    )
    assert pf305("--distro", "humble") == [("warning", nav2), ("error", rsp), ("warning", gazebo)]
    assert pf305() == [("warning", nav2), ("error", rsp), ("error", gazebo)]
