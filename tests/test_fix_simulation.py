"""`pkgforge fix` for the simulation findings (issue 31): a home-folder SDF <uri> (PF421), a models
folder Gazebo is not told of (PF422), ros2_control_node's ignored robot_description parameter
(PF709). Each: the failing fixture, the fix, the exact files after it, verify clean of the code,
a second run that changes nothing, and the file a fixer does not expect left as it was."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest
from conftest import FIXTURES, edit, line_of, run_pkgforge, verify_report
from test_fix import fix, snapshot, tree_diff
from test_simulation import simulation_package

WORLD = "src/world_sim/worlds/yard.sdf"
HOOK_CALL = 'ament_environment_hooks("${CMAKE_CURRENT_SOURCE_DIR}/hooks/gz_resource_path.dsv.in")'


def home_world(tmp_path: Path, distro: str | list[str] = "jazzy") -> Path:
    """tests/fixtures/worlds' package with its export gone and its world's include and mesh
    written as paths into its author's home folder."""
    package = tmp_path / "src" / "world_sim"
    shutil.copytree(FIXTURES / "worlds" / "world_sim", package)
    edit(package / "package.xml", '    <gazebo_ros gazebo_model_path="${prefix}/models"/>\n', "")
    world = package / "worlds" / "yard.sdf"
    edit(world, "<uri>model://crate</uri>", "<uri>file:///home/ada/ws/src/world_sim/models/crate</uri>")
    edit(
        world,
        "package://world_sim/models/crate/meshes/crate.stl",
        "/home/ada/ws/src/world_sim/models/crate/meshes/crate.stl",
    )
    (package / "pkgforge.toml").write_text(f"[verify]\ndistro = {json.dumps(distro)}\n")
    return package


def codes(root: Path) -> list[tuple[str, str, int]]:
    return [(d["code"], d["path"], d["line"]) for d in verify_report(root, "--no-cache")[1]["diagnostics"]]


