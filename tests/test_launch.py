"""Launch files resolved in the install space: the seed styles, each defect, broken files, three trees."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest
from conftest import (
    FIXTURES,
    VARIANTS,
    at_least,
    copy_fixture,
    edit,
    line_of,
    new_package,
    run_pkgforge,
    verify_report,
)

verify = verify_report


def found(report: dict, minimum: str = "warning") -> list[tuple]:
    return sorted((d["code"], d["name"], d["path"], d["line"]) for d in at_least(report, minimum))


SCRIPTS = Path(sysconfig.get_path("scripts"))


# --- fixtures: the two seed styles, clean -----------------------------------------------------


def humble_package(workspace: Path) -> Path:
    """Seed 000's style, with its names and install rule fixed: clean."""
    package = copy_fixture("seed000/rob_description", workspace)
    for path in package.rglob("*"):
        if path.is_file() and path.suffix.lower() != ".stl":
            path.write_text(path.read_text().replace("robot_description", "rob_description"))
    # (the parameter keeps its name: robot_state_publisher given none stops at start, PF321)
    edit(package / "launch" / "display.launch.py", "{'rob_description': doc", "{'robot_description': doc")
    edit(package / "CMakeLists.txt", "DIRECTORY launch meshes urdf", "DIRECTORY launch meshes rviz urdf")
    return package


def jazzy_package(workspace: Path, fmt: str = "py") -> Path:
    """Seed 001's style, without the tutorial's worlds/ and models/: clean."""
    package = copy_fixture("seed001/small_turtle", workspace)
    edit(package / "CMakeLists.txt", "launch worlds urdf meshes models rviz", "launch urdf meshes rviz")
    if fmt != "py":
        (package / "launch" / "display.launch.py").unlink()
        shutil.copy(FIXTURES / "launch" / f"display.launch.{fmt}", package / "launch")
    return package


@pytest.mark.parametrize("style", ["humble", "jazzy-py", "jazzy-xml", "jazzy-yaml"])
def test_clean_fixtures_have_no_errors(tmp_path, style):
    package = humble_package(tmp_path) if style == "humble" else jazzy_package(tmp_path, style.split("-")[1])
    status, report = verify(package)
    assert status == 0, report
    assert found(report) == []


# --- each seed defect, exactly its check --------------------------------------------------------


@pytest.mark.parametrize(
    "style, marker",
    [
        ("humble", "rviz_config_path = os.path.join("),
        ("jazzy-py", "rviz_config_path = PathJoinSubstitution("),
        ("jazzy-xml", '<arg name="rvizconfig"'),
        ("jazzy-yaml", 'default: "$(find-pkg-share small_turtle)/rviz/display.rviz"'),
    ],
)
def test_rviz_not_installed_is_an_uninstalled_reference(tmp_path, style, marker):
    if style == "humble":
        package = humble_package(tmp_path)
        edit(package / "CMakeLists.txt", "DIRECTORY launch meshes rviz urdf", "DIRECTORY launch meshes urdf")
    else:
        package = jazzy_package(tmp_path, style.split("-")[1])
        edit(package / "CMakeLists.txt", "launch urdf meshes rviz", "launch urdf meshes")
    launch = next((package / "launch").iterdir())
    status, report = verify(package)
    assert status == 1
    assert found(report) == [
        ("PF302", "uninstalled-reference", f"launch/{launch.name}", line_of(launch, marker))
    ]
    (diagnostic,) = [d for d in report["diagnostics"] if d["code"] == "PF302"]
    assert "rviz" in diagnostic["hint"] and "CMakeLists.txt:" in diagnostic["hint"]


@pytest.mark.triggers("PF304")
def test_package_looked_up_by_the_wrong_name_is_unknown(tmp_path):
    package = humble_package(tmp_path)
    launch = package / "launch" / "display.launch.py"
    edit(launch, "package_name = 'rob_description'", "package_name = 'robot_description'")
    status, report = verify(package)
    assert status == 1
    assert found(report) == [
        (
            "PF304",
            "unknown-package",
            "launch/display.launch.py",
            line_of(launch, "get_package_share_directory(package_name)"),
        )
    ]
    (diagnostic,) = [d for d in report["diagnostics"] if d["code"] == "PF304"]
    assert "'robot_description'" in diagnostic["message"]
    assert "rob_description" in diagnostic["hint"]


