"""`pkgforge migrate --gazebo` (issue 31): a ROS 1 package simulated in Gazebo Classic becomes one
that passes the simulation checks of its target distro, whose launch files load in both engines:
transmissions → <ros2_control>, gazebo_ros_control → the distro's gz ros2_control plugin naming
the converted controller YAML, Classic plugins → gz-sim systems (bridged) or removed."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from conftest import edit, line_of, run_pkgforge, verify_report
from migrate_fixtures import ros1_gazebo_package

DISTROS = ("humble", "jazzy")
NAMES = {
    "humble": (
        "ign_ros2_control/IgnitionSystem",
        "ign_ros2_control-system",
        "ign_ros2_control::IgnitionROS2ControlPlugin",
        "ignition-gazebo",
        "ignition::gazebo",
        "ignition.msgs",
        "ign_ros2_control",
    ),
    "jazzy": (
        "gz_ros2_control/GazeboSimSystem",
        "gz_ros2_control-system",
        "gz_ros2_control::GazeboSimROS2ControlPlugin",
        "gz-sim",
        "gz::sim",
        "gz.msgs",
        "gz_ros2_control",
    ),
}


def migrate(
    root: Path, distro: str, name: str = "sim_bot", *, source: Path | None = None
) -> tuple[Path, str]:
    """The fixture (or `source`) migrated with --gazebo into a workspace of its own."""
    source = source or ros1_gazebo_package(root / "ros1", name)
    workspace = root / f"ws_{distro}"
    (workspace / "src").mkdir(parents=True)
    result = run_pkgforge(
        "migrate", source, "--gazebo", "--distro", distro, "--destination", "src", cwd=workspace
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Traceback" not in result.stderr
    return workspace, result.stdout


def simulation_findings(report: dict) -> list[tuple[str, str, int | None, str]]:
    return sorted(
        (d["code"], d["path"], d["line"], d["message"])
        for d in report["diagnostics"]
        if d["code"].startswith(("PF7", "PF42")) or d["severity"] == "error"
    )


@pytest.fixture(scope="module", params=DISTROS)
def migrated(request, tmp_path_factory) -> tuple[str, Path, Path, str]:
    root = tmp_path_factory.mktemp(f"gazebo_{request.param}")
    workspace, out = migrate(root, request.param)
    return request.param, root / "ros1" / "sim_bot", workspace / "src" / "sim_bot", out


def test_migrated_package_passes_the_simulation_checks_in_both_engines(migrated, tmp_path):
    """verify --distro D of migrate's own output: no PF7xx, PF42x or any error, in the built-in
    engine and in the distro's real launch libraries."""
    from ros_prefix import make_prefix

    distro, _, package, _ = migrated
    workspace = package.parent.parent
    builtin = verify_report(workspace, "--no-cache", "--distro", distro, "--launch-engine", "builtin")[1]
    assert simulation_findings(builtin) == []
    assert [d for d in builtin["diagnostics"] if d["severity"] != "info"] == []
    prefix, reason = make_prefix(distro, tmp_path / "ros")
    if prefix is None:
        pytest.skip(f"no real ROS 2 launch library for {distro}: {reason}")
    real = verify_report(
        workspace, "--no-cache", "--distro", distro, "--launch-engine", "ros", "--ros-prefix", str(prefix)
    )[1]
    assert simulation_findings(real) == []
    assert [d for d in real["diagnostics"] if d["severity"] != "info"] == []


