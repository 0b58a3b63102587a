"""Checks of package.xml and of the names a package goes by."""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, NamedTuple

from pkgforge.checks.context import CheckContext, only_with
from pkgforge.checks.files import read_problem_hint
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Group, Severity
from pkgforge.model.cmake_syntax import Command
from pkgforge.model.exports import brought_by
from pkgforge.model.manifest import DEPENDENCY_TAGS, GENERIC_OVERLAPS, RUN_TAGS, Dependency
from pkgforge.model.names import REP144_RULE, rep144_advice, rep144_problem
from pkgforge.model.references import launch_kind

# Used by a package without being named in any file it ships.
# a package every package with these launch kinds (py, xml, yaml) or files uses without naming it
IMPLICIT_USES: dict[str, Callable[[set[str | None], list[Path]], bool]] = {
    "launch_xml": lambda kinds, files: "xml" in kinds,
    "launch_yaml": lambda kinds, files: "yaml" in kinds,
    "launch": lambda kinds, files: bool(kinds),
    "launch_ros": lambda kinds, files: bool(kinds),
    "ros2launch": lambda kinds, files: bool(kinds),
    "xacro": lambda kinds, files: any(f.name.endswith(".xacro") for f in files),
}


@register(
    "PF101",
    "manifest-invalid",
    "error",
    area="manifest",
    bad=(
        '<!-- package.xml -->\n<package format="3">\n  <name>rob_description</name>\n  <version>0.1</version>'
    ),
    good=(
        "<!-- package.xml -->\n"
        '<package format="3">\n'
        "  <name>rob_description</name>\n"
        "  <version>0.1.0</version>"
    ),
    summary="package.xml cannot be read, or is not a valid format 2/3 manifest",
    explanation="colcon, rosdep and ament read package.xml first; a manifest they reject "
    "means the package is skipped or fails before anything is built.",
    hint="fix the element named in the message (REP 149 lists what a manifest needs)",
)
def manifest_invalid(ctx: CheckContext) -> Iterator[Finding]:
    manifest = ctx.model.manifest
    for message, line in manifest.problems:
        yield Finding(message, manifest.path, line, hint=read_problem_hint(message))
    if not manifest.problems and manifest.format is not None and manifest.format < 2:
        yield Finding(
            f"package.xml uses format {manifest.format}; ROS 2 tools expect format 2 or 3",
            manifest.path,
            manifest.root_line,
            hint='use <package format="3"> and the format 3 dependency tags',
        )


@register(
    "PF102",
    "package-name-invalid",
    "error",
    area="manifest",
    bad=("<!-- package.xml -->\n<name>Rob-Description</name>"),
    good=("<!-- package.xml -->\n<name>rob_description</name>"),
    summary="the package name breaks REP 144",
    explanation="ROS 2 tools and the build farm refuse names outside REP 144; "
    "some accept them locally and fail later. A trailing '_' is a warning: REP 144's rules do "
    "not forbid it and catkin_pkg and colcon take it (`pkgforge new` still refuses it).",
    hint=REP144_RULE,
)
def package_name_invalid(ctx: CheckContext) -> Iterator[Finding]:
    manifest = ctx.model.manifest
    if manifest.name is None:
        return
    problem = rep144_problem(manifest.name)
    if problem:
        yield Finding(f"invalid package name: {problem}", manifest.path, manifest.name_line)
    elif advice := rep144_advice(manifest.name):
        yield Finding(
            f"package name: {advice}, which REP 144 means as a separator between words",
            manifest.path,
            manifest.name_line,
            severity=Severity.WARNING,
        )


