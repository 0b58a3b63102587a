"""The JSON reports of `pkgforge verify` on the test fixtures and a few scaffolds, for comparing two builds.

    python bench/report_parity.py PKGFORGE OUT_DIR [--ros-prefix DIR]

A refactoring that must not change behaviour (issue 33's launch layout) is checked by running
this with main's pkgforge and with the branch's, then `diff -r` of the two OUT_DIRs. Each
workspace is copied to the same place (/tmp/pkgforge-parity/<name>) for both runs, so the
reports' absolute paths agree; only timing fields are blanked. With --ros-prefix (a ROS 2
distro, e.g. one tests/ros_prefix.py builds: `--ros-prefix`) every workspace is verified with the ros engine too.
Asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

FIXTURES = Path(__file__).resolve().parent.parent / "tests" / "fixtures"
# fixture folders that hold packages (the others hold loose files the tests copy into packages)
WORKSPACES = (
    "launch_configurations",
    "launch_patterns",
    "physics",
    "realworld",
    "seed000",
    "seed001",
    "launch_conformance",
)
SCAFFOLDS = (
    ("py_cmake", ["--launch-format", "py"]),
    ("xml_python", ["--launch-format", "xml", "--build-type", "ament_python"]),
    ("yaml_humble", ["--launch-format", "yaml", "--distro", "humble"]),
)
PLACE = Path("/tmp/pkgforge-parity")
TIMING_KEYS = {"elapsed", "seconds", "duration", "time", "timings", "wall"}


def _blank_timing(value: object) -> object:
    """The report with every timing field's value replaced (they differ from run to run)."""
    if isinstance(value, dict):
        return {k: ("<time>" if k in TIMING_KEYS else _blank_timing(v)) for k, v in value.items()}
    if isinstance(value, list):
        return [_blank_timing(v) for v in value]
    return value


def _workspace(name: str, pkgforge: str) -> Path:
    root = PLACE / name
    shutil.rmtree(root, ignore_errors=True)
    if name.startswith("new_"):
        kind = dict(SCAFFOLDS)[name[4:]]
        (root / "src").mkdir(parents=True)
        subprocess.run(
            [pkgforge, "new", f"{name[4:]}_description", *kind, "--destination", str(root / "src")],
            check=True,
            capture_output=True,
            env={**os.environ, "GIT_CONFIG_GLOBAL": "/dev/null"},
        )
    else:
        shutil.copytree(FIXTURES / name, root / "src" / name)
    return root


def _verify(pkgforge: str, root: Path, engine: list[str]) -> str:
    run = subprocess.run(
        [pkgforge, "verify", "--no-cache", "--format", "json", *engine, "-j", "1", str(root)],
        capture_output=True,
        text=True,
    )
    try:
        report = json.loads(run.stdout)
    except json.JSONDecodeError:
        return f"exit {run.returncode}\n{run.stdout}\n{run.stderr}"
    return f"exit {run.returncode}\n" + json.dumps(_blank_timing(report), indent=1, sort_keys=True) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("pkgforge")
    parser.add_argument("out", type=Path)
    parser.add_argument("--ros-prefix")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    engines = [("builtin", ["--launch-engine", "builtin"])]
    if args.ros_prefix:
        engines.append(("ros", ["--launch-engine", "ros", "--ros-prefix", args.ros_prefix]))
    for name in [*WORKSPACES, *(f"new_{s}" for s, _ in SCAFFOLDS)]:
        root = _workspace(name, args.pkgforge)
        for engine, options in engines:
            (args.out / f"{name}.{engine}.json").write_text(_verify(args.pkgforge, root, options))
        print(name, file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
