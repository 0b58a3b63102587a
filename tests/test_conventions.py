"""The conventions of issue 17: every check has a test, an area that follows its code, examples
and a `pkgforge rule`; pkgforge.toml validated, with per-check severity; --color, NO_COLOR and
FORCE_COLOR; the GitLab code quality report; SARIF helpUri; the wheel's metadata."""

from __future__ import annotations

import ast
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import MAINTAINER, SCRIPTS, colcon, line_of, new_package, run_pkgforge

REPO = Path(__file__).resolve().parent.parent
TESTS = Path(__file__).resolve().parent
ANSI = "\x1b["


def registered():
    from pkgforge.checks.registry import all_checks

    return all_checks()


# --- every check code is triggered by a test ---------------------------------------------------


def marked_codes() -> dict[str, list[str]]:
    """code -> the tests marked @pytest.mark.triggers(code) (read from the source, so a test
    skipped or deselected here still counts; conftest checks at run time that the mark is true)."""
    found: dict[str, list[str]] = {}
    for path in sorted(TESTS.glob("test_*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and ast.unparse(node.func).endswith("mark.triggers"):
                for argument in node.args:
                    if isinstance(argument, ast.Constant) and isinstance(argument.value, str):
                        found.setdefault(argument.value, []).append(path.name)
    return found


def test_every_check_code_is_triggered_by_an_end_to_end_test():
    marked = marked_codes()
    missing = [f"{c.code} {c.name}" for c in registered() if c.code not in marked]
    assert not missing, (
        "these check codes are asserted by no test: "
        + "; ".join(missing)
        + ". Write an end-to-end test that runs the real pkgforge (conftest.run_pkgforge) and asserts "
        'the code, file and line, and mark it @pytest.mark.triggers("PFxxx")'
    )


def test_every_triggers_mark_names_a_registered_code():
    codes = {c.code for c in registered()}
    unknown = {code: files for code, files in marked_codes().items() if code not in codes}
    assert not unknown, f"marked triggers() of codes no check has: {unknown}"


# --- checks read a context computed once and never touch the file system ----------------------

# what reads or stats the file system: os / os.path / pathlib / builtins / pkgforge.walk
FILE_SYSTEM_CALLS = {
    "open",
    "read_text",
    "read_bytes",
    "write_text",
    "write_bytes",
    "exists",
    "lexists",
    "is_file",
    "is_dir",
    "is_symlink",
    "isfile",
    "isdir",
    "islink",
    "stat",
    "lstat",
    "resolve",
    "realpath",
    "readlink",
    "iterdir",
    "glob",
    "rglob",
    "listdir",
    "scandir",
    "walk",
    "getsize",
    "getmtime",
    "access",
    "samefile",
}
# where those facts live: computed once per run (CheckContext.files and the context's methods)
CONTEXT_MODULES = {"context.py", "facts.py", "catalogue.py", "__init__.py"}


def file_system_calls(source: str) -> list[tuple[int, str]]:
    """(line, call) of every call in `source` that reads the file system itself; a call through
    the context's file facts (`ctx.files.exists(...)`, a `files: FileFacts` parameter) is none."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Call):
            continue
        function = node.func
        if isinstance(function, ast.Name):
            if function.id == "resolve":
                continue  # a function of the check's own (Path.resolve is a method)
            name, receiver = function.id, None
        elif isinstance(function, ast.Attribute):
            name, receiver = function.attr, function.value
        else:
            continue
        if name not in FILE_SYSTEM_CALLS:
            continue
        through_facts = (isinstance(receiver, ast.Name) and receiver.id == "files") or (
            isinstance(receiver, ast.Attribute) and receiver.attr == "files"
        )
        if not through_facts:
            found.append((node.lineno, ast.unparse(function)))
    return found


def test_checks_never_touch_the_file_system():
    checks = REPO / "src" / "pkgforge" / "checks"
    offenders = [
        f"checks/{path.name}:{line}: {call}()"
        for path in sorted(checks.glob("*.py"))
        if path.name not in CONTEXT_MODULES
        for line, call in file_system_calls(path.read_text(encoding="utf-8"))
    ]
    assert not offenders, (
        "check modules read a context computed once and never touch the file system; ask "
        "CheckContext (ctx.files.exists(...), or a new memoised method in checks/context.py) instead: "
        + "; ".join(offenders)
    )


def test_the_file_system_scan_finds_a_check_that_stats_a_file():
    """The scan above can fail: each way a check could touch a file is found."""
    source = (
        "import os\n"
        "def check(ctx):\n"
        "    if (ctx.model.path / 'setup.py').exists() or os.path.isfile('x'):\n"
        "        yield open('y').read()\n"
        "    ctx.files.exists('z')\n"
        "    for name in walk(ctx.model.path): pass\n"
    )
    assert sorted(file_system_calls(source)) == [
        (3, "(ctx.model.path / 'setup.py').exists"),
        (3, "os.path.isfile"),
        (4, "open"),
        (6, "walk"),
    ]


# --- the registry: area follows the code, examples -------------------------------------------


def test_area_follows_the_code_prefix():
    """PF3xx is launch, PF4xx model, ...: `--select PF4` and the catalogue's areas agree. Codes are
    stable identifiers: a check in the wrong area moves area, never code."""
    from pkgforge.checks.registry import AREAS

    wrong = []
    for check in registered():
        hundred = check.code[2]
        if hundred not in AREAS:
            wrong.append(f"{check.code} {check.name}: PF{hundred}xx has no area in registry.AREAS (add it)")
        elif check.area != AREAS[hundred]:
            wrong.append(
                f"{check.code} {check.name}: area '{check.area}', but PF{hundred}xx is '{AREAS[hundred]}'"
            )
    assert not wrong, "; ".join(wrong)


def test_pf308_sits_in_launch_so_select_pf3_has_it():
    from pkgforge.verify.config import Selection

    assert "PF308" in Selection(["PF3"]).codes() and "PF308" not in Selection(["PF4"]).codes()
    assert {c.code for c in registered() if c.area == "launch"} == Selection(["PF3"]).codes()


def test_every_check_has_a_bad_and_a_fixed_example():
    missing = [f"{c.code} {c.name}" for c in registered() if not (c.bad and c.good) or c.bad == c.good]
    assert not missing, "no bad/good example in the check's register(bad=..., good=...): " + "; ".join(
        missing
    )


# --- pkgforge rule ---------------------------------------------------------------------------


@pytest.mark.parametrize("key", ["PF302", "pf302", "uninstalled-reference"])
def test_rule_explains_one_check(tmp_path, key):
    result = run_pkgforge("rule", key, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    text = result.stdout
    assert text.startswith("PF302 uninstalled-reference (error, area launch)\n")
    assert "Example:\n\n    # launch/display.launch.py" in text
    assert "Fixed:\n\n    # CMakeLists.txt\n    install(DIRECTORY launch rviz urdf" in text
    assert "\nFix: extend the install rule.\n" in text
    assert "Automatic fix: safe (`pkgforge fix`)." in text
    documentation = text.splitlines()[-1]
    assert documentation.startswith("Documentation: file:///"), documentation
    assert documentation.endswith("/checks.md#pf302-uninstalled-reference")


def test_rule_and_sarif_link_to_real_documentation(tmp_path, workspace):
    """Issue 30: `rule` and SARIF's helpUri give a URL that opens: the catalogue of the pkgforge
    that runs (a file:// URL of its docs/checks.md, which has the check's section), or the base
    PKGFORGE_DOCS_URL gives (a fork's docs on its forge)."""
    from urllib.parse import urlparse
    from urllib.request import url2pathname

    documentation = run_pkgforge("rule", "PF302", cwd=tmp_path).stdout.splitlines()[-1]
    url = documentation.removeprefix("Documentation: ")
    document, _, anchor = url.partition("#")
    catalogue = Path(url2pathname(urlparse(document).path))
    assert catalogue.is_file() and catalogue.read_text() == (REPO / "docs" / "checks.md").read_text()
    assert anchor == "pf302-uninstalled-reference" and anchor in github_anchors(catalogue.read_text())
    base = "https://forge.example.org/robots/pkgforge/-/blob/main/docs"
    env = dict(os.environ, PKGFORGE_DOCS_URL=base)
    told = run_pkgforge("rule", "uninstalled-reference", cwd=tmp_path, env=env).stdout.splitlines()[-1]
    assert told == f"Documentation: {base}/checks.md#pf302-uninstalled-reference"
    sarif = run_pkgforge("verify", ".", "--format", "sarif", cwd=workspace, env=env)
    rules = json.loads(sarif.stdout)["runs"][0]["tool"]["driver"]["rules"]
    assert {r["helpUri"] for r in rules if r["id"] == "PF104"} == {
        f"{base}/checks.md#pf104-folder-name-mismatch"
    }


def test_rule_texts_speak_of_the_user_s_package():
    """Issue 30: what `rule` and docs/checks.md say is about the user's package, never the
    project's own notes (user stories, issues, seeds)."""
    from pkgforge.checks.registry import all_checks

    internal = re.compile(r"user stor|\bissue \d|\bstop \d|\bseed \d", re.I)
    for check in all_checks():
        for text in (check.summary, check.explanation, check.hint, check.bad or "", check.good or ""):
            assert not internal.search(text), (check.code, text)


def test_rule_of_an_unknown_code_is_one_line_exit_2(tmp_path):
    result = run_pkgforge("rule", "PF3O2", cwd=tmp_path)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1
    assert result.stderr.startswith("pkgforge: error: no check is coded or named 'PF3O2' (did you mean ")
    assert "PF302" in result.stderr


def test_checks_md_shows_each_checks_examples():
    catalogue = (REPO / "docs" / "checks.md").read_text(encoding="utf-8")
    for check in registered():
        section = catalogue.split(f"## {check.code} {check.name}\n", 1)[1].split("\n## ", 1)[0]
        assert check.bad.strip() in section and check.good.strip() in section, check.code


# --- the checks the issue found untested, end to end -------------------------------------------

NAV_LAUNCH = """from launch import LaunchDescription
from nav2_common.launch import RewrittenYaml


def generate_launch_description():
    return LaunchDescription([])
"""
EXTRA_LAUNCH = """from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('world'),  # no default
        Node(package='rviz2', executable='rviz2', arguments=['-d', LaunchConfiguration('world')]),
    ])
"""
ROS1_LAUNCH = """<launch>
  <param name="robot_description" textfile="$(find rob_description)/urdf/robot.urdf"/>
</launch>
"""
NEEDS_ARGUMENT = """<?xml version="1.0"?>
<robot name="parts" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <link name="$(arg prefix)base"/>
</robot>
"""
MESHES_URDF = """<?xml version="1.0"?>
<robot name="meshes">
  <link name="base">
    <visual><geometry><mesh filename="file://{package}/meshes/source.stl"/></geometry></visual>
  </link>
  <link name="arm">
    <visual><geometry><mesh filename="package://rob_description/meshes/broken.stl"/></geometry></visual>
  </link>
  <joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint>
</robot>
"""


def defective_package(workspace: Path) -> Path:
    """A package made by `pkgforge new`, then one defect for each check the issue found untested."""
    (workspace / "src").mkdir(exist_ok=True)
    package = new_package(workspace, "rob_description")
    (package / "launch" / "extra.launch.py").write_text(EXTRA_LAUNCH)
    (package / "launch" / "nav.launch.py").write_text(NAV_LAUNCH)
    (package / "launch" / "old.launch").write_text(ROS1_LAUNCH)
    manifest = package / "package.xml"
    manifest.write_text(
        manifest.read_text().replace(
            "  <exec_depend>xacro</exec_depend>\n",
            "  <exec_depend>xacro</exec_depend>\n  <exec_depend>nav2_common</exec_depend>\n",
            1,
        )
    )
    stl = (package / "meshes" / "arm.stl").read_bytes()
    (package / "meshes" / "source.stl").write_bytes(stl)
    (package / "meshes" / "broken.stl").write_bytes(stl[:120])  # the header promises more triangles
    (package / "urdf" / "parts.urdf.xacro").write_text(NEEDS_ARGUMENT)
    (package / "urdf" / "meshes.urdf").write_text(MESHES_URDF.format(package=package))
    return package


@pytest.fixture(scope="module")
def defective(tmp_path_factory):
    workspace = tmp_path_factory.mktemp("defective")
    package = defective_package(workspace)
    result = run_pkgforge("verify", ".", "--format", "json", "--no-cache", cwd=workspace)
    assert result.returncode == 1 and "Traceback" not in result.stderr, result.stdout + result.stderr
    return package, json.loads(result.stdout)


# (code, file in the package, text on the line, or None for a diagnostic of the whole file, severity);
# each marked with its code, a literal: test_every_check_code_is_triggered_by_an_end_to_end_test reads it
UNTESTED = [
    pytest.param(
        "PF309",
        "launch/extra.launch.py",
        "DeclareLaunchArgument('world')",
        "info",
        marks=pytest.mark.triggers("PF309"),
        id="PF309",
    ),
    pytest.param(
        "PF311",
        "launch/nav.launch.py",
        "from nav2_common.launch import",
        "info",
        marks=pytest.mark.triggers("PF311"),
        id="PF311",
    ),
    pytest.param("PF312", "launch/old.launch", None, "info", marks=pytest.mark.triggers("PF312"), id="PF312"),
    pytest.param(
        "PF404", "urdf/meshes.urdf", "file://", "warning", marks=pytest.mark.triggers("PF404"), id="PF404"
    ),
    pytest.param(
        "PF405", "urdf/meshes.urdf", "broken.stl", "error", marks=pytest.mark.triggers("PF405"), id="PF405"
    ),
    pytest.param(
        "PF406",
        "urdf/parts.urdf.xacro",
        "$(arg prefix)",
        "info",
        marks=pytest.mark.triggers("PF406"),
        id="PF406",
    ),
]


@pytest.mark.parametrize("code, relative, text, severity", UNTESTED)
def test_untested_check_found_at_its_line(defective, code, relative, text, severity):
    package, report = defective
    line = line_of(package / relative, text) if text else None
    found = [(d["path"], d["line"], d["severity"]) for d in report["diagnostics"] if d["code"] == code]
    assert found == [(f"src/rob_description/{relative}", line, severity)], report["diagnostics"]


def test_each_defect_is_one_diagnostic(defective):
    _, report = defective
    assert sorted(d["code"] for d in report["diagnostics"]) == sorted(case.values[0] for case in UNTESTED)


# --- pkgforge.toml: validated, severity per check --------------------------------------------


@pytest.fixture
def workspace(tmp_path) -> Path:
    (tmp_path / "src").mkdir()
    package = new_package(tmp_path, "rob_description")
    manifest = package / "package.xml"
    manifest.write_text(
        manifest.read_text().replace(
            "  <exec_depend>xacro</exec_depend>\n",
            "  <exec_depend>xacro</exec_depend>\n  <exec_depend>tf2_ros</exec_depend>\n",
            1,
        )
    )  # PF107, info
    return tmp_path


@pytest.mark.parametrize(
    "content, line, says",
    [
        (
            '[verify]\nselect = ["PF1"]\nignor = ["PF107"]\n',
            3,
            "unknown key 'verify.ignor' (did you mean 'ignore'? known here: select, ignore, distro, packages, "
            "per-file-ignores)",
        ),
        ('[verfy]\nignore = ["PF107"]\n', 1, "unknown key 'verfy' (did you mean 'verify'?"),
        (
            '[verify]\nignore = "PF107"\n',
            2,
            "'verify.ignore' must be a list of check codes, code prefixes or names, not 'PF107'",
        ),
        ("[verify.packages]\nrob_description = 1\n", 2, "'verify.packages.rob_description' must be a table"),
        (
            '[verify.packages.rob_description]\nselect = ["PF1"]\n',
            2,
            "unknown key 'verify.packages.rob_description.select'",
        ),
        (
            '\n[severity]\nPF107 = "fatal"\n',
            3,
            "'severity.PF107' must be one of 'error', 'warning', 'info', not 'fatal'",
        ),
        ('[severity]\nPF1O7 = "error"\n', 2, "severity.PF1O7: no check is named or coded 'PF1O7'"),
        ('severity = ["PF107"]\n', 1, "'severity' must be a table ([severity])"),
        # [verify.per-file-ignores] (issue 30): a glob's checks a list of known checks, at its line
        (
            '[verify.per-file-ignores]\n"launch/*.py" = "PF301"\n',
            2,
            "'verify.per-file-ignores.\"launch/*.py\"' must be a list of check codes, code prefixes or "
            "names, not 'PF301'",
        ),
        (
            '[verify.per-file-ignores]\n"*.py" = ["PF3O1"]\n',
            2,
            "verify.per-file-ignores.\"*.py\": no check is named or coded 'PF3O1' (did you mean",
        ),
        ("[verify]\nper-file-ignores = 3\n", 2, "'verify.per-file-ignores' must be a table"),
    ],
)
def test_bad_pkgforge_toml_names_file_line_and_key(workspace, content, line, says):
    (workspace / "pkgforge.toml").write_text(content)
    result = run_pkgforge("verify", ".", cwd=workspace)
    assert result.returncode == 2 and result.stdout == "", result.stdout + result.stderr
    assert result.stderr.startswith(f"pkgforge: error: {workspace / 'pkgforge.toml'}:{line}: {says}"), (
        result.stderr
    )
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr


@pytest.mark.parametrize(
    "content, line",
    [("[verify\n", 1), ('[verify]\nignore = ["PF107"\n', 2), ("[verify]\nignore = []\nignore = []\n", 3)],
)
def test_malformed_pkgforge_toml_is_exit_2_with_its_line(workspace, content, line):
    config = workspace / "src" / "rob_description" / "pkgforge.toml"  # a package's own file
    config.write_text(content)
    result = run_pkgforge("verify", ".", cwd=workspace)
    assert (
        result.returncode == 2 and "Traceback" not in result.stderr and "internal error" not in result.stderr
    )
    assert result.stderr.startswith(f"pkgforge: error: {config}: invalid TOML: ")
    assert re.search(rf"\(at (line {line}, column \d+|end of document, line {line})\)", result.stderr), (
        result.stderr
    )
    assert result.stderr.count("\n") == 1


@pytest.mark.triggers("PF107")
def test_severity_override_changes_report_and_exit_code(workspace):
    line = line_of(workspace / "src" / "rob_description" / "package.xml", "tf2_ros")

    def verify(*args):
        result = run_pkgforge("verify", ".", "--format", "json", *args, cwd=workspace)
        report = json.loads(result.stdout)
        return result.returncode, [
            (d["code"], d["path"], d["line"], d["severity"]) for d in report["diagnostics"]
        ]

    assert verify() == (0, [("PF107", "src/rob_description/package.xml", line, "info")])
    (workspace / "pkgforge.toml").write_text('[severity]\nunused-exec-depend = "error"\n')
    assert verify() == (1, [("PF107", "src/rob_description/package.xml", line, "error")])  # the cache follows
    # a code beats a prefix; a package's own file beats the workspace's
    (workspace / "pkgforge.toml").write_text('[severity]\nPF1 = "error"\nPF107 = "warning"\n')
    assert verify() == (0, [("PF107", "src/rob_description/package.xml", line, "warning")])
    assert verify("--strict")[0] == 1
    (workspace / "src" / "rob_description" / "pkgforge.toml").write_text('[severity]\nPF107 = "error"\n')
    assert verify() == (1, [("PF107", "src/rob_description/package.xml", line, "error")])


def test_colcon_verify_honours_severity_and_color(workspace):
    """An empty install base: the package is not installed (PF209, an error by default)."""
    (workspace / "install").mkdir()
    args = ("verify", "--install-base", "install", "--select", "PF209")
    plain = colcon(*args, cwd=workspace, env=dict(os.environ, NO_COLOR="1", FORCE_COLOR="1"))
    assert plain.returncode == 1, plain.stdout + plain.stderr
    assert (
        plain.stdout.startswith("src/rob_description/package.xml:4: PF209 [error]")
        and ANSI not in plain.stdout
    )
    forced = colcon(*args, "--color", "always", cwd=workspace)
    assert f"{ANSI}1mPF209{ANSI}0m" in forced.stdout
    (workspace / "pkgforge.toml").write_text('[severity]\npackage-not-installed = "warning"\n')
    relaxed = colcon(*args, cwd=workspace)
    assert relaxed.returncode == 0 and "PF209 [warning]" in relaxed.stdout, relaxed.stdout + relaxed.stderr


def test_colcon_verify_has_no_build_base_it_would_ignore(tmp_path):
    result = colcon("verify", "--help", cwd=tmp_path)
    assert (
        result.returncode == 0 and "--install-base" in result.stdout and "--build-base" not in result.stdout
    )


# --- colour ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "env, args, colored",
    [
        ({}, [], False),  # not a terminal
        ({"FORCE_COLOR": "1"}, [], True),
        ({"FORCE_COLOR": "0"}, [], False),
        ({"NO_COLOR": "1", "FORCE_COLOR": "1"}, [], False),  # NO_COLOR wins
        ({"NO_COLOR": "1"}, ["--color", "always"], True),  # the option wins
        ({"FORCE_COLOR": "1"}, ["--color", "never"], False),
    ],
)
def test_color_in_every_command(workspace, env, args, colored):
    environment = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")} | env
    package_xml = "src/rob_description/package.xml"
    for command in (["verify", "."], ["verify-files", package_xml]):
        result = run_pkgforge(*command, *args, cwd=workspace, env=environment)
        shown = result.stdout + result.stderr
        assert "PF107" in shown, (command, shown)
        assert (ANSI in shown) == colored, (command, env, args, shown)
    # fix --diff prints a diff for `git apply` and one line of counts (issue 30): never coloured
    result = run_pkgforge("fix", "--diff", ".", *args, cwd=workspace, env=environment)
    assert ANSI not in result.stdout + result.stderr


def test_color_option_refuses_other_values(workspace):
    result = run_pkgforge("verify", ".", "--color", "sometimes", cwd=workspace)
    assert result.returncode == 2 and "'sometimes' is not one of 'auto', 'always', 'never'" in result.stderr


# --- reports: GitLab code quality, SARIF helpUri, --junit-xml ----------------------------------


def test_gitlab_code_quality_report(workspace):
    package = workspace / "src" / "rob_description"
    line = line_of(package / "package.xml", "tf2_ros")
    result = run_pkgforge("verify", ".", "--format", "gitlab", cwd=workspace)
    assert result.returncode == 0, result.stderr
    (issue,) = json.loads(result.stdout)
    assert issue["check_name"] == "PF107 unused-exec-depend" and issue["severity"] == "info"
    assert issue["location"] == {"path": "src/rob_description/package.xml", "lines": {"begin": line}}
    assert re.fullmatch(r"[0-9a-f]{64}", issue["fingerprint"]) and issue["type"] == "issue"
    assert issue["description"].startswith("PF107 nothing in rob_description uses exec_depend 'tf2_ros'")
    # in a repository that is the package (what `pkgforge new --ci gitlab` makes), paths are the
    # repository's, as GitLab matches them to the merge request's files
    (package / ".git").mkdir()
    again = json.loads(run_pkgforge("verify", ".", "--format", "gitlab", "--no-cache", cwd=workspace).stdout)
    assert again[0]["location"]["path"] == "package.xml" and again[0]["fingerprint"] != issue["fingerprint"]


def test_gitlab_template_writes_the_code_quality_report(tmp_path):
    import yaml

    assert run_pkgforge("new", "rob", *MAINTAINER, "--ci", "gitlab", cwd=tmp_path).returncode == 0
    job = yaml.safe_load((tmp_path / "rob" / ".gitlab-ci.yml").read_text())["pkgforge"]
    verify = next(line for line in job["script"] if " verify " in line)
    assert '--format gitlab --output "$CI_PROJECT_DIR/gl-code-quality-report.json"' in verify
    assert job["artifacts"]["reports"]["codequality"] == "gl-code-quality-report.json"


def github_anchors(markdown: str) -> set[str]:
    """GitHub's heading anchors: lower case, punctuation but '-' dropped, spaces to '-'."""
    return {
        re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-")
        for heading in re.findall(r"^#+ (.+)$", markdown, re.M)
    }


def test_sarif_rules_point_at_their_docs_anchor(workspace):
    result = run_pkgforge("verify", ".", "--format", "sarif", cwd=workspace)
    driver = json.loads(result.stdout)["runs"][0]["tool"]["driver"]
    anchors = github_anchors((REPO / "docs" / "checks.md").read_text(encoding="utf-8"))
    assert len(driver["rules"]) == len(registered())
    for rule in driver["rules"]:
        document, _, anchor = rule["helpUri"].partition("#")
        assert document.startswith("file:///") and document.endswith("/checks.md"), rule["helpUri"]
        assert anchor == f"{rule['id'].lower()}-{rule['name']}"
        assert anchor in anchors, rule["helpUri"]
    assert "informationUri" not in driver  # pypi.org/project/pkgforge is another project


@pytest.mark.triggers("PF107")
def test_junit_xml_beside_the_text_report(workspace, tmp_path):
    from lxml import etree

    schema = etree.XMLSchema(etree.parse(str(TESTS / "schemas" / "junit.xsd")))

    def verify() -> tuple[int, str, dict]:
        junit = tmp_path / "reports" / "pkgforge.xml"
        result = run_pkgforge("verify", ".", "--junit-xml", junit, cwd=workspace)
        schema.assertValid(etree.parse(str(junit)))
        (suite,) = etree.parse(str(junit)).getroot().iter("testsuite")
        assert suite.get("name") == "rob_description"
        return result.returncode, result.stdout, {case.get("name"): case for case in suite.iter("testcase")}

    status, text, cases = verify()
    assert status == 0 and "PF107 [info]" in text  # the text report is still printed
    assert len(cases) == len(registered())
    assert not [name for name, case in cases.items() if case.find("failure") is not None]
    assert "src/rob_description/package.xml" in cases["PF107 unused-exec-depend"].findtext("system-out")
    (workspace / "pkgforge.toml").write_text('[severity]\nPF107 = "error"\n')
    status, text, cases = verify()
    assert status == 1 and "PF107 [error]" in text
    assert [name for name, case in cases.items() if case.find("failure") is not None] == [
        "PF107 unused-exec-depend"
    ]


def test_junit_xml_that_cannot_be_written_is_exit_2(workspace):
    (workspace / "taken").write_text("")
    result = run_pkgforge("verify", ".", "--junit-xml", "taken/report.xml", cwd=workspace)
    assert result.returncode == 2 and result.stderr.startswith("pkgforge: error: ")
    assert "taken" in result.stderr and "Traceback" not in result.stderr


# --- parallel model loading ------------------------------------------------------------------


@pytest.mark.triggers("PF101", "PF103", "PF104")
def test_parallel_model_loading_matches_the_serial_one(tmp_path):
    """16 packages or more and -j 2 load the models in worker processes while colcon discovers;
    the result must be the serial one (including a folder named unlike its package, and a
    manifest catkin_pkg refuses: the loaders leave catkin_pkg to colcon's discovery, so that
    package is loaded again with catkin_pkg's message)."""
    import shutil

    from pkgforge.verify.discovery import PARALLEL_THRESHOLD

    (tmp_path / "src").mkdir()
    first = new_package(tmp_path, "p00_description")
    for number in range(1, PARALLEL_THRESHOLD + 2):
        name = f"p{number:02d}_description"
        copy = tmp_path / "src" / name
        shutil.copytree(first, copy)
        for file in ("package.xml", "CMakeLists.txt"):
            (copy / file).write_text((copy / file).read_text().replace("p00_description", name))
    renamed = tmp_path / "src" / "p05_description"
    (renamed / "package.xml").write_text(
        (renamed / "package.xml")
        .read_text()
        .replace("<name>p05_description</name>", "<name>p05_robot</name>")
    )

    refused = tmp_path / "src" / "p07_description"
    (refused / "package.xml").write_text(
        re.sub(r"<version>[^<]*</version>", "<version>1.0</version>", (refused / "package.xml").read_text())
    )

    def verify(jobs: str) -> dict:
        result = run_pkgforge(
            "verify", ".", "--format", "json", "--no-cache", "--select", "PF1", "-j", jobs, cwd=tmp_path
        )
        assert result.returncode == 1, result.stdout + result.stderr
        return json.loads(result.stdout)

    parallel, serial = verify("2"), verify("1")
    assert parallel == serial
    assert len(parallel["packages"]) == PARALLEL_THRESHOLD + 2
    found = {(d["code"], d["path"], d["line"]) for d in parallel["diagnostics"]}
    assert found == {
        ("PF101", "src/p07_description/package.xml", line_of(refused / "package.xml", "<version>")),
        ("PF103", "src/p05_description/CMakeLists.txt", line_of(renamed / "CMakeLists.txt", "project(")),
        ("PF104", "src/p05_description/package.xml", line_of(renamed / "package.xml", "<name>")),
    }
    (message,) = [d["message"] for d in parallel["diagnostics"] if d["code"] == "PF101"]
    assert message == 'Package version "1.0" does not follow version conventions'


# --- packaging -------------------------------------------------------------------------------


def test_wheel_metadata_is_honest():
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib

    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    assert project["license"] == "Apache-2.0" and project["license-files"] == ["LICENSE"]
    assert (REPO / "LICENSE").read_text().lstrip().startswith("Apache License")
    assert (REPO / "src" / "pkgforge" / "py.typed").is_file()
    classifiers = project["classifiers"]
    assert not [c for c in classifiers if c.startswith("Framework :: Robot Framework")]  # a test framework
    assert not [c for c in classifiers if c.startswith("License ::")]  # PEP 639: the expression says it
    trove = pytest.importorskip("trove_classifiers")
    assert set(classifiers) <= trove.classifiers
    text = (REPO / "pyproject.toml").read_text()
    assert "example.invalid" not in text and "example.com" not in text


def test_shell_completion_is_documented_and_works(tmp_path):
    readme = (REPO / "README.md").read_text()
    assert 'eval "$(_PKGFORGE_COMPLETE=bash_source pkgforge)"' in readme
    env = dict(os.environ, _PKGFORGE_COMPLETE="bash_complete", COMP_WORDS="pkgforge ru", COMP_CWORD="1")
    result = subprocess.run(
        [str(SCRIPTS / "pkgforge")], env=env, capture_output=True, text=True, timeout=60, cwd=tmp_path
    )
    assert result.returncode == 0 and "plain,rule" in result.stdout.split(), result.stdout + result.stderr


def test_exit_status_with_a_standard_stream_closed():
    """Started with stdout or stderr closed (`>&-`), Python has no stream there: the command's
    own exit status still comes out (cli.app._exit_now flushes only the streams that exist)."""
    for closed, args, status in ((1, ["checks"], 0), (2, ["checks"], 0), (2, ["rule", "PF999"], 2)):
        result = subprocess.run(
            [sys.executable, "-m", "pkgforge", *args],
            stdout=subprocess.DEVNULL if closed == 2 else None,
            stderr=subprocess.DEVNULL if closed == 1 else None,
            preexec_fn=lambda fd=closed: os.close(fd),  # noqa: PLW1509 - only os.close, before exec
            timeout=120,
        )
        assert result.returncode == status, (closed, args, result.returncode)


def test_the_readme_main_job_leaves_the_test_command_clean(tmp_path):
    """Issue 30: the README's main job builds its workspace in the checkout (ws/); the test command
    after it runs `ruff check .` and `ruff format --check .` there, which must not read ws/'s
    generated Python (colcon's install/*.py, a package's setup.py)."""
    readme = (REPO / "README.md").read_text()
    main_job = re.search(r"Run the main job.*?```sh\n(.+?)\n```", readme, re.S).group(1)
    assert "--destination ws/src" in main_job and "pkgforge build ws" in main_job, main_job
    shutil.copy(REPO / "pyproject.toml", tmp_path / "pyproject.toml")
    generated = tmp_path / "ws" / "install"
    generated.mkdir(parents=True)
    (generated / "_local_setup_util_sh.py").write_text("import os, sys\nx  =  [ 1,2 ]\n")
    for command in (["check", "."], ["format", "--check", "."]):
        result = subprocess.run(
            [str(SCRIPTS / "ruff"), *command], cwd=tmp_path, capture_output=True, text=True, timeout=120
        )
        assert result.returncode == 0, (command, result.stdout + result.stderr)


@pytest.mark.parametrize("command", [["verify"], ["fix", "--unsafe-fixes"]])
def test_the_readme_examples_are_what_pkgforge_prints(tmp_path, command):
    """Issue 30: the README's `pkgforge verify` and `pkgforge fix` examples are a real run on the
    workspace of seed000 and seed001 (regenerate them from one when the output changes). A
    sandbox note (what this machine's kernel lacks) is the machine's, not the example's."""
    from conftest import copy_fixture

    copy_fixture("seed000/rob_description", tmp_path)
    copy_fixture("seed001/small_turtle", tmp_path)
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_DISTRO", "PKGFORGE_LAUNCH_DISTRO")}
    result = run_pkgforge(*command, cwd=tmp_path, env=env)
    assert result.returncode in (0, 1), result.stderr
    printed = re.sub(r"; sandbox weaker: [^\n]*", "", result.stdout)
    readme = (REPO / "README.md").read_text()
    shown = f"```\n$ pkgforge {' '.join(command)}\n"
    assert shown in readme, shown
    start = readme.index(shown) + len(shown)
    assert readme[start : readme.index("```\n", start)] == printed
