"""What running setup.py costs (issue 34): cold `pkgforge verify` on ament_python packages whose
setup.py computes data_files (a helper with a loop over os.walk: run in the sandbox, as colcon
reads it), against the same packages with pkgforge new's literal setup.py (read from its text).

    .venv/bin/python bench/setup_py_cost.py [--packages 20] [--rounds 5]

Both workspaces have the same files but setup.py; rounds interleave them. The difference of the
medians, over the packages, is the CPU (every process, the workers' too) and wall time that
evaluating one setup.py adds; the first setup.py a worker runs also imports setuptools once into
its coordinator. Asserts nothing; prints a table.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scale import SCRIPTS, compiled, run  # noqa: E402  (the same timing as the scale bench)

from pkgforge.scaffold.package import create_package, make_spec  # noqa: E402

COMPUTED = """import os

from setuptools import setup

package_name = 'NAME'


def share_files(folders):
    out = []
    for folder in folders:
        for root, _, files in os.walk(folder):
            if files:
                out.append((os.path.join('share', package_name, root), [os.path.join(root, f) for f in files]))
    return out


setup(
    name=package_name,
    version='0.0.0',
    packages=[],
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ] + share_files(['launch', 'meshes', 'rviz', 'urdf']),
)
"""


def workspace(root: Path, count: int, computed: bool) -> Path:
    src = root / "src"
    src.mkdir(parents=True)
    for i in range(count):
        name = f"bench_{i:03d}_description"
        spec = make_spec(
            name, maintainer_name="Bench", maintainer_email="bench@example.com", build_type="ament_python"
        )
        create_package(spec, src)
        if computed:
            (src / name / "setup.py").write_text(COMPUTED.replace("NAME", name))
    return root


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packages", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=5)
    options = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        literal = workspace(Path(folder) / "literal", options.packages, computed=False)
        computed = workspace(Path(folder) / "computed", options.packages, computed=True)
        compiled([None])
        command = [str(SCRIPTS / "pkgforge"), "verify", "--no-cache"]
        times: dict[str, list[tuple[float, float]]] = {"literal": [], "computed": []}
        for _ in range(options.rounds):
            for name, root in (("literal", literal), ("computed", computed)):
                wall, _, cpu = run(command, root)
                times[name].append((wall, cpu))
    print(f"{options.packages} ament_python packages, {options.rounds} rounds (medians)")
    medians = {}
    for name, values in times.items():
        wall = statistics.median(w for w, _ in values)
        cpu = statistics.median(c for _, c in values)
        medians[name] = (wall, cpu)
        print(f"  {name:9} setup.py: wall {wall:6.2f} s   CPU {cpu:6.2f} s")
    wall = (medians["computed"][0] - medians["literal"][0]) / options.packages * 1000
    cpu = (medians["computed"][1] - medians["literal"][1]) / options.packages * 1000
    print(f"  per setup.py evaluated: {cpu:.0f} CPU ms, {wall:.0f} wall ms")


if __name__ == "__main__":
    main()
