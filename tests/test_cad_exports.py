"""Issue 29: `pkgforge migrate` and `new --from-urdf` on what CAD exporters write (tests/cad_exports.py):
a package named after the assembly, the exporter's package.xml, content after </robot>, URIs naming the
exporter's folder, xacro exports rewritten whole, models copied byte for byte, launch files that run
on the target distro (and load through both launch engines), one line per missing mesh. Each
migrated and imported package builds with `pkgforge build` and verifies with no error but the
model's own physics (PF6xx) and the defects the source had."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from cad_exports import TRANSMISSION, fusion_export, onshape_export, sw_export
from conftest import MAINTAINER, line_of, lines_of, run_pkgforge, verify_report
from migrate_fixtures import ros1_package
from ros_prefix import DISTROS, make_prefix


def _notes(out: str) -> list[str]:
    return [line for line in out.split("\nverify ", 1)[0].splitlines() if " PF8" in line]


def _errors(report: dict, *, but: tuple[str, ...] = ()) -> list[tuple]:
    """The report's errors and warnings, but the model's own physics (PF6xx) and `but` (paths)."""
    return [
        (d["code"], d["path"], d["message"])
        for d in report["diagnostics"]
        if d["severity"] != "info" and not d["code"].startswith("PF6") and not d["path"].endswith(but)
    ]


@pytest.fixture(scope="module")
def exports(tmp_path_factory):
    """One workspace: the exporters' packages migrated (py; xml with --gazebo for jazzy and humble)
    and their models imported with `new --from-urdf`; built once. The export with content after
    </robot> is migrated and imported in a workspace of its own (apart), whose errors are its own."""
    root = tmp_path_factory.mktemp("cad")
    sources = {
        "sw": sw_export(root / "ros1"),
        "fusion": fusion_export(root / "ros1"),
        "folder": sw_export(root / "ros1-folder", "arm_description", meshes_as="MyArm-URDF"),
    }
    trailing = sw_export(root / "ros1-trailing", "xr10-1500")
    model = trailing / "urdf/xr10-1500.urdf"
    model.write_bytes(model.read_bytes() + TRANSMISSION.replace("\n", "\r\n").encode() + b"\r\n")
    (trailing / "urdf/xr10-1500_trans.urdf").write_text('<robot name="x">\n  <link name="a">\n</robot>\n')
    sources["trailing"] = trailing
    onshape = onshape_export(root / "onshape" / "two_wheels")
    workspace = root / "ws"
    (workspace / "src").mkdir(parents=True)

    def migrate(source: Path, *options: str, destination: str = "src"):
        return run_pkgforge(
            "migrate", source, "--destination", destination, *MAINTAINER, *options, cwd=workspace
        )

    imports = root / "imports"
    (imports / "src").mkdir(parents=True)

    def new_from(model: Path):
        return run_pkgforge("new", *MAINTAINER, "--from-urdf", model, cwd=imports)

    outputs = {
        "sw": migrate(sources["sw"]),
        "fusion": migrate(sources["fusion"]),
        "folder": migrate(sources["folder"]),
        "trailing": migrate(sources["trailing"], destination=str(root / "apart/src")),
        "fusion-jazzy": migrate(
            sources["fusion"],
            "--gazebo",
            "--launch-format",
            "xml",
            "--distro",
            "jazzy",
            "--name",
            "arm_jazzy",
        ),
        "fusion-humble": migrate(
            sources["fusion"],
            "--gazebo",
            "--launch-format",
            "yaml",
            "--distro",
            "humble",
            "--name",
            "arm_humble",
        ),
        "sw-gazebo": migrate(sources["sw"], "--gazebo", "--name", "gripper_gazebo"),
        # NAME left out: the model's package's name, made valid (onshape: the export's folder)
        "import-sw": new_from(sources["sw"] / "urdf/GripperPrototype.urdf"),
        "import-fusion": new_from(sources["fusion"] / "urdf/Arm_2.xacro"),
        "import-onshape": new_from(onshape),
        "import-folder": new_from(sources["folder"] / "urdf/arm_description.urdf"),
        "import-trailing": run_pkgforge(
            "new", "xr10_imported", *MAINTAINER, "--from-urdf", model, cwd=root / "apart"
        ),
    }
    for name, result in outputs.items():
        assert result.returncode in (0, 1), (name, result.stdout, result.stderr)
        assert result.stderr == "", (name, result.stderr)  # catkin_pkg's warnings never leak
    for folder in (workspace, imports, root / "apart"):
        build = run_pkgforge("build", cwd=folder)
        assert build.returncode == 0, build.stdout + build.stderr
    return root, workspace, sources, outputs


@pytest.mark.parametrize(
    "folder, names",
    [
        (
            "ws",
            [
                "arm_2_description",
                "arm_description",
                "arm_humble",
                "arm_jazzy",
                "gripper_gazebo",
                "gripper_prototype",
            ],
        ),
        ("imports", ["arm_2_description", "arm_description", "gripper_prototype", "two_wheels"]),
    ],
)
def test_every_package_builds_and_verifies(exports, folder, names):
    """All of them built (the fixture) and verify with no error and no warning but the model's physics."""
    root, _, _, _ = exports
    status, report = verify_report(root / folder, "--no-cache")
    assert sorted(p["name"] for p in report["packages"]) == names
    # --from-urdf imports the model as it is but for its paths: fusion2urdf's Arm_2.gazebo keeps
    # ROS 1's gazebo_ros_control, which loads in no ROS 2 Gazebo (migrate leaves it out, or
    # converts it with --gazebo)
    classic = [
        ("PF701", "src/arm_2_description/urdf/Arm_2.gazebo", "plugin 'libgazebo_ros_control.so' does n")
    ]
    assert [(c, p, m[:40]) for c, p, m in _errors(report)] == (classic if folder == "imports" else [])
    assert status == (1 if folder == "imports" else 0)


