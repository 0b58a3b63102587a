"""Each message and hint says the real cause and the real fix (issue 11 item 7): every case is a
defect a user met, reproduced through the real `pkgforge` command."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import (
    MAINTAINER,
    NOBODY,
    edit,
    hand_made_install,
    line_of,
    run_command,
    run_pkgforge,
    verify_report,
)


def only(report: dict, code: str) -> dict:
    found = [d for d in report["diagnostics"] if d["code"] == code]
    assert len(found) == 1, report["diagnostics"]
    return found[0]


def test_self_calling_macro_is_named_as_such_not_an_include_loop(package):
    macros = package / "urdf" / "macros.xacro"
    edit(
        macros,
        "    </inertial>\n  </xacro:macro>",
        '    </inertial>\n    <xacro:box_inertial x="${x}" y="${y}" z="${z}" mass="${mass}"/>\n  </xacro:macro>',
    )
    status, report = verify_report(package, "--no-cache")
    assert status == 1
    diagnostic = only(report, "PF308")
    assert (diagnostic["path"], diagnostic["line"]) == (
        "urdf/macros.xacro",
        line_of(macros, "<xacro:box_inertial x="),
    )
    assert "macro box_inertial calls itself" in diagnostic["message"]
    assert "includes itself" not in diagnostic["message"]
    assert "xacro:if" in diagnostic["hint"]


def test_trailing_slash_in_install_directory_is_the_fix_named(package):
    cmake = package / "CMakeLists.txt"
    edit(cmake, "DIRECTORY launch meshes rviz urdf\n", "DIRECTORY launch meshes rviz urdf/\n")
    status, report = verify_report(package, "--no-cache")
    diagnostic = only(report, "PF302")
    launch = package / "launch" / "display.launch.py"
    assert (diagnostic["path"], diagnostic["line"]) == (
        "launch/display.launch.py",
        line_of(launch, "'urdf/rob_description.urdf.xacro'"),
    )
    assert "installs it as share/rob_description/rob_description.urdf.xacro" in diagnostic["message"]
    assert "trailing slash" in diagnostic["hint"] and "without the slash" in diagnostic["hint"]
    assert (
        f"CMakeLists.txt:{line_of(cmake, 'DIRECTORY launch')}" in diagnostic["hint"]
        or f"CMakeLists.txt:{line_of(cmake, 'install(')}" in diagnostic["hint"]
    )
    assert "add urdf to install" not in diagnostic["hint"]


@pytest.mark.parametrize("target_exists", [False, True])
def test_symlinked_mesh_folder_is_named_not_add_meshes(package, target_exists):
    model = package / "urdf" / "rob_description.urdf.xacro"
    edit(model, "package://rob_description/meshes/arm.stl", "package://rob_description/meshes/visual/arm.stl")
    (package / "meshes" / "visual").symlink_to("../cad/visual")
    if target_exists:
        (package / "cad" / "visual").mkdir(parents=True)
        shutil.copy(package / "meshes" / "arm.stl", package / "cad" / "visual")
    status, report = verify_report(package, "--no-cache")
    diagnostic = only(report, "PF402")
    assert (diagnostic["path"], diagnostic["line"]) == (
        "urdf/rob_description.urdf.xacro",
        line_of(model, "meshes/visual/arm.stl"),
    )
    assert "meshes/visual is a symbolic link to ../cad/visual" in diagnostic["message"]
    assert ("does not exist" in diagnostic["message"]) != target_exists
    assert "add meshes" not in diagnostic["hint"]
    assert ("restore ../cad/visual" in diagnostic["hint"]) != target_exists


def test_case_sensitive_glob_in_setup_py_names_the_entry(tmp_path):
    result = run_pkgforge("new", "rob_py", *MAINTAINER, "--build-type", "ament_python", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    package = tmp_path / "rob_py"
    setup = package / "setup.py"
    edit(setup, "import os\n", "import os\nfrom glob import glob\n")
    edit(
        setup,
        "        *share_files('meshes'),\n",
        "        (os.path.join('share', package_name, 'meshes'), glob('meshes/*.STL')),\n",
    )
    status, report = verify_report(package, "--no-cache")
    diagnostic = only(report, "PF402")
    assert f"data_files entry at setup.py:{line_of(setup, 'glob(')}" in diagnostic["hint"]
    assert "case-sensitive" in diagnostic["hint"] and "arm.stl" in diagnostic["hint"]
    assert "add (os.path.join" not in diagnostic["hint"]


def test_unknown_package_hint_never_repeats_the_wrong_name(tmp_path, template_package):
    # the folder is named robot_description, the package rob_description; the launch file looks up the folder
    package = tmp_path / "src" / "robot_description"
    shutil.copytree(template_package, package)
    launch = package / "launch" / "display.launch.py"
    edit(launch, "FindPackageShare('rob_description')", "FindPackageShare('robot_description')")
    status, report = verify_report(package, "--no-cache")
    lookups = [d for d in report["diagnostics"] if d["code"] == "PF304"]
    assert line_of(launch, "FindPackageShare('robot_description')") in [d["line"] for d in lookups]
    diagnostic = lookups[0]
    assert all(d["hint"] == diagnostic["hint"] for d in lookups)
    assert "did you mean robot_description" not in diagnostic["hint"]
    assert "'robot_description' is the name of the folder" in diagnostic["hint"]
    assert "write 'rob_description'" in diagnostic["hint"]


def test_timeout_hint_says_what_to_look_for_not_a_line(package):
    launch = package / "launch" / "display.launch.py"
    edit(
        launch,
        "def generate_launch_description():\n",
        "def generate_launch_description():\n    while True:\n        pass\n",
    )
    status, report = verify_report(package, "--no-cache", "--launch-timeout", "0.5", "--select", "PF301")
    diagnostic = only(report, "PF301")
    assert diagnostic["path"] == "launch/display.launch.py"
    assert "fix the line named" not in diagnostic["hint"]
    assert "--launch-timeout" in diagnostic["hint"] and "loop" in diagnostic["hint"]


def test_launch_arg_outside_its_choices_is_a_usage_error(package):
    result = run_pkgforge("verify", "--launch-arg", "gui:=maybe", "--no-cache", cwd=package)
    assert result.returncode == 2, result.stdout + result.stderr
    assert result.stdout == ""
    launch = package / "launch" / "display.launch.py"
    line = line_of(launch, "name='gui'") - 1  # the DeclareLaunchArgument( line
    assert result.stderr == (
        f"pkgforge: error: --launch-arg gui:=maybe: 'gui' allows only true, false "
        f"(declared at launch/display.launch.py:{line})\n"
    )
    result = run_pkgforge("verify", "--launch-arg", "gui:=false", "--no-cache", cwd=package)
    assert result.returncode == 0, result.stdout + result.stderr


def spaced_workspace(tmp_path, template_package, *, quoted: bool = False) -> tuple[Path, Path]:
    """A workspace under a folder whose name has a space, with an install tree as colcon makes it
    (no build needed); `quoted`: the launch file quotes the model's path in its Command."""
    workspace = tmp_path / "with space" / "ws"
    package = workspace / "src" / "rob_description"
    shutil.copytree(template_package, package)
    if quoted:
        edit(
            package / "launch" / "display.launch.py",
            "Command(['xacro ', LaunchConfiguration('model')])",
            "Command(['xacro \"', LaunchConfiguration('model'), '\"'])",
        )
    hand_made_install(package)
    return workspace, package


