"""Robot models, meshes and RViz configs in the install tree: each defect, exactly its check."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import MAINTAINER, at_least, edit, line_of, run_pkgforge, verify_report
from test_launch import humble_package

from pkgforge.scaffold.stl import binary_stl, box_triangles

verify = verify_report


def found(report: dict, minimum: str = "info") -> list[tuple]:
    return sorted((d["code"], d["name"], d["path"], d["line"]) for d in at_least(report, minimum))


PLATE = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="plate" params="parent">
    <link name="plate_link">
      <visual>
        <geometry>
          <mesh filename="package://base_description/meshes/plate.stl"/>
        </geometry>
      </visual>
    </link>
    <joint name="plate_joint" type="fixed">
      <parent link="${parent}"/>
      <child link="plate_link"/>
    </joint>
  </xacro:macro>
</robot>
"""


@pytest.fixture(scope="module")
def template(tmp_path_factory) -> Path:
    """Two packages: rob_description includes a macro (and its mesh) from base_description."""
    workspace = tmp_path_factory.mktemp("two")
    for name in ("base_description", "rob_description"):
        result = run_pkgforge("new", name, *MAINTAINER, "--destination", "src", cwd=workspace)
        assert result.returncode == 0, result.stderr
    base = workspace / "src" / "base_description"
    (base / "urdf" / "plate.xacro").write_text(PLATE)
    (base / "meshes" / "plate.stl").write_bytes(binary_stl(box_triangles((0.2, 0.2, 0.01))))
    rob = workspace / "src" / "rob_description"
    edit(
        rob / "urdf" / "rob_description.urdf.xacro",
        '  <xacro:include filename="$(find rob_description)/urdf/macros.xacro"/>\n',
        '  <xacro:include filename="$(find rob_description)/urdf/macros.xacro"/>\n'
        '  <xacro:include filename="$(find base_description)/urdf/plate.xacro"/>\n'
        '  <xacro:plate parent="base_link"/>\n',
    )
    edit(
        rob / "package.xml",
        "  <exec_depend>joint_state_publisher</exec_depend>\n",
        "  <exec_depend>base_description</exec_depend>\n  <exec_depend>joint_state_publisher</exec_depend>\n",
    )
    return workspace


@pytest.fixture
def workspace(tmp_path, template) -> Path:
    shutil.copytree(template / "src", tmp_path / "src")
    return tmp_path


def rob(workspace: Path) -> Path:
    return workspace / "src" / "rob_description"


def test_clean_across_two_packages(workspace):
    status, report = verify(workspace)
    assert status == 0
    assert found(report) == []


@pytest.mark.triggers("PF402")
def test_meshes_folder_not_installed(workspace):
    cmake = rob(workspace) / "CMakeLists.txt"
    edit(cmake, "DIRECTORY launch meshes rviz urdf", "DIRECTORY launch rviz urdf")
    model = rob(workspace) / "urdf" / "rob_description.urdf.xacro"
    status, report = verify(workspace)
    assert status == 1
    assert found(report) == [
        (
            "PF402",
            "mesh-not-found",
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, "meshes/arm.stl"),
        )
    ]
    assert f"CMakeLists.txt:{line_of(cmake, 'install(')}" in report["diagnostics"][0]["hint"]


@pytest.mark.triggers("PF403")
def test_mesh_case_mismatch(workspace):
    meshes = rob(workspace) / "meshes"
    (meshes / "arm.stl").rename(meshes / "arm.STL")
    model = rob(workspace) / "urdf" / "rob_description.urdf.xacro"
    status, report = verify(workspace)
    assert found(report) == [
        (
            "PF403",
            "mesh-case-mismatch",
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, "meshes/arm.stl"),
        )
    ]
    assert "arm.STL" in report["diagnostics"][0]["hint"]


@pytest.mark.triggers("PF305")
def test_find_of_an_undeclared_package(workspace):
    edit(rob(workspace) / "package.xml", "  <exec_depend>base_description</exec_depend>\n", "")
    model = rob(workspace) / "urdf" / "rob_description.urdf.xacro"
    status, report = verify(workspace)
    assert status == 1
    assert found(report) == [
        (
            "PF305",
            "missing-exec-depend",
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, "$(find base_description)"),
        )
    ]
    assert report["diagnostics"][0]["hint"].startswith("add <exec_depend>base_description</exec_depend>")


def test_include_of_a_missing_file(workspace):
    model = rob(workspace) / "urdf" / "rob_description.urdf.xacro"
    edit(model, "urdf/plate.xacro", "urdf/plates.xacro")
    status, report = verify(workspace)
    assert status == 1
    assert found(report) == [
        (
            "PF308",
            "xacro-error",
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, "plates.xacro"),
        )
    ]
    assert "plates.xacro" in report["diagnostics"][0]["message"]


