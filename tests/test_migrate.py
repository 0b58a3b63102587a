"""`pkgforge migrate` and `pkgforge new --from-urdf` end to end: the exporter's ROS 1 package, a bare
URDF and a real robot (example-robot-data) become ROS 2 packages that build with `pkgforge build`
and verify clean in all three modes; bad input writes nothing and exits 2 with a located message."""

from __future__ import annotations

import importlib.metadata
import json
import os
import re
from pathlib import Path

import pytest
from conftest import MAINTAINER, line_of, lines_of, run_pkgforge
from lxml import etree
from migrate_fixtures import bare_urdf, ros1_package

UR5 = "ur_description/urdf/ur5_robot.urdf"


def robots_folder() -> Path:
    """example-robot-data's robots/ (the wheel is in the test extra)."""
    distribution = importlib.metadata.distribution("example-robot-data")
    folder = Path(distribution.locate_file("cmeel.prefix/share/example-robot-data/robots"))
    assert folder.is_dir(), "install the test extra: pip install -e '.[ament,test]'"
    return folder


def not_physics(out: str) -> list[str]:
    """The errors and warnings of verify's report in a command's output, but for the model's own
    physics (PF6xx: what the exporter wrote; a root link with an inertia is PF604)."""
    report = out.split("\nverify ", 1)[-1]
    return [
        line
        for line in report.splitlines()
        if re.search(r" PF\d{3} \[(error|warning)\]", line) and " PF6" not in line
    ]


@pytest.fixture(scope="module")
def migrated(tmp_path_factory):
    """One workspace: the exporter package migrated (py; and xml with --gazebo and format 1), a bare
    URDF and UR5 imported with --from-urdf; built once."""
    root = tmp_path_factory.mktemp("migrate")
    ros1 = root / "ros1"
    arm = ros1_package(ros1, "robot_arm")
    other = ros1_package(ros1, "robot_arm_xml", format_=1)
    (other / "urdf.rviz").unlink()  # the exporter refers to urdf.rviz and does not write it
    workspace = root / "ws"
    (workspace / "src").mkdir(parents=True)
    outputs = {
        "py": run_pkgforge("migrate", arm, "--destination", "src", "--add-root-link", cwd=workspace),
        "xml": run_pkgforge(
            "migrate",
            other,
            "--destination",
            "src",
            "--launch-format",
            "xml",
            "--gazebo",
            "--distro",
            "jazzy",
            cwd=workspace,
        ),
        "bare": run_pkgforge(
            "new", "arm_description", *MAINTAINER, "--from-urdf", bare_urdf(root / "export"), cwd=workspace
        ),
        "ur5": run_pkgforge(
            "new", "ur5_description", *MAINTAINER, "--from-urdf", robots_folder() / UR5, cwd=workspace
        ),
    }
    for name, result in outputs.items():
        # the models' own physics may fail verify (UR5's wrist_3_link inertia, PF610, is wrong
        # upstream: ros-industrial/universal_robot#426), and UR5's ROS 1 gazebo_ros_control plugin,
        # which --from-urdf keeps as written, loads in no ROS 2 Gazebo (PF701); nothing else may
        assert result.returncode in (0, 1), (name, result.stdout, result.stderr)
        left = [line for line in not_physics(result.stdout) if not (name == "ur5" and " PF701 " in line)]
        assert left == [], (name, result.stdout)
    assert "0 errors, 0 warnings" in outputs["py"].stdout  # --add-root-link: no PF604 either
    build = run_pkgforge("build", cwd=workspace)
    assert build.returncode == 0, build.stdout + build.stderr
    return root, workspace, outputs


