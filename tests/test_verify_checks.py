"""Each check, triggered by a fixture modelled on the user stories: exact code, file and line.

Every fixture is a fresh `pkgforge new` package with one defect written into it,
so it triggers exactly the check named for it and nothing else at warning or above.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import FIXTURES, MAINTAINER, at_least, copy_fixture, edit, line_of, run_pkgforge, verify_report

verify_json = verify_report


def findings(report: dict, minimum: str = "info") -> list[tuple]:
    return sorted(
        (d["code"], d["name"], d["severity"], d["path"], d["line"]) for d in at_least(report, minimum)
    )


def test_clean_package_has_no_diagnostics(package):
    status, report = verify_json(package.parent.parent)
    assert status == 0
    assert report["diagnostics"] == []


def test_manifest_invalid_missing_license(package):
    manifest = package / "package.xml"
    edit(manifest, "  <license>Apache-2.0</license>\n", "")
    status, report = verify_json(package)
    assert status == 1
    assert findings(report) == [
        ("PF101", "manifest-invalid", "error", "package.xml", line_of(manifest, '<package format="3">'))
    ]
    assert "license" in report["diagnostics"][0]["message"]


@pytest.mark.triggers("PF101")
def test_manifest_invalid_truncated(package):
    manifest = package / "package.xml"
    manifest.write_text("\n".join(manifest.read_text().splitlines()[:8]) + "\n")
    status, report = verify_json(package)
    assert status == 1
    (diagnostic,) = report["diagnostics"]
    assert (diagnostic["code"], diagnostic["path"]) == ("PF101", "package.xml")
    assert diagnostic["line"] == 9  # where the data ends
    assert "not well-formed" in diagnostic["message"]


def test_manifest_invalid_not_utf8(package):
    manifest = package / "package.xml"
    description_line = line_of(manifest, "<description>")
    data = manifest.read_bytes().replace(b"<description>Robot", b"<description>Rob\xff\xfet", 1)
    manifest.write_bytes(data)
    status, report = verify_json(package)
    assert findings(report) == [("PF101", "manifest-invalid", "error", "package.xml", description_line)]
    assert f"not valid UTF-8: byte 0xff at line {description_line}" in report["diagnostics"][0]["message"]


@pytest.mark.triggers("PF102")
def test_package_name_invalid(tmp_path, template_package):
    target = tmp_path / "src" / "Rob_description"
    shutil.copytree(template_package, target)
    for path in target.rglob("*"):
        if path.is_file() and path.suffix != ".stl":
            path.write_text(path.read_text().replace("rob_description", "Rob_description"))
    (target / "urdf" / "rob_description.urdf.xacro").rename(target / "urdf" / "Rob_description.urdf.xacro")
    status, report = verify_json(target)
    assert findings(report) == [
        ("PF102", "package-name-invalid", "error", "package.xml", line_of(target / "package.xml", "<name>"))
    ]
    assert "upper-case" in report["diagnostics"][0]["message"]


@pytest.mark.triggers("PF103")
def test_project_name_mismatch(package):
    cmake = package / "CMakeLists.txt"
    edit(cmake, "project(rob_description NONE)", "project(robot_description NONE)")
    status, report = verify_json(package, "--select", "PF1,PF2,PF9")
    assert findings(report) == [
        ("PF103", "project-name-mismatch", "error", "CMakeLists.txt", line_of(cmake, "project("))
    ]
    # and what it breaks: the package installs as robot_description, so $(find rob_description) fails
    _, report = verify_json(package)
    model = package / "urdf" / "rob_description.urdf.xacro"
    assert (
        "PF308",
        "xacro-error",
        "error",
        "urdf/rob_description.urdf.xacro",
        line_of(model, "$(find rob_description)"),
    ) in findings(report)


@pytest.mark.triggers("PF104")
def test_folder_name_mismatch(package):
    renamed = package.with_name("rob_desc")
    package.rename(renamed)
    status, report = verify_json(renamed)
    assert status == 0
    # info (issue 12): repositories name folders differently on purpose; a use of the folder
    # name as a package name is unknown-package's
    assert findings(report) == [
        ("PF104", "folder-name-mismatch", "info", "package.xml", line_of(renamed / "package.xml", "<name>"))
    ]


@pytest.mark.triggers("PF110", "PF301", "PF304")
def test_package_name_duplicate(tmp_path, template_package):
    """Two copies of one package in a workspace (a repository of a course's sections): colcon build
    refuses it. Each copy gets package-name-duplicate; the copy the install tree does not hold is
    not resolved in the other's files (its launch error is not seen there, nor the other's found
    twice), and no diagnostic points into pkgforge's temporary tree."""
    first, second = tmp_path / "src" / "a" / "rob_description", tmp_path / "src" / "b" / "rob_description"
    shutil.copytree(template_package, first)
    shutil.copytree(template_package, second)
    broken = second / "launch" / "display.launch.py"
    broken.write_text(broken.read_text() + "\nbroken(\n")
    # a launch file only the tree's copy has: resolved once, as that copy's (not again as the
    # other's, which has no such source: it would point into the tree)
    extra = first / "launch" / "extra.launch.py"
    extra.write_text(
        "from ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\n\n\n"
        "def generate_launch_description():\n"
        "    get_package_share_directory('no_such_package')\n"
        "    return LaunchDescription([])\n"
    )
    # and one only the other copy has: the tree holds one copy whole, not a mix of both
    (second / "launch" / "only_here.launch.py").write_text(extra.read_text().replace("no_such", "absent"))
    name_line = line_of(first / "package.xml", "<name>")
    status, report = verify_report(tmp_path, "--no-cache")
    assert status == 1
    assert all(d["path"].startswith("src/") for d in report["diagnostics"]), report["diagnostics"]
    assert [(d["code"], d["path"], d["line"]) for d in at_least(report, "warning")] == [
        ("PF304", "src/a/rob_description/launch/extra.launch.py", line_of(extra, "no_such_package")),
        ("PF110", "src/a/rob_description/package.xml", name_line),
        ("PF110", "src/b/rob_description/package.xml", name_line),
    ]
    messages = [d["message"] for d in report["diagnostics"] if d["code"] == "PF110"]
    assert messages == [
        "package 'rob_description' is also at src/b/rob_description: colcon build refuses a workspace "
        "where packages share a name",
        "package 'rob_description' is also at src/a/rob_description: colcon build refuses a workspace "
        "where packages share a name; its launch files and models are not checked: the install tree "
        "holds another copy",
    ]
    # the copy alone (pre-commit): it is the tree's, so its launch error is found; the name still clashes
    status, alone = verify_report(second, "--no-cache")
    assert status == 1
    assert [(d["code"], d["path"], d["line"]) for d in at_least(alone, "warning")] == [
        ("PF301", "launch/display.launch.py", line_of(broken, "broken(")),
        ("PF304", "launch/only_here.launch.py", line_of(second / "launch" / "only_here.launch.py", "absent")),
        ("PF110", "package.xml", name_line),
    ]


