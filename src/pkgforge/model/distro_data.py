"""Which packages are released into which active ROS 2 distribution.

The data ships in the wheel as data/distros.txt (about 60 KB), written by
scripts/update-distro-data from ros/rosdistro (REP 143). Its format:

    # comment lines
    @distro humble lts ubuntu:jammy,rhel:8      one line per distro, in bit order
    =1f ament_cmake launch rviz2 ...            a hex mask of those distros, then the names
                                                released into exactly those

Reading it is lazy (the first question asks; nothing at import) and costs a
few milliseconds: bench/distro_data.py measures it.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from pkgforge.model.ros1_names import PACKAGES as REPLACEMENTS

DATA_FILE = Path(__file__).parent / "data" / "distros.txt"
# rosdep's keys (system packages: eigen, python3-numpy, ...), written by scripts/update-distro-data
# from ros/rosdistro's rosdep/*.yaml: a name neither released nor a key fails `rosdep install`
ROSDEP_FILE = Path(__file__).parent / "data" / "rosdep_keys.txt"


@dataclass(frozen=True)
class DistroInfo:
    name: str
    status: str  # lts | non-lts | rolling
    platforms: str  # ubuntu:noble,debian:bookworm,...


class DistroData:
    def __init__(self, distros: list[DistroInfo], masks: dict[str, int]):
        self.distros = distros
        self.names = [d.name for d in distros]
        self.masks = masks

    def released_in(self, package: str) -> list[str]:
        mask = self.masks.get(package, 0)
        return [name for bit, name in enumerate(self.names) if mask >> bit & 1]

    def released(self, package: str, distro: str | None = None) -> bool:
        mask = self.masks.get(package, 0)
        if distro is None:
            return mask != 0
        return distro in self.names and bool(mask >> self.names.index(distro) & 1)

    def packages(self, distro: str | None = None) -> list[str]:
        if distro is None:
            return list(self.masks)
        bit = 1 << self.names.index(distro)
        return [name for name, mask in self.masks.items() if mask & bit]

    def close_names(
        self, name: str, distro: str | None = None, n: int = 3, cutoff: float = 0.8, same_start: bool = False
    ) -> list[str]:
        """Released names close to `name` (difflib); `same_start`: only names with its first
        letter (fast enough to ask for every declared name; typos rarely hit the first letter)."""
        return list(_close_names(self, name, distro, n, cutoff, same_start))


@functools.lru_cache(maxsize=256)
def _close_names(
    data: DistroData, name: str, distro: str | None, n: int, cutoff: float, same_start: bool
) -> tuple[str, ...]:
    import difflib

    size = len(name)
    # a ratio is at most 2*min(len)/(len a + len b): names of other lengths cannot reach the cutoff
    candidates = [
        c
        for c in data.packages(distro)
        if 2 * min(size, len(c)) >= cutoff * (size + len(c)) and (not same_start or c[:1] == name[:1])
    ]
    return tuple(difflib.get_close_matches(name, candidates, n=n, cutoff=cutoff))


def parse(text: str) -> DistroData:
    distros: list[DistroInfo] = []
    masks: dict[str, int] = {}
    for line in text.splitlines():
        if not line or line[0] == "#":
            continue
        if line[0] == "@":
            _, name, status, platforms = (line.split() + ["", "", ""])[:4]
            distros.append(DistroInfo(name, status, platforms))
            continue
        if line[0] == "=":
            mask, *names = line[1:].split()
            masks.update(dict.fromkeys(names, int(mask, 16)))
    return DistroData(distros, masks)


@functools.lru_cache(maxsize=1)
def load() -> DistroData:
    return parse(DATA_FILE.read_text(encoding="utf-8"))


def active_distros() -> list[str]:
    return load().names


@functools.lru_cache(maxsize=1)
def rosdep_keys() -> frozenset[str]:
    """Every key of rosdep's default sources, for some platform (a key rosdep resolves on none of
    the target's platforms is not told apart)."""
    text = ROSDEP_FILE.read_text(encoding="utf-8")
    return frozenset(word for line in text.splitlines() if not line.startswith("#") for word in line.split())


def render_rosdep(keys: Iterable[str], source: str) -> str:
    """The rosdep key file's text: a header, then the keys sorted, a few to a line."""
    names = sorted(set(keys))
    lines = [
        "# rosdep's keys: the rules of rosdep's default sources for system packages (REP 111).",
        f"# Source: {source}. Written by scripts/update-distro-data; do not edit.",
    ]
    lines += [" ".join(names[start : start + 12]) for start in range(0, len(names), 12)]
    return "\n".join(lines) + "\n"


def replacement(name: str) -> tuple[str, str] | None:
    """(what to use instead, why) for a package name that has a known successor."""
    return REPLACEMENTS.get(name)


# --- writing the data (scripts/update-distro-data) -------------------------------------------


