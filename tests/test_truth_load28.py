"""Issue 28, class 2: a launch file that does not load (an ImportError such as FindPackageShare
from launch.substitutions, a SyntaxError, a NameError, an exception before
generate_launch_description returns) still names packages and files: they are read statically
and reported as they would be if it had loaded, each finding saying so. Through both launch
engines (the built-in one and the real launch libraries of humble and jazzy, tests/ros_prefix.py).
"""

from __future__ import annotations

import pytest
from conftest import line_of, verify_report
from ros_prefix import DISTROS, make_prefix
from test_truth_audit import package

NAME = "load_bot"
DEPENDS = ["launch", "launch_ros", "robot_state_publisher", "joint_state_publisher", "xacro"]
URDF = '<?xml version="1.0"?>\n<robot name="r">\n  <link name="base"/>\n</robot>\n'
CODES = {"PF301", "PF302", "PF303", "PF304", "PF305", "PF321", "PF322", "PF323"}
ENGINES = ("builtin", *DISTROS)

WRONG_IMPORT = """from launch import LaunchDescription
from launch.substitutions import FindPackageShare, PathJoinSubstitution
from launch_ros.actions import Node


def generate_launch_description():
    model = PathJoinSubstitution([FindPackageShare('load_bot'), 'urdf', 'absent.urdf'])
    return LaunchDescription([
        Node(package='joy', executable='joy_node'),
        Node(package='load_bot_typo', executable='x'),
        Node(package='robot_state_publisher', executable='robot_state_publisher', arguments=[model]),
    ])
"""
# the nearest case: the same import error, every reference sound
WRONG_IMPORT_CLEAN = """from launch import LaunchDescription
from launch.substitutions import FindPackageShare, PathJoinSubstitution
from launch_ros.actions import Node


def generate_launch_description():
    model = PathJoinSubstitution([FindPackageShare('load_bot'), 'urdf', 'robot.urdf'])
    return LaunchDescription([
        Node(package='joint_state_publisher', executable='joint_state_publisher', arguments=[model]),
    ])
"""
SYNTAX_ERROR = """from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        Node(package='joint_state_publisher', executable='joint_state_publisher')
        Node(package='teleop_twist_joy', executable='teleop_node'),
    ])
"""
# a lookup the file guards itself (an optional driver): ROS goes on without it
GUARDED = """from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
from launch import LaunchDescription


def generate_launch_description():
    try:
        driver = get_package_share_directory('load_bot_optional_driver')
    except PackageNotFoundError:
        driver = None
    return LaunchDescription([undefined_name])
"""
# a package used in one branch of a file that does not load: which branch runs is not known
# (mortadamoghazy/articubot_one's select_slam_launch.py starts hector_mapping on the user's choice)
BRANCH = """import os

from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    nodes = []
    if os.environ.get('RUNTIME_BOT_SLAM') == 'hector':
        nodes.append(Node(package='load_bot_hector_mapping', executable='hector_mapping'))
    return LaunchDescription(nodes + [undefined_name])
"""
# an exception before generate_launch_description returns: the model its xacro command names is
# still the file's (and missing)
RAISES_FIRST = """import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.substitutions import Command
from launch_ros.actions import Node


def generate_launch_description():
    model = os.path.join(get_package_share_directory('load_bot'), 'urdf', 'gone.urdf.xacro')
    configure_the_robot()
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[{'robot_description': Command(['xacro ', model])}]),
    ])
"""
# the same undeclared package in a file that does not load and in one that loads: one PF305, at
# the file that loads (the first file by name is the one that fails)
FAILS_FIRST = """from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([Node(package='teleop_twist_keyboard', executable='teleop'), undefined_name])
"""
LOADS_SECOND = """from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([Node(package='teleop_twist_keyboard', executable='teleop')])
"""
FILES = {
    "urdf/robot.urdf": URDF,
    "launch/a_fails.launch.py": FAILS_FIRST,
    "launch/teleop.launch.py": LOADS_SECOND,
    "launch/raises_first.launch.py": RAISES_FIRST,
    "launch/wrong_import.launch.py": WRONG_IMPORT,
    "launch/wrong_import_clean.launch.py": WRONG_IMPORT_CLEAN,
    "launch/syntax.launch.py": SYNTAX_ERROR,
    "launch/guarded.launch.py": GUARDED,
    "launch/branch.launch.py": BRANCH,
}


def verify_everywhere(tmp_path_factory, name: str, depends: list[str], files: dict[str, str]) -> dict:
    """engine → the JSON report of `pkgforge verify` on a workspace of one package made of these
    files, through the built-in engine and the real launch libraries of each distro; "folder": the
    package's folder."""
    workspace = tmp_path_factory.mktemp(name)
    out: dict = {"folder": package(workspace, name, depends, files)}
    out["builtin"] = verify_report(
        workspace, "--no-cache", "--distro", "jazzy", "--launch-engine", "builtin"
    )[1]
    base = tmp_path_factory.mktemp("ros")
    for distro in DISTROS:
        prefix, reason = make_prefix(distro, base)
        if prefix is None:
            pytest.skip(f"no real ROS 2 launch library for {distro}: {reason}")
        out[distro] = verify_report(
            workspace, "--no-cache", "--distro", distro, "--launch-engine", "ros", "--ros-prefix", str(prefix)
        )[1]
    return out


def found(report: dict, relative: str, name: str = NAME) -> list[tuple[str, str, int | None]]:
    """(code, severity, line) of this package file's findings of the issue's codes."""
    path = f"src/{name}/{relative}"
    return sorted(
        (d["code"], d["severity"], d["line"])
        for d in report["diagnostics"]
        if d["path"] == path and d["code"] in CODES
    )


