"""`pkgforge fix`: the seeds fixed and built, each fix in an unusual file style byte for byte,
--diff writes nothing, read-only and changed files are refused cleanly."""

from __future__ import annotations

import difflib
import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import NOBODY, copy_fixture, edit, line_of, new_package, run_command, run_pkgforge

# --- helpers ---------------------------------------------------------------------------------------


def snapshot(root: Path) -> dict[str, bytes]:
    """Every file under root's src/ (build output left out), by relative path."""
    out = {}
    for path in sorted((root / "src").rglob("*")):
        if path.is_file():
            out[path.relative_to(root).as_posix()] = path.read_bytes()
    return out


def tree_diff(before: dict[str, bytes], after: dict[str, bytes]) -> str:
    """A git-style unified diff (no index lines) of two snapshots."""
    out = []
    for name in sorted(set(before) | set(after)):
        old, new = before.get(name, b""), after.get(name, b"")
        if old != new:
            out.append(f"diff {name}\n")
            out.extend(
                difflib.unified_diff(
                    old.decode().splitlines(keepends=True),
                    new.decode().splitlines(keepends=True),
                    f"a/{name}",
                    f"b/{name}",
                )
            )
    return "".join(out)


def scaffold(workspace: Path, name: str, *options: str) -> Path:
    (workspace / "src").mkdir(exist_ok=True)
    return new_package(workspace, name, *options)


def fix(root: Path, *args: str, cwd: Path | None = None):
    result = run_pkgforge("fix", *args, cwd=cwd or root)
    assert "Traceback" not in result.stdout + result.stderr, result.stdout + result.stderr
    return result


def inject_seed_defects(workspace: Path) -> None:
    """Every defect pkgforge fix has a fix for, in the seed packages' own style."""
    rob = workspace / "src" / "rob_description"
    edit(rob / "package.xml", "  <exec_depend>rviz2</exec_depend>\n", "")
    edit(rob / "rviz" / "display.rviz", "        Value: /robot_description", '        Value: ""')
    edit(rob / "rviz" / "display.rviz", "Fixed Frame: base_link", "Fixed Frame: base_footprint")
    edit(rob / "urdf" / "robot_simple_without_track.urdf.xacro", "base_link.STL", "base_link.stl")
    edit(
        rob / "launch" / "display.launch.py",
        "        name='joint_state_publisher',\n",
        "        name='joint_state_publisher',\n        arguments=[robot_description],\n",
    )
    turtle = workspace / "src" / "small_turtle"
    edit(turtle / "CMakeLists.txt", "project(small_turtle)", "project(turtle_description)")
    edit(turtle / "package.xml", "  <exec_depend>robot_state_publisher</exec_depend>\n", "")
    launch = turtle / "launch" / "display.launch.py"
    edit(launch, "from launch_ros.parameter_descriptions import ParameterValue\n", "")
    edit(
        launch,
        'ParameterValue(Command(["xacro ", LaunchConfiguration("model")]),\n'
        "                                               value_type=str)",
        'Command(["xacro ", LaunchConfiguration("model")])',
    )
    edit(
        launch,
        'executable="joint_state_publisher_gui",',
        'executable="joint_state_publisher_gui",\n                       arguments=[LaunchConfiguration("model")],',
    )