def render(distros: list[DistroInfo], released: dict[str, set[str]], source: str) -> str:
    """The data file's text: `released` maps distro → package names."""
    masks: dict[str, int] = {}
    for bit, distro in enumerate(distros):
        for name in released[distro.name]:
            masks[name] = masks.get(name, 0) | 1 << bit
    lines = [
        "# Packages released into each active ROS 2 distribution (REP 143 distribution.yaml).",
        f"# Source: {source}. Written by scripts/update-distro-data; do not edit.",
        "# @distro NAME STATUS PLATFORMS, in bit order; then =HEXMASK NAMES... (released in exactly those)",
    ]
    lines += [f"@distro {d.name} {d.status} {d.platforms or '-'}" for d in distros]
    groups: dict[int, list[str]] = {}
    for name in sorted(masks):
        groups.setdefault(masks[name], []).append(name)
    for mask in sorted(groups):
        names = groups[mask]
        for start in range(0, len(names), 200):  # lines of a readable length for diffs
            lines.append(f"={mask:x} " + " ".join(names[start : start + 200]))
    return "\n".join(lines) + "\n"


# --- the distros a package targets -----------------------------------------------------------

CI_FILES = (".gitlab-ci.yml", ".gitlab-ci.yaml")
CI_FOLDER = ".github/workflows"
CI_DISTRO_KEYS = {
    "ros_distro",
    "rosdistro",
    "ros-distro",
    "distro",
    "distros",
    "ros_distros",
    "required-ros-distributions",
    "ros-distribution",
    "ros_distribution",
}


def _ci_files(folder: Path) -> list[Path]:
    """The CI files of a folder: two stats and, only when it exists, a listing of .github/workflows."""
    found = [folder / name for name in CI_FILES if (folder / name).is_file()]
    workflows = folder / CI_FOLDER
    if workflows.is_dir():
        found += sorted(p for p in workflows.iterdir() if p.suffix in (".yml", ".yaml") and p.is_file())
    return found


@functools.lru_cache(maxsize=4096)
def ci_distros(folder: Path) -> tuple[str, ...]:
    """The active distros a package's CI files build for: docker images ros:<distro>..., and
    ROS_DISTRO / setup-ros / matrix keys. Read with the YAML loader, never guessed."""
    files = _ci_files(folder)
    if not files:
        return ()
    import yaml

    from pkgforge.model.distros import DISTROS
    from pkgforge.model.source import read_regular
    from pkgforge.model.yamlnodes import load_all

    names = set(DISTROS)  # the same names as the data's (a test keeps them equal), without reading it
    found: set[str] = set()

    def distro_words(text: str) -> set[str]:
        return {w for w in text.replace(",", " ").split() if w in names}

    def walk(document: object) -> None:  # parsed YAML: any JSON-like value
        todo: list[tuple[object, str | None]] = [(document, None)]
        while todo:  # (no recursion: a file nests as deep as the YAML reader lets it)
            node, key = todo.pop()
            if isinstance(node, dict):
                todo += [(v, str(k).lower()) for k, v in node.items()]
            elif isinstance(node, list):
                todo += [(v, key) for v in node]
            elif isinstance(node, str):
                if key in CI_DISTRO_KEYS:
                    found.update(distro_words(node))
                for word in node.split():
                    image = word.split("/")[-1]  # ros:jazzy, osrf/ros:jazzy-desktop
                    if image.startswith("ros:"):
                        distro = image[4:].split("-")[0]
                        if distro in names:
                            found.add(distro)

    for path in files:
        try:
            documents = load_all(read_regular(path).decode("utf-8"))
        except (OSError, UnicodeDecodeError, yaml.YAMLError):  # (past the YAML reader's bounds too)
            continue  # not ours to report; the CI system does
        for document in documents:
            if not _builds_another_branch(document):
                walk(_without_branch_matrices(document))
    return tuple(d for d in DISTROS if d in found)


OTHER_BRANCH_KEYS = {"ref", "ref_for_scheduled_build"}


def _builds_another_branch(document: object) -> bool:
    """A GitHub workflow run only on a schedule (or by hand) that checks out a named ref: a build
    of another branch (ros-controls' and Universal_Robots' humble-binary-main.yml on main, with
    ref_for_scheduled_build: humble), not of the code it sits beside."""
    if not isinstance(document, dict):
        return False
    triggers = document.get("on", document.get(True))  # (YAML 1.1 reads the key `on` as true)
    names = set(triggers) if isinstance(triggers, (dict, list)) else {triggers}
    if not names or not names <= {"schedule", "workflow_dispatch"}:
        return False
    stack: list[object] = [document.get("jobs")]
    while stack:
        node = stack.pop()
        if isinstance(node, dict):
            if any(str(k).lower() in OTHER_BRANCH_KEYS and isinstance(v, str) and v for k, v in node.items()):
                return True
            stack.extend(node.values())
        elif isinstance(node, list):
            stack.extend(node)
    return False


BRANCH_MATRIX_KEYS = {"branch", "branches", "ref"}
MATRIX_VALUE = re.compile(r"\$\{\{\s*matrix\.([\w-]+)\s*\}\}")