@pytest.mark.triggers("PF110")
def test_a_second_copy_added_later_is_seen_by_the_cached_run(tmp_path, template_package):
    first = tmp_path / "src" / "a" / "rob_description"
    shutil.copytree(template_package, first)
    status, report = verify_report(tmp_path)
    assert status == 0 and not at_least(report, "warning")
    shutil.copytree(template_package, tmp_path / "src" / "b" / "rob_description")
    status, report = verify_report(tmp_path)
    assert status == 1
    assert [(d["code"], d["path"]) for d in at_least(report, "warning")] == [
        ("PF110", "src/a/rob_description/package.xml"),
        ("PF110", "src/b/rob_description/package.xml"),
    ]


def _copies(root: Path, template: Path, *folders: str) -> list[Path]:
    """Copies of the clean package under root/<folder>/rob_description."""
    made = []
    for folder in folders:
        made.append(root / folder / "rob_description")
        shutil.copytree(template, made[-1])
    return made


def _break_launch(package: Path) -> tuple[Path, int]:
    launch = package / "launch" / "display.launch.py"
    launch.write_text(launch.read_text() + "\nbroken(\n")
    return launch, line_of(launch, "broken(")


@pytest.mark.triggers("PF110", "PF301")
def test_a_copy_checked_alone_is_never_answered_by_a_workspace_run_from_the_cache(tmp_path, template_package):
    """The workspace run leaves the second copy's launch files unchecked (the tree holds the first);
    the copy alone is the tree's, so its broken launch file is found, cached run or not."""
    _, second = _copies(tmp_path / "src", template_package, "a", "b")
    launch, line = _break_launch(second)
    verify_report(tmp_path)  # with the cache
    status, alone = verify_report(second)
    assert status == 1
    assert ("PF301", "launch/display.launch.py", line) in [
        (d["code"], d["path"], d["line"]) for d in at_least(alone, "error")
    ]
    status, report = verify_report(tmp_path)  # and the workspace again, after the copy alone
    assert [
        d["message"].endswith("holds another copy") for d in report["diagnostics"] if d["code"] == "PF110"
    ] == [
        False,
        True,
    ]
    assert "PF301" not in {d["code"] for d in report["diagnostics"]}


@pytest.mark.triggers("PF110", "PF301")
def test_against_an_install_base_the_installed_copy_is_checked(tmp_path, template_package):
    """A copied install does not say which copy it holds: the first is taken for it, as the
    predicted tree would hold it; its launch files are checked there, the other's are not."""
    (first,) = _copies(tmp_path / "src", template_package, "a")
    _, line = _break_launch(first)
    built = run_pkgforge("build", cwd=tmp_path)
    assert built.returncode == 0, built.stdout + built.stderr
    _copies(tmp_path / "src", template_package, "b")
    status, report = verify_report(tmp_path, "--no-cache", "--install-base", "install")
    assert status == 1
    assert [(d["code"], d["path"], d["line"]) for d in at_least(report, "error")] == [
        ("PF301", "src/a/rob_description/launch/display.launch.py", line),
        ("PF110", "src/a/rob_description/package.xml", line_of(first / "package.xml", "<name>")),
        ("PF110", "src/b/rob_description/package.xml", line_of(first / "package.xml", "<name>")),
    ]
    messages = [d["message"] for d in report["diagnostics"] if d["code"] == "PF110"]
    assert [m.endswith("holds another copy") for m in messages] == [False, True]


