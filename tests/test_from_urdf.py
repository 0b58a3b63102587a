"""`pkgforge new NAME --from-urdf FILE` for a xacro export: includes through $(find OTHER), meshes and
textures through package://OTHER (OTHER found above the model or in AMENT_PREFIX_PATH), Collada
images beside the mesh, URIs as package:// or file://$(find NAME). (The plain URDF, UR5 and bad
input are in test_migrate.py, with the build they share.)"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from conftest import MAINTAINER, line_of, lines_of, run_pkgforge
from migrate_fixtures import bare_urdf

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
    assert "0 errors, 0 warnings, 0 infos in 1 package" in result.stdout
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


# --- what a model may make pkgforge copy (issue 35, case 18) ------------------------------------

KEY = b"-----BEGIN OPENSSH PRIVATE KEY-----\nnot a real key, a stand-in\n-----END OPENSSH PRIVATE KEY-----\n"
COPIED = ".stl .dae .obj .ply .glb .gltf .3ds .fbx .mesh .mtl .png .jpg .jpeg .tga .bmp .tif .tiff .dds .ktx"
NAMED_BESIDE = ".mtl .png .jpg .jpeg .tga .bmp .tif .tiff .dds .ktx"
NOT_A_MESH = f"not a mesh or texture file (pkgforge copies only {COPIED} files)"


def home_with_an_export(tmp_path: Path) -> tuple[Path, Path]:
    """A fake HOME (never the real one) with a private key, files outside the export, and the
    exporter's bare folder (urdf/arm.urdf naming ../meshes/*.STL, no package.xml): (home, model)."""
    home = tmp_path / "home"
    (home / ".ssh").mkdir(parents=True)
    key = home / ".ssh/id_rsa"
    key.write_bytes(KEY)
    key.chmod(0o600)
    (home / "elsewhere").mkdir()
    (home / "elsewhere/part.stl").write_bytes(binary_stl(box_triangles((0.1, 0.1, 0.1))))
    (home / "elsewhere/secret.png").write_bytes(PNG)
    (home / "elsewhere/parts.xacro").write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>\n')
    return home, bare_urdf(home / "export")


def name_link2(model: Path, uri: str) -> None:
    """link2's visual and collision name `uri` instead of ../meshes/link2.STL."""
    model.write_text(model.read_text().replace('"../meshes/link2.STL"', f'"{uri}"'))


