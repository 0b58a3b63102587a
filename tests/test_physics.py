"""The physical checks (PF6xx): each case fixture triggers exactly its check; real models give no errors."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from conftest import FIXTURES, VARIANTS, line_of, new_package, run_pkgforge, verify_report

CASES = FIXTURES / "physics" / "cases"
# check name → the text of the case file at whose line the diagnostic points
EXPECTED = {
    "mass-not-positive": ("PF601", "<inertial>"),
    "inertia-invalid": ("PF602", "<inertial>"),
    "collision-without-inertial": ("PF603", '<link name="arm">'),
    "root-link-inertia": ("PF604", "<inertial>"),
    "joint-limit-invalid": ("PF605", "<limit "),
    "continuous-joint-limits": ("PF606", "<limit "),
    "joint-axis-zero": ("PF607", '<joint name="shoulder"'),
    "mesh-scale-suspect": ("PF608", "link_mm.stl"),
    "collision-mesh-heavy": ("PF609", "heavy.stl"),
    "inertia-implausible": ("PF610", "<inertial>"),
    "mass-below-engine-minimum": ("PF611", "<inertial>"),
    "simulation-refused": ("PF612", '<link name="elbow_frame"/>'),
    "simulation-unstable": ("PF613", '<link name="rotor">'),
    "collision-overlap-at-zero": ("PF614", '<link name="forearm">'),
}
# the cases only verify --simulate's drop test finds (MuJoCo, the `simulate` extra)
SIMULATED = {"simulation-refused", "simulation-unstable", "collision-overlap-at-zero"}


def heavy_stl(path: Path, triangles: int = 20_001) -> None:
    """A small but finely tessellated mesh (a collision mesh exported from a visual one)."""
    from pkgforge.scaffold.stl import binary_stl

    step = 0.05 / triangles
    path.write_bytes(
        binary_stl(
            [
                ((0.0, 0.0, 1.0), (i * step, 0.0, 0.0), ((i + 1) * step, 0.0, 0.0), (i * step, 0.05, 0.3))
                for i in range(triangles)
            ]
        )
    )


def physics_package(tmp_path: Path, case: str | None) -> Path:
    package = tmp_path / "src" / "phys_description"
    shutil.copytree(FIXTURES / "physics" / "phys_description", package)
    heavy_stl(package / "meshes" / "heavy.stl")
    if case is not None:
        shutil.copy(CASES / f"{case}.urdf", package / "urdf" / "robot.urdf")
    return package


def test_the_clean_model_has_no_diagnostic(tmp_path):
    physics_package(tmp_path, None)
    status, report = verify_report(tmp_path)
    assert status == 0 and report["diagnostics"] == []


def test_every_physical_check_has_a_case():
    from pkgforge.checks.registry import all_checks

    assert {c.name for c in all_checks() if c.area == "physics"} == set(EXPECTED)
    assert {p.stem for p in CASES.glob("*.urdf")} == set(EXPECTED)


@pytest.mark.parametrize(
    "case",
    [
        pytest.param("mass-not-positive", marks=pytest.mark.triggers("PF601")),
        pytest.param("inertia-invalid", marks=pytest.mark.triggers("PF602")),
        pytest.param("collision-without-inertial", marks=pytest.mark.triggers("PF603")),
        pytest.param("root-link-inertia", marks=pytest.mark.triggers("PF604")),
        pytest.param("joint-limit-invalid", marks=pytest.mark.triggers("PF605")),
        pytest.param("continuous-joint-limits", marks=pytest.mark.triggers("PF606")),
        pytest.param("joint-axis-zero", marks=pytest.mark.triggers("PF607")),
        pytest.param("mesh-scale-suspect", marks=pytest.mark.triggers("PF608")),
        pytest.param("collision-mesh-heavy", marks=pytest.mark.triggers("PF609")),
        pytest.param("inertia-implausible", marks=pytest.mark.triggers("PF610")),
        pytest.param("mass-below-engine-minimum", marks=pytest.mark.triggers("PF611")),
        pytest.param("simulation-refused", marks=pytest.mark.triggers("PF612")),
        pytest.param("simulation-unstable", marks=pytest.mark.triggers("PF613")),
        pytest.param("collision-overlap-at-zero", marks=pytest.mark.triggers("PF614")),
    ],
)
def test_each_case_triggers_exactly_its_check(tmp_path, case):
    package = physics_package(tmp_path, case)
    code, text = EXPECTED[case]
    status, report = verify_report(tmp_path, *(["--simulate"] if case in SIMULATED else []))
    found = [(d["code"], d["path"], d["line"]) for d in report["diagnostics"]]
    model = package / "urdf" / "robot.urdf"
    assert found == [(code, "src/phys_description/urdf/robot.urdf", line_of(model, text))], found
    assert status == (1 if report["diagnostics"][0]["severity"] == "error" else 0)


def test_mesh_scale_hint_names_the_scale_attribute(tmp_path):
    physics_package(tmp_path, "mesh-scale-suspect")
    _, report = verify_report(tmp_path)
    (diagnostic,) = report["diagnostics"]
    assert 'scale="0.001 0.001 0.001"' in diagnostic["hint"]
    assert "link_mm.stl" in diagnostic["message"]


def test_scaffold_variants_have_no_physical_findings(tmp_path):
    for variant, options in VARIANTS.items():
        new_package(tmp_path, f"{variant}_description", *options)
    _, report = verify_report(tmp_path, "--select", "PF6")
    assert report["diagnostics"] == []
    assert report["summary"]["packages"] == len(VARIANTS)


ERD_ROBOTS = [
    "panda_description/urdf/panda.urdf",
    "ur_description/urdf/ur5_robot.urdf",
    "go2_description/urdf/go2.urdf",
]


def erd_share() -> Path:
    """The wheel's robots (a cmeel prefix in site-packages); the test extra installs it."""
    from importlib import metadata

    try:
        files = metadata.distribution("example-robot-data").files or []
    except metadata.PackageNotFoundError:
        pytest.skip("pip install -e '.[test]' installs example-robot-data")
    manifest = next(f for f in files if str(f).endswith("share/example-robot-data/package.xml"))
    return Path(manifest.locate()).parent


