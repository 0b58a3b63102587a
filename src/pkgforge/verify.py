"""`pkgforge verify`: discover → load one model per package → run checks → filter.

Packages are independent once discovered, so each is loaded and checked in a
worker process; only plain data (PackageReport) crosses back.
"""

from __future__ import annotations

import os
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


def _manifest_folders(base: Path, known: set[Path]) -> list[Path]:
    """Folders with a package.xml that colcon did not identify (it rejected the manifest)."""
    found = []
    for current, dirs, files in os.walk(base, followlinks=False):
        here = Path(current)
        if any(marker in files for marker in IGNORE_MARKERS):
            dirs[:] = []
            continue
        if "package.xml" in files:
            if here.resolve() not in known:
                found.append(here.resolve())
            dirs[:] = []
            continue
        dirs[:] = [d for d in dirs if not d.startswith(".")]
    return found


def find_targets(workspace: Workspace) -> tuple[list[PackageTarget], dict[str, Path]]:
    """The packages to verify, and every package of the workspace by name."""
    descriptors = discover(workspace.base_path)
    targets = []
    for descriptor in descriptors:
        path = Path(descriptor.path).resolve()
        if not (path / "package.xml").exists():
            continue  # a plain CMake or Python package: not a ROS package
        targets.append(PackageTarget(path, descriptor.name, str(descriptor.type),
                                     str(descriptor.type).startswith("ros.")))
    known = {t.path for t in targets}
    for path in _manifest_folders(workspace.base_path, known):
        targets.append(PackageTarget(path, path.name, None, False))
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
    targets, everything = find_targets(workspace)
    if not targets:
        raise PkgforgeError(f"no package found under {root}")
    jobs = options.jobs or os.cpu_count() or 1
    work = [(t, everything, config.for_package(t.name, t.path)) for t in targets]
    if jobs > 1 and len(work) >= PARALLEL_THRESHOLD:
        with ProcessPoolExecutor(max_workers=jobs, mp_context=get_context("fork")) as pool:
            reports = list(pool.map(_verify_one, work, chunksize=max(1, len(work) // (jobs * 4))))
    else:
        reports = [_verify_one(item) for item in work]
    checks_run = set().union(*(selection.codes() for _, _, selection in work))
    return VerifyResult(root, reports, checks_run)
