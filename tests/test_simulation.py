"""Simulation and control readiness (issue 31): Gazebo plugins, <ros2_control>, controller YAML,
spawners and how the description reaches the controller manager, per target distro."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import edit, line_of, new_package, run_pkgforge, verify_report

FIXTURE = Path(__file__).parent / "fixtures" / "simulation"


def simulation_package(tmp_path: Path, template_package: Path) -> Path:
    """The clean scaffold with tests/fixtures/simulation's model, controllers and launch file."""
    package = tmp_path / "src" / "rob_description"
    shutil.copytree(template_package, package)
    (package / "config").mkdir()
    for name in ("controllers.yaml", "broken.yaml"):
        shutil.copy(FIXTURE / name, package / "config" / name)
    shutil.copy(FIXTURE / "sim.urdf.xacro", package / "urdf" / "sim.urdf.xacro")
    shutil.copy(FIXTURE / "sim.launch.py", package / "launch" / "sim.launch.py")
    edit(
        package / "CMakeLists.txt",
        "DIRECTORY launch meshes rviz urdf",
        "DIRECTORY config launch meshes rviz urdf",
    )
    return package


def found(report: dict, prefix: str = "PF7") -> list[tuple[str, str, int | None, str]]:
    return sorted(
        (d["code"], d["path"], d["line"], d["severity"])
        for d in report["diagnostics"]
        if d["code"].startswith(prefix)
    )


@pytest.fixture(scope="module")
def broken(tmp_path_factory, template_package) -> tuple[Path, dict[str, dict]]:
    package = simulation_package(tmp_path_factory.mktemp("sim"), template_package)
    reports = {d: verify_report(package, "--no-cache", "--distro", d)[1] for d in ("humble", "jazzy")}
    return package, reports


@pytest.mark.triggers("PF701", "PF702", "PF703", "PF704", "PF705", "PF706", "PF707", "PF708", "PF709")
def test_each_simulation_defect_is_found_at_its_line_per_distro(broken):
    package, reports = broken
    model, launch = package / "urdf" / "sim.urdf.xacro", package / "launch" / "sim.launch.py"
    controllers = package / "config" / "controllers.yaml"
    common = [
        ("PF702", "urdf/sim.urdf.xacro", line_of(model, '<joint name="ghost_joint">'), "error"),
        ("PF702", "urdf/sim.urdf.xacro", line_of(model, '<joint name="body_joint">'), "error"),
        ("PF703", "urdf/sim.urdf.xacro", line_of(model, '<joint name="wheel_joint">'), "warning"),
        (
            "PF704",
            "urdf/sim.urdf.xacro",
            line_of(model, "<plugin>gz_ros2_control/GazeboSimSystem"),
            "warning",
        ),
        ("PF705", "config/broken.yaml", 4, "error"),
        ("PF706", "config/controllers.yaml", line_of(controllers, "joint_state_controller/"), "error"),
        ("PF707", "config/controllers.yaml", line_of(controllers, "right_wheel_names"), "error"),
        ("PF708", "launch/sim.launch.py", line_of(launch, '"drive_controller"'), "error"),
        ("PF701", "urdf/sim.urdf.xacro", line_of(model, "gz-sim-no-such-thing-system"), "error"),
    ]
    assert found(reports["humble"]) == sorted(common)
    assert found(reports["jazzy"]) == sorted(
        common
        + [
            ("PF701", "urdf/sim.urdf.xacro", line_of(model, "libgazebo_ros_diff_drive.so"), "error"),
            (
                "PF709",
                "launch/sim.launch.py",
                line_of(launch, 'executable="ros2_control_node"') - 2,
                "warning",
            ),
        ]
    )
    messages = {
        d["code"]: d["message"] for d in reports["jazzy"]["diagnostics"] if "libgazebo" in d["message"]
    }
    assert messages["PF701"] == (
        "plugin 'libgazebo_ros_diff_drive.so' does not load on jazzy: Gazebo Classic's "
        "libgazebo_ros_diff_drive.so (gazebo_plugins) is not released for jazzy; use gz-sim-diff-drive-system"
    )


