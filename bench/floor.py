"""The physical floor of a cold `pkgforge verify`, and how far the real command is from it.

    .venv/bin/python bench/floor.py [--packages 200] [--rounds 5] [--engine builtin|ros]
                                    [--upstream-distro jazzy] [--workspace DIR]

The floor is the work no design of verify can skip, done here in one process and one thread
with nothing around it: read every file of every package (bytes), run xacro on every robot
model once, and evaluate every launch file once with the launch engine verify uses (the
built-in stand-in, or the real launch libraries of ../shared/upstream with --engine ros).
What verify adds to that is its design: the install tree it predicts, the sandbox (a fresh
confined process per file), the checks, the report, the interpreter's start-up and imports
(timed here apart, as "imports").

Each round times, interleaved: the floor (in this process, after an untimed warm-up round),
`colcon list` and the cold verify (`--no-cache`, subprocesses). Printed: the medians, the
floor divided by the cores verify may use, and the cold verify's ratio to that figure, the
ratio the speed issue bounds (≤ 2). The packages' lookups are answered by a prefix of
symlinks to their sources, laid out untimed before the rounds (an install tree as colcon's
symlink install makes it). Asserts nothing.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from verify_workspace import ENV, generate  # noqa: E402  (one generator for every bench)

SCRIPTS = Path(sysconfig.get_path("scripts"))
LAUNCH_SUFFIXES = (".launch.py", ".launch.xml", ".launch.yaml")
MODEL_SUFFIXES = (".xacro", ".urdf")


def packages(root: Path) -> list[Path]:
    return sorted(p.parent for p in (root / "src").glob("*/package.xml"))


def symlink_prefix(root: Path, prefix: Path, real: Path | None = None) -> None:
    """share/<package> → its source folder, an empty share/<dependency> for every package they
    depend on (verify's predicted tree stands those in too), and the ament index entries."""
    import re

    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True, exist_ok=True)
    dependencies: set[str] = set()
    for package in packages(root):
        (index / package.name).touch()
        link = prefix / "share" / package.name
        if not link.exists():
            link.symlink_to(package)
        manifest = (package / "package.xml").read_text()
        dependencies.update(re.findall(r"<(?:\w+_)?depend>([^<]+)</", manifest))
    for name in dependencies - {p.name for p in packages(root)}:
        if real is not None and (real / "share" / name).is_dir():
            continue  # the distro's own (launch's grammar file lives in its share)
        (index / name).touch()
        (prefix / "share" / name).mkdir(exist_ok=True)


def files_of(root: Path) -> list[Path]:
    return sorted(p for p in (root / "src").rglob("*") if p.is_file())


def floor_work(root: Path, evaluate_launch: Callable[[str], object]) -> dict[str, float]:
    """Seconds of each irreducible part of one cold run, in this process."""
    import xacro

    seconds: dict[str, float] = {}
    files = files_of(root)
    start = time.perf_counter()
    for path in files:
        path.read_bytes()
    seconds["read every file"] = time.perf_counter() - start
    start = time.perf_counter()
    for path in files:
        if path.name.endswith(MODEL_SUFFIXES) and path.parent.name == "urdf":
            xacro.process_file(str(path), mappings={}).toxml()
    seconds["xacro on every model"] = time.perf_counter() - start
    start = time.perf_counter()
    for path in files:
        if path.name.endswith(LAUNCH_SUFFIXES):
            evaluate_launch(str(path))
    seconds["evaluate every launch file"] = time.perf_counter() - start
    return seconds


def launch_engine(engine: str, ros_prefix: Path | None, distro: str) -> Callable[[str], object]:
    """The evaluation a worker's request process runs, prepared as the worker prepares it."""
    os.environ["PKGFORGE_LAUNCH_ENGINE"] = engine
    os.environ["PKGFORGE_ROS_DISTRO"] = distro
    if ros_prefix is not None:
        os.environ["PKGFORGE_ROS_PREFIX"] = str(ros_prefix)
    from pkgforge.evaluation.requests import prepare

    prepare()
    if engine == "ros":
        from pkgforge.launch import ros_engine

        return lambda path: ros_engine.evaluate(path, {}, distro, None)
    from pkgforge.launch.evaluate import evaluate

    return lambda path: evaluate(path, {}, None)


