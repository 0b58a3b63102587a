"""`pkgforge verify`: discover → load one model per package → run checks → filter.

Packages are independent once discovered, so each is loaded and checked in a
worker process; only plain data (PackageReport) crosses back.
"""

from __future__ import annotations

import os
import re
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from multiprocessing import get_context
from pathlib import Path

from .checks.context import CheckContext
from .checks.registry import all_checks
from .config import Config, Selection, load_config
from .diagnostics import Diagnostic, Finding, PackageReport, Severity
from .errors import PkgforgeError
from .model.package import load_package
from .workspace import Workspace, discover, locate

IGNORE_MARKERS = ("COLCON_IGNORE", "AMENT_IGNORE", "CATKIN_IGNORE")
NAME_ELEMENT = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
# Below this many packages, starting worker processes costs more than it saves.
PARALLEL_THRESHOLD = 16


@dataclass(frozen=True)
class PackageTarget:
    path: Path
    name: str
    colcon_type: str | None
    parsed_by_colcon: bool


@dataclass
class VerifyOptions:
    selection: Selection = field(default_factory=Selection)
    jobs: int | None = None
    strict: bool = False


@dataclass
class VerifyResult:
    root: Path
    reports: list[PackageReport]
    checks_run: set[str]

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return [d for report in self.reports for d in report.diagnostics]

    def count(self, severity: Severity) -> int:
        return sum(1 for d in self.diagnostics if d.severity == severity)

    def exit_code(self, strict: bool) -> int:
        worst = max((d.severity for d in self.diagnostics), default=None)
        if worst == Severity.ERROR or (strict and worst == Severity.WARNING):
            return 1
        return 0


def package_folders(base: Path) -> list[Path]:
    """Folders with a package.xml under base, honouring the ignore markers as colcon does."""
    found = []
    for current, dirs, files in os.walk(base, followlinks=False):
        if any(marker in files for marker in IGNORE_MARKERS):
            dirs[:] = []
            continue
        if "package.xml" in files:
            found.append(Path(current).resolve())
            dirs[:] = []
            continue
        dirs[:] = [d for d in dirs if not d.startswith(".")]
    return found


def quick_name(folder: Path) -> str:
    """The package name for the workspace index, before colcon has identified anything."""
    try:
        match = NAME_ELEMENT.search((folder / "package.xml").read_text(errors="replace"))
    except OSError:
        match = None
    return match.group(1) if match else folder.name


def find_targets(workspace: Workspace) -> tuple[list[PackageTarget], dict[str, Path]]:
    """The packages to verify, and every package of the workspace by name.

    colcon's discovery decides; folders whose package.xml colcon rejected are
    added, so their manifest problems are reported instead of silently skipped.
    """
    descriptors = discover(workspace.base_path)
    targets = []
    for descriptor in descriptors:
        path = Path(descriptor.path).resolve()
        if not (path / "package.xml").exists():
            continue  # a plain CMake or Python package: not a ROS package
        targets.append(PackageTarget(path, descriptor.name, str(descriptor.type),
                                     str(descriptor.type).startswith("ros.")))
    known = {t.path for t in targets}
    for path in package_folders(workspace.base_path):
        if path not in known:
            targets.append(PackageTarget(path, quick_name(path), None, False))
    everything = {t.name: t.path for t in targets}
    if workspace.package_path is not None:
        targets = [t for t in targets if t.path == workspace.package_path.resolve()]
    return sorted(targets, key=lambda t: (t.name, str(t.path))), everything


def verify_package(target: PackageTarget, workspace_packages: dict[str, Path],
                   selection: Selection) -> PackageReport:
    """Load one package's model and run the selected checks on it (in a worker process)."""
    model = load_package(target.path, colcon_type=target.colcon_type,
                         parsed_by_colcon=target.parsed_by_colcon)
    context = CheckContext(model, workspace_packages)
    codes = selection.codes()
    report = PackageReport(model.name, model.path, model.build_type)
    for check in all_checks():
        if check.code not in codes:
            continue
        try:
            diagnostics = check.run(context)
        except Exception as exc:  # a bug in one check must not hide the others' results
            diagnostics = [check.diagnostic(model.name, Finding(
                f"internal error in check {check.name}: {type(exc).__name__}: {exc}", model.path,
                severity=Severity.WARNING, hint="please report this to pkgforge"))]
        for diagnostic in diagnostics:
            if not model.suppressed(diagnostic.path, diagnostic.line, {check.code, check.name}):
                report.diagnostics.append(diagnostic)
    report.diagnostics.sort(key=Diagnostic.sort_key)
    return report


def _verify_one(args) -> PackageReport:
    return verify_package(*args)


def verify(path: Path, options: VerifyOptions) -> VerifyResult:
    root = path.resolve()
    workspace = locate(path)
    config: Config = load_config(workspace.root, options.selection)
    jobs = options.jobs or os.cpu_count() or 1
    guessed = package_folders(workspace.base_path)
    if jobs > 1 and len(guessed) >= PARALLEL_THRESHOLD and workspace.package_path is None:
        reports = _verify_overlapped(workspace, config, guessed, jobs)
    else:
        targets, everything = find_targets(workspace)
        reports = [_verify_one((t, everything, config.for_package(t.name, t.path))) for t in targets]
    if not reports:
        raise PkgforgeError(f"no package found under {root}")
    checks_run = set().union(*(config.for_package(r.name, r.path).codes() for r in reports))
    return VerifyResult(root, reports, checks_run)


# The workspace index, set before the pool forks so workers inherit it instead
# of receiving a copy with every package.
_FORKED_WORKSPACE: dict[str, Path] = {}


def _verify_chunk(items: list[tuple[PackageTarget, Selection]]) -> list[PackageReport]:
    return [verify_package(target, _FORKED_WORKSPACE, selection) for target, selection in items]


def _verify_overlapped(workspace: Workspace, config: Config, guessed: list[Path], jobs: int):
    """Workers verify the folders a quick walk found while colcon's discovery runs here.

    Discovery and model loading are independent, and each takes about half of
    a run: overlapping them is most of what a second core can give. colcon's
    answer then decides which results count; what it found that the walk did
    not is verified afterwards.
    """
    global _FORKED_WORKSPACE
    named = [(quick_name(p), p) for p in guessed]
    _FORKED_WORKSPACE = dict(named)
    workers = max(1, jobs - 1)  # this process runs discovery meanwhile
    items = [(PackageTarget(p, name, None, False), config.for_package(name, p)) for name, p in named]
    size = max(1, -(-len(items) // (workers * 4)))
    chunks = [items[i:i + size] for i in range(0, len(items), size)]
    with ProcessPoolExecutor(max_workers=workers, mp_context=get_context("fork")) as pool:
        futures = [pool.submit(_verify_chunk, chunk) for chunk in chunks]
        targets, everything = find_targets(workspace)
        done = {report.path: report for future in futures for report in future.result()}
    reports = []
    for target in targets:
        report = done.get(target.path)
        if report is None or everything != _FORKED_WORKSPACE:
            report = _verify_one((target, everything, config.for_package(target.name, target.path)))
        reports.append(report)
    return reports
