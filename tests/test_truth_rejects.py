"""Issue 28, classes 3, 6, 7 and 8: what rviz2, ROS 2's xacro, colcon, urdfdom and rosdep reject
or silently ignore at run time, caught by verify at the file and line a person edits.

3. ROS 1 leftovers: an RViz 1 config (rviz/ classes rviz2 cannot load; `fix` converts it) and
   xacro's un-prefixed ROS 1 tags (<macro>, <property>, <if> ...).
6. A package.xml inside another package's folder, which colcon never finds.
7. What urdfdom refuses (the whole model) or drops (a part, a colour), and a <mimic> naming no
   joint, read from urdfdom's parser (link.cpp, joint.cpp, pose.cpp, model.cpp).
8. A dependency released in no active distro, no rosdep key, not in the workspace nor a .repos
   file: `rosdep install` fails on it everywhere.

Each with the nearest case that must stay clean.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import FIXTURES, edit, line_of, run_pkgforge, verify_report

ROS1 = FIXTURES / "ros1_leftovers"
URDFDOM = FIXTURES / "urdfdom"


def found(report: dict, code: str) -> list[tuple[str, int | None, str]]:
    """(path, line, severity) of every diagnostic with `code`, sorted."""
    return sorted((d["path"], d["line"], d["severity"]) for d in report["diagnostics"] if d["code"] == code)


def messages(report: dict, code: str) -> list[str]:
    return [d["message"] for d in report["diagnostics"] if d["code"] == code]


def at_least_warnings(report: dict) -> list[tuple[str, str, int | None]]:
    return sorted(
        (d["code"], d["path"], d["line"])
        for d in report["diagnostics"]
        if d["severity"] in ("warning", "error")
    )


# --- 3. an RViz 1 config ---------------------------------------------------------------------------


@pytest.mark.triggers("PF504")
def test_an_rviz1_config_is_an_error_at_its_robot_model_naming_the_rviz2_classes(package):
    config = package / "rviz" / "display.rviz"
    shutil.copy(ROS1 / "display_rviz1.rviz", config)
    status, report = verify_report(package, "--no-cache")
    assert status == 1
    assert at_least_warnings(report) == [
        ("PF504", "rviz/display.rviz", line_of(config, "Class: rviz/RobotModel"))
    ]
    (message,) = messages(report, "PF504")
    assert "rviz/RobotModel → rviz_default_plugins/RobotModel, rviz/TF → rviz_default_plugins/TF" in message
    assert message.endswith("it shows no robot")


def test_the_plugins_an_rviz1_config_names_are_no_dependency(package):
    """One cause, one finding: rviz2 loads no display of an RViz 1 config, so a display from an
    undeclared plugin package there (husky_viz's rviz_imu_plugin/Imu) is not also missing-exec-depend."""
    config = package / "rviz" / "display.rviz"
    shutil.copy(ROS1 / "display_rviz1.rviz", config)
    edit(config, "Class: rviz/TF", "Class: rviz_imu_plugin/Imu")
    _, report = verify_report(package, "--no-cache")
    assert at_least_warnings(report) == [
        ("PF504", "rviz/display.rviz", line_of(config, "Class: rviz/RobotModel"))
    ]


def test_fix_converts_an_rviz1_config_only_with_unsafe_fixes(package):
    config = package / "rviz" / "display.rviz"
    shutil.copy(ROS1 / "display_rviz1.rviz", config)
    workspace = package.parent.parent
    before = config.read_bytes()
    result = run_pkgforge("fix", ".", cwd=workspace)
    assert result.returncode == 1 and config.read_bytes() == before  # unsafe: not by default
    result = run_pkgforge("fix", ".", "--unsafe-fixes", cwd=workspace)
    assert result.returncode == 0, result.stdout + result.stderr
    text = config.read_text()
    assert "rviz/" not in text.replace("Orbit (rviz)", "")
    # the group and its displays kept (rviz/Group is rviz_common/Group), the RobotModel on the topic
    assert "Class: rviz_common/Group" in text and "Class: rviz_default_plugins/TF" in text
    assert "Description Source: Topic" in text and "Value: /robot_description" in text
    assert "Robot Description:" not in text
    _, report = verify_report(workspace, "--no-cache")
    assert at_least_warnings(report) == []


def test_an_rviz2_config_naming_rviz_elsewhere_is_no_rviz1_config(package):
    # the scaffold's RViz 2 config (its view's Value: Orbit (rviz)), with a plugin of another package
    config = package / "rviz" / "display.rviz"
    edit(
        config,
        "    - Class: rviz_default_plugins/TF\n",
        "    - Class: rviz_plugin/Overlay\n      Name: O\n    - Class: rviz_default_plugins/TF\n",
    )
    _, report = verify_report(package, "--no-cache")
    assert found(report, "PF504") == []


# --- 3. xacro's ROS 1 tags ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def xacro_tags(tmp_path_factory, template_package) -> tuple[Path, dict]:
    workspace = tmp_path_factory.mktemp("ros1tags")
    package = workspace / "src" / "rob_description"
    shutil.copytree(template_package, package)
    for name in ("ros1_macros.urdf.xacro", "ros1_if.urdf.xacro", "prefixed.urdf.xacro"):
        shutil.copy(ROS1 / name, package / "urdf" / name)
    return package, verify_report(package, "--no-cache")[1]


@pytest.mark.triggers("PF408")
def test_a_bare_macro_is_named_at_its_line_not_a_name_error(xacro_tags):
    package, report = xacro_tags
    model = package / "urdf" / "ros1_macros.urdf.xacro"
    assert ("urdf/ros1_macros.urdf.xacro", line_of(model, "<property"), "error") in found(report, "PF408")
    (message,) = [m for m in messages(report, "PF408") if "ros1_macros" in m]
    assert (
        f"<property> (line {line_of(model, '<property')}), <macro> (line {line_of(model, '<macro')})"
        in message
    )
    hint = next(
        d["hint"] for d in report["diagnostics"] if d["code"] == "PF408" and "ros1_macros" in d["message"]
    )
    assert hint.startswith("write <xacro:property>")
    # the NameError is xacro's consequence, not a second diagnostic
    assert not [d for d in report["diagnostics"] if d["code"] == "PF308"]


def test_a_bare_if_that_xacro_passes_is_named_too(xacro_tags):
    package, report = xacro_tags
    model = package / "urdf" / "ros1_if.urdf.xacro"
    assert ("urdf/ros1_if.urdf.xacro", line_of(model, "<if value="), "error") in found(report, "PF408")


def test_prefixed_tags_and_sdf_include_in_gazebo_are_no_ros1_tags(xacro_tags):
    _, report = xacro_tags
    assert [d for d in report["diagnostics"] if "prefixed.urdf.xacro" in d["path"]] == []
    assert len(found(report, "PF408")) == 2


# --- 6. a package inside another -------------------------------------------------------------------


def inner_manifest(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True)
    manifest = folder / "package.xml"
    manifest.write_text(
        '<?xml version="1.0"?>\n<package format="3">\n'
        f"  <name>{name}</name>\n  <version>0.1.0</version>\n  <description>inner</description>\n"
        '  <maintainer email="t@example.com">T</maintainer>\n  <license>Apache-2.0</license>\n'
        "  <buildtool_depend>ament_cmake</buildtool_depend>\n"
        "  <export><build_type>ament_cmake</build_type></export>\n</package>\n"
    )
    (folder / "CMakeLists.txt").write_text(
        f"cmake_minimum_required(VERSION 3.8)\nproject({name} NONE)\n"
        "find_package(ament_cmake REQUIRED)\nament_package()\n"
    )
    return manifest


@pytest.mark.triggers("PF111")
def test_a_package_inside_another_is_a_warning_at_its_manifest(package):
    manifest = inner_manifest(package / "simulation" / "rob_gazebo", "rob_gazebo")
    _, report = verify_report(package, "--no-cache")
    assert at_least_warnings(report) == [
        ("PF111", "simulation/rob_gazebo/package.xml", line_of(manifest, "<name>"))
    ]
    (message,) = messages(report, "PF111")
    assert "inside package 'rob_description'" in message
    (hint,) = [d["hint"] for d in report["diagnostics"] if d["code"] == "PF111"]
    assert "beside rob_description (a sibling folder, e.g. src/rob_gazebo)" in hint


def test_a_sibling_package_an_ignored_one_and_one_installed_as_data_are_no_nested_package(package):
    inner_manifest(package.parent / "rob_gazebo", "rob_gazebo")  # beside it: colcon finds it
    inner_manifest(package / "ros1" / "rob_old", "rob_old")
    (package / "ros1" / "rob_old" / "CATKIN_IGNORE").touch()
    inner_manifest(package / "templates" / "rob_template", "rob_template")
    edit(package / "CMakeLists.txt", "DIRECTORY launch meshes", "DIRECTORY templates launch meshes")
    _, report = verify_report(package, "--no-cache")
    assert found(report, "PF111") == []


# --- 7. what urdfdom refuses or drops ------------------------------------------------------------


@pytest.fixture(scope="module")
def urdfdom(tmp_path_factory, template_package) -> tuple[Path, dict]:
    workspace = tmp_path_factory.mktemp("urdfdom")
    package = workspace / "src" / "rob_description"
    shutil.copytree(template_package, package)
    for model in URDFDOM.iterdir():
        shutil.copy(model, package / "urdf" / model.name)
    return package, verify_report(package, "--no-cache")[1]


@pytest.mark.triggers("PF401")
def test_what_urdfdom_refuses_the_model_for_is_urdf_invalid_at_each_element(urdfdom):
    package, report = urdfdom
    model = package / "urdf" / "refused.urdf"
    assert [f for f in found(report, "PF401") if "refused" in f[0]] == [
        ("urdf/refused.urdf", line_of(model, '<material name="grey">') + 1, "error"),  # the second one
        ("urdf/refused.urdf", line_of(model, '"ja"'), "error"),
        ("urdf/refused.urdf", line_of(model, '"jb"'), "error"),
        ("urdf/refused.urdf", line_of(model, '"jc"'), "error"),
        ("urdf/refused.urdf", line_of(model, '"jd"'), "error"),
    ]
    text = " | ".join(messages(report, "PF401"))
    for said in (
        "material 'grey' is defined twice under <robot>",
        "joint 'ja': <origin xyz=\"0 0 0.1 0\">: 4 value(s), not 3",
        "joint 'jb': <limit>: no effort=",
        "joint 'jc': <axis xyz=\"0,0,1\">: '0,0,1' is not a number",
        "joint 'jd': <dynamics> has neither damping= nor friction=",
        "urdfdom refuses the whole model",
    ):
        assert said in text
    # a limit without effort is urdf-invalid's, not a joint-limit-invalid warning about None
    assert not [d for d in report["diagnostics"] if d["code"] == "PF605" and "refused" in d["path"]]


@pytest.mark.triggers("PF409")
def test_a_part_urdfdom_cannot_read_is_dropped_with_what_follows(urdfdom):
    package, report = urdfdom
    model = package / "urdf" / "dropped.urdf"
    assert [f for f in found(report, "PF409") if "dropped.urdf" in f[0]] == [
        ("urdf/dropped.urdf", line_of(model, '<origin xyz="0 0.1"/>'), "error"),
        ("urdf/dropped.urdf", line_of(model, '<inertia ixx="0.01" iyy'), "error"),
        ("urdf/dropped.urdf", line_of(model, "<capsule"), "error"),
    ]
    text = " | ".join(messages(report, "PF409"))
    assert (
        "link 'arm': <visual>: <origin xyz=\"0 0.1\">: 2 value(s), not 3: urdfdom drops it and every collision"
        in text
    )
    assert "link 'wrist': <inertial>: <inertia>: no ixy=: urdfdom drops its visuals and collisions" in text
    assert "<capsule> is no shape urdfdom knows" in text
    # one cause, one finding: the dropped collision is no collision-without-inertial, the unread
    # inertia no inertia-invalid
    assert not [
        d for d in report["diagnostics"] if d["code"] in ("PF602", "PF603") and "dropped" in d["path"]
    ]


def test_a_macro_defect_used_twice_is_one_finding_at_its_written_line(urdfdom):
    package, report = urdfdom
    model = package / "urdf" / "macro_origin.urdf.xacro"
    assert [f for f in found(report, "PF409") if "macro_origin" in f[0]] == [
        ("urdf/macro_origin.urdf.xacro", line_of(model, '<origin xyz="0 0.02"'), "error")
    ]
    assert any(
        m.startswith("links 'left_finger', 'right_finger': <visual>") for m in messages(report, "PF409")
    )


def test_a_texture_in_an_included_file_is_reported_at_its_line(urdfdom):
    package, report = urdfdom
    included = package / "urdf" / "textured.xacro"
    assert ("urdf/textured.xacro", line_of(included, "<texture"), "error") in found(report, "PF402")


@pytest.mark.triggers("PF410")
def test_a_colour_urdfdom_reads_otherwise_is_a_warning(urdfdom):
    package, report = urdfdom
    model = package / "urdf" / "dropped.urdf"
    assert [f for f in found(report, "PF410") if "dropped.urdf" in f[0]] == [
        ("urdf/dropped.urdf", line_of(model, 'rgba="0 0 255 1"'), "warning"),
        ("urdf/dropped.urdf", line_of(model, 'rgba="0 1 0 1"'), "warning"),
        ("urdf/dropped.urdf", line_of(model, 'rgba="1 1 0"'), "warning"),
    ]
    text = " | ".join(messages(report, "PF410"))
    assert "'255' is not a number from 0 to 1: urdfdom drops the material" in text
    assert (
        "material 'red' is given another colour than where it is first defined (first at dropped.urdf:"
        in text
    )
    assert '<color rgba="1 1 0"> has 3 value(s), not 4: urdfdom reads it as black' in text


@pytest.mark.triggers("PF411")
def test_a_mimic_of_no_joint_is_an_error_at_the_mimic(urdfdom):
    package, report = urdfdom
    model = package / "urdf" / "dropped.urdf"
    assert found(report, "PF411") == [("urdf/dropped.urdf", line_of(model, "<mimic"), "error")]
    (message,) = messages(report, "PF411")
    assert "mimics 'finger_joint', which is no joint of the model" in message


def test_the_nearest_models_urdfdom_reads_whole_are_clean(urdfdom):
    _, report = urdfdom
    assert [d for d in report["diagnostics"] if d["path"] == "urdf/clean.urdf"] == []


# --- 8. released nowhere -----------------------------------------------------------------------------


def declare(package: Path, *lines: str) -> None:
    edit(
        package / "package.xml",
        "  <exec_depend>xacro</exec_depend>\n",
        "  <exec_depend>xacro</exec_depend>\n" + "".join(f"  {line}\n" for line in lines),
    )


@pytest.mark.triggers("PF108")
def test_a_dependency_released_nowhere_and_no_rosdep_key_is_a_warning_without_a_distro(package):
    declare(package, "<exec_depend>rob_private_driver</exec_depend>")
    manifest = package / "package.xml"
    _, report = verify_report(package, "--no-cache")
    assert at_least_warnings(report) == [("PF108", "package.xml", line_of(manifest, "rob_private_driver"))]
    assert found(report, "PF108")[0][2] == "warning"
    (message,) = messages(report, "PF108")
    assert "released in no active ROS 2 distro and is no rosdep key" in message
    _, report = verify_report(package, "--no-cache", "--distro", "jazzy")
    assert found(report, "PF108") == [("package.xml", line_of(manifest, "rob_private_driver"), "error")]


def test_a_rosdep_key_a_repos_entry_and_a_doc_depend_are_not_released_nowhere(package):
    declare(
        package,
        "<depend>eigen</depend>",
        "<exec_depend>python3-numpy</exec_depend>",
        "<exec_depend>rob_private_driver</exec_depend>",
        "<doc_depend>rob_doc_theme</doc_depend>",
    )
    # the driver's repository, named by its URL only
    (package.parent / "drivers.repos").write_text(
        "repositories:\n  drivers/private:\n    type: git\n"
        "    url: https://example.com/rob/rob_private_driver.git\n    version: main\n"
    )
    _, report = verify_report(package, "--no-cache", "--distro", "jazzy")
    assert found(report, "PF108") == []


def test_a_dependency_in_an_ignored_folder_says_which_marker_hides_it(package):
    declare(package, "<exec_depend>rob_perception</exec_depend>")
    inner = package.parent / "rob_perception"
    inner.mkdir()
    (inner / "package.xml").write_text(
        (package / "package.xml")
        .read_text()
        .replace("<name>rob_description</name>", "<name>rob_perception</name>")
    )
    (inner / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.8)\nproject(rob_perception NONE)\n"
    )
    (inner / "COLCON_IGNORE").touch()
    _, report = verify_report(package, "--no-cache", "--distro", "jazzy")
    manifest = package / "package.xml"
    assert found(report, "PF108") == [("package.xml", line_of(manifest, "rob_perception"), "error")]
    (hint,) = [d["hint"] for d in report["diagnostics"] if d["code"] == "PF108"]
    assert hint.startswith("rob_perception is in the workspace, but rob_perception/COLCON_IGNORE hides it")