@pytest.mark.triggers("PF103", "PF304")
def test_two_packages_installing_one_share_folder_are_both_resolved(tmp_path, template_package):
    """Two packages named differently whose project() names agree (PF103) are no namesakes: both
    are placed in the tree, as before PF110, and the second's launch file is still resolved."""
    first, second = _copies(tmp_path / "src", template_package, "pkg_a", "pkg_b")
    edit(first / "package.xml", "<name>rob_description</name>", "<name>pkg_a</name>")
    edit(second / "package.xml", "<name>rob_description</name>", "<name>pkg_b</name>")
    extra = second / "launch" / "only_b.launch.py"
    extra.write_text(
        "from ament_index_python.packages import get_package_share_directory\n"
        "from launch import LaunchDescription\n\n\n"
        "def generate_launch_description():\n"
        "    get_package_share_directory('absent_package')\n"
        "    return LaunchDescription([])\n"
    )
    status, report = verify_report(tmp_path, "--no-cache")
    assert status == 1
    codes = {(d["code"], d["path"]) for d in at_least(report, "error")}
    assert ("PF304", "src/pkg_b/rob_description/launch/only_b.launch.py") in codes, codes
    assert "PF110" not in {code for code, _ in codes}


@pytest.mark.triggers("PF110", "PF303")
def test_a_lookup_in_a_name_two_copies_have_reads_the_copy_the_tree_holds(tmp_path, template_package):
    """Only the second copy has config/params.yaml: another package's launch file asking the
    first copy's share folder (the tree's) for it gets missing-file, the same alone and in the
    workspace, not an uninstalled-reference naming the other copy's source."""
    _, second = _copies(tmp_path / "src", template_package, "a", "b")
    (second / "config").mkdir()
    (second / "config" / "params.yaml").write_text("x: 1\n")
    edit(second / "CMakeLists.txt", "DIRECTORY launch", "DIRECTORY config launch")
    user = tmp_path / "src" / "user_bringup"
    shutil.copytree(template_package, user)
    edit(user / "package.xml", "<name>rob_description</name>", "<name>user_bringup</name>")
    edit(user / "CMakeLists.txt", "project(rob_description", "project(user_bringup")
    edit(
        user / "package.xml",
        "<exec_depend>xacro</exec_depend>",
        "<exec_depend>xacro</exec_depend>\n  <exec_depend>rob_description</exec_depend>",
    )
    (user / "launch" / "params.launch.xml").write_text(
        '<launch>\n  <node pkg="rob_description" exec="x" name="x">\n'
        '    <param from="$(find-pkg-share rob_description)/config/params.yaml"/>\n  </node>\n</launch>\n'
    )
    line = line_of(user / "launch" / "params.launch.xml", "params.yaml")
    _, report = verify_report(tmp_path, "--no-cache")
    _, alone = verify_report(user, "--no-cache")
    in_workspace = [
        (d["code"], d["line"]) for d in report["diagnostics"] if d["path"].endswith("params.launch.xml")
    ]
    by_itself = [
        (d["code"], d["line"]) for d in alone["diagnostics"] if d["path"].endswith("params.launch.xml")
    ]
    assert in_workspace == by_itself and ("PF303", line) in in_workspace, (in_workspace, by_itself)


@pytest.mark.triggers("PF110")
def test_namesakes_are_named_from_the_workspace_root(tmp_path, template_package):
    """A repository of workspaces verified from its root (no src/ there): the other copy's folder in
    the message reads as the report's paths do."""
    _copies(tmp_path, template_package, "s1/src", "s2/src")
    _, report = verify_report(tmp_path, "--no-cache")
    found = [(d["path"], d["message"].split(":")[0]) for d in report["diagnostics"] if d["code"] == "PF110"]
    assert found == [
        ("s1/src/rob_description/package.xml", "package 'rob_description' is also at s2/src/rob_description"),
        ("s2/src/rob_description/package.xml", "package 'rob_description' is also at s1/src/rob_description"),
    ]


@pytest.mark.triggers("PF105")
def test_build_type_missing(package):
    manifest = package / "package.xml"
    content = manifest.read_text()
    start, end = content.index("  <export>"), content.index("</export>") + len("</export>\n")
    manifest.write_text(content[:start] + content[end:])
    status, report = verify_json(package)
    assert findings(report) == [
        ("PF105", "build-type-missing", "error", "package.xml", line_of(manifest, '<package format="3">'))
    ]
    assert "<build_type>ament_cmake</build_type>" in report["diagnostics"][0]["hint"]


