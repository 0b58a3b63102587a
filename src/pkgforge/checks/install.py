"""Checks of the build files' install rules against the package's folders."""

from __future__ import annotations

import os
from collections.abc import Collection, Iterator
from pathlib import Path
from typing import Any

from pkgforge.checks.context import CheckContext
from pkgforge.checks.facts import FileFacts
from pkgforge.checks.files import read_problem_hint
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Severity
from pkgforge.model.package import RESOURCE_FOLDERS, PackageModel
from pkgforge.model.references import Reference

RESOURCE_SUFFIXES = (
    ".urdf",
    ".xacro",
    ".rviz",
    ".stl",
    ".dae",
    ".obj",
    ".sdf",
    ".world",
    ".launch.py",
    ".launch.xml",
    ".launch.yaml",
)


def _place_in_package(path: Path, line: int | None, model: PackageModel) -> str:
    """`path:line` as a message shows it: relative to the package folder when inside it."""
    try:
        shown = path.relative_to(model.path)
    except ValueError:
        shown = path
    return f"{shown}:{line}" if line else str(shown)


def linked_folder(files: FileFacts, model: PackageModel, relative: str) -> tuple[str, str, bool] | None:
    """(folder, link target, target exists) for the first symbolic link on the way to `relative` in
    the package's source; None when no link is on the way. pkgforge's tree, like CMake's
    install(DIRECTORY), installs a link as the link itself, not what it points to."""
    path = model.path
    parts = relative.split("/")
    for index, part in enumerate(parts[:-1]):
        path = path / part
        if files.is_link(path):
            target = files.link_target(path)
            if target is None:
                return None
            return "/".join(parts[: index + 1]), target, files.exists(path)
        if not files.is_dir(path):
            return None
    return None


def link_hint(files: FileFacts, model: PackageModel, relative: str) -> tuple[str, str] | None:
    """(what is wrong, the fix) when a symbolic link stands between the package and `relative`."""
    found = linked_folder(files, model, relative)
    if found is None:
        return None
    folder, target, exists = found
    if not exists:
        return (
            f"{folder} is a symbolic link to {target}, which does not exist",
            f"restore {target} (git keeps the link, not what it points to; was it committed?) or "
            f"replace the link {folder} by the folder itself",
        )
    return (
        f"{folder} is a symbolic link to {target}: the install keeps the link, so the file is found "
        f"only if {target} is installed too",
        f"replace the link {folder} by the folder itself, or install what it points to at the same "
        "relative place",
    )


def install_fix(model: PackageModel, folder: str, file: str | None = None) -> str:
    """How to install `folder` (for `file` in it, when known): extend the existing rule, or add one."""
    rules = model.layout.directory_rules
    share = f"share/{model.share_name}"
    if model.setup_py is not None:
        for entry in model.layout.destinations:
            if entry.destination == f"{share}/{folder}":
                # an entry for the folder exists: its file list (a glob) misses the file
                name = Path(file).name if file else f"the files of {folder}/"
                return (
                    f"the data_files entry at {_place_in_package(entry.path, entry.line, model)} installs into "
                    f"{share}/{folder} but does not list {name}: glob() is case-sensitive and matches "
                    f"only what its pattern names (*.STL is not *.stl); use glob('{folder}/*') or fix "
                    "the pattern"
                )
        line = next((line for _, line, _, _ in rules), None)
        where = f"setup.py:{line}" if line else "setup.py"
        return (
            f"add (os.path.join('share', package_name, '{folder}'), glob('{folder}/*')) "
            f"to data_files in {where}"
        )
    for path, line, folders, destination in rules:
        if f"{folder}/" in folders:
            into = destination or "the install prefix"
            return (
                f"'{folder}/' with a trailing slash installs the folder's contents into {into}/, "
                f"not into {into}/{folder}/: write {folder} without the slash in "
                f"install(DIRECTORY ...) at {_place_in_package(path, line, model)}"
            )
    for path, line, folders, destination in rules:
        if destination == share:
            return f"add {folder} to install(DIRECTORY {' '.join(folders)} ...) at {_place_in_package(path, line, model)}"
    return f"add install(DIRECTORY {folder} DESTINATION share/${{PROJECT_NAME}}) to CMakeLists.txt"


def install_fix_data(model: PackageModel, folder: str) -> dict[str, Any]:
    """What `pkgforge fix` needs to install `folder` of `model`."""
    return {"install_folder": folder, "package_path": str(model.path)}