def hostile(case: str, home: Path, model: Path) -> tuple[Path, str, str, str, dict[str, str]]:
    """Make the export hostile in one way: (the file reported, at the first line naming the uri;
    kind, uri as written, why it is refused, environment added)."""
    export, key, part = home / "export", home / ".ssh/id_rsa", home / "elsewhere/part.stl"
    meshes = export / "meshes"
    if case == "file-uri-to-a-key":
        name_link2(model, f"file://{key}")
        return model, "mesh", f"file://{key}", NOT_A_MESH, {}
    if case == "relative-escape":
        name_link2(model, "../../elsewhere/part.stl")
        return model, "mesh", "../../elsewhere/part.stl", f"{part} is outside {export}", {}
    if case == "absolute-outside":
        name_link2(model, str(part))
        return model, "mesh", str(part), f"{part} is outside {export}", {}
    if case == "link-to-a-key":  # the URI is the exporter's; the file is a link
        (meshes / "link2.STL").unlink()
        (meshes / "link2.STL").symlink_to(key)
        why = f"it leads to {key} (a symbolic link), {NOT_A_MESH}"
        return model, "mesh", "../meshes/link2.STL", why, {}
    if case == "link-out-of-the-tree":
        (meshes / "link2.STL").unlink()
        (meshes / "link2.STL").symlink_to(part)
        why = f"it leads to {part} (a symbolic link), outside {export}"
        return model, "mesh", "../meshes/link2.STL", why, {}
    if case == "fifo":
        (meshes / "link2.STL").unlink()
        os.mkfifo(meshes / "link2.STL")
        why = f"{meshes / 'link2.STL'} is not a regular file (a FIFO)"
        return model, "mesh", "../meshes/link2.STL", why, {}
    if case == "too-big":  # sparse: no disk space used
        os.truncate(meshes / "link2.STL", (256 << 20) + (1 << 20))
        why = f"{meshes / 'link2.STL'} is 257 MiB, over the 256 MiB pkgforge copies: copy it by hand"
        return model, "mesh", "../meshes/link2.STL", why, {}
    if case == "package-uri-escape":
        share = home / "prefix/share/parts"
        share.mkdir(parents=True)
        (share / "package.xml").write_text('<package format="3"><name>parts</name></package>\n')
        uri = "package://parts/../../../elsewhere/part.stl"
        name_link2(model, uri)
        return (
            model,
            "mesh",
            uri,
            f"{part} is outside {export} and {share}",
            {"AMENT_PREFIX_PATH": str(home / "prefix")},
        )
    if case == "collada-texture-outside":
        secret = home / "elsewhere/secret.png"
        (meshes / "skin.dae").write_text(COLLADA.replace("../../textures/skin.png", str(secret)))
        name_link2(model, "../meshes/skin.dae")
        return meshes / "skin.dae", "texture", str(secret), f"{secret} is outside {export}", {}
    if case == "obj-material-library-is-a-key":
        (meshes / "part.obj").write_text("mtllib ../../.ssh/id_rsa\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        name_link2(model, "../meshes/part.obj")
        why = f"not a mesh or texture file (pkgforge copies only {NAMED_BESIDE} files)"
        return meshes / "part.obj", "material library", "../../.ssh/id_rsa", why, {}
    assert case == "include-outside"
    parts = home / "elsewhere/parts.xacro"
    model.write_text(
        model.read_text().replace(
            '<robot name="arm">',
            f'<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n  <xacro:include filename="{parts}"/>',
        )
    )
    return model, "include", str(parts), f"{parts} is outside {export}", {}


HOSTILE_IMPORTS = (
    "file-uri-to-a-key",
    "relative-escape",
    "absolute-outside",
    "link-to-a-key",
    "link-out-of-the-tree",
    "fifo",
    "too-big",
    "package-uri-escape",
    "collada-texture-outside",
    "obj-material-library-is-a-key",
    "include-outside",
)


@pytest.mark.parametrize("case", HOSTILE_IMPORTS)
def test_a_model_naming_a_file_it_may_not_copy_writes_nothing(tmp_path, case):
    """The bad-input classes of the import (the campaign in test_campaign.py covers verify only):
    each refused file named at its file:line with why, exit 2, nothing written, the key nowhere."""
    home, model = home_with_an_export(tmp_path)
    where, kind, uri, why, env = hostile(case, home, model)
    result = run_pkgforge(
        "new",
        "arm_description",
        *MAINTAINER,
        "--from-urdf",
        model,
        "--destination",
        tmp_path / "out",
        cwd=tmp_path,
        env={**os.environ, **env},
        timeout=120,  # a FIFO read would block for ever
    )
    assert result.returncode == 2, result.stdout + result.stderr
    lines = result.stderr.splitlines()
    first, *others = lines_of(where, uri)
    also = f" (also line {', '.join(map(str, others))})" if others else ""  # one line per file named
    assert lines[0] == f"pkgforge: error: {where}:{first}: {kind} '{uri}' not copied: {why}{also}"
    assert lines[-1].endswith(
        "file(s) the model names cannot be imported: nothing written; pkgforge copies only mesh and "
        "texture files, from the model's package tree and the packages the model names: copy them "
        "there, or pass --force to write the package without them"
    )
    assert "Traceback" not in result.stderr and KEY.decode() not in result.stdout + result.stderr
    assert not (tmp_path / "out").exists()


def test_a_key_named_by_the_model_is_left_out_with_force(tmp_path):
    """--force writes the package without the refused file (as without a missing mesh), says so at
    its line, and the key is in no file of the package."""
    home, model = home_with_an_export(tmp_path)
    key = home / ".ssh/id_rsa"
    name_link2(model, f"file://{key}")
    result = run_pkgforge(
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
    package = tmp_path / "out/arm_description"
    assert package.is_dir(), result.stdout + result.stderr
    # (a message is one line of at most 300 characters: with pytest's long paths, its middle is left out)
    where = f"home/export/urdf/arm.urdf:{line_of(model, str(key))}: PF801 [warning] "
    [line] = [line for line in result.stdout.splitlines() if line.startswith(where)]
    assert line.startswith(f"{where}mesh 'file://{key}' not copied (")
    assert line.endswith(
        "the package was written without it (--force) (full text: --format json) (migrate-dropped)"
    )
    assert all(KEY not in p.read_bytes() for p in package.rglob("*") if p.is_file())
    assert sorted(p.name for p in (package / "meshes").iterdir()) == ["base_link.STL", "link1.STL"]


def current_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def test_copies_never_get_a_wider_mode(tmp_path):
    """A copy keeps its source's permission bits, narrowed by the umask (a 600 mesh stays 600,
    never 644); no execute bits on a mesh."""
    model = bare_urdf(tmp_path / "export")
    meshes = tmp_path / "export/meshes"
    (meshes / "base_link.STL").chmod(0o600)
    (meshes / "link1.STL").chmod(0o755)
    (meshes / "link2.STL").chmod(0o664)
    model.chmod(0o640)
    result = run_pkgforge(
        "new", "arm_description", *MAINTAINER, "--from-urdf", model, "--destination", "out", cwd=tmp_path
    )
    assert result.returncode == 0, result.stdout + result.stderr
    package = tmp_path / "out/arm_description"
    mask = current_umask()

    def mode(relative: str) -> int:
        return (package / relative).stat().st_mode & 0o777

    assert mode("meshes/base_link.STL") == 0o600
    assert mode("meshes/link1.STL") == 0o644 & ~mask
    assert mode("meshes/link2.STL") == 0o664 & ~mask
    assert mode("urdf/arm.urdf") == 0o640 & ~mask
    assert mode("package.xml") == 0o666 & ~mask


def test_meshes_inside_the_tree_and_from_a_symlink_installed_package_are_copied(tmp_path):
    """The nearest clean cases: a relative mesh inside the export (.STL in capitals), a link to a
    file inside it, a Collada texture inside it, and package://parts from an install tree whose
    files link back to parts' source folder (colcon --symlink-install)."""
    model = bare_urdf(tmp_path / "export")
    export = tmp_path / "export"
    (export / "meshes/shared").mkdir()
    (export / "meshes/link1.STL").rename(export / "meshes/shared/link1.STL")
    (export / "meshes/link1.STL").symlink_to("shared/link1.STL")
    (export / "textures").mkdir()
    (export / "textures/skin.png").write_bytes(PNG)
    (export / "meshes/base.dae").write_text(
        COLLADA.replace("../../textures/skin.png", "../textures/skin.png")
    )
    model.write_text(model.read_text().replace('"../meshes/base_link.STL"', '"../meshes/base.dae"'))
    source = tmp_path / "ws/src/parts"
    (source / "meshes").mkdir(parents=True)
    (source / "package.xml").write_text('<package format="3"><name>parts</name></package>\n')
    (source / "meshes/gripper.stl").write_bytes(binary_stl(box_triangles((0.05, 0.05, 0.05))))
    share = tmp_path / "ws/install/share/parts"
    (share / "meshes").mkdir(parents=True)
    (share / "package.xml").symlink_to(source / "package.xml")
    (share / "meshes/gripper.stl").symlink_to(source / "meshes/gripper.stl")
    name_link2(model, "package://parts/meshes/gripper.stl")
    result = run_pkgforge(
        "new",
        "arm_description",
        *MAINTAINER,
        "--from-urdf",
        model,
        "--destination",
        "out",
        cwd=tmp_path,
        env={**os.environ, "AMENT_PREFIX_PATH": str(tmp_path / "ws/install")},
    )
    assert result.returncode == 0, result.stdout + result.stderr
    package = tmp_path / "out/arm_description"
    copied = sorted(p.relative_to(package / "meshes").as_posix() for p in (package / "meshes").rglob("*.*"))
    assert copied == [
        "export/meshes/base.dae",
        "export/meshes/shared/link1.STL",
        "export/textures/skin.png",
        "ws/src/parts/meshes/gripper.stl",
    ]
    text = (package / "urdf/arm.urdf").read_text()
    assert 'filename="package://arm_description/meshes/ws/src/parts/meshes/gripper.stl"' in text
    assert 'filename="package://arm_description/meshes/export/meshes/shared/link1.STL"' in text
