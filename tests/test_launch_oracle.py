"""The oracle: every launch file through both engines, the records compared.

The real engine is the ROS 2 `launch` libraries of humble and jazzy from
../shared/upstream/ros2-launch, laid out as a ROS prefix at test time
(tests/ros_prefix.py); the built-in engine is pkgforge's own. Each launch file of
the fixtures, of every `pkgforge new` variant and of the conformance set
(tests/fixtures/launch_conformance) must give identical records: nodes, package
lookups, paths, includes, commands, conditions, arguments, errors, each with its
file, line and the argument values it was seen with. Order is not compared (ROS
gives none that a check relies on). Where the built-in engine differs today, the
file is xfail(strict=True) with the difference as the reason.
"""

from __future__ import annotations

import json
import os
import re
import shutil
from pathlib import Path

import pytest
from conftest import FIXTURES, VARIANTS, copy_fixture, new_package
from ros_prefix import DISTROS, make_prefix

from pkgforge.launch.engines import LaunchEngine, builtin
from pkgforge.launch.records import ITEM_KINDS, as_dict

CONFORMANCE = FIXTURES / "launch_conformance"
PATTERNS = FIXTURES / "launch_patterns" / "pattern_bot"  # issue 10's patterns of real packages
CONFIGS = (
    FIXTURES / "launch_configurations" / "config_bot"
)  # issue 28: configurations with and without a value
SUFFIXES = (".launch.py", ".launch.xml", ".launch.yaml")


def _launch_files() -> list[str]:
    """Every launch file the oracle evaluates, as package/launch/name."""
    files = ["rob_description/launch/display.launch.py", "small_turtle/launch/display.launch.py"]
    files += [f"small_turtle/launch/{p.name}" for p in sorted((FIXTURES / "launch").iterdir())]
    for name, options in VARIANTS.items():
        fmt = options[options.index("--launch-format") + 1] if "--launch-format" in options else "py"
        files.append(f"{name}/launch/display.launch.{fmt}")
    files += [
        f"launch_conformance/launch/{p.name}"
        for p in sorted(CONFORMANCE.iterdir())
        if p.name.endswith(SUFFIXES)
    ]
    files += [f"pattern_bot/launch/{p.name}" for p in sorted((PATTERNS / "launch").iterdir())]
    files += [f"config_bot/launch/{p.name}" for p in sorted((CONFIGS / "launch").iterdir())]
    return files


FILES = _launch_files()

C = "launch_conformance/launch/"
# names that exist from Iron on: in humble, importing them is an error, as in ROS
NOT_IN_HUMBLE = {
    C + f
    for f in (
        "py_all_any.launch.py",
        "py_equals_typed.launch.py",
        "py_file_content.launch.py",
        "py_not_equals_if_else.launch.py",
        "xml_equals.launch.xml",
        "xml_file_content.launch.xml",
    )
}
# files that do not load in ROS (status load-error is what is compared)
LOAD_ERRORS = {
    (d, f) for d in DISTROS for f in FILES if f.startswith(C + "error_") and "bad_node" not in f
} | {("humble", f) for f in NOT_IN_HUMBLE}
P = "pattern_bot/launch/"
# the patterns ROS refuses (bool default: TypeError; nav2_common not installed here; jazzy's own
# front end on $(any)/$(all)), and in humble what only Iron on has ($(equals), $(file-content),
# <push_ros_namespace>...)
LOAD_ERRORS |= {
    (d, P + f)
    for d in DISTROS
    for f in ("all_any.launch.xml", "bool_default.launch.py", "nav2_style.launch.py")
} | {
    ("humble", P + f)
    for f in (
        "equals_typed.launch.py",
        "equals_typed.launch.xml",
        "file_content.launch.xml",
        "frontend_tags.launch.xml",
        "frontend_tags.launch.yaml",
        "push_namespace.launch.xml",
        "unsupported_api.launch.py",
    )
}

