"""`pkgforge fix`: verify (default mode), apply the fixes the findings carry, verify again.

Each pass verifies, asks each diagnostic's fixer for edits, merges the edits of
every file (a fix whose edits overlap another's waits for the next pass),
parses each edited file again, and writes it atomically. A fix can uncover a
finding that had been hidden (rviz/ installed, its config is read): passes
repeat until one has nothing left to apply, so a second `pkgforge fix` changes
nothing. With --diff there is one pass and nothing is written. A dependency fix
that would close a cycle among the workspace's packages (with the pass's other
fixes or the dependencies declared already) is not applied: colcon refuses it.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from pkgforge.diagnostics import Diagnostic
from pkgforge.fix.edits import (
    Edit,
    FileSet,
    NotOffered,
    Outcome,
    Unfixable,
    apply,
    create_exclusively,
    parse_problem,
    unified_diff,
    write_atomically,
)
from pkgforge.fix.registry import Fix, FixContext, all_fixers
from pkgforge.verify.options import VerifyOptions
from pkgforge.verify.pipeline import VerifyResult, verify
from pkgforge.walk import WalkLimit, walk

MAX_PASSES = 4


@dataclass
class FixOptions:
    verify: VerifyOptions = field(default_factory=VerifyOptions)
    unsafe: bool = False
    diff: bool = False


@dataclass
class Applied:
    diagnostic: Diagnostic
    description: str


@dataclass
class FixRun:
    result: VerifyResult  # what remains (with --diff: what verify found)
    fixed: list[Applied] = field(default_factory=list)
    not_fixed: list[tuple[Diagnostic, str]] = field(default_factory=list)  # (diagnostic, why)
    unsafe_available: list[Diagnostic] = field(default_factory=list)
    failures: list[Outcome] = field(default_factory=list)  # files that could not be written
    diff: str = ""
    diff_mode: bool = False
    files_written: set[Path] = field(default_factory=set)
    passes: int = 0

    def exit_code(self, strict: bool) -> int:
        return 1 if self.failures else self.result.exit_code(strict)


@dataclass
class _Plan:
    fixes: list[tuple[Diagnostic, Fix]] = field(default_factory=list)
    edits: dict[Path, list[Edit]] = field(default_factory=dict)
    creates: dict[Path, str] = field(default_factory=dict)
    deferred: list[Diagnostic] = field(default_factory=list)


def fix_kind(diagnostic: Diagnostic) -> str | None:
    """safe, unsafe or None: the check's kind, unless the finding says its own fix is unsafe (a
    viewer started only with a setting: only the user knows whether the package's users use it)."""
    from pkgforge.checks.registry import all_checks

    check = next((c for c in all_checks() if c.code == diagnostic.code), None)
    if check is None or check.fix is None:
        return None
    return "unsafe" if (diagnostic.fix or {}).get("unsafe") else check.fix


def plan(result: VerifyResult, files: FileSet, unsafe: bool, run: FixRun) -> _Plan:
    """The edits of every fixable diagnostic, merged per file."""
    context = FixContext(files)
    out = _Plan()
    roots = [report.path.resolve() for report in result.reports]
    candidates: list[tuple[Diagnostic, Fix]] = []
    for diagnostic in result.diagnostics:
        kind = fix_kind(diagnostic)
        function = all_fixers().get(diagnostic.name)
        if kind is None or function is None:
            continue
        if kind == "unsafe" and not unsafe:
            run.unsafe_available.append(diagnostic)
            continue
        try:
            fix = function(diagnostic, context)
        except NotOffered:
            continue
        except Unfixable as exc:
            run.not_fixed.append((diagnostic, str(exc)))
            continue
        except Exception as exc:  # a bug in one fixer must not stop the others
            run.not_fixed.append(
                (
                    diagnostic,
                    f"internal error in the fixer: {type(exc).__name__}: {exc} "
                    "(please report this to pkgforge)",
                )
            )
            continue
        outside = [
            p for p in fix.paths if not any(Path(os.path.realpath(p)).is_relative_to(r) for r in roots)
        ]
        if outside:
            run.not_fixed.append(
                (diagnostic, f"the fix edits {outside[0]}, outside the package(s) being fixed")
            )
            continue
        candidates.append((diagnostic, fix))
    cycles = _cycles([fix for _, fix in candidates], result.root)
    for index, (diagnostic, fix) in enumerate(candidates):
        if index in cycles:
            run.not_fixed.append((diagnostic, cycles[index]))
            continue
        if _clashes(fix, out.edits, out.creates):
            out.deferred.append(diagnostic)
            continue
        for path, edits in fix.edits.items():
            merged = out.edits.setdefault(path, [])
            merged.extend(e for e in edits if e not in merged)
        out.creates.update(fix.creates)
        out.fixes.append((diagnostic, fix))
    return out


