"""`pkgforge view` and `verify --artifacts`: real models rendered headless, measured on the images."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from conftest import FIXTURES, new_package, run_pkgforge

pytest.importorskip("trimesh", reason="the `view` extra: pip install -e '.[view]'")
np = pytest.importorskip("numpy")
Image = pytest.importorskip("PIL.Image")

VIEWS = ("front", "side", "top", "iso")
# the model's axes each view shows across and up (iso: measured against its projected box)
AXES = {"front": (1, 2), "side": (0, 2), "top": (1, 0)}


def silhouette(path: Path, area) -> tuple[int, int]:
    """Width and height in pixels of everything not background inside the drawing area."""
    pixels = np.asarray(Image.open(path).convert("RGB"))
    x0, y0, x1, y1 = area
    inside = pixels[y0:y1, x0:x1]
    drawn = np.any(inside != 255, axis=2)
    assert drawn.any(), f"{path.name} is blank"
    ys, xs = np.nonzero(drawn)
    return xs.max() - xs.min() + 1, ys.max() - ys.min() + 1


def expected_bounds(model: Path, resolve) -> tuple:
    """The model's bounds from the pure-Python numbers (robot.py, physics.py), not the renderer's."""
    from pkgforge.urdf import physics, robot

    data = robot.process_model(str(model), {})
    assert data["status"] == "ok", data
    return physics.world_bounds(data["robot"], resolve)


def assert_views_match(out: Path, stem: str, bounds) -> None:
    from pkgforge.view.raster import project

    index = json.loads((out / "view.json").read_text())
    entry = next(e for e in index["models"] if e["images"] and e["images"][0]["file"].startswith(stem))
    low, high = (np.asarray(b) for b in bounds)
    extent = high - low
    for info in entry["images"]:
        width, height = silhouette(out / info["file"], info["area"])
        measured = np.array([width, height]) / info["pixels_per_metre"]
        if info["view"] in AXES:
            wanted = extent[list(AXES[info["view"]])]
            assert np.allclose(measured, wanted, rtol=0.10, atol=2 / info["pixels_per_metre"]), (
                info["view"],
                measured,
                wanted,
            )
        else:  # the box's projected corners bound the silhouette from outside
            corners = np.array(
                [[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])]
            )
            screen = project(corners, info["view"])[:, :2]
            box = screen.max(axis=0) - screen.min(axis=0)
            assert np.all(measured <= box * 1.10) and np.all(measured >= box * 0.6), (measured, box)


def test_the_scaffold_renders_in_every_view(tmp_path):
    new_package(tmp_path, "demo_description")
    package = tmp_path / "demo_description"  # `new` outside a workspace: ./NAME
    out = tmp_path / "out"
    result = run_pkgforge("view", ".", "-o", out, "--no-frame", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    for view in VIEWS:
        assert (out / f"demo_description-demo_description-{view}.png").is_file()

    # the size `--explain-model` gives (xacro in verify's worker, pure-Python bounds): not the renderer's
    model = package / "urdf" / "demo_description.urdf.xacro"
    explained = run_pkgforge("verify", package, "--explain-model", model, cwd=tmp_path)
    line = next(each for each in explained.stdout.splitlines() if each.startswith("size: "))
    extent = [float(v) for v in line.split(" m ")[0].removeprefix("size: ").split(" × ")]
    assert_views_match(out, "demo_description-", ((0.0, 0.0, 0.0), tuple(extent)))
    svg = next(out.glob("*-tree.svg")).read_text()
    assert "arm_joint (revolute)" in svg and "axis " in svg


ERD_ROBOTS = {
    "panda": "panda_description/urdf/panda.urdf",
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "go2": "go2_description/urdf/go2.urdf",
}


@pytest.mark.parametrize("name", sorted(ERD_ROBOTS))
def test_example_robot_data_renders_in_every_view(tmp_path, name):
    from test_physics import erd_share

    share = erd_share()
    model = share / "robots" / ERD_ROBOTS[name]
    out = tmp_path / "out"
    result = run_pkgforge("view", model, "-o", out, "--no-frame", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr

    def resolve(uri):
        prefix = "package://example-robot-data/"
        return share / uri[len(prefix) :] if uri.startswith(prefix) else None

    assert_views_match(out, "example-robot-data-", expected_bounds(model, resolve))


def _physics_package(tmp_path: Path) -> Path:
    shutil.copytree(FIXTURES / "physics" / "phys_description", tmp_path / "src" / "phys_description")
    return tmp_path / "src" / "phys_description"


def test_a_moved_joint_gives_a_different_image(tmp_path):
    _physics_package(tmp_path)
    images = {}
    for label, extra in (("zero", []), ("moved", ["--joint", "shoulder:=0.7"])):
        out = tmp_path / label
        result = run_pkgforge("view", ".", "-o", out, *extra, cwd=tmp_path)
        assert result.returncode == 0, result.stderr
        images[label] = np.asarray(Image.open(out / "phys_description-robot-top.png"))
        assert json.loads((out / "view.json").read_text())["models"][0]["joints"] == (
            {"shoulder": 0.7} if extra else {}
        )
    assert (images["zero"] != images["moved"]).any()


def test_frame_is_drawn_by_default(tmp_path):
    _physics_package(tmp_path)
    for label, extra in (("frame", []), ("bare", ["--no-frame"])):
        assert run_pkgforge("view", ".", "-o", tmp_path / label, *extra, cwd=tmp_path).returncode == 0
    framed = np.asarray(Image.open(tmp_path / "frame" / "phys_description-robot-iso.png"))
    bare = np.asarray(Image.open(tmp_path / "bare" / "phys_description-robot-iso.png"))
    red = (framed[..., 0] > 200) & (framed[..., 1] < 60) & (framed[..., 2] < 60)
    assert red.any() and not ((bare[..., 0] > 200) & (bare[..., 1] < 60) & (bare[..., 2] < 60)).any()


def test_unknown_joint_is_a_one_line_error(tmp_path):
    _physics_package(tmp_path)
    result = run_pkgforge("view", ".", "-o", tmp_path / "out", "--joint", "elbow:=1", cwd=tmp_path)
    assert result.returncode == 2
    assert "--joint elbow: no processed model has such a joint" in result.stderr
    assert "Traceback" not in result.stderr
    bad = run_pkgforge("view", ".", "--joint", "shoulder=1", cwd=tmp_path)
    assert bad.returncode == 2 and "--joint 'shoulder=1' is not NAME:=VALUE" in bad.stderr


def test_verify_artifacts_writes_the_images_and_a_summary(tmp_path):
    _physics_package(tmp_path)
    out = tmp_path / "artifacts"
    result = run_pkgforge("verify", ".", "--artifacts", out, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [f"phys_description-robot-{v}.png" for v in VIEWS]
        + ["phys_description-robot-tree.svg", "summary.md", "view.json"]
    )
    summary = (out / "summary.md").read_text()
    assert "![front](phys_description-robot-front.png)" in summary
    assert "size 0.2 x 0.2 x 0.4 m" in summary


def test_without_the_view_extra_verify_still_works_and_says_how_to_install(tmp_path):
    import os

    _physics_package(tmp_path)
    hidden = tmp_path / "no-numpy"
    (hidden / "numpy").mkdir(parents=True)
    (hidden / "numpy" / "__init__.py").write_text("raise ImportError('hidden by the test')\n")
    env = {**os.environ, "PYTHONPATH": str(hidden)}
    out = tmp_path / "artifacts"
    result = run_pkgforge("verify", ".", "--artifacts", out, cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "pip install 'ros-pkgforge[view]'" in result.stderr and "Traceback" not in result.stderr
    assert sorted(p.name for p in out.iterdir()) == [
        "phys_description-robot-tree.svg",
        "summary.md",
        "view.json",
    ]
    view = run_pkgforge("view", ".", "-o", tmp_path / "out", cwd=tmp_path, env=env)
    assert view.returncode == 2 and "pip install 'ros-pkgforge[view]'" in view.stderr
    assert not (tmp_path / "out").exists()


# --- issue 30: one set of images per distinct model, short names, numbers for people ------------

ARGUED_MODEL = """\
<?xml version="1.0"?>
<robot name="argued" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="sim" default="false"/>
  <xacro:arg name="arm" default="short"/>
  <xacro:property name="length" value="${0.6 if '$(arg arm)' == 'long' else 0.3}"/>
  <material name="black"><color rgba="0 0 0 1"/></material>
  <link name="base_link">
    <visual><geometry><box size="0.2 0.2 0.1"/></geometry><material name="black"/></visual>
  </link>
  <link name="arm_link">
    <visual><geometry><box size="0.05 0.05 ${length}"/></geometry><material name="black"/></visual>
  </link>
  <joint name="arm_joint" type="revolute">
    <parent link="base_link"/><child link="arm_link"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="${-pi/4}" upper="${pi}" velocity="${pi/2}" effort="10"/>
  </joint>