MODES = {"predicted": (), "install-base": ("--install-base", "install"), "build": ("--build",)}


@pytest.mark.parametrize("mode", MODES)
def test_workspace_path_with_a_space_names_the_split(tmp_path, template_package, mode):
    # ROS's Command joins ['xacro ', <path>] into one line and splits it shell-like: a space in
    # the workspace path cuts the model's path in two. pkgforge's own copy of the install tree has
    # no space, so the check reads the line as the user's install base would give it.
    workspace, package = spaced_workspace(tmp_path, template_package)
    status, report = verify_report(workspace, *MODES[mode], "--no-cache", "--select", "PF3,PF4")
    assert status == 1
    diagnostic = only(report, "PF308")
    launch = package / "launch" / "display.launch.py"
    assert (diagnostic["path"], diagnostic["line"]) == (
        "src/rob_description/launch/display.launch.py",
        line_of(launch, "Command(['xacro '"),
    )
    model = workspace / "install" / "share" / "rob_description" / "urdf" / "rob_description.urdf.xacro"
    # (the whole text is the detail when the message is cut to 300 characters)
    assert (diagnostic["detail"] or diagnostic["message"]) == (
        f"xacro rob_description.urdf.xacro got '{tmp_path}/with': Command joins its parts into one line "
        f"that it splits at spaces (ROS's Command does too), and the path '{model}' has a space"
    )
    assert diagnostic["message"].startswith(f"xacro rob_description.urdf.xacro got '{tmp_path}/with': ")
    assert "quote the path" in diagnostic["hint"]
    assert "pkgforge-tree-" not in json.dumps(report)


