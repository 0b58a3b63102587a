"""`pkgforge verify`: discover → one model per package → install tree → resolve launch files → checks.

Models load in worker processes while colcon's discovery runs here; launch
files are resolved in worker subprocesses (user code); the checks then read
the models and resolutions in this process. Only plain data crosses a process.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pkgforge.diagnostics import Diagnostic, Finding, PackageReport, Severity
from pkgforge.errors import BuildFailed, PkgforgeError
from pkgforge.verify.config import Config, load_config
from pkgforge.verify.discovery import (
    Namesakes,
    PackageTarget,
    first_of_each,
    load_models,
    load_one_package,
    namesakes_of,
    rviz_files,
)
from pkgforge.verify.distros import by_launch_engine, launch_distro, package_distros
from pkgforge.verify.grouping import once_across_packages
from pkgforge.verify.lookup import cache_lookup, store_whole, workspace_lookup
from pkgforge.verify.options import VerifyOptions
from pkgforge.verify.progress import Progress
from pkgforge.workspace import Workspace, locate

if TYPE_CHECKING:
    from pkgforge.checks.context import CheckContext
    from pkgforge.checks.registry import Check
    from pkgforge.launch.engines import LaunchEngine
    from pkgforge.launch.records import LaunchFile, Resolution
    from pkgforge.model.package import PackageModel
    from pkgforge.model.rviz import RvizConfig
    from pkgforge.robot_models import ModelResult
    from pkgforge.sandbox.protocol import Confinement
    from pkgforge.sandbox.zygote import Zygote
    from pkgforge.simulate import Outcome
    from pkgforge.tree import InstallTree
    from pkgforge.verify.cache import ResultCache

    # package → (its own RViz configs, [(a config, the launch file passing it with -d)])
    RvizFound = dict[str, tuple[list[RvizConfig], list[tuple[RvizConfig, LaunchFile]]]]

# The model layer (lxml, catkin_pkg) and the checks load only when something
# must be verified: a run answered from the cache never imports them.

# areas whose checks need the install tree and worker subprocesses
TREE_AREAS = ("launch", "model", "physics", "rviz", "simulation")


def _tree_codes() -> set[str]:
    """The codes of the checks that need the install tree (and worker subprocesses)."""
    from pkgforge.checks.registry import all_checks

    return {c.code for c in all_checks() if c.area in TREE_AREAS}


@dataclass
class VerifyResult:
    root: Path
    reports: list[PackageReport]
    checks_run: set[str]
    # package folder → files outside it that its verification read (for the cache)
    externals: dict[Path, set[str]] = field(default_factory=dict)
    # package folders whose result depends on the machine's state (a timeout, a crashed or
    # killed worker, a limit hit): never cached
    unstable: set[Path] = field(default_factory=set)
    engine: str = "builtin"  # the launch engine: builtin | ros
    distro: str | None = None  # the ROS 2 distro whose launch libraries ran (ros engine)
    # what confined the processes that evaluated launch files and models; None: none ran
    sandbox: Confinement | None = None

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return [d for report in self.reports for d in report.diagnostics]

    @property
    def launch_distros(self) -> dict[tuple[str, str], list[str]]:
        """(distro, where it came from) → the packages whose launch files the built-in engine
        evaluated under that distro's launch API, in the order first met."""
        out: dict[tuple[str, str], list[str]] = {}
        for report in self.reports:
            if report.launch_distro is not None:
                out.setdefault(report.launch_distro, []).append(report.name)
        return out

    def count(self, severity: Severity) -> int:
        return sum(1 for d in self.diagnostics if d.severity == severity)

    @property
    def internal_errors(self) -> list[str]:
        return [error for report in self.reports for error in report.internal_errors]

    def exit_code(self, strict: bool) -> int:
        if self.internal_errors:
            return 2  # verify could not run completely: a bug in pkgforge
        worst = max((d.severity for d in self.diagnostics), default=None)
        if worst == Severity.ERROR or (strict and worst == Severity.WARNING):
            return 1
        return 0