</robot>
"""

ARGUED_LAUNCH = """\
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import Command, LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    model = PathJoinSubstitution([FindPackageShare('{package}'), 'urdf', '{model}'])
    description = ParameterValue(Command(['xacro ', model, ' sim:=', LaunchConfiguration('sim'),
                                          ' arm:=', LaunchConfiguration('arm')]), value_type=str)
    return LaunchDescription([
        DeclareLaunchArgument('sim', default_value='false', choices=['true', 'false']),
        DeclareLaunchArgument('arm', default_value='short', choices=['short', 'long']),
        Node(package='robot_state_publisher', executable='robot_state_publisher',
             parameters=[{{'robot_description': description}}]),
    ])
"""


def _argued_package(tmp_path: Path, package: str, model: str) -> Path:
    (tmp_path / "src").mkdir()
    folder = new_package(tmp_path, package)
    (folder / "launch" / "display.launch.py").unlink()
    for old in (folder / "urdf").iterdir():
        old.unlink()
    (folder / "urdf" / model).write_text(ARGUED_MODEL)
    (folder / "launch" / "argued.launch.py").write_text(ARGUED_LAUNCH.format(package=package, model=model))
    return folder


def test_argument_combinations_of_one_model_share_its_images(tmp_path):
    """Issue 30: sim:=true/false changes nothing the pictures show, arm:=long does: two sets of
    images (`<package>-<model>[-<n>]-<view>.png`), each listing the arguments that gave it in
    view.json and summary.md; numbers in the tree rounded for people; black parts shaded."""
    _argued_package(tmp_path, "argued_description", "argued.urdf.xacro")
    out = tmp_path / "out"
    result = run_pkgforge("view", ".", "-o", out, "--no-frame", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    stems = ["argued_description-argued", "argued_description-argued-2"]
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [f"{stem}-{view}.png" for stem in stems for view in VIEWS]
        + [f"{stem}-tree.svg" for stem in stems]
        + ["summary.md", "view.json"]
    )
    entries = json.loads((out / "view.json").read_text())["models"]
    arguments = {e["tree"]: e["arguments"] for e in entries}
    assert arguments == {
        "argued_description-argued-tree.svg": [
            {"arm": "short", "sim": "false"},
            {"arm": "short", "sim": "true"},
        ],
        "argued_description-argued-2-tree.svg": [
            {"arm": "long", "sim": "false"},
            {"arm": "long", "sim": "true"},
        ],
    }
    summary = (out / "summary.md").read_text()
    assert "xacro arguments: `arm:=long` `sim:=false`; `arm:=long` `sim:=true`" in summary
    svg = (out / "argued_description-argued-tree.svg").read_text()
    assert "[-0.785, 3.14] v1.57 e10" in svg and "3.1415" not in svg

    # black boxes: their visible faces in the iso view are shades, not one flat colour
    iso = np.asarray(Image.open(out / "argued_description-argued-iso.png").convert("RGB"))
    area = entries[0]["images"][3]["area"]
    inside = iso[area[1] : area[3], area[0] : area[2]].reshape(-1, 3)
    drawn = inside[np.any(inside != 255, axis=1)]
    shades = {tuple(p) for p in drawn}
    luma = drawn @ np.array([0.299, 0.587, 0.114])
    assert len(shades) >= 3 and luma.max() - luma.min() >= 30, sorted(shades)[:10]


def test_image_names_stay_within_100_characters(tmp_path):
    """Issue 30: a long package name and a long model file name still give file names of at most
    100 characters, distinct for the two geometries."""
    package = "a_very_long_robot_description_package_name_for_a_manipulator_arm_description"
    model = "a_very_long_model_file_name_with_every_option_spelled_out.urdf.xacro"
    _argued_package(tmp_path, package, model)
    out = tmp_path / "out"
    result = run_pkgforge("view", ".", "-o", out, "--no-frame", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    names = sorted(p.name for p in out.iterdir())
    assert len(names) == 12 and all(len(n) <= 100 for n in names), names
    assert len({n for n in names if n.endswith("-front.png")}) == 2
