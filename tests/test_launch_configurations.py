"""Issue 28, class 1: launch configurations that do not exist.

`LaunchConfiguration('x')` (`$(var x)`) with no default, where nothing declared or set x when
the action executes: `ros2 launch` stops with "launch configuration 'x' does not exist". Each
case is a launch file of tests/fixtures/launch_configurations/config_bot, verified through the
built-in engine and the real launch libraries of humble and jazzy (tests/ros_prefix.py): the
same diagnostics, at the substitution's line. The oracle compares the records themselves
(tests/test_launch_oracle.py, the execute level among them).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import FIXTURES, copy_fixture, line_of, verify_report
from ros_prefix import DISTROS, make_prefix

PACKAGE = FIXTURES / "launch_configurations" / "config_bot"
LAUNCH = PACKAGE / "launch"
SOURCE = "src/config_bot/launch/"
ENGINES = ["builtin", *DISTROS]

# (file, the text on the substitution's line, the configuration): each an error, at that line
UNSET = [
    ("node_parameters.launch.py", "LaunchConfiguration('use_sim_time')", "use_sim_time"),
    ("node_fields.launch.py", "LaunchConfiguration('rviz_config')", "rviz_config"),
    ("node_fields.launch.py", "LaunchConfiguration('cmd_topic')", "cmd_topic"),
    ("node_fields.launch.py", "LaunchConfiguration('node_name')", "node_name"),
    ("node_fields.launch.py", "LaunchConfiguration('robot_ns')", "robot_ns"),
    ("node_fields.launch.py", "LaunchConfiguration('log_level')", "log_level"),
    ("node_fields.launch.py", "LaunchConfiguration('label')", "label"),
    ("condition.launch.py", "LaunchConfiguration('use_rviz')", "use_rviz"),
    ("include_argument.launch.py", "LaunchConfiguration('robot_name')", "robot_name"),
    ("timer.launch.py", "LaunchConfiguration('use_sim_time')", "use_sim_time"),
    ("handler.launch.py", "LaunchConfiguration('rviz_config')", "rviz_config"),
    ("handler_target_in_timer.launch.py", "LaunchConfiguration('rviz_config')", "rviz_config"),
    ("process.launch.py", "LaunchConfiguration('bag_folder')", "bag_folder"),
    ("process.launch.py", "LaunchConfiguration('domain')", "domain"),
    ("process.launch.py", "LaunchConfiguration('output')", "output"),
    ("process.launch.py", "LaunchConfiguration('respawn')", "respawn"),
    ("timer_scoped_group.launch.py", "LaunchConfiguration('robot')", "robot"),
    ("scoped_include.launch.py", "LaunchConfiguration('robot')", "robot"),
    ("launch_arg.launch.py", "LaunchConfiguration('robot_model')", "robot_model"),
    ("param_file_substs.launch.py", "'substs.yaml'", "use_sim_time"),
    ("opaque.launch.py", "LaunchConfiguration('mode')", "mode"),
    ("argument_default.launch.py", "LaunchConfiguration('robot_type')", "robot_type"),
    ("undeclared.launch.xml", "$(var use_sim_time)", "use_sim_time"),
    ("undeclared.launch.xml", "$(var use_rviz)", "use_rviz"),
    ("undeclared.launch.xml", "$(var bag_folder)", "bag_folder"),
    ("undeclared.launch.xml", "$(var robot_ns)", "robot_ns"),
    ("undeclared.launch.xml", "$(var output)", "output"),
    ("undeclared.launch.yaml", "- name: use_sim_time", "use_sim_time"),  # the <param> element
    # the <let> fails; the node using what it would have set is its consequence, not said again;
    # an include's <arg> and a <remap> stand on their own lines
    ("cascade.launch.xml", "$(var headless)", "headless"),
    ("cascade.launch.xml", "$(var robot_name)", "robot_name"),
    ("cascade.launch.xml", "$(var joint_topic)", "joint_topic"),
    ("undeclared.launch.yaml", "# rviz, if use_rviz", "use_rviz"),  # the <node> element
]
# the nearest cases that must stay clean: declared in an include, a default, <let>/SetLaunchConfiguration,
# declared after a handler that runs later, an unscoped group, chained include arguments, values given
CLEAN = [
    "declared_in_include.launch.py",
    "declares.launch.py",
    "defaults.launch.py",
    "handler_declared_after.launch.py",
    "handler_target_not_started.launch.py",
    "timer_unscoped_group.launch.py",
    "include_chained_arguments.launch.py",
    "bringup.launch.py",
    "process_values.launch.py",
    "process_values.launch.xml",
]


@pytest.fixture(scope="module")
def prefixes(tmp_path_factory) -> dict[str, Path]:
    base = tmp_path_factory.mktemp("ros")
    out = {}
    for distro in DISTROS:
        prefix, reason = make_prefix(distro, base)
        if prefix is None:
            pytest.skip(f"no real ROS 2 launch library for {distro}: {reason}")
        out[distro] = prefix
    return out


def _engine_options(engine: str, prefixes: dict[str, Path]) -> list[str]:
    if engine == "builtin":
        return ["--launch-engine", "builtin", "--distro", "jazzy"]
    return ["--launch-engine", "ros", "--ros-prefix", str(prefixes[engine]), "--distro", engine]


@pytest.fixture(scope="module")
def reports(tmp_path_factory, prefixes) -> dict[tuple[str, str], dict]:
    """(engine, "" or the --launch-arg given) -> verify's JSON report of config_bot."""
    workspace = tmp_path_factory.mktemp("configs")
    (workspace / "src").mkdir()
    copy_fixture("launch_configurations/config_bot", workspace)
    out = {}
    for engine in ENGINES:
        options = _engine_options(engine, prefixes)
        out[engine, ""] = verify_report(workspace, "--no-cache", *options)[1]
        out[engine, "robot_model:=r2"] = verify_report(
            workspace, "--no-cache", "--launch-arg", "robot_model:=r2", *options
        )[1]
    return out


