"""Directory walks never follow a link cycle, never leave the tree, and stop at bounded depth
(folder-not-walked, PF903) without Python recursion, in every verify mode (issue 11 item 6)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from conftest import hand_made_install, run_pkgforge, verify_report

# a subprocess timeout is a hang guard here, not a timing assert: before the fix these never ended
HANG_GUARD = 240


@pytest.fixture
def nest(request):
    """nest(folder, depth): depth nested folders d/d/d/... under folder, removed again after the
    test without recursion (pytest's own clean-up of old temporary folders recurses, and would
    fail on them in every later run, anyone's)."""
    made = []

    def make(folder: Path, depth: int) -> Path:
        path = folder
        for _ in range(depth):
            path = path / "d"
            path.mkdir()
            made.append(path)
        return path

    yield make
    for path in reversed(made):
        for entry in os.scandir(path):
            if not entry.is_dir(follow_symlinks=False):
                os.unlink(entry.path)
        os.rmdir(path)


def codes(report: dict, minimum: str = "warning") -> list[tuple]:
    order = ["info", "warning", "error"]
    return sorted(
        (d["code"], d["path"])
        for d in report["diagnostics"]
        if order.index(d["severity"]) >= order.index(minimum)
    )


def test_link_cycles_in_a_real_build_end_and_deep_nesting_is_named(package, nest):
    workspace = package.parent.parent
    os.symlink(".", package / "meshes" / "self")
    os.symlink(".", package / "launch" / "a")
    os.symlink(".", package / "launch" / "b")  # two links to '.': 2**40 paths when followed
    nest(package / "urdf", 70)  # installed too: pkgforge's copy of the build reaches its walks' bound
    result = run_pkgforge("verify", "--build", "--format", "json", cwd=workspace, timeout=HANG_GUARD)
    assert "Traceback" not in result.stderr, result.stderr
    assert result.returncode == 0, result.stdout + result.stderr
    import json

    assert [(d["code"], d["path"]) for d in json.loads(result.stdout)["diagnostics"]] == [
        ("PF903", "src/rob_description/urdf" + "/d" * 63)
    ]


def test_link_cycles_and_links_out_of_an_install_base(package, tmp_path):
    workspace = package.parent.parent
    share = hand_made_install(package)
    os.symlink(".", share / "launch" / "a")
    os.symlink("..", share / "launch" / "up")
    # a folder outside the install tree: its launch file must never be loaded
    outside = tmp_path / "elsewhere"  # beside the workspace's src/, outside its install/
    outside.mkdir()
    (outside / "evil.launch.py").write_text("raise RuntimeError('walked out of the tree')\n")
    os.symlink(outside, share / "launch" / "out")
    status, report = verify_report(workspace, "--install-base", "install", "--select", "PF3,PF9")
    assert not any("walked out of the tree" in d["message"] for d in report["diagnostics"])
    assert codes(report) == [], report["diagnostics"]


@pytest.mark.triggers("PF903")
def test_deep_nesting_in_the_package_is_reported_not_a_recursion_error(package, nest):
    deepest = nest(package / "meshes", 1000)
    (deepest / "part.stl").write_bytes(b"solid x\nendsolid x\n")
    result = run_pkgforge(
        "verify", "--format", "json", "--no-cache", cwd=package.parent.parent, timeout=HANG_GUARD
    )
    assert "Traceback" not in result.stderr and "RecursionError" not in result.stdout, result.stderr
    assert result.returncode == 0, result.stdout + result.stderr
    import json

    report = json.loads(result.stdout)
    (diagnostic,) = report["diagnostics"]
    assert diagnostic["code"] == "PF903" and diagnostic["severity"] == "warning"
    assert diagnostic["path"] == "src/rob_description/meshes" + "/d" * 63  # 64 folders below the package
    assert "64 deep" in diagnostic["message"]


@pytest.mark.parametrize("layout", ["merged", "isolated"])
def test_deep_nesting_in_an_install_base_is_reported(package, nest, layout):
    # pkgforge resolves an install base in its own copy: the copy must reach as deep as the walks
    # over it do, or the folder past their bound is a link out, silently not walked
    workspace = package.parent.parent
    share = hand_made_install(package, layout)
    deepest = nest(share / "launch", 1000)
    (deepest / "x.launch.py").write_text("raise RuntimeError('too deep to be seen')\n")
    os.symlink(".", deepest / "self")  # a loop at the bottom, and one half-way
    os.symlink("..", share / "launch" / Path(*["d"] * 500) / "up")
    status, report = verify_report(workspace, "--install-base", "install", "--select", "PF3,PF9")
    assert status == 0
    (diagnostic,) = report["diagnostics"]
    # no source folder matches it: the folder of the user's install base is named, 64 below the share
    relative = share.relative_to(workspace)
    assert (diagnostic["code"], diagnostic["path"], diagnostic["line"]) == (
        "PF903",
        f"{relative}/launch" + "/d" * 63,
        None,
    )
    assert diagnostic["message"] == (
        "folders nest more than 64 deep below this one: pkgforge did not look inside"
    )


def test_deep_nesting_in_package_and_install_base_is_one_diagnostic_at_the_source(package, nest):
    # the same nesting in the source and in the install base it was installed to: named once, at the
    # source, as in the default mode
    workspace = package.parent.parent
    share = hand_made_install(package)
    nest(package / "meshes", 200)
    nest(share / "meshes", 200)
    for args in [(), ("--install-base", "install")]:
        status, report = verify_report(workspace, *args, "--no-cache", "--select", "PF3,PF9")
        assert status == 0
        assert [(d["code"], d["path"]) for d in report["diagnostics"]] == [
            ("PF903", "src/rob_description/meshes" + "/d" * 63)
        ], args


def test_migrate_walks_the_ros1_package_with_the_bounded_walk(tmp_path, nest):
    """migrate reads the user's folder through pkgforge.walk: nesting past its bound stops the
    migration with a one-line error naming the folder, before anything is written."""
    from migrate_fixtures import ros1_package

    package = ros1_package(tmp_path / "ros1", "robot_arm")
    (package / "extra").mkdir()
    deepest = nest(package / "extra", 70)
    result = run_pkgforge(
        "migrate", package, "--destination", tmp_path / "out", cwd=tmp_path, timeout=HANG_GUARD
    )
    assert result.returncode == 2, result.stdout + result.stderr
    first = result.stderr.splitlines()[0]
    assert first.startswith(f"pkgforge: error: {package / 'extra'}/d/"), first
    assert "nest more than 64 deep" in first and first.endswith("(nothing written)"), first
    assert str(deepest) not in first and "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists()