# --- checks ---------------------------------------------------------------------------------


def run_checks(
    context: CheckContext, codes: set[str], ignored: Callable[[Path, Check], bool] | None = None
) -> PackageReport:
    """The package's diagnostics of the checks `codes`; `ignored`: whether pkgforge.toml's
    per-file-ignores silence a check in a file."""
    from pkgforge.checks.registry import all_checks

    model = context.model
    report = PackageReport(model.name, model.path, model.build_type)
    seen = set()
    for check in all_checks():
        if check.code not in codes:
            continue
        try:
            diagnostics = check.run(context)
        except OSError as exc:  # a file the check had to look at cannot be read: located, not a crash
            from pkgforge.checks.registry import REGISTRY
            from pkgforge.errors import describe_os_error

            where = Path(exc.filename) if isinstance(exc.filename, str) else model.path
            diagnostics = [
                REGISTRY["PF901"].diagnostic(
                    model.name,
                    Finding(
                        f"not read while checking {check.name}: {describe_os_error(exc)}",
                        where,
                        hint="make the file (and its folders) readable; checks that need it are incomplete",
                    ),
                )
            ]
        except Exception as exc:  # a bug in one check must not hide the others' results
            import traceback

            report.internal_errors.append(
                f"in check {check.name} ({check.code}) on {model.name}: {type(exc).__name__}: {exc}\n"
                + traceback.format_exc()
            )
            diagnostics = [
                check.diagnostic(
                    model.name,
                    Finding(
                        f"internal error in check {check.name}: {type(exc).__name__}: {exc}",
                        model.path,
                        severity=Severity.ERROR,
                        hint="a bug in pkgforge: please report it (pkgforge --debug "
                        "verify shows the traceback)",
                    ),
                )
            ]
        for diagnostic in diagnostics:
            key = (diagnostic.code, str(diagnostic.path), diagnostic.line, diagnostic.message)
            if (
                key in seen
                or model.suppressed(diagnostic.path, diagnostic.line, {check.code, check.name})
                or (ignored is not None and ignored(diagnostic.path, check))
            ):
                continue
            seen.add(key)
            report.diagnostics.append(diagnostic)
    from pkgforge.verify.grouping import grouped

    # (after the suppressions, which silence one line each: a group holds what is left)
    report.diagnostics = grouped(report.diagnostics)
    report.diagnostics.sort(key=Diagnostic.sort_key)
    return report


def make_tree(options: VerifyOptions, workspace: Workspace, models: list[PackageModel]) -> InstallTree:
    from pkgforge.tree import built_tree, existing_tree, predicted_tree

    evaluate_setup_files(models, options, None, 1)  # (when the caller did not: --explain-launch)
    if options.mode == "install-base":
        if options.install_base is None:
            raise PkgforgeError("verify against an install base needs --install-base")
        return existing_tree(options.install_base, models)
    if options.mode == "build":
        return built_tree(workspace, models, out=sys.stderr)
    return predicted_tree(models, user_install=workspace.root / "install")


def _shadowed(models: list[PackageModel], namesakes: Namesakes, tree: InstallTree) -> set[Path]:
    """Of the packages sharing a name, all but the one the install tree holds: the copy whose
    package.xml the tree's is (a predicted tree, a symlinked install), else the first, which the
    predicted tree would hold (a copied install does not say whose it is). The others' launch
    files and models cannot be resolved in it."""
    copies: dict[str, list[PackageModel]] = {}
    for model in models:
        if model.path in namesakes:
            copies.setdefault(model.name, []).append(model)
    shadowed = set()
    for same in copies.values():
        share = tree.share(same[0].share_name)
        origin = tree.origin(str(share / "package.xml")) if share is not None else None
        held = next((m for m in same if origin == os.path.realpath(m.path / "package.xml")), same[0])
        shadowed |= {m.path for m in same if m is not held}
    return shadowed


