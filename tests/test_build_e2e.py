"""`pkgforge build` end to end: real colcon, real ament_cmake, real xacro, real install trees."""

from __future__ import annotations

import os

import pytest
from conftest import VARIANTS, copy_fixture, run_pkgforge, xacro_command
from lxml import etree

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_variant_installs_everything(variants_workspace, name):
    install = variants_workspace / "install"
    share = install / "share" / name
    launch_format = {
        "v_xml": "xml",
        "v_yaml": "yaml",
        "v_humble_xml": "xml",
        "v_humble_yaml": "yaml",
        "v_python_xml": "xml",
    }.get(name, "py")
    for relative in (
        "package.xml",
        f"launch/display.launch.{launch_format}",
        f"urdf/{name}.urdf.xacro",
        "urdf/macros.xacro",
        "meshes/arm.stl",
        "rviz/display.rviz",
    ):
        assert (share / relative).is_file(), relative
    assert (install / "share" / "ament_index" / "resource_index" / "packages" / name).is_file()


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_installed_xacro_expands_and_meshes_resolve(variants_workspace, name):
    install = variants_workspace / "install"
    result = xacro_command(install / "share" / name / "urdf" / f"{name}.urdf.xacro", install)
    assert result.returncode == 0, result.stderr
    robot = etree.fromstring(result.stdout.encode())
    assert [link.get("name") for link in robot.findall("link")] == ["base_link", "arm_link"]
    assert [joint.get("type") for joint in robot.findall("joint")] == ["revolute"]
    uris = [mesh.get("filename") for mesh in robot.iter("mesh")]
    assert uris == [f"package://{name}/meshes/arm.stl"]
    for uri in uris:
        package, _, relative = uri[len("package://") :].partition("/")
        assert (install / "share" / package / relative).is_file()


def test_seed000_shape_builds_without_ros(tmp_path):
    """ros2 pkg create's BUILD_TESTING / ament_lint_auto block and find_package(urdf)."""
    copy_fixture("seed000/rob_description", tmp_path)
    result = run_pkgforge("build", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "stubbed for find_package(): urdf" in result.stderr
    assert (
        tmp_path / "install" / "share" / "robot_description" / "urdf" / "robot_simple_description.urdf.xacro"
    ).is_file()
    # seed case 1: rviz/ is not in the install rule, so it is not installed
    assert not (tmp_path / "install" / "share" / "robot_description" / "rviz").exists()


def test_a_dependency_under_a_build_set_up_condition_is_stubbed(tmp_path):
    """<depend condition="$ROBOT_BUILD_TYPE == simulation">std_msgs</depend> with the variable
    unset: colcon leaves it out, the CMakeLists.txt still finds it (panther_gazebo's shape)."""
    copy_fixture("realworld/build_type_description", tmp_path)
    env = {k: v for k, v in os.environ.items() if k != "ROBOT_BUILD_TYPE"}
    result = run_pkgforge("build", cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "stubbed for find_package(): std_msgs" in result.stderr


def test_seed001_shape_fails_with_cmakes_message(tmp_path):
    """An install rule naming worlds/ and models/ that do not exist."""
    copy_fixture("seed001/small_turtle", tmp_path)
    result = run_pkgforge("build", cwd=tmp_path)
    output = result.stdout + result.stderr
    assert result.returncode == 1, output
    assert "file INSTALL cannot find" in output
    assert "src/small_turtle/worlds" in output
    assert "pkgforge: error: build failed: small_turtle" in result.stderr
    assert "Traceback" not in output


def test_build_of_a_folder_without_packages_exits_2(tmp_path):
    (tmp_path / "src").mkdir()
    result = run_pkgforge("build", cwd=tmp_path)
    assert result.returncode == 2
    assert "no package found" in result.stderr


def test_build_one_package_path_inside_a_workspace(tmp_path):
    run = run_pkgforge(
        "new", "only_me", "--maintainer-email", "t@example.com", "--destination", "src", cwd=tmp_path
    )
    assert run.returncode == 0, run.stderr
    copy_fixture("seed001/small_turtle", tmp_path)
    result = run_pkgforge("build", "src/only_me", cwd=tmp_path)
    # the broken neighbour is not built, so the build passes
    assert result.returncode == 0, result.stdout + result.stderr
    assert (tmp_path / "install" / "share" / "only_me" / "package.xml").is_file()
    assert not (tmp_path / "install" / "share" / "small_turtle").exists()
    assert "built 1 package into install/" in result.stdout
