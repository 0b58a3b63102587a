"""The readers behind the model: CMake language, install rules, setup.py data_files, layout."""

from __future__ import annotations

from pathlib import Path

import pytest

from pkgforge.model.cmake import Unknown, load_cmake
from pkgforge.model.cmake_syntax import CMakeSyntaxError, parse
from pkgforge.model.layout import layout_from_cmake, layout_from_setup_py
from pkgforge.model.setup_py import load_setup_py
from pkgforge.model.source import read_source


def write(folder: Path, files: dict[str, str]) -> Path:
    for relative, content in files.items():
        path = folder / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(content)
    return folder


# --- CMake syntax ---------------------------------------------------------------------------


def test_arguments_quoting_and_lines():
    text = 'install(\n  DIRECTORY "my dir" [=[br]acket]=] plain\\;part # comment\n  DESTINATION x)\n'
    (command,) = parse(text, Path("CMakeLists.txt"))
    assert command.name == "install" and command.line == 1
    assert [(a.text, a.kind, a.line) for a in command.args] == [
        ("DIRECTORY", "unquoted", 2),
        ("my dir", "quoted", 2),
        ("br]acket", "bracket", 2),
        ("plain\\;part", "unquoted", 2),
        ("DESTINATION", "unquoted", 3),
        ("x", "unquoted", 3),
    ]


def test_bracket_comment_and_continuation():
    text = '#[[ a\nmulti-line comment ]]\nset(X "a\\\nb")\n'
    (command,) = parse(text, Path("x"))
    assert command.line == 3
    assert command.args[1].text == "ab"


def test_nested_parentheses():
    (command,) = parse("if((A AND B) OR C)\n", Path("x"))
    assert [a.text for a in command.args] == ["(", "A", "AND", "B", ")", "OR", "C"]


@pytest.mark.parametrize(
    "text, line, column, message",
    [
        ('install(DIRECTORY "abc DESTINATION x)', 1, 19, "unterminated quoted argument"),
        ("project(x)\ninstall(DIRECTORY a\n", 2, 1, "missing ')'"),
        ("#[==[ never closed", 1, 2, "unterminated bracket comment"),
        ("set(X [[open)", 1, 7, "unterminated bracket argument"),
        ("foo bar", 1, 5, "expected '(' after 'foo'"),
    ],
)
def test_syntax_errors_are_located(text, line, column, message):
    with pytest.raises(CMakeSyntaxError) as error:
        parse(text, Path("x"))
    assert (error.value.line, error.value.column) == (line, column)
    assert message in error.value.message


# --- interpretation -------------------------------------------------------------------------


def test_variables_foreach_include_and_subdirectory(tmp_path):
    write(
        tmp_path,
        {
            "CMakeLists.txt": "cmake_minimum_required(VERSION 3.10)\nproject(robo NONE)\n"
            "set(FOLDERS launch urdf)\nlist(APPEND FOLDERS meshes)\n"
            "include(cmake/extra.cmake)\ninclude(GNUInstallDirs)\n"
            "foreach(dir ${FOLDERS})\n"
            "  install(DIRECTORY ${dir} DESTINATION ${CMAKE_INSTALL_DATADIR}/${PROJECT_NAME})\n"
            "endforeach()\nadd_subdirectory(sub)\n"
            "function(never_called)\n  install(DIRECTORY nothing DESTINATION share)\nendfunction()\n"
            "ament_package()\n",
            "cmake/extra.cmake": "install(FILES ${CMAKE_CURRENT_SOURCE_DIR}/extra.yaml DESTINATION share/${PROJECT_NAME}/config)\n",
            "sub/CMakeLists.txt": "install(DIRECTORY maps/ DESTINATION share/${PROJECT_NAME}/maps)\n",
        },
    )
    model = load_cmake(tmp_path)
    assert model.project_name == "robo"
    rules = [
        (r.mode, [s for s, _ in r.sources], r.destination, r.path.name, r.line) for r in model.install_rules
    ]
    assert rules == [
        ("FILES", [f"{tmp_path}/extra.yaml"], "share/robo/config", "extra.cmake", 1),
        ("DIRECTORY", ["launch"], "share/robo", "CMakeLists.txt", 8),
        ("DIRECTORY", ["urdf"], "share/robo", "CMakeLists.txt", 8),
        ("DIRECTORY", ["meshes"], "share/robo", "CMakeLists.txt", 8),
        ("DIRECTORY", ["maps/"], "share/robo/maps", "CMakeLists.txt", 1),
    ]
    assert model.install_rules[-1].base_dir == tmp_path / "sub"
    assert model.ament_package_command.line == 14


