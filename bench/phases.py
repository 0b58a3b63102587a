"""Where one `pkgforge verify` spends its wall time, phase by phase (this process only).

    .venv/bin/python bench/phases.py WORKSPACE [verify options...]

Runs the verify command in this process with timers wrapped around the phases of
verify/pipeline.py (the model loading, the install tree, launch evaluation, robot models,
RViz configs, the checks) and prints each phase's wall seconds. Asserts nothing.
"""

from __future__ import annotations

import os
import sys
import time
from collections import defaultdict

TIMES: dict[str, float] = defaultdict(float)
CPU: dict[str, float] = defaultdict(float)
CALLS: dict[str, int] = defaultdict(int)


def cpu() -> float:
    """CPU seconds of this process and of the children it has waited for."""
    import resource

    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def timed(module, name: str, label: str) -> None:
    original = getattr(module, name)

    def wrapper(*args, **kwargs):
        start, used = time.perf_counter(), cpu()
        try:
            return original(*args, **kwargs)
        finally:
            TIMES[label] += time.perf_counter() - start
            CPU[label] += cpu() - used
            CALLS[label] += 1

    setattr(module, name, wrapper)


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    os.chdir(sys.argv[1])
    from pkgforge.launch import resolve
    from pkgforge.urdf import select as models
    from pkgforge.verify import pipeline as verify

    timed(verify, "cache_lookup", "cache lookup")
    timed(verify, "load_models", "discovery + models")
    timed(verify, "load_one_package", "discovery + models (one package)")
    timed(verify, "make_tree", "install tree")
    timed(verify, "run", "run (tree .. checks)")
    timed(resolve, "find_launch_files", "find launch files")
    timed(resolve, "resolve", "launch evaluation")
    timed(models, "collect", "collect models")
    timed(models, "process", "robot models (xacro)")
    timed(verify, "rviz_configs", "rviz configs")
    timed(verify, "run_checks", "checks")
    from pkgforge.cli import main as cli

    start = time.perf_counter()
    try:
        cli(["verify", "--format", "json", *sys.argv[2:]], standalone_mode=False)
    except SystemExit:
        pass
    total = time.perf_counter() - start
    print(f"{'phase':<34}{'wall s':>8}{'CPU s':>8}", file=sys.stderr)
    for label, seconds in TIMES.items():
        print(f"{label:<34}{seconds:>8.2f}{CPU[label]:>8.2f}  ({CALLS[label]} calls)", file=sys.stderr)
    print(
        f"{'total (after start-up)':<34}{total:>8.2f}{cpu():>8.2f}  load average {os.getloadavg()[0]:.1f}",
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