@pytest.mark.triggers("PF801", "PF802", "PF803", "PF804", "PF805", "PF806")
def test_migrate_reports_every_change_at_its_line(migrated):
    root, _, outputs = migrated
    out = outputs["py"].stdout
    source = root / "ros1" / "robot_arm"
    display, gazebo, rviz = (
        source / "launch/display.launch",
        source / "launch/gazebo.launch",
        source / "urdf.rviz",
    )

    workspace = root / "ws"
    rviz_node, model_arg, rsp_type = 'pkg="rviz"', 'name="model"', 'type="state_publisher"'
    root_link = '<link name="base_link">'

    def at(path: Path, text: str) -> str:
        return f"{os.path.relpath(path, workspace)}:{line_of(path, text)}:"

    expected = [
        f"{at(display, rsp_type)} PF803 [info] node robot_state_publisher/state_publisher → "
        "robot_state_publisher/robot_state_publisher (migrate-renamed)",
        f"{at(display, rviz_node)} PF803 [info] node rviz/rviz → rviz2/rviz2 (migrate-renamed)",
        f"{at(display, 'textfile=')} PF806 [info] robot_description from textfile",
        f"{at(source / 'urdf/robot_arm.urdf', root_link)} PF806 [info] root link base_link has "
        "an inertia, which KDL ignores: link base_link_root added as the root, joined to it by a fixed joint "
        "(--add-root-link)",
        f"{at(display, model_arg)} PF806 [info] argument 'model' has no default and nothing uses it",
        f"{at(gazebo, 'empty_world')} PF802 [warning] Gazebo Classic's gazebo_ros launch/empty_world.launch left out",
        f"{at(gazebo, 'spawn_model')} PF802 [warning] gazebo_ros spawn_model (Gazebo Classic) left out",
        f"{at(gazebo, 'rostopic')} PF801 [warning] <node> left out: rostopic is a ROS 1 command-line tool",
        f"{at(rviz, 'jsk_rviz_plugin')} PF801 [warning] RViz class jsk_rviz_plugin/OverlayText has no RViz 2 "
        "equivalent",
        f"{at(rviz, 'rviz/RobotModel')} PF803 [info] RViz class rviz/RobotModel → rviz_default_plugins/RobotModel",
        f"{at(source / 'package.xml', 'catkin')} PF804 [info] <buildtool_depend>catkin</buildtool_depend> is "
        "ROS 1 only",
        f"{at(source / 'package.xml', '>gazebo<')} PF804 [info] <exec_depend>gazebo</exec_depend>: Gazebo Classic",
    ]
    rows = out.splitlines()
    for line in expected:
        assert any(row.startswith(line) for row in rows), (line, out)
    xml = outputs["xml"].stdout
    assert "PF805 [info] urdf.rviz (the -d config of rviz) is not in the source: rviz/urdf.rviz made" in xml
    assert "PF803 [info] gazebo_ros/spawn_model → ros_gz_sim/create" in xml


def test_migrated_package_is_ros2(migrated):
    _, workspace, _ = migrated
    package = workspace / "src" / "robot_arm"
    manifest = etree.parse(str(package / "package.xml")).getroot()
    assert manifest.get("format") == "3"
    assert manifest.findtext("buildtool_depend") == "ament_cmake"
    assert sorted(e.text for e in manifest.iter("exec_depend")) == [
        "joint_state_publisher",
        "joint_state_publisher_gui",
        "launch",
        "launch_ros",
        "robot_state_publisher",
        "rviz2",
        "rviz_default_plugins",
        "tf2_ros",
        "xacro",
    ]
    assert "DIRECTORY config launch meshes rviz textures urdf" in (package / "CMakeLists.txt").read_text()
    assert sorted(p.name for p in (package / "launch").iterdir()) == [
        "display.launch.py",
        "display_xacro.launch.py",
        "gazebo.launch.py",
    ]
    rviz = (package / "rviz" / "urdf.rviz").read_text()
    assert "rviz/" not in rviz.replace("rviz_", "") and "Value: /robot_description" in rviz
    assert "jsk_rviz_plugin" not in rviz and "Fixed Frame: base_link" in rviz
    # models unchanged but for the massless root KDL asks for (PF604 root-link-inertia), with
    # --add-root-link only: without it, byte for byte
    assert (workspace / "src/robot_arm_xml/urdf/robot_arm_xml.urdf").read_bytes() == (
        workspace.parent / "ros1/robot_arm_xml/urdf/robot_arm_xml.urdf"
    ).read_bytes()
    source_model = (workspace.parent / "ros1/robot_arm/urdf/robot_arm.urdf").read_text()
    migrated_model = (package / "urdf/robot_arm.urdf").read_text()
    added = (
        '\n  <link name="base_link_root"/>\n  <joint name="base_link_root_joint" type="fixed">\n'
        '    <parent link="base_link_root"/>\n    <child link="base_link"/>\n  </joint>'
    )
    assert added in migrated_model
    assert (
        re.sub(r"\n  <!-- added by pkgforge \(add-root-link\):[^\n]*-->", "", migrated_model).replace(
            added, ""
        )
        == source_model
    )
    gazebo = (workspace / "src/robot_arm_xml/launch/gazebo.launch.xml").read_text()
    assert '<include file="$(find-pkg-share ros_gz_sim)/launch/gz_sim.launch.py">' in gazebo
    assert 'exec="create"' in gazebo and "-name robot_arm_xml" in gazebo