def test_the_simulation_package_fixed_is_clean_on_humble_and_jazzy(tmp_path, template_package):
    package = simulation_package(tmp_path, template_package)
    model, launch = package / "urdf" / "sim.urdf.xacro", package / "launch" / "sim.launch.py"
    edit(
        model, '    <joint name="ghost_joint">\n      <state_interface name="position"/>\n    </joint>\n', ""
    )
    edit(model, '    <joint name="body_joint">\n      <state_interface name="position"/>\n    </joint>\n', "")
    edit(model, '      <state_interface name="pos"/>\n', "")
    edit(model, '    <plugin filename="libgazebo_ros_diff_drive.so" name="classic_drive"/>\n', "")
    edit(model, "gz-sim-no-such-thing-system", "gz-sim-sensors-system")
    edit(
        package / "config" / "controllers.yaml",
        "    old_states:\n      type: joint_state_controller/JointStateController\n",
        "",
    )
    edit(package / "config" / "controllers.yaml", "[right_wheel]", "[wheel_joint]")
    edit(
        launch,
        '            Node(package="controller_manager", executable="spawner", arguments=["drive_controller"]),\n',
        "",
    )
    edit(
        launch,
        '            Node(package="controller_manager", executable="spawner", arguments=["extra", "--param-file", broken]),\n',
        "",
    )
    edit(
        launch,
        "parameters=[description, controllers],",
        'parameters=[controllers], remappings=[("~/robot_description", "/robot_description")],',
    )
    edit(
        package / "package.xml",
        "<exec_depend>",
        "<exec_depend>gz_ros2_control</exec_depend>\n  <exec_depend>",
    )
    for distro in ("humble", "jazzy"):
        assert found(verify_report(package, "--no-cache", "--distro", distro)[1]) == [], distro


def test_the_description_reaches_the_controller_manager_as_each_distro_reads_it(tmp_path, template_package):
    """Humble reads the parameter (or a remapped ~/robot_description); Jazzy only the topic."""
    package = simulation_package(tmp_path, template_package)
    launch = package / "launch" / "sim.launch.py"
    edit(launch, "parameters=[description, controllers],", "parameters=[controllers],")
    line = line_of(launch, 'executable="ros2_control_node"') - 2
    humble = verify_report(package, "--no-cache", "--distro", "humble")[1]
    jazzy = verify_report(package, "--no-cache", "--distro", "jazzy")[1]
    assert found(humble, "PF709") == [("PF709", "launch/sim.launch.py", line, "error")]
    assert found(jazzy, "PF709") == []


@pytest.mark.parametrize("distro", ["humble", "jazzy"])
def test_new_sim_gz_is_clean_and_its_launch_files_load_in_both_engines(tmp_path, distro):
    """`pkgforge new --sim gz`: a world, sim.launch.py (ros_gz_sim, the clock bridge, the spawners),
    <ros2_control> with the distro's Gazebo plugin and controllers.yaml; clean in both engines."""
    from ros_prefix import make_prefix

    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "sim_robot", "--sim", "gz", "--distro", distro)
    model = (package / "urdf" / "sim_robot.urdf.xacro").read_text()
    world = (package / "worlds" / "empty.sdf").read_text()
    plugin, system = (
        ("ign_ros2_control-system", "ignition-gazebo-physics-system")
        if distro == "humble"
        else ("gz_ros2_control-system", "gz-sim-physics-system")
    )
    assert f'filename="{plugin}"' in model and f'filename="{system}"' in world
    assert (package / "config" / "controllers.yaml").is_file()
    builtin = verify_report(tmp_path, "--no-cache", "--distro", distro, "--launch-engine", "builtin")[1]
    assert builtin["diagnostics"] == []
    prefix, reason = make_prefix(distro, tmp_path / "ros")
    if prefix is None:
        pytest.skip(f"no real ROS 2 launch library for {distro}: {reason}")
    real = verify_report(
        tmp_path, "--no-cache", "--distro", distro, "--launch-engine", "ros", "--ros-prefix", str(prefix)
    )[1]
    assert real["diagnostics"] == []


@pytest.mark.parametrize("distro", ["humble", "jazzy"])
def test_new_sim_gz_checks_what_it_wrote(tmp_path, distro):
    """The scaffold's launch file and model are really read: a spawner of a controller the YAML
    lacks is found at its line (a clean report is not an unread one)."""
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "sim_robot", "--sim", "gz", "--distro", distro)
    launch = package / "launch" / "sim.launch.py"
    edit(launch, "arguments=['arm_controller']", "arguments=['arm_ctrl']")
    edit(package / "config" / "controllers.yaml", "      - arm_joint\n", "      - arm_joint_x\n")
    report = verify_report(tmp_path, "--no-cache", "--distro", distro, "--launch-engine", "builtin")[1]
    assert found(report) == [
        (
            "PF707",
            "src/sim_robot/config/controllers.yaml",
            line_of(package / "config" / "controllers.yaml", "arm_joint_x"),
            "error",
        ),
        ("PF708", "src/sim_robot/launch/sim.launch.py", line_of(launch, "'arm_ctrl'") - 3, "error"),
    ]