def _without_branch_matrices(document: object) -> object:
    """The workflow without the matrices of jobs that build several branches: a matrix whose rows
    name two or more branches pairs each distro with a branch, and at most one of them is the
    checkout read here (which one pkgforge cannot tell). moveit2_tutorials' deploy.yml, the same
    file on main and on humble, builds the pages of {branch: main, rosdistro: rolling} and
    {branch: humble, rosdistro: humble}: neither branch targets both distros. A matrix naming no
    branch, or one only, still says what the code beside it is built for."""
    if not isinstance(document, dict) or not isinstance(document.get("jobs"), dict):
        return document
    jobs = dict(document["jobs"])
    triggered = _trigger_branches(document)
    for name, job in jobs.items():
        strategy = job.get("strategy") if isinstance(job, dict) else None
        if not isinstance(strategy, dict):
            continue
        matrix = strategy.get("matrix")
        if isinstance(matrix, dict) and len(_matrix_branches(job, matrix, triggered)) > 1:
            jobs[name] = {**job, "strategy": {k: v for k, v in strategy.items() if k != "matrix"}}
    return {**document, "jobs": jobs}


def _trigger_branches(document: dict[object, object]) -> set[str]:
    """The branches a workflow's push and pull_request triggers name (deploy.yml: main, humble)."""
    triggers = document.get("on", document.get(True))  # (YAML 1.1 reads the key `on` as true)
    names: set[str] = set()
    if isinstance(triggers, dict):
        for event in ("push", "pull_request", "pull_request_target"):
            given = triggers.get(event)
            branches = given.get("branches") if isinstance(given, dict) else None
            if isinstance(branches, list):
                names.update(str(b) for b in branches)
            elif isinstance(branches, str):
                names.add(branches)
    return names


def _matrix_branches(
    job: dict[object, object], matrix: dict[object, object], triggered: set[str]
) -> set[str]:
    """The branches of this repository a job's matrix rows name: the literal values of the key a
    checkout (or a reusable workflow's `ref`) of this repository reads, or of a `branch`,
    `branches` or `ref` key whose values are branches the workflow's own triggers name
    (moveit2_tutorials' deploy.yml: on push to main and humble, rows {branch: main},
    {branch: humble}). A key only another repository's checkout reads (`repository:` given), or
    whose values the triggers do not name (a dependencies' .repos URL), names another
    repository's branch: the code here is built on each row's distro."""
    own: set[str] = set()
    other: set[str] = set()
    steps = job.get("steps")
    for step in [job] + (list(steps) if isinstance(steps, list) else []):  # a reusable workflow's `with` too
        given = step.get("with") if isinstance(step, dict) else None
        if not isinstance(given, dict):
            continue
        for key in OTHER_BRANCH_KEYS:
            value = given.get(key)
            if isinstance(value, str):
                (other if "repository" in given else own).update(
                    k.lower() for k in MATRIX_VALUE.findall(value)
                )
    include = matrix.get("include")
    rows = [matrix] + ([r for r in include if isinstance(r, dict)] if isinstance(include, list) else [])
    branches: set[str] = set()
    for row in rows:
        for name, value in row.items():
            key = str(name).lower()
            if key not in own and (key not in BRANCH_MATRIX_KEYS or key in other):
                continue
            for v in value if isinstance(value, list) else [value]:
                if isinstance(v, (str, int, float)) and "${{" not in str(v):
                    if key in own or str(v) in triggered:
                        branches.add(str(v))
    return branches


def target_distros(
    package_path: Path, root: Path, option: str | None, configured: str | Iterable[str] | None
) -> tuple[tuple[str, ...], str]:
    """(distros, where that came from); ((), 'every active distro') when nothing says.

    In order: --distro, ROS_DISTRO, pkgforge.toml [verify] distro, the package's CI files
    (the package folder, then its parents up to the workspace root)."""
    import os

    from pkgforge.model.distros import DISTROS

    names = list(DISTROS)
    if option:
        return (option,), "--distro"
    environment = os.environ.get("ROS_DISTRO", "")
    if environment in names:
        return (environment,), "ROS_DISTRO"
    if configured:
        chosen = (configured,) if isinstance(configured, str) else tuple(configured)
        return tuple(d for d in names if d in chosen), "pkgforge.toml"
    folder = package_path
    while True:
        found = ci_distros(folder)
        if found:
            return found, "CI file"
        if folder == root or root not in folder.parents:
            break
        folder = folder.parent
    return (), "every active distro"


@functools.lru_cache(maxsize=8)
def released_set(distros: tuple[str, ...] = ()) -> frozenset[str]:
    """The packages released for every one of `distros`, or for any active distro when empty."""
    data = load()
    if not distros:
        return frozenset(data.masks)
    bits = 0
    for distro in distros:
        bits |= 1 << data.names.index(distro)
    return frozenset(name for name, mask in data.masks.items() if mask & bits == bits)