@pytest.mark.parametrize("mode", [[], ["--build"], ["--install-base", "install"]])
def test_all_verify_clean_in_every_mode(migrated, mode):
    _, workspace, _ = migrated
    result = run_pkgforge("verify", "--format", "json", *mode, cwd=workspace)
    assert "Traceback" not in result.stderr
    report = json.loads(result.stdout)
    assert sorted(report["packages"][i]["name"] for i in range(len(report["packages"]))) == [
        "arm_description",
        "robot_arm",
        "robot_arm_xml",
        "ur5_description",
    ]
    assert [
        (d["code"], d["path"], d["message"][:40])
        for d in report["diagnostics"]
        if d["severity"] != "info" and not d["code"].startswith("PF6")
    ] == [("PF701", "src/ur5_description/urdf/ur5_robot.urdf", "plugin 'libgazebo_ros_control.so' does n")]
    # the errors left are UR5's own: its wrist_3_link inertia (PF610: wrong upstream,
    # ros-industrial/universal_robot#426) and its ROS 1 gazebo_ros_control plugin (PF701), which
    # --from-urdf keeps as written (migrate leaves it out, or converts it with --gazebo)
    errors = {
        (d["code"], d["path"].split("/")[-1]) for d in report["diagnostics"] if d["severity"] == "error"
    }
    assert errors <= {("PF610", "ur5_robot.urdf"), ("PF701", "ur5_robot.urdf")}, errors
    assert result.returncode == (1 if errors else 0)


@pytest.mark.parametrize(
    "package, launch, gui, config",
    [
        ("robot_arm", "display.launch.py", "joint_state_publisher", "share/robot_arm/rviz/urdf.rviz"),
        (
            "robot_arm",
            "display_xacro.launch.py",
            "joint_state_publisher_gui",
            "share/robot_arm/rviz/urdf.rviz",
        ),
        (
            "robot_arm_xml",
            "display.launch.xml",
            "joint_state_publisher",
            "share/robot_arm_xml/rviz/urdf.rviz",
        ),
        (
            "arm_description",
            "display.launch.py",
            "joint_state_publisher",
            "share/arm_description/rviz/display.rviz",
        ),
    ],
)
def test_converted_display_launch_resolves(migrated, package, launch, gui, config):
    _, workspace, _ = migrated
    result = run_pkgforge(
        "verify",
        "--install-base",
        "install",
        "--explain-launch",
        f"src/{package}/launch/{launch}",
        cwd=workspace,
    )
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert "robot_state_publisher/robot_state_publisher\n      param robot_description: typed-str" in out
    assert f"{gui}/{gui}" in out
    assert f"rviz2/rviz2 args ['-d', '{config}']" in out
    assert f"✓ {config}" in out and "✗" not in out