def test_transmission_and_gazebo_ros_control_become_ros2_control(migrated):
    distro, _, package, _ = migrated
    hardware, plugin, plugin_name, system, namespace, _, _ = NAMES[distro]
    model = (package / "urdf" / "sim_bot.urdf.xacro").read_text()
    assert "<transmission" not in model and "libgazebo_ros" not in model
    assert (
        f"""  <ros2_control name="arm_transmission" type="system">
    <hardware>
      <plugin>{hardware}</plugin>
    </hardware>
    <joint name="arm_joint">
      <command_interface name="position"/>
      <state_interface name="position"/>
      <state_interface name="velocity"/>
    </joint>
  </ros2_control>
"""
        in model
    )
    assert (
        f"""  <gazebo>
    <plugin filename="{plugin}" name="{plugin_name}">
      <parameters>$(find sim_bot)/config/controllers.yaml</parameters>
    </plugin>
  </gazebo>
"""
        in model
    )
    assert (
        f"""    <plugin filename="{system}-diff-drive-system" name="{namespace}::systems::DiffDrive">
      <left_joint>left_wheel_joint</left_joint>
      <right_joint>right_wheel_joint</right_joint>
      <wheel_separation>0.25</wheel_separation>
      <wheel_radius>0.05</wheel_radius>
      <topic>/cmd_vel</topic>
      <odom_topic>/odom</odom_topic>
      <frame_id>odom</frame_id>
      <child_frame_id>base_footprint</child_frame_id>
      <tf_topic>/tf</tf_topic>
    </plugin>
"""
        in model
    )
    # the camera's plugin is gone, its <sensor> stays
    assert '<sensor type="camera" name="camera">' in model and "camera_controller" not in model


def test_controller_yaml_becomes_controller_manager_parameters(migrated):
    _, _, package, _ = migrated
    assert (package / "config" / "controllers.yaml").read_text() == (
        "# Converted from ROS 1 controllers.yaml by pkgforge migrate --gazebo: 2 controller(s) for\n"
        "# gz_ros2_control's controller manager (the model's <parameters> names this file).\n"
        "controller_manager:\n"
        "  ros__parameters:\n"
        "    update_rate: 100\n"
        "    use_sim_time: true\n"
        "    joint_state_broadcaster:\n"
        "      type: joint_state_broadcaster/JointStateBroadcaster\n"
        "    arm_controller:\n"
        "      type: joint_trajectory_controller/JointTrajectoryController\n"
        "arm_controller:\n"
        "  ros__parameters:\n"
        "    joints:\n"
        "    - arm_joint\n"
        "    command_interfaces:\n"
        "    - position\n"
        "    state_interfaces:\n"
        "    - position\n"
        "    - velocity\n"
        "    constraints:\n"
        "      goal_time: 0.6\n"
    )


def test_launch_file_bridges_the_clock_and_the_plugins_topics(migrated):
    distro, source, package, out = migrated
    msgs, control = NAMES[distro][5], NAMES[distro][6]
    launch = (package / "launch" / "gazebo.launch.py").read_text()
    assert (
        f"arguments=['/clock@rosgraph_msgs/msg/Clock[{msgs}.Clock', '/cmd_vel@geometry_msgs/msg/Twist]{msgs}.Twist', "
        f"'/odom@nav_msgs/msg/Odometry[{msgs}.Odometry', '/tf@tf2_msgs/msg/TFMessage[{msgs}.Pose_V'],"
    ) in launch
    assert "arguments=['joint_state_broadcaster', 'arm_controller']," in launch
    manifest = (package / "package.xml").read_text()
    depends = sorted(re.findall(r"<exec_depend>([^<]+)</exec_depend>", manifest))
    assert depends == sorted(
        [
            "controller_manager",
            control,
            "joint_state_broadcaster",
            "joint_trajectory_controller",
            "launch",
            "launch_ros",
            "robot_state_publisher",
            "ros_gz_bridge",
            "ros_gz_sim",
            "xacro",
        ]
    )
    model = source / "urdf" / "sim_bot.urdf.xacro"
    shown = os.path.relpath(model, package.parent.parent)
    assert (
        f"{shown}:{line_of(model, 'libgazebo_ros_camera.so')}: PF802 [warning] sensor plugin "
        "libgazebo_ros_camera.so removed: the <sensor> stays" in out
    )