@pytest.mark.triggers("PF106")
def test_duplicate_dependency(package):
    manifest = package / "package.xml"
    edit(
        manifest,
        "  <exec_depend>xacro</exec_depend>\n",
        "  <exec_depend>xacro</exec_depend>\n  <exec_depend>xacro</exec_depend>\n",
    )
    status, report = verify_json(package)
    assert status == 0
    assert findings(report) == [
        (
            "PF106",
            "duplicate-dependency",
            "warning",
            "package.xml",
            line_of(manifest, "<exec_depend>xacro") + 1,
        )
    ]


def test_duplicate_generic_dependency_is_an_error(package):
    manifest = package / "package.xml"
    edit(
        manifest,
        "  <exec_depend>rviz2</exec_depend>\n",
        "  <depend>rviz2</depend>\n  <exec_depend>rviz2</exec_depend>\n",
    )
    status, report = verify_json(package)
    assert status == 1
    assert findings(report) == [
        ("PF106", "duplicate-dependency", "error", "package.xml", line_of(manifest, "<exec_depend>rviz2"))
    ]


@pytest.mark.triggers("PF107")
def test_unused_exec_depend(package):
    manifest = package / "package.xml"
    edit(
        manifest,
        "  <exec_depend>xacro</exec_depend>\n",
        "  <exec_depend>xacro</exec_depend>\n  <exec_depend>gazebo_ros</exec_depend>\n",
    )
    status, report = verify_json(package)
    assert status == 0
    assert findings(report) == [
        ("PF107", "unused-exec-depend", "info", "package.xml", line_of(manifest, "gazebo_ros"))
    ]


@pytest.mark.triggers("PF201")
def test_install_missing_directory_seed001(tmp_path):
    package = copy_fixture("seed001/small_turtle", tmp_path)
    status, report = verify_json(package)
    assert status == 1
    rule_line = line_of(package / "CMakeLists.txt", "install(DIRECTORY")
    assert (
        findings(report) == [("PF201", "install-missing-directory", "error", "CMakeLists.txt", rule_line)] * 2
    )
    messages = [d["message"] for d in report["diagnostics"]]
    assert any("'worlds'" in m for m in messages) and any("'models'" in m for m in messages)
    assert [d["column"] for d in report["diagnostics"]] == [26, 45]


@pytest.mark.triggers("PF202")
def test_directory_not_installed_referenced_is_an_error(package):
    """Without launch resolution (issue 4's checks alone) the folder is reported."""
    cmake = package / "CMakeLists.txt"
    edit(cmake, "DIRECTORY launch meshes rviz urdf", "DIRECTORY launch meshes urdf")
    status, report = verify_json(package, "--select", "PF1,PF2")
    assert status == 1
    assert findings(report) == [("PF202", "directory-not-installed", "error", "rviz", None)]
    diagnostic = report["diagnostics"][0]
    assert (
        f"launch/display.launch.py:{line_of(package / 'launch' / 'display.launch.py', 'display.rviz')}"
        in diagnostic["message"]
    )
    assert f"CMakeLists.txt:{line_of(cmake, 'install(')}" in diagnostic["hint"]


@pytest.mark.triggers("PF302")
def test_folder_a_launch_file_needs_is_reported_at_the_launch_line(package):
    """With launch resolution, the launch file's line is where the problem shows."""
    cmake = package / "CMakeLists.txt"
    edit(cmake, "DIRECTORY launch meshes rviz urdf", "DIRECTORY launch meshes urdf")
    status, report = verify_json(package)
    assert status == 1
    launch = package / "launch" / "display.launch.py"
    assert findings(report) == [
        (
            "PF302",
            "uninstalled-reference",
            "error",
            "launch/display.launch.py",
            line_of(launch, "'rviz', 'display.rviz'"),
        )
    ]
    assert f"CMakeLists.txt:{line_of(cmake, 'install(')}" in report["diagnostics"][0]["hint"]


def test_directory_not_installed_unreferenced_is_a_warning(package):
    (package / "config").mkdir()
    (package / "config" / "joints.yaml").write_text("a: 1\n")
    status, report = verify_json(package)
    assert status == 0
    assert findings(report) == [("PF202", "directory-not-installed", "warning", "config", None)]


def test_seed000_shape(tmp_path):
    """Issue 4's checks on the seed 000 shape: the names, and rviz/ not installed."""
    package = copy_fixture("seed000/rob_description", tmp_path)
    status, report = verify_json(package, "--select", "PF1,PF2")
    assert status == 1
    assert findings(report, "warning") == [("PF202", "directory-not-installed", "error", "rviz", None)]
    assert (
        "PF104",
        "folder-name-mismatch",
        "info",
        "package.xml",
        line_of(package / "package.xml", "<name>"),
    ) in findings(report)
    rviz = next(d for d in report["diagnostics"] if d["code"] == "PF202")
    assert f"CMakeLists.txt:{line_of(package / 'CMakeLists.txt', 'install(')}" in rviz["hint"]