def test_real_robot_keeps_every_mesh(migrated):
    _, workspace, outputs = migrated
    source = robots_folder() / UR5
    meshes = {e.get("filename") for e in etree.parse(str(source)).iter("mesh")}
    assert len(meshes) == 14
    package = workspace / "src/ur5_description"
    copied = sorted(
        p.relative_to(package / "meshes").as_posix() for p in (package / "meshes").rglob("*") if p.is_file()
    )
    assert copied == sorted(m.split("/meshes/ur5/")[1] for m in meshes)
    model = (package / "urdf/ur5_robot.urdf").read_text()
    assert model.count("package://ur5_description/meshes/") == 14 and "example-robot-data" not in model
    assert "Fixed Frame: world" in (package / "rviz/display.rviz").read_text()
    explain = run_pkgforge(
        "verify",
        "--install-base",
        "install",
        "--explain-model",
        "src/ur5_description/urdf/ur5_robot.urdf",
        cwd=workspace,
    )
    assert explain.stdout.count("✓ package://ur5_description/meshes/") == 14 and "✗" not in explain.stdout
    assert (
        "PF802 [warning] Gazebo Classic plugin libgazebo_ros_control.so is kept as written"
        in outputs["ur5"].stdout
    )


def test_bare_urdf_meshes_by_relative_path(migrated):
    _, workspace, _ = migrated
    package = workspace / "src/arm_description"
    assert sorted(p.name for p in (package / "meshes").iterdir()) == [
        "base_link.STL",
        "link1.STL",
        "link2.STL",
    ]
    model = (package / "urdf/arm.urdf").read_text()
    assert 'filename="package://arm_description/meshes/link1.STL"' in model and "../meshes" not in model
    assert not (package / "urdf/macros.xacro").exists() and not (package / "meshes/arm.stl").exists()
    assert "urdf/arm.urdf" in (package / "launch/display.launch.py").read_text()


# --- bad input: a located message, exit 2, nothing written ---------------------------------------


def _break(kind: str, package: Path) -> tuple[Path, str]:
    """Break the ROS 1 package; (the file the message names, the text at its line)."""
    if kind == "not-catkin":
        manifest = package / "package.xml"
        manifest.write_text(manifest.read_text().replace(">catkin<", ">ament_cmake<"))
        return manifest, "<buildtool_depend>"
    if kind == "launch-xml":
        launch = package / "launch/display.launch"
        launch.write_text(
            launch.read_text().replace('<arg name="gui" default="False" />', '<arg name="gui" <')
        )
        return launch, '<arg name="gui" <'
    if kind == "missing-mesh":
        (package / "meshes/link1.STL").unlink()
        return package / "urdf/robot_arm.urdf", "meshes/link1.STL"
    raise AssertionError(kind)


@pytest.mark.parametrize(
    "kind, message",
    [
        ("not-catkin", "not a catkin package (its build tool is ament_cmake, not catkin)"),
        ("launch-xml", "not well-formed XML"),
        ("missing-mesh", "mesh 'package://robot_arm/meshes/link1.STL' not found"),
    ],
)
def test_migrate_bad_input_writes_nothing(tmp_path, kind, message):
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    path, text = _break(kind, package)
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out" / "src", cwd=tmp_path)
    assert result.returncode == 2, result.stdout + result.stderr
    first = result.stderr.splitlines()[0]
    assert first.startswith(f"pkgforge: error: {path}:{line_of(path, text)}: ") and message in first, first
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("file", ["package.xml", "launch/display.launch", "meshes/link1.STL"])
@pytest.mark.parametrize("what", ["fifo", "/dev/zero"])
def test_migrate_refuses_a_fifo_or_a_device_and_writes_nothing(tmp_path, file, what):
    """issue 35: a read of a FIFO blocks for ever, of /dev/zero never ends"""
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / file).unlink()
    os.mkfifo(package / file) if what == "fifo" else os.symlink(what, package / file)
    result = run_pkgforge(
        "migrate", package, "--destination", tmp_path / "out" / "src", cwd=tmp_path, timeout=120
    )
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stdout + result.stderr
    kind = "a FIFO (named pipe)" if what == "fifo" else "a link to /dev/zero, a character device"
    assert result.stderr.splitlines()[0] == (
        f"pkgforge: error: {package / file}: {kind}: pkgforge reads only regular files"
        + ("" if file == "package.xml" else "; move it out of the package")
        + " (nothing written)"
    )
    assert not (tmp_path / "out").exists()