@pytest.mark.parametrize(
    ("distro", "variables"),
    [
        ("jazzy", ["GZ_SIM_RESOURCE_PATH"]),
        ("humble", ["IGN_GAZEBO_RESOURCE_PATH"]),
        (["humble", "jazzy"], ["GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH"]),
    ],
)
def test_home_uris_become_model_uris_and_a_hook_puts_the_models_on_the_resource_path(
    tmp_path, distro, variables
):
    package = home_world(tmp_path, distro)
    world = package / "worlds" / "yard.sdf"
    include, mesh = line_of(world, "models/crate</uri>"), line_of(world, "crate.stl")
    assert codes(tmp_path) == [
        ("PF422", "src/world_sim/models/crate/model.sdf", 7),
        ("PF421", WORLD, include),
        ("PF421", WORLD, mesh),
    ]
    before = snapshot(tmp_path)
    result = fix(tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    # PF422 first (model.sdf's model://crate); then, the models on the path, the model:// rewrites are safe
    assert [line.split(": ")[1] for line in result.stdout.splitlines() if line.startswith("fixed src/")] == [
        "PF422 gazebo-resource-path-unset",
        "PF421 sdf-uri-unresolved",
        "PF421 sdf-uri-unresolved",
    ]
    hook = "".join(f"+prepend-non-duplicate;{v};share/@PROJECT_NAME@/models\n" for v in variables)
    assert tree_diff(before, snapshot(tmp_path)) == (
        "diff src/world_sim/CMakeLists.txt\n"
        "--- a/src/world_sim/CMakeLists.txt\n+++ b/src/world_sim/CMakeLists.txt\n"
        "@@ -5,4 +5,7 @@\n \n install(DIRECTORY worlds models DESTINATION share/${PROJECT_NAME})\n \n"
        "+# Gazebo finds model://NAME of share/<package>/models on its resource path only\n"
        f"+{HOOK_CALL}\n+\n ament_package()\n"
        "diff src/world_sim/hooks/gz_resource_path.dsv.in\n"
        "--- a/src/world_sim/hooks/gz_resource_path.dsv.in\n+++ b/src/world_sim/hooks/gz_resource_path.dsv.in\n"
        f"@@ -0,0 +1{'' if len(variables) == 1 else ',2'} @@\n{hook}"
        f"diff {WORLD}\n--- a/{WORLD}\n+++ b/{WORLD}\n"
        "@@ -2,14 +2,14 @@\n"
        ' <sdf version="1.9">\n   <world name="yard">\n     <include>\n'
        "-      <uri>file:///home/ada/ws/src/world_sim/models/crate</uri>\n"
        "+      <uri>model://crate</uri>\n"
        '       <pose relative_to="world">1 0 0 0 0 0</pose>\n     </include>\n'
        '     <model name="post">\n       <static>true</static>\n       <link name="post">\n'
        '         <visual name="post">\n'
        "-          <geometry><mesh><uri>/home/ada/ws/src/world_sim/models/crate/meshes/crate.stl</uri></mesh></geometry>\n"
        "+          <geometry><mesh><uri>model://crate/meshes/crate.stl</uri></mesh></geometry>\n"
        "         </visual>\n       </link>\n     </model>\n"
    )
    assert codes(tmp_path) == []
    after = snapshot(tmp_path)
    again = fix(tmp_path)
    assert again.returncode == 0 and "fixed" not in again.stdout
    assert snapshot(tmp_path) == after
    # nothing written outside the package: the workspace holds the package and nothing else
    assert sorted(p.name for p in tmp_path.iterdir()) == ["src"]


@pytest.mark.parametrize(
    ("depends", "variables"),
    [
        ("gazebo_ros", "GAZEBO_MODEL_PATH"),  # Classic (turtlebot3_manipulation_gazebo's humble)
        ("gazebo_ros</exec_depend>\n  <exec_depend>ros_gz_sim", "IGN_GAZEBO_RESOURCE_PATH;GAZEBO_MODEL_PATH"),
    ],
)
def test_the_hook_names_the_variable_of_the_gazebo_the_package_runs(tmp_path, depends, variables):
    package = home_world(tmp_path, "humble")
    edit(
        package / "package.xml",
        "  <export>",
        f"  <exec_depend>{depends}</exec_depend>\n\n  <export>",
    )
    fix(tmp_path, "--select", "PF422")
    assert (package / "hooks" / "gz_resource_path.dsv.in").read_text() == "".join(
        f"prepend-non-duplicate;{v};share/@PROJECT_NAME@/models\n" for v in variables.split(";")
    )


@pytest.mark.slow
def test_the_hook_builds_and_sets_the_variable(tmp_path):
    """A real colcon build of the fixed package: ament_cmake installs the hook and lists it in the
    package's local_setup.dsv, and the install's local_setup.sh sets GZ_SIM_RESOURCE_PATH."""
    home_world(tmp_path)
    assert fix(tmp_path).returncode == 0
    built = run_pkgforge("verify", "--build", "--format", "json", cwd=tmp_path)
    assert built.returncode == 0, built.stdout + built.stderr
    assert json.loads(built.stdout)["diagnostics"] == []
    install = tmp_path / "build" / "pkgforge-verify" / "install"
    share = install / "share" / "world_sim"
    assert (share / "environment" / "gz_resource_path.dsv").read_text() == (
        "prepend-non-duplicate;GZ_SIM_RESOURCE_PATH;share/world_sim/models\n"
    )
    assert (
        "source;share/world_sim/environment/gz_resource_path.dsv\n" in (share / "local_setup.dsv").read_text()
    )
    sourced = subprocess.run(
        ["sh", "-c", '. "$1/local_setup.sh" && printf %s "$GZ_SIM_RESOURCE_PATH"', "sh", str(install)],
        capture_output=True,
        text=True,
        check=True,
        env={"PATH": "/usr/bin:/bin"},
    )
    assert sourced.stdout == str(share / "models")


def test_diff_shows_the_new_hook_and_writes_nothing(tmp_path):
    home_world(tmp_path)
    before = snapshot(tmp_path)
    result = run_pkgforge("fix", "--diff", cwd=tmp_path)
    assert result.returncode in (0, 1), result.stderr
    assert snapshot(tmp_path) == before
    assert (
        "--- a/src/world_sim/hooks/gz_resource_path.dsv.in\n+++ b/src/world_sim/hooks/gz_resource_path.dsv.in\n"
        "@@ -0,0 +1 @@\n+prepend-non-duplicate;GZ_SIM_RESOURCE_PATH;share/@PROJECT_NAME@/models\n"
    ) in result.stdout
    assert "+      <uri>model://crate</uri>\n" in result.stdout


def test_a_mesh_outside_the_models_becomes_package_uri_only_with_unsafe_fixes(tmp_path):
    """package://world_sim/... is found by Gazebo only with install/share on its resource path
    (gz-common's FindFileURI drops the scheme): an unsafe fix."""
    package = home_world(tmp_path)
    (package / "meshes").mkdir()
    (package / "meshes" / "post.stl").write_bytes((package / "models/crate/meshes/crate.stl").read_bytes())
    edit(package / "CMakeLists.txt", "DIRECTORY worlds models", "DIRECTORY worlds models meshes")
    world = package / "worlds" / "yard.sdf"
    edit(world, "/home/ada/ws/src/world_sim/models/crate/meshes/crate.stl", "/home/ada/robot/meshes/post.stl")
    line = line_of(world, "post.stl")
    safe = fix(tmp_path)
    assert (
        "1 unsafe fix(es) not applied (--unsafe-fixes applies them): PF421 sdf-uri-unresolved ×1"
        in safe.stdout
    )
    assert "/home/ada/robot/meshes/post.stl" in world.read_text()
    unsafe = fix(tmp_path, "--unsafe-fixes")
    assert (
        f"fixed {WORLD}:{line}: PF421 sdf-uri-unresolved: <uri> /home/ada/robot/meshes/post.stl → "
        "package://world_sim/meshes/post.stl"
    ) in unsafe.stdout
    assert line_of(world, "<uri>package://world_sim/meshes/post.stl</uri>") == line
    assert codes(tmp_path) == []


def test_an_include_of_an_sdf_file_in_the_models_folder_keeps_the_file(tmp_path):
    """sdformat's <include> takes an SDF file too: model://crate/model.sdf, found as the folder is."""
    package = home_world(tmp_path)
    world = package / "worlds" / "yard.sdf"
    edit(world, "/models/crate</uri>", "/models/crate/model.sdf</uri>")
    line = line_of(world, "model.sdf</uri>")
    result = fix(tmp_path)
    assert (
        f"fixed {WORLD}:{line}: PF421 sdf-uri-unresolved: <uri> "
        "file:///home/ada/ws/src/world_sim/models/crate/model.sdf → model://crate/model.sdf"
    ) in result.stdout
    assert line_of(world, "<uri>model://crate/model.sdf</uri>") == line
    assert codes(tmp_path) == []


def test_uris_the_fixer_does_not_expect_are_left_as_they_are_with_a_reason(tmp_path):
    package = home_world(tmp_path)
    world = package / "worlds" / "yard.sdf"
    # no installed model at the path's end; a URI written with a character reference
    edit(world, "file:///home/ada/ws/src/world_sim/models/crate", "file:///home/ada/models/oak")
    edit(
        world,
        "/home/ada/ws/src/world_sim/models/crate/meshes/crate.stl",
        "/home/ada/ws/src/world_sim/models/crate/meshes/crate&#46;stl",
    )
    (package / "worlds" / "other.sdf").write_text(
        '<sdf version="1.9">\n  <model name="m"><include><uri>model://crate</uri></include></model>\n</sdf>\n'
    )
    before = snapshot(tmp_path)
    result = fix(tmp_path)
    assert (
        f"not fixed {WORLD}:{line_of(world, 'oak')}: PF421 sdf-uri-unresolved: no model folder or mesh"
        in (result.stdout)
    )
    assert (
        f"not fixed {WORLD}:{line_of(world, 'crate&#46;stl')}: PF421 sdf-uri-unresolved: the <uri> at yard.sdf:"
        in result.stdout
    )
    changed = tree_diff(before, snapshot(tmp_path))
    assert f"diff {WORLD}" not in changed  # only the hook and its CMake line (PF422 of other.sdf)
    assert "hooks/gz_resource_path.dsv.in" in changed


def test_a_hook_the_fixer_does_not_expect_is_left_with_a_reason(tmp_path):
    package = home_world(tmp_path)
    (package / "hooks").mkdir()
    (package / "hooks" / "gz_resource_path.dsv.in").write_text("prepend-non-duplicate;PATH;bin\n")
    edit(package / "CMakeLists.txt", "ament_package()", "if(TRUE)\n  ament_package()\nendif()")
    before = snapshot(tmp_path)
    result = fix(tmp_path, "--unsafe-fixes")
    assert (
        "not fixed src/world_sim/models/crate/model.sdf:7: PF422 gazebo-resource-path-unset: "
        "CMakeLists.txt calls no ament_package() outside a block to put the hook before"
    ) in result.stdout
    edit(package / "CMakeLists.txt", "if(TRUE)\n  ament_package()\nendif()", "ament_package()")
    before = snapshot(tmp_path)
    result = fix(tmp_path, "--unsafe-fixes")
    assert (
        "not fixed src/world_sim/models/crate/model.sdf:7: PF422 gazebo-resource-path-unset: "
        "gz_resource_path.dsv.in exists already: pkgforge does not overwrite it"
    ) in result.stdout
    changed = tree_diff(before, snapshot(tmp_path))
    assert "hooks/" not in changed and "CMakeLists.txt" not in changed


def test_an_ament_python_package_gets_no_hook_and_says_why(tmp_path):
    package = home_world(tmp_path)
    (package / "CMakeLists.txt").unlink()
    edit(package / "package.xml", "<buildtool_depend>ament_cmake</buildtool_depend>", "")
    edit(
        package / "package.xml",
        "<build_type>ament_cmake</build_type>",
        "<build_type>ament_python</build_type>",
    )
    (package / "resource").mkdir()
    (package / "resource" / "world_sim").write_text("")
    (package / "setup.cfg").write_text(
        "[develop]\nscript_dir=$base/lib/world_sim\n[install]\ninstall_scripts=$base/lib/world_sim\n"
    )
    (package / "setup.py").write_text(
        "from glob import glob\n\nfrom setuptools import setup\n\n"
        "setup(\n    name='world_sim',\n    version='0.1.0',\n    packages=[],\n    data_files=[\n"
        "        ('share/ament_index/resource_index/packages', ['resource/world_sim']),\n"
        "        ('share/world_sim', ['package.xml']),\n"
        "        ('share/world_sim/worlds', glob('worlds/*.sdf')),\n"
        "        ('share/world_sim/models/crate', glob('models/crate/model.*')),\n"
        "        ('share/world_sim/models/crate/meshes', glob('models/crate/meshes/*')),\n"
        "    ],\n)\n"
    )
    before = snapshot(tmp_path)
    result = fix(tmp_path, "--unsafe-fixes")
    assert (
        "not fixed src/world_sim/models/crate/model.sdf:7: PF422 gazebo-resource-path-unset: an ament_python "
        "package has no environment hook of its own"
    ) in result.stdout
    assert "hooks/" not in tree_diff(before, snapshot(tmp_path))


# --- PF709 ------------------------------------------------------------------------------------------


def test_the_ignored_description_parameter_is_dropped_in_python(tmp_path, template_package):
    package = simulation_package(tmp_path, template_package)
    (package / "pkgforge.toml").write_text('[verify]\ndistro = "jazzy"\n')
    launch = package / "launch" / "sim.launch.py"
    line = line_of(launch, 'executable="ros2_control_node"') - 2
    assert ("PF709", "src/rob_description/launch/sim.launch.py", line) in codes(tmp_path)
    text = launch.read_text()
    result = fix(tmp_path, "--select", "PF709")
    assert (
        f"fixed src/rob_description/launch/sim.launch.py:{line}: PF709 controller-description-delivery: "
        "removed robot_description (description) from ros2_control_node's parameters"
    ) in result.stdout
    assert launch.read_text() == text.replace(
        "parameters=[description, controllers],", "parameters=[controllers],"
    )
    assert "PF709" not in [c for c, _, _ in codes(tmp_path)]
    after = snapshot(tmp_path)
    assert "fixed" not in fix(tmp_path, "--select", "PF709").stdout and snapshot(tmp_path) == after


@pytest.mark.parametrize(
    ("written", "left"),
    [
        (
            "parameters=[{'robot_description': description, 'use_sim_time': True}, controllers],",
            "parameters=[{'use_sim_time': True}, controllers],",
        ),
        (
            "parameters=[\n{'robot_description': description},\ncontrollers,\n],",
            "parameters=[\ncontrollers,\n],",
        ),
        ("parameters=[controllers, {'robot_description': description}],", "parameters=[controllers],"),
    ],
)
def test_the_parameter_is_dropped_from_a_dict_literal(tmp_path, template_package, written, left):
    package = simulation_package(tmp_path, template_package)
    (package / "pkgforge.toml").write_text('[verify]\ndistro = "jazzy"\n')
    launch = package / "launch" / "sim.launch.py"
    edit(
        launch,
        'description = {"robot_description": Command(["xacro ", model])}',
        'description = Command(["xacro ", model])',
    )
    edit(launch, "parameters=[description]),", "parameters=[{'robot_description': description}]),")
    edit(launch, "parameters=[description, controllers],", written)
    fix(tmp_path, "--select", "PF709")
    assert left in launch.read_text() and "PF709" not in [c for c, _, _ in codes(tmp_path)]


XML_LAUNCH = """<launch>
  <node pkg="robot_state_publisher" exec="robot_state_publisher">
    <param name="robot_description" value="$(command 'xacro $(find-pkg-share rob_description)/urdf/sim.urdf.xacro')"/>
  </node>
  <node pkg="controller_manager" exec="ros2_control_node">
    <param name="robot_description" value="$(command 'xacro $(find-pkg-share rob_description)/urdf/sim.urdf.xacro')"/>
    <param from="$(find-pkg-share rob_description)/config/controllers.yaml"/>
  </node>
</launch>
"""

YAML_LAUNCH = """launch:
- node:
    pkg: controller_manager
    exec: ros2_control_node
    param:
    - name: robot_description
      value: "$(command 'xacro $(find-pkg-share rob_description)/urdf/sim.urdf.xacro')"
    - name: use_sim_time
      value: true
"""


def test_xml_and_yaml_are_edited_a_flow_list_and_humble_targets_are_not(tmp_path, template_package):
    package = simulation_package(tmp_path, template_package)
    (package / "launch" / "sim.launch.py").unlink()
    xml, yaml = package / "launch" / "control.launch.xml", package / "launch" / "control.launch.yaml"
    xml.write_text(XML_LAUNCH)
    yaml.write_text(YAML_LAUNCH)
    (package / "pkgforge.toml").write_text('[verify]\ndistro = "jazzy"\n')
    result = fix(tmp_path, "--select", "PF709")
    assert (
        "fixed src/rob_description/launch/control.launch.xml:5: PF709 controller-description-delivery: "
        'removed <param name="robot_description"> from ros2_control_node'
    ) in result.stdout
    lines = XML_LAUNCH.splitlines(keepends=True)
    assert xml.read_text() == "".join(lines[:5] + lines[6:])
    assert (
        "fixed src/rob_description/launch/control.launch.yaml:2: PF709 controller-description-delivery: "
        "removed the robot_description item from ros2_control_node's param"
    ) in result.stdout
    lines = YAML_LAUNCH.splitlines(keepends=True)
    assert yaml.read_text() == "".join(lines[:5] + lines[7:])
    assert "PF709" not in [c for c, _, _ in codes(tmp_path)]
    # the only item: the param key goes with it (an empty param is null, which launch refuses)
    yaml.write_text("".join(lines[:7]))
    fix(tmp_path, "--select", "PF709")
    assert yaml.read_text() == "".join(lines[:4])
    # a flow-style list is not what the fixer edits: left as it is, with the reason
    flow = YAML_LAUNCH.replace(
        "    param:\n    - name: robot_description\n", "    param: [{name: robot_description, "
    ).replace("\n    - name: use_sim_time\n      value: true\n", "}]\n")
    yaml.write_text(flow)
    result = fix(tmp_path, "--select", "PF709")
    assert (
        "not fixed src/rob_description/launch/control.launch.yaml:2: PF709 controller-description-delivery: "
        "the node's param is not a block list (- name: ...): drop the parameter by hand"
    ) in result.stdout
    assert yaml.read_text() == flow
    # humble and jazzy: humble reads the parameter, so dropping it is the user's decision
    xml.write_text(XML_LAUNCH)
    (package / "pkgforge.toml").write_text('[verify]\ndistro = ["humble", "jazzy"]\n')
    result = fix(tmp_path, "--select", "PF709", "--unsafe-fixes")
    assert "fixed" not in result.stdout
    assert xml.read_text() == XML_LAUNCH
    assert [c for c, p, _ in codes(tmp_path) if c == "PF709" and p.endswith(".xml")] == ["PF709"]
