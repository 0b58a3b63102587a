"""Issue 12: real-world install idioms, references read by parsers, packages known per distro,
new checks, precision, Lyrical. Each fixture in fixtures/realworld/ has one shape seen in real
packages; the whole workspace is verified once per target distro and every package's findings
are asserted exactly (code, file, line)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import FIXTURES, MAINTAINER, edit, line_of, new_package, run_pkgforge, verify_report

REALWORLD = FIXTURES / "realworld"
REPO = Path(__file__).resolve().parent.parent


def findings(report: dict, package: str) -> list[tuple]:
    """(check name, path inside the package, line) of one package's diagnostics."""
    return sorted(
        (d["name"], d["path"].removeprefix(f"src/{package}/"), d["line"])
        for d in report["diagnostics"]
        if d["package"] == package
    )


def by_name(report: dict, package: str, name: str) -> list[dict]:
    return [d for d in report["diagnostics"] if d["package"] == package and d["name"] == name]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("realworld")
    shutil.copytree(REALWORLD, root / "src")
    return root


@pytest.fixture(scope="module")
def every_distro(workspace) -> dict:
    env = {k: v for k, v in os.environ.items() if k != "ROS_DISTRO"}
    result = run_pkgforge("verify", workspace, "--format", "json", "--no-cache", cwd=workspace, env=env)
    assert "Traceback" not in result.stderr, result.stderr
    import json

    return json.loads(result.stdout)


@pytest.fixture(scope="module")
def jazzy(workspace) -> dict:
    return verify_report(workspace, "--no-cache", "--distro", "jazzy")[1]


def src(workspace: Path, package: str, relative: str) -> Path:
    return workspace / "src" / package / relative


# --- 1. install idioms ------------------------------------------------------------------------


@pytest.mark.parametrize(
    "package",
    [
        "auto_description",
        "py_description",
        "cfg_description",
        "cmake_python_description",
        "comments_description",
        "robot_meta",
    ],
)
def test_clean_real_world_shapes(every_distro, package):
    """ament_auto_package(INSTALL_TO_SHARE), setup.py loops/glob/os.walk, setup.cfg data_files,
    ament_cmake_python, references only in comments, a metapackage: nothing to report."""
    assert findings(every_distro, package) == []


def test_variables_foreach_and_install_files_with_one_unevaluable_rule(every_distro, workspace):
    cmake = src(workspace, "loops_description", "CMakeLists.txt")
    assert findings(every_distro, "loops_description") == [
        ("install-rule-unevaluated", "CMakeLists.txt", line_of(cmake, "$ENV{EXTRA_ASSETS}"))
    ]


@pytest.mark.parametrize(
    "package, installed",
    [
        ("auto_description", ["launch/display.launch.py", "meshes/base_link.STL", "urdf/robot.urdf"]),
        (
            "loops_description",
            ["launch/display.launch.py", "meshes/base_link.STL", "rviz/view.rviz", "urdf/robot.urdf"],
        ),
        (
            "py_description",
            ["config/arm/limits.yaml", "launch/display.launch.py", "meshes/base_link.STL", "urdf/robot.urdf"],
        ),
        ("cfg_description", ["launch/display.launch.py", "meshes/base_link.STL", "urdf/robot.urdf"]),
        ("cmake_python_description", ["launch/display.launch.py", "meshes/base_link.STL", "urdf/robot.urdf"]),
    ],
)
def test_the_predicted_install_tree_of_each_idiom(package, installed):
    from pkgforge.model.package import load_package

    model = load_package(REALWORLD / package)
    share = f"share/{package}/"
    assert sorted(f[len(share) :] for f in model.layout.files if f.startswith(share)) == sorted(
        installed + ["package.xml"]
    )
    if package == "cmake_python_description":  # ament_python_install_package(${PROJECT_NAME})
        assert "lib/python3/site-packages/cmake_python_description/tools.py" in model.layout.files


def test_a_setup_py_loop_over_something_unknown_is_unevaluated_not_guessed(tmp_path):
    from pkgforge.model.setup_py import load_setup_py
    from pkgforge.model.source import read_source

    (tmp_path / "launch").mkdir()
    (tmp_path / "launch" / "a.launch.py").write_text("")
    setup = tmp_path / "setup.py"
    setup.write_text(
        "import os\nfrom glob import glob\nfrom setuptools import setup\n"
        "data_files = [('share/p', ['package.xml'])]\n"
        "for folder in os.listdir('.'):\n"
        "    data_files.append(('share/p/' + folder, glob(folder + '/*')))\n"
        "setup(name='p', data_files=data_files)\n"
    )
    model = load_setup_py(read_source(setup), tmp_path)
    assert model.entries == []
    assert [line for line, _ in model.unknown] == [line_of(setup, "for folder in")]


