"""What the shipped distro data costs a verify: reading it, and the sets the checks ask for.

    .venv/bin/python bench/distro_data.py [--repeat 30]

Each round is a fresh interpreter (as a verify is): the data is read lazily, once per
process, and a fully cached verify never reads it. Prints the median and the worst of
the rounds, in milliseconds. Run it with bytecode caching on (unset
PYTHONDONTWRITEBYTECODE), as an installed pkgforge runs: otherwise the import
includes compiling the module. Asserts nothing.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys

ROUND = """
import time
import dataclasses, functools, pathlib, re  # already imported by every verify
import pkgforge
t0 = time.perf_counter()
from pkgforge.model import distro_data
t1 = time.perf_counter()
data = distro_data.load()
t2 = time.perf_counter()
distro_data.released_set(())
distro_data.released_set(('jazzy',))
t3 = time.perf_counter()
print((t1 - t0) * 1000, (t2 - t1) * 1000, (t3 - t2) * 1000)
"""


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=30)
    args = parser.parse_args()
    rows = []
    for _ in range(args.repeat):
        out = subprocess.run([sys.executable, "-c", ROUND], capture_output=True, text=True, check=True).stdout
        rows.append([float(x) for x in out.split()])
    for index, what in enumerate(
        ("import pkgforge.model.distro_data", "load() (read + parse)", "released_set((), ('jazzy',))")
    ):
        values = [row[index] for row in rows]
        print(f"{what:32s} median {statistics.median(values):6.2f} ms   max {max(values):6.2f} ms")
    totals = [sum(row) for row in rows]
    print(
        f"{'total':32s} median {statistics.median(totals):6.2f} ms   max {max(totals):6.2f} ms"
        f"   ({args.repeat} fresh interpreters)"
    )


if __name__ == "__main__":
    main()