def test_migrate_not_a_package_and_existing_destination(tmp_path):
    (tmp_path / "empty").mkdir()
    result = run_pkgforge("migrate", tmp_path / "empty", "--destination", tmp_path / "out", cwd=tmp_path)
    assert result.returncode == 2 and "no package.xml: not a catkin package" in result.stderr
    assert not (tmp_path / "out").exists()
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (tmp_path / "out" / "robot_arm").mkdir(parents=True)
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out", cwd=tmp_path)
    assert result.returncode == 2
    assert f"{tmp_path / 'out' / 'robot_arm'} already exists: migrate never overwrites" in result.stderr
    assert list((tmp_path / "out").iterdir()) == [tmp_path / "out" / "robot_arm"]
    assert list((tmp_path / "out" / "robot_arm").iterdir()) == []


def test_migrate_default_destination_beside_the_source(tmp_path):
    package = ros1_package(tmp_path, "robot_arm")
    result = run_pkgforge("migrate", package, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert (tmp_path / "robot_arm_ros2" / "launch" / "display.launch.py").is_file()
    assert (package / "launch" / "display.launch").is_file()  # the source is left as it was


def test_from_urdf_missing_mesh_writes_nothing(tmp_path):
    model = bare_urdf(tmp_path / "export")
    (tmp_path / "export/meshes/link2.STL").unlink()
    result = run_pkgforge(
        "new",
        "arm_description",
        *MAINTAINER,
        "--from-urdf",
        model,
        "--destination",
        tmp_path / "out",
        cwd=tmp_path,
    )
    assert result.returncode == 2
    # one line per missing mesh, not one per visual and collision naming it
    visual, collision = lines_of(model, "link2.STL")
    assert result.stderr.splitlines() == [
        f"pkgforge: error: {model}:{visual}: mesh '../meshes/link2.STL' not found: "
        f"no file {tmp_path / 'export/urdf/../meshes/link2.STL'} (also line {collision})",
        "1 file(s) the model names cannot be found: nothing written; copy them where the model says, "
        "or pass --force to write the package without them",
    ]
    assert not (tmp_path / "out").exists()
    forced = run_pkgforge(
        "new",
        "arm_description",
        *MAINTAINER,
        "--from-urdf",
        model,
        "--force",
        "--destination",
        tmp_path / "out",
        cwd=tmp_path,
    )
    assert forced.returncode == 1  # written without it; verify reports the mesh
    assert (
        "PF402" in forced.stdout and "PF801 [warning] mesh '../meshes/link2.STL' not found" in forced.stdout
    )


TUTORIAL = """<launch>
  <arg name="model" default="$(find robot_arm)/urdf/robot_arm.urdf"/>
  <arg name="gui" default="true" />
  <arg name="rvizconfig" default="$(find robot_arm)/urdf.rviz" />
  <param name="robot_description" command="$(find xacro)/xacro $(arg model)" />
  <node if="$(arg gui)" name="joint_state_publisher" pkg="joint_state_publisher_gui" type="joint_state_publisher_gui" />
  <node unless="$(arg gui)" name="joint_state_publisher" pkg="joint_state_publisher" type="joint_state_publisher" />
  <node name="robot_state_publisher" pkg="robot_state_publisher" type="robot_state_publisher">
    <remap from="joint_states" to="/arm/joint_states"/>
  </node>
  <group ns="tools">
    <node name="rviz" pkg="rviz" type="rviz" args="-d $(arg rvizconfig)">
      <rosparam command="load" file="$(find robot_arm)/config/joint_names_robot_arm.yaml"/>
    </node>
  </group>
  <machine name="robot" address="robot.local"/>
</launch>
"""


@pytest.mark.parametrize("launch_format", ["py", "xml", "yaml"])
def test_urdf_tutorial_style_launch(tmp_path, launch_format):
    """Arguments with defaults, if/unless, a remap, a group with a namespace, a node's rosparam file,
    and an RViz config named through an argument (which follows the config to rviz/)."""
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / "launch" / "display.launch").write_text(TUTORIAL)
    (tmp_path / "ws" / "src").mkdir(parents=True)
    result = run_pkgforge(
        "migrate", package, "--destination", "src", "--launch-format", launch_format, cwd=tmp_path / "ws"
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert not_physics(result.stdout) == [], result.stdout
    # the node's rosparam file, as a ROS 2 parameters file (rcl refuses ROS 1's layout: PF322)
    config = tmp_path / "ws/src/robot_arm/config/joint_names_robot_arm.yaml"
    assert config.read_text().startswith("/**:\n  ros__parameters:\n    controller_joint_names: ['',")
    launch = package / "launch/display.launch"
    assert (
        f"../ros1/robot_arm/launch/display.launch:{line_of(launch, '<machine')}: PF801 [warning] <machine> has "
        "no ROS 2 launch equivalent: left out (migrate-dropped)" in result.stdout
    )
    explain = run_pkgforge(
        "verify",
        "--explain-launch",
        f"src/robot_arm/launch/display.launch.{launch_format}",
        cwd=tmp_path / "ws",
    )
    out = explain.stdout
    assert "rviz2/rviz2 args ['-d', 'share/robot_arm/rviz/urdf.rviz']" in out, out
    assert "✓ share/robot_arm/config/joint_names_robot_arm.yaml" in out and "✗" not in out
    assert "joint_state_publisher_gui/joint_state_publisher_gui" in out and "[gui:=false]" in out


KEY = b"-----BEGIN OPENSSH PRIVATE KEY-----\nnot a real key, a stand-in\n-----END OPENSSH PRIVATE KEY-----\n"


def test_migrate_copies_no_link_out_of_the_package(tmp_path):
    """migrate copies the package's own regular files: a mesh or a config that is a link to a key in
    a (fake) HOME is refused by name before anything is written (a FIFO or a device is refused even
    before: test_migrate_refuses_a_fifo_or_a_device_and_writes_nothing)."""
    key = tmp_path / "home/.ssh/id_rsa"
    key.parent.mkdir(parents=True)
    key.write_bytes(KEY)
    key.chmod(0o600)
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / "meshes/link2.STL").unlink()
    (package / "meshes/link2.STL").symlink_to(key)
    (package / "config/secret.yaml").symlink_to(key)
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out", cwd=tmp_path, timeout=120)
    assert result.returncode == 2, result.stdout + result.stderr
    assert result.stderr.splitlines() == [
        f"pkgforge: error: {package / 'config/secret.yaml'}: it leads to {key} (a symbolic link), outside "
        f"{package}: not copied",
        f"{package / 'meshes/link2.STL'}: it leads to {key} (a symbolic link), outside {package}: not copied",
        "2 file(s) of the package cannot be copied: nothing written; replace each link that leads out of "
        "the package by the file it names, or move the file out of the package",
    ]
    assert KEY.decode() not in result.stdout + result.stderr
    assert not (tmp_path / "out").exists()