def test_an_unreadable_controller_configuration_is_one_finding(tmp_path):
    """One cause, one finding: the only controller YAML not valid YAML is PF705 at its line; the
    spawners of controllers it would define are not each told that none is defined (PF708)."""
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "sim_robot", "--sim", "gz", "--distro", "jazzy")
    controllers = package / "config" / "controllers.yaml"
    controllers.write_text("controller_manager:\n  ros__parameters:\n    update_rate: 100\n  bad: [\n")
    report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy", "--launch-engine", "builtin")[1]
    assert found(report) == [("PF705", "src/sim_robot/config/controllers.yaml", 5, "error")]


FOREIGN_CONTROLLERS = """from launch import LaunchDescription
from launch.substitutions import PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    controllers = PathJoinSubstitution([FindPackageShare("PACKAGE"), "config", "FILE"])
    return LaunchDescription([
        Node(package="controller_manager", executable="ros2_control_node", parameters=[controllers]),
        Node(
            package="controller_manager",
            executable="spawner",
            arguments=["forward_position_controller", "--param-file", controllers],
        ),
    ])
"""


@pytest.mark.parametrize(
    ("package", "file", "expected"),
    [
        ("ros2_control_demo_example_9", "rrbot_controllers.yaml", False),
        ("sim_robot", "controllers.yaml", True),  # nearest unclean: its own file, which lacks it
    ],
)
def test_a_spawner_of_a_controller_manager_reading_another_package_s_file_is_that_package_s(
    tmp_path, package, file, expected
):
    """protobot_bringup: ros2_control_node and the spawner read ros2_control_demo_example_9's
    rrbot_controllers.yaml, which defines forward_position_controller; what that file defines is
    not known here, so the spawner is no PF708 (the package not being there is PF304's)."""
    (tmp_path / "src").mkdir()
    robot = new_package(tmp_path, "sim_robot", "--sim", "gz", "--distro", "jazzy")
    launch = robot / "launch" / "demo.launch.py"
    launch.write_text(FOREIGN_CONTROLLERS.replace("PACKAGE", package).replace("FILE", file))
    report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy", "--launch-engine", "builtin")[1]
    where = (
        "PF708",
        "src/sim_robot/launch/demo.launch.py",
        line_of(launch, 'executable="spawner"') - 2,
        "error",
    )
    assert found(report, "PF708") == ([where] if expected else [])


def test_a_controller_file_ros2_control_node_reads_is_said_once_by_rcl_s_check(tmp_path):
    """One cause, one finding: a controllers.yaml given to ros2_control_node that rcl refuses is
    parameters-file-invalid (PF322, the node does not start), not controller-config-invalid too;
    both read it with the one reader of rcl's rules (model/ros_params)."""
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "sim_robot", "--sim", "gz", "--distro", "jazzy")
    controllers = package / "config" / "controllers.yaml"
    controllers.write_text("controller_manager:\n  ros__parameters:\n    update_rate: 100\n  bad: [\n")
    (package / "launch" / "cm.launch.py").write_text(
        FOREIGN_CONTROLLERS.replace("PACKAGE", "sim_robot").replace("FILE", "controllers.yaml")
    )
    report = verify_report(tmp_path, "--no-cache", "--distro", "jazzy", "--launch-engine", "builtin")[1]
    assert [f for f in found(report, "PF") if f[3] == "error"] == [
        ("PF322", "src/sim_robot/config/controllers.yaml", 5, "error")
    ]