# Differences still found, each an xfail(strict=True) whose reason points to its entry in
# docs/launch-builtin.md ("docs/launch-builtin.md#anchor: what differs"):
# (distro or None for both, file) → the difference. None today: both engines agree on every file.
KNOWN_DIFFERENCES: dict[tuple[str | None, str], str] = {}


def _params():
    out = []
    for distro in DISTROS:
        for file in FILES:
            reason = KNOWN_DIFFERENCES.get((distro, file)) or KNOWN_DIFFERENCES.get((None, file))
            marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
            out.append(pytest.param(distro, file, marks=marks, id=f"{distro}-{file}"))
    return out


@pytest.fixture(scope="module")
def oracle_workspace(tmp_path_factory) -> Path:
    """The fixtures, every `pkgforge new` variant and the conformance package, in one workspace."""
    workspace = tmp_path_factory.mktemp("oracle")
    (workspace / "src").mkdir()
    copy_fixture("seed000/rob_description", workspace)
    turtle = copy_fixture("seed001/small_turtle", workspace)
    for launch in sorted((FIXTURES / "launch").iterdir()):
        shutil.copy(launch, turtle / "launch")
    copy_fixture("launch_patterns/pattern_bot", workspace)
    copy_fixture("launch_configurations/config_bot", workspace)
    for name, options in VARIANTS.items():
        new_package(workspace, name, *options)
    package = workspace / "src" / "launch_conformance"
    shutil.copytree(CONFORMANCE, package, ignore=shutil.ignore_patterns(*[f"*{s}" for s in SUFFIXES]))
    (package / "launch").mkdir()
    for launch in CONFORMANCE.iterdir():
        if launch.name.endswith(SUFFIXES):
            shutil.copy(launch, package / "launch")
    return workspace


@pytest.fixture(scope="module")
def prefixes(tmp_path_factory) -> dict[str, Path]:
    base = tmp_path_factory.mktemp("ros")
    out = {}
    for distro in DISTROS:
        prefix, reason = make_prefix(distro, base)
        if prefix is None:
            print(f"oracle skipped: {reason}")
            if os.environ.get("CI"):  # CI has shared/ beside the clone: a skip there hides a broken setup
                pytest.fail(f"the oracle must run in CI: {reason}")
            pytest.skip(f"no real ROS 2 launch library for {distro}: {reason}")
        out[distro] = prefix
    return out


def _canonical(resolution) -> dict:
    """A resolution as comparable data: every record without its order."""
    error = as_dict(resolution.error) if resolution.error else None
    if error:
        error.pop("branches"), error.pop("branch")
        # where the module that raised lives differs: the distro's launch, or pkgforge's
        error["message"] = re.sub(r" \((?:/|<)[^\n]*?\.py\)", "", error["message"])
    # the same argument combinations planned by both engines; at this limit every one evaluated
    out = {
        "status": resolution.status,
        "error": error,
        "combinations": [resolution.branching.planned, resolution.branching.evaluated],
        "arguments": sorted(json.dumps(_strip(as_dict(a)), sort_keys=True) for a in resolution.arguments),
    }
    for kind in ITEM_KINDS:
        out[kind] = sorted(
            json.dumps(_strip(as_dict(r)), sort_keys=True, default=str) for r in getattr(resolution, kind)
        )
    return out


def _strip(data: dict) -> dict:
    data.pop("branch", None)
    data["branches"] = sorted(data.get("branches", []))
    data.pop("robot", None)  # the model's structure: the same xacro run in both
    return data