def rviz_configs(
    tree: InstallTree, checked: list[PackageModel], resolutions: dict[str, list[Resolution]]
) -> RvizFound:
    """package → (its RViz configs, [(config, launch file passing it with -d)])."""
    from pkgforge.launch.resolve import source_of
    from pkgforge.model.rviz import read_rviz

    out: RvizFound = {}
    for model in checked:
        # read by the loader processes when they loaded the model (beside discovery), else here
        configs: dict[Path, RvizConfig] = dict(rviz_files(model, getattr(model, "rviz_read", None)))
        launches = []
        for resolution in resolutions.get(model.name, []):
            for node in resolution.nodes:
                arguments = node.arguments
                if node.package != "rviz2" or "-d" not in arguments[:-1]:
                    continue
                source = source_of(Path(arguments[arguments.index("-d") + 1]), tree, model)
                if source is None or not source.is_file():
                    continue  # another package's config, or missing (uninstalled-reference says so)
                if source not in configs:
                    configs[source] = read_rviz(source)
                launches.append((configs[source], resolution.launch))
        out[model.name] = (list(configs.values()), launches)
    return out


def _drop_tests(
    tree: InstallTree, model_results: dict[str, list[ModelResult]], progress: Progress, jobs: int
) -> dict[Path, Outcome]:
    """--simulate: each robot model's drop test (simulate/), one limited process per model,
    `jobs` of them at a time."""
    from concurrent.futures import ThreadPoolExecutor

    from pkgforge.simulate import drop_test, model_urdf
    from pkgforge.urdf.meshes import resolve_uri

    models = [
        result
        for results in model_results.values()
        for result in results
        if result.status == "ok" and result.robot and result.robot.get("root_tag") == "robot"
    ]
    done = progress.counter("drop tests", len(models))

    def test(result: ModelResult) -> Outcome:
        def resolve(uri: str) -> Path | None:
            lookup = resolve_uri(uri, tree, result.installed)
            return lookup.path if lookup.status == "found" else None

        assert result.robot is not None
        children = {joint.get("child") for joint in result.robot.get("joints", [])}
        root = next((link["name"] for link in result.robot["links"] if link["name"] not in children), None)
        outcome = drop_test(model_urdf(result.robot, resolve), root)
        done()
        return outcome

    with ThreadPoolExecutor(max(1, jobs)) as pool:
        return dict(zip([r.installed for r in models], pool.map(test, models), strict=True))


# Python's cyclic collector makes a pass each time 700 more objects are allocated than freed, and
# a full one every 100 of those (the default 700, 10, 10): verify keeps ~1e6 objects alive (models,
# launch records), so the passes found next to nothing while they took ~0.6 of the main process's
# 3.3 CPU s at 800 packages (bench/scale.py). 100x fewer passes; peak memory 104 -> 105 MiB there.
COLLECTOR_THRESHOLDS = (100_000, 20, 100)


@contextmanager
def _fewer_collections() -> Iterator[None]:
    """The collector's thresholds for one verify (and the model loaders it forks), restored after:
    verify is also called in-process (colcon verify, tests)."""
    import gc

    before = gc.get_threshold()
    gc.set_threshold(*COLLECTOR_THRESHOLDS)
    try:
        yield
    finally:
        gc.set_threshold(*before)


