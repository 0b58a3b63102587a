"""The JSON reports of `pkgforge verify` on the test fixtures, scaffolds and real packages, for comparing two builds.

    python bench/report_parity.py PKGFORGE OUT_DIR [--ros-prefix DIR]... [--extra DIR]... [--place DIR]

A refactoring that must not change behaviour (issue 33) is checked by running this with the
build before and the build after, then `diff -r` of the two OUT_DIRs. Each workspace is laid
out in the same place (PLACE/<name>, PLACE is --place) for both runs, so the reports' absolute
paths agree; only timing fields are blanked. Every --ros-prefix (a ROS 2 distro, e.g. one
tests/ros_prefix.py builds) adds a run of every workspace with the ros engine on it. Every
--extra DIR (a workspace with src/, or a folder of packages) adds a real-package workspace.

What a build does not have is skipped, not failed, so two builds of different ages compare on
what both have: `new --sim` scaffolds, `verify --simulate`, `verify --distro` variants, the
`rule` command. OUT_DIR/cli/ holds the help of every command, `checks --format markdown` and a
few `rule` pages; OUT_DIR/<scaffold>.files the sha256 of every file a scaffold wrote;
OUT_DIR/colcon_<name>.<engine>.json what `colcon verify` (the colcon beside PKGFORGE) says of a
few workspaces `pkgforge build` built. Asserts nothing.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import shutil
import struct
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

FIXTURES = Path(__file__).resolve().parent.parent / "tests" / "fixtures"
# fixture folders that hold packages, copied whole into a workspace's src/
WORKSPACES = (
    "launch_configurations",
    "launch_patterns",
    "physics",
    "realworld",
    "seed000",
    "seed001",
    "launch_conformance",
    "worlds",
)
SCAFFOLDS = (
    ("py_cmake", ["--launch-format", "py"]),
    ("xml_python", ["--launch-format", "xml", "--build-type", "ament_python"]),
    ("yaml_humble", ["--launch-format", "yaml", "--distro", "humble"]),
)
# `new --sim gz`, per distro (only with a build whose `new` has --sim)
SIM_SCAFFOLDS = (
    ("sim_gz_humble", ["--sim", "gz", "--distro", "humble"]),
    ("sim_gz_jazzy", ["--sim", "gz", "--distro", "jazzy"]),
)
# the physics fixture's cases (tests/test_physics.py); these three only `verify --simulate` finds
PHYSICS_CASES = sorted(p.stem for p in (FIXTURES / "physics" / "cases").glob("*.urdf"))
SIMULATED = ("simulation-refused", "simulation-unstable", "collision-overlap-at-zero")
DISTROS = ("humble", "jazzy")
# the workspaces also verified with --distro humble and --distro jazzy (they hold Gazebo and
# ros2_control files, whose checks answer per distro), as are new --sim's and the --extra ones
DISTRO_WORKSPACES = ("simulation", "worlds")
# the workspaces also built (`pkgforge build`) and checked with `colcon verify` on their install tree
COLCON_WORKSPACES = ("seed000", "seed001", "launch_patterns", "simulation", "new_xml_python")
RULES = ("PF101", "PF202", "PF305", "PF401", "PF612", "PF701", "PF999")
MAINTAINER = ["--maintainer-name", "Test Maintainer", "--maintainer-email", "test@example.com"]
PLACE = Path("/tmp/pkgforge-parity")
TIMING_KEYS = {"elapsed", "seconds", "duration", "time", "timings", "wall"}
# the same environment for both builds: no user git identity, one help width, and one catalogue
# URL (else `rule` names the docs/checks.md of the checkout each build is installed from)
ENVIRONMENT = {
    **os.environ,
    "GIT_CONFIG_GLOBAL": "/dev/null",
    "COLUMNS": "80",
    "PKGFORGE_DOCS_URL": "https://example.invalid/pkgforge/docs/checks.md",
}


def _blank_timing(value: object) -> object:
    """The report with every timing field's value replaced (they differ from run to run)."""
    if isinstance(value, dict):
        return {k: ("<time>" if k in TIMING_KEYS else _blank_timing(v)) for k, v in value.items()}
    if isinstance(value, list):
        return [_blank_timing(v) for v in value]
    return value