@pytest.mark.triggers("PF805", "PF806")
def test_package_named_after_the_assembly_gets_a_valid_name(exports):
    """GripperPrototype → gripper_prototype (REP 144's suggestion), every reference to it rewritten
    and reported at its file and first line; the model otherwise byte for byte (CRLF kept)."""
    root, workspace, sources, outputs = exports
    source, out = sources["sw"], outputs["sw"].stdout
    manifest, model = source / "package.xml", source / "urdf/GripperPrototype.urdf"
    display = source / "launch/display.launch"

    def at(path: Path, line: int) -> str:
        return f"{os.path.relpath(path, workspace)}:{line}:"

    notes = _notes(out)
    expected = [
        f"{at(manifest, line_of(manifest, '<name>'))} PF805 [info] package name 'GripperPrototype' → "
        "'gripper_prototype' ('GripperPrototype' has upper-case letters, which REP 144 forbids); package://, "
        "$(find) and project() follow (migrate-generated)",
        f"{at(model, lines_of(model, 'package://')[0])} PF805 [info] 6 reference(s) to GripperPrototype "
        f"rewritten to package gripper_prototype (package://, $(find); line "
        f"{', '.join(map(str, lines_of(model, 'package://')))}) (migrate-generated)",
        f"{at(display, line_of(display, 'textfile='))} PF805 [info] 2 reference(s) to GripperPrototype rewritten "
        f"to package gripper_prototype (package://, $(find); line {line_of(display, 'textfile=')}, "
        f"{line_of(display, 'urdf.rviz')}) (migrate-generated)",
        f"{at(source / 'CMakeLists.txt', 1)} PF806 [info] CMakeLists.txt: ament_cmake, project(gripper_prototype), "
        "install(DIRECTORY config launch meshes rviz urdf DESTINATION share/${PROJECT_NAME}) (migrate-changed)",
    ]
    for line in expected:
        assert line in notes, (line, notes)
    package = workspace / "src/gripper_prototype"
    assert (package / "urdf/GripperPrototype.urdf").read_bytes() == model.read_bytes().replace(
        b"package://GripperPrototype/", b"package://gripper_prototype/"
    )
    assert b"\r\n" in (package / "urdf/GripperPrototype.urdf").read_bytes()
    assert "project(gripper_prototype NONE)" in (package / "CMakeLists.txt").read_text()
    assert "FindPackageShare('gripper_prototype')" in (package / "launch/display.launch.py").read_text()
    assert sorted(p.name for p in (package / "meshes").iterdir()) == [
        "Fing 1.STL",
        "Thumb.STL",
        "base_link.STL",
    ]