@pytest.mark.parametrize("mode", ["predicted", "install-base"])
def test_a_quoted_path_with_a_space_is_clean(tmp_path, template_package, mode):
    workspace, package = spaced_workspace(tmp_path, template_package, quoted=True)
    status, report = verify_report(workspace, *MODES[mode], "--no-cache")
    assert (status, report["diagnostics"]) == (0, [])


def test_a_model_file_named_with_a_space_names_the_split(package):
    # the space is in the package's own file: pkgforge's copy has it too, and its run splits as ROS's
    (package / "urdf" / "rob_description.urdf.xacro").rename(package / "urdf" / "rob description.urdf.xacro")
    launch = package / "launch" / "display.launch.py"
    edit(launch, "'urdf/rob_description.urdf.xacro'", "'urdf/rob description.urdf.xacro'")
    status, report = verify_report(package, "--no-cache", "--select", "PF3,PF4")
    diagnostic = only(report, "PF308")
    assert (status, diagnostic["path"], diagnostic["line"]) == (
        1,
        "launch/display.launch.py",
        line_of(launch, "Command(['xacro '"),
    )
    share = package.parent.parent / "install" / "share" / "rob_description" / "urdf"
    assert (diagnostic["detail"] or diagnostic["message"]) == (
        f"xacro rob description.urdf.xacro got '{share}/rob': Command joins its parts into one line that "
        f"it splits at spaces (ROS's Command does too), and the path '{share}/rob description.urdf.xacro' "
        "has a space"
    )


def test_a_space_in_pkgforges_own_temporary_folder_is_no_error_of_the_user(tmp_path, package):
    # the tree is not on /dev/shm (full) and TMPDIR has a space: pkgforge puts its tree elsewhere
    spaced = tmp_path / "tmp dir"
    spaced.mkdir()
    patch = (
        f"import os, tempfile\nos.environ['TMPDIR'] = {str(spaced)!r}\ntempfile.tempdir = None\n"
        "import pkgforge.tree\npkgforge.tree._fast_folder = lambda needed: None\n"
    )
    result = run_patched(patch, "verify", str(package), "--no-cache", cwd=package)
    assert (result.returncode, result.stderr) == (0, ""), result.stdout
    assert result.stdout.startswith("0 errors, 0 warnings, 0 infos in 1 package; launch: built-in engine")
    assert list(spaced.iterdir()) == []


# --- errors: one located line, exit 2; internal errors say "please report" -------------------------


def run_patched(patch: str, *args: str, cwd: Path) -> subprocess.CompletedProcess:
    """The real command line, with one function of pkgforge replaced first (to make it fail)."""
    script = (
        f"import sys\n{patch}\nsys.argv = ['pkgforge', *{list(args)!r}]\n"
        "from pkgforge.cli import main\nmain()\n"
    )
    return run_command([sys.executable, "-c", script], cwd=cwd)


def test_an_oserror_anywhere_is_one_located_line_exit_2(package):
    patch = (
        "import pkgforge.verify.pipeline\n"
        "def broken(*a, **k):\n"
        "    raise PermissionError(13, 'Permission denied', '/srv/robots/x.urdf')\n"
        "pkgforge.verify.pipeline.verify = broken\n"
    )
    result = run_patched(patch, "verify", str(package), cwd=package)
    assert result.returncode == 2
    assert result.stderr == (
        "pkgforge: error: /srv/robots/x.urdf: Permission denied; check its "
        "permissions (ls -l) or run as its owner\n"
    )


def test_an_unexpected_exception_exits_2_asking_for_a_report(package):
    patch = (
        "import pkgforge.verify.pipeline\n"
        "def broken(*a, **k):\n"
        "    raise KeyError('surprise')\n"
        "pkgforge.verify.pipeline.verify = broken\n"
    )
    result = run_patched(patch, "verify", str(package), cwd=package)
    assert result.returncode == 2
    assert result.stderr.startswith("pkgforge: internal error: KeyError: 'surprise'; please report it")
    assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1
    result = run_patched(patch, "--debug", "verify", str(package), cwd=package)
    assert result.returncode == 2
    assert "please report" in result.stderr and "Traceback (most recent call last)" in result.stderr