@pytest.mark.parametrize("distro", DISTROS)
def test_nearest_unclean_input_gets_its_note_and_stays_clean(tmp_path, distro):
    """A transmission naming a joint the model lacks and a controller type with no ROS 2
    equivalent: each is left out with its note at its line; the spawner no longer names it, and
    the package still verifies clean."""
    source = ros1_gazebo_package(tmp_path / "ros1", "sim_bot")
    model, controllers = source / "urdf" / "sim_bot.urdf.xacro", source / "config" / "controllers.yaml"
    edit(
        model,
        '  <transmission name="arm_transmission">',
        '  <transmission name="ghost_transmission">\n    <joint name="ghost_joint">\n'
        "      <hardwareInterface>EffortJointInterface</hardwareInterface>\n    </joint>\n  </transmission>\n"
        '  <transmission name="arm_transmission">',
    )
    with controllers.open("a") as stream:
        stream.write("\narm_pid:\n  type: effort_controllers/JointPositionController\n  joint: arm_joint\n")
    edit(
        source / "launch" / "gazebo.launch",
        'args="joint_state_controller arm_controller"',
        'args="joint_state_controller arm_controller arm_pid"',
    )
    # hector_gazebo_plugins' IMU (mir_description): Gazebo Classic too, plugin and dependency
    edit(
        model,
        "</robot>",
        '  <gazebo><plugin name="imu" filename="libhector_gazebo_ros_imu.so"/></gazebo>\n</robot>',
    )
    edit(
        source / "package.xml",
        "  <exec_depend>xacro",
        "  <exec_depend>hector_gazebo_plugins</exec_depend>\n  <exec_depend>xacro",
    )
    # ROS 1's gazebo_ros_control PID gains, loaded for the spawner too: no controller in it
    pid = source / "config" / "pid.yaml"
    pid.write_text("gazebo_ros_control:\n  pid_gains:\n    arm_joint: {p: 100.0, i: 0.01, d: 10.0}\n")
    edit(
        source / "launch" / "gazebo.launch",
        '  <node name="controller_spawner"',
        '  <rosparam file="$(find sim_bot)/config/pid.yaml" command="load"/>\n  <node name="controller_spawner"',
    )
    workspace, out = migrate(tmp_path, distro, source=source)

    def shown(path: Path) -> str:
        return os.path.relpath(path, workspace)

    assert (
        f"{shown(model)}:{line_of(model, 'ghost_transmission')}: PF807 [warning] transmission 'ghost_transmission' "
        "names joint 'ghost_joint', which the model does not have: left out (gazebo_ros_control skipped it too) "
        "(migrate-source-defect)"
    ) in out.splitlines()
    assert (
        f"{shown(controllers)}:{line_of(controllers, 'effort_controllers/JointPositionController')}: PF802 [warning] "
        f"controller 'arm_pid' (effort_controllers/JointPositionController) has no ROS 2 equivalent on {distro}: "
        "left out, and out of the spawner (migrate-gazebo-classic)"
    ) in out.splitlines()
    assert (
        f"{shown(model)}:{line_of(model, 'libhector_gazebo_ros_imu.so')}: PF802 [warning] Gazebo Classic plugin "
        "libhector_gazebo_ros_imu.so removed: it loads in no Gazebo (gz) (migrate-gazebo-classic)"
    ) in out.splitlines()
    assert (
        f"{shown(pid)}: PF802 [warning] config/pid.yaml holds no ros_control controller (a mapping with a type): "
        "copied as written, not given to gz_ros2_control (migrate-gazebo-classic)"
    ) in out.splitlines()
    package = workspace / "src" / "sim_bot"
    assert (package / "config" / "pid.yaml").read_text() == pid.read_text()
    assert "pid.yaml" not in (package / "urdf" / "sim_bot.urdf.xacro").read_text()
    assert (
        "hector"
        not in (package / "package.xml").read_text() + (package / "urdf" / "sim_bot.urdf.xacro").read_text()
    )
    assert "ghost" not in (package / "urdf" / "sim_bot.urdf.xacro").read_text()
    assert "arm_pid" not in (package / "config" / "controllers.yaml").read_text()
    assert (
        "arguments=['joint_state_broadcaster', 'arm_controller'],"
        in (package / "launch" / "gazebo.launch.py").read_text()
    )
    report = verify_report(workspace, "--no-cache", "--distro", distro, "--launch-engine", "builtin")[1]
    assert simulation_findings(report) == []