@pytest.mark.parametrize(
    "fmt, marker",
    [
        ("py", 'executable="joint_state_publisher_gui"'),
        ("xml", 'pkg="joint_state_publisher_gui"'),
        ("yaml", "pkg: joint_state_publisher_gui"),
    ],
)
def test_missing_exec_depend_found_through_the_gui_branch(tmp_path, fmt, marker):
    package = jazzy_package(tmp_path, fmt)
    edit(package / "package.xml", "  <exec_depend>joint_state_publisher_gui</exec_depend>\n", "")
    launch = next((package / "launch").iterdir())
    status, report = verify(package)
    assert status == 1
    expected_line = line_of(launch, marker) - (1 if fmt == "yaml" else 0)  # a YAML entity starts at its key
    if fmt == "py":
        expected_line = line_of(launch, 'ld.add_action(Node(package="joint_state_publisher_gui"')
    assert found(report) == [("PF305", "missing-exec-depend", f"launch/{launch.name}", expected_line)]
    (diagnostic,) = report["diagnostics"]
    assert "(only with gui:=true)" in diagnostic["message"]
    assert diagnostic["hint"].startswith("add <exec_depend>joint_state_publisher_gui</exec_depend>")


def jsp_given_the_model(tmp_path: Path) -> tuple[Path, Path]:
    """Seed 001's package, its joint_state_publisher_gui given the model file (user story 4);
    (the package, its launch file)."""
    package = jazzy_package(tmp_path)
    launch = package / "launch" / "display.launch.py"
    edit(
        launch,
        'executable="joint_state_publisher_gui",',
        'executable="joint_state_publisher_gui", arguments=[urdf_model_path],',
    )
    return package, launch


@pytest.mark.triggers("PF306")
def test_jsp_given_the_model_as_an_argument(tmp_path):
    package, launch = jsp_given_the_model(tmp_path)
    # a model written with xacro (user story 4): the node parses it unexpanded
    model = package / "urdf" / "small_turtle.urdf"
    edit(
        model,
        '<robot name="small_turtle">',
        '<robot name="small_turtle" xmlns:xacro="http://www.ros.org/wiki/xacro">',
    )
    status, report = verify(package)
    assert status == 1
    assert found(report) == [
        (
            "PF306",
            "jsp-model-argument",
            "launch/display.launch.py",
            line_of(launch, 'package="joint_state_publisher_gui"'),
        )
    ]


def test_jsp_given_a_plain_urdf_reads_it_as_robot_state_publisher_does(tmp_path):
    # joint_state_publisher's description_file: a plain URDF (or SDF: ros_gz_project_template's
    # rrbot_setup.launch.py) that robot_state_publisher gets as it is, not through xacro, is read
    # the same way by both; no finding
    package, launch = jsp_given_the_model(tmp_path)
    edit(
        launch,
        'Command(["xacro ", LaunchConfiguration("model")])',
        'Command(["cat ", LaunchConfiguration("model")])',
    )
    status, report = verify(package)
    assert (status, found(report)) == (0, [])


@pytest.mark.triggers("PF307")
def test_robot_description_without_value_type(tmp_path):
    package = jazzy_package(tmp_path)
    launch = package / "launch" / "display.launch.py"
    edit(
        launch,
        'ParameterValue(Command(["xacro ", LaunchConfiguration("model")]),\n'
        "                                               value_type=str)",
        'Command(["xacro ", LaunchConfiguration("model")])',
    )
    status, report = verify(package)
    # the line to edit: where the Command is built, not where the node uses it
    assert found(report) == [
        (
            "PF307",
            "robot-description-not-string",
            "launch/display.launch.py",
            line_of(launch, "robot_description_content = Command("),
        )
    ]


@pytest.mark.triggers("PF308")
def test_xacro_error_names_xacros_message(tmp_path):
    package = jazzy_package(tmp_path)
    (package / "urdf" / "small_turtle.urdf").write_text(
        '<robot name="t" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="$(find small_turtle)/urdf/gone.xacro"/>\n</robot>\n'
    )
    status, report = verify(package)
    assert status == 1
    # at the model's include line, where the fix goes (not at the launch line that runs xacro)
    assert found(report) == [("PF308", "xacro-error", "urdf/small_turtle.urdf", 2)]
    assert "gone.xacro" in report["diagnostics"][0]["message"]