def test_unknown_values_are_not_guessed(tmp_path):
    write(
        tmp_path,
        {
            "CMakeLists.txt": "project(p NONE)\ninstall(DIRECTORY ${SOMEWHERE}/urdf DESTINATION share/p)\n"
            "install(DIRECTORY urdf DESTINATION $ENV{PREFIX})\n"
        },
    )
    first, second = load_cmake(tmp_path).install_rules
    assert isinstance(first.sources[0][0], Unknown) and "${SOMEWHERE}" in first.sources[0][0].why
    assert isinstance(second.destination, Unknown)


def test_rules_in_if_are_kept_and_marked(tmp_path):
    write(
        tmp_path,
        {
            "CMakeLists.txt": "project(p NONE)\nif(BUILD_TESTING)\n"
            "  install(DIRECTORY test DESTINATION share/p)\nendif()\n"
        },
    )
    (rule,) = load_cmake(tmp_path).install_rules
    assert rule.conditional


# --- layout ---------------------------------------------------------------------------------


def test_directory_patterns_trailing_slash_and_rename(tmp_path):
    write(
        tmp_path,
        {
            "CMakeLists.txt": "project(p NONE)\n"
            "install(DIRECTORY meshes DESTINATION share/${PROJECT_NAME} FILES_MATCHING "
            'PATTERN "*.stl" PATTERN "old" EXCLUDE)\n'
            "install(DIRECTORY config/ DESTINATION share/${PROJECT_NAME}/params)\n"
            "install(FILES notes.txt DESTINATION share/${PROJECT_NAME} RENAME README)\n"
            "install(DIRECTORY gone urdf DESTINATION share/${PROJECT_NAME})\n"
            "ament_package()\n",
            "meshes/a.stl": "x",
            "meshes/a.dae": "x",
            "meshes/old/b.stl": "x",
            "meshes/sub/c.stl": "x",
            "config/x.yaml": "x",
            "notes.txt": "x",
            "urdf/r.urdf": "x",
        },
    )
    model = load_cmake(tmp_path)
    layout = layout_from_cmake(model, tmp_path, "p")
    assert sorted(layout.files) == [
        "share/ament_index/resource_index/packages/p",
        "share/p/README",
        "share/p/meshes/a.stl",
        "share/p/meshes/sub/c.stl",
        "share/p/package.xml",
        "share/p/params/x.yaml",
        "share/p/urdf/r.urdf",
    ]
    assert [(m.text, m.line, m.column) for m in layout.missing] == [("gone", 5, 19)]
    assert layout.exists("share/p/meshes") and not layout.exists("share/p/meshes/old")


def test_destination_outside_the_prefix(tmp_path):
    write(
        tmp_path,
        {
            "CMakeLists.txt": "project(p NONE)\ninstall(DIRECTORY urdf DESTINATION /opt/robot)\n",
            "urdf/r.urdf": "x",
        },
    )
    layout = layout_from_cmake(load_cmake(tmp_path), tmp_path, "p")
    (destination,) = layout.destinations
    assert destination.destination is None and destination.raw == "/opt/robot"
    assert layout.files == {}


# --- setup.py -------------------------------------------------------------------------------


def test_setup_py_data_files(tmp_path):
    write(
        tmp_path,
        {
            "setup.py": "import os\nfrom glob import glob\nfrom setuptools import setup\n"
            "package_name = 'rob'\n"
            "setup(name=package_name, data_files=[\n"
            "    ('share/ament_index/resource_index/packages', ['resource/' + package_name]),\n"
            "    (f'share/{package_name}', ['package.xml']),\n"
            "    (os.path.join('share', package_name, 'launch'), glob('launch/*.py')),\n"
            "    (os.path.join('share', package_name, 'urdf'), glob(os.path.join('urdf', '*'))),\n"
            "    (os.path.join('share', package_name, 'x'), compute()),\n"
            "])\n",
            "resource/rob": "",
            "package.xml": "<package/>",
            "launch/a.launch.py": "",
            "urdf/r.urdf": "x",
        },
    )
    model = load_setup_py(read_source(tmp_path / "setup.py"), tmp_path)
    assert model.name == "rob"
    assert [(e.destination, e.files, e.line) for e in model.entries] == [
        ("share/ament_index/resource_index/packages", ("resource/rob",), 6),
        ("share/rob", ("package.xml",), 7),
        ("share/rob/launch", ("launch/a.launch.py",), 8),
        ("share/rob/urdf", ("urdf/r.urdf",), 9),
    ]
    assert model.unknown == [(10, "compute() is not evaluated")]
    layout = layout_from_setup_py(model, tmp_path)
    assert "share/rob/launch/a.launch.py" in layout.files
    assert layout.unknown == [(tmp_path / "setup.py", 10, "compute() is not evaluated")]


def test_setup_py_syntax_error(tmp_path):
    write(tmp_path, {"setup.py": "from setuptools import setup\nsetup(name='x',,)\n"})
    model = load_setup_py(read_source(tmp_path / "setup.py"), tmp_path)
    assert model.syntax_error[0] == 2