# the true defects these models have: the UR5's wrist_3_link has the inertia of wrist 2 (0.0171
# kg·m² for a 0.19 kg disc 8 cm across, ~130 times too big), fixed upstream by
# ros-industrial/universal_robot#426 ("the inertia's geometry of wrist3 is matching wrist2")
ERD_DEFECTS = {"ur_description/urdf/ur5_robot.urdf": [("PF610", "wrist_3_link")]}


@pytest.mark.parametrize("model", ERD_ROBOTS)
def test_example_robot_data_models_have_no_physical_errors(model):
    """The checks over the structure robot.py extracts, with meshes resolved in the wheel's share/."""
    from types import SimpleNamespace

    from pkgforge.checks.physics import _resolver
    from pkgforge.checks.registry import all_checks
    from pkgforge.diagnostics import Severity
    from pkgforge.urdf import robot as robots
    from pkgforge.urdf.physics import world_bounds

    share = erd_share()
    path = share / "robots" / model
    data = robots.process_model(str(path), {})
    assert data["status"] == "ok"

    class Tree:  # the wheel's share/ as the install tree of package example-robot-data
        phantom_packages: set = set()

        def installed_share(self, package):
            return share if package == "example-robot-data" else None

    result = SimpleNamespace(
        status="ok", robot=data["robot"], installed=path, source=path, origins=[], error=None
    )
    context = SimpleNamespace(
        model_results=[result],
        tree=Tree(),
        own_source=lambda file: Path(file),
        simulator_feeding=lambda result: None,  # no launch file feeds it to a simulator
        simulations={},
    )
    errors = []
    for check in all_checks():
        if check.area == "physics":
            errors += [
                (check.code, f.message)
                for f in check.function(context)
                if (f.severity or check.severity) == Severity.ERROR
            ]
    assert [(code, message.split("'")[1]) for code, message in errors] == ERD_DEFECTS.get(model, [])
    # the meshes did resolve (the scale check compared real sizes): the robot is 0.3 to 2 m
    low, high = world_bounds(data["robot"], _resolver(context, result))
    assert 0.3 < max(h - lo for lo, h in zip(low, high, strict=False)) < 2.0