def message(report: dict, relative: str, code: str, name: str = NAME) -> str:
    (only,) = [
        d["message"]
        for d in report["diagnostics"]
        if d["path"] == f"src/{name}/{relative}" and d["code"] == code
    ]
    return str(only)


def everything(report: dict) -> list[tuple]:
    return sorted(
        (d["code"], d["path"], d["line"], d["severity"], d["message"]) for d in report["diagnostics"]
    )


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict:
    return verify_everywhere(tmp_path_factory, NAME, DEPENDS, FILES)


def test_the_engines_agree(runs):
    for distro in DISTROS:
        assert everything(runs[distro]) == everything(runs["builtin"]), distro


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.triggers("PF301", "PF303", "PF304", "PF305")
def test_a_file_that_does_not_load_is_read_statically(runs, engine):
    launch = runs["folder"] / "launch" / "wrong_import.launch.py"
    relative = "launch/wrong_import.launch.py"
    assert found(runs[engine], relative) == sorted(
        [
            ("PF301", "error", line_of(launch, "import FindPackageShare")),
            ("PF303", "error", line_of(launch, "'absent.urdf'")),
            ("PF304", "error", line_of(launch, "load_bot_typo")),
            ("PF305", "error", line_of(launch, "package='joy'")),
        ]
    )
    assert message(runs[engine], relative, "PF303") == (
        "share/load_bot/urdf/absent.urdf does not exist, in the install tree or in load_bot's "
        "source (read statically: wrong_import.launch.py does not load)"
    )
    assert message(runs[engine], relative, "PF305").endswith(
        "(read statically: wrong_import.launch.py does not load)"
    )
    (load,) = [
        d for d in runs[engine]["diagnostics"] if d["code"] == "PF301" and d["path"].endswith(relative)
    ]
    assert (
        load["hint"]
        == "import it from launch_ros.substitutions: from launch_ros.substitutions import FindPackageShare"
    )


@pytest.mark.parametrize("engine", ENGINES)
def test_a_file_that_does_not_load_with_sound_references_is_only_its_load_error(runs, engine):
    launch = runs["folder"] / "launch" / "wrong_import_clean.launch.py"
    assert found(runs[engine], "launch/wrong_import_clean.launch.py") == [
        ("PF301", "error", line_of(launch, "import FindPackageShare"))
    ]


@pytest.mark.parametrize("engine", ENGINES)
def test_a_syntax_error_leaves_the_rest_of_the_file_read(runs, engine):
    # the line Python stops at is left out; the node after it is still the file's
    launch = runs["folder"] / "launch" / "syntax.launch.py"
    assert found(runs[engine], "launch/syntax.launch.py") == sorted(
        [
            ("PF301", "error", line_of(launch, "executable='joint_state_publisher')")),
            ("PF305", "error", line_of(launch, "teleop_twist_joy")),
        ]
    )


@pytest.mark.parametrize("engine", ENGINES)
def test_a_lookup_the_file_guards_is_no_unknown_package(runs, engine):
    launch = runs["folder"] / "launch" / "guarded.launch.py"
    assert found(runs[engine], "launch/guarded.launch.py") == [
        ("PF301", "error", line_of(launch, "undefined_name"))
    ]


@pytest.mark.parametrize("engine", ENGINES)
def test_an_unknown_package_in_one_branch_of_a_file_that_does_not_load_is_a_warning(runs, engine):
    launch = runs["folder"] / "launch" / "branch.launch.py"
    assert found(runs[engine], "launch/branch.launch.py") == sorted(
        [
            ("PF301", "error", line_of(launch, "undefined_name")),
            ("PF304", "warning", line_of(launch, "load_bot_hector_mapping")),
        ]
    )
    assert message(runs[engine], "launch/branch.launch.py", "PF304").endswith(
        "(read statically: branch.launch.py does not load) (only in the branch "
        "`if os.environ.get('RUNTIME_BOT_SLAM') == 'hector'`)"
    )


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.triggers("PF303")
def test_a_file_that_raises_before_returning_still_names_its_xacro_model(runs, engine):
    launch = runs["folder"] / "launch" / "raises_first.launch.py"
    assert found(runs[engine], "launch/raises_first.launch.py") == sorted(
        [
            ("PF301", "error", line_of(launch, "configure_the_robot()")),
            ("PF303", "error", line_of(launch, "'gone.urdf.xacro'")),
        ]
    )
    assert message(runs[engine], "launch/raises_first.launch.py", "PF303") == (
        "share/load_bot/urdf/gone.urdf.xacro does not exist, in the install tree or in load_bot's "
        "source (read statically: raises_first.launch.py does not load)"
    )


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.triggers("PF305")
def test_a_package_named_where_a_file_loads_is_reported_there(runs, engine):
    failing = runs["folder"] / "launch" / "a_fails.launch.py"
    loading = runs["folder"] / "launch" / "teleop.launch.py"
    assert found(runs[engine], "launch/a_fails.launch.py") == [
        ("PF301", "error", line_of(failing, "undefined_name"))
    ]
    assert found(runs[engine], "launch/teleop.launch.py") == [
        ("PF305", "error", line_of(loading, "teleop_twist_keyboard"))
    ]
    assert message(runs[engine], "launch/teleop.launch.py", "PF305") == (
        "Node package 'teleop_twist_keyboard' is used at run time but package.xml does not declare it"
    )