def test_a_crash_inside_one_check_keeps_the_others_and_exits_2(package):
    patch = (
        "import pkgforge.checks.load_all\n"
        "from pkgforge.checks.registry import REGISTRY\n"
        "import dataclasses\n"
        "def broken(ctx):\n"
        "    raise ValueError('bug')\n"
        "REGISTRY['PF104'] = dataclasses.replace(REGISTRY['PF104'], function=broken)\n"
    )
    edit(package / "package.xml", "  <license>Apache-2.0</license>\n", "")  # a real finding: PF101
    result = run_patched(patch, "verify", "--format", "json", "--no-cache", str(package), cwd=package)
    assert result.returncode == 2, result.stderr
    report = json.loads(result.stdout)
    assert {d["code"] for d in report["diagnostics"]} >= {"PF101", "PF104"}
    assert "pkgforge: internal error in check folder-name-mismatch (PF104)" in result.stderr
    assert "please report" in result.stderr and "Traceback" not in result.stderr


# --- as a user without root: permissions ------------------------------------------------------


@pytest.fixture(scope="module")
def as_nobody():
    """run(args, cwd): pkgforge as the unprivileged user nobody, or skip when that is impossible."""
    if os.geteuid() != 0:
        pytest.skip("needs root to switch to an unprivileged user")
    if shutil.which("setpriv") is None:
        pytest.skip("setpriv (util-linux) is not installed")
    import site

    import pkgforge

    path = os.pathsep.join([*site.getsitepackages(), str(Path(pkgforge.__file__).resolve().parents[1])])
    version = f"python{sys.version_info[0]}.{sys.version_info[1]}"
    env = dict(os.environ, PYTHONPATH=path, HOME="/nonexistent", XDG_CACHE_HOME="/nonexistent")
    # the virtual environment's interpreter may sit in a folder nobody cannot enter (/root)
    for interpreter in dict.fromkeys(
        [
            sys.executable,
            os.path.realpath(sys.executable),
            getattr(sys, "_base_executable", sys.executable),
            f"/usr/bin/{version}",
            f"/usr/local/bin/{version}",
        ]
    ):
        # pkgforge starts workers with its own interpreter: that must work as nobody too
        probe = subprocess.run(
            [
                *NOBODY,
                interpreter,
                "-c",
                "import subprocess, sys; subprocess.run("
                "[sys.executable, '-c', 'import lxml, xacro; from pkgforge.cli import main'], check=True)",
            ],
            capture_output=True,
            env=env,
            cwd="/",
        )
        if probe.returncode == 0:
            break
    else:
        pytest.skip("no Python interpreter with pkgforge's dependencies that nobody may run")

    def run(*args, cwd: Path):
        return run_command([*NOBODY, interpreter, "-m", "pkgforge", *args], cwd=cwd, env=env)

    return run


@pytest.fixture
def shared(template_package):
    """A workspace in a folder nobody can read (pytest's own temporary folders are root's, 0700)."""
    import tempfile

    root = Path(tempfile.mkdtemp(prefix="pkgforge-nobody-", dir="/tmp"))
    os.chmod(root, 0o755)
    package = root / "ws" / "src" / "rob_description"
    shutil.copytree(template_package, package)
    for folder, _dirs, _files in os.walk(root):
        os.chmod(folder, 0o755)
    yield package
    for folder, _dirs, files in os.walk(root):
        os.chmod(folder, 0o755)
        for name in files:
            if not os.path.islink(os.path.join(folder, name)):
                os.chmod(os.path.join(folder, name), 0o644)
    shutil.rmtree(root)


def test_new_in_a_read_only_folder_is_one_line_exit_2(as_nobody, shared):
    read_only = shared.parent.parent / "read-only"
    read_only.mkdir(mode=0o555)
    os.chmod(read_only, 0o555)
    result = as_nobody("new", "rob_description", *MAINTAINER, cwd=read_only)
    assert result.returncode == 2, result.stdout + result.stderr
    assert result.stderr == (
        f"pkgforge: error: cannot create the package in {read_only}: Permission denied "
        "(choose a folder you can write to with --destination)\n"
    )
    assert list(read_only.iterdir()) == []


def test_unreadable_folder_is_located_not_an_internal_error(as_nobody, shared):
    os.chmod(shared / "urdf", 0)
    result = as_nobody("verify", "--format", "json", cwd=shared.parent.parent)
    assert "internal error" not in result.stdout + result.stderr and "Traceback" not in result.stderr
    assert result.returncode == 1, result.stdout + result.stderr
    report = json.loads(result.stdout)
    folder = only(report, "PF903")
    assert (folder["path"], folder["severity"]) == ("src/rob_description/urdf", "warning")
    assert "cannot read this folder: Permission denied" in folder["message"] and "chmod" in folder["hint"]
    missing = only(report, "PF303")
    assert "rob_description's folder urdf/ cannot be read" in missing["message"]


