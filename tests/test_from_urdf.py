"""`pkgforge new NAME --from-urdf FILE` for a xacro export: includes through $(find OTHER), meshes and
textures through package://OTHER (OTHER found above the model or in AMENT_PREFIX_PATH), Collada
images beside the mesh, URIs as package:// or file://$(find NAME). (The plain URDF, UR5 and bad
input are in test_migrate.py, with the build they share.)"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from conftest import MAINTAINER, line_of, run_pkgforge

from pkgforge.scaffold.stl import binary_stl, box_triangles

MODEL = """<?xml version="1.0"?>
<robot name="exported_robot" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find exported_robot)/urdf/parts.xacro"/>
  <link name="base_link">
    <visual>
      <geometry><mesh filename="package://exported_robot/meshes/visual/base.dae"/></geometry>
      <material name="wood"><texture filename="package://exported_robot/textures/wood.png"/></material>
    </visual>
  </link>
  <xacro:arm parent="base_link"/>
</robot>
"""
PARTS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm" params="parent">
    <link name="arm_link">
      <visual><geometry><mesh filename="package://exported_robot/meshes/visual/Arm.STL"/></geometry></visual>
    </link>
    <joint name="arm_joint" type="fixed"><parent link="${parent}"/><child link="arm_link"/></joint>
  </xacro:macro>
</robot>
"""
COLLADA = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_images><image id="skin"><init_from>../../textures/skin.png</init_from></image></library_images>
  <library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
  <technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/>
  <param name="Z" type="float"/></accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/>
  </vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""
PNG = b"\x89PNG\r\n\x1a\n" + bytes(16)


def exported(folder: Path, *, manifest: bool = True) -> Path:
    package = folder / "exported_robot"
    for sub in ("urdf", "meshes/visual", "textures"):
        (package / sub).mkdir(parents=True)
    if manifest:
        (package / "package.xml").write_text('<package format="2"><name>exported_robot</name></package>\n')
    (package / "urdf/robot.urdf.xacro").write_text(MODEL)
    (package / "urdf/parts.xacro").write_text(PARTS)
    (package / "meshes/visual/base.dae").write_text(COLLADA)
    (package / "meshes/visual/Arm.STL").write_bytes(binary_stl(box_triangles((0.1, 0.1, 0.1))))
    (package / "textures/wood.png").write_bytes(PNG)
    (package / "textures/skin.png").write_bytes(PNG)
    return package


@pytest.mark.parametrize(
    "style, uri", [("package", "package://my_robot/meshes/"), ("find", "file://$(find my_robot)/meshes/")]
)
def test_xacro_export_with_includes_and_textures(tmp_path, style, uri):
    source = exported(tmp_path)
    (tmp_path / "ws/src").mkdir(parents=True)
    result = run_pkgforge(
        "new",
        "my_robot",
        *MAINTAINER,
        "--from-urdf",
        source / "urdf/robot.urdf.xacro",
        "--mesh-uri",
        style,
        cwd=tmp_path / "ws",
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 errors, 0 warnings, 0 infos in 1 packages" in result.stdout
    package = tmp_path / "ws/src/my_robot"
    files = sorted(p.relative_to(package).as_posix() for p in package.rglob("*") if p.is_file())
    # sub-folders below the folder they share (the exporter's package) kept, names and case kept
    assert files == [
        "CMakeLists.txt",
        "launch/display.launch.py",
        "meshes/meshes/visual/Arm.STL",
        "meshes/meshes/visual/base.dae",
        "meshes/textures/skin.png",
        "meshes/textures/wood.png",
        "package.xml",
        "rviz/display.rviz",
        "urdf/parts.xacro",
        "urdf/robot.urdf.xacro",
    ]
    model = (package / "urdf/robot.urdf.xacro").read_text()
    assert '<xacro:include filename="$(find my_robot)/urdf/parts.xacro"/>' in model
    assert (
        f'filename="{uri}meshes/visual/base.dae"' in model and f'filename="{uri}textures/wood.png"' in model
    )
    assert f'filename="{uri}meshes/visual/Arm.STL"' in (package / "urdf/parts.xacro").read_text()
    assert "exported_robot" not in model.replace('robot name="exported_robot"', "")
    assert "urdf/robot.urdf.xacro" in (package / "launch/display.launch.py").read_text()
    assert "Fixed Frame: base_link" in (package / "rviz/display.rviz").read_text()


def test_package_found_in_ament_prefix_path(tmp_path):
    """The model outside its package (no package.xml above it): package:// resolves in AMENT_PREFIX_PATH."""
    source = exported(tmp_path / "prefix" / "share")
    model = tmp_path / "robot.urdf.xacro"
    model.write_text((source / "urdf/robot.urdf.xacro").read_text())
    (tmp_path / "out").mkdir()
    env = dict(os.environ, AMENT_PREFIX_PATH=str(tmp_path / "prefix"))
    result = run_pkgforge(
        "new", "my_robot", *MAINTAINER, "--from-urdf", model, "--destination", "out", cwd=tmp_path, env=env
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert (tmp_path / "out/my_robot/meshes/meshes/visual/Arm.STL").is_file()
    without = run_pkgforge(
        "new",
        "other_robot",
        *MAINTAINER,
        "--from-urdf",
        model,
        "--destination",
        "out",
        cwd=tmp_path,
        env={k: v for k, v in os.environ.items() if k != "AMENT_PREFIX_PATH"},
    )
    assert without.returncode == 2
    assert without.stderr.splitlines()[0] == (
        f"pkgforge: error: {model}:{line_of(model, 'xacro:include')}: include "
        "'$(find exported_robot)/urdf/parts.xacro' not found: package 'exported_robot' is found neither above "
        "robot.urdf.xacro nor in AMENT_PREFIX_PATH"
    )
    assert not (tmp_path / "out/other_robot").exists()


def test_not_a_urdf(tmp_path):
    model = tmp_path / "robot.urdf"
    model.write_text("<?xml version='1.0'?>\n<sdf version='1.6'>\n</sdf>\n")
    result = run_pkgforge(
        "new", "my_robot", *MAINTAINER, "--from-urdf", model, "--destination", "out", cwd=tmp_path
    )
    assert result.returncode == 2
    assert result.stderr.startswith(f"pkgforge: error: {model}:2: the root element is <sdf>, not <robot>")
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'>\n  <link name='a'>\n</robot>\n")
    result = run_pkgforge(
        "new", "my_robot", *MAINTAINER, "--from-urdf", broken, "--destination", "out", cwd=tmp_path
    )
    assert result.returncode == 2 and result.stderr.startswith(
        f"pkgforge: error: {broken}:3: not well-formed XML"
    )
    assert not (tmp_path / "out").exists()