@register(
    "PF201",
    "install-missing-directory",
    "error",
    area="install",
    fix="unsafe",
    bad=(
        "# CMakeLists.txt (the package has no worlds/)\n"
        "install(DIRECTORY launch urdf worlds DESTINATION share/${PROJECT_NAME})"
    ),
    good=("# CMakeLists.txt\ninstall(DIRECTORY launch urdf DESTINATION share/${PROJECT_NAME})"),
    summary="an install rule names a source folder that does not exist",
    explanation="CMake stops at install time with 'file INSTALL cannot find': your package's "
    "build fails (an install rule copied from a tutorial often lists worlds/ and models/ your "
    "package does not have).",
    hint="create the folder or remove it from the install rule",
)
def install_missing_directory(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    for missing in model.layout.missing:
        if missing.mode != "DIRECTORY":
            continue
        yield Finding(
            f"install(DIRECTORY) names '{missing.text}', which does not exist in {model.name}",
            missing.path,
            missing.line,
            missing.column,
            hint=f"remove '{missing.text}' from the install rule at "
            f"{_place_in_package(missing.path, missing.line, model)}, or create {missing.text}/ "
            "with a file in it (git keeps no empty folder)",
            fix={"folder": missing.text},
        )


@register(
    "PF207",
    "install-missing-file",
    "error",
    area="install",
    bad=(
        "# CMakeLists.txt (there is no README.txt)\n"
        "install(FILES README.txt DESTINATION share/${PROJECT_NAME})"
    ),
    good=("# CMakeLists.txt\ninstall(FILES README.md DESTINATION share/${PROJECT_NAME})"),
    summary="an install rule or data_files entry names a file that does not exist",
    explanation="The build stops at install time (CMake) or setuptools fails on the "
    "missing file or on a folder listed as a file.",
    hint="fix the path or remove it",
)
def install_missing_file(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    for missing in model.layout.missing:
        if missing.mode == "DIRECTORY":
            continue
        what = "data_files" if missing.mode == "data_files" else f"install({missing.mode})"
        yield Finding(
            f"{what} names '{missing.text}', which is not a file in {model.name}",
            missing.path,
            missing.line,
            missing.column,
        )


@register(
    "PF202",
    "directory-not-installed",
    "warning",
    area="install",
    fix="safe",
    bad=(
        "# CMakeLists.txt (rviz/display.rviz is used by launch/display.launch.py)\n"
        "install(DIRECTORY launch urdf DESTINATION share/${PROJECT_NAME})"
    ),
    good=("# CMakeLists.txt\ninstall(DIRECTORY launch rviz urdf DESTINATION share/${PROJECT_NAME})"),
    summary="a folder of run-time resources is covered by no install rule",
    explanation="Launch files resolve paths in install/share/<pkg>/, not in src/: a folder "
    "left out of the install rules is simply absent at run time, with no error "
    "(rviz/ not installed: RViz starts with no config). An error "
    "when a file of the package refers to the folder, a warning otherwise.",
    hint="install the folder to share/${PROJECT_NAME}",
)
def directory_not_installed(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    if not model.layout.known or model.layout.unknown:
        return  # a rule pkgforge cannot read may install the folder
    # a launch file that resolves into the folder reports it, at its own line (uninstalled-reference)
    covered_by_launch = ctx.folders_reported_uninstalled()
    installed = model.layout.installed_sources()
    own_names = {model.name, model.share_name}
    referenced = _referenced_folders(model, installed, own_names)
    for folder, files in sorted(model.top_level_folders().items()):
        if folder not in RESOURCE_FOLDERS and folder not in referenced:
            continue
        if any(model.path / f in installed for f in files) or folder in covered_by_launch:
            continue
        reference = referenced.get(folder)
        if reference is not None:
            message = (
                f"{folder}/ is not installed, but {_place_in_package(reference.path, reference.line, model)} "
                f"refers to {reference.relative}"
            )
            severity = Severity.ERROR
        else:
            message = f"{folder}/ holds {len(files)} file(s) but no install rule covers it"
            severity = None
        yield Finding(
            message,
            model.path / folder,
            None,
            hint=install_fix(model, folder),
            severity=severity,
            fix=install_fix_data(model, folder),
        )


def _referenced_folders(
    model: PackageModel, installed: Collection[Path], own_names: Collection[str]
) -> dict[str, Reference]:
    """Top-level folder → the first reference into it from a file that is used at run time: an
    installed file, a file outside any folder, or a file of a folder so referenced. A folder that
    only its own (or another uninstalled folder's) files refer to is not needed at run time: a
    xacro source folder kept next to the URDF generated from it."""

    def folder_of(path: Path) -> str | None:
        try:
            parts = Path(path).relative_to(model.path).parts
        except ValueError:
            return None
        return parts[0] if len(parts) > 1 else None

    own = [r for r in model.references if r.package in own_names and r.relative]
    referenced: dict[str, Reference] = {}
    changed = True
    while changed:
        changed = False
        for reference in own:
            target = (reference.relative or "").split("/")[0]
            source = folder_of(reference.path)
            used = reference.path in installed or source is None or source in referenced
            if used and target not in referenced and target != source:
                referenced[target] = reference
                changed = True
    return referenced


@register(
    "PF203",
    "install-wrong-destination",
    "error",
    area="install",
    bad=("# CMakeLists.txt\ninstall(DIRECTORY urdf DESTINATION share)"),
    good=("# CMakeLists.txt\ninstall(DIRECTORY urdf DESTINATION share/${PROJECT_NAME})"),
    summary="resources are installed outside share/<package>",
    explanation="FindPackageShare, $(find pkg) and package:// all resolve to "
    "share/<package>/; resources installed elsewhere are never found.",
    hint="use DESTINATION share/${PROJECT_NAME}",
)
def install_wrong_destination(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    share = f"share/{model.share_name}"
    # what another rule installs under share/<package> as well is found there: a copy in a
    # folder of its own beside it is no mistake (doosan's common2 installs bin/DRCF/config beside
    # its emulator in bin/common2, and its whole bin/ folder under share/common2); one in share/
    # itself is (it lands among every package's folders)
    in_share = [
        str(f.source)
        for d, f in model.layout.files.items()
        if d.startswith(share + "/") and f.source is not None
    ]

    def also_in_share(source: str) -> bool:
        where = str(model.path / source.rstrip("/"))
        return any(s == where or s.startswith(where + os.sep) for s in in_share)

    for rule in model.layout.destinations:
        resources = [
            s
            for s in rule.sources
            if (
                Path(s.rstrip("/")).name in RESOURCE_FOLDERS
                or s.endswith(RESOURCE_SUFFIXES)
                or (Path(s).parts and Path(s).parts[0] in RESOURCE_FOLDERS)
            )
            and not (
                rule.destination is not None
                and rule.destination.split("/")[0] != "share"
                and also_in_share(s)
            )
        ]
        if not resources:
            continue
        destination = rule.destination
        if destination is not None and (destination == share or destination.startswith(share + "/")):
            continue
        where = "outside the install prefix" if destination is None else f"to {destination}/"
        yield Finding(
            f"{', '.join(resources)} installed {where}, not under {share}/",
            rule.path,
            rule.line,
            rule.column,
            hint="use DESTINATION share/${PROJECT_NAME}"
            if model.setup_py is None
            else "use os.path.join('share', package_name, ...) as the destination",
        )


@register(
    "PF204",
    "cmake-invalid",
    "error",
    area="install",
    bad=("# CMakeLists.txt\ncmake_minimum_required(VERSION 3.8)\nfind_package(ament_cmake REQUIRED"),
    good=(
        "# CMakeLists.txt\n"
        "cmake_minimum_required(VERSION 3.8)\n"
        "project(rob_description NONE)\n"
        "find_package(ament_cmake REQUIRED)"
    ),
    summary="CMakeLists.txt cannot be read, or has no project()",
    explanation="CMake stops at configure time; pkgforge cannot predict the install tree either.",
    hint="fix the syntax at the named line",
)
def cmake_invalid(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    cmake = model.cmake
    if cmake is None:
        return
    for error in cmake.syntax_errors:
        yield Finding(f"CMake syntax: {error.message}", error.path, error.line, error.column)
    for source in cmake.unreadable:
        yield Finding(
            f"{source.path.name}: {source.problem}",
            source.path,
            source.problem_line,
            hint=read_problem_hint(source.problem),
        )
    if not cmake.syntax_errors and not cmake.unreadable and cmake.project_command is None:
        yield Finding(
            "CMakeLists.txt has no project() call",
            model.path / "CMakeLists.txt",
            1,
            hint=f"add cmake_minimum_required(VERSION 3.10) and project({model.name} NONE)",
        )


@register(
    "PF205",
    "ament-package-missing",
    "error",
    area="install",
    bad=("# CMakeLists.txt\ninstall(DIRECTORY urdf DESTINATION share/${PROJECT_NAME})"),
    good=("# CMakeLists.txt\ninstall(DIRECTORY urdf DESTINATION share/${PROJECT_NAME})\nament_package()"),
    summary="an ament_cmake package never calls ament_package()",
    explanation="ament_package() installs package.xml and the ament index marker; without "
    "them FindPackageShare, get_package_share_directory and `ros2 launch` "
    "cannot find the package at all.",
    hint="call ament_package() at the end of CMakeLists.txt",
)
def ament_package_missing(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    cmake = model.cmake
    if cmake is None or model.build_type != "ament_cmake" or cmake.syntax_errors or cmake.unreadable:
        return
    if cmake.ament_package_command is None:
        yield Finding(
            "CMakeLists.txt never calls ament_package(): the package is not registered in the ament index",
            model.path / "CMakeLists.txt",
            None,
        )


@register(
    "PF206",
    "install-rule-unevaluated",
    "info",
    area="install",
    bad=("# CMakeLists.txt\ninstall(DIRECTORY $ENV{MODEL_DIR} DESTINATION share/${PROJECT_NAME})"),
    good=("# CMakeLists.txt\ninstall(DIRECTORY urdf DESTINATION share/${PROJECT_NAME})"),
    summary="pkgforge cannot tell what an install rule installs",
    explanation="The rule depends on something pkgforge does not evaluate (an environment "
    "variable, a variable set outside the package, a call it does not model). A setup.py whose "
    "data_files are computed is run as colcon runs it (setuptools' setup(), stopped before any "
    "command, in the sandbox: it may write nothing); this says where that run failed. What the "
    "package installs is then unknown: its files are not in the predicted tree, other packages' "
    "lookups into it are not checked (unpredicted-lookup), and its own launch files and models "
    "are evaluated against its source. Verify with --build or --install-base to check the real tree.",
    hint="use literal paths, or verify against a real build (--build)",
)
def install_rule_unevaluated(ctx: CheckContext) -> Iterator[Finding]:
    setup_py = ctx.model.setup_py
    unknown = ctx.model.layout.unknown
    if setup_py is not None and setup_py.evaluation_error is not None:
        line, why = setup_py.evaluation_error
    else:
        line, why = None, None
    # One cause, one finding: where the text's own reading already said why a rule is
    # unpredictable at that very line (a function that calls itself), the run that then
    # failed there says nothing more.
    if (
        setup_py is not None
        and why is not None
        and not any(path == setup_py.source.path and at == line for path, at, _ in unknown)
    ):
        yield Finding(
            f"setup.py could not be evaluated here ({why}); its computed install rules are not predicted",
            setup_py.source.path,
            line or setup_py.data_files_line or setup_py.setup_line,
            hint="make setup.py run without what this machine lacks (or without writing files), or "
            "verify against a real build (--build)",
        )
    for path, at, reason in unknown:
        yield Finding(f"cannot predict this install rule: {reason}", path, at)


@register(
    "PF208",
    "setup-py-invalid",
    "error",
    area="install",
    bad=("# setup.py\nfrom setuptools import setup\nsetup(name='rob_description',"),
    good=("# setup.py\nfrom setuptools import setup\nsetup(name='rob_description')"),
    summary="setup.py cannot be parsed, or calls no setup()",
    explanation="colcon builds ament_python packages by running setup.py.",
    hint="fix setup.py at the named line",
)
def setup_py_invalid(ctx: CheckContext) -> Iterator[Finding]:
    setup_py = ctx.model.setup_py
    if setup_py is None:
        return
    if setup_py.syntax_error is not None:
        line, message = setup_py.syntax_error
        yield Finding(f"setup.py: {message}", setup_py.source.path, line)
    elif not setup_py.has_setup_call:
        yield Finding("setup.py never calls setup()", setup_py.source.path, 1)


@register(
    "PF209",
    "package-not-installed",
    "error",
    area="install",
    bad=(
        "$ colcon build            # rob_description fails to build\n"
        "$ pkgforge verify . --install-base install"
    ),
    good=(
        "$ colcon build            # fixed: every package builds\n$ pkgforge verify . --install-base install"
    ),
    summary="--install-base: a verified package is missing from the install base",
    explanation="colcon installs a package only when its build succeeds: a package absent "
    "from the install base most often failed to build (or was skipped), and "
    "nothing of it can be checked against the real tree.",
    hint="look at colcon's log (log/latest_build/<package>/stdout_stderr.log), fix the build, "
    "and build again",
)
def package_not_installed(ctx: CheckContext) -> Iterator[Finding]:
    if ctx.install_base is None:
        return
    model = ctx.model
    installed = ctx.install_base_packages()
    if model.share_name not in installed and model.name not in installed:
        yield Finding(
            f"{model.name} is not in the install base {ctx.install_base}: its build failed or "
            f"it was not built",
            model.manifest.path,
            model.manifest.name_line,
            hint=f"look at colcon's log (log/latest_build/{model.name}/stdout_stderr.log), fix "
            f"the build, and run colcon build again",
        )