# --- catkin_pkg without its condition grammar until a condition needs it ------------------------

CONDITIONS = [
    None,
    "$ROS_VERSION == 2",
    "$ROS_VERSION == 1",
    "$ROS_DISTRO == humble or $ROS_DISTRO == jazzy",
    "$ROS_DISTRO != rolling and $ROS_PYTHON_VERSION == 3",
    "($ROS_VERSION == 2) and ($UNSET == '')",
    "$ROS_DISTRO >= humble",
    "$ROS_VERSION ==",  # refused: ValueError naming the condition
    "ROS_VERSION = 2",
    "",
]
CONDITION_SCRIPT = """
import json, sys
if sys.argv[1] == "deferred":
    import pkgforge.model.catkin
import catkin_pkg.package as package
before = "pyparsing" in sys.modules
answers = []
for condition in json.loads(sys.argv[2]):
    try:
        answers.append(["value", package.evaluate_condition(
            condition, {"ROS_VERSION": "2", "ROS_DISTRO": "jazzy", "ROS_PYTHON_VERSION": "3"})])
    except Exception as error:
        answers.append([type(error).__name__, str(error)])
print(json.dumps([before, answers]))
"""


def test_catkin_conditions_answer_as_catkin_pkg_does_and_build_no_grammar_before_one():
    """pkgforge.model.catkin defers catkin_pkg.condition (its pyparsing grammar costs ~25 ms per
    run): every condition, None, valid or refused, gets catkin_pkg's own answer."""
    import json
    import subprocess
    import sys

    def answers(mode: str) -> list:
        run = subprocess.run(
            [sys.executable, "-c", CONDITION_SCRIPT, mode, json.dumps(CONDITIONS)],
            capture_output=True,
            text=True,
            check=True,
        )
        return json.loads(run.stdout)

    deferred_before, deferred = answers("deferred")
    real_before, real = answers("real")
    assert deferred == real
    assert [kind for kind, _ in real].count("ValueError") >= 2  # the refused ones were refused
    assert (deferred_before, real_before) == (False, True)


def test_packages_identify_without_the_grammar_until_a_condition(tmp_path):
    """colcon's ROS extension (identify_folder) and pkgforge's manifest reader through the deferred
    module: no grammar for a package without conditions; a condition loads it and is evaluated."""
    import subprocess
    import sys

    manifest = (
        '<?xml version="1.0"?>\n<package format="3"><name>{name}</name><version>0.1.0</version>'
        '<description>d</description><maintainer email="m@x.org">m</maintainer><license>MIT</license>'
        "<exec_depend>xacro</exec_depend>{more}"
        "<export><build_type>ament_cmake</build_type></export></package>\n"
    )
    write(tmp_path / "plain", {"package.xml": manifest.format(name="plain", more="")})
    conditioned = '<exec_depend condition="$ROS_VERSION == 1">rospy</exec_depend>'
    write(tmp_path / "conditioned", {"package.xml": manifest.format(name="conditioned", more=conditioned)})
    script = (
        "import sys\nfrom pathlib import Path\nfrom pkgforge.workspace import identify_folder\n"
        "from pkgforge.model.manifest import load_manifest\nfrom pkgforge.model.source import read_source\n"
        "for name in ('plain', 'conditioned'):\n"
        "    folder = Path(sys.argv[1]) / name\n"
        "    d = identify_folder(folder)\n"
        "    m = load_manifest(read_source(folder / 'package.xml'))\n"
        "    print(d.name, d.type, [x.name for x in m.active_dependencies()], 'pyparsing' in sys.modules)\n"
    )
    run = subprocess.run([sys.executable, "-c", script, str(tmp_path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [
        "plain ros.ament_cmake ['xacro'] False",
        "conditioned ros.ament_cmake ['xacro'] True",
    ]


def test_the_deferred_condition_module_is_catkin_pkg_s_attribute_as_the_real_one_is():
    """`import catkin_pkg.condition` then `catkin_pkg.condition.evaluate_condition(...)`: how a
    colcon extension in the same process may call it, before and after the real module loads."""
    import subprocess
    import sys

    script = (
        "import sys\nimport pkgforge.model.catkin\nimport catkin_pkg.condition\nimport catkin_pkg\n"
        "first = catkin_pkg.condition.evaluate_condition(None, {})\n"
        "before = 'pyparsing' in sys.modules\n"
        "second = catkin_pkg.condition.evaluate_condition('$ROS_VERSION == 2', {'ROS_VERSION': '2'})\n"
        "print(first, before, second, catkin_pkg.condition is sys.modules['catkin_pkg.condition'])\n"
    )
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["True", "False", "True", "True"]
