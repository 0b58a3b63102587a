"""Real robots from the `example-robot-data` wheel (PyPI): real URDFs, real meshes, no errors.

The wheel (131 MB) is downloaded once into a cache (PKGFORGE_TEST_CACHE, default
~/.cache/pkgforge-tests); only the robots used here are extracted. Its cmeel
prefix is a genuine ament prefix, so it stands in for an installed package,
as /opt/ros would.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from conftest import MAINTAINER, run_pkgforge
from lxml import etree

pytestmark = pytest.mark.slow

VERSION = "6.0.0"
ROBOTS = {  # wrapper package → URDF inside the wheel's robots/ folder
    "panda_wrap_description": "panda_description/urdf/panda.urdf",
    "ur5_wrap_description": "ur_description/urdf/ur5_robot.urdf",
    "talos_wrap_description": "talos_data/robots/talos_full_v2.urdf",
    "go2_wrap_description": "go2_description/urdf/go2.urdf",
}
PREFIX_IN_WHEEL = "cmeel.prefix/"


@pytest.fixture(scope="session")
def robot_prefix() -> Path:
    cache = Path(os.environ.get("PKGFORGE_TEST_CACHE", Path.home() / ".cache" / "pkgforge-tests"))
    cache.mkdir(parents=True, exist_ok=True)
    wheels = sorted(cache.glob(f"example_robot_data-{VERSION}-*.whl"))
    if not wheels:
        result = subprocess.run(
            [
                sys.executable,
                "-m",
                "pip",
                "download",
                "--no-deps",
                "-q",
                "-d",
                str(cache),
                f"example-robot-data=={VERSION}",
            ],
            capture_output=True,
            text=True,
            timeout=900,
        )
        wheels = sorted(cache.glob(f"example_robot_data-{VERSION}-*.whl"))
        if not wheels:
            pytest.skip(f"example-robot-data could not be downloaded: {result.stderr[-500:]}")
    prefix = cache / f"example-robot-data-{VERSION}"
    folders = {ROBOTS[name].split("/")[0] for name in ROBOTS}
    marker = prefix / "share/ament_index/resource_index/packages/example-robot-data"
    if not marker.exists() or not all(
        (prefix / "share/example-robot-data/robots" / f).is_dir() for f in folders
    ):
        with zipfile.ZipFile(wheels[0]) as wheel:
            wanted = [
                n
                for n in wheel.namelist()
                if n.startswith(PREFIX_IN_WHEEL + "share/")
                and (
                    "/ament_index/" in n
                    or n.endswith("example-robot-data/package.xml")
                    or any(f"/robots/{f}/" in n for f in folders)
                )
            ]
            for name in wanted:
                target = prefix / name[len(PREFIX_IN_WHEEL) :]
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(wheel.read(name))
    return prefix


def root_link(urdf: bytes) -> str:
    robot = etree.fromstring(urdf)
    children = {j.find("child").get("link") for j in robot.findall("joint")}
    return next(link.get("name") for link in robot.findall("link") if link.get("name") not in children)


def test_real_robots_verify_without_errors(tmp_path, robot_prefix):
    (tmp_path / "src").mkdir()
    for name, relative in ROBOTS.items():
        assert run_pkgforge("new", name, *MAINTAINER, cwd=tmp_path).returncode == 0
        package = tmp_path / "src" / name
        urdf = (robot_prefix / "share/example-robot-data/robots" / relative).read_bytes()
        (package / "urdf" / f"{name}.urdf.xacro").write_bytes(urdf)
        (package / "meshes" / "arm.stl").unlink()  # the scaffold's mesh: the robot brings its own
        manifest = package / "package.xml"
        manifest.write_text(
            manifest.read_text().replace(
                "  <exec_depend>joint_state_publisher</exec_depend>",
                "  <exec_depend>example-robot-data</exec_depend>\n  <exec_depend>joint_state_publisher</exec_depend>",
            )
        )
        rviz = package / "rviz" / "display.rviz"
        rviz.write_text(rviz.read_text().replace("Fixed Frame: base_link", f"Fixed Frame: {root_link(urdf)}"))
    env = dict(os.environ, AMENT_PREFIX_PATH=str(robot_prefix))
    result = run_pkgforge("verify", "--format", "json", cwd=tmp_path, env=env)
    assert "Traceback" not in result.stderr
    report = json.loads(result.stdout)
    # root-link-inertia (PF604, a warning) is true of several of them: KDL ignores the root's inertia
    problems = [
        (d["package"], d["code"])
        for d in report["diagnostics"]
        if d["severity"] != "info" and d["code"] != "PF604"
    ]
    # a real defect in the wheel: TALOS writes package:///example-robot-data/... (three slashes)
    talos = [
        d
        for d in report["diagnostics"]
        if d["package"] == "talos_wrap_description" and d["code"] not in ("PF604", "PF410", "PF701")
    ]
    assert talos and all(d["code"] == "PF402" and "names no package" in d["message"] for d in talos)
    # and ROS 1's Gazebo Classic plugins (gazebo_ros_pkgs' noetic-devel), which load in no ROS 2
    # Gazebo: TALOS's and UR5's gazebo_ros_control, TALOS's openni_kinect camera
    classic = sorted(
        (d["package"], d["message"].split("'")[1]) for d in report["diagnostics"] if d["code"] == "PF701"
    )
    assert classic == [
        ("talos_wrap_description", "libgazebo_ros_control.so"),
        ("talos_wrap_description", "libgazebo_ros_openni_kinect.so"),
        ("ur5_wrap_description", "libgazebo_ros_control.so"),
    ]
    # and a true colour: rgbd_link writes DarkGrey as 0.5 grey, urdfdom keeps <robot>'s DarkGrey (0.2)
    (colour,) = [d for d in report["diagnostics"] if d["code"] == "PF410"]
    assert colour["package"] == "talos_wrap_description" and colour["severity"] == "warning"
    assert colour["message"].startswith("link 'rgbd_link': material 'DarkGrey' is given another colour")
    assert len({d["line"] for d in talos}) == len(talos)  # each at its own <mesh> line
    # and UR5's wrist_3_link inertia, wrong upstream (ros-industrial/universal_robot#426): PF610
    assert sorted(p for p in problems if p[0] != "talos_wrap_description") == [
        ("ur5_wrap_description", "PF610"),
        ("ur5_wrap_description", "PF701"),
    ]
    # the meshes were resolved in the installed package, not skipped
    explain = run_pkgforge(
        "verify",
        "--explain-model",
        "src/panda_wrap_description/urdf/panda_wrap_description.urdf.xacro",
        cwd=tmp_path,
        env=env,
    )
    assert "✓ package://example-robot-data/robots/panda_description/meshes/visual/link0.dae" in explain.stdout
    assert "✗" not in explain.stdout