def _found(report: dict, code: str) -> list[tuple[str, int, str]]:
    return sorted((d["path"], d["line"], d["severity"]) for d in report["diagnostics"] if d["code"] == code)


@pytest.mark.triggers("PF320")
@pytest.mark.parametrize("engine", ENGINES)
def test_each_configuration_not_set_is_an_error_at_its_substitution(reports, engine):
    report = reports[engine, ""]
    expected = sorted({(SOURCE + file, line_of(LAUNCH / file, text), "error") for file, text, _ in UNSET})
    expected.append(
        (SOURCE + "robot.launch.py", line_of(LAUNCH / "robot.launch.py", "'robot_name'"), "warning")
    )
    uncertain = LAUNCH / "after_unevaluated_include.launch.py"
    expected.append(
        (SOURCE + uncertain.name, line_of(uncertain, "LaunchConfiguration('use_sim_time')"), "info")
    )
    assert _found(report, "PF320") == sorted(expected)
    by_place = {(d["path"], d["line"]): d for d in report["diagnostics"] if d["code"] == "PF320"}
    for file, text, name in UNSET:
        finding = by_place[SOURCE + file, line_of(LAUNCH / file, text)]
        assert f"launch configuration '{name}' does not exist" in finding["message"], finding
        assert name in finding["hint"], finding
    # nothing else is said of them: no launch-load-error beside it
    assert not [d for d in report["diagnostics"] if d["code"] == "PF301"]


@pytest.mark.parametrize("engine", ENGINES)
def test_the_nearest_cases_stay_clean(reports, engine):
    """Declared in an included file, a default, a value set before, a handler that runs after the
    declaration, an unscoped group, an include argument using the one given before it."""
    report = reports[engine, ""]
    for file in CLEAN:
        assert [d for d in report["diagnostics"] if d["path"] == SOURCE + file] == [], file


@pytest.mark.parametrize("engine", ENGINES)
def test_a_required_argument_declared_after_its_use_is_only_required(reports, engine):
    """ros2 launch refuses to start without robot:=..., so the node before the declaration has it."""
    report = reports[engine, ""]
    found = [
        (d["code"], d["line"])
        for d in report["diagnostics"]
        if d["path"] == SOURCE + "required_argument.launch.py"
    ]
    assert found == [
        ("PF309", line_of(LAUNCH / "required_argument.launch.py", "DeclareLaunchArgument('robot')"))
    ]


@pytest.mark.parametrize("engine", ENGINES)
def test_a_launch_arg_gives_the_configuration_its_value(reports, engine):
    report = reports[engine, "robot_model:=r2"]
    assert [d for d in report["diagnostics"] if d["path"] == SOURCE + "launch_arg.launch.py"] == []
    assert _found(report, "PF320") == [
        f for f in _found(reports[engine, ""], "PF320") if f[0] != SOURCE + "launch_arg.launch.py"
    ]


@pytest.mark.parametrize("engine", ENGINES)
def test_what_runs_after_the_description_says_so(reports, engine):
    """A timer's or a handler's action runs once the description is done: said, and for a scoped
    group's configuration (ros2/launch#825), that the group has ended by then."""
    by_file = {
        d["path"].rsplit("/", 1)[1]: d for d in reports[engine, ""]["diagnostics"] if d["code"] == "PF320"
    }
    assert (
        "(in a TimerAction: its actions run when its period has passed"
        in by_file["timer.launch.py"]["message"]
    )
    assert (
        "(in an OnProcessExit: its actions run when its event comes"
        in by_file["handler.launch.py"]["message"]
    )
    scoped = by_file["timer_scoped_group.launch.py"]
    assert (
        "robot is set where the TimerAction stands, but the scoped GroupAction around it" in scoped["message"]
    )
    assert "outside the scoped GroupAction" in scoped["hint"]
    included = by_file["robot.launch.py"]
    bringup = line_of(LAUNCH / "bringup.launch.py", "IncludeLaunchDescription(")
    assert f"bringup.launch.py:{bringup} includes it with robot_name:=..." in included["message"]
    assert included["hint"].startswith("launch it through its includer")


def test_the_hint_speaks_the_file_s_format(reports):
    hints = {
        d["path"].rsplit(".", 1)[1]: d["hint"]
        for d in reports["builtin", ""]["diagnostics"]
        if d["code"] == "PF320"
    }
    assert hints["xml"].startswith('declare it with <arg name="')
    assert hints["yaml"].startswith("declare it with `- arg: {name: ")
    assert hints["py"].startswith("declare it with DeclareLaunchArgument('")


@pytest.mark.parametrize("engine", ENGINES)
def test_after_an_include_not_evaluated_here_it_is_not_known(reports, engine):
    """nav2_bringup is declared, not installed here: its bringup_launch.py may declare use_sim_time
    (launch lets an included file's declarations stand after the include), so no error."""
    (finding,) = [
        d
        for d in reports[engine, ""]["diagnostics"]
        if d["path"] == SOURCE + "after_unevaluated_include.launch.py" and d["code"] == "PF320"
    ]
    assert finding["severity"] == "info"
    assert (
        "unless nav2_bringup/launch/bringup_launch.py, included before it and not evaluated here"
        in (finding["message"])
    )
