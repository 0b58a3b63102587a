"""Launch patterns of real packages, evaluated as ROS evaluates them (built-in engine).

tests/fixtures/launch_patterns/pattern_bot holds one plain launch file per pattern; one
`pkgforge verify` of it must give exactly the diagnostics below (code, file, line), no
more: a pattern ROS accepts gives nothing, one ROS rejects gives ROS's error.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import copy_fixture, line_of, run_pkgforge

FIXTURE = "launch_patterns/pattern_bot"
LAUNCH = "src/pattern_bot/launch"


def verify(workspace: Path, distro: str = "jazzy") -> list[dict]:
    """The built-in engine held to `distro`'s launch API (verify's target distro)."""
    env = {k: v for k, v in os.environ.items() if k not in ("PKGFORGE_LAUNCH_DISTRO", "ROS_DISTRO")}
    result = run_pkgforge(
        "verify",
        workspace,
        "--format",
        "json",
        "--no-cache",
        "--distro",
        distro,
        "--launch-engine",
        "builtin",
        cwd=workspace,
        env=env,
    )
    assert "Traceback" not in result.stderr, result.stderr
    assert result.returncode in (0, 1), result.stdout + result.stderr
    return json.loads(result.stdout)["diagnostics"]


def at(package: Path, name: str, text: str) -> tuple[str, int]:
    path = package / ("launch" if not name.startswith("urdf/") else "") / name
    return f"src/pattern_bot/{'launch/' if not name.startswith('urdf/') else ''}{name}", line_of(path, text)


def at_before(package: Path, name: str, text: str) -> tuple[str, int]:
    """A YAML entity's line: the `- tag:` line above its attribute `text`."""
    path, line = at(package, name, text)
    return path, line - 1


@pytest.fixture(scope="module")
def pattern_bot(tmp_path_factory) -> Path:
    workspace = tmp_path_factory.mktemp("patterns")
    copy_fixture(FIXTURE, workspace)
    return workspace


@pytest.fixture(scope="module")
def jazzy_report(pattern_bot) -> list[dict]:
    return verify(pattern_bot)


def expected_jazzy(package: Path) -> set[tuple]:
    def d(code, name, text):
        return (code, *at(package, name, text))

    return {
        # ROS raises TypeError: a bool is not a substitution (launch.utilities normalize)
        d("PF301", "bool_default.launch.py", "DeclareLaunchArgument('use_sim_time'"),
        # typed equals: '1' equals 1.0, '1' equals True: both nodes start
        d("PF305", "equals_typed.launch.py", "package='tf2_ros'"),
        d("PF305", "equals_typed.launch.py", "package='topic_tools'"),
        d("PF305", "equals_typed.launch.xml", 'pkg="tf2_tools"'),
        # OnProcessExit(on_exit=[...]) and OpaqueFunction results are visited
        d("PF305", "event_handler.launch.py", "package='usb_cam'"),
        d("PF305", "event_handler.launch.py", "package='twist_mux'"),
        # $(file-content) evaluates; the node after it is checked
        d("PF305", "file_content.launch.xml", 'pkg="turtlesim"'),
        # forwarding=False hides 'demo' from the first group: only the second node starts
        d("PF305", "group_forwarding.launch.py", "package='demo_nodes_cpp'"),
        # [FindPackageShare(...), '/config/calibration.yaml'] is one joined path
        d("PF303", "list_params.launch.py", "Node(package='robot_state_publisher'"),
        # the misspelt package is reported and the file goes on
        d("PF304", "missing_package.launch.py", "FindPackageShare('pattern_bott')"),
        d("PF305", "missing_package.launch.py", "package='teleop_twist_keyboard'"),
        # nav2_common is declared, not installed: read statically
        d("PF311", "nav2_style.launch.py", "from nav2_common.launch import"),
        d("PF305", "nav2_style.launch.py", "package='robot_localization'"),
        # the package is recorded before the parameters fail
        d("PF305", "package_before_params.launch.py", "package='joint_state_publisher_gui'"),
        d("PF308", "urdf/broken.urdf.xacro", "${body_size}"),
        # <push-ros-namespace>, <set_remap>: the node after them is checked
        d("PF305", "push_namespace.launch.yaml", "- node:"),
        # a run-time query is not run at verify time (an info); the timer's actions are visited
        d("PF310", "runtime_command.launch.py", "rate = Command("),
        d("PF305", "runtime_command.launch.py", "package='joy'"),
        # the front end's tags and substitutions: the nodes at the end are still checked
        d("PF305", "frontend_tags.launch.xml", 'pkg="slam_toolbox"'),
        ("PF305", *at_before(package, "frontend_tags.launch.yaml", 'pkg: "nav2_map_server"')),
        # <set_use_sim_time> sets a parameter of the launch's own ROS node: not evaluated (an info)
        d("PF310", "frontend_tags.launch.xml", "<set_use_sim_time"),
        # Jazzy's own front end fails on $(any ...) and $(all ...)
        d("PF301", "all_any.launch.xml", 'if="$(any '),
        # a real name pkgforge does not evaluate: an info, not a load error
        d("PF310", "unsupported_api.launch.py", "LaunchLogDir()"),
        # xacro warns on stderr: Command's default on_stderr='fail' fails, 'ignore' does not
        d("PF308", "xacro_stderr.launch.py", "Command(['xacro ', model]), value_type=str)"),
        # robot_state_publisher given no robot_description (nor a model file) stops at start
        d("PF321", "list_params.launch.py", "Node(package='robot_state_publisher'"),
        d("PF321", "nonstring_defaults.launch.py", "Node("),
        d("PF321", "optional_probe.launch.py", "Node(package='robot_state_publisher'"),
    }