def test_a_type_given_in_the_controller_s_own_section_defines_the_controller(tmp_path, template_package):
    """Jazzy's form (gz_ros2_control's demos): `drive: ros__parameters: type: ...`; the spawner of
    it is no finding, and its joints are still checked."""
    package = simulation_package(tmp_path, template_package)
    controllers = package / "config" / "controllers.yaml"
    edit(controllers, "    drive:\n      type: diff_drive_controller/DiffDriveController\n", "")
    edit(
        controllers,
        "drive:\n  ros__parameters:\n",
        "drive:\n  ros__parameters:\n    type: diff_drive_controller/DiffDriveController\n",
    )
    report = verify_report(package, "--no-cache", "--distro", "jazzy")[1]
    launch = package / "launch" / "sim.launch.py"
    assert found(report, "PF708") == [
        ("PF708", "launch/sim.launch.py", line_of(launch, '"drive_controller"'), "error")
    ]
    assert found(report, "PF707") == [
        ("PF707", "config/controllers.yaml", line_of(controllers, "right_wheel_names"), "error")
    ]


def test_an_sdf_a_model_config_offers_for_an_older_version_is_not_what_gazebo_loads(package):
    """turtlebot3_gazebo's models: model-1_4.sdf (Classic plugins) for SDF 1.4 beside model.sdf for
    gz; Gazebo loads the newest, so only a world that really names a Classic plugin is found."""
    models = package / "models" / "bot"
    models.mkdir(parents=True)
    (models / "model.config").write_text(
        '<?xml version="1.0"?>\n<model>\n  <name>bot</name>\n  <sdf version="1.4">model-1_4.sdf</sdf>\n'
        '  <sdf version="1.6">model.sdf</sdf>\n</model>\n'
    )
    classic = '<plugin name="drive" filename="libgazebo_ros_diff_drive.so"/>'
    modern = '<plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive"/>'
    model = '<?xml version="1.0"?>\n<sdf version="{v}">\n  <model name="bot">\n    {p}\n  </model>\n</sdf>\n'
    (models / "model-1_4.sdf").write_text(model.format(v="1.4", p=classic))
    (models / "model.sdf").write_text(model.format(v="1.6", p=modern))
    (models / "model-1_4_.sdf").write_text(model.format(v="1.4", p=classic))  # named by no config
    (package / "worlds").mkdir()
    world = package / "worlds" / "classic.world"
    world.write_text(
        '<?xml version="1.0"?>\n<sdf version="1.6">\n  <world name="w">\n    '
        + classic
        + "\n  </world>\n</sdf>\n"
    )
    report = verify_report(package, "--no-cache", "--distro", "jazzy")[1]
    assert found(report, "PF701") == [
        ("PF701", "worlds/classic.world", line_of(world, "libgazebo_ros"), "error")
    ]
    assert found(verify_report(package, "--no-cache", "--distro", "humble")[1], "PF701") == []


def test_a_hardware_package_declared_for_some_distros_is_not_undeclared(tmp_path, template_package):
    """bumperbot_description declares gz_ros2_control for $ROS_DISTRO >= iron (ign_ros2_control for
    humble) and its xacro picks the plugin alike: the model, evaluated once, is not judged against
    the declaration of another distro."""
    package = simulation_package(tmp_path, template_package)
    edit(
        package / "package.xml",
        "<exec_depend>",
        '<exec_depend condition="$ROS_DISTRO != humble">gz_ros2_control</exec_depend>\n  <exec_depend>',
    )
    assert found(verify_report(package, "--no-cache", "--distro", "humble")[1], "PF704") == []


BRANCHED = """<?xml version="1.0"?>
<robot name="branched" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="is_ignition" default="true"/>
  <xacro:arg name="ground_truth" default="true"/>
  <link name="base_link"/>
  <gazebo>
    <xacro:if value="$(arg is_ignition)">
      <plugin filename="ign_ros2_control-system" name="ign_ros2_control::IgnitionROS2ControlPlugin"/>
    </xacro:if>
    <xacro:unless value="$(arg is_ignition)">
      <plugin filename="gz_ros2_control-system" name="gz_ros2_control::GazeboSimROS2ControlPlugin"/>
    </xacro:unless>
    <xacro:if value="$(arg ground_truth)">
      <plugin filename="libgazebo_ros_p3d.so" name="ground_truth"/>
    </xacro:if>
  </gazebo>
</robot>
"""


def test_a_plugin_in_a_xacro_conditional_is_judged_per_branch(package):
    """bumperbot_description: ign_ros2_control-system under is_ignition (default true, for humble),
    gz_ros2_control-system under its unless: on jazzy the other branch loads, no finding; a Classic
    plugin in a conditional with no other branch is still one."""
    model = package / "urdf" / "branched.urdf.xacro"
    model.write_text(BRANCHED)
    report = verify_report(package, "--no-cache", "--distro", "jazzy")[1]
    assert found(report, "PF701") == [
        ("PF701", "urdf/branched.urdf.xacro", line_of(model, "libgazebo_ros_p3d.so"), "error")
    ]