def test_import_of_a_name_ros_does_not_have(tmp_path):
    """A real mistake: PathJoinSubstitution lives in launch.substitutions, not launch_ros."""
    package = jazzy_package(tmp_path)
    launch = package / "launch" / "display.launch.py"
    edit(
        launch,
        "from launch_ros.substitutions import FindPackageShare",
        "from launch_ros.substitutions import FindPackageShare, PathJoinSubstitution",
    )
    status, report = verify(package)
    assert found(report) == [
        (
            "PF301",
            "launch-load-error",
            "launch/display.launch.py",
            line_of(launch, "from launch_ros.substitutions import"),
        )
    ]
    assert "cannot import name 'PathJoinSubstitution'" in report["diagnostics"][0]["message"]


# --- broken launch files: reported, and the rest still verified ---------------------------------

BROKEN = {
    "loops": ("def generate_launch_description():\n    while True:\n        pass\n", 2, "limit"),
    "exits": ("import sys\n\n\ndef generate_launch_description():\n    sys.exit(3)\n", 5, "sys.exit(3)"),
    "syntax": ("def generate_launch_description(:\n    return None\n", 1, "SyntaxError"),
    "imports": (
        "import no_such_module_anywhere\n\n\ndef generate_launch_description():\n    pass\n",
        1,
        "No module named 'no_such_module_anywhere'",
    ),
}


@pytest.mark.triggers("PF301")
def test_broken_launch_files_are_reported_and_the_rest_verified(tmp_path):
    for name, (code, _, _) in BROKEN.items():
        result = run_pkgforge(
            "new", f"b_{name}", "--maintainer-email", "t@example.com", "--destination", "src", cwd=tmp_path
        )
        assert result.returncode == 0
        (tmp_path / "src" / f"b_{name}" / "launch" / "display.launch.py").write_text(code)
    jazzy_package(tmp_path)
    status, report = verify(tmp_path, "--launch-timeout", "3")
    assert status == 1
    by_package = {}
    for d in report["diagnostics"]:
        if d["severity"] == "error":
            by_package.setdefault(d["package"], []).append(d)
    for name, (_, line, text) in BROKEN.items():
        (diagnostic,) = by_package[f"b_{name}"]
        if name == "loops" and diagnostic["line"] is None:
            # a machine busy enough that the worker's own stop came after the parent's grace: the
            # parent killed it, knowing no line (test_processes holds the worker's located stop)
            line, text = None, "still running after the 3 s limit"
        assert (diagnostic["code"], diagnostic["path"], diagnostic["line"]) == (
            "PF301",
            f"src/b_{name}/launch/display.launch.py",
            line,
        )  # loops: where the limit hit it
        assert text in diagnostic["message"]
    assert "small_turtle" not in by_package
    assert {p["name"] for p in report["packages"]} == {f"b_{n}" for n in BROKEN} | {"small_turtle"}


# --- the three install trees agree ------------------------------------------------------------


def plain_colcon_build(workspace: Path) -> None:
    """What a user without ROS runs: colcon build, with the ament_cmake wheels on the prefix path."""
    env = dict(os.environ, CMAKE_PREFIX_PATH=sys.prefix, PATH=f"{SCRIPTS}{os.pathsep}{os.environ['PATH']}")
    result = subprocess.run(
        [str(SCRIPTS / "colcon"), "build", "--merge-install", "--cmake-args", "-DBUILD_TESTING=OFF"],
        cwd=workspace,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.slow
def test_three_modes_agree(tmp_path):
    humble = humble_package(tmp_path)
    # a plain colcon build without ROS cannot find urdf (pkgforge build stubs it; colcon cannot)
    edit(humble / "CMakeLists.txt", "find_package(urdf REQUIRED)\n", "")
    broken = jazzy_package(tmp_path, "xml")
    edit(broken / "package.xml", "  <exec_depend>joint_state_publisher_gui</exec_depend>\n", "")
    edit(broken / "CMakeLists.txt", "launch urdf meshes rviz", "launch urdf meshes")
    plain_colcon_build(tmp_path)
    results = {}
    for mode, args in {
        "predicted": (),
        "build": ("--build",),
        "existing": ("--install-base", "install"),
    }.items():
        status, report = verify(tmp_path, *args)
        results[mode] = (status, found(report, "info"))
    assert results["predicted"][0] == 1
    assert {code for code, *_ in results["predicted"][1]} >= {"PF302", "PF305"}
    assert results["build"] == results["predicted"]
    assert results["existing"] == results["predicted"]
    assert (tmp_path / "build" / "pkgforge-verify" / "install").is_dir()


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["predicted", "build", "existing"])
def test_every_scaffold_variant_verifies_clean_in_every_mode(variants_workspace, mode):
    args = {"predicted": (), "build": ("--build",), "existing": ("--install-base", "install")}[mode]
    status, report = verify(variants_workspace, *args)
    assert status == 0, report["diagnostics"]
    assert sorted(p["name"] for p in report["packages"]) == sorted(VARIANTS)
    assert found(report) == []


