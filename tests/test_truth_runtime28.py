"""Issue 28, classes 4 and 5: what robot_state_publisher and rcl refuse when a node starts,
caught at verify time, through both launch engines (the built-in one and the real launch
libraries of humble and jazzy, tests/ros_prefix.py).

4. robot_state_publisher given neither robot_description nor a model file stops at start.
5. A parameters file rcl refuses (or a ros_gz_bridge config the bridge cannot read) makes the
   node fail: reported at the YAML file's line, naming the node.
"""

from __future__ import annotations

import pytest
from conftest import line_of
from ros_prefix import DISTROS
from test_truth_load28 import URDF, everything, verify_everywhere
from test_truth_load28 import found as found_in
from test_truth_load28 import message as message_in

NAME = "runtime_bot"
DEPENDS = ["launch", "launch_ros", "robot_state_publisher", "joint_state_publisher", "ros_gz_bridge"]
ENGINES = ("builtin", *DISTROS)

RSP = """from launch import LaunchDescription
from launch.substitutions import PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    share = FindPackageShare('runtime_bot')
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='bare'),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='no_model',
             parameters=[PathJoinSubstitution([share, 'config', 'rsp_rate.yaml'])]),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='model_file',
             parameters=[PathJoinSubstitution([share, 'config', 'rsp_model.yaml'])]),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='given',
             parameters=[{'robot_description': '<robot name="r"/>'}]),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='rule',
             ros_arguments=['-p', 'robot_description:=<robot/>']),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='argument',
             arguments=[PathJoinSubstitution([share, 'urdf', 'robot.urdf'])]),
    ])
"""
# the XML front end: a node with nothing, and one given the model in a <param>
RSP_XML = """<launch>
  <node pkg="robot_state_publisher" exec="robot_state_publisher" name="xml_bare"/>
  <node pkg="robot_state_publisher" exec="robot_state_publisher" name="xml_given">
    <param name="robot_description" value="&lt;robot name='r'/&gt;"/>
  </node>
</launch>
"""
PARAMS = """from launch import LaunchDescription
from launch.substitutions import PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def node(name, config):
    return Node(package='joint_state_publisher', executable='joint_state_publisher', name=name,
                parameters=[PathJoinSubstitution([FindPackageShare('runtime_bot'), 'config', config])])


def generate_launch_description():
    return LaunchDescription([
        node('misspelt', 'misspelt.yaml'),
        node('tabbed', 'tabbed.yaml'),
        node('mixed', 'mixed.yaml'),
        node('sound', 'sound.yaml'),
    ])
"""
PARAMS_XML = """<launch>
  <node pkg="joint_state_publisher" exec="joint_state_publisher" name="top_value">
    <param from="$(find-pkg-share runtime_bot)/config/top_value.yaml"/>
  </node>
</launch>
"""
BRIDGE = """from launch import LaunchDescription
from launch.substitutions import PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def bridge(config):
    path = PathJoinSubstitution([FindPackageShare('runtime_bot'), 'config', config])
    return Node(package='ros_gz_bridge', executable='parameter_bridge', parameters=[{'config_file': path}])


def generate_launch_description():
    return LaunchDescription([bridge('bridge_map.yaml'), bridge('bridge_list.yaml')])
"""
CONFIGS = {
    "config/rsp_rate.yaml": "robot_state_publisher:\n  ros__parameters:\n    publish_frequency: 30.0\n",
    "config/rsp_model.yaml": "/**:\n  ros__parameters:\n    robot_description: <robot name='r'/>\n",
    "config/misspelt.yaml": "misspelt:\n  ros_parameters:\n    rate: 30\n",
    "config/tabbed.yaml": "tabbed:\n  ros__parameters:\n\trate: 30\n",
    "config/mixed.yaml": "/**:\n  ros__parameters:\n    rate: 30\n    scale: [0.5, 1, 2.0]\n",
    "config/sound.yaml": (
        "/**:\n  ros__parameters:\n    rate: 30\n    scale: [0.5, 1.0]\n    names: [a, 'b']\n"
        "    nested:\n      deeper: true\n    empty: ''\n"
    ),
    "config/top_value.yaml": "use_sim_time: true\n",
    "config/bridge_map.yaml": (
        "clock:\n  ros_type_name: rosgraph_msgs/msg/Clock\n  gz_type_name: gz.msgs.Clock\n"
    ),
    "config/bridge_list.yaml": (
        "- ros_topic_name: clock\n  gz_topic_name: /clock\n  ros_type_name: rosgraph_msgs/msg/Clock\n"
        "  gz_type_name: gz.msgs.Clock\n  direction: GZ_TO_ROS\n"
    ),
}
FILES = {
    "urdf/robot.urdf": URDF,
    "launch/rsp.launch.py": RSP,
    "launch/rsp.launch.xml": RSP_XML,
    "launch/params.launch.py": PARAMS,
    "launch/params.launch.xml": PARAMS_XML,
    "launch/bridge.launch.py": BRIDGE,
    **CONFIGS,
}


def found(report: dict, relative: str) -> list[tuple[str, str, int | None]]:
    return found_in(report, relative, NAME)


def message(report: dict, relative: str, code: str) -> str:
    return message_in(report, relative, code, NAME)


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict:
    return verify_everywhere(tmp_path_factory, NAME, DEPENDS, FILES)