def test_seed000_shape_with_launch_resolution(tmp_path):
    package = copy_fixture("seed000/rob_description", tmp_path)
    status, report = verify_json(package)
    launch = package / "launch" / "display.launch.py"
    assert findings(report, "warning") == [
        (
            "PF302",
            "uninstalled-reference",
            "error",
            "launch/display.launch.py",
            line_of(launch, "rviz_config_path = "),
        ),
    ]
    assert (
        "PF104",
        "folder-name-mismatch",
        "info",
        "package.xml",
        line_of(package / "package.xml", "<name>"),
    ) in findings(report)


@pytest.mark.triggers("PF203")
def test_install_wrong_destination(package):
    cmake = package / "CMakeLists.txt"
    edit(cmake, "ament_package()", "install(DIRECTORY urdf DESTINATION share)\nament_package()")
    status, report = verify_json(package)
    assert findings(report) == [
        (
            "PF203",
            "install-wrong-destination",
            "error",
            "CMakeLists.txt",
            line_of(cmake, "DESTINATION share)"),
        )
    ]


@pytest.mark.triggers("PF203")
def test_a_resource_also_installed_under_share_may_stand_beside_a_program_too(package):
    """doosan's common2 installs bin/DRCF/config beside its emulator (bin/common2) and, by another
    rule, under share/common2: lookups find it there, so the copy beside the program is no
    mistake. A resource installed only beside it stays install-wrong-destination."""
    cmake = package / "CMakeLists.txt"
    (package / "config").mkdir()
    (package / "config" / "params.yaml").write_text("x: 1\n")
    edit(
        cmake,
        "ament_package()",
        "install(DIRECTORY urdf DESTINATION lib/${PROJECT_NAME})\n"
        "install(DIRECTORY config DESTINATION lib/${PROJECT_NAME})\nament_package()",
    )
    status, report = verify_json(package)
    assert [f for f in findings(report) if f[0] == "PF203"] == [
        ("PF203", "install-wrong-destination", "error", "CMakeLists.txt", line_of(cmake, "DIRECTORY config"))
    ]


@pytest.mark.triggers("PF109")
def test_an_optional_find_package_undeclared_is_a_warning(package):
    """find_package(X QUIET) without REQUIRED, then if(X_FOUND) (zed_components'
    point_cloud_transport): a clean machine builds without what needs it. A REQUIRED one that
    package.xml does not declare stays an error."""
    cmake = package / "CMakeLists.txt"
    edit(
        cmake,
        "ament_package()",
        "find_package(urdf QUIET)\nif(urdf_FOUND)\nendif()\nfind_package(tf2 REQUIRED)\nament_package()",
    )
    status, report = verify_json(package)
    assert status == 1
    assert [f for f in findings(report) if f[0] == "PF109"] == [
        ("PF109", "find-package-undeclared", "error", "CMakeLists.txt", line_of(cmake, "find_package(tf2")),
        (
            "PF109",
            "find-package-undeclared",
            "warning",
            "CMakeLists.txt",
            line_of(cmake, "find_package(urdf"),
        ),
    ]


def test_cmake_invalid_unterminated_argument(package):
    cmake = package / "CMakeLists.txt"
    edit(cmake, "DESTINATION share/${PROJECT_NAME}", 'DESTINATION "share/${PROJECT_NAME}')
    status, report = verify_json(package)
    assert findings(report) == [
        ("PF204", "cmake-invalid", "error", "CMakeLists.txt", line_of(cmake, 'DESTINATION "'))
    ]
    assert "unterminated quoted argument" in report["diagnostics"][0]["message"]


@pytest.mark.triggers("PF204")
def test_cmake_invalid_empty_file(package):
    (package / "CMakeLists.txt").write_text("")
    status, report = verify_json(package)
    assert ("PF204", "cmake-invalid", "error", "CMakeLists.txt", 1) in findings(report)


@pytest.mark.triggers("PF205")
def test_ament_package_missing(package):
    edit(package / "CMakeLists.txt", "ament_package()", "")
    status, report = verify_json(package)
    assert findings(report) == [("PF205", "ament-package-missing", "error", "CMakeLists.txt", None)]


@pytest.mark.triggers("PF206")
def test_install_rule_unevaluated(package):
    cmake = package / "CMakeLists.txt"
    edit(
        cmake,
        "ament_package()",
        "install(DIRECTORY $ENV{EXTRA} DESTINATION share/${PROJECT_NAME})\nament_package()",
    )
    status, report = verify_json(package)
    assert status == 0
    assert findings(report) == [
        ("PF206", "install-rule-unevaluated", "info", "CMakeLists.txt", line_of(cmake, "$ENV{EXTRA}"))
    ]


@pytest.mark.triggers("PF207")
def test_install_missing_file(package):
    cmake = package / "CMakeLists.txt"
    edit(
        cmake,
        "ament_package()",
        "install(FILES README.md DESTINATION share/${PROJECT_NAME})\nament_package()",
    )
    status, report = verify_json(package)
    assert findings(report) == [
        ("PF207", "install-missing-file", "error", "CMakeLists.txt", line_of(cmake, "README.md"))
    ]