def imports_seconds(engine: str) -> float:
    """A fresh interpreter importing what verify's processes import, less a bare interpreter."""
    modules = "import pkgforge.verify.pipeline, pkgforge.launch.evaluate, xacro, lxml.etree; from pkgforge.cli import main"

    def once(code: str) -> float:
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True, env=ENV)
        return time.perf_counter() - start

    return statistics.median(once(modules) - once("pass") for _ in range(3))


def timed_subprocess(cmd: list[str], cwd: Path, env: dict[str, str]) -> float:
    start = time.perf_counter()
    done = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    if done.returncode not in (0, 1):
        sys.exit(f"failed ({done.returncode}): {' '.join(cmd)}\n{done.stderr.decode()[-2000:]}")
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packages", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--engine", choices=("builtin", "ros"), default="builtin")
    parser.add_argument("--upstream-distro", default="jazzy", help="the real launch libraries (--engine ros)")
    parser.add_argument("--workspace", type=Path, default=None, help="an existing workspace (else generated)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = args.workspace.resolve() if args.workspace else generate(Path(tmp) / "ws", args.packages)
        prefix = Path(tmp) / "prefix"
        env = dict(ENV)
        verify = [sys.executable, "-m", "pkgforge", "verify", "--format", "json", "--no-cache"]
        ros_prefix = None
        if args.engine == "ros":
            sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
            from ros_prefix import make_prefix

            ros_prefix, reason = make_prefix(args.upstream_distro, Path(tmp) / "ros")
            if ros_prefix is None:
                sys.exit(f"no upstream launch libraries: {reason}")
            verify += ["--launch-engine", "ros", "--ros-prefix", str(ros_prefix)]
        symlink_prefix(root, prefix, ros_prefix)
        os.environ["AMENT_PREFIX_PATH"] = os.pathsep.join(str(p) for p in (prefix, ros_prefix) if p)
        evaluate_launch = launch_engine(args.engine, ros_prefix, args.upstream_distro)
        floor_work(root, evaluate_launch)  # warm: the page cache, the engine's first-use imports
        timed_subprocess(verify, root, env)
        parts: dict[str, list[float]] = {}
        floors, lists, colds = [], [], []
        for _ in range(args.rounds):
            seconds = floor_work(root, evaluate_launch)
            for name, value in seconds.items():
                parts.setdefault(name, []).append(value)
            floors.append(sum(seconds.values()))
            lists.append(timed_subprocess([str(SCRIPTS / "colcon"), "list"], root, ENV))
            colds.append(timed_subprocess(verify, root, env))
        imports = imports_seconds(args.engine)
    cores = os.cpu_count() or 1
    floor = statistics.median(floors)
    cold = statistics.median(colds)
    print(f"{args.packages} packages, engine {args.engine}, {args.rounds} interleaved rounds, {cores} cores")
    for name, values in parts.items():
        print(f"  floor: {name:<26}{statistics.median(values):>8.3f} s")
    print(f"  floor, single-threaded           {floor:>8.3f} s")
    print(f"  imports (not in the floor)       {imports:>8.3f} s")
    print(f"  colcon list                      {statistics.median(lists):>8.3f} s")
    print(f"  cold verify                      {cold:>8.3f} s")
    print(f"  floor / cores                    {floor / cores:>8.3f} s")
    print(f"  cold verify / (floor / cores)    {cold / (floor / cores):>8.2f}")
    print(
        f"  cold verify / colcon list        {statistics.median(c / b for c, b in zip(colds, lists, strict=True)):>8.2f}"
    )
    print(f"  (load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
