"""`pkgforge build`: a real colcon build (merged install) with the detected toolchain."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from pkgforge.build.toolchain import Toolchain, detect, prepend_path, require_cmake
from pkgforge.errors import BuildFailed, PkgforgeError
from pkgforge.workspace import Workspace, discover

if TYPE_CHECKING:
    from colcon_core.package_descriptor import PackageDescriptor  # untyped: Any to mypy

# Build tools and test-only packages never need a stub: ament_cmake is the
# toolchain itself, and tests are off unless asked for.
NEVER_STUBBED_PREFIXES = ("ament_cmake", "ament_lint")

LOG_TAIL_LINES = 40


@dataclass
class BuildOptions:
    build_base: Path
    install_base: Path
    log_base: Path
    build_tests: bool = False
    stub_missing: bool = True
    packages_select: tuple[str, ...] = ()
    cmake_args: tuple[str, ...] = ()
    parallel_workers: int | None = None
    continue_on_error: bool = (
        False  # build every package that can be built (verify --build reports each failure)
    )
    extra_env: dict[str, str] = field(default_factory=dict)


@dataclass
class BuildResult:
    install_base: Path
    packages: list[str]
    stubbed: list[str]


def default_options(
    workspace: Workspace, build_base: Path | None = None, install_base: Path | None = None
) -> BuildOptions:
    return BuildOptions(
        build_base=(build_base or workspace.root / "build").resolve(),
        install_base=(install_base or workspace.root / "install").resolve(),
        log_base=(workspace.root / "log").resolve(),
    )


def build_closure(descriptors: list[PackageDescriptor], selection: list[str]) -> list[PackageDescriptor]:
    """The selected packages and every workspace package they depend on (all when none selected)."""
    if not selection:
        return descriptors
    by_name = {d.name: d for d in descriptors}
    wanted: set[str] = set()
    todo = list(selection)
    while todo:
        name = todo.pop()
        if name in wanted or name not in by_name:
            continue
        wanted.add(name)
        for deps in by_name[name].dependencies.values():
            todo.extend(str(dep) for dep in deps)
    return [d for d in descriptors if d.name in wanted]


def missing_dependencies(
    descriptors: list[PackageDescriptor], toolchain: Toolchain, env: dict[str, str]
) -> list[str]:
    """Build dependencies of CMake packages that neither the workspace nor a prefix provides.

    find_package() on them would stop the configure step on a machine without
    ROS, although a description package uses nothing from them at build time.
    """
    in_workspace = {d.name for d in descriptors}
    missing: set[str] = set()
    for descriptor in descriptors:
        if not str(descriptor.type).endswith("cmake"):
            continue
        for name in sorted(
            {str(dep) for dep in descriptor.dependencies.get("build", set())} | _conditional(descriptor)
        ):
            if name in in_workspace or name.startswith(NEVER_STUBBED_PREFIXES):
                continue
            if not toolchain.find_cmake_config(name, env):
                missing.add(name)
    return sorted(missing)


def write_stub_prefix(prefix: Path, names: list[str]) -> None:
    """Empty CMake package configs, so find_package(<name> REQUIRED) succeeds."""
    for name in names:
        folder = prefix / "share" / name / "cmake"
        folder.mkdir(parents=True, exist_ok=True)
        (folder / f"{name}Config.cmake").write_text(
            f"# pkgforge stub: {name} is declared in package.xml but not installed here.\n"
            f"set({name}_FOUND TRUE)\n"
            f'set({name}_INCLUDE_DIRS "")\nset({name}_LIBRARIES "")\n'
        )


def colcon_command(
    workspace: Workspace,
    options: BuildOptions,
    selection: list[str],
    cmake_args: list[str],
    paths: list[str] | None = None,
) -> list[str]:
    """colcon build's command line; `paths`: the package folders to build from, instead of
    crawling the workspace (none of them with a shell wildcard, which colcon would expand)."""
    if paths is not None and any(set(p) & set("*?[") for p in paths):
        paths = None
    cmd = [
        sys.executable,
        "-m",
        "colcon",
        "--log-base",
        str(options.log_base),
        "build",
        "--merge-install",
        *(["--paths", *paths] if paths else ["--base-paths", str(workspace.base_path)]),
        "--build-base",
        str(options.build_base),
        "--install-base",
        str(options.install_base),
    ]
    if options.continue_on_error:
        cmd += ["--continue-on-error"]
    if options.parallel_workers:
        cmd += ["--parallel-workers", str(options.parallel_workers)]
    if selection:
        cmd += ["--packages-up-to", *selection]
    if cmake_args:
        # a lone `--cmake-args` list must not swallow later options: keep it last
        cmd += ["--cmake-args", *cmake_args]
    return cmd


def failed_packages(build_base: Path, names: list[str]) -> list[str]:
    """Packages whose colcon job ended non-zero (colcon-core writes build/<pkg>/colcon_build.rc)."""
    failed = []
    for name in names:
        try:
            rc = (build_base / name / "colcon_build.rc").read_text().strip()
        except OSError:
            continue
        if rc not in ("", "0"):
            failed.append(name)
    return failed


def log_tail(log_base: Path, package: str, lines: int = LOG_TAIL_LINES) -> str:
    log = log_base / "latest_build" / package / "stdout_stderr.log"
    try:
        text = log.read_text(errors="replace").splitlines()
    except OSError:
        return f"(no log at {log})"
    return "\n".join(text[-lines:])


# a log tail replaced by one located line: colcon could not run the package's setup.py
SETUP_PY_UNREADABLE = "pkgforge-setup-py: "
HINT_SEPARATOR = "; hint: "
# colcon's traceback when running setup.py to read an ament_python package's metadata failed
SETUP_PY_RUN = ("get_setup_information", "CalledProcessError")


def unreadable_setup_py(folder: Path | None, tail: str) -> str | None:
    """One line for a package whose setup.py colcon could not run to read its metadata (colcon's
    log then holds only colcon's own traceback; the file's error went to colcon's output): the
    file, and the first module it imports at its top that colcon's Python cannot find, where one
    is (read from its syntax tree, nothing of it run); None for any other failure."""
    if folder is None or not all(part in tail for part in SETUP_PY_RUN):
        return None
    import ast
    import importlib.util

    setup_py = folder / "setup.py"
    where, why = str(setup_py), "its error is in colcon's output above"
    try:
        tree = ast.parse(setup_py.read_text(encoding="utf-8", errors="replace"))
    except (OSError, SyntaxError, ValueError):
        tree = None
    for node in tree.body if tree is not None else []:
        names = (
            [a.name for a in node.names]
            if isinstance(node, ast.Import)
            else [node.module]
            if isinstance(node, ast.ImportFrom) and node.module and not node.level
            else []
        )
        missing = [n for n in names if importlib.util.find_spec(n.split(".")[0]) is None]
        if missing:
            where = f"{setup_py}:{node.lineno}"
            why = f"it imports {missing[0]}, which {sys.executable} cannot import"
            break
    return (
        f"{SETUP_PY_UNREADABLE}{where}: colcon could not run setup.py to read the package's metadata "
        f"({why}){HINT_SEPARATOR}install what it imports into that Python, or import it only inside "
        "the functions that need it"
    )


def _shown(line: str) -> str:
    """The line with its absolute path made relative to the current folder."""
    import os

    path, sep, rest = line.partition(": ")
    file, colon, number = path.rpartition(":") if path.rpartition(":")[2].isdigit() else (path, "", "")
    return f"{os.path.relpath(file)}{colon}{number}{sep}{rest}"


def _conditional(descriptor: PackageDescriptor) -> set[str]:
    """Build dependencies under a condition on a variable of the user's own build set-up
    ($HUSARION_ROS_BUILD_TYPE): colcon left them out, as the variable is unset here, but the
    CMakeLists.txt may still find_package() them (verify counts them as declared too)."""
    from pkgforge.model.manifest import load_manifest
    from pkgforge.model.source import read_source

    manifest = load_manifest(read_source(Path(descriptor.path) / "package.xml"))
    return {d.name for d in manifest.dependencies if d.condition} & manifest.build_dependencies()


def run_build(
    workspace: Workspace,
    options: BuildOptions,
    *,
    out: TextIO | None = None,
    colcon_output_to_stderr: bool = False,
    quiet_failures: bool = False,
) -> BuildResult:
    """Build with colcon; raise BuildFailed (exit 1) naming the failing packages.

    `colcon_output_to_stderr` keeps standard output free for a report (verify --build);
    `quiet_failures`: the caller reports the failing packages' log tails itself.
    """
    out = out or sys.stderr
    toolchain = detect()
    env = toolchain.environment()
    env.update(options.extra_env)
    require_cmake(env)
    unreadable: list[Path] = []
    descriptors = discover(workspace.base_path, unreadable=unreadable)
    if not descriptors:
        raise PkgforgeError(f"no package found under {workspace.base_path}")
    selection = list(options.packages_select)
    if workspace.package_path is not None and not selection:
        selection = [d.name for d in descriptors if Path(d.path).resolve() == workspace.package_path]

    stubbed: list[str] = []
    if options.stub_missing:
        stubbed = missing_dependencies(build_closure(descriptors, selection), toolchain, env)
        if stubbed:
            stub_prefix = options.build_base / "pkgforge_stubs"
            write_stub_prefix(stub_prefix, stubbed)
            env["CMAKE_PREFIX_PATH"] = prepend_path(str(stub_prefix), env.get("CMAKE_PREFIX_PATH", ""))
            print(
                f"pkgforge: not installed here, stubbed for find_package(): {', '.join(stubbed)} "
                "(use --no-stubs to fail instead)",
                file=out,
            )

    cmake_args = [
        f"-DBUILD_TESTING={'ON' if options.build_tests else 'OFF'}",
        f"-DPython3_EXECUTABLE={sys.executable}",
        *toolchain.cmake_generator_args(env),
        *options.cmake_args,
    ]
    # a setup.py colcon cannot run was said once (discover): colcon's own discovery would print
    # its traceback again, so colcon is given the packages found instead of the folder to crawl
    paths = [str(d.path) for d in descriptors] if unreadable else None
    cmd = colcon_command(workspace, options, selection, cmake_args, paths)
    names = selection or [d.name for d in descriptors]
    built = [d.name for d in build_closure(descriptors, selection)]  # with what they depend on
    # a stale rc from an earlier run must not name a package that now passes
    for name in built:
        (options.build_base / name / "colcon_build.rc").unlink(missing_ok=True)
    out.flush()
    try:
        completed = subprocess.run(
            cmd,
            cwd=workspace.root,
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=sys.stderr if colcon_output_to_stderr else None,
        )
    except OSError as exc:
        raise PkgforgeError(f"cannot run colcon: {exc}") from exc
    if completed.returncode != 0:
        failed = failed_packages(options.build_base, built)
        if not failed:
            raise BuildFailed(
                f"colcon exited with {completed.returncode}; see its output above",
                status=completed.returncode,
            )
        folders = {d.name: Path(d.path) for d in descriptors}
        failures = [
            (
                package,
                options.log_base / "latest_build" / package / "stdout_stderr.log",
                unreadable_setup_py(folders.get(package), log_tail(options.log_base, package))
                or log_tail(options.log_base, package),
            )
            for package in failed
        ]
        if not quiet_failures:
            for package, log, tail in failures:
                if tail.startswith(SETUP_PY_UNREADABLE):
                    said = _shown(tail.removeprefix(SETUP_PY_UNREADABLE)).replace(HINT_SEPARATOR, ": ")
                    print(f"\npkgforge: {said}", file=out)
                    continue
                print(f"\npkgforge: package '{package}' failed; last lines of its log ({log}):", file=out)
                print(tail, file=out)
        raise BuildFailed(
            f"build failed: {', '.join(failed)} "
            "(`pkgforge verify` points at the file and line of most such problems)",
            failures,
            completed.returncode,
        )
    return BuildResult(options.install_base, names, stubbed)
