"""How `pkgforge verify` scales: 50, 200 and 800 packages, each figure a ratio to `colcon list`.

    .venv/bin/python bench/scale.py [--sizes 50,200,800] [--rounds 5] [--no-install-base]
                                    [--install-base-sizes 50,200] [--engine builtin|ros] [--keep DIR]
                                    [--baseline-src OTHER_CHECKOUT/src]

For each workspace size (packages made by pkgforge's own scaffold: py/xml/yaml launch
files in turn, one in ten ament_python, as bench/verify_workspace.py makes them) it
times, as subprocesses interleaved round by round with `colcon list` on the same
workspace:

- cold verify: the default mode with `--no-cache`;
- re-run: the default mode on an unchanged workspace (answered by the cache);
- one package: a package inside the workspace, cold (what the pre-commit hook does);
- --install-base: against a real `colcon build` of the workspace (built once, untimed).

Each row gives the median seconds, the median of the per-round ratios to `colcon list`,
the median CPU seconds (user + system, the command and every process it waited for: steadier
than wall time on a shared machine), and the peak resident memory of the largest single
process of that command (wait4's ru_maxrss), with the load average when the size ended.
With --baseline-src DIR, every verify row runs a second time per round with DIR (another
checkout's src/) first on PYTHONPATH, interleaved: a before/after table from one run.
Asserts nothing; prints a table.
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

sys.path.insert(0, str(Path(__file__).resolve().parent))
from verify_workspace import ENV, generate  # noqa: E402  (one generator for every bench)

SCRIPTS = Path(sysconfig.get_path("scripts"))


def run(cmd: list[str], cwd: Path, ok=(0, 1), env: dict | None = None) -> tuple[float, int, float]:
    """(wall seconds, peak RSS in KiB of the largest process, CPU seconds) of one run."""
    start = time.perf_counter()
    process = subprocess.Popen(
        cmd,
        cwd=cwd,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        env=env or ENV,
    )
    _, status, usage = os.wait4(process.pid, 0)
    elapsed = time.perf_counter() - start
    code = os.waitstatus_to_exitcode(status)
    process.returncode = code
    if code not in ok:
        sys.exit(f"failed ({code}): {' '.join(cmd)}\n{process.stderr.read().decode()[-2000:]}")
    process.stderr.close()
    cpu = usage.ru_utime + usage.ru_stime  # with every process it waited for (the workers too)
    return elapsed, usage.ru_maxrss, cpu


def build(root: Path) -> None:
    env = dict(ENV, CMAKE_PREFIX_PATH=sys.prefix, PATH=f"{SCRIPTS}{os.pathsep}{ENV['PATH']}")
    for folder in ("build", "install", "log"):
        shutil.rmtree(root / folder, ignore_errors=True)
    subprocess.run(
        [str(SCRIPTS / "colcon"), "build", "--merge-install", "--cmake-args", "-DBUILD_TESTING=OFF"],
        cwd=root,
        env=env,
        capture_output=True,
        check=True,
    )


def measure(
    root: Path, count: int, rounds: int, install_base: bool, engine: list[str], baseline: Path | None = None
) -> list[tuple]:
    verify = [sys.executable, "-m", "pkgforge", "verify", "--format", "json", *engine]
    one = root / "src" / f"bench_{count // 2:03d}_description"
    commands = {
        "colcon list": [str(SCRIPTS / "colcon"), "list"],
        "cold verify": [*verify, "--no-cache"],
        "re-run (cache)": verify,
        "one package, cold": [*verify, "--no-cache", str(one)],
    }
    if install_base:
        build(root)
        commands["--install-base install"] = [*verify, "--install-base", "install"]
    envs = {name: ENV for name in commands}
    if baseline is not None:  # the same commands with the other checkout's pkgforge
        before = dict(ENV, PYTHONPATH=os.pathsep.join(filter(None, [str(baseline), ENV.get("PYTHONPATH")])))
        for name in [n for n in commands if n != "colcon list"]:
            commands[f"{name} (baseline)"], envs[f"{name} (baseline)"] = commands[name], before
    for name, cmd in commands.items():
        run(cmd, root, env=envs[name])  # warm the page cache, write byte code, fill pkgforge's cache
    times: dict[str, list[float]] = {name: [] for name in commands}
    cpu: dict[str, list[float]] = {name: [] for name in commands}
    memory: dict[str, int] = {name: 0 for name in commands}
    for _ in range(rounds):
        for name, cmd in commands.items():
            seconds, rss, used = run(cmd, root, env=envs[name])
            times[name].append(seconds)
            cpu[name].append(used)
            memory[name] = max(memory[name], rss)
    base = times["colcon list"]
    return [
        (
            name,
            statistics.median(values),
            statistics.median(v / b for v, b in zip(values, base, strict=False)),
            statistics.median(cpu[name]),
            memory[name] / 1024,
        )
        for name, values in times.items()
    ]


def compiled(folders: list[Path | None]) -> None:
    """Byte code for every module of pkgforge (and of the baseline), as pip writes it when it
    installs the wheel: in an editable checkout run with PYTHONDONTWRITEBYTECODE, the modules only
    launch workers import would otherwise be compiled again in every timed run."""
    for folder in folders:
        if folder is not None:
            subprocess.run(
                [sys.executable, "-m", "compileall", "-q", str(folder)],
                stdout=subprocess.DEVNULL,
                check=False,
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="50,200,800")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--no-install-base", action="store_true", help="skip the colcon build and that row")
    parser.add_argument(
        "--engine",
        choices=("builtin", "ros"),
        default=None,
        help="pass --launch-engine to verify (default: the tool's own choice)",
    )
    parser.add_argument("--keep", type=Path, default=None, help="generate into (and keep) DIR/<size>")
    parser.add_argument(
        "--install-base-sizes",
        default=None,
        help="sizes that get the --install-base row (default: every size; a colcon build each)",
    )
    parser.add_argument(
        "--baseline-src",
        type=Path,
        default=None,
        help="also time each verify row with this src/ folder first on PYTHONPATH",
    )
    args = parser.parse_args()
    compiled([Path(__import__("pkgforge").__file__).parent, args.baseline_src])
    engine = ["--launch-engine", args.engine] if args.engine else []
    built = (
        None if args.install_base_sizes is None else {int(s) for s in args.install_base_sizes.split(",") if s}
    )
    print(
        f"{'packages':>8}  {'command':<37}{'median s':>10}{'x colcon list':>15}{'CPU s':>8}{'peak MiB':>10}"
    )
    for count in (int(s) for s in args.sizes.split(",")):
        with tempfile.TemporaryDirectory() as tmp:
            root = generate((args.keep / str(count)) if args.keep else Path(tmp), count)
            install_base = not args.no_install_base and (built is None or count in built)
            for name, seconds, ratio, used, mib in measure(
                root, count, args.rounds, install_base, engine, args.baseline_src
            ):
                print(
                    f"{count:>8}  {name:<37}{seconds:>10.2f}{ratio:>15.2f}{used:>8.2f}{mib:>10.0f}",
                    flush=True,
                )
            print(f"{'':>8}  (load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)", flush=True)


if __name__ == "__main__":
    main()