@_fewer_collections()
def verify(path: Path, options: VerifyOptions, zygote: Zygote | None = None) -> VerifyResult:
    """Verify the package(s) at `path`. `zygote`: the launch workers' fork server, when the caller
    started it already (cli: before its imports); closed here once verify is done with it."""
    root = path.resolve()
    engine = options.engine()  # before any work: a --launch-engine that cannot be had stops here
    workspace = locate(path)
    config: Config = load_config(workspace.root, options.selection)
    jobs = options.jobs or os.cpu_count() or 1
    cache: ResultCache | None = None
    keys: dict[Path, str] = {}
    hits: dict[Path, tuple[PackageReport, set[str]]] = {}
    whole = None
    if options.use_cache and options.mode == "predicted":
        try:
            whole, answer = workspace_lookup(workspace, config, options)
            if answer is not None:  # nothing changed anywhere since a run that cached every package
                reports = once_across_packages(answer[0])
                return VerifyResult(root, reports, answer[1], engine=engine.name, distro=engine.distro)
            cache, keys, hits = cache_lookup(workspace, config, options)
        except OSError:  # a cache folder this user may not write: verify without the cache
            cache, keys, hits, whole = None, {}, {}, None
        if keys and len(hits) == len(keys):  # everything unchanged: no discovery, no models
            reports = sorted((report for report, _ in hits.values()), key=lambda r: (r.name, str(r.path)))
            reports = once_across_packages(reports)
            codes = set().union(*(codes for _, codes in hits.values()))
            store_whole(cache, whole, keys, reports)
            return VerifyResult(root, reports, codes, engine=engine.name, distro=engine.distro)
    zygote = zygote if zygote is not None else _early_zygote(options, engine)
    try:
        if workspace.package_path is not None:
            targets, models, everything, namesakes = load_one_package(workspace)
        else:
            targets, models = load_models(workspace, jobs)
            everything = {name: m.path for name, m in first_of_each(models.values(), "name").items()}
            namesakes = namesakes_of([(t.name, t.path) for t in targets])
        if not targets:
            raise PkgforgeError(f"no package found under {root}")
        todo = [t for t in targets if t.path not in hits]
        result = (
            run(root, workspace, config, todo, models, everything, options, zygote, namesakes)
            if todo
            else VerifyResult(root, [], set())
        )
    finally:
        if zygote is not None:
            zygote.close()
    if cache is not None:
        try:
            for report in result.reports:
                if report.path in keys and report.path not in result.unstable and not report.internal_errors:
                    cache.store(
                        report.path,
                        keys[report.path],
                        report,
                        result.externals.get(report.path, set()),
                        config.for_package(report.name, report.path).codes(),
                    )
            cache.save_index()
        except OSError:
            pass  # the results stand; the next run verifies again
    result.reports = once_across_packages(
        sorted(result.reports + [r for r, _ in hits.values()], key=lambda r: (r.name, str(r.path)))
    )
    result.checks_run |= set().union(*(codes for _, codes in hits.values()))
    store_whole(cache, whole, keys, result.reports)
    result.engine, result.distro = engine.name, engine.distro
    return result


def _early_zygote(options: VerifyOptions, engine: LaunchEngine) -> Zygote | None:
    """The launch workers' fork server, started before discovery so that its imports run beside
    it (pipelined); None when launch files will not be evaluated (--select without them, --build,
    whose colcon build takes long enough)."""
    if options.mode == "build":
        return None
    if options.selection.select and not options.selection.codes() & _tree_codes():
        return None  # (without --select, some package may select launch checks in pkgforge.toml)
    from pkgforge.sandbox.zygote import start_zygote

    return start_zygote(engine)


def check_launch_arguments(values: dict[str, str], resolutions: dict[str, list[Resolution]]) -> None:
    """A --launch-arg value outside the choices its launch file declares is a usage error (exit 2),
    not one launch-load-error per place the value reaches. The choices are the launch file's own
    code (computed, or from an included file), so only its evaluation knows them: this runs on the
    resolutions, before any check."""
    problems = []
    for package_resolutions in resolutions.values():
        for resolution in package_resolutions:
            by_installed = {str(resolution.launch.installed): resolution.launch.source}
            for argument in resolution.arguments:
                name, choices = argument.name, argument.choices
                if name not in values or not choices or values[name] in choices:
                    continue
                where = by_installed.get(argument.file or "") or argument.file or "?"
                where = os.path.relpath(where) if os.path.isabs(str(where)) else where
                line = f":{argument.line}" if argument.line else ""
                problem = (
                    f"--launch-arg {name}:={values[name]}: '{name}' allows only "
                    f"{', '.join(map(str, choices))} (declared at {where}{line})"
                )
                if problem not in problems:
                    problems.append(problem)
    if problems:
        raise PkgforgeError(*problems)  # one line each