@pytest.mark.triggers("PF401")
def test_joint_with_a_missing_child_link(workspace):
    model = rob(workspace) / "urdf" / "rob_description.urdf.xacro"
    edit(model, '<child link="arm_link"/>', '<child link="arm"/>')
    status, report = verify(workspace)
    assert status == 1
    assert (
        "PF401",
        "urdf-invalid",
        "src/rob_description/urdf/rob_description.urdf.xacro",
        line_of(model, '<joint name="arm_joint"'),
    ) in found(report)
    messages = [d["message"] for d in report["diagnostics"] if d["code"] == "PF401"]
    assert "joint 'arm_joint' has child link 'arm', which does not exist" in messages
    assert {d["code"] for d in report["diagnostics"]} == {"PF401"}


@pytest.mark.triggers("PF502")
def test_robot_model_with_an_empty_description_topic(workspace):
    config = rob(workspace) / "rviz" / "display.rviz"
    edit(config, "        Value: /robot_description", '        Value: ""')
    status, report = verify(workspace)
    assert status == 1
    assert found(report) == [
        (
            "PF502",
            "rviz-no-description",
            "src/rob_description/rviz/display.rviz",
            line_of(config, "Description Topic:"),
        )
    ]


@pytest.mark.triggers("PF503")
def test_fixed_frame_not_in_the_model(workspace):
    config = rob(workspace) / "rviz" / "display.rviz"
    edit(config, "Fixed Frame: base_link", "Fixed Frame: base_footprint")
    status, report = verify(workspace)
    assert status == 0
    assert found(report) == [
        (
            "PF503",
            "rviz-fixed-frame-unknown",
            "src/rob_description/rviz/display.rviz",
            line_of(config, "Fixed Frame:"),
        )
    ]
    assert "map, odom or world" in report["diagnostics"][0]["hint"]


def test_fixed_frame_map_is_accepted(workspace):
    edit(rob(workspace) / "rviz" / "display.rviz", "Fixed Frame: base_link", "Fixed Frame: map")
    assert found(verify(workspace)[1]) == []


@pytest.mark.triggers("PF501")
def test_rviz_config_that_is_not_rviz(workspace):
    config = rob(workspace) / "rviz" / "display.rviz"
    config.write_text("Panels: [\n  - oops\n")
    status, report = verify(workspace)
    assert found(report, "warning") == [("PF501", "rviz-invalid", "src/rob_description/rviz/display.rviz", 2)]


def test_rviz_plugin_from_an_undeclared_package(workspace):
    config = rob(workspace) / "rviz" / "display.rviz"
    edit(
        config,
        "    - Class: rviz_default_plugins/TF\n",
        "    - Class: nav2_rviz_plugins/GoalTool\n      Name: Goal\n    - Class: rviz_default_plugins/TF\n",
    )
    status, report = verify(workspace)
    assert found(report) == [
        (
            "PF305",
            "missing-exec-depend",
            "src/rob_description/rviz/display.rviz",
            line_of(config, "nav2_rviz_plugins"),
        )
    ]


# --- the seed 000 model shape --------------------------------------------------------------


def test_seed000_model_verifies_clean_once_installed(tmp_path):
    humble_package(tmp_path)
    status, report = verify(tmp_path)
    assert status == 0
    assert found(report, "warning") == []


def test_seed000_model_with_an_include_deleted(tmp_path):
    package = humble_package(tmp_path)
    (package / "urdf" / "rviz_track.urdf.xacro").unlink()
    top = package / "urdf" / "robot_simple_description.urdf.xacro"
    status, report = verify(tmp_path)
    assert status == 1
    assert found(report, "warning") == [
        (
            "PF308",
            "xacro-error",
            "src/rob_description/urdf/robot_simple_description.urdf.xacro",
            line_of(top, "rviz_track.urdf.xacro"),
        )
    ]


# --- broken models: located, no traceback ---------------------------------------------------


def test_broken_models(workspace):
    urdf = rob(workspace) / "urdf"
    (urdf / "big.urdf").write_bytes(b'<robot name="big">' + b" " * 50_000_000 + b"</robot>")
    (urdf / "loop.xacro").write_text(
        '<robot name="l" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="a"/>\n'
        '  <xacro:include filename="$(find rob_description)/urdf/loop.xacro"/>\n'
        "</robot>\n"
    )
    (urdf / "garbage.urdf").write_bytes(bytes(range(256)) * 64)
    (urdf / "escape.urdf").write_text(
        '<robot name="e">\n  <link name="a">\n    <visual><geometry>\n'
        '      <mesh filename="package://rob_description/../../etc/passwd"/>\n'
        "    </geometry></visual>\n  </link>\n</robot>\n"
    )
    status, report = verify(workspace, "--launch-timeout", "8")
    by_file = {}
    for d in report["diagnostics"]:
        by_file.setdefault(Path(d["path"]).name, []).append((d["code"], d["line"]))
    assert by_file["big.urdf"] == [("PF901", None)]
    assert by_file["loop.xacro"] == [("PF308", 3)]
    assert by_file["garbage.urdf"] == [("PF401", 1)]
    assert by_file["escape.urdf"] == [("PF402", 4)]


