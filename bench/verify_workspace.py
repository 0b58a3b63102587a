"""`pkgforge verify` against `colcon list` (and `colcon build`) on one generated workspace.

    .venv/bin/python bench/verify_workspace.py [--packages 200] [--repeat 9] [--keep DIR] [--with-build]
                                               [--ros-prefix DIR | --upstream-distro jazzy]

The packages are made with pkgforge's own scaffold (the code behind `pkgforge new`).
Every command runs as a subprocess, as a user runs it, interleaved with the
others; the table gives each one's median wall time and its median ratio to
`colcon list` in the same round. With --ros-prefix (a ROS 2 distro) or --upstream-distro
(the real launch libraries from ../shared/upstream laid out as one, as the tests do), the
default verify runs with each launch engine too. With --with-build, `colcon build` and
`pkgforge verify --build` run once each (cold). Asserts nothing.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

from pkgforge.scaffold.package import create_package, make_spec

SCRIPTS = Path(sysconfig.get_path("scripts"))


def generate(root: Path, count: int) -> Path:
    src = root / "src"
    src.mkdir(parents=True, exist_ok=True)
    formats = ("py", "xml", "yaml")
    for i in range(count):
        name = f"bench_{i:03d}_description"
        if (src / name).exists():
            continue
        spec = make_spec(
            name,
            maintainer_name="Bench",
            maintainer_email="bench@example.com",
            launch_format=formats[i % 3],
            build_type="ament_python" if i % 10 == 9 else "ament_cmake",
        )
        create_package(spec, src)
    return root


# As on a user's machine, where pip byte-compiled everything it installed: an
# editable checkout with PYTHONDONTWRITEBYTECODE would recompile pkgforge each run.
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def timed(cmd: list[str], cwd: Path, ok=(0,)) -> float:
    start = time.perf_counter()
    result = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, stdin=subprocess.DEVNULL, env=ENV)
    elapsed = time.perf_counter() - start
    if result.returncode not in ok:
        sys.exit(
            f"failed ({result.returncode}): {' '.join(cmd)}\n{result.stdout[-2000:]}{result.stderr[-2000:]}"
        )
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packages", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=9)
    parser.add_argument("--keep", type=Path, default=None, help="generate into (and keep) this folder")
    parser.add_argument("--with-build", action="store_true", help="also time colcon build and verify --build")
    parser.add_argument(
        "--ros-prefix", type=Path, default=None, help="time the real launch engine of this distro"
    )
    parser.add_argument(
        "--upstream-distro", default=None, help="time the real launch engine of ../shared/upstream"
    )
    args = parser.parse_args()

    verify = [sys.executable, "-m", "pkgforge", "verify", "--format", "json"]
    static = ["--select", "PF1,PF2,PF9"]  # manifest and install checks: no launch resolution
    commands = {
        "colcon list": [str(SCRIPTS / "colcon"), "list"],
        "verify, manifest+install checks": [*verify, *static, "--no-cache"],
        "  same, --jobs 1": [*verify, *static, "--jobs", "1", "--no-cache"],
        "verify (default), first run": [*verify, "--no-cache"],
        "verify (default), second run": verify,  # unchanged workspace: from the cache
    }
    with tempfile.TemporaryDirectory() as tmp:
        prefix = args.ros_prefix
        if args.upstream_distro:
            sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
            from ros_prefix import make_prefix

            prefix, reason = make_prefix(args.upstream_distro, Path(tmp) / "ros")
            if prefix is None:
                sys.exit(f"no upstream launch libraries: {reason}")
        if prefix is not None:
            commands["verify, built-in launch engine"] = [*verify, "--no-cache", "--launch-engine", "builtin"]
            commands["verify, real launch engine"] = [
                *verify,
                "--no-cache",
                "--launch-engine",
                "ros",
                "--ros-prefix",
                str(prefix),
            ]
        root = generate(args.keep or Path(tmp) / "ws", args.packages)
        for cmd in commands.values():
            timed(cmd, root)  # warm caches, write byte code
        # interleaved, so a slow spell of the machine hits every command alike
        times: dict[str, list[float]] = {name: [] for name in commands}
        for _ in range(args.repeat):
            for name, cmd in commands.items():
                times[name].append(timed(cmd, root))
        once = {}
        if args.with_build:
            env_build = dict(ENV, CMAKE_PREFIX_PATH=sys.prefix, PATH=f"{SCRIPTS}{os.pathsep}{ENV['PATH']}")
            for folder in ("build", "install", "log"):
                shutil.rmtree(root / folder, ignore_errors=True)
            start = time.perf_counter()
            subprocess.run(
                [str(SCRIPTS / "colcon"), "build", "--merge-install", "--cmake-args", "-DBUILD_TESTING=OFF"],
                cwd=root,
                env=env_build,
                capture_output=True,
                check=True,
            )
            once["colcon build (cold)"] = time.perf_counter() - start
            once["verify --build (cold)"] = timed([*verify, "--build"], root)
            once["verify --install-base install"] = timed([*verify, "--install-base", "install"], root)

    base = times["colcon list"]
    print(f"workspace: {args.packages} packages, {args.repeat} interleaved runs")
    print(f"{'command':<34}{'median s':>10}{'ratio to colcon list':>24}")
    for name, values in times.items():
        ratio = statistics.median(v / b for v, b in zip(values, base, strict=False))
        print(f"{name:<34}{statistics.median(values):>10.2f}{ratio:>24.2f}")
    for name, seconds in once.items():
        print(f"{name:<34}{seconds:>10.2f}{seconds / statistics.median(base):>24.2f}")


if __name__ == "__main__":
    main()