def test_an_rviz_config_follows_the_new_name(tmp_path):
    """An RViz config naming a mesh of the package (package://GripperPrototype/...) names it under the
    new name, reported at its line like every other file's rewrites."""
    source = sw_export(tmp_path / "ros1")
    (source / "rviz").mkdir()
    (source / "rviz/tool.rviz").write_text(
        "Panels:\n  - Class: rviz/Displays\nVisualization Manager:\n  Displays:\n    - Class: rviz/Marker\n"
        "      Name: Tool\n      Mesh Resource: package://GripperPrototype/meshes/Thumb.STL\n"
        "  Global Options:\n    Fixed Frame: base_link\n"
    )
    result = run_pkgforge("migrate", source, "--destination", tmp_path / "out", *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert (
        "ros1/GripperPrototype/rviz/tool.rviz:7: PF805 [info] 1 reference(s) to GripperPrototype rewritten to "
        "package gripper_prototype (package://, $(find); line 7) (migrate-generated)"
    ) in result.stdout
    written = (tmp_path / "out/gripper_prototype/rviz/tool.rviz").read_text()
    assert "Mesh Resource: package://gripper_prototype/meshes/Thumb.STL" in written
    assert "GripperPrototype" not in written


def test_the_exporters_package_xml_is_filled_in(exports):
    """<maintainer email="TODO@email.com" /> with no name: filled from --maintainer-name/-email,
    reported at its line; the <p>s of the description, the author and the license kept."""
    _, workspace, sources, outputs = exports
    manifest = sources["sw"] / "package.xml"
    assert (
        f"{os.path.relpath(manifest, workspace)}:{line_of(manifest, '<maintainer')}: PF806 [info] package.xml: "
        '<maintainer email="TODO@email.com"/> has no name: Test Maintainer <test@example.com> (name from '
        "--maintainer-name, e-mail from --maintainer-email) (migrate-changed)"
    ) in _notes(outputs["sw"].stdout)
    written = (workspace / "src/gripper_prototype/package.xml").read_text()
    assert '<maintainer email="test@example.com">Test Maintainer</maintainer>' in written
    assert "<description><p>URDF Description package for GripperPrototype</p>" in written
    assert "<author>TODO</author>" in written and "<license>BSD</license>" in written
    assert "<version>1.0.0</version>" in written


def test_the_maintainer_comes_from_git_config_without_options(tmp_path):
    """No --maintainer-name/-email: the exporter's nameless maintainer is filled from git config, as
    `new` fills it, and said so."""
    gitconfig = tmp_path / "gitconfig"
    gitconfig.write_text("[user]\n\tname = Ada Lovelace\n\temail = ada@example.org\n")
    env = dict(os.environ, GIT_CONFIG_GLOBAL=str(gitconfig), GIT_CONFIG_NOSYSTEM="1", HOME=str(tmp_path))
    source = sw_export(tmp_path / "ros1")
    result = run_pkgforge("migrate", source, "--destination", tmp_path / "out", cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stdout + result.stderr
    manifest = source / "package.xml"
    assert (
        f"ros1/GripperPrototype/package.xml:{line_of(manifest, '<maintainer')}: PF806 [info] package.xml: "
        '<maintainer email="TODO@email.com"/> has no name: Ada Lovelace <ada@example.org> (name from git config '
        "user.name, e-mail from git config user.email) (migrate-changed)"
    ) in result.stdout
    written = (tmp_path / "out/gripper_prototype/package.xml").read_text()
    assert '<maintainer email="ada@example.org">Ada Lovelace</maintainer>' in written


def test_a_format_1_exporter_package_xml_is_read(tmp_path):
    """The older exporters' format 1 manifest (<package>, <build_depend>, <run_depend>) with the
    nameless maintainer: read, the maintainer filled in, the ROS 1 dependencies said at their lines."""
    source = sw_export(tmp_path / "ros1", "Arm_2_description")
    manifest = source / "package.xml"
    text = manifest.read_text().replace('<package format="2">', "<package>")
    text = text.replace("<depend>roslaunch</depend>", "<build_depend>roslaunch</build_depend>")
    manifest.write_text(text.replace("<depend>", "<run_depend>").replace("</depend>", "</run_depend>"))
    result = run_pkgforge("migrate", source, "--destination", tmp_path / "out", *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stderr == ""
    notes = _notes(result.stdout)
    where = "ros1/Arm_2_description/package.xml"
    for expected in (
        f"{where}:{line_of(manifest, '<maintainer')}: PF806 [info] package.xml: <maintainer "
        'email="TODO@email.com"/> has no name: Test Maintainer <test@example.com> (name from --maintainer-name, '
        "e-mail from --maintainer-email) (migrate-changed)",
        f"{where}:{line_of(manifest, '<build_depend>roslaunch')}: PF804 [info] <build_depend>roslaunch</build_depend> "
        "is ROS 1 only: not carried over (migrate-dependency-dropped)",
        f"{where}:{line_of(manifest, '<run_depend>gazebo')}: PF804 [info] <run_depend>gazebo</run_depend>: Gazebo "
        "Classic, not carried over (--gazebo uses ros_gz_sim) (migrate-dependency-dropped)",
    ):
        assert expected in notes, (expected, notes)
    written = (tmp_path / "out/arm_2_description/package.xml").read_text()
    assert '<package format="3">' in written and "<exec_depend>rviz2</exec_depend>" in written


@pytest.mark.triggers("PF807")
def test_content_after_the_root_is_read_as_ros1_did(exports):
    """A <transmission> after </robot> (a model the display launch uses) and a broken model no
    launch file uses: the migration goes on, each file kept byte for byte and reported (PF807) at
    its line; verify names the same two defects (xacro refuses the first) and nothing else. The
    import of the first model (--from-urdf) says the same and has the same errors, no other."""
    root, _, sources, outputs = exports
    source, out = sources["trailing"], outputs["trailing"].stdout
    model, broken = source / "urdf/xr10-1500.urdf", source / "urdf/xr10-1500_trans.urdf"
    where = os.path.relpath(model, root / "ws")
    assert (
        f"{where}:{line_of(model, '<transmission')}: PF807 [warning] content after </robot>: ROS 1's parser read "
        "the first element and went on; xacro refuses it; kept as written (migrate-source-defect)"
    ) in _notes(out)
    assert (
        f"{os.path.relpath(broken, root / 'ws')}:3: PF807 [warning] not well-formed XML: Opening and ending tag "
        "mismatch: link line 2 and robot, line 3, column 9; no launch file uses it: copied as written "
        "(migrate-source-defect)"
    ) in _notes(out)
    package = root / "apart/src/xr10_1500"
    assert (package / "urdf/xr10-1500_trans.urdf").read_bytes() == broken.read_bytes()
    assert (package / "urdf/xr10-1500.urdf").read_bytes() == model.read_bytes().replace(
        b"package://xr10-1500/", b"package://xr10_1500/"
    )
    status, report = verify_report(package, "--no-cache")
    assert sorted((d[0], d[1]) for d in _errors(report)) == [
        ("PF308", "launch/display.launch.py"),
        ("PF401", "urdf/xr10-1500.urdf"),
        ("PF401", "urdf/xr10-1500_trans.urdf"),
    ]
    imported = outputs["import-trailing"].stdout
    assert (
        f"{os.path.relpath(model, root / 'apart')}:{line_of(model, '<transmission')}: PF807 [warning] content after "
        "</robot>: ROS 1's parser read the first element and went on; xacro refuses it; kept as written "
        "(migrate-source-defect)"
    ) in _notes(imported)
    package = root / "apart/src/xr10_imported"
    assert (package / "urdf/xr10-1500.urdf").read_bytes() == model.read_bytes().replace(
        b"package://xr10-1500/", b"package://xr10_imported/"
    )
    status, report = verify_report(package, "--no-cache")
    assert sorted((d[0], d[1]) for d in _errors(report)) == [
        ("PF308", "launch/display.launch.py"),
        ("PF401", "urdf/xr10-1500.urdf"),
    ]


def test_uris_naming_the_exporters_folder(exports):
    """package://MyArm-URDF/meshes/... in package arm_description: read in the package's folder, said
    once, rewritten to package://arm_description/ (and in --from-urdf: package://assets/ of
    onshape-to-robot, read beside the model)."""
    _, workspace, sources, outputs = exports
    model = sources["folder"] / "urdf/arm_description.urdf"
    notes = _notes(outputs["folder"].stdout)
    said = [n for n in notes if "names no package" in n]
    assert said == [
        f"{os.path.relpath(model, workspace)}:{lines_of(model, 'MyArm-URDF')[0]}: PF805 [info] "
        "package://MyArm-URDF/ names no package: read as arm_description/, the package folder around "
        "arm_description.urdf, where the exporter put what it names (migrate-generated)"
    ]
    for folder, out in (("ws", outputs["folder"]), ("imports", outputs["import-folder"])):
        text = (workspace.parent / folder / "src/arm_description/urdf/arm_description.urdf").read_text()
        assert "MyArm-URDF" not in text and text.count("package://arm_description/meshes/") == 6
        said = [n for n in _notes(out.stdout) if "names no package" in n]
        assert (
            len(said) == 1 and "package://MyArm-URDF/ names no package: read as arm_description/" in said[0]
        )
    onshape = outputs["import-onshape"].stdout
    assert [n for n in _notes(onshape) if "names no package" in n] == [
        f"{os.path.relpath(workspace.parent / 'onshape/two_wheels/robot.urdf', workspace.parent / 'imports')}:"
        f"{line_of(workspace.parent / 'onshape/two_wheels/robot.urdf', 'package://assets/')}: PF805 [info] "
        "package://assets/ names no package: read as assets/, the folder beside robot.urdf, where the exporter "
        "put what it names (migrate-generated)"
    ]
    assert (
        "package://two_wheels/meshes/body.stl"
        in (workspace.parent / "imports/src/two_wheels/urdf/robot.urdf").read_text()
    )


def test_an_import_resolves_every_reference_the_source_did(exports):
    """fusion2urdf's xacro names each mesh in a start tag over two lines (filename, then scale): each
    use is rewritten (the visual was left on package://Arm_2_description/ before), and every mesh
    of the model resolves in the new package."""
    _, workspace, sources, _ = exports
    text = (workspace.parent / "imports/src/arm_2_description/urdf/Arm_2.xacro").read_text()
    assert "Arm_2_description" not in text
    assert text.count('filename="package://arm_2_description/meshes/base_link.stl"') == 2
    explain = run_pkgforge(
        "verify",
        "--explain-model",
        "src/arm_2_description/urdf/Arm_2.xacro",
        cwd=workspace.parent / "imports",
    ).stdout
    assert explain.count("✓ package://arm_2_description/meshes/") == 4 and "✗" not in explain, explain


def test_models_are_copied_byte_for_byte(exports):
    """No link added without --add-root-link (PF604 stays a warning of the model's own), no CRLF
    turned into LF, in migrate and in --from-urdf alike."""
    _, workspace, sources, _ = exports
    source = sources["sw"] / "urdf/GripperPrototype.urdf"
    for folder, package in (
        ("ws", "gripper_prototype"),
        ("ws", "gripper_gazebo"),
        ("imports", "gripper_prototype"),
    ):
        copied = (workspace.parent / folder / "src" / package / "urdf/GripperPrototype.urdf").read_bytes()
        assert copied == source.read_bytes().replace(b"GripperPrototype/", package.encode() + b"/")
    for relative in ("urdf/Arm_2.trans", "urdf/materials.xacro"):
        assert (workspace / "src/arm_2_description" / relative).read_bytes() == (
            sources["fusion"] / relative
        ).read_bytes()
    # fusion2urdf's Arm_2.gazebo loads ROS 1's gazebo_ros_control: without --gazebo it is left out
    # (it loads in no ROS 2 Gazebo), the rest of the file kept
    written = (workspace / "src/arm_2_description/urdf/Arm_2.gazebo").read_text()
    original = (sources["fusion"] / "urdf/Arm_2.gazebo").read_text()
    assert "libgazebo_ros_control.so" in original and "libgazebo_ros_control.so" not in written
    assert written.count("<gazebo reference=") == original.count("<gazebo reference=") > 0


def test_migrate_records_the_distro_it_was_given(exports):
    """migrate --distro humble writes pkgforge.toml as new --distro does: verify then targets
    humble (ign_ros2_control's IgnitionSystem; on the newest LTS it would be gz_ros2_control's)."""
    _, workspace, _, _ = exports
    assert 'distro = "humble"' in (workspace / "src/arm_humble/pkgforge.toml").read_text()
    assert not (workspace / "src/arm_2_description/pkgforge.toml").exists()  # no --distro given


def test_launch_files_that_cannot_run_are_not_written(exports):
    """fusion2urdf's gazebo.launch without --gazebo starts nothing in ROS 2: not written, said so;
    its controller.launch gives robot_state_publisher the package's model and ROS 2's controller
    names; rviz's required="true" is on_exit=Shutdown()."""
    _, workspace, sources, outputs = exports
    package = workspace / "src/arm_2_description"
    assert sorted(p.name for p in (package / "launch").glob("*.launch.*")) == [
        "controller.launch.py",
        "display.launch.py",
    ]
    gazebo = sources["fusion"] / "launch/gazebo.launch"
    assert (
        f"{os.path.relpath(gazebo, workspace)}: PF801 [warning] launch/gazebo.launch.py not written: nothing in it "
        "starts in ROS 2 (migrate-dropped)"
    ) in _notes(outputs["fusion"].stdout)
    controller = (package / "launch/controller.launch.py").read_text()
    assert "'joint_state_broadcaster'" in controller and "joint_state_controller" not in controller
    assert (
        "parameters=[{'robot_description': ParameterValue(Command(['xacro ', FindPackageShare('arm_2_description'), "
        "'/urdf/Arm_2.xacro']), value_type=str)}]"
    ) in controller
    assert "on_exit=Shutdown()" in (package / "launch/display.launch.py").read_text()
    assert (
        "from launch.actions import DeclareLaunchArgument, Shutdown"
        in (package / "launch/display.launch.py").read_text()
    )


@pytest.mark.parametrize(
    "package, suffix, distro", [("arm_jazzy", "xml", "jazzy"), ("arm_humble", "yaml", "humble")]
)
def test_gazebo_launch_files_run_on_the_target_distro(exports, package, suffix, distro):
    """--gazebo: ros_gz_sim create reads the model as its own parameter (-param robot_description:
    nothing in the file publishes /robot_description), gz sim opens empty.sdf paused (paused:=true);
    required="true" is on_exit="shutdown" where the frontends read it (after Humble)."""
    _, workspace, sources, outputs = exports
    launch = (workspace / "src" / package / f"launch/gazebo.launch.{suffix}").read_text()
    assert "-param robot_description" in launch and "-topic" not in launch
    assert "empty.sdf" in launch and "-r" not in launch
    display = (workspace / "src" / package / f"launch/display.launch.{suffix}").read_text()
    assert ("on_exit" in display) == (distro != "humble")
    notes = _notes(outputs[f"fusion-{distro}"].stdout)
    source = os.path.relpath(sources["fusion"] / "launch/display.launch", workspace)
    rviz = line_of(sources["fusion"] / "launch/display.launch", 'name="rviz"')
    if distro == "humble":
        assert (
            f'{source}:{rviz}: PF801 [warning] node attribute required="true" left out: humble\'s YAML launch has no '
            "on_exit (Python's on_exit=Shutdown() has: --launch-format py) (migrate-dropped)"
        ) in notes
    else:
        assert (
            f'{source}:{rviz}: PF806 [info] node attribute required="true" → on_exit="shutdown": the launch ends '
            "when it exits (migrate-changed)" in notes
        )


@pytest.fixture(scope="module")
def prefixes(tmp_path_factory) -> dict[str, Path]:
    base = tmp_path_factory.mktemp("ros")
    out = {}
    for distro in DISTROS:
        prefix, reason = make_prefix(distro, base)
        if prefix is None:
            pytest.skip(f"no real ROS 2 launch library for {distro}: {reason}")
        out[distro] = prefix
    return out


@pytest.mark.parametrize("distro", DISTROS)
def test_every_generated_launch_file_loads_through_both_engines(exports, prefixes, distro):
    """The launch files the migrations and the imports wrote, evaluated by pkgforge's engine and by
    the real launch libraries of humble and jazzy: none fails to load, and both engines say the
    same. (arm_jazzy targets jazzy: humble's frontends refuse its on_exit="shutdown", which is why
    humble's own package has none.)"""
    root, workspace, _, _ = exports
    elsewhere = "src/arm_jazzy/" if distro == "humble" else "\0"
    reports = {
        (engine, folder.name): verify_report(
            folder,
            "--no-cache",
            "--distro",
            distro,
            "--launch-engine",
            engine,
            *(["--ros-prefix", str(prefixes[distro])] if engine == "ros" else []),
        )[1]
        for engine in ("builtin", "ros")
        for folder in (workspace, root / "imports")
    }
    launch = {
        key: sorted(
            (d["code"], d["path"], d["line"])
            for d in report["diagnostics"]
            if d["code"].startswith("PF3") and d["severity"] != "info" and not d["path"].startswith(elsewhere)
        )
        for key, report in reports.items()
    }
    assert all(found == [] for found in launch.values()), json.dumps({str(k): v for k, v in launch.items()})


def test_a_generated_launch_file_that_does_not_load_is_not_written(tmp_path):
    """A ROS 1 launch file including a ROS 1 XML file (sub.xml, copied as it is): its ROS 2 form
    fails to load (the include does): left out, said so; the others are written."""
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / "launch/sub.xml").write_text(
        '<launch>\n  <param name="use_sim_time" value="true"/>\n</launch>\n'
    )
    (package / "launch/top.launch").write_text(
        '<launch>\n  <include file="$(find robot_arm)/launch/sub.xml"/>\n</launch>\n'
    )
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out", cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr  # sub.xml itself is the source's
    assert (
        "ros1/robot_arm/launch/top.launch: PF801 [warning] launch/top.launch.py not written: it does not load on "
        "lyrical (IncludeLaunchDescription failed: FrontendError: Unrecognized entity of the type: param) "
        "(migrate-dropped)"
    ) in result.stdout
    written = sorted(p.name for p in (tmp_path / "out/robot_arm/launch").iterdir())
    assert written == ["display.launch.py", "display_xacro.launch.py", "gazebo.launch.py", "sub.xml"]
    assert "top.launch" not in (tmp_path / "out/robot_arm/package.xml").read_text()


def test_a_generated_launch_file_reading_a_file_that_exists_nowhere_is_not_written(tmp_path):
    """The exporter's display.launch names <package>.urdf, a model the package does not have (the
    user kept the export's <robot>.xacro): its ROS 2 form fails at start as the ROS 1 file did (the
    model is read when the launch starts): left out, said so with the path; verify then finds no
    missing file. (faro_description, rg6_gripper_description's gazebo.launch in the campaign.)"""
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / "launch/show.launch").write_text(
        "<launch>\n"
        '  <param name="robot_description" textfile="$(find robot_arm)/urdf/robot_arm_description.urdf"/>\n'
        '  <node name="robot_state_publisher" pkg="robot_state_publisher" type="robot_state_publisher"/>\n'
        "</launch>\n"
    )
    out = tmp_path / "out"
    result = run_pkgforge("migrate", package, "--destination", out, *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert (
        "ros1/robot_arm/launch/show.launch: PF801 [warning] launch/show.launch.py not written: it reads a file "
        "that exists nowhere: share/robot_arm/urdf/robot_arm_description.urdf does not exist, in the install tree "
        "or in robot_arm's source (migrate-dropped)"
    ) in result.stdout
    written = sorted(p.name for p in (out / "robot_arm/launch").iterdir())
    assert written == ["display.launch.py", "display_xacro.launch.py", "gazebo.launch.py"]
    _, report = verify_report(out / "robot_arm", "--no-cache")
    assert [d for d in report["diagnostics"] if d["code"] == "PF303"] == []


def test_one_line_per_missing_mesh(tmp_path):
    """A mesh the visual and the collision both name is missing: one line, with the other line."""
    package = sw_export(tmp_path / "ros1")
    (package / "meshes/Thumb.STL").unlink()
    model = package / "urdf/GripperPrototype.urdf"
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out", *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 2
    visual, collision = lines_of(model, "Thumb.STL")
    assert result.stderr.splitlines() == [
        f"pkgforge: error: {model}:{visual}: mesh 'package://GripperPrototype/meshes/Thumb.STL' not found: no file "
        f"{package / 'meshes/Thumb.STL'} (also line {collision})",
        "1 file(s) the model names cannot be found: nothing written; copy them where the model says",
    ]
    assert not (tmp_path / "out").exists()


def test_name_options(tmp_path):
    """--name chooses the name; an invalid --name, or a source name no valid name is near, stops
    with one line and writes nothing. `new` leaves NAME out only with --from-urdf."""
    bare = run_pkgforge("new", *MAINTAINER, cwd=tmp_path)
    assert (
        bare.returncode == 2
        and "Missing argument 'NAME' (it may be left out with --from-urdf only)" in bare.stderr
    )
    package = sw_export(tmp_path / "ros1", "7260501 TB6-URDF")
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out", *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr == (
        f"pkgforge: error: {package / 'package.xml'}:2: package name: '7260501 TB6-URDF' starts with a digit, and "
        "no valid name is near it: give the ROS 2 package's name with --name (nothing written)\n"
    )
    bad = run_pkgforge("migrate", package, "--name", "Tb6", "--destination", tmp_path / "out", cwd=tmp_path)
    assert bad.returncode == 2 and bad.stderr.startswith(
        "pkgforge: error: invalid --name: 'Tb6' has upper-case"
    )
    assert not (tmp_path / "out").exists()
    good = run_pkgforge(
        "migrate",
        package,
        "--name",
        "tb6_description",
        "--destination",
        tmp_path / "out",
        *MAINTAINER,
        cwd=tmp_path,
    )
    assert good.returncode == 0, good.stdout + good.stderr
    text = (tmp_path / "out/tb6_description/urdf/7260501 TB6-URDF.urdf").read_text()
    assert "package://tb6_description/meshes/" in text and "TB6-URDF/meshes" not in text


def test_remaps_keep_their_substitutions_and_navigation_nodes_get_ros2_names(tmp_path):
    """A remap to $(arg scan_topic) remaps to the argument's value (it was the literal text, no topic
    name at all); ROS 1 navigation's map_server and amcl are nav2's, declared as such."""
    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / "launch/amcl.launch").write_text(
        '<launch>\n  <arg name="scan_topic" default="scan"/>\n'
        '  <node pkg="map_server" type="map_server" name="map_server" args="$(find robot_arm)/config/map.yaml"/>\n'
        '  <node pkg="amcl" type="amcl" name="amcl">\n    <remap from="scan" to="$(arg scan_topic)"/>\n  </node>\n'
        "</launch>\n"
    )
    (package / "config/map.yaml").write_text("image: map.pgm\nresolution: 0.05\n")
    result = run_pkgforge("migrate", package, "--destination", tmp_path / "out", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    launch = (tmp_path / "out/robot_arm/launch/amcl.launch.py").read_text()
    assert "remappings=[('scan', LaunchConfiguration('scan_topic'))]" in launch
    assert "package='nav2_map_server'" in launch and "package='nav2_amcl'" in launch
    manifest = (tmp_path / "out/robot_arm/package.xml").read_text()
    assert (
        "<exec_depend>nav2_amcl</exec_depend>" in manifest
        and "<exec_depend>map_server</exec_depend>" not in manifest
    )