@pytest.fixture(scope="module")
def evaluations(prefixes, oracle_workspace) -> dict:
    """(engine, file) → canonical records; every file through the built-in engine and each distro."""
    from pkgforge.launch.resolve import find_launch_files, resolve
    from pkgforge.verify.discovery import load_models
    from pkgforge.verify.pipeline import VerifyOptions, make_tree
    from pkgforge.workspace import locate

    workspace = locate(oracle_workspace)
    _, models = load_models(workspace, 1)
    tree = make_tree(VerifyOptions(), workspace, list(models.values()))
    try:
        launch_files, _ = find_launch_files(tree, list(models.values()))
        source = oracle_workspace.resolve() / "src"
        by_name = {f.source.resolve().relative_to(source).as_posix(): f for f in launch_files if f.source}
        missing = sorted(set(FILES) - set(by_name))
        assert not missing, f"not installed, so not evaluated: {missing}"
        chosen = [by_name[f] for f in FILES]
        out = {}
        for distro, prefix in prefixes.items():
            # the built-in engine held to the same distro's names, as `verify --distro` holds it
            engines = {
                f"builtin-{distro}": builtin(distro),
                distro: LaunchEngine("ros", str(prefix), distro, "test"),
            }
            for label, engine in engines.items():
                resolutions = resolve(chosen, tree, jobs=2, timeout=60, engine=engine)
                for name, resolution in zip(FILES, resolutions, strict=False):
                    out[label, name] = _canonical(resolution)
        return out
    finally:
        tree.close()


@pytest.mark.parametrize("distro,file", _params())
def test_both_engines_give_the_same_records(evaluations, distro, file):
    real, builtin = evaluations[distro, file], evaluations[f"builtin-{distro}", file]
    assert real["status"] == ("load-error" if (distro, file) in LOAD_ERRORS else "ok"), real["error"]
    differences = {
        kind: {
            "ros": _differing(real[kind], builtin[kind]),
            "built-in": _differing(builtin[kind], real[kind]),
        }
        for kind in real
        if real[kind] != builtin[kind]
    }
    assert not differences, json.dumps(differences, indent=1)


def _differing(mine, theirs):
    """What `mine` has that `theirs` lacks, shown by the fields that differ from the nearest of theirs."""
    if not isinstance(mine, list):
        return mine
    out = []
    others = [json.loads(t) for t in theirs if t not in mine]
    for text in mine:
        if text in theirs:
            continue
        record = json.loads(text)
        near = min(others, key=lambda o: sum(o.get(k) != v for k, v in record.items()), default=None)
        if near is None:
            out.append(record)
        else:
            same = {"file": record.get("file", "").rsplit("/", 3)[-3:] if record.get("file") else None}
            out.append(
                {
                    **{k: v for k, v in record.items() if near.get(k) != v},
                    **({"name": record["name"]} if "name" in record else {}),
                    "where": same,
                }
            )
    return out


def test_the_oracle_covers_at_least_60_files_per_distro():
    assert len(FILES) >= 60, len(FILES)


def _commands(evaluations, label: str, file: str) -> list[tuple]:
    """(program, ok, runtime_only) of each command a file's evaluation recorded."""
    return sorted(
        (c["command"][0], c["ok"], c["runtime_only"])
        for c in map(json.loads, evaluations[label, C + file]["commands"])
    )


@pytest.mark.parametrize("distro", DISTROS)
def test_one_command_policy_in_both_engines(evaluations, distro):
    """records.runs_at_verify_time decides for both engines: cat of a file runs (and fails on a
    file that is not there, as in ROS), a run-time query is recorded as run-time only, never run."""
    for label in (distro, f"builtin-{distro}"):
        assert _commands(evaluations, label, "py_command_cat.launch.py") == [
            ("cat", False, False),
            ("cat", True, False),
        ], label
        assert _commands(evaluations, label, "py_command_runtime_query.launch.py") == [
            ("ros2", True, True)
        ], label
        assert _commands(evaluations, label, "xml_command_runtime.launch.xml") == [
            ("cat", True, False),
            ("ros2", True, True),
        ], label


