"""Gazebo worlds and SDF models a package installs (PF420-PF422, issue 31 item 4): each case is the
clean fixture with one defect, asserted at its code, file and line; the clean fixture, and its
nearest-clean variants, give nothing on humble and on jazzy."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import FIXTURES, edit, line_of, verify_report

WORLD = "src/world_sim/worlds/yard.sdf"
MODEL = "src/world_sim/models/crate/model.sdf"


def world_package(tmp_path: Path) -> Path:
    package = tmp_path / "src" / "world_sim"
    shutil.copytree(FIXTURES / "worlds" / "world_sim", package)
    return package


def found(report: dict) -> list[tuple[str, str, str, int]]:
    return [(d["code"], d["severity"], d["path"], d["line"]) for d in report["diagnostics"]]


@pytest.mark.parametrize("distro", ["humble", "jazzy"])
def test_the_clean_world_package_has_no_diagnostic(tmp_path, distro):
    world_package(tmp_path)
    status, report = verify_report(tmp_path, "--distro", distro)
    assert (status, report["diagnostics"]) == (0, [])


@pytest.mark.triggers("PF420")
def test_a_world_that_is_not_xml_or_has_no_sdf_version_is_an_error(tmp_path):
    package = world_package(tmp_path)
    world = package / "worlds" / "yard.sdf"
    edit(world, '<sdf version="1.9">', "<sdf>")
    (package / "worlds" / "cut.sdf").write_text('<sdf version="1.9">\n  <world name="cut">\n')
    (package / "worlds" / "future.world").write_text('<sdf version="2.0">\n  <world name="f"/>\n</sdf>\n')
    status, report = verify_report(tmp_path)
    assert status == 1
    assert found(report) == [
        ("PF420", "error", "src/world_sim/worlds/cut.sdf", 3),  # where the text ends
        ("PF420", "error", "src/world_sim/worlds/future.world", 1),
        ("PF420", "error", WORLD, line_of(world, "<sdf>")),
    ]
    assert "without a version" in report["diagnostics"][2]["message"]


def test_an_attribute_newer_than_the_declared_version_and_model_uris_with_three_slashes_pass(tmp_path):
    """Nearest clean: sdformat converts a 1.6 file to its newest version before reading it, so
    relative_to (SDF 1.8) is read (ros_gz_project_template's diff_drive.sdf: merge= in 1.8);
    model:///crate is model://crate (turtlebot3_house's table_marble: gz-common and Classic join
    the rest to each resource path)."""
    package = world_package(tmp_path)
    world = package / "worlds" / "yard.sdf"
    edit(world, '<sdf version="1.9">', '<sdf version="1.6">')
    edit(world, "<uri>model://crate</uri>", "<uri>model:///crate</uri>")
    status, report = verify_report(tmp_path)
    assert (status, report["diagnostics"]) == (0, [])


def test_what_sdformats_xml_reader_reads_is_no_error(tmp_path):
    """Nearest clean (gz_ros2_control_demos' empty_ft_sensor.sdf): tinyxml2, sdformat's reader,
    ends a comment at the first "-->" ("--" inside is text), an attribute at its quote, keeps an
    unknown entity as text and knows no namespaces (a world Gazebo saved keeps its models'
    <surface_props:material> without their xmlns); what it refuses too (a tag left open) is still
    PF420."""
    package = world_package(tmp_path)
    world = package / "worlds" / "yard.sdf"
    edit(
        world,
        '<sdf version="1.9">',
        '<!--\n  gz service -s /world/yard/create --req "..."\n-->\n<sdf version="1.9">',
    )
    edit(
        world,
        "<uri>model://crate</uri>",
        "<uri>model://crate</uri><!-- a <b> -- note -->\n"
        "      <surface_props:material>metal&nbsp;sheet</surface_props:material>",
    )
    (package / "worlds" / "open.world").write_text(
        '<!-- a -- b -->\n<sdf version="1.6">\n  <world name="w">\n</sdf>\n'
    )
    status, report = verify_report(tmp_path)
    assert found(report) == [("PF420", "error", "src/world_sim/worlds/open.world", 4)]


def test_a_world_plugin_written_over_two_lines_is_checked_and_a_commented_one_is_not(tmp_path):
    """gopigo3's worlds: `<plugin` on one line, `filename="libignition-gazebo-...so"` on the next
    was not read (Gazebo Ionic loads no ignition-gazebo- library); a plugin inside a comment loads
    nowhere and is no finding."""
    package = world_package(tmp_path)
    world = package / "worlds" / "yard.sdf"
    edit(
        world,
        '<world name="yard">',
        '<world name="yard">\n    <plugin\n      filename="libignition-gazebo-user-commands-system.so"\n'
        '      name="ignition::gazebo::systems::UserCommands"/>\n'
        '    <!-- <plugin filename="libgazebo_ros_diff_drive.so" name="drive"/> -->',
    )
    status, report = verify_report(tmp_path, "--distro", "kilted")
    assert found(report) == [("PF701", "error", WORLD, line_of(world, "    <plugin"))]
    assert "use gz-sim-user-commands-system" in report["diagnostics"][0]["message"]


@pytest.mark.triggers("PF421")
def test_uris_not_found_or_into_a_home_folder(tmp_path):
    package = world_package(tmp_path)
    world, model = package / "worlds" / "yard.sdf", package / "models" / "crate" / "model.sdf"
    edit(world, "crate/meshes/crate.stl</uri>", "crate/meshes/gone.stl</uri>")
    edit(model, "model://crate/meshes/crate.stl", "model://crate/meshes/lost.stl")
    edit(model, "<uri>meshes/crate.stl</uri>", "<uri>meshes/crate.STL</uri>")
    (package / "worlds" / "home.world").write_text(
        '<sdf version="1.6">\n  <world name="w">\n    <include><uri>model://sun</uri></include>\n'
        "    <include><uri>file:///home/ada/models/tree</uri></include>\n"
        "    <include><uri>model://oak_tree</uri></include>\n"
        "    <include><uri>birch</uri></include>\n  </world>\n</sdf>\n"
    )
    status, report = verify_report(tmp_path)
    assert status == 1
    assert found(report) == [
        ("PF421", "error", MODEL, line_of(model, "lost.stl")),
        ("PF421", "error", MODEL, line_of(model, "crate.STL")),
        ("PF421", "error", "src/world_sim/worlds/home.world", 4),
        ("PF421", "warning", "src/world_sim/worlds/home.world", 5),
        ("PF421", "warning", "src/world_sim/worlds/home.world", 6),  # a bare name: the path too
        ("PF421", "error", WORLD, line_of(world, "gone.stl")),
    ]
    assert "home folder" in report["diagnostics"][2]["message"]


@pytest.mark.triggers("PF422")
def test_a_models_folder_nothing_puts_on_the_resource_path(tmp_path):
    package = world_package(tmp_path)
    edit(package / "package.xml", '    <gazebo_ros gazebo_model_path="${prefix}/models"/>\n', "")
    model = package / "models" / "crate" / "model.sdf"
    status, report = verify_report(tmp_path)
    assert status == 1
    assert found(report) == [("PF422", "error", MODEL, line_of(model, "model://crate"))]
    # nearest clean: an environment hook of the package sets the variable
    (package / "hooks").mkdir()
    (package / "hooks" / "world_sim.dsv.in").write_text(
        "prepend-non-duplicate;GZ_SIM_RESOURCE_PATH;share/world_sim/models\n"
    )
    edit(
        package / "CMakeLists.txt",
        "ament_package()",
        'ament_environment_hooks("${CMAKE_CURRENT_SOURCE_DIR}/hooks/world_sim.dsv.in")\nament_package()',
    )
    status, report = verify_report(tmp_path)
    assert (status, report["diagnostics"]) == (0, [])


def test_an_export_of_the_share_parent_covers_package_uris_not_model_names(tmp_path):
    """${prefix}/.. (ros_gz_sim's README's advice) puts install/share on the path: model://crate
    (a folder of share/world_sim/models) is then on no resource path."""
    package = world_package(tmp_path)
    edit(package / "package.xml", "${prefix}/models", "${prefix}/..")
    status, report = verify_report(tmp_path)
    assert [d["code"] for d in report["diagnostics"]] == ["PF422"]
    edit(
        package / "worlds" / "yard.sdf",
        "<uri>model://crate</uri>",
        "<uri>model://world_sim/models/crate</uri>",
    )
    edit(
        package / "models" / "crate" / "model.sdf",
        "model://crate/meshes",
        "model://world_sim/models/crate/meshes",
    )
    status, report = verify_report(tmp_path)
    assert (status, report["diagnostics"]) == (0, [])