def _cycles(fixes: list[Fix], root: Path) -> dict[int, str]:
    """The fixes (by index) whose dependency would close a cycle among the workspace's packages,
    with the other fixes of the run and the dependencies declared already (any kind but
    doc_depend, on any distro: colcon orders by them all and refuses a cycle), and why.

    Two packages each using the other undeclared (ROBOTIS ai_worker's ffw_description and
    ffw_bringup) each get a true finding, but declaring both is a cycle colcon refuses to build.
    Neither is declared: which package is meant to need the other (and which use should move)
    is the user's choice, and a second run finds the same two and again changes nothing."""
    from pkgforge.model.files import quick_name
    from pkgforge.model.manifest import load_manifest
    from pkgforge.model.source import read_source
    from pkgforge.verify.discovery import package_folders
    from pkgforge.workspace import locate

    declaring = [(index, fix.declares) for index, fix in enumerate(fixes) if fix.declares is not None]
    if not declaring:
        return {}
    names: dict[Path, str] = {}  # each workspace package's folder → its name
    edges: dict[str, set[str]] = {}
    for folder in package_folders(locate(root).base_path):
        manifest = load_manifest(read_source(folder / "package.xml"))
        name = manifest.name or quick_name(folder)
        names[folder] = name
        edges.setdefault(name, set()).update(
            d.name for d in manifest.dependencies if d.tag != "doc_depend" and d.active()
        )
    proposed: dict[int, tuple[str, str]] = {}
    for index, (manifest_path, dependency) in declaring:
        owner = names.get(Path(os.path.realpath(manifest_path)).parent)
        if owner is not None and dependency in edges and dependency != owner:
            proposed[index] = (owner, dependency)
    for owner, dependency in proposed.values():
        edges[owner].add(dependency)
    out: dict[int, str] = {}
    for index, (owner, dependency) in sorted(proposed.items()):
        path = _path(edges, dependency, owner)
        if path is None:
            continue
        cycle = [owner, *path]
        steps = list(zip(cycle, cycle[1:], strict=False))
        others = [f"{b} in {a}" for a, b in steps[1:] if (a, b) in proposed.values()]
        shown = " → ".join(cycle)
        if others:
            out[index] = (
                f"declaring {dependency} here and, as {'another fix' if len(others) == 1 else 'other fixes'} "
                f"of this run would, {' and '.join(others)} makes a cycle colcon refuses ({shown}): "
                f"{'neither is' if len(others) == 1 else 'none of them is'} applied; declare the "
                "dependency that is meant, and move the other use"
            )
        else:
            out[index] = (
                f"{dependency} depends on {owner} ({shown}), so declaring it makes a cycle colcon refuses"
            )
    return out


def _path(edges: dict[str, set[str]], start: str, goal: str) -> list[str] | None:
    """The shortest path of dependencies from start to goal (start and goal in it), or None."""
    previous: dict[str, str] = {}
    todo, seen = [start], {start}
    while todo:
        following: list[str] = []
        for name in todo:
            for next_name in sorted(edges.get(name, ())):
                if next_name in seen or next_name not in edges:
                    continue
                previous[next_name] = name
                if next_name == goal:
                    path = [goal]
                    while path[-1] != start:
                        path.append(previous[path[-1]])
                    return path[::-1]
                seen.add(next_name)
                following.append(next_name)
        todo = following
    return None