def test_explain_launch(tmp_path):
    package = jazzy_package(tmp_path)
    edit(package / "CMakeLists.txt", "launch urdf meshes rviz", "launch urdf meshes")
    result = run_pkgforge(
        "verify", "--explain-launch", "src/small_turtle/launch/display.launch.py", cwd=tmp_path
    )
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert "evaluated for: gui:=false; gui:=true" in out
    assert "✗ share/small_turtle/rviz/display.rviz (PathJoinSubstitution)" in out
    assert "✓ share/small_turtle/urdf/small_turtle.urdf (PathJoinSubstitution)" in out
    assert "joint_state_publisher_gui/joint_state_publisher_gui  @ display.launch.py:" in out


def test_explain_launch_follows_verify_s_rules(tmp_path):
    """Issue 30: --explain-launch refuses a launch argument value outside the file's declared
    choices as verify does (exit 2, one line naming them), and a file that does not exist is
    said to not exist (not 'not installed by any package')."""
    package = jazzy_package(tmp_path)
    launch = "src/small_turtle/launch/display.launch.py"
    line = line_of(package / "launch" / "display.launch.py", 'name="gui"')
    for command in (["--explain-launch", launch], []):
        result = run_pkgforge("verify", *command, "--launch-arg", "gui:=maybe", cwd=tmp_path)
        assert (result.returncode, result.stdout) == (2, ""), (command, result.stdout + result.stderr)
        assert result.stderr.splitlines()[-1].startswith(
            "pkgforge: error: --launch-arg gui:=maybe: 'gui' allows only "
        )
        assert f"(declared at {launch}:{line})" in result.stderr, result.stderr
    missing = run_pkgforge(
        "verify", "--explain-launch", "src/small_turtle/launch/nope.launch.py", cwd=tmp_path
    )
    assert missing.returncode == 2
    assert missing.stderr == (
        "pkgforge: error: src/small_turtle/launch/nope.launch.py: does not exist; give a file of a package "
        "of the workspace (or of its install tree)\n"
    )


def test_launch_arg_fixes_a_branch(tmp_path):
    package = jazzy_package(tmp_path)
    edit(package / "package.xml", "  <exec_depend>joint_state_publisher_gui</exec_depend>\n", "")
    status, report = verify(package, "--launch-arg", "gui:=false")
    assert status == 0
    bad = run_pkgforge("verify", package, "--launch-arg", "gui", cwd=tmp_path)
    assert bad.returncode == 2 and "NAME:=VALUE" in bad.stderr


@pytest.mark.parametrize(
    "fmt,marker", [("xml", '<node pkg="robot_state_publisher"'), ("yaml", "- node:")]
)  # the node's first line, as ROS reports it
def test_untyped_model_that_is_not_yaml_stops_robot_state_publisher(tmp_path, fmt, marker):
    """Humble's front ends have no type="str": launch_ros reads the xacro output as YAML, and a
    'NAME: text' comment in the model is a YAML error, so robot_state_publisher never starts."""
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "hb", "--distro", "humble", "--launch-format", fmt)
    model = package / "urdf" / "hb.urdf.xacro"
    edit(model, "<!-- hb, a base", "<!-- hb: a base")
    status, report = verify(package)
    launch = package / "launch" / f"display.launch.{fmt}"
    assert status == 1
    assert found(report) == [
        ("PF301", "launch-load-error", f"launch/display.launch.{fmt}", line_of(launch, marker))
    ]
    message = at_least(report, "error")[0]["message"]
    assert "using yaml rules: yaml.safe_load() failed" in message and "\n" not in message, message