def _run(pkgforge: str, *words: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([pkgforge, *words], capture_output=True, text=True, env=ENVIRONMENT)


class Build:
    """One pkgforge build and what its command line offers."""

    def __init__(self, pkgforge: str) -> None:
        self.pkgforge = pkgforge
        self.help = _run(pkgforge, "--help").stdout
        self.commands = _commands(self.help)
        self.new_help = _run(pkgforge, "new", "--help").stdout
        self.verify_help = _run(pkgforge, "verify", "--help").stdout

    def new_has(self, option: str) -> bool:
        return re.search(rf"{re.escape(option)}\b", self.new_help) is not None

    def verify_has(self, option: str) -> bool:
        return re.search(rf"{re.escape(option)}\b", self.verify_help) is not None

    def new(self, destination: Path, name: str, *options: str) -> None:
        destination.mkdir(parents=True, exist_ok=True)
        run = _run(self.pkgforge, "new", name, *options, "--destination", str(destination))
        if run.returncode != 0:
            raise SystemExit(f"pkgforge new {name} {' '.join(options)} failed:\n{run.stderr}")


def _commands(help_text: str) -> list[str]:
    """The subcommands a click group's --help lists under Commands:."""
    section = help_text.split("\nCommands:\n", 1)[-1] if "\nCommands:\n" in help_text else ""
    return [m.group(1) for m in re.finditer(r"^  ([a-z][\w-]*)", section, re.MULTILINE)]


def _binary_stl(path: Path, triangles: int = 20_001) -> None:
    """tests/test_physics.py's heavy.stl: a small but finely tessellated mesh (PF609's case)."""
    step = 0.05 / triangles
    facets = b"".join(
        struct.pack(
            "<12fH", 0.0, 0.0, 1.0, i * step, 0.0, 0.0, (i + 1) * step, 0.0, 0.0, i * step, 0.05, 0.3, 0
        )
        for i in range(triangles)
    )
    path.write_bytes(b"\0" * 80 + struct.pack("<I", triangles) + facets)


def _template(build: Build, src: Path) -> Path:
    """A clean `pkgforge new rob_description` in src/, as the tests' template_package."""
    build.new(src, "rob_description", *MAINTAINER)
    return src / "rob_description"


def _simulation(build: Build, src: Path) -> None:
    """tests/test_simulation.py's simulation_package: the scaffold with the simulation fixture."""
    package = _template(build, src)
    fixture = FIXTURES / "simulation"
    (package / "config").mkdir(exist_ok=True)
    for name in ("controllers.yaml", "broken.yaml"):
        shutil.copy(fixture / name, package / "config" / name)
    shutil.copy(fixture / "sim.urdf.xacro", package / "urdf" / "sim.urdf.xacro")
    shutil.copy(fixture / "sim.launch.py", package / "launch" / "sim.launch.py")
    cmake = package / "CMakeLists.txt"
    text = cmake.read_text()
    old = "DIRECTORY launch meshes rviz urdf"
    if old not in text:
        raise SystemExit(f"{cmake}: no {old!r} to add config to (the scaffold changed)")
    cmake.write_text(text.replace(old, "DIRECTORY config launch meshes rviz urdf"))


def _ros1_leftovers(build: Build, src: Path) -> None:
    """tests/test_truth_rejects.py's two: ROS 1 xacro tags in urdf/, an RViz 1 config."""
    package = _template(build, src)
    fixture = FIXTURES / "ros1_leftovers"
    for name in ("ros1_macros.urdf.xacro", "ros1_if.urdf.xacro", "prefixed.urdf.xacro"):
        shutil.copy(fixture / name, package / "urdf" / name)
    shutil.copy(fixture / "display_rviz1.rviz", package / "rviz" / "display.rviz")


def _urdfdom(build: Build, src: Path) -> None:
    """tests/test_truth_rejects.py's urdfdom fixture: every model in urdf/."""
    package = _template(build, src)
    for model in (FIXTURES / "urdfdom").iterdir():
        shutil.copy(model, package / "urdf" / model.name)


def _physics_case(case: str | None) -> Callable[[Build, Path], None]:
    """tests/test_physics.py's physics_package: phys_description with heavy.stl and a case's robot.urdf."""

    def make(build: Build, src: Path) -> None:
        package = src / "phys_description"
        shutil.copytree(FIXTURES / "physics" / "phys_description", package)
        _binary_stl(package / "meshes" / "heavy.stl")
        if case is not None:
            shutil.copy(FIXTURES / "physics" / "cases" / f"{case}.urdf", package / "urdf" / "robot.urdf")

    return make


def _fixture(name: str) -> Callable[[Build, Path], None]:
    def make(build: Build, src: Path) -> None:
        shutil.copytree(FIXTURES / name, src / name)

    return make


def _scaffold(name: str, options: list[str]) -> Callable[[Build, Path], None]:
    def make(build: Build, src: Path) -> None:
        build.new(src, f"{name}_description", *options)

    return make


def _extra(folder: Path) -> Callable[[Build, Path], None]:
    """A real-package workspace: DIR/src's packages, or DIR itself as one folder of src/."""

    def make(build: Build, src: Path) -> None:
        if (folder / "src").is_dir():
            shutil.copytree(folder / "src", src, symlinks=True, dirs_exist_ok=True)
        else:
            shutil.copytree(folder, src / folder.name, symlinks=True)

    return make


Case = tuple[str, str, list[str]]  # (report name, workspace name, verify options)


def _plan(build: Build, extras: list[Path]) -> tuple[dict[str, Callable[[Build, Path], None]], list[Case]]:
    """The workspaces to lay out and the verify runs on them, as far as this build offers them."""
    makers: dict[str, Callable[[Build, Path], None]] = {name: _fixture(name) for name in WORKSPACES}
    makers |= {"simulation": _simulation, "ros1_leftovers": _ros1_leftovers, "urdfdom": _urdfdom}
    makers["physics_clean"] = _physics_case(None)
    makers |= {f"physics_{case}": _physics_case(case) for case in PHYSICS_CASES}
    scaffolds = [*SCAFFOLDS, *(SIM_SCAFFOLDS if build.new_has("--sim") else [])]
    makers |= {f"new_{name}": _scaffold(name, options) for name, options in scaffolds}
    makers |= {f"extra_{folder.name}": _extra(folder) for folder in extras}
    cases: list[Case] = [(name, name, []) for name in makers]
    if build.verify_has("--distro"):
        sims = [f"new_{n}" for n, _ in scaffolds if n.startswith("sim_")]
        for name in [*DISTRO_WORKSPACES, *sims, *(f"extra_{folder.name}" for folder in extras)]:
            cases += [(f"{name}.{d}", name, ["--distro", d]) for d in DISTROS]
    else:
        print("skipped: verify --distro (this build has none)", file=sys.stderr)
    if build.verify_has("--simulate"):
        simulated = ["physics_clean", *(f"physics_{c}" for c in SIMULATED)]
        cases += [(f"{name}.simulate", name, ["--simulate"]) for name in simulated]
    else:
        print("skipped: verify --simulate (this build has none)", file=sys.stderr)
    if not build.new_has("--sim"):
        print("skipped: new --sim gz (this build has none)", file=sys.stderr)
    return makers, cases


def _verify(pkgforge: str, root: Path, options: list[str]) -> str:
    run = _run(pkgforge, "verify", "--no-cache", "--format", "json", *options, "-j", "1", str(root))
    try:
        report = json.loads(run.stdout)
    except json.JSONDecodeError:
        return f"exit {run.returncode}\n{run.stdout}\n{run.stderr}"
    return f"exit {run.returncode}\n" + json.dumps(_blank_timing(report), indent=1, sort_keys=True) + "\n"


def _files(root: Path) -> str:
    """The sha256 and path of every file under root, sorted: what a scaffold wrote, byte for byte."""
    lines = [
        f"{hashlib.sha256(p.read_bytes()).hexdigest()}  {p.relative_to(root)}"
        for p in sorted(root.rglob("*"))
        if p.is_file()
    ]
    return "\n".join(lines) + "\n"


def _cli(build: Build, out: Path) -> None:
    """The help of every command, the checks catalogue and a few rule pages."""
    out.mkdir(parents=True, exist_ok=True)

    def record(name: str, *words: str) -> None:
        run = _run(build.pkgforge, *words)
        (out / name).write_text(f"exit {run.returncode}\n{run.stdout}\n--- stderr\n{run.stderr}")

    record("help.txt", "--help")
    for command in build.commands:
        record(f"{command}.help.txt", command, "--help")
    if "checks" in build.commands:
        record("checks.txt", "checks")
        record("checks.markdown.txt", "checks", "--format", "markdown")
    if "rule" in build.commands:
        for code in RULES:
            record(f"rule.{code}.txt", "rule", code)


def _colcon(
    build: Build, roots: dict[str, Path], place: Path, engines: list[tuple[str, list[str]]], out: Path
) -> None:
    """`colcon verify` (pkgforge's colcon verb) on a few workspaces `pkgforge build` built."""
    colcon = Path(build.pkgforge).with_name("colcon")
    usage = subprocess.run([str(colcon), "verify", "--help"], capture_output=True, text=True, env=ENVIRONMENT)
    if usage.returncode != 0:
        print(f"skipped: colcon verify ({colcon} has no verify verb)", file=sys.stderr)
        return
    (out / "cli").mkdir(exist_ok=True)
    (out / "cli" / "colcon-verify.help.txt").write_text(usage.stdout.replace(str(colcon), "colcon"))
    # older builds name the verb's format option --pkgforge-format (later a hidden alias of --format)
    fmt = "--pkgforge-format" if "--pkgforge-format" in usage.stdout else "--format"
    for name in roots:
        root = place / f"colcon_{name}"
        shutil.rmtree(root, ignore_errors=True)
        shutil.copytree(roots[name], root)
        built = _run(build.pkgforge, "build", str(root))
        for engine, options in engines:
            words = [str(colcon), "verify", fmt, "json", *options]
            run = subprocess.run(words, capture_output=True, text=True, env=ENVIRONMENT, cwd=root)
            try:
                text = json.dumps(_blank_timing(json.loads(run.stdout)), indent=1, sort_keys=True)
            except json.JSONDecodeError:
                text = f"{run.stdout}\n{run.stderr}"
            (out / f"colcon_{name}.{engine}.json").write_text(
                f"build exit {built.returncode}\nexit {run.returncode}\n{text}\n"
            )
        print(f"colcon_{name}", file=sys.stderr)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("pkgforge")
    parser.add_argument("out", type=Path)
    parser.add_argument(
        "--ros-prefix", action="append", default=[], help="repeatable: one ros engine run each"
    )
    parser.add_argument(
        "--extra", action="append", default=[], type=Path, help="repeatable: a real workspace"
    )
    parser.add_argument("--place", type=Path, default=PLACE, help="where the workspaces are laid out")
    parser.add_argument(
        "--only",
        action="append",
        default=[],
        help="repeatable: only the outputs whose name starts so (a bisection)",
    )
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    build = Build(args.pkgforge)
    engines = [("builtin", ["--launch-engine", "builtin"])]
    for prefix in args.ros_prefix:
        engines.append((f"ros_{Path(prefix).name}", ["--launch-engine", "ros", "--ros-prefix", prefix]))

    def wanted(name: str) -> bool:
        return not args.only or any(name.startswith(prefix) for prefix in args.only)

    if wanted("cli"):
        _cli(build, args.out / "cli")
    makers, cases = _plan(build, [p.resolve() for p in args.extra])
    roots: dict[str, Path] = {}

    def lay_out(name: str) -> Path:
        """PLACE/name with the workspace in it, laid out once per run."""
        if name not in roots:
            root = args.place / name
            shutil.rmtree(root, ignore_errors=True)
            (root / "src").mkdir(parents=True)
            makers[name](build, root / "src")
            roots[name] = root
            if name.startswith("new_"):
                (args.out / f"{name}.files").write_text(_files(root))
        return roots[name]

    for report, name, options in cases:
        if not wanted(report):
            continue
        root = lay_out(name)
        for engine, engine_options in engines:
            (args.out / f"{report}.{engine}.json").write_text(
                _verify(args.pkgforge, root, [*engine_options, *options])
            )
        print(report, file=sys.stderr)
    colcon = {name: lay_out(name) for name in COLCON_WORKSPACES if wanted(f"colcon_{name}")}
    if colcon:
        _colcon(build, colcon, args.place, engines, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
