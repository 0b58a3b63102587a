"""What pkgforge's own process reads of the user's files is bounded (issue 35): only regular files
are opened (a FIFO blocks a read for ever, a link to /dev/zero or /dev/urandom never ends), YAML
is read within bounds on nesting and on what aliases expand to, and a deep xacro says what was
too deep. Each case is a located diagnostic, never a hang, a MemoryError or a traceback."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from conftest import line_of, new_package, run_pkgforge

# a subprocess timeout is a hang guard here, not a timing assert: before the fix these never ended
HANG_GUARD = 240
DEVICES = ["/dev/zero", "/dev/urandom"]
# a YAML "billion laughs": 12 lines of anchors, each alias ten of the one before (10**12 nodes)
ALIAS_BOMB = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"] + [
    f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 12)
]


def verify(workspace: Path, *args: str) -> dict:
    """`pkgforge verify --format json` of the workspace (conftest.verify_report, with a hang guard)."""
    result = run_pkgforge("verify", ".", "--format", "json", *args, cwd=workspace, timeout=HANG_GUARD)
    assert "Traceback" not in result.stderr and result.returncode in (0, 1), result.stdout + result.stderr
    return json.loads(result.stdout)


def found(report: dict, code: str) -> list[tuple[str, int | None, str]]:
    return [(d["path"], d["line"], d["message"]) for d in report["diagnostics"] if d["code"] == code]


@pytest.fixture
def yaml_package(tmp_path) -> Path:
    (tmp_path / "src").mkdir()
    return new_package(tmp_path, "rob_description", "--launch-format", "yaml", "--distro", "humble")


# --- FIFOs and devices: refused by what they are, never read --------------------------------------


@pytest.mark.triggers("PF101")
@pytest.mark.parametrize("device", DEVICES)
def test_a_package_xml_linked_to_a_device_is_a_located_error_not_a_read(package, device):
    workspace = package.parent.parent
    (package / "package.xml").unlink()
    os.symlink(device, package / "package.xml")
    for mode in ([], ["--no-cache"]):  # the cache's fingerprint of the files reads them too
        report = verify(workspace, *mode)
        assert found(report, "PF101") == [
            (
                "src/rob_description/package.xml",
                None,
                f"package.xml: a link to {device}, a character device: pkgforge reads only regular files",
            )
        ]


@pytest.mark.parametrize(
    ("name", "code"),
    [
        pytest.param("package.xml", "PF101", marks=pytest.mark.triggers("PF101")),
        pytest.param("CMakeLists.txt", "PF204", marks=pytest.mark.triggers("PF204")),
    ],
)
def test_a_build_file_that_is_a_fifo_is_a_located_error_not_a_read_that_blocks(package, name, code):
    workspace = package.parent.parent
    (package / name).unlink()
    os.mkfifo(package / name)
    diagnostics = verify(workspace)["diagnostics"]
    assert [(d["code"], d["path"], d["message"]) for d in diagnostics if d["code"] == code] == [
        (
            code,
            f"src/rob_description/{name}",
            f"{name}: a FIFO (named pipe): pkgforge reads only regular files",
        )
    ]
    hint = next(d["hint"] for d in diagnostics if d["code"] == code)
    assert "a FIFO or a device has no end" in hint, hint


@pytest.mark.triggers("PF901")
@pytest.mark.parametrize("device", DEVICES)
def test_a_launch_file_linked_to_a_device_is_not_read_nor_run(yaml_package, device):
    workspace = yaml_package.parent.parent
    launch = yaml_package / "launch" / "display.launch.yaml"
    launch.unlink()
    os.symlink(device, launch)
    report = verify(workspace, "--no-cache")
    assert found(report, "PF901") == [
        (
            "src/rob_description/launch/display.launch.yaml",
            None,
            f"launch/display.launch.yaml not read: a link to {device}, a character device: "
            "pkgforge reads only regular files",
        )
    ]
    assert found(report, "PF301") == []  # no worker read it either (it ran out of memory there)


@pytest.mark.triggers("PF405")
@pytest.mark.parametrize("device", DEVICES)
def test_a_mesh_linked_to_a_device_is_named_for_what_it_is(package, device):
    workspace = package.parent.parent
    (package / "meshes" / "arm.stl").unlink()
    os.symlink(device, package / "meshes" / "arm.stl")
    report = verify(workspace)
    model = package / "urdf" / "rob_description.urdf.xacro"
    assert found(report, "PF405") == [
        (
            "src/rob_description/urdf/rob_description.urdf.xacro",
            line_of(model, "meshes/arm.stl"),
            f"package://rob_description/meshes/arm.stl: a link to {device}, a character device: "
            "pkgforge reads only regular files",
        )
    ]
    assert found(report, "PF403") == []  # not "no such file, but 'arm.stl' exists (case differs)"


# --- YAML: bounded in nesting and in what its aliases expand to -----------------------------------


@pytest.mark.triggers("PF301")
def test_a_yaml_alias_bomb_in_a_launch_file_is_located_where_it_passes_the_bound(yaml_package):
    launch = yaml_package / "launch" / "bomb.launch.yaml"
    launch.write_text(
        "launch:\n- let:\n    name: laughs\n    value:\n" + "".join(f"      {line}\n" for line in ALIAS_BOMB)
    )
    report = verify(yaml_package.parent.parent, "--no-cache")
    assert found(report, "PF301") == [
        (
            "src/rob_description/launch/bomb.launch.yaml",
            line_of(launch, "&a5"),  # where what the aliases add passes a million nodes
            "loading bomb.launch.yaml failed: FrontendError: its aliases expand to more than 1,000,000 nodes: "
            "pkgforge reads YAML up to that size",
        )
    ]


@pytest.mark.triggers("PF501")
def test_a_yaml_alias_bomb_in_an_rviz_config_is_located_where_it_passes_the_bound(package):
    config = package / "rviz" / "display.rviz"
    config.write_text(config.read_text() + "Laughs:\n" + "".join(f"  {line}\n" for line in ALIAS_BOMB))
    report = verify(package.parent.parent, "--no-cache")
    assert found(report, "PF501") == [
        (
            "src/rob_description/rviz/display.rviz",
            line_of(config, "&a5"),
            "display.rviz: its aliases expand to more than 1,000,000 nodes: pkgforge reads YAML up to that size",
        )
    ]


@pytest.mark.triggers("PF501")
def test_an_alias_inside_the_collection_it_names_is_located_not_an_endless_walk(package):
    config = package / "rviz" / "display.rviz"
    config.write_text(config.read_text() + "Loop: &loop\n  - *loop\n")
    report = verify(package.parent.parent, "--no-cache")
    assert found(report, "PF501") == [
        (
            "src/rob_description/rviz/display.rviz",
            line_of(config, "*loop"),
            "display.rviz: alias *loop is inside the collection it names: expanding it never ends",
        )
    ]


@pytest.mark.triggers("PF301")
def test_a_launch_yaml_nested_50000_deep_is_located_not_a_recursion_error(yaml_package):
    launch = yaml_package / "launch" / "deep.launch.yaml"
    launch.write_text("launch:\n- let:\n    name: deep\n    value: " + "[" * 50_000 + "]" * 50_000 + "\n")
    report = verify(yaml_package.parent.parent, "--no-cache")
    assert found(report, "PF301") == [
        (
            "src/rob_description/launch/deep.launch.yaml",
            4,
            "loading deep.launch.yaml failed: FrontendError: nested deeper than 500 levels: "
            "pkgforge reads YAML up to that depth",
        )
    ]


@pytest.mark.parametrize("libyaml", [True, False])
def test_the_yaml_reader_bounds_nesting_with_and_without_libyaml(monkeypatch, libyaml):
    """libyaml's composer recurses in C (a stack overflow where its parser sets no bound), PyYAML's
    in Python (RecursionError): neither runs on a deep text, with or without libyaml."""
    import yaml

    from pkgforge.model import yamlnodes

    if not libyaml:
        monkeypatch.setattr(yamlnodes, "_FAST", None)
    yamlnodes._compose.cache_clear()
    for text, line in [
        ("[" * 50_000 + "]" * 50_000, 1),
        ("".join(" " * i + "k:\n" for i in range(2_000)), 501),  # block mappings, one per line
        ("a: &a " + "[" * 300 + "]" * 300 + "\nb: " + "[" * 201 + "*a" + "]" * 201 + "\n", 2),
    ]:
        with pytest.raises(yamlnodes.YAMLLimit) as raised:
            yamlnodes.compose_all(text)
        assert raised.value.problem_mark.line + 1 == line
        assert str(raised.value.problem).startswith("nested deeper than 500 levels")
    # at the bound itself: read, as PyYAML reads it (where PyYAML's recursion allows)
    nested = yamlnodes.load("[" * 500 + "1" + "]" * 500)
    for _ in range(499):
        nested = nested[0]
    assert nested == [1]
    assert yamlnodes.compose("a: &x [1, 2]\nb: *x\n").value[1][1].value[0].value == "1"
    with pytest.raises(yaml.composer.ComposerError, match="found undefined alias"):
        yamlnodes.compose("a: *nowhere\n")
    yamlnodes._compose.cache_clear()


# --- xacro: a deep model says what was too deep -------------------------------------------------


@pytest.mark.triggers("PF308")
def test_a_xacro_nested_100000_deep_says_so_not_an_include_cycle(package):
    model = package / "urdf" / "deep.urdf.xacro"
    depth = 100_000
    model.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="deep">\n'
        + "<group>\n" * depth
        + "</group>\n" * depth
        + "</robot>\n"
    )
    report = verify(package.parent.parent, "--no-cache")
    # <robot> (line 2) is level 1, the <group> on line n is level n - 1: level 257 (one past
    # libxml2's 256) stands on line 258
    assert found(report, "PF308") == [
        (
            "src/rob_description/urdf/deep.urdf.xacro",
            258,
            "xacro deep.urdf.xacro: elements nest deeper than 256 levels here: xacro recurses once per "
            "level, and ran out of stack",
        )
    ]


# --- every other walk of the user's data: bounded, or without recursion ----------------------------


def test_a_cmake_condition_of_5000_nots_is_read_and_3000_parentheses_are_no_recursion_error(package):
    cmake = package / "CMakeLists.txt"
    text = cmake.read_text()
    assert "find_package(ament_cmake REQUIRED)\n" in text
    cmake.write_text(
        text.replace(
            "find_package(ament_cmake REQUIRED)\n",
            "find_package(ament_cmake REQUIRED)\nfind_package(gazebo_ros QUIET)\n"
            f"if({'NOT ' * 5000}gazebo_ros_FOUND)\n  install(DIRECTORY worlds DESTINATION share/${{PROJECT_NAME}})\n"
            f"endif()\nif({'(' * 3000}gazebo_ros_FOUND{')' * 3000})\nendif()\n",
        )
    )
    report = verify(package.parent.parent, "--no-cache")
    # an even number of NOTs: the rule runs when gazebo_ros is found, and names a missing folder
    assert [(d["path"], d["line"]) for d in report["diagnostics"] if d["code"] == "PF201"] == [
        ("src/rob_description/CMakeLists.txt", line_of(cmake, "install(DIRECTORY worlds"))
    ]


@pytest.fixture
def python_package(tmp_path) -> Path:
    (tmp_path / "src").mkdir()
    return new_package(tmp_path, "rob_description", "--build-type", "ament_python")


@pytest.mark.triggers("PF206")
def test_a_setup_py_function_that_calls_itself_is_located_not_a_recursion_error(python_package):
    setup = python_package / "setup.py"
    text = setup.read_text()
    setup.write_text(
        text.replace("package_name = ", "def again(x):\n    return again(x)\n\n\npackage_name = ", 1).replace(
            "        *share_files('urdf'),\n",
            "        *share_files('urdf'),\n        (again('share'), []),\n",
        )
    )
    report = verify(python_package.parent.parent, "--no-cache")
    assert found(report, "PF206") == [
        (
            "src/rob_description/setup.py",
            line_of(setup, "return again(x)"),  # where evaluating it passed the bound
            "cannot predict this install rule: evaluating it goes more than 100 levels deep (an expression "
            "nested that deep, or a function that calls itself): pkgforge evaluates no deeper",
        )
    ]


@pytest.mark.triggers("PF208")
def test_a_setup_py_too_deep_for_pythons_parser_is_located_at_its_statement(python_package):
    setup = python_package / "setup.py"
    text = setup.read_text()
    deep = " + ".join(["'a'"] * 5000)  # CPython's parser runs out of stack building the tree
    setup.write_text(
        text.replace(
            "        *share_files('urdf'),\n",
            f"        *share_files('urdf'),\n        ('share', [{deep}]),\n",
        )
    )
    report = verify(python_package.parent.parent, "--no-cache")
    assert found(report, "PF208") == [
        (
            "src/rob_description/setup.py",
            line_of(setup, "setup("),
            "setup.py: nested too deep for Python's parser (it ran out of stack): Python cannot run it either",
        )
    ]


def test_a_launch_file_too_deep_for_pythons_parser_is_no_internal_error(package):
    launch = package / "launch" / "deep.launch.py"
    launch.write_text(
        "from launch import LaunchDescription\nx = " + "1 + " * 5000 + "1\n"
        "def generate_launch_description():\n    return LaunchDescription([])\n"
    )
    report = verify(package.parent.parent, "--no-cache")
    assert [d["path"] for d in report["diagnostics"] if d["code"] == "PF301"] == [
        "src/rob_description/launch/deep.launch.py"  # (the worker's own compile fails on it too)
    ]


def test_a_chain_of_3000_links_is_drawn_and_explained_without_recursion(package, tmp_path):
    links = 3000
    model = package / "urdf" / "chain.urdf"
    model.write_text(
        '<?xml version="1.0"?>\n<robot name="chain">\n'
        + "".join(f'<link name="l{i}"/>\n' for i in range(links))
        + "".join(
            f'<joint name="j{i}" type="fixed"><parent link="l{i}"/><child link="l{i + 1}"/></joint>\n'
            for i in range(links - 1)
        )
        + "</robot>\n"
    )
    workspace = package.parent.parent
    verify(workspace, "--no-cache", "--artifacts", str(tmp_path / "artifacts"))
    assert f"l{links - 1}" in (tmp_path / "artifacts" / "rob_description-chain-tree.svg").read_text()
    result = run_pkgforge("verify", ".", "--explain-model", model, cwd=workspace, timeout=HANG_GUARD)
    assert result.returncode == 0 and "Traceback" not in result.stderr, result.stderr[-2000:]
    assert f"(fixed) → l{links - 1}" in result.stdout
