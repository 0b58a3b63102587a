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
