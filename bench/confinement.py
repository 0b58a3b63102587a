"""What the sandbox costs: cold `pkgforge verify` with every protection, with the kernel's turned off,
and (optionally) another checkout's, interleaved with `colcon list` on one generated workspace.

    .venv/bin/python bench/confinement.py [--packages 200] [--rounds 5] [--baseline-src OTHER/src]

Rows (each the median of interleaved rounds; ratio = median of per-round ratios to `colcon list`):
- cold verify: this checkout as users get it (a fresh process per launch file and per model,
  Landlock, the read-only view and PID namespace where the kernel has them);
- ... kernel protections off: PKGFORGE_SANDBOX_DISABLE=landlock,namespaces (the fresh process
  per request and the guard only): the difference to the row above is what Landlock and the
  namespaces cost;
- ... baseline: `--baseline-src`'s pkgforge (e.g. a checkout of the commit before the sandbox:
  one long-lived worker per thread, the guard only): the difference is what the whole
  confinement costs.

A generated package has one launch file and one model, so a run makes 2 requests per package;
the last lines give the CPU milliseconds each protection adds per request (launch file or model).
Asserts nothing; prints a table.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scale import SCRIPTS, compiled, run  # noqa: E402  (the same timing as the scale bench)
from verify_workspace import ENV, generate  # noqa: E402

REQUESTS_PER_PACKAGE = 2  # one launch file and one model per generated package


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packages", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--baseline-src", type=Path, default=None)
    args = parser.parse_args()
    compiled([Path(__import__("pkgforge").__file__).parent, args.baseline_src])
    verify = [sys.executable, "-m", "pkgforge", "verify", "--format", "json", "--no-cache"]
    rows: dict[str, tuple[list[str], dict[str, str]]] = {
        "colcon list": ([str(SCRIPTS / "colcon"), "list"], ENV),
        "cold verify": (verify, ENV),
        "cold verify, kernel protections off": (
            verify,
            dict(ENV, PKGFORGE_SANDBOX_DISABLE="landlock,namespaces"),
        ),
    }
    if args.baseline_src is not None:
        path = os.pathsep.join(filter(None, [str(args.baseline_src), ENV.get("PYTHONPATH")]))
        rows["cold verify, baseline"] = (verify, dict(ENV, PYTHONPATH=path))
    with tempfile.TemporaryDirectory() as tmp:
        root = generate(Path(tmp), args.packages)
        for command, env in rows.values():
            run(command, root, env=env)  # warm caches and byte code
        wall: dict[str, list[float]] = {name: [] for name in rows}
        cpu: dict[str, list[float]] = {name: [] for name in rows}
        for _ in range(args.rounds):
            for name, (command, env) in rows.items():
                seconds, _, used = run(command, root, env=env)
                wall[name].append(seconds)
                cpu[name].append(used)
    base = wall["colcon list"]
    print(f"{args.packages} packages, {args.rounds} interleaved rounds, {os.cpu_count()} cores")
    print(f"{'command':<40}{'median s':>10}{'x colcon list':>15}{'CPU s':>8}")
    median_cpu = {}
    for name in rows:
        ratio = statistics.median(w / b for w, b in zip(wall[name], base, strict=True))
        median_cpu[name] = statistics.median(cpu[name])
        print(f"{name:<40}{statistics.median(wall[name]):>10.2f}{ratio:>15.2f}{median_cpu[name]:>8.2f}")
    requests = args.packages * REQUESTS_PER_PACKAGE
    kernel = (median_cpu["cold verify"] - median_cpu["cold verify, kernel protections off"]) / requests
    print(f"Landlock + namespaces: {kernel * 1000:+.2f} CPU ms per request ({requests} requests)")
    if "cold verify, baseline" in median_cpu:
        whole = (median_cpu["cold verify"] - median_cpu["cold verify, baseline"]) / requests
        print(f"whole confinement vs baseline: {whole * 1000:+.2f} CPU ms per request")
    print(f"(load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
