"""Wall time of `pkgforge --help`, `pkgforge new`, and `pkgforge build` on 1 and N packages.

    .venv/bin/python bench/foundation.py [--packages 20] [--repeat 5]

Prints a table; asserts nothing. Each build runs in a fresh workspace, so it
measures a first (cold) colcon build, which is what CI pays.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PKGFORGE = [sys.executable, "-m", "pkgforge"]
MAINTAINER = ["--maintainer-name", "Bench", "--maintainer-email", "bench@example.com"]


# As on a user's machine, where pip byte-compiled what it installed.
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def timed(cmd: list[str], cwd: Path) -> float:
    start = time.perf_counter()
    result = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, stdin=subprocess.DEVNULL, env=ENV)
    elapsed = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{result.stdout}{result.stderr}")
    return elapsed


def workspace_with(count: int, root: Path) -> Path:
    (root / "src").mkdir(parents=True)
    for i in range(count):
        timed([*PKGFORGE, "new", f"bench_{i:03d}_description", *MAINTAINER], root)
    return root


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packages", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp)
        helps = [timed([*PKGFORGE, "--help"], tmp_path) for _ in range(args.repeat)]
        rows.append(("pkgforge --help", statistics.median(helps), args.repeat))

        news = []
        for i in range(args.repeat):
            news.append(timed([*PKGFORGE, "new", f"n{i}", *MAINTAINER], tmp_path))
        rows.append(("pkgforge new", statistics.median(news), args.repeat))

        for count in (1, args.packages):
            builds = []
            for i in range(max(1, args.repeat // 2)):
                ws = workspace_with(count, tmp_path / f"ws{count}_{i}")
                builds.append(timed([*PKGFORGE, "build"], ws))
            rows.append((f"pkgforge build, {count} package(s)", statistics.median(builds), len(builds)))

    print(f"{'what':<34}{'median s':>10}{'runs':>6}")
    for what, seconds, runs in rows:
        print(f"{what:<34}{seconds:>10.2f}{runs:>6}")


if __name__ == "__main__":
    main()