def run(
    root: Path,
    workspace: Workspace,
    config: Config,
    targets: list[PackageTarget],
    models: dict[Path, PackageModel],
    everything: dict[str, Path],
    options: VerifyOptions,
    zygote: Zygote | None = None,
    namesakes: Namesakes | None = None,
) -> VerifyResult:
    """Verify the targets; `models` holds every package the install tree needs. `zygote`: the
    launch workers' fork server, when one was started already (closed here). `namesakes`: the
    targets whose package name another workspace folder has too."""
    from pkgforge.checks.context import CheckContext

    jobs = options.jobs or os.cpu_count() or 1
    selections = {t.path: config.for_package(t.name, t.path) for t in targets}
    launch_distros = {t.path: launch_distro(t.path, workspace, config, options) for t in targets}
    codes = {path: selection.codes() for path, selection in selections.items()}
    tree_codes = _tree_codes() | {BUILD_FAILED}
    checked = [models[t.path] for t in targets]

    tree = None
    sandbox: Confinement | None = None
    build_failure: BuildFailed | None = None
    resolutions: dict[str, list[Resolution]] = {}
    ros1: dict[str, list[LaunchFile]] = {}
    model_results: dict[str, list[ModelResult]] = {}
    rviz: RvizFound = {}
    simulations: dict[Path, Outcome] = {}  # --simulate: each model's drop test, by its installed file
    needs_tree = any(codes[t.path] & tree_codes for t in targets)
    # setup.py files the static reader could not read, run as colcon reads them (sandboxed): their
    # layouts before the tree is made from them; the packages in the tree too when there is one
    evaluated = evaluate_setup_files(
        checked + (list(first_of_each(models.values(), "name").values()) if needs_tree else []),
        options,
        zygote,
        jobs,
    )
    if needs_tree:
        from pkgforge import robot_models
        from pkgforge.launch.resolve import WorkerLimits, find_launch_files, resolve
        from pkgforge.launch.uninstalled import source_only

        limits = WorkerLimits(options.launch_timeout, options.worker_memory)
        progress = Progress(enabled=None if options.progress else False)
        progress.show(f"{len(checked)} packages: install tree")
        # one copy of a package name, as an install folder holds one (the others are shadowed,
        # PF110): files only another copy has would stand in its share folder, sourceless
        placed = first_of_each(models.values(), "name")
        try:
            tree = make_tree(options, workspace, list(placed.values()))
        except BuildFailed as failure:
            if options.mode != "build":
                raise
            build_failure = failure  # reported as build-failed beside every check that needs no tree
            codes = {
                path: selected - tree_codes | (selected & {BUILD_FAILED}) for path, selected in codes.items()
            }
    shadowed: set[Path] = set()
    if tree is not None:
        from pkgforge.sandbox.zygote import Zygote

        # a package whose namesake's files the tree holds: its tree checks would read the other's
        shadowed = _shadowed(checked, namesakes or {}, tree)
        codes = {
            path: selected - tree_codes if path in shadowed else selected for path, selected in codes.items()
        }
        in_tree = [model for model in checked if model.path not in shadowed]
        # one fork server for the launch files' and the models' workers
        zygote = zygote if zygote is not None else Zygote()
        try:  # a signal or an error: the temporary tree goes too
            launch_files, ros1_files = find_launch_files(tree, in_tree)
            launch_files += source_only(in_tree, launch_files)  # evaluated from the source
            # a FIFO or a device where a launch file stands is no file to run (PF901 says what it is)
            launch_files = [f for f in launch_files if os.path.isfile(f.installed)]
            on_done = progress.counter("launch files", len(launch_files))
            for engine, group in by_launch_engine(launch_files, in_tree, launch_distros, options):
                for resolution in resolve(
                    group,
                    tree,
                    jobs=jobs,
                    timeout=options.launch_timeout,
                    arguments=options.launch_arguments,
                    limits=limits,
                    engine=engine,
                    zygote=zygote,
                    on_done=on_done,
                ):
                    resolutions.setdefault(resolution.launch.package, []).append(resolution)
            for launch in ros1_files:
                ros1.setdefault(launch.package, []).append(launch)
            tree.restore()  # the checks read the user's files, not what a launch file wrote over them
            to_process = robot_models.collect(tree, in_tree, resolutions)
            pending = sum(1 for r in to_process if r.robot is None)
            for result in robot_models.process(
                to_process,
                tree,
                jobs=jobs,
                timeout=options.launch_timeout,
                on_done=progress.counter("robot models", pending),
                limits=limits,
                zygote=zygote,
            ):
                model_results.setdefault(result.package, []).append(result)
            zygote.close()
            sandbox = zygote.confinement
            if options.on_models is not None:
                options.on_models(tree, [r for results in model_results.values() for r in results])
            rviz = rviz_configs(tree, in_tree, resolutions)
            if options.simulate:
                simulations = _drop_tests(tree, model_results, progress, jobs)
            progress.clear()
        except BaseException:
            progress.clear()
            zygote.close()
            tree.close()
            raise
    read: dict[Path, set[str]] = {}
    try:
        check_launch_arguments(options.launch_arguments, resolutions)
        by_share = first_of_each(models.values(), "share_name")
        shared: dict[
            Any, Any
        ] = {}  # what every package's checks would otherwise build again (CheckContext.shared)

        def check(target: PackageTarget) -> tuple[PackageReport, set[str] | None]:
            model = models[target.path]
            # (by name: a shadowed namesake's would be the tree's copy's)
            own = target.path not in shadowed
            configs, launches = rviz.get(model.name, ([], [])) if own else ([], [])
            model.manifest.distros = package_distros(target.path, workspace, config, options)
            context = CheckContext(
                model,
                everything,
                by_share,
                tree,
                resolutions.get(model.name, []) if own else [],
                ros1.get(model.name, []) if own else [],
                model_results.get(model.name, []) if own else [],
                configs,
                launches,
                distros=model.manifest.distros,
                install_base=options.install_base if options.mode == "install-base" else None,
                workspace_base=workspace.base_path,
                namesakes=(namesakes or {}).get(target.path, ()),
                shadowed=not own,
                shared=shared,
                simulations=simulations,
            )
            selection = selections[target.path]
            report = run_checks(
                context, codes[target.path], selection.ignored_in if selection.per_file else None
            )
            if options.engine().name == "builtin":
                report.launch_distro = launch_distros[target.path]
            if build_failure is not None and BUILD_FAILED in codes[target.path]:
                _report_build_failure(report, model, build_failure, {t.name for t in targets})
            selections[target.path].apply_severity(report)  # [severity] of pkgforge.toml
            if options.use_cache and tree is not None:
                from pkgforge.verify.cache import externals as read_elsewhere

                return report, read_elsewhere(context)
            return report, None

        # in forked processes (verify/forked.py), each computing CheckContext.shared for its own slice
        from pkgforge.verify.forked import forked_map

        reports = []
        for target, (report, elsewhere) in zip(targets, forked_map(check, targets, jobs), strict=True):
            reports.append(report)
            if elsewhere is not None:
                read[target.path] = elsewhere
    finally:
        if tree is not None:
            tree.close()
    checks_run = set().union(*codes.values())
    unstable = {
        t.path
        for t in targets
        if t.path in evaluated
        or _machine_dependent(
            resolutions.get(models[t.path].name, []), model_results.get(models[t.path].name, [])
        )
        # a package sharing its name: which copy the tree holds differs between a run on the
        # workspace and one on the package alone, and so do its checks (PF110)
        or t.path in (namesakes or {})
    }
    engine = options.engine()
    return VerifyResult(
        root,
        reports,
        checks_run,
        externals=read,
        unstable=unstable,
        engine=engine.name,
        distro=engine.distro,
        sandbox=sandbox,
    )


