"""The cost of the physical checks (PF6xx) inside a cold verify of N scaffold packages.

    .venv/bin/python bench/physics_cost.py [--packages 200]

Runs one verify in-process (no cache) with every PF6 check function wrapped in a timer and
prints the checks' own CPU seconds beside the whole verify's wall seconds. One run: the
checks' time is measured inside the run, not as a difference of two noisy runs.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from verify_workspace import generate  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packages", type=int, default=200)
    arguments = parser.parse_args()
    from pkgforge.checks.registry import all_checks
    from pkgforge.verify.options import VerifyOptions
    from pkgforge.verify.pipeline import verify

    spent = {"seconds": 0.0, "calls": 0}
    for check in all_checks():
        if check.area == "physics":
            original = check.function

            def timed(ctx, original=original):
                start = time.process_time()
                found = list(original(ctx))
                spent["seconds"] += time.process_time() - start
                spent["calls"] += 1
                return found

            object.__setattr__(check, "function", timed)
    with tempfile.TemporaryDirectory(prefix="pkgforge-physics-bench-") as folder:
        root = Path(folder)
        generate(root, arguments.packages)
        start = time.perf_counter()
        result = verify(root, VerifyOptions(use_cache=False))
        wall = time.perf_counter() - start
    print(
        f"{arguments.packages} packages: verify {wall:.2f} s wall; physical checks "
        f"{spent['seconds'] * 1000:.1f} ms CPU in {spent['calls']} calls "
        f"({100 * spent['seconds'] / wall:.2f} % of the run); diagnostics by code: "
        f"{dict(Counter(d.code for d in result.diagnostics))}"
    )


if __name__ == "__main__":
    main()