@pytest.mark.triggers("PF208")
def test_setup_py_invalid(tmp_path):
    result = run_pkgforge(
        "new", "rob_py", *MAINTAINER, "--build-type", "ament_python", "--destination", "src", cwd=tmp_path
    )
    assert result.returncode == 0
    setup = tmp_path / "src" / "rob_py" / "setup.py"
    edit(setup, "zip_safe=True,", "zip_safe=True,,")
    status, report = verify_json(tmp_path)
    assert findings(report) == [
        ("PF208", "setup-py-invalid", "error", "src/rob_py/setup.py", line_of(setup, "zip_safe"))
    ]


def test_ament_python_data_files_missing_folder(tmp_path):
    result = run_pkgforge(
        "new", "rob_py", *MAINTAINER, "--build-type", "ament_python", "--destination", "src", cwd=tmp_path
    )
    assert result.returncode == 0
    setup = tmp_path / "src" / "rob_py" / "setup.py"
    edit(setup, "        *share_files('rviz'),\n", "")
    status, report = verify_json(tmp_path, "--select", "PF2")
    assert findings(report) == [("PF202", "directory-not-installed", "error", "src/rob_py/rviz", None)]
    assert "data_files in setup.py" in report["diagnostics"][0]["hint"]
    status, report = verify_json(tmp_path)
    launch = tmp_path / "src" / "rob_py" / "launch" / "display.launch.py"
    assert findings(report) == [
        (
            "PF302",
            "uninstalled-reference",
            "error",
            "src/rob_py/launch/display.launch.py",
            line_of(launch, "'rviz', 'display.rviz'"),
        )
    ]
    assert "data_files in setup.py" in report["diagnostics"][0]["hint"]


@pytest.mark.triggers("PF901")
def test_file_not_read_for_a_50mb_file(package):
    (package / "urdf" / "huge.urdf").write_bytes(b"<robot>" + b" " * 50_000_000)
    status, report = verify_json(package)
    assert status == 0
    assert findings(report) == [("PF901", "file-not-read", "info", "urdf/huge.urdf", None)]


def test_symlink_loop_in_the_workspace(package):
    (package / "urdf" / "loop").symlink_to("..")
    (package.parent / "again").symlink_to(".")
    status, report = verify_json(package.parent.parent)
    assert status == 0
    assert [p["name"] for p in report["packages"]] == ["rob_description"]


def test_binary_garbage_named_package_xml(package):
    (package / "package.xml").write_bytes(bytes(range(256)) * 4)
    status, report = verify_json(package)
    assert status == 1
    assert report["diagnostics"][0]["code"] == "PF101"


def test_no_package_is_exit_2(tmp_path):
    result = run_pkgforge("verify", tmp_path, cwd=tmp_path)
    assert result.returncode == 2
    assert "no package found" in result.stderr and "Traceback" not in result.stderr


def test_missing_path_is_exit_2(tmp_path):
    result = run_pkgforge("verify", tmp_path / "nope", cwd=tmp_path)
    assert result.returncode == 2 and "does not exist" in result.stderr


# --- configuration --------------------------------------------------------------------------


def test_select_and_ignore(tmp_path):
    copy_fixture("seed000/rob_description", tmp_path)
    _, report = verify_json(tmp_path, "--select", "PF1")
    assert {d["code"] for d in report["diagnostics"]} == {"PF104", "PF107"}
    status, report = verify_json(tmp_path, "--ignore", "directory-not-installed,uninstalled-reference,PF107")
    assert status == 0
    assert {d["code"] for d in report["diagnostics"]} == {"PF104"}


def test_unknown_check_name_is_exit_2(tmp_path):
    copy_fixture("seed000/rob_description", tmp_path)
    result = run_pkgforge("verify", "--ignore", "no-such-check", cwd=tmp_path)
    assert result.returncode == 2 and "no-such-check" in result.stderr


def test_pkgforge_toml_workspace_and_package(tmp_path):
    copy_fixture("seed000/rob_description", tmp_path)
    (tmp_path / "pkgforge.toml").write_text(
        '[verify]\nignore = ["PF107"]\n[verify.packages.robot_description]\nignore = ["directory-not-installed", "PF302"]\n'
    )
    status, report = verify_json(tmp_path)
    assert status == 0
    assert {d["code"] for d in report["diagnostics"]} == {"PF104"}
    (tmp_path / "src" / "rob_description" / "pkgforge.toml").write_text('[verify]\nignore = ["PF104"]\n')
    _, report = verify_json(tmp_path)
    assert report["diagnostics"] == []


def test_bad_pkgforge_toml_is_exit_2(tmp_path):
    copy_fixture("seed000/rob_description", tmp_path)
    (tmp_path / "pkgforge.toml").write_text("[verify\n")
    result = run_pkgforge("verify", cwd=tmp_path)
    assert result.returncode == 2 and "pkgforge.toml: invalid TOML" in result.stderr