SEEDS_DIFF = """\
diff src/rob_description/CMakeLists.txt
--- a/src/rob_description/CMakeLists.txt
+++ b/src/rob_description/CMakeLists.txt
@@ -13,7 +13,7 @@
 # find_package(<dependency> REQUIRED)
 
 install(
-  DIRECTORY launch meshes urdf
+  DIRECTORY launch meshes rviz urdf
   DESTINATION share/${PROJECT_NAME}
 )
 
diff src/rob_description/launch/display.launch.py
--- a/src/rob_description/launch/display.launch.py
+++ b/src/rob_description/launch/display.launch.py
@@ -22,7 +22,6 @@
         package='joint_state_publisher',
         executable='joint_state_publisher',
         name='joint_state_publisher',
-        arguments=[robot_description],
     )
     robot_state_publisher_node = Node(
         package='robot_state_publisher',
diff src/rob_description/package.xml
--- a/src/rob_description/package.xml
+++ b/src/rob_description/package.xml
@@ -14,6 +14,7 @@
   <exec_depend>joint_state_publisher</exec_depend>
   <exec_depend>joint_state_publisher_gui</exec_depend>
   <exec_depend>xacro</exec_depend>
+  <exec_depend>rviz2</exec_depend>
 
   <test_depend>ament_lint_auto</test_depend>
   <test_depend>ament_lint_common</test_depend>
diff src/rob_description/rviz/display.rviz
--- a/src/rob_description/rviz/display.rviz
+++ b/src/rob_description/rviz/display.rviz
@@ -54,7 +54,7 @@
         Durability Policy: Transient Local
         History Policy: Keep Last
         Reliability Policy: Reliable
-        Value: ""
+        Value: /robot_description
       Enabled: true
       Links:
         All Links Enabled: true
@@ -73,7 +73,7 @@
   Enabled: true
   Global Options:
     Background Color: 48; 48; 48
-    Fixed Frame: base_footprint
+    Fixed Frame: base_link
     Frame Rate: 30
   Name: root
   Tools:
diff src/rob_description/urdf/robot_simple_without_track.urdf.xacro
--- a/src/rob_description/urdf/robot_simple_without_track.urdf.xacro
+++ b/src/rob_description/urdf/robot_simple_without_track.urdf.xacro
@@ -4,7 +4,7 @@
     <link name="base_link">
       <visual>
         <geometry>
-          <mesh filename="package://robot_description/meshes/base_link.stl"/>
+          <mesh filename="package://robot_description/meshes/base_link.STL"/>
         </geometry>
       </visual>
     </link>
diff src/small_turtle/CMakeLists.txt
--- a/src/small_turtle/CMakeLists.txt
+++ b/src/small_turtle/CMakeLists.txt
@@ -1,9 +1,9 @@
 cmake_minimum_required(VERSION 3.8)
-project(turtle_description)
+project(small_turtle)
 
 find_package(ament_cmake REQUIRED)
 
-install(DIRECTORY launch worlds urdf meshes models rviz
+install(DIRECTORY launch urdf meshes rviz
   DESTINATION share/${PROJECT_NAME})
 
 ament_package()
diff src/small_turtle/launch/display.launch.py
--- a/src/small_turtle/launch/display.launch.py
+++ b/src/small_turtle/launch/display.launch.py
@@ -4,6 +4,7 @@
 from launch.substitutions import PathJoinSubstitution, LaunchConfiguration, Command
 from launch_ros.actions import Node
 from launch.conditions import IfCondition, UnlessCondition
+from launch_ros.parameter_descriptions import ParameterValue
 
 
 def generate_launch_description():
@@ -19,13 +20,12 @@
     ld.add_action(DeclareLaunchArgument(name="model", default_value=urdf_model_path,
                                         description="Path to robot urdf"))
 
-    robot_description_content = Command(["xacro ", LaunchConfiguration("model")])
+    robot_description_content = ParameterValue(Command(["xacro ", LaunchConfiguration("model")]), value_type=str)
     ld.add_action(Node(package="robot_state_publisher", executable="robot_state_publisher",
                        parameters=[{"robot_description": robot_description_content}]))
     ld.add_action(Node(package="joint_state_publisher", executable="joint_state_publisher",
                        condition=UnlessCondition(LaunchConfiguration("gui"))))
     ld.add_action(Node(package="joint_state_publisher_gui", executable="joint_state_publisher_gui",
-                       arguments=[LaunchConfiguration("model")],
                        condition=IfCondition(LaunchConfiguration("gui"))))
     ld.add_action(Node(package="rviz2", executable="rviz2",
                        arguments=["-d", LaunchConfiguration("rvizconfig")], output="screen"))
diff src/small_turtle/package.xml
--- a/src/small_turtle/package.xml
+++ b/src/small_turtle/package.xml
@@ -15,6 +15,7 @@
   <exec_depend>joint_state_publisher_gui</exec_depend>
   <exec_depend>xacro</exec_depend>
   <exec_depend>launch_ros</exec_depend>
+  <exec_depend>robot_state_publisher</exec_depend>
 
   <export>
     <build_type>ament_cmake</build_type>
"""


# --- the seeds ----------------------------------------------------------------------------------------


@pytest.fixture
def seeds(tmp_path) -> Path:
    copy_fixture("seed000/rob_description", tmp_path)
    copy_fixture("seed001/small_turtle", tmp_path)
    inject_seed_defects(tmp_path)
    return tmp_path


def test_seeds_fixed_then_build_verifies_without_errors(seeds):
    before = snapshot(seeds)
    result = fix(seeds, "--unsafe-fixes")
    assert result.returncode == 0, result.stdout + result.stderr
    after = snapshot(seeds)
    assert tree_diff(before, after) == SEEDS_DIFF
    fixed = sorted(
        line.split(": ")[1].split()[0] for line in result.stdout.splitlines() if line.startswith("fixed src/")
    )
    # PF305: rviz2 and robot_state_publisher (rviz2 brings RViz's own display packages)
    assert fixed == [
        "PF103",
        "PF201",
        "PF201",
        "PF302",
        "PF305",
        "PF305",
        "PF306",
        "PF306",
        "PF307",
        "PF403",
        "PF502",
        "PF503",
    ]
    remaining = result.stdout.split("remaining, by code:\n")[1].split("\nsrc/")[0].splitlines()
    assert remaining and all(line.startswith("  PF") and "[error]" not in line for line in remaining), (
        remaining
    )
    assert "  PF104 folder-name-mismatch" in "\n".join(
        remaining
    )  # no automatic fix: a rename touches everything

    # idempotent: a second run finds nothing to fix and changes no byte
    again = fix(seeds, "--unsafe-fixes")
    assert again.returncode == 0 and "fixed" not in again.stdout
    assert snapshot(seeds) == after

    # a real colcon build of the fixed packages: no error, every launch file resolved
    built = run_pkgforge("verify", "--build", "--format", "json", cwd=seeds)
    report = json.loads(built.stdout)
    assert built.returncode == 0, built.stdout + built.stderr
    assert [d for d in report["diagnostics"] if d["severity"] == "error"] == []
    assert not {"PF301", "PF308", "PF311"} & {
        d["code"] for d in report["diagnostics"]
    }  # every launch file loaded
    install = seeds / "build" / "pkgforge-verify" / "install" / "share"
    assert (install / "robot_description" / "rviz" / "display.rviz").is_file()
    assert (install / "small_turtle" / "launch" / "display.launch.py").is_file()