def _clashes(fix: Fix, edits: dict[Path, list[Edit]], creates: dict[Path, str]) -> bool:
    if any(path in creates and creates[path] != text for path, text in fix.creates.items()):
        return True
    for path, new in fix.edits.items():
        for edit in new:
            for other in edits.get(path, []):
                if edit != other and edit.start < other.end and other.start < edit.end:
                    return True
    return False


def run_fix(
    path: Path,
    options: FixOptions,
    *,
    shown_root: Path | None = None,
    _first: list[VerifyResult] | None = None,
    _original: Callable[[Path], Path] | None = None,
) -> FixRun:
    """`_original`: a file's path in the user's tree, for a run on a copy (--diff): the formatter
    its repository configures is found from there."""
    shown_root = shown_root or Path.cwd()
    if options.diff:
        mirrored = _diff_on_a_copy(path, options, shown_root)
        if mirrored is not None:
            return mirrored
    verify_options = dataclasses.replace(options.verify, mode="predicted", install_base=None, use_cache=False)
    result = verify(path, verify_options)
    if _first is not None:
        _first.append(result)
    run = FixRun(result, diff_mode=options.diff)
    previous: set[tuple[str, str, int | None, str]] | None = None
    for number in range(1, MAX_PASSES + 1):
        run.passes = number
        run.not_fixed, run.unsafe_available = [], []
        files = FileSet()
        planned = plan(result, files, options.unsafe, run)
        keys = {(d.code, str(d.path), d.line, d.message) for d, _ in planned.fixes}
        if not planned.fixes or keys == previous:
            break
        previous = keys
        new_texts: dict[Path, str] = {}
        broken: dict[Path, str] = {}
        for file, edits in planned.edits.items():
            source = files.get(file)
            text = apply(source.text, edits)
            if text == source.text:
                continue
            problem = parse_problem(file, text)
            if problem is not None and parse_problem(file, source.text) is None:
                broken[file] = problem
                continue
            if file.suffix == ".py":  # a launch file: stable under the repository's formatter
                from pkgforge.fix.formatter import keep_formatted

                text = keep_formatted(_original(file) if _original else file, source.text, text)
            new_texts[file] = text
        for file, text in planned.creates.items():
            problem = parse_problem(file, text)
            if problem is not None:
                broken[file] = problem
        applied: list[tuple[Diagnostic, Fix]] = []
        for diagnostic, fix in planned.fixes:
            bad = [broken[p] for p in fix.paths if p in broken]
            if bad:
                run.not_fixed.append(
                    (diagnostic, f"the fix would leave the file unparsable ({bad[0]}); nothing written")
                )
            else:
                applied.append((diagnostic, fix))
        if options.diff:
            created = {p: t for p, t in planned.creates.items() if p not in broken}
            run.diff = "".join(
                unified_diff(p, files.get(p).text if p in files.files else "", t, _shown(p, shown_root))
                for p, t in sorted({**new_texts, **created}.items())
            )
            run.fixed = [Applied(d, f.description) for d, f in applied]
            return run
        failed: set[Path] = set()
        for file, text in sorted(new_texts.items()):
            outcome = write_atomically(files.get(file), text)
            if outcome.written:
                run.files_written.add(file)
            else:
                run.failures.append(outcome)
                failed.add(file)
        written = set(new_texts) - failed
        for file, text in sorted(planned.creates.items()):
            if file in broken or not any(file in fix.creates for _, fix in applied):
                continue
            outcome = create_exclusively(file, text)
            if outcome.written:
                run.files_written.add(file)
                written.add(file)
            else:
                run.failures.append(outcome)
                failed.add(file)
        for diagnostic, fix in applied:
            if any(p in failed for p in fix.paths):
                continue
            if all(p in broken or p in new_texts for p in fix.edits) or not fix.edits:
                run.fixed.append(Applied(diagnostic, fix.description))
        if failed or not written:
            result = verify(path, verify_options) if written else result
            break
        result = verify(path, verify_options)
    run.result = result
    # what is left unfixable is judged on the final result
    run.not_fixed = [(d, why) for d, why in run.not_fixed if d in result.diagnostics]
    run.unsafe_available = [d for d in run.unsafe_available if d in result.diagnostics]
    return run