def test_the_engines_agree(runs):
    for distro in DISTROS:
        assert everything(runs[distro]) == everything(runs["builtin"]), distro


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.triggers("PF321")
def test_robot_state_publisher_with_no_description(runs, engine):
    # bare: nothing; no_model: its parameters file holds no robot_description. The nearest clean
    # cases: a parameters file that holds it, the parameter itself, a -p rule
    launch = runs["folder"] / "launch" / "rsp.launch.py"
    assert found(runs[engine], "launch/rsp.launch.py") == [
        ("PF321", "error", line_of(launch, "name='bare'")),
        ("PF321", "error", line_of(launch, "name='no_model'")),
    ]
    messages = sorted(d["message"] for d in runs[engine]["diagnostics"] if d["code"] == "PF321")
    assert messages == [
        "robot_state_publisher gets no robot_description parameter and no model file (its "
        "parameters file holds none): it stops at start",
        "robot_state_publisher gets no robot_description parameter and no model file: it stops at start",
        "robot_state_publisher gets no robot_description parameter and no model file: it stops at start",
    ]
    xml = runs["folder"] / "launch" / "rsp.launch.xml"
    assert found(runs[engine], "launch/rsp.launch.xml") == [("PF321", "error", line_of(xml, "xml_bare"))]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.triggers("PF322")
def test_parameters_files_rcl_refuses(runs, engine):
    folder = runs["folder"]
    launch = folder / "launch" / "params.launch.py"
    expected = {
        "config/misspelt.yaml": (
            "rate: 30",
            "'rate' has a value outside ros__parameters ('ros_parameters' at line 2 is not ros__parameters); joint_state_publisher (launch/params.launch.py:{line}) does not start",
        ),
        "config/tabbed.yaml": (
            "\trate",
            "not valid YAML: found character '\\t' that cannot start any token; joint_state_publisher (launch/params.launch.py:{line}) does not start",
        ),
        "config/mixed.yaml": (
            "scale",
            "parameter 'scale' mixes double and integer items: rcl takes a list of one type (write 1.0, not 1); joint_state_publisher (launch/params.launch.py:{line}) does not start",
        ),
    }
    node_line = line_of(launch, "return Node(")
    for relative, (text, said) in expected.items():
        assert found(runs[engine], relative) == [("PF322", "error", line_of(folder / relative, text))], (
            relative
        )
        assert message(runs[engine], relative, "PF322") == (
            "rcl refuses this parameters file: " + said.format(line=node_line)
        )
    # <param from=...> in a launch XML file: a top-level key that is no node name
    xml = folder / "launch" / "params.launch.xml"
    assert found(runs[engine], "config/top_value.yaml") == [("PF322", "error", 1)]
    assert message(runs[engine], "config/top_value.yaml", "PF322").endswith(
        f"joint_state_publisher (launch/params.launch.xml:{line_of(xml, '<node')}) does not start"
    )
    assert found(runs[engine], "config/sound.yaml") == []  # the nearest clean case
    assert found(runs[engine], "launch/params.launch.py") == []


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.triggers("PF323")
def test_a_bridge_config_that_is_no_list(runs, engine):
    assert found(runs[engine], "config/bridge_map.yaml") == [("PF323", "error", 1)]
    assert message(runs[engine], "config/bridge_map.yaml", "PF323").startswith(
        "ros_gz_bridge cannot use this config: the top level is not a list: ros_gz_bridge bridges nothing"
    )
    assert found(runs[engine], "config/bridge_list.yaml") == []


def test_rcls_rules_one_by_one():
    """The parser's rules, each on the smallest file (the first problem rcl stops at, its line)."""
    from pkgforge.model.ros_params import read_parameters

    def problem(text: str) -> tuple[int, str] | None:
        read = read_parameters(text)
        return (read.problem.line, read.problem.message) if read.problem else None

    assert problem("/**:\n  ros__parameters:\n    a: 1\n    b: [a, 'b']\n") is None
    # y is a boolean to rcl (its get_value's word list), x a string: no list of one type
    assert problem("/**:\n  ros__parameters:\n    axes: [x, y, z]\n") == (
        3,
        "parameter 'axes' mixes string and bool items: rcl takes a list of one type ('y' is a "
        "boolean to rcl: quote it)",
    )
    assert problem("ns:\n  node:\n    ros__parameters:\n      a: {b: 1}\n") is None
    assert problem("'*':\n  ros__parameters:\n    a: ~\n") is None  # ~ is the text '~' to rcl
    assert problem("") is None  # no node, no parameter
    assert problem("- a\n") == (
        1,
        "the top level is a list: a parameters file maps node names (or /**) to ros__parameters",
    )
    assert problem("n:\n  ros__parameters:\n    a:\n") == (
        3,
        "parameter 'a' has no value (write '' for an empty string)",
    )
    assert problem("ros__parameters:\n  a: 1\n") == (
        1,
        "ros__parameters with no node name above it (write /**: for every node)",
    )
    assert problem("my-node:\n  ros__parameters:\n    a: 1\n") == (
        2,
        "'my-node' is no valid node name: 'my-node' holds '-' (only letters, digits and _)",
    )
    assert problem("n:\n  ros__parameters:\n    a: &x 1\n    b: *x\n") == (
        4,
        "an alias (*name): rcl does not read YAML aliases",
    )
    assert problem("n:\n  ros__parameters:\n    a: [1, true]\n") == (
        3,
        "parameter 'a' mixes integer and bool items: rcl takes a list of one type",
    )
    assert (
        problem("n:\n  ros__parameters:\n    a: [1, 0x10, 010]\n") is None
    )  # strtoll's base 0: all integers
    assert (
        problem("n:\n  ros__parameters:\n    a: [1.5, 08]\n") is None
    )  # strtol stops at 8: strtod reads 8.0
    assert problem("n:\n  ros__parameters:\n") == (2, "ros__parameters of 'n' is empty (write {} for none)")
    # a layout rcl walks otherwise: not judged past it
    unsure = read_parameters("a:\n  ros__parameters:\n    x: 1\n  b:\n    ros__parameters:\n      y: 1\n")
    assert unsure.problem is None and not unsure.judged