def test_every_pattern_gives_exactly_what_ros_gives(pattern_bot, jazzy_report):
    package = pattern_bot / "src" / "pattern_bot"
    found = {(d["code"], d["path"], d["line"]) for d in jazzy_report}
    assert found == expected_jazzy(package), json.dumps(jazzy_report, indent=1)


@pytest.mark.triggers("PF310")
def test_messages_name_the_cause(jazzy_report):
    messages = {(d["code"], Path(d["path"]).name): d["message"] for d in jazzy_report}
    assert messages[("PF301", "bool_default.launch.py")].endswith("TypeError: 'bool' object is not iterable")
    assert messages[("PF310", "runtime_command.launch.py")].startswith(
        "Command 'ros2 param get' (run-time only)"
    )
    assert messages[("PF310", "unsupported_api.launch.py")].startswith("LaunchLogDir ")
    assert messages[("PF301", "all_any.launch.xml")].endswith(
        "AnySubstitution.__init__() got an unexpected keyword argument 'args'"
    )
    assert "redefining global symbol: len" in messages[("PF308", "xacro_stderr.launch.py")]
    assert "\n" not in messages[("PF308", "xacro_stderr.launch.py")]


def test_humble_lacks_the_names_jazzy_added(pattern_bot):
    """The target distro's list: EqualsSubstitution and LaunchLogDir are ImportErrors in Humble."""
    package = pattern_bot / "src" / "pattern_bot"
    report = verify(pattern_bot, "humble")
    errors = {(d["path"], d["line"]): d["message"] for d in report if d["code"] == "PF301"}
    path, line = at(package, "equals_typed.launch.py", "from launch.substitutions import EqualsSubstitution")
    assert (
        "ImportError: cannot import name 'EqualsSubstitution' from 'launch.substitutions'"
        in errors[(path, line)]
    )
    path, line = at(package, "unsupported_api.launch.py", "from launch.substitutions import LaunchLogDir")
    assert "cannot import name 'LaunchLogDir'" in errors[(path, line)]
    # <equals> is no Humble substitution either
    path, line = at(package, "equals_typed.launch.xml", "$(equals")
    assert "Unknown substitution: equals" in errors[(path, line)]


@pytest.mark.triggers("PF315")
def test_launch_files_not_installed_are_evaluated_from_the_source(tmp_path):
    package = copy_fixture(FIXTURE, tmp_path)
    cmake = package / "CMakeLists.txt"
    cmake.write_text(
        cmake.read_text().replace(
            "install(DIRECTORY config launch urdf\n",
            "install(FILES launch/find_share_find.launch.py DESTINATION share/${PROJECT_NAME}/launch)\n"
            "install(DIRECTORY config urdf\n",
        )
    )
    report = verify(tmp_path)
    uninstalled = {d["path"] for d in report if d["code"] == "PF315"}
    expected = {
        f"{LAUNCH}/{p.name}" for p in (package / "launch").iterdir() if p.name != "find_share_find.launch.py"
    }
    assert uninstalled == expected
    assert all(d["line"] is None and d["severity"] == "warning" for d in report if d["code"] == "PF315")
    # evaluated all the same, from the source: what they use is checked
    found = {(d["code"], d["path"], d["line"]) for d in report}
    assert ("PF305", *at(package, "event_handler.launch.py", "package='twist_mux'")) in found
    assert ("PF304", *at(package, "missing_package.launch.py", "FindPackageShare('pattern_bott')")) in found


# --- the worker's record, for what the diagnostics do not show ---------------------------------