def test_the_conditional_is_known_by_its_xacro_prefix_whatever_its_uri(package):
    """xacro knows xacro:if by its prefix: bumperbot_description binds http://ros.org/wiki/xacro."""
    model = package / "urdf" / "branched.urdf.xacro"
    model.write_text(BRANCHED.replace("http://www.ros.org/wiki/xacro", "http://ros.org/wiki/xacro"))
    report = verify_report(package, "--no-cache", "--distro", "jazzy")[1]
    assert found(report, "PF701") == [
        ("PF701", "urdf/branched.urdf.xacro", line_of(model, "libgazebo_ros_p3d.so"), "error")
    ]


def test_selecting_the_simulation_checks_runs_what_they_read(broken, tmp_path, template_package):
    """--select PF7: the install tree, the launch files and the models are evaluated for them."""
    package = simulation_package(tmp_path, template_package)
    report = verify_report(package, "--no-cache", "--distro", "jazzy", "--select", "PF7")[1]
    assert found(report) == found(broken[1]["jazzy"])


@pytest.mark.parametrize(
    ("code", "named"),
    [
        ("PF701", ["gazebosim/gz-sim", "gz-sim8@", "(Harmonic)", "gazebo_ros_pkgs: ros2@"]),
        ("PF706", ["ros-controls/ros2_controllers", "jazzy@", "master@"]),
        ("PF709", ["ros-controls/ros2_control", "controller_manager.cpp"]),
        ("PF422", ["gazebosim/ros_gz", "gz_sim.launch.py.in"]),
    ],
)
def test_a_simulation_rule_names_the_branch_and_commit_it_is_read_from(tmp_path, code, named):
    """Issue 31: the sources of each rule (which gz-sim, ros_gz, ros2_control branch) are named
    by `pkgforge rule` and in docs/checks.md."""
    shown = run_pkgforge("rule", code, cwd=tmp_path).stdout
    sources = [line for line in shown.splitlines() if line.startswith(("Source:", "  "))]
    assert sources and all(any(name in line for line in sources) for name in named), shown
    catalogue = (Path(__file__).parent.parent / "docs" / "checks.md").read_text()
    section = catalogue.split(f"## {code} ", 1)[1].split("\n## ", 1)[0]
    assert "**Sources:**" in section and all(name in section for name in named)


ROS1_PLUGINS = """  <gazebo>
    <plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so"/>
  </gazebo>
  <gazebo reference="arm_link">
    <sensor type="ray" name="laser">
      <plugin name="laser" filename="libgazebo_ros_laser.so"/>
    </sensor>
  </gazebo>
</robot>"""


@pytest.mark.parametrize(
    ("distro", "control", "laser"),
    [
        ("humble", "libgazebo_ros2_control.so", "libgazebo_ros_ray_sensor.so"),
        ("jazzy", "gz_ros2_control-system", "gz-sim-sensors-system"),
    ],
)
def test_a_ros1_gazebo_classic_plugin_loads_on_no_ros2_distro(tmp_path, distro, control, laser):
    """ROS 1's libgazebo_ros_control.so and libgazebo_ros_laser.so (gazebo_ros_pkgs' noetic-devel)
    are in no ROS 2 gazebo_plugins: a package copied from a ROS 1 tutorial loads neither, on any
    distro (they were missed: only ROS 2's Classic names were known). The replacement is ROS 2
    Classic's name where the distro releases Classic, else Gazebo's."""
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "rob_description", "--distro", distro)
    model = package / "urdf" / "rob_description.urdf.xacro"
    edit(model, "</robot>", ROS1_PLUGINS)
    report = verify_report(tmp_path, "--no-cache", "--distro", distro, "--select", "PF701")[1]
    assert found(report, "PF701") == [
        (
            "PF701",
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, "libgazebo_ros_control.so"),
            "error",
        ),
        (
            "PF701",
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, "libgazebo_ros_laser.so"),
            "error",
        ),
    ]
    messages = [d["message"] for d in report["diagnostics"]]
    assert f"use {control}" in messages[0] and f"use {laser}" in messages[1], messages