@pytest.mark.parametrize("distro", DISTROS)
def test_a_package_not_found_keeps_what_uses_it(evaluations, distro):
    """Issue 10, item 4, in both engines: the lookup is reported, the package stands in as an
    empty one, and the node or process using it is still recorded, with what follows it."""
    for label in (distro, f"builtin-{distro}"):
        records = evaluations[label, C + "py_unknown_package.launch.py"]
        assert sorted(json.loads(n)["package"] for n in records["nodes"]) == [
            "robot_state_publisher",
            "rviz2",
        ]
        assert [
            (p["name"], p["found"])
            for p in map(json.loads, records["packages"])
            if p["name"] == "not_a_package_here"
        ] == [("not_a_package_here", False)], label
        records = evaluations[label, C + "py_executable_in_package.launch.py"]
        commands = sorted(json.loads(n)["cmd"][0].rsplit("/", 3)[-3:] for n in records["nodes"])
        assert commands == [
            ["echo"],
            ["lib", "launch_conformance", "tool"],
            ["lib", "not_a_package_here", "tool"],
            ["lib", "robot_state_publisher", "robot_state_publisher"],
        ], label
        assert records["errors"] == [], label


# --- the execute level: what executing each action performs, before it would start a process ---


def _executions(evaluations, label: str, file: str) -> list[dict]:
    return [json.loads(e) for e in evaluations[label, file]["executions"]]


@pytest.mark.parametrize("distro,file", _params())
def test_executing_each_action_performs_what_the_real_library_performs(evaluations, distro, file):
    """The real library's execution of every action that would start a process (launch's
    ExecuteLocal.prepare and output, launch_ros's Node._perform_substitutions: the command with
    launch-prefix, the name, cwd, environment, respawn; or the failure that stops the launch)
    equals the built-in engine's. Every node or process the visit reached was executed."""
    real, builtin = evaluations[distro, file], evaluations[f"builtin-{distro}", file]
    assert real["executions"] == builtin["executions"], json.dumps(
        {
            "ros": _differing(real["executions"], builtin["executions"]),
            "built-in": _differing(builtin["executions"], real["executions"]),
        },
        indent=1,
    )
    executed = {(e["file"], e["line"]) for e in _executions(evaluations, distro, file)}
    started = {(n["file"], n["line"]) for n in map(json.loads, real["nodes"])}
    assert started <= executed, sorted(started - executed)


@pytest.mark.parametrize("distro", DISTROS)
def test_the_execute_level_covers_failures_and_values(evaluations, distro):
    """The execute level is no empty comparison: the suite has executions that succeed with
    performed values (a launch-prefix, a cwd, an environment) and executions that fail on a launch
    configuration not set, each named the same by both engines."""
    runs = [e for f in FILES for e in _executions(evaluations, distro, f)]
    assert len(runs) >= 100, len(runs)
    failures = {e["failure"] for e in runs if e["failure"]}
    assert "SubstitutionFailure: launch configuration 'use_sim_time' does not exist" in failures
    process = _executions(evaluations, distro, "config_bot/launch/process.launch.py")
    assert sorted(e["failure"] for e in process) == sorted(
        f"SubstitutionFailure: launch configuration '{name}' does not exist"
        for name in ("bag_folder", "domain", "output", "respawn")
    )
    for label in (distro, f"builtin-{distro}"):
        recorder, node = sorted(
            _executions(evaluations, label, "config_bot/launch/process_values.launch.py"),
            key=lambda e: e["line"],
        )
        assert (recorder["cmd"], recorder["name"], recorder["cwd"]) == (
            ["nice", "-n", "5", "ros2", "bag", "record", "-a"],
            "recorder",
            "/tmp",
        ), label
        assert (recorder["additional_env"], recorder["output"], recorder["respawn"]) == (
            [["ROS_DOMAIN_ID", "7"]],
            "screen",
            True,
        ), label
        assert node["cmd"][:2] == ["xterm", "-e"] and node["cmd"][2].endswith("/robot_state_publisher"), label
        assert node["cmd"][3:] == [
            "--verbose",
            "--ros-args",
            "--log-level",
            "debug",
            "--ros-args",
            "-r",
            "__node:=publisher",
        ], label
        assert (node["name"], node["output"], node["failure"]) == ("rsp", "log", None), label