@register(
    "PF103",
    "project-name-mismatch",
    "error",
    area="manifest",
    fix="safe",
    bad=("# CMakeLists.txt (package.xml: <name>rob_description</name>)\nproject(robot_description NONE)"),
    good=("# CMakeLists.txt\nproject(rob_description NONE)"),
    summary="CMake project() differs from package.xml <name>",
    explanation="ament installs to share/${PROJECT_NAME} and registers that name in the "
    "ament index, while every tool looks the package up by its package.xml "
    "name: FindPackageShare and `ros2 launch` find nothing of your package.",
    hint="make project() and package.xml <name> the same",
)
def project_name_mismatch(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    cmake = model.cmake
    if cmake is None or cmake.project_command is None or not isinstance(cmake.project_name, str):
        return
    if model.manifest.name and cmake.project_name != model.manifest.name:
        command = cmake.project_command
        yield Finding(
            f"project({cmake.project_name}) but package.xml names the package '{model.manifest.name}'",
            command.path,
            command.line,
            command.column,
            hint=f"write project({model.manifest.name} ...): package.xml <name> decides the package name",
            fix={"name": model.manifest.name},
        )


@register(
    "PF104",
    "folder-name-mismatch",
    "info",
    area="manifest",
    bad="# folder src/rob_description/, package.xml: <name>robot_description</name>",
    good="# folder src/robot_description/, package.xml: <name>robot_description</name>",
    summary="the package folder's name differs from package.xml <name>",
    explanation="Nothing breaks by itself (many repositories name folders differently on "
    "purpose); it matters only when a file uses the folder name as a package "
    "name in FindPackageShare or package:// URIs, which resolve by the package "
    "name, and unknown-package reports that use (a folder rob_description holding the "
    "package robot_description). A package at the root of its git repository "
    "is not reported: its folder is named by whoever cloned it (the repository's name).",
    hint="rename the folder, or rename the package everywhere",
)
def folder_name_mismatch(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    name = model.manifest.name
    if not name or model.path.name == name or ctx.files.exists(model.path / ".git"):
        return  # (.git: a repository's clone, its folder named as the clone was)
    hint = f"rename the folder to '{name}'"
    if rep144_problem(model.path.name) is None:  # never a name package.xml cannot hold (Owner+Repo)
        hint += f", or the package to '{model.path.name}' in package.xml, project() and every reference"
    yield Finding(
        f"folder '{model.path.name}' holds package '{name}': references must use '{name}'",
        model.manifest.path,
        model.manifest.name_line,
        hint=hint,
    )


@register(
    "PF105",
    "build-type-missing",
    "error",
    area="manifest",
    bad=("<!-- package.xml -->\n<export>\n</export>"),
    good=("<!-- package.xml -->\n<export>\n  <build_type>ament_cmake</build_type>\n</export>"),
    summary="package.xml has no <export><build_type>",
    explanation="Without it colcon takes the package for a catkin (ROS 1) package, "
    "which a ROS 2 workspace cannot build.",
    hint="add <export><build_type>ament_cmake</build_type></export>",
)
def build_type_missing(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    manifest = model.manifest
    if manifest.name is None or manifest.problems or manifest.build_type:
        return
    build_type = (
        "ament_python" if ctx.files.exists(model.path / "setup.py") and model.cmake is None else "ament_cmake"
    )
    yield Finding(
        "package.xml declares no build type; colcon will treat the package as catkin",
        manifest.path,
        manifest.export_line or manifest.root_line,
        hint=f"add <export><build_type>{build_type}</build_type></export> to package.xml",
    )


@register(
    "PF106",
    "duplicate-dependency",
    "warning",
    area="manifest",
    bad=("<!-- package.xml -->\n<depend>xacro</depend>\n<exec_depend>xacro</exec_depend>"),
    good=("<!-- package.xml -->\n<exec_depend>xacro</exec_depend>"),
    fix="safe",
    summary="a dependency is declared twice",
    explanation="An exact repeat is noise; <depend> beside <build_depend>, "
    "<build_export_depend> or <exec_depend> of the same package makes "
    "catkin_pkg reject the manifest, and colcon then skips the package. Declarations under different "
    "conditions are not repeats (only one holds where they exclude each other). The fix deletes the repeat "
    "(or the tag <depend> covers), unless the two declarations' conditions differ.",
    hint="keep one declaration",
)
def duplicate_dependency(ctx: CheckContext) -> Iterator[Finding]:
    manifest = ctx.model.manifest
    # by name and condition: catkin_pkg tells declarations apart by their conditions too, so
    # <test_depend condition="$ROS_VERSION == 2">x</...> beside one for $ROS_VERSION == 1 is no repeat
    seen: dict[tuple[str, str], list[Dependency]] = {}
    for dependency in manifest.dependencies:
        seen.setdefault((dependency.name, " ".join((dependency.condition or "").split())), []).append(
            dependency
        )
    for (name, _), declarations in seen.items():
        tags = [d.tag for d in declarations]
        if "depend" in tags and any(t in GENERIC_OVERLAPS for t in tags):
            specific = next(d for d in declarations if d.tag in GENERIC_OVERLAPS)
            yield Finding(
                f"<depend>{name}</depend> already covers <{specific.tag}>{name}</{specific.tag}>; "
                "catkin_pkg rejects this manifest",
                manifest.path,
                specific.line,
                severity=Severity.ERROR,
                hint=f"delete <{specific.tag}>{name}</{specific.tag}> "
                f"(line {specific.line}): <depend> includes it",
                fix=_repeat_fix(specific, next(d for d in declarations if d.tag == "depend")),
            )
            continue
        for index, dependency in enumerate(declarations):
            if dependency.tag in tags[:index]:
                first = declarations[tags.index(dependency.tag)]
                yield Finding(
                    f"<{dependency.tag}>{name}</{dependency.tag}> is declared again "
                    f"(first at line {first.line})",
                    manifest.path,
                    dependency.line,
                    hint=f"delete the repeat at line {dependency.line}",
                    fix=_repeat_fix(dependency, first),
                    group=Group(
                        "again",
                        f"<{dependency.tag}>{name}</{dependency.tag}> (first at line {first.line})",
                        "{count} dependencies are declared again: {items}",
                    ),
                )


def _repeat_fix(repeat: Dependency, kept: Dependency) -> dict[str, Any] | None:
    """The fix data that deletes `repeat`, which `kept` declares already (under the same condition:
    realsense2_camera repeats sensor_msgs_py so); None if their conditions differ after all."""
    if (repeat.condition or "").split() != (kept.condition or "").split():
        return None
    return {"tag": repeat.tag, "dependency": repeat.name, "line": repeat.line}


# imports whose rosdep key is not python3-<module>
PYTHON_KEYS = {
    "cv2": "python3-opencv",
    "PIL": "python3-pil",
    "serial": "python3-serial",
    "usb": "python3-usb",
}


@register(
    "PF107",
    "unused-exec-depend",
    "info",
    area="manifest",
    bad=("<!-- package.xml (nothing in the package uses tf2_ros) -->\n<exec_depend>tf2_ros</exec_depend>"),
    good=("<!-- package.xml -->\n<!-- the exec_depend removed -->"),
    summary="an exec_depend that nothing in the package uses",
    explanation="A run-time dependency no launch file, model, RViz config, ros2_control or "
    "plugin YAML, <plugin> element or Python module of the package names is "
    "usually left over from a tutorial; it costs installs on every machine that "
    "deploys the package. Metapackages are exempt, and so is a dependency that brings along "
    "a package the package uses without declaring it (moveit brings moveit_ros_move_group): "
    "removing it would leave that use uninstalled.",
    hint="remove it if nothing needs it at run time",
)
def unused_exec_depend(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    if model.manifest.metapackage or not model.top_level_folders().keys() - {"resource"}:
        return  # a metapackage (tagged, or nothing but its manifest): its dependencies are its content
    # launch, models, RViz displays, ros2_control and Gazebo plugins, controller types in YAML,
    # the imports of the package's own Python modules
    used = {r.package for r in model.references}
    # an import of a Python library is a use of its rosdep key (import yaml: python3-yaml)
    for module in {r.package for r in model.references if r.via == "import"}:
        used |= {f"python3-{module.lower()}", f"python3-{module.lower().replace('_', '-')}"}
        used |= {key for key in [PYTHON_KEYS.get(module)] if key}
    if model.cmake is not None:
        used |= {name for name, _ in model.cmake.find_packages}
        if model.cmake.auto_find_command is not None:  # ament_auto_find_build_dependencies()
            used |= model.manifest.build_dependencies()
    kinds = {launch_kind(f) for f in model.files} - {None}
    for name, rule in IMPLICIT_USES.items():
        if rule(kinds, model.files):
            used.add(name)
    # what evaluation saw the launch files use (Node(package=VIEWER), VIEWER from a helper module)
    used |= {item.name for resolution in ctx.resolutions for item in resolution.packages}
    if "rviz_default_plugins" in used or "rviz_common" in used:
        used |= {"rviz_common", "rviz_default_plugins"}
    # a use the package leaves undeclared, which a declared package brings along (moveit brings
    # moveit_ros_move_group): that declaration is what installs it (missing-exec-depend names it)
    from pkgforge.checks.launch_depends import LAUNCH_INFRASTRUCTURE

    unused = [
        dependency
        for dependency in model.manifest.active_dependencies()
        if dependency.tag in RUN_TAGS
        and dependency.tag != "depend"
        and dependency.name not in used
        and _not_in_distro(ctx, dependency.name, declared=True, tag=dependency.tag)
        is None  # that one says it
    ]
    undeclared = (used & ctx.real_packages()) - model.manifest.declared() - LAUNCH_INFRASTRUCTURE
    undeclared -= {model.name, model.share_name}
    if unused and undeclared:  # (the workspace's exports read only then: every manifest parsed)
        # (brought by a dependency the package uses itself: that one installs it; rviz2 brings the
        # RViz displays, urdf_tutorial does too, and is still unused)
        workspace = ctx.workspace_exports()
        directly = sorted(used & model.manifest.declared())
        undeclared = {u for u in undeclared if brought_by(u, directly, ctx.distros, workspace) is None}
        unused = [
            d
            for d in unused
            if not any(brought_by(u, [d.name], ctx.distros, workspace) == d.name for u in sorted(undeclared))
        ]
    for dependency in unused:
        yield Finding(
            f"nothing in {model.name} uses exec_depend '{dependency.name}'",
            model.manifest.path,
            dependency.line,
            group=Group(
                "unused", dependency.name, f"nothing in {model.name} uses {{count}} exec_depends: {{items}}"
            ),
        )


def _library(name: str) -> str:
    """A system library's name as a rosdep key or a CMake package names it, for comparing the
    two: lower case, no lib prefix, no -dev suffix, no python3- prefix, no digits or separators."""
    text = name.lower().removeprefix("python3-").removesuffix("-dev")
    text = text.removeprefix("lib") if len(text) > 4 else text
    return re.sub(r"[^a-z]", "", text)


# names the ROS 1 → ROS 2 table renames that are also rosdep keys of a system package on some
# distros' platforms: the distros where they resolve, and what they are
SYSTEM_KEYS = {"gazebo": (("humble",), "Gazebo Classic, packaged for Ubuntu jammy")}

# what a build installs first (a find_package inside BUILD_TESTING: test_depend too)
BUILD_TAGS = ("depend", "build_depend", "buildtool_depend")

# first words too common to tie a package to a repository (ros2_control holds no ros_x_driver)
GENERIC_WORDS = frozenset({"ros", "ros2", "robot", "gazebo", "gz", "ign", "moveit", "nav2", "urdf", "common"})


def _first_word(name: str) -> str:
    return re.split(r"[_-]", name, maxsplit=1)[0]


def _from_a_repository(ctx: CheckContext, name: str) -> bool:
    """Whether a repository the workspace's .repos files import plausibly holds `name`: its first
    word is the package's (c3pzero.repos imports piper_ros2, which holds piper_description;
    `rosdep install --ignore-src` skips a package imported from source)."""
    word = _first_word(name)
    if len(word) < 3 or word in GENERIC_WORDS:
        return False
    return any(_first_word(repository) == word for repository in ctx.source_repositories())


class DistroProblem(NamedTuple):
    message: str
    hint: str
    severity: Severity | None = None  # None: the check's own (error)


def _not_in_distro(
    ctx: CheckContext, name: str, *, declared: bool, tag: str | None = None
) -> DistroProblem | None:
    """What is wrong when `name` is not released for the target distros (None: nothing): `tag`,
    the declaration's (a doc_depend is no key `rosdep install` looks up by default)."""
    from pkgforge.model.distro_data import load, replacement, rosdep_keys

    data = load()
    released = data.released_in(name)
    better = replacement(name)
    if released:
        missing = [d for d in ctx.distros if d not in released]
        if not missing:
            return None
        message = f"'{name}' is not released for {', '.join(missing)} (released for {', '.join(released)})"
        if better is not None and all(data.released(better[0], d) for d in missing):
            hint = f"use {better[0]} instead: {better[1]}"
        else:
            hint = (
                f"build {name} from source in the workspace, or target "
                f"{' or '.join(released)} (--distro, ROS_DISTRO or pkgforge.toml [verify] distro)"
            )
        return DistroProblem(message, hint)
    if not declared or name in ctx.installed_packages():
        return None
    system = SYSTEM_KEYS.get(name)
    if system is not None:
        # a rosdep key of the system's own package where it has one (ros/rosdistro rosdep/base.yaml)
        missing = [d for d in ctx.distros if d not in system[0]]
        if not missing:
            return None  # (no target distro given: a distro where it resolves counts)
        return DistroProblem(
            f"'{name}' is a rosdep key only for {', '.join(system[0])} ({system[1]}), not for "
            f"{', '.join(missing)} (rosdep install fails on it there)",
            f"use {better[0]} instead: {better[1]}"
            if better is not None
            else f"target {', '.join(system[0])}",
        )
    if better is not None:
        return DistroProblem(
            f"'{name}' is released in no ROS 2 distro: {better[1]} (rosdep install fails on it)",
            f"declare {better[0]} instead",
        )
    if name in rosdep_keys():
        return None  # a system package rosdep's own rules install (eigen, python3-numpy, libboost-dev)
    near = data.close_names(name, n=1, cutoff=0.85, same_start=True)
    from_source = _from_a_repository(ctx, name)
    if near and not (from_source and _first_word(near[0]) != _first_word(name)):
        # (a released sibling's near-spelling is a typo, whatever the .repos files hold)
        return DistroProblem(
            f"'{name}' is released in no ROS 2 distro (rosdep install fails on it)",
            f"did you mean {near[0]}?",
        )
    if from_source or tag == "doc_depend":
        return None
    # neither released in an active distro nor a key of rosdep's rules, not in the workspace nor
    # (by its name) in a repository a .repos file imports: `rosdep install` stops on it wherever it
    # runs ("Cannot locate rosdep definition"); a warning while no target distro is known (a
    # private rosdep source may define it), an error with one
    hint = (
        f"build {name} from source: put its repository in the workspace or in a .repos file beside the "
        "packages (vcs import); or declare the released package or rosdep key it stands for"
    )
    ignored = ctx.ignored_packages().get(name)
    if ignored is not None:
        # (rosdep's --from-paths skips the folders colcon skips: catkin_pkg's ignore markers)
        folder, marker = ignored
        base = ctx.workspace_base or folder.parent
        shown = marker.relative_to(base) if marker.is_relative_to(base) else marker
        hint = (
            f"{name} is in the workspace, but {shown} hides it from colcon and from rosdep's "
            f"--ignore-src: delete {marker.name} to build it, or drop the dependency"
        )
    return DistroProblem(
        f"'{name}' is released in no active ROS 2 distro and is no rosdep key: `rosdep install` fails "
        "on it on every machine, whatever the distro",
        hint,
        None if ctx.distros else Severity.WARNING,
    )


@register(
    "PF108",
    "package-not-in-distro",
    "error",
    area="manifest",
    bad=("<!-- package.xml, targeting jazzy -->\n<exec_depend>gazebo_ros</exec_depend>"),
    good=("<!-- package.xml -->\n<exec_depend>ros_gz_sim</exec_depend>"),
    summary="a package used or declared is not released for the target ROS 2 distro, or is "
    "released nowhere and no rosdep key",
    explanation="rosdep and the binary packages install only what is released for the "
    "distro: on a clean machine the dependency cannot be installed (gazebo_ros "
    "after Humble, ROS 1 names such as rviz or roslaunch, a typo in package.xml). "
    "The target distro comes from --distro, ROS_DISTRO, pkgforge.toml [verify] "
    "distro or the package's CI files (not a matrix that names several branches, "
    "nor a scheduled build of another branch, nor a workflow run only for branches named after "
    "other distros than the one checked out); without one, a package released in "
    "any active distro counts. A declared name released in no active distro, that is no key "
    "of rosdep's rules (ros/rosdistro rosdep/*.yaml: eigen, python3-numpy), not in the "
    "workspace and not plausibly in a repository a .repos/.rosinstall file imports fails "
    "`rosdep install` on every machine: an error with a target distro, a warning without "
    "(a private rosdep source may define it).",
    hint="use the ROS 2 package released for the distro",
)
def package_not_in_distro(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    manifest = model.manifest
    if not manifest.valid:
        return
    local = set(ctx.workspace) | {model.name, model.share_name} | ctx.source_repositories()
    reported = set()
    for dependency in manifest.active_dependencies():
        name = dependency.name
        if name in local or name in reported:
            continue
        problem = _not_in_distro(ctx, name, declared=True, tag=dependency.tag)
        if problem is not None:
            reported.add(name)
            yield Finding(
                f"<{dependency.tag}>{name}</{dependency.tag}>: {problem.message}",
                manifest.path,
                dependency.line,
                severity=problem.severity,
                hint=problem.hint,
            )
    if not ctx.distros:
        return
    from pkgforge.checks.launch import read_as_failed, static_note
    from pkgforge.checks.launch_depends import _looked_up

    uses: dict[str, list[tuple[bool, bool, str, int, Path, int | None, str, bool]]] = {}
    # the argument settings other than the defaults each use is seen only with ([]: the defaults)
    settings: dict[str, list[list[str]]] = {}
    # a file checked statically: its actions given a condition= (the file could not be evaluated)
    conditional = {
        (r.package, r.path, r.line): f"condition={r.launch_condition}"
        if r.launch_condition
        else r.python_branch
        for references in ctx.static_fallback().values()
        for r in references
        if r.launch_condition or (r.python_branch and ctx.branch_on_distros(r.python_branch) is None)
    }
    for name, path, line, via, item, resolution in _looked_up(ctx):
        if name not in local and name not in reported and name not in manifest.declared():
            uses.setdefault(name, []).append(
                (
                    line is None,
                    read_as_failed(ctx, path, item),
                    str(path),
                    line or 0,
                    path,
                    line,
                    via,
                    item is None,
                )
            )
            only = resolution.off_default(item) if resolution is not None and item is not None else []
            if resolution is None and (condition := conditional.get((name, path, line or 0))):
                only = [condition]
            settings.setdefault(name, []).append(only)
    for name, found in sorted(uses.items()):
        problem = _not_in_distro(ctx, name, declared=False)
        if problem is None:
            continue
        found.sort()
        _, _, _, _, path, line, via, static = found[0]
        more = len({(f[2], f[3]) for f in found}) - 1
        note = static_note(ctx, path, None) if static else ""
        message = f"{via} '{name}': {problem.message}{note}" + (f" (and {more} more)" if more else "")
        if all(settings[name]):
            # only with settings other than the defaults (moveit_resources' demo.launch.py runs
            # warehouse_ros_mongo only with db:=True): the default launch runs, that option fails
            note, detail = only_with(sorted({s for one in settings[name] for s in one}))
            yield Finding(
                f"{message}{note}",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"{problem.hint}; or leave that setting unsupported on this distro",
                detail=detail,
            )
            continue
        yield Finding(message, path, line, hint=problem.hint)


@register(
    "PF109",
    "find-package-undeclared",
    "error",
    area="manifest",
    bad=("# CMakeLists.txt (package.xml declares no urdf)\nfind_package(urdf REQUIRED)"),
    good=("<!-- package.xml -->\n<build_depend>urdf</build_depend>"),
    summary="CMakeLists.txt calls find_package() on a ROS package that package.xml does not "
    "declare for the build",
    explanation="rosdep installs only declared build dependencies: on a clean machine (a "
    "build farm, a Docker image after `rosdep install`) the find_package() fails. "
    "It builds here because the package is installed anyway, or because "
    "pkgforge build stubs declared packages. A warning when it builds all the same: "
    "optional (QUIET), inside an if() that holds only where an optional find_package() found a "
    "package nothing declared installs (`if(X_FOUND)`, `if(TARGET X::x)`, after `if(NOT X_FOUND) "
    "return()`: a clean machine skips it), declared as another kind (rosdep installs every kind), or brought "
    "along by a declared core package (ament_cmake brings ament_cmake_python, rclcpp brings "
    "rmw: the package.xml files of the core repositories, model/exports.py).",
    hint="declare it with <build_depend> (or <depend>)",
)
def find_package_undeclared(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    manifest = model.manifest
    if model.cmake is None or not manifest.valid:
        return
    from pkgforge.model.distro_data import released_set

    build = manifest.build_dependencies() | {
        d.name for d in manifest.active_dependencies() if d.tag in ("test_depend", "build_export_depend")
    }
    released = released_set(())  # with the workspace's: the ROS packages (no set built per package)
    reported = set()
    after = manifest.last_dependency_line()
    # what `rosdep install` puts on a clean machine: every kind declared but doc, what they bring
    installed = {d.name for d in manifest.active_dependencies() if d.tag != "doc_depend"}
    installing = tuple(tag for tag in DEPENDENCY_TAGS if tag != "doc_depend")
    gated = model.cmake.gated

    # the system libraries the declared rosdep keys name, as CMake names them (libopencv-dev and
    # opencv: opencv; eigen: eigen; python3-numpy: numpy), for the gates below
    system = {_library(key) for key in installed if key not in ctx.workspace and key not in released}

    def gates(command: Command) -> tuple[tuple[str, Command], ...]:
        """The optional finds the command runs only with, of packages a clean machine lacks: a
        ROS package neither declared nor brought along, or a system library (CUDA, the ZED SDK)
        no declared rosdep key names; find_package(Eigen3) where eigen is declared is found."""
        return tuple(
            (name, found)
            for name, found in gated.get((command.path, command.line), ())
            if name not in installed
            and ctx.brought_along(name, installing) is None
            and (name in ctx.workspace or name in released or _library(name) not in system)
        )

    def optional(command: Command) -> bool:
        words = {argument.text for argument in command.args[1:]}
        return "QUIET" in words and "REQUIRED" not in words

    # a name found more than once: where a clean machine fails first, else where it is found first
    finds = sorted(model.cmake.find_packages, key=lambda found: optional(found[1]) or bool(gates(found[1])))
    for name, command in finds:
        if (
            name in build
            or name in reported
            or (name not in ctx.workspace and name not in released)
            or name in (model.name,)
        ):
            continue
        reported.add(name)
        other = next((d for d in manifest.active_dependencies() if d.name == name), None)
        why = f" (only <{other.tag}> at package.xml:{other.line})" if other is not None else ""
        if (command.path, command.line) in model.cmake.test_only:
            tag = "test_depend"  # inside if(BUILD_TESTING): colcon builds with it on by default
        else:
            tag = "buildtool_depend" if name.startswith("ament_cmake") else "build_depend"
        needed = gates(command)
        # find_package(X QUIET) without REQUIRED (zed_components' point_cloud_transport, then
        # if(X_FOUND)): the build goes on without it, it only leaves out what needs it
        providers = BUILD_TAGS + (("test_depend",) if tag == "test_depend" else ())
        provider = None
        if optional(command):
            because = "; it is optional (QUIET), so a clean machine builds without what needs it"
        elif needed and (provider := ctx.brought_along(name, providers)) is None:
            # inside if(X_FOUND) after find_package(X QUIET) (tmr_ros2's tm_driver: MoveIt's
            # trajectory_msgs, control_msgs): a clean machine, without X, never runs it
            because = (
                f"; it is needed only where {_names(needed)} found (an if() on the optional "
                f"find_package() at {_where(needed, command)}), so a clean machine builds without it"
            )
        elif other is not None and other.tag != "doc_depend":
            # declared as another kind: `rosdep install` (every kind but doc by default) installs
            # it, the release build (bloom's Build-Depends, the build farm) does not
            because = (
                "; `rosdep install` installs it, so it builds from source, but the release build "
                "(bloom, the build farm) installs build dependencies only and fails"
            )
        elif provider is not None or (provider := ctx.brought_along(name, providers)):
            # ament_cmake brings ament_cmake_python, rclcpp brings rmw (model/exports.py)
            because = f"; {provider}, which it declares, brings it along, so it builds"
        else:
            because = ""
        yield Finding(
            f"find_package({name}) but package.xml does not declare {name} for the build{why}{because}",
            command.path,
            command.line,
            command.column,
            severity=Severity.WARNING if because else None,
            hint=(
                f"change package.xml:{other.line} to <depend>{name}</depend>"
                if other is not None and tag != "test_depend"
                else f"add <{tag}>{name}</{tag}> to package.xml" + (f" after line {after}" if after else "")
            ),
            # `fix` adds the test_depend the hint names (otherwise it works the tag out itself)
            fix={"dependency": name, "tag": tag} if tag == "test_depend" else None,
        )


def _names(gates: tuple[tuple[str, Command], ...]) -> str:
    names = [name for name, _ in gates]
    return (names[0] + " is") if len(names) == 1 else (", ".join(names[:-1]) + f" and {names[-1]} are")


def _where(gates: tuple[tuple[str, Command], ...], command: Command) -> str:
    """The optional finds' lines, with the file's name when it is another file."""
    places = [
        f"line {found.line}" if found.path == command.path else f"{found.path.name}:{found.line}"
        for _, found in gates
    ]
    return places[0] if len(places) == 1 else ", ".join(places[:-1]) + f" and {places[-1]}"


@register(
    "PF110",
    "package-name-duplicate",
    "error",
    area="manifest",
    bad="# src/a/twin_description/package.xml and src/b/twin_description/package.xml:\n"
    "<name>twin_description</name>",
    good="# src/b/twin_description/COLCON_IGNORE (an empty file): colcon builds the other copy",
    summary="another package of the workspace has the same name",
    explanation='colcon build and colcon test refuse the whole workspace ("Duplicate package '
    'names not supported") before building anything. It happens when a repository holds '
    "several workspaces (a course's sections) or a package was copied to try a change. The "
    "install tree can hold one copy only: the launch files and models of the others are not "
    "checked.",
    hint="build one copy: put an empty COLCON_IGNORE file in each other copy's folder, or verify the "
    "one workspace you build",
)
def package_name_duplicate(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    name = model.manifest.name
    if not ctx.namesakes or not name:
        return
    # the workspace's root (where colcon runs: the paths of the report, run there, start there)
    base = ctx.workspace_base if ctx.workspace_base is not None else model.path.parent
    top = base.parent if base.name == "src" else base

    def shown(folder: Path) -> str:
        return os.path.relpath(folder, top) if folder.is_relative_to(top) else str(folder)

    others = ", ".join(shown(folder) for folder in ctx.namesakes)
    unchecked = (
        "; its launch files and models are not checked: the install tree holds another copy"
        if ctx.shadowed
        else ""
    )
    yield Finding(
        f"package '{name}' is also at {others}: colcon build refuses a workspace where packages "
        f"share a name{unchecked}",
        model.manifest.path,
        model.manifest.name_line,
        hint="build one copy: put an empty COLCON_IGNORE file in each other copy's folder, or verify the "
        "folder of the one workspace you build",
    )


@register(
    "PF111",
    "package-nested",
    "warning",
    area="manifest",
    bad="# src/rob_description/package.xml and src/rob_description/rob_gazebo/package.xml",
    good="# src/rob_description/package.xml and src/rob_gazebo/package.xml (beside it)",
    summary="a package.xml inside another package's folder: colcon never finds that package",
    explanation="colcon's discovery stops at the first folder with a package.xml and looks no "
    "deeper: a package inside another package's folder is never built, installed or found by "
    "`ros2 launch` (its launch files and models are not checked either). A folder the outer "
    "package installs as data (a template its users copy) is not reported, nor one marked "
    "AMENT_IGNORE or CATKIN_IGNORE, nor test fixtures under test/.",
    hint="move the inner package's folder beside the outer package (a sibling folder under src/)",
)
def package_nested(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    if not model.manifest.valid or not model.manifest.name:
        return  # colcon may not take the outer folder for a package: it would look inside
    installed = model.layout.installed_sources()
    for name, folder in sorted(ctx.nested_packages().items(), key=lambda item: str(item[1])):
        if any(source.is_relative_to(folder) for source in installed):
            continue  # shipped as data (clearpath's project_bringup template): meant to be copied
        if any(ctx.files.exists(folder / marker) for marker in ("AMENT_IGNORE", "CATKIN_IGNORE")):
            continue  # colcon-ros ignores it on purpose
        manifest = folder / "package.xml"
        lines = ctx.files.lines(manifest)
        line = next((n for n, text in enumerate(lines, start=1) if "<name>" in text), 1 if lines else None)
        relative = folder.relative_to(model.path).as_posix()
        yield Finding(
            f"package '{name}' ({relative}/) is inside package '{model.manifest.name}': colcon stops "
            f"at {model.path.name}/package.xml and never builds, installs or finds '{name}'",
            manifest,
            line,
            hint=f"move {model.path.name}/{relative} beside {model.path.name} (a sibling folder, e.g. "
            f"{model.path.parent.name}/{folder.name}), or delete it if it is a leftover copy",
        )
