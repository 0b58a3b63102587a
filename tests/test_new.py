"""`pkgforge new`: what it writes, and what it refuses."""

from __future__ import annotations

import ast
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import click
import pytest
import yaml
from catkin_pkg.package import parse_package
from conftest import MAINTAINER, run_pkgforge
from lxml import etree

from pkgforge.cli import main as cli_main
from pkgforge.errors import PkgforgeError
from pkgforge.scaffold import package as scaffold

REPO = Path(__file__).resolve().parent.parent


def listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


@pytest.mark.parametrize("name", ["Rob", "rob-desc", "1rob", "rob__d", "rob_", "../x"])
def test_bad_names_exit_2_and_create_nothing(tmp_path, name):
    result = run_pkgforge("new", name, *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 2
    assert "invalid package name" in result.stderr
    assert "REP 144" in result.stderr
    assert "Traceback" not in result.stderr
    assert listing(tmp_path) == []
    assert not (tmp_path.parent / "x").exists()


def test_existing_folder_is_refused_and_unchanged(tmp_path):
    target = tmp_path / "rob_description"
    target.mkdir()
    (target / "package.xml").write_text("mine")
    result = run_pkgforge("new", "rob_description", *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 2
    assert "already exists" in result.stderr and "--force" in result.stderr
    assert listing(tmp_path) == ["rob_description", "rob_description/package.xml"]
    assert (target / "package.xml").read_text() == "mine"


def test_force_lists_edited_files_and_replaces_them_only_when_given_twice(tmp_path):
    target = tmp_path / "rob_description"
    target.mkdir()
    (target / "package.xml").write_text("old")
    (target / "notes.txt").write_text("keep me")
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--force", cwd=tmp_path)
    assert result.returncode == 2, result.stdout + result.stderr
    assert "--force would replace 1 file(s)" in result.stderr and "\n  package.xml\n" in result.stderr
    assert "twice" in result.stderr and "Traceback" not in result.stderr
    assert listing(tmp_path) == [
        "rob_description",
        "rob_description/notes.txt",
        "rob_description/package.xml",
    ]
    assert (target / "package.xml").read_text() == "old"
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--force", "--force", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "package.xml (replaced)" in result.stdout
    assert (target / "notes.txt").read_text() == "keep me"
    assert "<name>rob_description</name>" in (target / "package.xml").read_text()
    # the same files again: nothing differs, so one --force is enough, and each is listed unchanged
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--force", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "package.xml (unchanged)" in result.stdout and "(replaced)" not in result.stdout


def test_force_refuses_a_fifo_where_it_writes_a_file_without_reading_it(tmp_path):
    """issue 35: comparing what is there with what would be written read the FIFO: it blocked for ever"""
    target = tmp_path / "rob_description"
    target.mkdir()
    os.mkfifo(target / "package.xml")
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--force", cwd=tmp_path, timeout=120)
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stdout + result.stderr
    assert result.stderr == (
        f"pkgforge: error: cannot read {target / 'package.xml'}: a FIFO (named pipe): "
        "pkgforge reads only regular files\n"
    )
    assert listing(tmp_path) == ["rob_description", "rob_description/package.xml"]


def test_force_adds_missing_files_and_keeps_identical_ones(tmp_path):
    run_pkgforge("new", "rob_description", *MAINTAINER, cwd=tmp_path)
    target = tmp_path / "rob_description"
    (target / "rviz" / "display.rviz").unlink()
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--force", "--ci", "github", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "  rviz/display.rviz\n" in result.stdout and "  .github/workflows/pkgforge.yml\n" in result.stdout
    assert "  CMakeLists.txt (unchanged)\n" in result.stdout
    assert (target / "rviz" / "display.rviz").is_file()


def test_new_honours_the_umask(tmp_path):
    for mask, folder_mode, file_mode in ((0o022, 0o755, 0o644), (0o027, 0o750, 0o640)):
        destination = tmp_path / f"m{mask:o}"
        script = (
            f"import os, sys; os.umask({mask}); sys.argv = ['pkgforge', 'new', 'rob_description', "
            f"*{MAINTAINER!r}, '--destination', {str(destination)!r}]; "
            "from pkgforge.cli import main; main()"
        )
        result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=tmp_path)
        assert result.returncode == 0, result.stderr
        package = destination / "rob_description"
        assert package.stat().st_mode & 0o777 == folder_mode
        assert (package / "urdf").stat().st_mode & 0o777 == folder_mode
        assert (package / "package.xml").stat().st_mode & 0o777 == file_mode


def test_force_never_writes_through_a_link_out_of_the_package(tmp_path):
    run_pkgforge("new", "rob_description", *MAINTAINER, cwd=tmp_path)
    target = tmp_path / "rob_description"
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "keep.txt").write_text("mine")
    shutil.rmtree(target / "urdf")
    (target / "urdf").symlink_to(elsewhere)
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--force", "--force", cwd=tmp_path)
    assert result.returncode == 2
    assert f"{target / 'urdf'} is a symbolic link to {elsewhere}" in result.stderr
    assert "nothing written" in result.stderr and "Traceback" not in result.stderr
    assert listing(elsewhere) == ["keep.txt"]
    # the package folder itself a link to another folder
    linked = tmp_path / "other" / "rob_description"
    linked.parent.mkdir()
    linked.symlink_to(elsewhere)
    result = run_pkgforge(
        "new", "rob_description", *MAINTAINER, "--force", "--destination", "other", cwd=tmp_path
    )
    assert result.returncode == 2 and "is a symbolic link" in result.stderr, result.stderr
    assert listing(elsewhere) == ["keep.txt"]