def test_migrated_controllers_are_really_checked(migrated, tmp_path):
    """A clean report is not an unread one: the converted YAML and <ros2_control> are what verify
    reads (a spawner of a controller the YAML lacks is PF708 at its line)."""
    import shutil

    distro, _, package, _ = migrated
    workspace = tmp_path / "ws"
    shutil.copytree(package, workspace / "src" / "sim_bot")
    launch = workspace / "src" / "sim_bot" / "launch" / "gazebo.launch.py"
    edit(launch, "'arm_controller']", "'arm_ctrl']")
    report = verify_report(workspace, "--no-cache", "--distro", distro, "--launch-engine", "builtin")[1]
    assert [
        (d["code"], d["path"], d["line"]) for d in report["diagnostics"] if d["code"].startswith("PF7")
    ] == [("PF708", "src/sim_bot/launch/gazebo.launch.py", line_of(launch, "'arm_ctrl'") - 5)]


def test_a_converted_model_keeps_its_declaration_and_line_ends(tmp_path):
    """The model is re-serialised where it changed: its own XML declaration and CRLF stay; a
    plain .urdf's controller <parameters> use $(find), which xacro (run on it by the migrated
    launch files and by verify) resolves: said so."""
    source = ros1_gazebo_package(tmp_path / "ros1", "sim_bot")
    model = source / "urdf" / "sim_bot.urdf.xacro"
    urdf = model.with_name("sim_bot.urdf")
    model.rename(urdf)
    urdf.write_bytes(urdf.read_bytes().replace(b"\n", b"\r\n"))
    edit(
        source / "launch" / "gazebo.launch",
        'command="$(find xacro)/xacro $(find sim_bot)/urdf/sim_bot.urdf.xacro"',
        'textfile="$(find sim_bot)/urdf/sim_bot.urdf"',
    )
    workspace, out = migrate(tmp_path, "jazzy", source=source)
    written = (workspace / "src" / "sim_bot" / "urdf" / "sim_bot.urdf").read_bytes()
    assert written.startswith(b'<?xml version="1.0"?>\r\n<robot ')
    assert b"\n" not in written.replace(b"\r\n", b"")
    assert b"<parameters>$(find sim_bot)/config/controllers.yaml</parameters>" in written
    assert (
        "; its $(find) needs xacro, which the migrated launch files run on the .urdf "
        "(ros_gz_sim create -file of the .urdf itself would not resolve it); left out: robotNamespace (migrate-changed)"
    ) in out
    report = verify_report(workspace, "--no-cache", "--distro", "jazzy", "--launch-engine", "builtin")[1]
    assert simulation_findings(report) == []


def test_controllers_no_model_loads_are_said_to_reach_nothing(tmp_path):
    """A package whose launch file loads controllers for the spawner but whose models load no
    gazebo_ros_control (diffbot_control: the model is another package's): the converted file
    reaches no controller manager, said at the file; the transmissions stay as written."""
    source = ros1_gazebo_package(tmp_path / "ros1", "sim_bot")
    edit(
        source / "urdf" / "sim_bot.urdf.xacro",
        '  <gazebo>\n    <plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so">\n'
        "      <robotNamespace>/</robotNamespace>\n    </plugin>\n  </gazebo>\n",
        "",
    )
    workspace, out = migrate(tmp_path, "jazzy", source=source)
    controllers = source / "config" / "controllers.yaml"
    assert (
        f"{os.path.relpath(controllers, workspace)}: PF802 [warning] no model of this package loads "
        "gazebo_ros_control: config/controllers.yaml reaches no controller manager (name it in a <parameters> "
        "of the gz_ros2_control-system plugin of the robot's model) (migrate-gazebo-classic)"
    ) in out.splitlines()
    model = (workspace / "src" / "sim_bot" / "urdf" / "sim_bot.urdf.xacro").read_text()
    assert '<transmission name="arm_transmission">' in model and "ros2_control" not in model