BUILD_FAILED = "PF902"


def evaluate_setup_files(
    models: Iterable[PackageModel], options: VerifyOptions, zygote: Zygote | None, jobs: int
) -> set[Path]:
    """Run each setup.py the static reader could not fully read, as colcon reads a package's
    metadata, in the sandbox (a request each: SetupRequest), and make the package's install
    layout from what setup() got; a failure leaves the static reading, with the failure said.
    → the packages whose evaluation this machine decided (a limit, a crash): never cached."""
    from pkgforge.model.setup_eval import apply_setup_reply, evaluation_request, needs_evaluation

    todo = list({id(m): m for m in models if needs_evaluation(m)}.values())
    if not todo:
        return set()
    from pkgforge.launch.resolve import WorkerLimits, run_requests
    from pkgforge.sandbox.protocol import SetupRequest
    from pkgforge.tree import predicted_tree

    requests: list[SetupRequest] = [{"setup": evaluation_request(model)} for model in todo]
    progress = Progress(enabled=None if options.progress else False)
    progress.show(f"{len(todo)} setup.py files")
    # the workers' environment is a tree's: an empty one here (setup.py runs before any tree is made)
    tree = predicted_tree([])
    try:
        replies = run_requests(
            requests,
            tree,
            jobs=jobs,
            timeout=options.launch_timeout,
            limits=WorkerLimits(options.launch_timeout, options.worker_memory),
            engine=options.engine(),
            zygote=zygote,
            on_done=progress.counter("setup.py files", len(todo)),
        )
    finally:
        tree.close()
        progress.clear()
    for model, reply in zip(todo, replies, strict=True):
        apply_setup_reply(model, reply)
    return {m.path for m in todo if m.setup_py is not None and m.setup_py.evaluation_unstable}