def test_too_long_a_name_is_one_line_exit_2(tmp_path):
    result = run_pkgforge("new", "a" * 250, *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "250 characters" in result.stderr, result.stderr
    assert listing(tmp_path) == []


def test_failure_half_way_leaves_nothing_behind(tmp_path, monkeypatch):
    spec = scaffold.make_spec("rob_description", maintainer_name="A", maintainer_email="a@example.com")
    calls = []
    real_write = scaffold._write_new  # every file of the package is written through it

    def failing_write(path, content, mode):
        calls.append(path)
        if len(calls) == 3:
            raise OSError(28, "No space left on device")
        return real_write(path, content, mode)

    monkeypatch.setattr(scaffold, "_write_new", failing_write)
    with pytest.raises(PkgforgeError, match="No space left"):
        scaffold.create_package(spec, tmp_path)
    assert listing(tmp_path) == []


def test_default_destination_is_src_in_a_workspace_root(tmp_path):
    (tmp_path / "src").mkdir()
    result = run_pkgforge("new", "rob_description", *MAINTAINER, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "src" / "rob_description" / "package.xml").is_file()


def test_destination_option(tmp_path):
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--destination", "deep/er", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "deep" / "er" / "rob_description" / "package.xml").is_file()


def test_next_steps_build_the_workspace_the_package_landed_in(tmp_path):
    """The README's main job: `new --destination ws/src` from the folder above ws/; a bare
    `pkgforge build` there would look for packages in the wrong folder."""
    result = run_pkgforge("new", "rob_description", *MAINTAINER, "--destination", "ws/src", cwd=tmp_path)
    assert "  pkgforge build ws " in result.stdout
    assert "  pkgforge verify ws/src/rob_description\n" in result.stdout
    (tmp_path / "w2" / "src").mkdir(parents=True)
    result = run_pkgforge("new", "rob_description", *MAINTAINER, cwd=tmp_path / "w2")
    assert "  pkgforge build  " in result.stdout


def test_maintainer_defaults_from_git_config(tmp_path):
    gitconfig = tmp_path / "gitconfig"
    gitconfig.write_text("[user]\n\tname = Ada Lovelace\n\temail = ada@example.org\n")
    env = dict(os.environ, GIT_CONFIG_GLOBAL=str(gitconfig), GIT_CONFIG_NOSYSTEM="1", HOME=str(tmp_path))
    result = run_pkgforge("new", "rob_description", cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stderr
    manifest = (tmp_path / "rob_description" / "package.xml").read_text()
    assert '<maintainer email="ada@example.org">Ada Lovelace</maintainer>' in manifest


def test_bad_maintainer_email_is_refused(tmp_path):
    result = run_pkgforge("new", "rob_description", "--maintainer-email", "a@b", cwd=tmp_path)
    assert result.returncode == 2
    assert "invalid maintainer e-mail 'a@b'" in result.stderr
    assert listing(tmp_path) == []


def test_every_option_is_in_help():
    for command in [cli_main, *cli_main.commands.values()]:
        path = [] if command is cli_main else [command.name]
        result = subprocess.run(
            [sys.executable, "-m", "pkgforge", *path, "--help"], capture_output=True, text=True, timeout=60
        )
        assert result.returncode == 0
        for param in command.params:
            if isinstance(param, click.Option):
                for opt in param.opts:
                    assert opt in result.stdout, f"{opt} missing from `pkgforge {' '.join(path)} --help`"


def test_version():
    result = run_pkgforge("--version", cwd=REPO)
    assert result.returncode == 0 and re.search(r"pkgforge, version \d+\.\d+\.\d+", result.stdout)


def test_templates_ship_in_the_wheel(tmp_path):
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "-q",
            "-w",
            str(tmp_path),
            str(REPO),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    (wheel,) = tmp_path.glob("ros_pkgforge-*.whl")  # the distribution's own name, not PyPI's `pkgforge`
    names = zipfile.ZipFile(wheel).namelist()
    assert "pkgforge/__init__.py" in names  # the import package keeps its name
    for template in (
        "package/package.xml.j2",
        "package/CMakeLists.txt.j2",
        "package/launch/display.launch.py.j2",
        "package/rviz/display.rviz.j2",
    ):
        assert f"pkgforge/scaffold/templates/{template}" in names
    # the released packages of every active distro, which verify reads (distro_data)
    assert (
        zipfile.ZipFile(wheel).read("pkgforge/model/data/distros.txt")
        == (REPO / "src" / "pkgforge" / "model" / "data" / "distros.txt").read_bytes()
    )


# --- what the files say --------------------------------------------------------------------


@pytest.fixture(scope="module")
def jazzy_package(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("new")
    result = run_pkgforge("new", "rob_description", *MAINTAINER, cwd=folder)
    assert result.returncode == 0, result.stderr
    return folder / "rob_description"


def test_manifest(jazzy_package):
    package = parse_package(str(jazzy_package / "package.xml"))
    assert package.package_format == 3
    assert package.name == "rob_description"
    assert package.version == "0.0.0"
    assert [str(d) for d in package.buildtool_depends] == ["ament_cmake"]
    assert sorted(str(d) for d in package.exec_depends) == [
        "joint_state_publisher",
        "joint_state_publisher_gui",
        "launch",
        "launch_ros",
        "robot_state_publisher",
        "rviz2",
        "rviz_default_plugins",
        "xacro",
    ]
    assert [e.content for e in package.exports if e.tagname == "build_type"] == ["ament_cmake"]
    assert [str(lic) for lic in package.licenses] == ["Apache-2.0"]


def test_cmakelists_installs_exactly_the_created_folders(jazzy_package):
    text = (jazzy_package / "CMakeLists.txt").read_text()
    assert "project(rob_description NONE)" in text
    installed = re.search(r"install\(\s*DIRECTORY ([^\n]+)\n\s*DESTINATION share/\$\{PROJECT_NAME\}", text)
    folders = sorted(p.name for p in jazzy_package.iterdir() if p.is_dir())
    assert sorted(installed.group(1).split()) == folders == ["launch", "meshes", "rviz", "urdf"]


def test_rviz_config_shows_the_robot(jazzy_package):
    config = yaml.safe_load((jazzy_package / "rviz" / "display.rviz").read_text())
    manager = config["Visualization Manager"]
    assert manager["Global Options"]["Fixed Frame"] == "base_link"
    classes = [d["Class"] for d in manager["Displays"]]
    assert classes == [
        "rviz_default_plugins/Grid",
        "rviz_default_plugins/TF",
        "rviz_default_plugins/RobotModel",
    ]
    robot_model = manager["Displays"][2]
    assert robot_model["Description Source"] == "Topic"
    assert robot_model["Description Topic"]["Value"] == "/robot_description"


def test_python_launch_has_the_urdf_launch_shape(jazzy_package):
    tree = ast.parse((jazzy_package / "launch" / "display.launch.py").read_text())
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "id", "") == "Node"]
    packages = {
        kw.value.value: {k.arg for k in n.keywords} for n in calls for kw in n.keywords if kw.arg == "package"
    }
    assert set(packages) == {
        "robot_state_publisher",
        "joint_state_publisher",
        "joint_state_publisher_gui",
        "rviz2",
    }
    # seed case 4: joint_state_publisher gets no model argument
    assert "arguments" not in packages["joint_state_publisher"]
    assert "arguments" not in packages["joint_state_publisher_gui"]
    declared = [
        n.keywords
        for n in ast.walk(tree)
        if isinstance(n, ast.Call) and getattr(n.func, "id", "") == "DeclareLaunchArgument"
    ]
    assert sorted(kw.value.value for kws in declared for kw in kws if kw.arg == "name") == [
        "gui",
        "model",
        "rvizconfig",
    ]
    assert "value_type=str" in (jazzy_package / "launch" / "display.launch.py").read_text()


@pytest.mark.parametrize(
    "distro, typed", [("humble", False), ("jazzy", True), ("lyrical", True), ("rolling", True)]
)
def test_xml_launch_per_distro(tmp_path, distro, typed):
    result = run_pkgforge(
        "new", "rob", *MAINTAINER, "--launch-format", "xml", "--distro", distro, cwd=tmp_path
    )
    assert result.returncode == 0, result.stderr
    root = etree.parse(str(tmp_path / "rob" / "launch" / "display.launch.xml")).getroot()
    assert root.tag == "launch"
    param = root.find("node[@pkg='robot_state_publisher']/param")
    assert param.get("value") == "$(command 'xacro $(var model)')"
    assert (param.get("type") == "str") is typed
    assert [c.get("value") for c in root.findall("arg[@name='gui']/choice")] == ["true", "false"]
    manifest = (tmp_path / "rob" / "package.xml").read_text()
    assert "<exec_depend>launch_xml</exec_depend>" in manifest


def test_yaml_launch(tmp_path):
    result = run_pkgforge("new", "rob", *MAINTAINER, "--launch-format", "yaml", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    doc = yaml.safe_load((tmp_path / "rob" / "launch" / "display.launch.yaml").read_text())
    nodes = [entry["node"] for entry in doc["launch"] if "node" in entry]
    assert [n["pkg"] for n in nodes] == [
        "robot_state_publisher",
        "joint_state_publisher",
        "joint_state_publisher_gui",
        "rviz2",
    ]
    assert nodes[0]["param"][0] == {
        "name": "robot_description",
        "value": "$(command 'xacro $(var model)')",
        "type": "str",
    }
    assert "<exec_depend>launch_yaml</exec_depend>" in (tmp_path / "rob" / "package.xml").read_text()


def test_ament_python_package(tmp_path):
    result = run_pkgforge("new", "rob", *MAINTAINER, "--build-type", "ament_python", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    package = tmp_path / "rob"
    assert (package / "resource" / "rob").is_file()
    assert not (package / "CMakeLists.txt").exists()
    manifest = parse_package(str(package / "package.xml"))
    assert [e.content for e in manifest.exports if e.tagname == "build_type"] == ["ament_python"]
    compile((package / "setup.py").read_text(), "setup.py", "exec")