def test_diff_writes_nothing(seeds):
    def digest() -> str:
        return hashlib.sha256(
            json.dumps({k: v.hex() for k, v in snapshot(seeds).items()}).encode()
        ).hexdigest()

    before = digest()
    result = fix(seeds, "--diff", "--unsafe-fixes")
    assert digest() == before
    assert not list(seeds.rglob("*.pkgforge-fix"))
    assert result.returncode == 1  # like verify: the errors are still there
    assert result.stdout.startswith(
        "--- a/src/rob_description/CMakeLists.txt\n+++ b/src/rob_description/CMakeLists.txt\n"
    )
    assert "-  DIRECTORY launch meshes urdf\n+  DIRECTORY launch meshes rviz urdf\n" in result.stdout
    assert (
        "-install(DIRECTORY launch worlds urdf meshes models rviz\n+install(DIRECTORY launch urdf meshes rviz\n"
        in result.stdout
    )
    # beside the diff, one line of counts (ruff's --diff): the findings are verify's (issue 30)
    assert result.stderr.startswith("would fix ") and result.stderr.count("\n") == 1, result.stderr
    # every pass ran on a copy: applied, the diff is exactly what `pkgforge fix` writes
    if shutil.which("git") is None:
        pytest.skip("git is not installed: the diff's application is not checked")
    before = snapshot(seeds)
    applied = subprocess.run(
        ["git", "apply", "-"], input=result.stdout, text=True, cwd=seeds, capture_output=True
    )
    assert applied.returncode == 0, applied.stderr
    assert tree_diff(before, snapshot(seeds)) == SEEDS_DIFF