def test_migrate_copies_never_get_a_wider_mode(tmp_path):
    """A 600 mesh stays 600 (never 644), a script keeps its execute bits, a converted model keeps
    its source's bits; each narrowed by the umask. A link to a file inside the package is copied."""
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / "meshes/link1.STL").chmod(0o600)
    (package / "urdf/robot_arm.urdf").chmod(0o640)
    (package / "scripts").mkdir()
    (package / "scripts/tool.py").write_text("#!/usr/bin/env python3\n")
    (package / "scripts/tool.py").chmod(0o755)
    (package / "meshes/alias.STL").symlink_to("link2.STL")
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    migrated = tmp_path / "out/robot_arm"
    mask = os.umask(0o022)
    os.umask(mask)

    def mode(relative: str) -> int:
        return (migrated / relative).stat().st_mode & 0o777

    assert mode("meshes/link1.STL") == 0o600
    assert mode("scripts/tool.py") == 0o755 & ~mask
    assert mode("urdf/robot_arm.urdf") == 0o640 & ~mask
    assert mode("meshes/link2.STL") == 0o644 & ~mask
    assert mode("package.xml") == 0o666 & ~mask
    assert (migrated / "meshes/alias.STL").read_bytes() == (package / "meshes/link2.STL").read_bytes()
    assert not (migrated / "meshes/alias.STL").is_symlink()