# --- 2. references from parsers --------------------------------------------------------------


def test_references_in_comments_are_no_use(workspace):
    from pkgforge.model.package import load_package

    model = load_package(workspace / "src" / "comments_description")
    names = {r.package for r in model.references}
    assert not names & {
        "old_robot_description",
        "gazebo_ros",
        "rviz",
        "joint_state_publisher_gui",
        "turtlebot3_description",
    }
    xacro = src(workspace, "comments_description", "urdf/robot.urdf.xacro")
    (mesh,) = [r for r in model.references if r.via == "package://"]
    assert (mesh.path, mesh.line, mesh.relative) == (
        xacro,
        line_of(xacro, 'filename="package://comments'),
        "meshes/base_link.STL",
    )
    yaml_launch = src(workspace, "comments_description", "launch/state.launch.yaml")
    assert [
        (r.package, r.line) for r in model.references if r.path == yaml_launch and r.via == "node pkg"
    ] == [("robot_state_publisher", line_of(yaml_launch, "pkg: robot_state_publisher"))]


# --- 3. packages known per distro ------------------------------------------------------------


def test_distro_data_every_active_distro():
    from pkgforge.model.distro_data import load

    data = load()
    assert data.names == ["humble", "jazzy", "kilted", "lyrical", "rolling"]
    assert data.released_in("gazebo_ros") == ["humble"]
    assert data.released_in("ros_gz_sim") == data.names
    assert not data.released("rviz") and not data.released("roslaunch")
    assert len(data.masks) > 2000


def test_every_replacement_is_released_where_its_name_is_not():
    from pkgforge.model.distro_data import REPLACEMENTS, load

    data = load()
    for name, (successor, why) in REPLACEMENTS.items():
        assert not data.released(name, "rolling"), name
        assert data.released_in(successor) == data.names, (name, successor)
        assert why