def test_explain_model(workspace):
    result = run_pkgforge(
        "verify", "--explain-model", "src/rob_description/urdf/rob_description.urdf.xacro", cwd=workspace
    )
    assert result.returncode == 0, result.stderr
    assert "base_link" in result.stdout and "arm_joint (revolute) → arm_link" in result.stdout
    assert "✓ package://rob_description/meshes/arm.stl" in result.stdout
    assert "✓ package://base_description/meshes/plate.stl" in result.stdout


# --- models wherever they are installed (issue 12) ---------------------------------------------

XACRO = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
ARM_MODEL = """<?xml version="1.0"?>
<robot name="arm_bot">
  <link name="base_link"/>
  <link name="tool">
    <visual>
      <geometry>
        <mesh filename="package://rob_description/meshes/tool.stl"/>
      </geometry>
    </visual>
  </link>
  <joint name="tool_joint" type="fixed">
    <parent link="base_link"/>
    <child link="tool"/>
  </joint>
</robot>
"""
GRIPPER_MACROS = f"""<?xml version="1.0"?>
<robot {XACRO}>
  <!-- a library: the model that includes it sets parts_dir first -->
  <xacro:include filename="${{parts_dir}}/gripper_parts.xacro"/>
  <xacro:property name="finger_length" value="0.05"/>
  <xacro:macro name="gripper" params="parent">
    <link name="finger"/>
    <joint name="finger_joint" type="fixed">
      <parent link="${{parent}}"/>
      <child link="finger"/>
    </joint>
  </xacro:macro>
</robot>
"""
CELL_MODEL = f"""<?xml version="1.0"?>
<robot name="cell" {XACRO}>
  <xacro:include filename="$(find rob_description)/config/cell_macros.xacro"/>
  <link name="world"/>
  <xacro:table parent="world"/>
</robot>
"""
CELL_MACROS = f"""<?xml version="1.0"?>
<robot {XACRO}>
  <xacro:macro name="table" params="parent">
    <link name="table"/>
    <joint name="table_joint" type="fixed">
      <parent link="${{parent}}_frame"/>
      <child link="table"/>
    </joint>
  </xacro:macro>
</robot>
"""
# a piece of a robot whose include is commented out in the robot (articubot_one's depth_camera.xacro):
# processed alone it could only fail on 'chassis'
CAMERA_FRAGMENT = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <joint name="camera_joint" type="fixed">
    <parent link="chassis"/>
    <child link="camera_link"/>
  </joint>
  <link name="camera_link"/>
</robot>
"""
WORLD = f"""<?xml version="1.0"?>
<sdf version="1.6" {XACRO}>
  <world name="${{undefined_world_name}}"/>
</sdf>
"""


def test_models_are_found_wherever_installed_and_macro_libraries_alone_give_nothing(workspace):
    package = rob(workspace)
    (package / "models" / "arm_bot").mkdir(parents=True)
    (package / "models" / "arm_bot" / "model.urdf").write_text(ARM_MODEL)  # tool.stl does not exist
    (package / "models" / "gripper").mkdir()
    (package / "models" / "gripper" / "gripper_macros.xacro").write_text(GRIPPER_MACROS)
    (package / "config").mkdir()
    (package / "config" / "cell.urdf.xacro").write_text(CELL_MODEL)  # a joint's parent link is wrong
    (package / "config" / "cell_macros.xacro").write_text(CELL_MACROS)
    (package / "config" / "depth_camera.xacro").write_text(CAMERA_FRAGMENT)  # a fragment: nothing
    (package / "worlds").mkdir()
    (package / "worlds" / "empty.world.xacro").write_text(WORLD)  # not a robot
    (package / "top.urdf").write_text(ARM_MODEL.replace("arm_bot", "top").replace("tool.stl", "top.stl"))
    edit(
        package / "CMakeLists.txt",
        "DIRECTORY launch meshes rviz urdf",
        "DIRECTORY config launch meshes models rviz urdf worlds",
    )
    edit(
        package / "CMakeLists.txt",
        "ament_package()",
        "install(FILES top.urdf DESTINATION share/${PROJECT_NAME})\n\nament_package()",
    )
    for args in [(), ("--build",)]:
        status, report = verify(workspace, *args, "--no-cache")
        assert status == 1
        assert found(report) == [
            (
                "PF401",
                "urdf-invalid",
                "src/rob_description/config/cell_macros.xacro",
                line_of(package / "config" / "cell_macros.xacro", '<joint name="table_joint"'),
            ),
            (
                "PF402",
                "mesh-not-found",
                "src/rob_description/models/arm_bot/model.urdf",
                line_of(package / "models" / "arm_bot" / "model.urdf", "tool.stl"),
            ),
            (
                "PF402",
                "mesh-not-found",
                "src/rob_description/top.urdf",
                line_of(package / "top.urdf", "top.stl"),
            ),
        ], args