def _report_build_failure(
    report: PackageReport, model: PackageModel, failure: BuildFailed, verified: set[str]
) -> None:
    """One build-failed error for a package colcon could not build; when only packages outside
    the verified ones failed (a dependency) or colcon stopped before any ran, each verified
    package gets one, so a failed build never passes."""
    from pkgforge.checks.build import build_failed_finding
    from pkgforge.checks.facts import FileFacts
    from pkgforge.checks.registry import REGISTRY

    own: list[tuple[str | None, Path | None, str]] = [
        (package, log, tail) for package, log, tail in failure.failures if package == model.name
    ]
    if not own and not any(package in verified for package, _, _ in failure.failures):
        own = failure.failures[:1] or [(None, None, "")]
    for package, log, tail in own:
        finding = build_failed_finding(
            model.path,
            model.build_type,
            log,
            tail,
            failure.status,
            None if package == model.name else package,
            files=FileFacts(),
        )
        if model.suppressed(finding.path, finding.line, {BUILD_FAILED, "build-failed"}):
            continue
        report.diagnostics.append(REGISTRY[BUILD_FAILED].diagnostic(model.name, finding))
    report.diagnostics.sort(key=Diagnostic.sort_key)


def _machine_dependent(resolutions: list[Resolution], model_results: list[ModelResult]) -> bool:
    """A result that the machine's load or limits decided: a timeout, a crashed or killed worker,
    a limit hit. Run again, it may differ, so it is never cached."""
    from pkgforge.launch.resolve import MACHINE_DEPENDENT

    def limit(error: object) -> bool:  # a launch record (launch.records.Error) or a model's ModelError
        return bool(error.get("limit") if isinstance(error, dict) else getattr(error, "limit", None))

    items: list[Resolution | ModelResult] = [*resolutions, *model_results]
    for item in items:
        if item.status in MACHINE_DEPENDENT or limit(item.error or {}):
            return True
        if getattr(item, "unevaluated", 0):  # argument combinations the time limit left out
            return True
        if any(limit(error) for error in getattr(item, "errors", [])):
            return True
    return False