@pytest.mark.parametrize(
    "file, code, wrong",
    [
        ("package.xml", "PF101", "the element named"),
        ("CMakeLists.txt", "PF204", "the named line"),
        ("rviz/display.rviz", "PF501", "save the config again"),
        ("meshes/arm.stl", "PF405", "export the mesh again"),
        ("launch/display.launch.py", "PF301", "fix the line named"),
    ],
)
def test_unreadable_file_hints_say_permission(as_nobody, shared, file, code, wrong):
    os.chmod(shared / file, 0)
    result = as_nobody("verify", "--format", "json", cwd=shared)
    assert "Traceback" not in result.stderr and result.returncode == 1, result.stdout + result.stderr
    report = json.loads(result.stdout)
    diagnostic = [d for d in report["diagnostics"] if d["code"] == code][0]
    assert "Permission denied" in diagnostic["message"]
    assert wrong not in diagnostic["hint"] and "chmod a+r" in diagnostic["hint"]
    for info in (d for d in report["diagnostics"] if d["code"] == "PF901"):
        assert "ASCII" not in info["hint"] and "chmod a+r" in info["hint"]
    assert "/tmp/pkgforge-tree-" not in result.stdout  # the user's file is named, not pkgforge's tree


def test_encoding_problems_say_save_as_utf8(package):
    launch = package / "launch" / "display.launch.py"
    comment_line = line_of(launch, "# value_type")
    for relative, old in (
        ("package.xml", b"<description>"),
        ("rviz/display.rviz", b"Panels"),
        ("launch/display.launch.py", b"# value_type"),
    ):
        path = package / relative
        path.write_bytes(path.read_bytes().replace(old, old + b"\xe9", 1))
    status, report = verify_report(package, "--no-cache")
    by_code = {d["code"]: d for d in report["diagnostics"]}
    assert set(by_code) == {"PF101", "PF501", "PF901"}, report["diagnostics"]
    assert by_code["PF101"]["hint"] == "save the file as UTF-8"  # not "fix the element named"
    assert by_code["PF501"]["hint"] == "save the file as UTF-8"  # not "save the config again from RViz"
    assert (by_code["PF901"]["path"], by_code["PF901"]["line"]) == ("launch/display.launch.py", comment_line)
    assert "UTF-8" in by_code["PF901"]["hint"] and "ASCII" not in by_code["PF901"]["hint"]


# --- issue 30: a setup.py colcon cannot run ----------------------------------------------------


def test_a_setup_py_colcon_cannot_run_is_one_located_line(tmp_path):
    """Issue 30: a folder of the workspace whose setup.py imports a module that is not installed
    (colcon runs it in discovery to learn the package's name) is one line naming the file, its
    line and the error, not the traceback of the Python colcon started; and an ament_python
    package whose setup.py colcon cannot run at build time is one located build-failed line."""
    workspace = tmp_path / "ws"
    (workspace / "src").mkdir(parents=True)
    result = run_pkgforge("new", "py_bot", *MAINTAINER, "--build-type", "ament_python", cwd=workspace)
    assert result.returncode == 0, result.stderr
    helper = workspace / "src" / "helper_lib"
    helper.mkdir()
    (helper / "setup.py").write_text(
        "from setuptools import setup\nimport not_installed_helper\nsetup(name='helper_lib')\n"
    )
    result = run_pkgforge("verify", cwd=workspace)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stderr.splitlines() == [
        "pkgforge: warning: src/helper_lib/setup.py:2: colcon could not run it to read the package's name "
        "(ModuleNotFoundError: No module named 'not_installed_helper'), so it skips the folder: install what "
        "it imports, or put a COLCON_IGNORE file beside it if it is no package"
    ]
    setup_py = workspace / "src" / "py_bot" / "setup.py"
    setup_py.write_text("import not_installed_helper\n" + setup_py.read_text())
    # (colcon's own output of the build, on stderr, is colcon's: the report is pkgforge's)
    built = run_pkgforge("verify", "--build", "--format", "json", cwd=workspace)
    assert built.returncode == 1, built.stdout + built.stderr
    (failed,) = [d for d in json.loads(built.stdout)["diagnostics"] if d["code"] == "PF902"]
    assert (failed["path"], failed["line"]) == ("src/py_bot/setup.py", 1)
    assert failed["message"].startswith(
        "colcon could not run setup.py to read the package's metadata (it imports not_installed_helper, which "
    )
    assert failed["message"].endswith(" cannot import)") and "\n" not in failed["message"]
    assert (
        failed["hint"]
        == "install what it imports into that Python, or import it only inside the functions that need it"
    )