def worker(requests: list[dict], env: dict | None = None) -> list[dict]:
    """The replies of `python -m pkgforge.evaluation` to the requests (each line followed by
    its token line, as the parent sends them); its first line, the hello, is left out."""
    done = subprocess.run(
        [sys.executable, "-m", "pkgforge.evaluation"],
        capture_output=True,
        text=True,
        input="".join(json.dumps(r) + f"\nt{i}\n" for i, r in enumerate(requests)),
        timeout=120,
        env=dict(os.environ, **(env or {})),
    )
    hello, *replies = [json.loads(line) for line in done.stdout.splitlines()]
    assert "hello" in hello, done.stdout
    assert [r.pop("token") for r in replies] == [f"t{i}" for i in range(len(requests))]
    return replies


def test_namespace_and_remaps_reach_the_nodes(pattern_bot, tmp_path):
    package = pattern_bot / "src" / "pattern_bot"
    index = tmp_path / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    (index / "pattern_bot").write_text("")
    (tmp_path / "share" / "pattern_bot").symlink_to(package)
    env = {"AMENT_PREFIX_PATH": str(tmp_path)}
    xml, yaml_file = worker(
        [
            {"file": str(package / "launch" / "push_namespace.launch.xml")},
            {"file": str(package / "launch" / "push_namespace.launch.yaml")},
        ],
        env,
    )
    assert xml["status"] == "ok", xml
    node = xml["nodes"][0]
    assert (node["package"], node["namespace"], node["remappings"]) == (
        "robot_state_publisher",
        "/bot1",
        [["/tf", "tf"]],
    )
    assert yaml_file["nodes"][0]["namespace"] == "/bot2"


def test_real_module_paths_and_signatures(tmp_path):
    """Every module and public name of the real API imports from its real path, re-exports are
    the same object, and a call the real signature refuses raises CPython's TypeError."""
    script = tmp_path / "probe.py"
    script.write_text(
        "import importlib, json, sys\n"
        "from pkgforge.launch import api\n"
        "api.install()\n"
        "missing = []\n"
        "for module, info in api.modules().items():\n"
        "    loaded = importlib.import_module(module)\n"
        "    for name, entry in info['names'].items():\n"
        "        if entry['kind'] in ('class', 'function', 'alias', 'module') and not hasattr(loaded, name):\n"
        "            missing.append(f'{module}.{name}')\n"
        "from launch.substitutions.launch_configuration import LaunchConfiguration as A\n"
        "from launch.substitutions import LaunchConfiguration as B\n"
        "import launch.launch_context\n"
        "from launch_ros.substitutions import FindPackageShare\n"
        "errors = []\n"
        "for call in (lambda: FindPackageShare('a', 'b'), lambda: FindPackageShare('a').find('a', 'b'),\n"
        "             lambda: __import__('launch_ros.actions').actions.Node(package='p')):\n"
        "    try:\n"
        "        call()\n"
        "    except TypeError as error:\n"
        "        errors.append(str(error))\n"
        "print(json.dumps({'missing': missing, 'same': A is B, 'errors': errors,\n"
        "                  'context': launch.launch_context.LaunchContext.__name__}))\n"
    )
    for distro in ("humble", "jazzy", "rolling"):
        done = subprocess.run(
            [sys.executable, str(script)],
            capture_output=True,
            text=True,
            timeout=120,
            env=dict(os.environ, PKGFORGE_LAUNCH_DISTRO=distro),
        )
        assert done.returncode == 0, done.stderr
        result = json.loads(done.stdout)
        assert result["missing"] == [] and result["same"] and result["context"] == "LaunchContext"
        assert result["errors"] == [
            "FindPackageShare.__init__() takes 2 positional arguments but 3 were given",
            "FindPackageShare.find() takes 2 positional arguments but 3 were given",
            "Node.__init__() missing 1 required keyword-only argument: 'executable'",
        ]


def test_generated_list_is_current():
    """api_names.json is what scripts/gen_launch_api.py makes of the upstream sources."""
    root = Path(__file__).resolve().parent.parent
    upstream = next(
        (
            p / "upstream" / "ros2-launch"
            for p in (root.parent / "shared", root.parent.parent / "shared")
            if (p / "upstream" / "ros2-launch" / "jazzy").is_dir()
        ),
        None,
    )
    if upstream is None:
        pytest.skip("no ../shared/upstream/ros2-launch sources here")
    sys.path.insert(0, str(root / "scripts"))
    try:
        import gen_launch_api
    finally:
        sys.path.pop(0)
    data = json.loads((root / "src" / "pkgforge" / "launch" / "api_names.json").read_text())
    fresh = gen_launch_api.generate(upstream)
    assert data["distros"] == fresh["distros"], "run scripts/gen_launch_api.py and commit its output"