def test_explain_model_shows_mass_size_and_mesh_bounds(tmp_path):
    from conftest import run_pkgforge

    package = physics_package(tmp_path, None)
    result = run_pkgforge("verify", ".", "--explain-model", package / "urdf" / "robot.urdf", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert "mass: 1 kg total (1 of 2 links have a mass)" in lines
    assert any(line.startswith("size: 0.2 × 0.2 × 0.4 m ") for line in lines), lines
    assert (
        "     visual ✓ package://phys_description/meshes/link.stl  [0.05 × 0.05 × 0.3 m in the file, "
        "12 triangles]"
    ) in lines


COLLADA_BOX = """<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="1"/></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="9">0 0 0 0.3 0 0 0 0.3 0</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node><instance_geometry url="#g"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""


def test_unusual_mesh_files_never_stop_the_physical_checks(tmp_path):
    """A real vendor package's .dae starts with a blank line before <?xml (assimp reads it; lxml
    refuses): it crashed PF608 with an internal error. Its numbers are read; a .dae that is not
    XML at all gives no numbers, and no check stops."""
    from pkgforge.urdf.physics import mesh_info

    package = physics_package(tmp_path, None)
    (package / "meshes" / "blank_first.dae").write_text(
        '\n<?xml version="1.0" encoding="utf-8"?>\n' + COLLADA_BOX
    )
    (package / "meshes" / "not_xml.dae").write_bytes(b"\x00\x01 solid binary junk")
    model = package / "urdf" / "robot.urdf"
    meshes = "".join(
        f'<visual><geometry><mesh filename="package://phys_description/meshes/{name}"/></geometry></visual>'
        for name in ("blank_first.dae", "not_xml.dae")
    )
    model.write_text(
        model.read_text().replace(
            '<material name="grey"/>\n    </visual>', f'<material name="grey"/>\n    </visual>{meshes}', 1
        )
    )
    info = mesh_info(str(package / "meshes" / "blank_first.dae"))
    assert info is not None and info.triangles == 1
    assert mesh_info(str(package / "meshes" / "not_xml.dae")) is None
    result = run_pkgforge("verify", tmp_path, "--format", "json", "--no-cache", cwd=tmp_path)
    assert "internal error" not in result.stderr and result.returncode in (0, 1), result.stderr
    assert not [d for d in json.loads(result.stdout)["diagnostics"] if d["code"].startswith("PF6")]


def test_zero_effort_and_zero_velocity_are_warnings_reversed_limits_an_error(tmp_path):
    """ROS-Industrial arms (KUKA, FANUC) declare effort="0" on purpose (position controlled), and
    exporters write velocity="0" (MoveIt reads it as no limit): warnings that say who would
    enforce them; an error where something of the workspace holds the joint to it (issue 30)."""
    package = physics_package(tmp_path, "joint-limit-invalid")
    model = package / "urdf" / "robot.urdf"
    model.write_text(
        model.read_text().replace(
            'lower="1.57" upper="-1.57" velocity="1.0" effort="10"',
            'lower="-1.57" upper="1.57" velocity="1.0" effort="0"',
        )
    )
    status, report = verify_report(tmp_path, "--no-cache")
    line = line_of(model, "<limit ")
    assert status == 0
    assert [
        (d["code"], d["severity"], d["path"], d["line"], d["message"]) for d in report["diagnostics"]
    ] == [
        (
            "PF605",
            "warning",
            "src/phys_description/urdf/robot.urdf",
            line,
            "revolute joint 'shoulder': effort=\"0\" (nothing here enforces it: MoveIt and RViz never "
            "read it; a simulator or ros2_control would stop the joint)",
        )
    ]
    # SolidWorks' exporter writes velocity="0" (mycobot_ros2): only planning and simulation read it
    model.write_text(model.read_text().replace('velocity="1.0" effort="0"', 'velocity="0" effort="10"'))
    status, report = verify_report(tmp_path, "--no-cache")
    assert status == 0 and [(d["code"], d["severity"]) for d in report["diagnostics"]] == [
        ("PF605", "warning")
    ]
    # a package that merely declares ros2_control enforces nothing on this model: still a warning
    package_xml = package / "package.xml"
    package_xml.write_text(
        package_xml.read_text().replace("<export>", "<exec_depend>ros2_control</exec_depend>\n  <export>", 1)
    )
    status, report = verify_report(tmp_path, "--no-cache")
    assert [(d["code"], d["severity"]) for d in report["diagnostics"] if d["code"] == "PF605"] == [
        ("PF605", "warning")
    ]
    # a <ros2_control> block naming the joint holds it to its limits: an error
    text = model.read_text()
    model.write_text(
        text.replace(
            "</robot>",
            '  <ros2_control name="arm" type="system">\n    <joint name="shoulder">'
            '<command_interface name="velocity"/></joint>\n  </ros2_control>\n</robot>',
        )
    )
    status, report = verify_report(tmp_path, "--no-cache")
    assert [
        (d["code"], d["severity"], d["message"]) for d in report["diagnostics"] if d["code"] == "PF605"
    ] == [
        (
            "PF605",
            "error",
            "revolute joint 'shoulder': velocity=\"0\", and <ros2_control> holds the joint to it: the "
            "joint cannot move",
        )
    ]
    model.write_text(text)
    package_xml.write_text(package_xml.read_text().replace("<exec_depend>ros2_control</exec_depend>\n  ", ""))
    # reversed limits leave no allowed position: an error
    model.write_text(
        model.read_text().replace(
            'lower="-1.57" upper="1.57" velocity="0"', 'lower="1.57" upper="-1.57" velocity="1"'
        )
    )
    status, report = verify_report(tmp_path, "--no-cache")
    assert status == 1 and [(d["code"], d["severity"]) for d in report["diagnostics"]] == [("PF605", "error")]


@pytest.mark.parametrize("model", [*ERD_ROBOTS, "talos_data/robots/talos_full_v2.urdf"])
def test_real_robots_pass_the_drop_test(model):
    """verify --simulate's drop test (MuJoCo in its own limited process) on real robots: none is
    refused or unstable, collision shapes overlap deeper than 1 cm (their convex hulls) only where
    PANDA_FOLDED says, and one model costs seconds, not minutes (~1.3 s of it the process starting
    and importing MuJoCo)."""
    pytest.importorskip("mujoco")
    from pkgforge.simulate import drop_test, model_urdf
    from pkgforge.urdf import robot as robots

    share = erd_share()
    data = robots.process_model(str(share / "robots" / model), {})

    def resolve(uri: str) -> Path | None:
        path = share / uri.removeprefix("package://example-robot-data/")
        return path if uri.startswith("package://example-robot-data/") and path.is_file() else None

    outcome = drop_test(model_urdf(data["robot"], resolve), data["robot"]["links"][0]["name"])
    assert outcome.error is None
    assert [p.kind for p in outcome.problems if p.kind != "overlap"] == []
    assert [p.links for p in outcome.problems if p.kind == "overlap"] == PANDA_FOLDED.get(model, [])
    assert outcome.seconds < 20


# the Panda's joint 6 at 0 folds the hand back beside link 5 (its convex hull): a warning, PF614
PANDA_FOLDED = {"panda_description/urdf/panda.urdf": [["panda_link5", "panda_link7"]]}


def test_a_mass_the_static_check_reports_is_not_reported_again_by_the_drop_test(tmp_path):
    """One cause, one finding: MuJoCo refuses the 1e-20 kg link (mjMINVAL), which
    mass-below-engine-minimum says already; --simulate adds no PF612 for it."""
    pytest.importorskip("mujoco")
    package = physics_package(tmp_path, "mass-below-engine-minimum")
    status, report = verify_report(tmp_path, "--simulate")
    model = package / "urdf" / "robot.urdf"
    assert [(d["code"], d["path"], d["line"]) for d in report["diagnostics"]] == [
        ("PF611", "src/phys_description/urdf/robot.urdf", line_of(model, "<inertial>"))
    ]
    assert status == 1