def test_distro_data_regenerates_identically_from_the_lists(tmp_path):
    lists = Path("/work/shared/rosdistro")
    if not lists.is_dir():
        pytest.skip("no rosdistro lists on this machine")
    out = tmp_path / "distros.txt"
    result = subprocess.run(
        [
            sys.executable,
            str(REPO / "scripts" / "update-distro-data"),
            "--lists",
            str(lists),
            "--output",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stderr
    assert out.read_text() == (REPO / "src" / "pkgforge" / "model" / "data" / "distros.txt").read_text()


def test_distro_data_from_a_rosdistro_checkout(tmp_path):
    """The REP 143 layout: index-v4.yaml names the active ROS 2 distros, distribution.yaml their packages."""
    import yaml

    (tmp_path / "index-v4.yaml").write_text(
        yaml.safe_dump(
            {
                "type": "index",
                "version": 4,
                "distributions": {
                    "jazzy": {
                        "distribution": ["jazzy/distribution.yaml"],
                        "distribution_status": "active",
                        "distribution_type": "ros2",
                    },
                    "noetic": {
                        "distribution": ["noetic/distribution.yaml"],
                        "distribution_status": "end-of-life",
                        "distribution_type": "ros1",
                    },
                },
            }
        )
    )
    (tmp_path / "jazzy").mkdir()
    (tmp_path / "jazzy" / "distribution.yaml").write_text(
        yaml.safe_dump(
            {
                "release_platforms": {"ubuntu": ["noble"]},
                "repositories": {
                    "xacro": {"release": {"version": "2.0.0-1"}},
                    "ros_gz": {"release": {"packages": ["ros_gz", "ros_gz_sim"], "version": "1.0.0-1"}},
                    "source_only": {"source": {"type": "git"}},
                },
            }
        )
    )
    out = tmp_path / "distros.txt"
    result = subprocess.run(
        [
            sys.executable,
            str(REPO / "scripts" / "update-distro-data"),
            "--checkout",
            str(tmp_path),
            "--output",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stderr
    from pkgforge.model.distro_data import parse

    data = parse(out.read_text())
    assert data.names == ["jazzy"] and sorted(data.masks) == ["ros_gz", "ros_gz_sim", "xacro"]


def test_a_real_package_outside_the_old_list_is_missing_exec_depend(every_distro, workspace):
    launch = src(workspace, "distro_description", "launch/display.launch.py")
    manifest = src(workspace, "distro_description", "package.xml")
    assert findings(every_distro, "distro_description") == sorted(
        [
            ("missing-exec-depend", "launch/display.launch.py", line_of(launch, "'foxglove_bridge'")),
            ("package-not-in-distro", "package.xml", line_of(manifest, "<exec_depend>rviz</exec_depend>")),
            ("package-not-in-distro", "package.xml", line_of(manifest, "join_state_publisher")),
        ]
    )
    hints = {
        d["message"].split(">")[1].split("<")[0]: d["hint"]
        for d in by_name(every_distro, "distro_description", "package-not-in-distro")
    }
    assert hints == {
        "rviz": "declare rviz2 instead",
        "join_state_publisher": "did you mean joint_state_publisher?",
    }


@pytest.mark.triggers("PF108")
def test_gazebo_ros_on_jazzy_is_package_not_in_distro(jazzy, workspace):
    manifest = src(workspace, "distro_description", "package.xml")
    launch = src(workspace, "distro_description", "launch/display.launch.py")
    model = src(workspace, "distro_description", "urdf/robot.urdf")
    # the condition="$ROS_DISTRO == humble" dependency does not count on jazzy, $ROS_VERSION == 1 never;
    # and Gazebo Classic's diff drive plugin does not load on jazzy's Gazebo (PF701)
    assert findings(jazzy, "distro_description") == sorted(
        [
            ("gazebo-plugin-unavailable", "urdf/robot.urdf", line_of(model, "libgazebo_ros_diff_drive")),
            ("missing-exec-depend", "launch/display.launch.py", line_of(launch, "'foxglove_bridge'")),
            ("package-not-in-distro", "package.xml", line_of(manifest, "<exec_depend>gazebo_ros<")),
            ("package-not-in-distro", "package.xml", line_of(manifest, "<exec_depend>rviz</exec_depend>")),
            ("package-not-in-distro", "package.xml", line_of(manifest, "join_state_publisher")),
        ]
    )
    (gazebo,) = [
        d
        for d in by_name(jazzy, "distro_description", "package-not-in-distro")
        if "gazebo_ros" in d["message"]
    ]
    assert "not released for jazzy (released for humble)" in gazebo["message"]
    assert gazebo["hint"].startswith("use ros_gz_sim instead")


def test_a_condition_on_a_variable_of_the_users_build_counts_as_declared(every_distro, workspace):
    # husarion's panther_gazebo: <depend condition="$HUSARION_ROS_BUILD_TYPE == simulation">;
    # colcon and rosdep read the variable from the build's environment, which verify cannot know
    launch = src(workspace, "build_type_description", "launch/display.launch.py")
    assert findings(every_distro, "build_type_description") == [
        # $ROS_VERSION == 1 never holds on ROS 2: still missing
        ("missing-exec-depend", "launch/display.launch.py", line_of(launch, "'joint_state_publisher'")),
    ]


def test_an_undeclared_ros_module_import_is_missing_exec_depend_not_a_load_error(every_distro, workspace):
    # agilex limo: `import lifecycle_msgs.msg` undeclared; on the user's machine lifecycle_msgs is
    # most likely installed, so the fault is the missing exec_depend, and the file that includes
    # it loads there too
    lidar = src(workspace, "lidar_bringup", "launch/lidar.launch.py")
    assert findings(every_distro, "lidar_bringup") == [
        ("launch-unevaluated", "launch/lidar.launch.py", line_of(lidar, "import lifecycle_msgs")),
        ("missing-exec-depend", "launch/lidar.launch.py", line_of(lidar, "import lifecycle_msgs")),
    ]


def test_a_choice_whose_files_the_user_gives_is_a_warning_not_an_error(every_distro, workspace):
    # husarion panther_description: wheel_type:=custom makes wheel_config_path's default
    # config/custom.yaml, which does not exist: with that choice the user gives wheel_config_path
    launch = src(workspace, "choice_description", "launch/robot.launch.py")
    assert findings(every_distro, "choice_description") == [
        ("missing-file", "launch/robot.launch.py", line_of(launch, "default_value=PathJoinSubstitution(")),
    ]
    (warning,) = by_name(every_distro, "choice_description", "missing-file")
    assert warning["severity"] == "warning"
    assert "default of argument 'wheel_config_path' with wheel_type:=custom" in warning["message"]
    # xacro's failure on that file is the same defect: no xacro-error beside it
    assert not by_name(every_distro, "choice_description", "xacro-error")


def test_a_find_only_under_a_xacro_option_is_a_warning(every_distro, workspace):
    # franka_description: $(find franka_gazebo_bringup) inside <xacro:if value="${gazebo}">;
    # franka_gazebo_bringup depends on franka_description, so declaring it would be a cycle
    # husky_description: urdf/accessories/sick_lms1xx_mount.urdf.xacro and its $(find lms1xx), a
    # file no model of the package includes (an accessory for integrators' models)
    model = src(workspace, "gazebo_option_description", "urdf/robot.urdf.xacro")
    accessory = src(workspace, "gazebo_option_description", "urdf/accessories/lidar_mount.urdf.xacro")
    assert findings(every_distro, "gazebo_option_description") == [
        (
            "missing-exec-depend",
            "urdf/accessories/lidar_mount.urdf.xacro",
            line_of(accessory, "$(find velodyne_description)"),
        ),
        ("missing-exec-depend", "urdf/robot.urdf.xacro", line_of(model, "$(find controller_manager)")),
    ]
    mount, gazebo = by_name(every_distro, "gazebo_option_description", "missing-exec-depend")
    assert mount["severity"] == gazebo["severity"] == "warning"
    assert 'only inside <xacro:if value="$(arg gazebo)">' in gazebo["message"]
    assert "which no robot model of gazebo_option_description reads" in mount["message"]


def test_a_package_template_shipped_as_data_is_no_unknown_package(every_distro):
    # clearpath_customization installs project_bringup/ (its own package.xml: a template the user
    # copies); its launch file finds its own name, which is no typo
    assert findings(every_distro, "template_kit") == []


def test_a_dependency_the_repos_file_brings_from_source_is_no_distro_error(jazzy, workspace):
    # husarion rosbot_ros (humble): rosbot_hardware_interfaces comes from rosbot_hardware.repos
    manifest = src(workspace, "source_deps_description", "package.xml")
    assert findings(jazzy, "source_deps_description") == [
        ("package-not-in-distro", "package.xml", line_of(manifest, "<exec_depend>create_driver")),
    ]


def test_a_model_failing_only_with_a_choice_is_a_warning_that_names_it(every_distro, workspace):
    # kortex view_robot.launch.py: robot_type:=gen3_lite with the default dof:=7 (gen3_lite has 6)
    # at the include whose filename the arguments build (issue 30: every finding at its line)
    model = src(workspace, "choice_model_description", "urdf/robot.urdf.xacro")
    assert findings(every_distro, "choice_model_description") == [
        ("xacro-error", "urdf/robot.urdf.xacro", line_of(model, "<xacro:include"))
    ]
    (warning,) = by_name(every_distro, "choice_model_description", "xacro-error")
    assert warning["severity"] == "warning"
    assert warning["message"].endswith("(only with robot_type:=small)")
    assert warning["hint"].startswith("with robot_type:=small, the user must give other arguments too")


def test_a_model_failing_with_the_defaults_stays_an_error(tmp_path):
    shutil.copytree(REALWORLD / "choice_model_description", tmp_path / "src" / "choice_model_description")
    launch = tmp_path / "src" / "choice_model_description" / "launch" / "display.launch.py"
    edit(launch, "default_value='big'", "default_value='small'")
    _, report = verify_report(tmp_path, "--no-cache")
    model = tmp_path / "src" / "choice_model_description" / "urdf" / "robot.urdf.xacro"
    assert findings(report, "choice_model_description") == [
        ("xacro-error", "urdf/robot.urdf.xacro", line_of(model, "<xacro:include"))
    ]
    (error,) = by_name(report, "choice_model_description", "xacro-error")
    assert error["severity"] == "error" and "only with" not in error["message"]


def test_what_this_machine_lacks_is_no_launch_error(every_distro, workspace):
    # linorobot2: sensor:=xv11 runs xv_11_driver, cloned from source (a warning, only with it);
    # open_manipulator: rs_launch imported from realsense2_camera's share folder (not installed
    # here); realsense-ros: `ros2 component types` run while loading (no ros2 here); linorobot2's
    # EnvironmentVariable('ROS_DISTRO') with no default (set wherever ROS 2 is: distro.launch.py)
    launch = workspace / "src" / "driver_options_bringup" / "launch"
    assert findings(every_distro, "driver_options_bringup") == [
        (
            "launch-unevaluated",
            "launch/camera.launch.py",
            line_of(launch / "camera.launch.py", "import rs_launch"),
        ),
        (
            "launch-unevaluated",
            "launch/components.launch.py",
            line_of(launch / "components.launch.py", "subprocess.run("),
        ),
        (
            "unknown-package",
            "launch/lasers.launch.py",
            line_of(launch / "lasers.launch.py", "from source") + 1,  # the Node( below the comment
        ),
    ]
    (unknown,) = by_name(every_distro, "driver_options_bringup", "unknown-package")
    assert unknown["severity"] == "warning" and unknown["message"].endswith("(only with sensor:=xv11)")
    (_, program) = by_name(every_distro, "driver_options_bringup", "launch-unevaluated")
    assert "runs ros2 while loading, a program not installed here" in program["message"]


def test_an_undeclared_use_not_released_for_the_target(every_distro, jazzy, workspace):
    launch = src(workspace, "gz_use_description", "launch/display.launch.py")
    gazebo, ignition = line_of(launch, "'gazebo_ros'"), line_of(launch, "'ros_ign_gazebo'")
    assert findings(every_distro, "gz_use_description") == [
        ("missing-exec-depend", "launch/display.launch.py", gazebo),
        ("missing-exec-depend", "launch/display.launch.py", ignition),
    ]
    assert findings(jazzy, "gz_use_description") == [
        ("package-not-in-distro", "launch/display.launch.py", gazebo),
        ("package-not-in-distro", "launch/display.launch.py", ignition),
    ]


@pytest.mark.parametrize("how", ["ROS_DISTRO", "pkgforge.toml", "github", "gitlab"])
def test_the_target_distro_from_environment_config_or_ci(tmp_path, how):
    shutil.copytree(REALWORLD / "gz_use_description", tmp_path / "src" / "gz_use_description")
    package = tmp_path / "src" / "gz_use_description"
    env = {k: v for k, v in os.environ.items() if k != "ROS_DISTRO"}
    if how == "ROS_DISTRO":
        env["ROS_DISTRO"] = "jazzy"
    elif how == "pkgforge.toml":
        (tmp_path / "pkgforge.toml").write_text('[verify]\ndistro = ["jazzy", "rolling"]\n')
    elif how == "github":
        (package / ".github" / "workflows").mkdir(parents=True)
        (package / ".github" / "workflows" / "ci.yml").write_text(
            "jobs:\n  build:\n    runs-on: ubuntu-latest\n    container: ros:jazzy-ros-base\n"
        )
    else:
        (package / ".gitlab-ci.yml").write_text("build:\n  image: osrf/ros:kilted-desktop\n")
    import json

    result = run_pkgforge("verify", tmp_path, "--format", "json", "--no-cache", cwd=tmp_path, env=env)
    report = json.loads(result.stdout)
    assert [d["name"] for d in report["diagnostics"]] == ["package-not-in-distro"] * 2, result.stdout
    assert "not released for" in report["diagnostics"][0]["message"]


def test_unknown_package_is_a_name_in_no_distro(tmp_path):
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "rob_description")
    launch = package / "launch" / "display.launch.py"
    text = launch.read_text().replace("package='rviz2'", "package='rvizz2'")
    launch.write_text(text)
    status, report = verify_report(tmp_path)
    (diagnostic,) = [d for d in report["diagnostics"] if d["name"] == "unknown-package"]
    lines = launch.read_text().splitlines()
    node = max(i for i in range(line_of(launch, "'rvizz2'")) if "Node(" in lines[i]) + 1  # Node( of rvizz2
    assert (diagnostic["path"], diagnostic["line"]) == ("src/rob_description/launch/display.launch.py", node)
    assert "rviz2" in diagnostic["hint"] and "released in no ROS 2 distro" in diagnostic["message"]


# --- 4. new checks ---------------------------------------------------------------------------


@pytest.mark.triggers("PF109")
def test_find_package_undeclared(every_distro, workspace):
    cmake = src(workspace, "find_description", "CMakeLists.txt")
    manifest = src(workspace, "find_description", "package.xml")
    assert findings(every_distro, "find_description") == [
        ("find-package-undeclared", "CMakeLists.txt", line_of(cmake, "find_package(xacro"))
    ]
    (diagnostic,) = by_name(every_distro, "find_description", "find-package-undeclared")
    declared = line_of(manifest, "<exec_depend>xacro")
    assert diagnostic["hint"] == f"change package.xml:{declared} to <depend>xacro</depend>"


@pytest.mark.triggers("PF313", "PF314")
def test_node_arguments_string_and_rsp_model_argument(every_distro, workspace):
    launch = src(workspace, "args_description", "launch/display.launch.py")
    assert findings(every_distro, "args_description") == [
        ("node-arguments-string", "launch/display.launch.py", line_of(launch, "package='rviz2'")),
        (
            "rsp-model-argument",
            "launch/display.launch.py",
            line_of(launch, "package='robot_state_publisher'"),
        ),
    ]
    (string,) = by_name(every_distro, "args_description", "node-arguments-string")
    assert string["hint"] == "write arguments=['--display-config', 'view.rviz']"
    (rsp,) = by_name(every_distro, "args_description", "rsp-model-argument")
    assert rsp["severity"] == "warning"


def test_rsp_model_argument_is_an_error_on_rolling(workspace):
    status, report = verify_report(
        workspace, "--no-cache", "--distro", "rolling", "--select", "rsp-model-argument"
    )
    assert [d["severity"] for d in report["diagnostics"]] == ["error"]


@pytest.mark.triggers("PF209")
def test_package_not_installed_from_the_install_base(tmp_path, variants_workspace):
    """A package that failed to build is absent from the install base: an error, not a clean report.
    The session's built variants are the install base; v_jazzy is in it, broken_description not."""
    (tmp_path / "src").mkdir()
    shutil.copytree(variants_workspace / "src" / "v_jazzy", tmp_path / "src" / "v_jazzy")
    broken = new_package(tmp_path, "broken_description")
    status, report = verify_report(
        tmp_path, "--install-base", str(variants_workspace / "install"), "--no-cache"
    )
    assert status == 1
    assert [(d["package"], d["name"], d["path"], d["line"]) for d in report["diagnostics"]] == [
        (
            "broken_description",
            "package-not-installed",
            "src/broken_description/package.xml",
            line_of(broken / "package.xml", "<name>"),
        )
    ]
    assert "colcon" in report["diagnostics"][0]["hint"]


# --- 5. precision ----------------------------------------------------------------------------


@pytest.mark.triggers("PF303")
def test_one_defect_one_diagnostic_and_user_paths(every_distro, workspace):
    launch = src(workspace, "precise_description", "launch/display.launch.py")
    manifest = src(workspace, "precise_description", "package.xml")
    # a typo in the model path: missing-file only (no xacro-error); the same missing config on two
    # lines: one diagnostic; controllers, the gz plugin, RViz classes and a script's import are uses
    assert findings(every_distro, "precise_description") == [
        ("missing-file", "launch/display.launch.py", line_of(launch, "robt.urdf.xacro")),
        ("missing-file", "launch/display.launch.py", line_of(launch, "gone.rviz")),
        ("unused-exec-depend", "package.xml", line_of(manifest, "urdf_tutorial")),
    ]
    (gone,) = [
        d for d in by_name(every_distro, "precise_description", "missing-file") if "gone.rviz" in d["message"]
    ]
    second = line_of(launch, "gone.rviz") + 2
    assert gone["message"].endswith(f"(and 1 more in this file: line {second})")
    assert all("pkgforge-tree-" not in d["message"] + d["hint"] for d in every_distro["diagnostics"])


def test_xacro_error_messages_name_the_users_file(tmp_path):
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "rob_description")
    model = package / "urdf" / "rob_description.urdf.xacro"
    model.write_text(model.read_text().replace("urdf/macros.xacro", "urdf/macroz.xacro"))
    status, report = verify_report(tmp_path, "--no-cache")
    (diagnostic,) = report["diagnostics"]
    assert diagnostic["name"] == "xacro-error"
    assert "pkgforge-tree-" not in diagnostic["message"] and "urdf/macroz.xacro" in diagnostic["message"]


def test_folder_name_mismatch_is_info(tmp_path):
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "rob_description")
    package.rename(package.parent / "robot_folder")
    status, report = verify_report(tmp_path, "--no-cache")
    assert status == 0
    assert [(d["name"], d["severity"]) for d in report["diagnostics"]] == [("folder-name-mismatch", "info")]


# --- 6. Lyrical ------------------------------------------------------------------------------


def test_new_defaults_to_ros_distro_else_the_newest_lts(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROS_DISTRO"}
    assert run_pkgforge("new", "a_rob", *MAINTAINER, "--ci", "github", cwd=tmp_path, env=env).returncode == 0
    assert (
        "container: ros:lyrical"
        in (tmp_path / "a_rob" / ".github" / "workflows" / "pkgforge.yml").read_text()
    )
    env["ROS_DISTRO"] = "humble"
    assert run_pkgforge("new", "b_rob", *MAINTAINER, "--ci", "github", cwd=tmp_path, env=env).returncode == 0
    assert (
        "container: ros:humble" in (tmp_path / "b_rob" / ".github" / "workflows" / "pkgforge.yml").read_text()
    )


# --- false errors measured on real public description packages (p1-review) -------------------
# Each fixture is a hand-written minimal package with the shape seen in real packages.


def test_rviz_own_displays_need_no_dependency_of_their_own(every_distro):
    """An RViz config whose displays are RViz's own (rviz_common, rviz_default_plugins), opened by
    another package's launch file (urdf_launch runs rviz2): no missing-exec-depend."""
    assert findings(every_distro, "rviz_config_description") == []


@pytest.mark.triggers("PF407")
def test_a_declared_packages_xacro_include_absent_here_is_info(every_distro, workspace):
    """A model including a macro file of a declared, released package that is not installed here
    (pmb2 → pal_urdf_utils, turtlebot4 → irobot_create_description): model-unevaluated, at the
    include, and no xacro-error."""
    model = src(workspace, "absent_include_description", "urdf/robot.urdf.xacro")
    assert findings(every_distro, "absent_include_description") == [
        ("model-unevaluated", "urdf/robot.urdf.xacro", line_of(model, "_d435.urdf.xacro"))
    ]
    (info,) = by_name(every_distro, "absent_include_description", "model-unevaluated")
    assert info["severity"] == "info" and "realsense2_description" in info["message"]


def test_a_template_argument_left_empty_and_pyyaml_are_no_unknown_package(every_distro, workspace):
    """A bringup template whose description package is an argument defaulting to '' (abb_bringup),
    and a file read statically (its module package is absent here) that imports PyYAML."""
    moveit = src(workspace, "template_bringup", "launch/moveit.launch.py")
    assert findings(every_distro, "template_bringup") == [
        ("launch-unevaluated", "launch/moveit.launch.py", line_of(moveit, "moveit_configs_utils"))
    ]


def test_a_launch_name_newer_than_jazzy(every_distro, jazzy, workspace):
    """PathSubstitution (ros2_control_demos' master, for Rolling) is not in Jazzy's launch: an info
    when the package may target a later distro, ROS's own ImportError when it targets Jazzy."""
    show = src(workspace, "newer_api_bringup", "launch/show.launch.py")
    line = line_of(show, "import PathSubstitution")
    assert findings(every_distro, "newer_api_bringup") == [
        ("unsupported-launch-api", "launch/show.launch.py", line)
    ]
    assert findings(jazzy, "newer_api_bringup") == [("launch-load-error", "launch/show.launch.py", line)]


def test_a_folder_only_uninstalled_files_refer_to_is_no_error(every_distro):
    """xacro/ kept next to the URDF generated from it (a Unitree Go2 description): only xacro/'s own
    files refer to xacro/ and meshes/, nothing installed does; each folder is the usual warning
    for an uninstalled resource folder, not an error."""
    found = {
        d["path"].removeprefix("src/xacro_source_description/"): d["severity"]
        for d in by_name(every_distro, "xacro_source_description", "directory-not-installed")
    }
    assert findings(every_distro, "xacro_source_description") == [
        ("directory-not-installed", "meshes", None),
        ("directory-not-installed", "xacro", None),
    ]
    assert found == {"meshes": "warning", "xacro": "warning"}


@pytest.mark.triggers("PF317")
def test_an_environment_variable_the_robot_setup_exports(every_distro, workspace, tmp_path):
    """os.environ['TURTLEBOT3_MODEL'] (TurtleBot3) and os.getenv('LINOROBOT2_BASE') in a path
    (linorobot2), not set here: launch-environment-unset (info) instead of launch-load-error and
    missing-file; with the variables set, the files are checked and clean."""
    robot = src(workspace, "environment_bringup", "launch/robot.launch.py")
    description = src(workspace, "environment_bringup", "launch/description.launch.py")
    assert findings(every_distro, "environment_bringup") == [
        ("launch-environment-unset", "launch/description.launch.py", line_of(description, "f'{base}.urdf'")),
        ("launch-environment-unset", "launch/robot.launch.py", line_of(robot, "os.environ[")),
    ]
    shutil.copytree(workspace / "src" / "environment_bringup", tmp_path / "src" / "environment_bringup")
    env = {**os.environ, "PKGFORGE_TEST_ROBOT_MODEL": "small", "PKGFORGE_TEST_ROBOT_BASE": "small"}
    result = run_pkgforge("verify", tmp_path, "--format", "json", "--no-cache", cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stdout + result.stderr


def test_an_undeclared_find_is_one_diagnostic_without_pkgforges_folders(every_distro, workspace):
    """$(find X) of a real package not declared (Clearpath): missing-exec-depend only, not also a
    xacro-error at the same line; of a package released nowhere (Doosan's old name): xacro-error,
    whose message names no folder of pkgforge's tree."""
    base = src(workspace, "undeclared_find_description", "urdf/base.urdf.xacro")
    arm = src(workspace, "undeclared_find_description", "urdf/arm.urdf.xacro")
    assert findings(every_distro, "undeclared_find_description") == [
        ("missing-exec-depend", "urdf/base.urdf.xacro", line_of(base, "$(find realsense2_description)")),
        ("xacro-error", "urdf/arm.urdf.xacro", line_of(arm, "$(find undeclared_find_old_name)")),
    ]
    (error,) = by_name(every_distro, "undeclared_find_description", "xacro-error")
    assert "searching" not in error["message"] and error["message"].count("not found") == 1


# --- a model whose includes are built from xacro:args its launch files always set (Kinova's gen3) ----


def dof_workspace(tmp_path: Path) -> Path:
    """dof_description (arm.xacro: xacro:arg dof default '', include arms/$(arg dof)dof/...) and
    dof_bringup (a launch running xacro on it with dof:=7)."""
    for package in ("dof_description", "dof_bringup"):
        shutil.copytree(REALWORLD / package, tmp_path / "src" / package)
    return tmp_path


@pytest.mark.triggers("PF406")
def test_empty_default_xacro_args_are_info_and_the_launch_run_counts(every_distro, workspace):
    """On its own with its defaults, arm.xacro includes arms/dof/urdf/...: no defect of the model,
    a value its launch files give. PF406 names the argument at its declaration (not prefix, also
    empty but not the cause); the launch's run with dof:=7 is clean."""
    model = src(workspace, "dof_description", "robots/arm.xacro")
    assert findings(every_distro, "dof_description") == [
        ("model-needs-arguments", "robots/arm.xacro", line_of(model, '<xacro:arg name="dof"'))
    ]
    (info,) = by_name(every_distro, "dof_description", "model-needs-arguments")
    assert info["severity"] == "info" and info["code"] == "PF406"
    assert "xacro argument(s) dof (empty default" in info["message"] and "prefix" not in info["message"]
    assert findings(every_distro, "dof_bringup") == []


def test_empty_default_xacro_args_with_build(tmp_path):
    root = dof_workspace(tmp_path)
    status, report = verify_report(root, "--build", "--no-cache")
    model = root / "src/dof_description/robots/arm.xacro"
    assert status == 0
    assert findings(report, "dof_description") == [
        ("model-needs-arguments", "robots/arm.xacro", line_of(model, '<xacro:arg name="dof"'))
    ]
    assert findings(report, "dof_bringup") == []


@pytest.mark.parametrize("given, shown", [(" dof:=9", "arm.xacro dof:=9: "), ("", "arm.xacro: ")])
def test_the_launchs_arguments_failing_are_an_error_at_the_launch_line(tmp_path, given, shown):
    """dof:=9 names a folder that does not exist, and a launch giving no dof includes arms/dof/...:
    the launch's xacro run is the truth, PF308 at the launch line (not in pkgforge's tree), with
    the arguments it gave."""
    root = dof_workspace(tmp_path)
    launch = root / "src/dof_bringup/launch/arm.launch.py"
    edit(launch, "' dof:=7'", f"'{given}'")
    status, report = verify_report(root, "--no-cache")
    assert status == 1
    assert findings(report, "dof_bringup") == [
        ("xacro-error", "launch/arm.launch.py", line_of(launch, "Command("))
    ]
    (error,) = by_name(report, "dof_bringup", "xacro-error")
    assert error["code"] == "PF308" and shown in error["message"] and "No such file" in error["message"]
    assert [d["code"] for d in report["diagnostics"] if d["package"] == "dof_description"] == ["PF406"]


@pytest.mark.parametrize(
    "old, new",
    [
        ('name="dof" default=""', 'name="dof" default="6"'),  # a default naming no folder
        ("arms/$(arg dof)dof/urdf/arm_macro.xacro", "arms/7dof/urdf/arm_macros.xacro"),  # a typo, args unused
    ],
)
def test_a_model_failing_whatever_its_empty_arguments_is_still_an_error(tmp_path, old, new):
    root = dof_workspace(tmp_path)
    model = root / "src/dof_description/robots/arm.xacro"
    edit(model, old, new)
    status, report = verify_report(root, "--no-cache")
    assert status == 1
    assert findings(report, "dof_description") == [
        ("xacro-error", "robots/arm.xacro", line_of(model, "<xacro:include"))
    ]


@pytest.mark.triggers("PF605")
def test_a_joint_is_placed_at_its_urdf_tag_not_its_ros2_control_mention(every_distro, workspace):
    """Dobot's cra_description: a CAD export writes `<joint` and `name=` on lines of their own, and
    a ros2_control block names the same joints (no type=). The finding is at the URDF joint."""
    model = src(workspace, "exported_joint_description", "urdf/arm.urdf.xacro")
    first = line_of(model, '    name="joint1"') - 1  # the `<joint` line above its name
    second = line_of(model, 'type="revolute" name="joint2"')
    # (one cause, one diagnostic: both joints' velocity="0", at the first, naming both lines)
    assert findings(every_distro, "exported_joint_description") == [
        ("joint-limit-invalid", "urdf/arm.urdf.xacro", first)
    ]
    (grouped,) = by_name(every_distro, "exported_joint_description", "joint-limit-invalid")
    assert grouped["message"].endswith(f": joint1, joint2 (lines {first}, {second})"), grouped["message"]