def test_inline_suppression_cmake_and_xml(package):
    cmake = package / "CMakeLists.txt"
    edit(
        cmake,
        "ament_package()",
        "# pkgforge: ignore=install-missing-file\ninstall(FILES README.md DESTINATION share/${PROJECT_NAME})\n"
        "ament_package()",
    )
    manifest = package / "package.xml"
    edit(
        manifest,
        "  <exec_depend>xacro</exec_depend>\n",
        "  <exec_depend>xacro</exec_depend>\n  <!-- pkgforge: ignore=PF107 -->\n"
        "  <exec_depend>gazebo_ros</exec_depend>\n",
    )
    status, report = verify_json(package)
    assert status == 0
    assert report["diagnostics"] == []


def test_strict_turns_warnings_into_exit_1(package):
    (package / "config").mkdir()
    (package / "config" / "view.yaml").write_text("a: 1\n")  # not installed, not referenced: a warning
    assert run_pkgforge("verify", package, cwd=package).returncode == 0
    assert run_pkgforge("verify", "--strict", package, cwd=package).returncode == 1


def test_text_format(tmp_path):
    package = copy_fixture("seed001/small_turtle", tmp_path)
    result = run_pkgforge("verify", cwd=tmp_path)
    assert result.returncode == 1
    lines = result.stdout.splitlines()
    assert lines[0] == (
        "src/small_turtle/CMakeLists.txt:6:26: PF201 [error] install(DIRECTORY) names "
        "'worlds', which does not exist in small_turtle (install-missing-directory)"
    )
    assert lines[1].startswith("    hint: remove 'worlds' from the install rule at CMakeLists.txt:6")
    assert (
        lines[-1]
        == "2 errors, 0 warnings, 0 infos in 1 package; launch: built-in engine (lyrical, the newest LTS)"
    )
    assert "\x1b[" not in result.stdout  # no colour when not on a terminal
    assert package.is_dir()


def test_verify_one_package_of_a_workspace(tmp_path):
    copy_fixture("seed000/rob_description", tmp_path)
    copy_fixture("seed001/small_turtle", tmp_path)
    status, report = verify_json(tmp_path / "src" / "small_turtle")
    assert [p["name"] for p in report["packages"]] == ["small_turtle"]
    assert {d["package"] for d in report["diagnostics"]} == {"small_turtle"}


def test_one_package_is_identified_as_colcons_discovery_of_the_workspace_does(tmp_path):
    """The one-package path identifies its folder with colcon's ignore and ROS extensions only
    (workspace.identify_folder): its name, build type and diagnostics are the whole workspace's."""
    copy_fixture("seed000/rob_description", tmp_path)
    copy_fixture("seed001/small_turtle", tmp_path)
    _, whole = verify_json(tmp_path)
    _, one = verify_json(tmp_path / "src" / "small_turtle")
    [entry] = [p for p in whole["packages"] if p["name"] == "small_turtle"]
    assert [(p["name"], p["build_type"]) for p in one["packages"]] == [("small_turtle", entry["build_type"])]

    def seen(report):
        return sorted(
            (d["code"], Path(d["path"]).name, d["line"], d["message"])
            for d in report["diagnostics"]
            if d["package"] == "small_turtle"
        )

    assert seen(one) == seen(whole) and seen(one)


def test_identification_entry_points_read_as_importlib_metadata_reads_them():
    """workspace.identify_folder decides from the names of colcon's identification entry points,
    read from the entry_points.txt files directly (cheaper than importlib.metadata)."""
    from importlib.metadata import entry_points

    from pkgforge.workspace import IDENTIFICATION, _identification_names, _section_names

    assert _identification_names() == {
        e.name for e in entry_points(group="colcon_core.package_identification")
    }
    assert _identification_names() == IDENTIFICATION  # as installed with pkgforge
    text = (
        "[console_scripts]\nros = x:y\n\n[colcon_core.package_identification]\n# c = d:e\n"
        "ros = colcon_ros.package_identification.ros:RosPackageIdentification\n  extra=m:N\n[other]\nz = a:b\n"
    )
    assert _section_names(text, "colcon_core.package_identification") == {"ros", "extra"}


def _described(descriptors) -> list:
    return [(d.name, str(d.type), str(d.path)) for d in descriptors]


def test_discovery_with_the_ros_extension_alone_is_colcons_or_asks_every_extension(tmp_path):
    """verify's discovery identifies with colcon's ignore and ROS extensions only (no setuptools)
    when that is what every extension decides; a folder the ROS extension leaves alone that holds
    a CMakeLists.txt or setup.py (a plain CMake project hiding a ROS package, a Python package, a
    package.xml colcon-ros rejects beside a CMakeLists.txt) makes it ask them all, as colcon does."""
    from pkgforge.workspace import discover

    src = tmp_path / "src"
    copy_fixture("seed001/small_turtle", tmp_path)
    assert (
        run_pkgforge("new", "plain_description", *MAINTAINER, "--destination", "src", cwd=tmp_path).returncode
        == 0
    )
    only_ros = discover(src, augment=False, ros_only=True)
    assert _described(only_ros) == _described(discover(src)) and len(only_ros) == 2

    outer = src / "outer"  # colcon's cmake extension takes the folder: it never looks inside
    outer.mkdir()
    (outer / "CMakeLists.txt").write_text("cmake_minimum_required(VERSION 3.8)\nproject(outer)\n")
    shutil.copytree(src / "plain_description", outer / "inner_description")
    python = src / "py_tool"
    python.mkdir()
    (python / "setup.py").write_text("from setuptools import setup\nsetup(name='py_tool')\n")
    mixed = discover(src, augment=False, ros_only=True)
    assert _described(mixed) == _described(discover(src))
    assert ("outer", "cmake", str(outer)) in _described(mixed)
    assert not any(path.startswith(str(outer / "inner_description")) for _, _, path in _described(mixed))