def _shown(path: Path, root: Path) -> str:
    import os

    try:
        return Path(os.path.relpath(path, root)).as_posix()
    except ValueError:
        return str(path)


# --- --diff: every pass on a copy, so the diff is what `pkgforge fix` would write -----------------

COPY_LIMIT_FILES = 20000
COPY_LIMIT_BYTES = 512 * 1024 * 1024
SKIPPED = {".git", ".hg", ".svn", "__pycache__"}
ROOT_OUTPUTS = {"build", "install", "log"}


def _diff_on_a_copy(path: Path, options: FixOptions, shown_root: Path) -> FixRun | None:
    """Run the fix passes on a temporary copy of what verify reads; None when it is too large to copy
    (then --diff shows the first pass only)."""
    import shutil
    import tempfile

    from pkgforge.workspace import locate

    workspace = locate(path)
    root, base = workspace.root, workspace.base_path
    files, size = 0, 0
    limits: list[WalkLimit] = []
    for folder, dirs, names in walk(base, limits=limits):
        dirs[:] = [d for d in dirs if d not in SKIPPED and not (Path(folder) == root and d in ROOT_OUTPUTS)]
        files += len(names)
        size += sum((Path(folder) / n).lstat().st_size for n in names)
        if files > COPY_LIMIT_FILES or size > COPY_LIMIT_BYTES:
            return None
    if limits:  # a folder not walked (unreadable, too deep): its size is unknown
        return None
    with tempfile.TemporaryDirectory(prefix="pkgforge-fix-diff-") as temporary:
        copy_root = Path(temporary) / "ws"
        copy_base = copy_root / base.relative_to(root)

        def ignore(folder: str, names: list[str]) -> list[str]:
            return [n for n in names if n in SKIPPED or (Path(folder) == root and n in ROOT_OUTPUTS)]

        shutil.copytree(base, copy_base, symlinks=True, ignore=ignore)
        if (root / "pkgforge.toml").is_file() and not (copy_root / "pkgforge.toml").exists():
            shutil.copy2(root / "pkgforge.toml", copy_root / "pkgforge.toml")
        copy_path = copy_root / path.resolve().relative_to(root)
        writing = dataclasses.replace(options, diff=False)
        first: list[VerifyResult] = []

        def back(file: Path) -> Path:
            try:
                return root / Path(file).relative_to(copy_root)
            except ValueError:
                return Path(file)

        run = run_fix(copy_path, writing, shown_root=shown_root, _first=first, _original=back)

        out = FixRun(_remap(first[0], back), diff_mode=True, passes=run.passes)
        out.result.root = path.resolve()
        out.fixed = [Applied(_moved(a.diagnostic, back), a.description) for a in run.fixed]
        out.not_fixed = [(_moved(d, back), why) for d, why in run.not_fixed]
        out.unsafe_available = [_moved(d, back) for d in run.unsafe_available]
        out.failures = [Outcome(back(o.path), o.written, o.problem) for o in run.failures]
        diffs: list[str] = []
        for written in sorted(run.files_written):
            original = back(written)
            # a file the fix creates: its diff is from nothing
            before = original.read_bytes().decode("utf-8") if original.exists() else ""
            after = written.read_bytes().decode("utf-8")
            diffs.append(
                unified_diff(
                    original,
                    before.removeprefix("\ufeff"),
                    after.removeprefix("\ufeff"),
                    _shown(original, shown_root),
                )
            )
        out.diff = "".join(diffs)
        return out


def _moved(diagnostic: Diagnostic, back: Callable[[Path], Path]) -> Diagnostic:
    return dataclasses.replace(
        diagnostic, path=back(diagnostic.path), message=diagnostic.message, hint=diagnostic.hint
    )


def _remap(result: VerifyResult, back: Callable[[Path], Path]) -> VerifyResult:
    from pkgforge.diagnostics import PackageReport

    reports = []
    for report in result.reports:
        moved = PackageReport(
            report.name, back(report.path), report.build_type, [_moved(d, back) for d in report.diagnostics]
        )
        moved.launch_distro = report.launch_distro
        reports.append(moved)
    return VerifyResult(
        back(result.root), reports, result.checks_run, engine=result.engine, distro=result.distro
    )