def test_unsafe_fixes_wait_for_the_flag_and_verify_fix_is_fix(tmp_path):
    package = copy_fixture("seed001/small_turtle", tmp_path)
    cmake = package / "CMakeLists.txt"
    before = cmake.read_bytes()
    result = fix(tmp_path)
    assert result.returncode == 1
    assert cmake.read_bytes() == before
    assert (
        "2 unsafe fix(es) not applied (--unsafe-fixes applies them): PF201 install-missing-directory ×2"
        in result.stdout
    )
    # verify --fix, given a file as the pre-commit hook does
    result = run_pkgforge("verify", "--fix", "--unsafe-fixes", "src/small_turtle", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "install(DIRECTORY launch urdf meshes rviz\n" in cmake.read_text()
    assert run_pkgforge("verify", "--fix", "--build", cwd=tmp_path).returncode == 2


def test_fix_given_files_fixes_their_packages(tmp_path):
    package = copy_fixture("seed001/small_turtle", tmp_path)
    edit(package / "package.xml", "  <exec_depend>xacro</exec_depend>\n", "")
    result = fix(
        tmp_path,
        "src/small_turtle/package.xml",
        "src/small_turtle/urdf/small_turtle.urdf",
        "--select",
        "missing-exec-depend",
    )
    assert result.returncode == 0, result.stdout
    assert "  <exec_depend>xacro</exec_depend>\n" in (package / "package.xml").read_text()
    assert "worlds" in (package / "CMakeLists.txt").read_text()  # not selected: untouched


# --- each fix in an unusual but valid style: every other byte kept --------------------------------------

PACKAGE_XML_CRLF_TABS = (
    '<?xml version="1.0"?>\r\n'
    '<package format="3">\r\n'
    "\t<name>rob</name>\r\n"
    "\t<version>0.0.0</version>\r\n"
    "\t<description>Tabs, CRLF, comments between tags, depend among exec_depend</description>\r\n"
    '\t<maintainer email="test@example.com">a</maintainer>\r\n'
    "\t<license>Apache-2.0</license>\r\n"
    "\t<buildtool_depend>ament_cmake</buildtool_depend>\r\n"
    "\t<exec_depend>joint_state_publisher</exec_depend>\r\n"
    "\t<!-- the GUI, when gui:=true -->\r\n"
    "\t<exec_depend>joint_state_publisher_gui</exec_depend>\r\n"
    "\t<depend>launch</depend>\r\n"
    "\t<exec_depend>launch_ros</exec_depend>\r\n"
    "\t<exec_depend>robot_state_publisher</exec_depend>\r\n"
    "\t<exec_depend>rviz2</exec_depend> <!-- RViz itself -->\r\n"
    "\t<exec_depend>rviz_default_plugins</exec_depend>\r\n"
    "\t<exec_depend>xacro</exec_depend>\r\n"
    "\t<export>\r\n"
    "\t\t<build_type>ament_cmake</build_type>\r\n"
    "\t</export>\r\n"
    "</package>\r\n"
)

CMAKE_MULTILINE = (
    "cmake_minimum_required(VERSION 3.10)\n"
    'project(\t"rob"\tNONE)\n'
    "\n"
    "find_package(ament_cmake REQUIRED)\n"
    "\n"
    "install(\n"
    "\tDIRECTORY\n"
    "\t\tlaunch\n"
    "\t\tmeshes  # STL files\n"
    "\t\trviz\n"
    "\t\turdf\n"
    "\tDESTINATION share/${PROJECT_NAME}\n"
    ")\n"
    "\n"
    "ament_package()\n"
)


@pytest.fixture
def styled(tmp_path) -> Path:
    """A scaffolded package rewritten in unusual styles (verifies clean before any defect)."""
    package = scaffold(tmp_path, "rob")
    (package / "package.xml").write_bytes(PACKAGE_XML_CRLF_TABS.encode())
    (package / "CMakeLists.txt").write_bytes(CMAKE_MULTILINE.encode())
    rviz = package / "rviz" / "display.rviz"
    rviz.write_bytes(rviz.read_text().replace("\n", "\r\n").encode())
    return package


def test_styles_clean_before_the_defects(styled):
    result = run_pkgforge("verify", cwd=styled)
    assert result.returncode == 0 and result.stdout.startswith(
        "0 errors, 0 warnings, 0 infos in 1 package"
    ), result.stdout


def test_every_fix_keeps_every_other_byte(styled):
    package = styled
    original = {p: p.read_bytes() for p in package.rglob("*") if p.is_file()}
    manifest, cmake = package / "package.xml", package / "CMakeLists.txt"
    rviz, model = package / "rviz" / "display.rviz", package / "urdf" / "rob.urdf.xacro"
    launch = package / "launch" / "display.launch.py"
    # the defects
    manifest.write_bytes(
        PACKAGE_XML_CRLF_TABS.replace("\t<exec_depend>robot_state_publisher</exec_depend>\r\n", "")
        .replace("\t<exec_depend>xacro</exec_depend>\r\n", "")
        .encode()
    )
    cmake.write_bytes(
        CMAKE_MULTILINE.replace('"rob"', '"robot"')
        .replace("\t\trviz\n", "")
        .replace("\t\turdf\n", "\t\turdf\n\t\tworlds\n")
        .encode()
    )
    rviz.write_bytes(
        original[rviz]
        .replace(b"Description Source: Topic", b"Description Source: File")
        .replace(b"Value: /robot_description", b"Value: ''")
        .replace(b"Fixed Frame: base_link", b"Fixed Frame: chassis")
    )
    (package / "meshes" / "arm.stl").rename(package / "meshes" / "Arm.STL")
    launch_text = original[launch].decode()
    typed = (
        "    robot_description = ParameterValue(\n        Command(['xacro ', LaunchConfiguration('model')]),"
        " value_type=str\n    )\n"
    )
    assert typed in launch_text
    launch.write_text(
        launch_text.replace("from launch_ros.parameter_descriptions import ParameterValue\n", "")
        .replace(
            typed, "    robot_description = Command(['xacro ', LaunchConfiguration('model')])  # the model\n"
        )
        .replace(
            "            executable='joint_state_publisher',\n",
            "            executable='joint_state_publisher', arguments=[LaunchConfiguration('model')],\n",
        )
    )

    result = fix(package, "--unsafe-fixes")
    assert result.returncode == 0, result.stdout + result.stderr

    assert manifest.read_bytes() == PACKAGE_XML_CRLF_TABS.encode()
    assert cmake.read_bytes() == CMAKE_MULTILINE.encode()
    assert rviz.read_bytes() == original[rviz]
    assert model.read_bytes() == original[model].replace(b"meshes/arm.stl", b"meshes/Arm.STL")
    assert launch.read_text() == (
        launch_text.replace("from launch_ros.parameter_descriptions import ParameterValue\n", "")
        .replace(
            "from launch_ros.substitutions import FindPackageShare\n",
            "from launch_ros.substitutions import FindPackageShare\n"
            "from launch_ros.parameter_descriptions import ParameterValue\n",
        )
        .replace(
            typed,
            "    robot_description = ParameterValue(Command(['xacro ', LaunchConfiguration('model')]), "
            "value_type=str)  # the model\n",
        )
    )
    changed = {p for p in original if p.exists() and p.read_bytes() != original[p]}
    assert changed == {model, launch}  # the rest is back to its exact bytes


def test_new_install_rule_after_the_last_one(tmp_path):
    package = scaffold(tmp_path, "rob")
    cmake = package / "CMakeLists.txt"
    text = (
        cmake.read_text()
        .replace("  DIRECTORY launch meshes rviz urdf\n", "  DIRECTORY launch meshes urdf\n")
        .replace(
            "DESTINATION share/${PROJECT_NAME}\n)",
            'DESTINATION share/${PROJECT_NAME}\n  PATTERN "*.bak" EXCLUDE\n)',
        )
    )
    cmake.write_text(text)
    result = fix(package, "--select", "PF2,PF3")
    assert result.returncode == 0, result.stdout
    assert cmake.read_text() == text.replace(
        '  PATTERN "*.bak" EXCLUDE\n)\n',
        '  PATTERN "*.bak" EXCLUDE\n)\ninstall(DIRECTORY rviz DESTINATION share/${PROJECT_NAME})\n',
    )


def test_format_1_manifest_gets_run_depend(tmp_path):
    package = scaffold(tmp_path, "rob")
    manifest = package / "package.xml"
    text = (
        manifest.read_text()
        .replace('format="3"', 'format="1"')
        .replace("exec_depend>", "run_depend>")
        .replace("package_format3.xsd", "package_format1.xsd")
    )
    manifest.write_text(text.replace("  <run_depend>xacro</run_depend>\n", ""))
    result = fix(package, "--select", "missing-exec-depend")
    assert result.returncode == 0, result.stdout
    assert manifest.read_text() == text


def test_setup_py_with_glob(tmp_path):
    package = scaffold(tmp_path, "pyr", "--build-type", "ament_python")
    setup = package / "setup.py"
    text = (
        "import os\n"
        "from glob import glob\n\n"
        "from setuptools import setup\n\n"
        "package_name = 'pyr'\n\n"
        "setup(\n"
        "    name=package_name,\n"
        "    version='0.0.0',\n"
        "    packages=[],\n"
        "    data_files=[\n"
        "        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),\n"
        "        ('share/' + package_name, ['package.xml']),\n"
        "        (os.path.join('share', package_name, 'launch'), glob('launch/*')),\n"
        "        (os.path.join('share', package_name, 'meshes'), glob('meshes/*')),  # STL\n"
        "        (os.path.join('share', package_name, 'urdf'), glob('urdf/*')),\n"
        "    ],\n"
        "    install_requires=['setuptools'],\n"
        "    zip_safe=True,\n"
        "    maintainer='a',\n"
        "    maintainer_email='test@example.com',\n"
        "    description='d',\n"
        "    license='Apache-2.0',\n"
        ")\n"
    )
    setup.write_text(text)
    result = fix(package)
    assert result.returncode == 0, result.stdout
    assert setup.read_text() == text.replace(
        "        (os.path.join('share', package_name, 'urdf'), glob('urdf/*')),\n",
        "        (os.path.join('share', package_name, 'rviz'), glob('rviz/*')),\n"
        "        (os.path.join('share', package_name, 'urdf'), glob('urdf/*')),\n",
    )


def test_xml_launch_jsp_args_removed(tmp_path):
    package = scaffold(tmp_path, "rob", "--launch-format", "xml")
    launch = package / "launch" / "display.launch.xml"
    text = launch.read_text()
    start = text.index('<node pkg="joint_state_publisher"')
    end = text.index(">", start)
    tag = text[start:end]
    launch.write_text(
        text[:start]
        + tag.replace('pkg="joint_state_publisher"', 'pkg="joint_state_publisher" args="$(var model)"', 1)
        + text[end:]
    )
    result = fix(package)
    assert result.returncode == 0, result.stdout
    assert launch.read_text() == text


# --- refusing to write ----------------------------------------------------------------------------------


def test_read_only_file_is_refused_cleanly(tmp_path):
    package = copy_fixture("seed001/small_turtle", tmp_path)
    manifest = package / "package.xml"
    edit(manifest, "  <exec_depend>xacro</exec_depend>\n", "")
    before = manifest.read_bytes()
    manifest.chmod(0o444)
    result = fix(tmp_path, "--select", "missing-exec-depend")
    assert result.returncode == 1
    assert "pkgforge: error: src/small_turtle/package.xml not written: it is read-only" in result.stdout
    assert manifest.read_bytes() == before
    assert oct(manifest.stat().st_mode & 0o777) == "0o444"
    assert sorted(p.name for p in package.iterdir() if p.name.startswith(".")) == []


@pytest.fixture
def request_cleanup():
    folders: list[Path] = []
    yield folders
    for folder in folders:
        shutil.rmtree(folder, ignore_errors=True)


def test_unwritable_folder_as_an_unprivileged_user(request_cleanup):
    """As nobody, on a copy nobody can read but not write: a clear message, nothing half-written."""
    if os.geteuid() != 0 or shutil.which("setpriv") is None:
        pytest.skip("needs root and setpriv to run pkgforge as an unprivileged user")
    import tempfile

    top = Path(tempfile.mkdtemp(prefix="pkgforge-fix-nobody-"))  # pytest's own tmp is private to root
    request_cleanup.append(top)
    workspace = top / "ws"
    package = copy_fixture("seed001/small_turtle", workspace)
    # a check that needs no launch worker: the unprivileged user may not run this interpreter's workers
    manifest = package / "CMakeLists.txt"
    edit(manifest, "project(small_turtle)", "project(turtle_description)")
    before = manifest.read_bytes()
    for path in [top, *top.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    home = top / "home"
    home.mkdir()
    os.chown(home, 65534, 65534)
    # not measured by scripts/coverage: the unprivileged user cannot write its data file (it would
    # say so on stderr at exit, with a traceback)
    env = {k: v for k, v in os.environ.items() if not k.startswith("COVERAGE_")}
    probe = subprocess.run(
        [
            *NOBODY,
            sys.executable,
            "-c",
            "import pkgforge, pathlib, sys; pathlib.Path(sys.argv[1]).read_bytes()",
            str(manifest),
        ],
        capture_output=True,
        text=True,
        env=env,
    )
    if probe.returncode != 0:
        pytest.skip(f"the unprivileged user cannot read the test files or pkgforge: {probe.stderr[-200:]}")
    env = dict(env, HOME=str(home), XDG_CACHE_HOME=str(home / ".cache"))
    result = run_command(
        [*NOBODY, sys.executable, "-m", "pkgforge", "fix", "--select", "project-name-mismatch"],
        cwd=workspace,
        env=env,
        timeout=600,
    )
    assert "Traceback" not in result.stdout + result.stderr, result.stdout + result.stderr
    assert result.returncode == 1, result.stdout + result.stderr
    assert "src/small_turtle/CMakeLists.txt not written: it is read-only" in result.stdout
    assert manifest.read_bytes() == before
    assert [p.name for p in package.iterdir() if p.name.startswith(".")] == []


def test_file_changed_since_read_is_skipped(tmp_path):
    """The engine itself: a file that changes between reading and writing is left as it now is."""
    from pkgforge.fix.edits import Edit, SourceText, apply, write_atomically

    path = tmp_path / "package.xml"
    path.write_text("<package>\n</package>\n")
    source = SourceText(path)
    new = apply(source.text, [Edit(10, 10, "  <name>x</name>\n")])
    path.write_text("<package>\n  <!-- edited meanwhile -->\n</package>\n")
    outcome = write_atomically(source, new)
    assert (
        not outcome.written and outcome.problem == "it changed since pkgforge read it; run pkgforge fix again"
    )
    assert path.read_text() == "<package>\n  <!-- edited meanwhile -->\n</package>\n"
    assert [p.name for p in tmp_path.iterdir()] == ["package.xml"]


def test_unparsable_result_is_never_written():
    from pathlib import Path as P

    from pkgforge.fix.edits import parse_problem

    assert parse_problem(P("package.xml"), "<package><name>x</package>") is not None
    assert parse_problem(P("CMakeLists.txt"), "install(DIRECTORY a\n") is not None
    assert parse_problem(P("a.launch.py"), "def f(:\n") is not None
    assert parse_problem(P("a.rviz"), "a: [\n") is not None
    assert parse_problem(P("package.xml"), "<package/>") is None


def test_find_package_undeclared_plugs_in(tmp_path):
    """The dependency fixer is generic: a find_package() finding (issue 12's check) declares a build_depend."""
    from pkgforge.checks.registry import DEFAULT_FIXES
    from pkgforge.diagnostics import Diagnostic, Severity
    from pkgforge.fix.edits import FileSet, apply
    from pkgforge.fix.registry import FixContext, all_fixers

    assert DEFAULT_FIXES["find-package-undeclared"] == "safe"
    package = copy_fixture("seed001/small_turtle", tmp_path)
    cmake = package / "CMakeLists.txt"
    cmake.write_text(
        cmake.read_text().replace(
            "find_package(ament_cmake REQUIRED)\n",
            "find_package(ament_cmake REQUIRED)\nfind_package(urdf REQUIRED)\n",
        )
    )
    diagnostic = Diagnostic(
        "PF109",
        "find-package-undeclared",
        Severity.ERROR,
        "small_turtle",
        cmake,
        5,
        1,
        "find_package(urdf) but package.xml does not declare urdf for the build",
        "",
    )
    files = FileSet()
    fix = all_fixers()["find-package-undeclared"](diagnostic, FixContext(files))
    manifest = package / "package.xml"
    text = apply(files.get(manifest).text, fix.edits[manifest])
    assert text == manifest.read_text().replace(
        "  <buildtool_depend>ament_cmake</buildtool_depend>\n",
        "  <buildtool_depend>ament_cmake</buildtool_depend>\n  <build_depend>urdf</build_depend>\n",
    )


def test_find_package_for_tests_gets_a_test_depend(tmp_path):
    """A find_package() inside if(BUILD_TESTING) (panther's ament_cmake_gtest) is a test
    dependency: verify's hint and fix's edit say <test_depend>; its else() branch is not."""
    package = copy_fixture("seed001/small_turtle", tmp_path / "src")
    cmake = package / "CMakeLists.txt"
    cmake.write_text(
        cmake.read_text().replace(
            "ament_package()",
            "if(BUILD_TESTING)\n  find_package(ament_cmake_gtest REQUIRED)\nelse()\n"
            "  find_package(urdf REQUIRED)\nendif()\nament_package()",
        )
    )
    report = json.loads(run_pkgforge("verify", "--format", "json", "--no-cache", cwd=tmp_path).stdout)
    found = {
        d["message"].split("(")[1].split(")")[0]: (d["line"], d["hint"])
        for d in report["diagnostics"]
        if d["name"] == "find-package-undeclared"
    }
    text = cmake.read_text().splitlines()
    assert found["ament_cmake_gtest"][0] == text.index("  find_package(ament_cmake_gtest REQUIRED)") + 1
    assert found["ament_cmake_gtest"][1].startswith("add <test_depend>ament_cmake_gtest</test_depend>")
    assert found["urdf"][1].startswith("add <build_depend>urdf</build_depend>")
    fix(tmp_path)
    manifest = (package / "package.xml").read_text()
    assert "<test_depend>ament_cmake_gtest</test_depend>" in manifest
    assert "<build_depend>urdf</build_depend>" in manifest


def test_checks_list_shows_the_fix_kind():
    result = run_pkgforge("checks", cwd=Path(__file__).parent)
    assert any(
        line.startswith("PF201  install-missing-directory") and " unsafe " in line
        for line in result.stdout.splitlines()
    )
    assert any(
        line.startswith("PF305  missing-exec-depend") and " safe " in line
        for line in result.stdout.splitlines()
    )
    assert any(
        line.startswith("PF104  folder-name-mismatch") and " - " in line
        for line in result.stdout.splitlines()
    )


def test_pre_commit_fix_hook_beside_verify():
    import re

    import yaml

    hooks = {
        h["id"]: h for h in yaml.safe_load((Path(__file__).parents[1] / ".pre-commit-hooks.yaml").read_text())
    }
    assert set(hooks) == {"pkgforge-verify", "pkgforge-fix"}
    hook = hooks["pkgforge-fix"]
    assert hook["entry"] == "pkgforge fix" and hook["pass_filenames"] and hook["language"] == "python"
    assert hook["files"] == hooks["pkgforge-verify"]["files"]
    assert re.search(hook["files"], "src/rob/package.xml")


def _fixed(name: str, path: Path, line: int, data: dict | None = None) -> str:
    """The text of path after the fixer of check `name` ran for a finding at `line` (in-process)."""
    from pkgforge.diagnostics import Diagnostic, Severity
    from pkgforge.fix.edits import FileSet, apply
    from pkgforge.fix.registry import FixContext, all_fixers

    diagnostic = Diagnostic("PF000", name, Severity.ERROR, "p", path, line, None, "m", "h", fix=data)
    files = FileSet()
    fix = all_fixers()[name](diagnostic, FixContext(files))
    return apply(files.get(path).text, fix.edits[path])


def test_rviz_description_added_where_the_display_has_none(tmp_path):
    rviz = tmp_path / "display.rviz"
    rviz.write_text(
        "Visualization Manager:\n  Displays:\n    - Alpha: 1\n      Class: rviz_default_plugins/RobotModel\n"
        "      Enabled: true\n      Name: RobotModel\n"
    )
    assert _fixed("rviz-no-description", rviz, 4, {"display_line": 4}) == (
        "Visualization Manager:\n  Displays:\n    - Alpha: 1\n      Class: rviz_default_plugins/RobotModel\n"
        "      Description Source: Topic\n      Description Topic:\n        Depth: 5\n"
        "        Durability Policy: Transient Local\n        History Policy: Keep Last\n"
        "        Reliability Policy: Reliable\n        Value: /robot_description\n"
        "      Enabled: true\n      Name: RobotModel\n"
    )


def test_robot_description_command_inline_in_the_node(tmp_path):
    launch = tmp_path / "x.launch.py"
    launch.write_text(
        '"""Doc."""\nfrom launch_ros.actions import Node\n\n\ndef generate_launch_description():\n'
        "    return LaunchDescription([Node(\n        package='robot_state_publisher',\n"
        "        parameters=[{'robot_description': Command(['xacro ', 'm'])}],\n    )])\n"
    )
    assert _fixed("robot-description-not-string", launch, 6) == (
        '"""Doc."""\nfrom launch_ros.actions import Node\n'
        "from launch_ros.parameter_descriptions import ParameterValue\n\n\ndef generate_launch_description():\n"
        "    return LaunchDescription([Node(\n        package='robot_state_publisher',\n"
        "        parameters=[{'robot_description': ParameterValue(Command(['xacro ', 'm']), value_type=str)}],\n"
        "    )])\n"
    )


def test_a_symlinked_file_stays_a_symlink(tmp_path):
    from pkgforge.fix.edits import Edit, SourceText, apply, write_atomically

    target = tmp_path / "shared.rviz"
    target.write_text("Fixed Frame: map\n")
    target.chmod(0o640)
    link = tmp_path / "display.rviz"
    link.symlink_to(target.name)
    source = SourceText(link)
    assert write_atomically(source, apply(source.text, [Edit(13, 16, "base_link")])).written
    assert link.is_symlink() and target.read_text() == "Fixed Frame: base_link\n"
    assert oct(target.stat().st_mode & 0o777) == "0o640"


def test_a_fix_that_would_break_the_file_writes_nothing(tmp_path, monkeypatch):
    """A fixer whose edit leaves package.xml unparsable (a stand-in fixer, the rest real): nothing written."""
    import dataclasses

    from pkgforge.checks.registry import REGISTRY, all_checks
    from pkgforge.fix import registry
    from pkgforge.fix.edits import Edit
    from pkgforge.fix.run import FixOptions, run_fix
    from pkgforge.verify.config import Selection
    from pkgforge.verify.pipeline import VerifyOptions

    package = copy_fixture("seed001/small_turtle", tmp_path)
    package = package.rename(package.with_name("turtle"))
    manifest = package / "package.xml"
    before = manifest.read_bytes()
    all_checks()
    monkeypatch.setitem(REGISTRY, "PF104", dataclasses.replace(REGISTRY["PF104"], fix="safe"))

    def breaking(diagnostic, context):
        source = context.files.get(manifest)
        start = source.text.index("</package>")
        fix = registry.Fix("drops </package>")
        fix.add(manifest, Edit(start, start + len("</package>"), ""))
        return fix

    monkeypatch.setitem(registry.all_fixers(), "folder-name-mismatch", breaking)
    run = run_fix(package, FixOptions(VerifyOptions(Selection(["folder-name-mismatch"], []))))
    assert manifest.read_bytes() == before
    assert run.fixed == [] and run.files_written == set()
    ((diagnostic, why),) = run.not_fixed
    assert diagnostic.name == "folder-name-mismatch" and why.startswith(
        "the fix would leave the file unparsable"
    )


# --- issue 30: fixes that respect the target distro and the hint ----------------------------------

GAZEBO_CLASSIC_SPAWN = """\
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        Node(package='gazebo_ros', executable='spawn_entity.py', arguments=['-entity', 'rob']),
    ])
"""


@pytest.mark.parametrize("target", ["new --distro jazzy", "no target"])
def test_fix_never_declares_what_the_target_distro_has_not(tmp_path, target):
    """Issue 30: gazebo_ros is released for humble only. A package `new --distro jazzy` made gets
    package-not-in-distro naming ros_gz_sim, and `fix` declares nothing; with no target distro
    stated, missing-exec-depend stays, its hint names the successor, and `fix` declares nothing."""
    package = scaffold(tmp_path, "sim_bot", *(["--distro", "jazzy"] if target != "no target" else []))
    launch = package / "launch" / "sim.launch.py"
    launch.write_text(GAZEBO_CLASSIC_SPAWN)
    before = snapshot(tmp_path)
    result = fix(tmp_path, "--unsafe-fixes")
    assert snapshot(tmp_path) == before, result.stdout
    line = line_of(launch, "Node(package='gazebo_ros'")
    if target == "no target":
        assert (
            f"src/sim_bot/launch/sim.launch.py:{line}: PF305 [error] Node package 'gazebo_ros' is used at "
            "run time but package.xml does not declare it (missing-exec-depend)"
        ) in result.stdout.splitlines()
        assert (
            "    hint: use ros_gz_sim instead (Gazebo Classic (gazebo_ros) is released for Humble only; use "
            "Gazebo with ros_gz_sim); or, for a package that targets humble only, add "
            '<exec_depend>gazebo_ros</exec_depend> to package.xml and say so in pkgforge.toml ([verify] distro = "humble")'
        ) in result.stdout.splitlines()
    else:
        assert (
            f"src/sim_bot/launch/sim.launch.py:{line}: PF108 [error] Node package 'gazebo_ros': 'gazebo_ros' "
            "is not released for jazzy (released for humble) (package-not-in-distro)"
        ) in result.stdout.splitlines()
        assert (
            "    hint: use ros_gz_sim instead: Gazebo Classic (gazebo_ros) is released for Humble only; use Gazebo with ros_gz_sim"
            in result.stdout.splitlines()
        )
    assert "not fixed" not in result.stdout
    assert "PF305" not in result.stdout or target == "no target"


def test_a_viewer_used_only_with_a_setting_gets_an_unsafe_fix(tmp_path):
    """Issue 30: joint_state_publisher_gui started only under gui:=true (default false) is a
    warning whose hint names the dependency: `fix` leaves it (an unsafe fix, counted as such),
    `fix --unsafe-fixes` declares it, never 'the finding does not say which dependency'."""
    package = scaffold(tmp_path, "quiet_bot")
    edit(package / "launch" / "display.launch.py", "default_value='true',", "default_value='false',")
    edit(package / "package.xml", "  <exec_depend>joint_state_publisher_gui</exec_depend>\n", "")
    before = snapshot(tmp_path)
    safe = fix(tmp_path)
    assert snapshot(tmp_path) == before
    assert (
        "1 unsafe fix(es) not applied (--unsafe-fixes applies them): PF305 missing-exec-depend ×1"
        in safe.stdout
    )
    assert "does not say which dependency" not in safe.stdout
    gui_node = line_of(package / "launch" / "display.launch.py", "package='joint_state_publisher_gui'") - 1
    unsafe = fix(tmp_path, "--unsafe-fixes")
    assert unsafe.returncode == 0, unsafe.stdout + unsafe.stderr
    assert (
        f"fixed src/quiet_bot/launch/display.launch.py:{gui_node}: PF305 missing-exec-depend: declared "
        "<exec_depend>joint_state_publisher_gui</exec_depend> in package.xml"
    ) in unsafe.stdout.splitlines()
    assert "<exec_depend>joint_state_publisher_gui</exec_depend>" in (package / "package.xml").read_text()
    assert "PF305" not in run_pkgforge("verify", cwd=tmp_path).stdout


def test_a_repeated_dependency_is_deleted(tmp_path):
    """Issue 30: duplicate-dependency has a safe fix: the repeat's line goes (a repeat sharing a
    line with another tag loses only its element), and <depend> beside <exec_depend> of the same
    package (catkin_pkg rejects it) loses the <exec_depend>; a repeat under the same condition
    (realsense2_camera's sensor_msgs_py) goes too, one under another condition stays; every other
    byte stays."""
    package = scaffold(tmp_path, "twice_bot")
    manifest = package / "package.xml"
    edit(
        manifest,
        "  <exec_depend>xacro</exec_depend>\n",
        "  <exec_depend>xacro</exec_depend>\n  <exec_depend>xacro</exec_depend>\n"
        '  <test_depend condition="$ROS_DISTRO != foxy">launch_testing</test_depend>\n'
        '  <test_depend condition="$ROS_DISTRO != foxy">launch_testing</test_depend>\n'
        '  <test_depend condition="$ROS_VERSION == 2">ament_cmake_pytest</test_depend>\n'
        '  <test_depend condition="$ROS_VERSION == 1">ament_cmake_pytest</test_depend>\n',
    )
    edit(
        manifest,
        "  <exec_depend>rviz2</exec_depend>\n",
        "  <depend>rviz2</depend> <exec_depend>rviz2</exec_depend>\n",
    )
    expected = (
        manifest.read_text()
        .replace(
            "  <exec_depend>xacro</exec_depend>\n  <exec_depend>xacro</exec_depend>\n",
            "  <exec_depend>xacro</exec_depend>\n",
        )
        .replace(
            '  <test_depend condition="$ROS_DISTRO != foxy">launch_testing</test_depend>\n' * 2,
            '  <test_depend condition="$ROS_DISTRO != foxy">launch_testing</test_depend>\n',
        )
        .replace("<depend>rviz2</depend> <exec_depend>rviz2</exec_depend>", "<depend>rviz2</depend>")
    )
    result = fix(tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert manifest.read_text() == expected
    assert result.stdout.count("PF106 duplicate-dependency: deleted the repeated") == 3, result.stdout
    assert "PF106" not in run_pkgforge("verify", cwd=tmp_path).stdout  # (the two conditions: no repeat)


@pytest.mark.parametrize("configured", ["pyproject.toml", ".pre-commit-config.yaml"])
def test_a_launch_file_fix_keeps_the_repository_formatter_stable(tmp_path, configured):
    """Issue 30: the repository formats its Python with ruff format (pyproject.toml's [tool.ruff], or
    a ruff-format pre-commit hook) and the launch file is stable under it; wrapping its Command in
    ParameterValue(..., value_type=str) makes a line too long, so the fixed file is formatted as
    ruff writes it: `ruff format --check` still passes after `pkgforge fix` and after its --diff."""
    from conftest import SCRIPTS

    package = scaffold(tmp_path, "fmt_bot")
    if configured == "pyproject.toml":
        (tmp_path / "pyproject.toml").write_text("[tool.ruff]\nline-length = 88\n")
    else:
        (tmp_path / ".pre-commit-config.yaml").write_text(
            "repos:\n  - repo: https://github.com/astral-sh/ruff-pre-commit\n    rev: v0.6.0\n"
            "    hooks:\n      - id: ruff\n      - id: ruff-format\n"
        )
    launch = package / "launch" / "display.launch.py"
    edit(
        launch,
        "    robot_description = ParameterValue(\n        Command(['xacro ', LaunchConfiguration('model')]), value_type=str\n    )\n",
        "    robot_description = Command(['xacro ', LaunchConfiguration('model')])\n",
    )
    edit(launch, "from launch_ros.parameter_descriptions import ParameterValue\n", "")
    assert run_command([SCRIPTS / "ruff", "format", launch], cwd=tmp_path).returncode == 0

    def stable() -> bool:
        return run_command([SCRIPTS / "ruff", "format", "--check", launch], cwd=tmp_path).returncode == 0

    assert stable()
    diff = fix(tmp_path, "--diff")
    assert "+    robot_description = ParameterValue(\n" in diff.stdout, diff.stdout + diff.stderr
    result = fix(tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'Command(["xacro ", LaunchConfiguration("model")]), value_type=str\n' in launch.read_text()
    assert stable(), launch.read_text()