def test_colcon_ignore_is_honoured(tmp_path):
    copy_fixture("seed001/small_turtle", tmp_path)
    (tmp_path / "src" / "small_turtle" / "COLCON_IGNORE").touch()
    copy_fixture("seed000/rob_description", tmp_path)
    _, report = verify_json(tmp_path)
    assert [p["name"] for p in report["packages"]] == ["robot_description"]


def test_fixture_folders_exist():
    assert (FIXTURES / "seed000" / "rob_description" / "package.xml").is_file()


# --- issue 30: xacro's $(find X) of an undeclared package -----------------------------------------

XACRO_IN_AN_OPAQUE_FUNCTION = """\
import os

import xacro
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import OpaqueFunction
from launch_ros.actions import Node


def setup(context):
    path = os.path.join(get_package_share_directory('rob_description'), 'urdf', 'arm.urdf.xacro')
    description = xacro.process_file(path).toxml()
    return [Node(package='robot_state_publisher', executable='robot_state_publisher',
                 parameters=[{'robot_description': description}])]


def generate_launch_description():
    return LaunchDescription([OpaqueFunction(function=setup)])
"""

ARM_WITH_A_FIND = """\
<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <link name="base_link">
    <visual><geometry><mesh filename="file://$(find {package})/meshes/arm.stl"/></geometry></visual>
  </link>
</robot>
"""


@pytest.mark.triggers("PF305", "PF308")
def test_a_find_of_an_undeclared_package_is_missing_exec_depend(package):
    """Issue 30: a model's $(find ur_description), undeclared, read by xacro.process_file() in an
    OpaqueFunction, is missing-exec-depend with its fix at the model's line, and nothing else
    (no launch-load-error quoting Python's <class '...PackageNotFoundError'> and pkgforge's tree);
    a $(find) of a name that exists nowhere is xacro-error with xacro's words, no repr, no tree."""
    model = package / "urdf" / "arm.urdf.xacro"
    model.write_text(ARM_WITH_A_FIND.format(package="ur_description"))
    (package / "launch" / "opaque.launch.py").write_text(XACRO_IN_AN_OPAQUE_FUNCTION)
    status, report = verify_json(package.parent.parent)
    assert status == 1
    assert [(d["code"], d["path"], d["line"], d["message"], d["hint"]) for d in report["diagnostics"]] == [
        (
            "PF305",
            "src/rob_description/urdf/arm.urdf.xacro",
            line_of(model, "$(find ur_description)"),
            "$(find) 'ur_description' is used at run time but package.xml does not declare it",
            f"add <exec_depend>ur_description</exec_depend> to package.xml (after line "
            f"{line_of(package / 'package.xml', '<exec_depend>xacro</exec_depend>')})",
        )
    ]
    fixed = run_pkgforge("fix", cwd=package.parent.parent)
    assert "<exec_depend>ur_description</exec_depend>" in (package / "package.xml").read_text(), fixed.stdout
    model.write_text(ARM_WITH_A_FIND.format(package="ur_descripton_parts"))
    status, report = verify_json(package.parent.parent)
    shown = [(d["code"], d["path"], d["message"]) for d in report["diagnostics"]]
    assert (
        "PF308",
        "src/rob_description/urdf/arm.urdf.xacro",
        "xacro arm.urdf.xacro: PackageNotFoundError: \"package 'ur_descripton_parts' not found\"",
    ) in shown
    assert all(
        "<class" not in d["message"] and "pkgforge-tree" not in d["message"] for d in report["diagnostics"]
    )


def test_folder_name_mismatch_suggests_only_valid_names(package):
    """Issue 30: a folder named as a repository snapshot is (Owner+Repo) is no package name:
    the hint offers only the folder's rename; at the root of a git repository (the folder is the
    clone's name) the folder's name is no finding at all."""
    renamed = package.with_name("Owner+Repo")
    package.rename(renamed)
    status, report = verify_json(renamed)
    assert [(d["code"], d["path"], d["line"], d["hint"]) for d in report["diagnostics"]] == [
        (
            "PF104",
            "package.xml",
            line_of(renamed / "package.xml", "<name>"),
            "rename the folder to 'rob_description'",
        )
    ]
    (renamed / ".git").mkdir()
    (renamed / ".git" / "HEAD").write_text("ref: refs/heads/main\n")
    status, report = verify_json(renamed)  # (the cached answer of the first run does not stand)
    assert status == 0
    assert report["diagnostics"] == []
