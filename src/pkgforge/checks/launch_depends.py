"""Packages a launch file uses: known, and declared as the package's dependencies."""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterator
from pathlib import Path
from typing import NamedTuple

from pkgforge.checks.context import CheckContext, only_with
from pkgforge.checks.launch import _branch_note, read_as_failed, static_note
from pkgforge.checks.launch_paths import _share_reference
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Group, Severity
from pkgforge.launch.records import PackageLookup, Record, Resolution
from pkgforge.model.manifest import EXPORT_TAGS
from pkgforge.model.package import PackageModel
from pkgforge.model.references import Reference
from pkgforge.urdf import ANY_MODEL_SUFFIXES, XACRO_MODEL_SUFFIXES

# rviz2 depends on these: their displays come with whatever starts RViz (an rviz2 Node is checked
# where it is started; a config that another package's launch file opens needs nothing of its own)
RVIZ_BUILTIN = {"rviz_common", "rviz_default_plugins"}
# uses that missing-exec-depend checks; unknown names there are xacro's or RViz's error to report
# ("import": a file read statically; a module that is no ROS package is a Python library)
STATIC_ONLY_FOR_DEPENDENCIES = {"import of", "import", "package://", "$(find)", "RViz display from"}
# `ros2 launch` (ros2launch) depends on these: whoever can launch has them
LAUNCH_INFRASTRUCTURE = {
    "launch",
    "launch_ros",
    "launch_xml",
    "launch_yaml",
    "ament_index_python",
    "ros2launch",
}
# a package name with an empty part: f"kuka_{family}_support" of an empty argument
EMPTY_PART = re.compile(r"^_|__|_$")
# a path part that is the text of None (an f-string of os.getenv() of a variable not set)
# a package a launch file, a model or a file of the package uses: (name, source path, line, how,
# the launch record, its resolution); the last two are None for a static reference
Use = tuple[str, Path, "int | None", str, "Record | None", "Resolution | None"]


def _looked_up(ctx: CheckContext) -> Iterator[Use]:
    """(package name, source path, line, how, item, resolution) for every package a launch file uses."""
    for resolution in ctx.resolutions:
        for item in resolution.packages:
            position = ctx.source_position(resolution, item.file, item.line)
            if position is not None:
                yield item.name, position[0], position[1], item.via, item, resolution
        for include in resolution.includes:
            located = _share_reference(ctx, include.path) or (
                ctx.tree.locate(include.path) if ctx.tree is not None else None
            )
            position = ctx.source_position(resolution, include.file, include.line)
            if located is not None and position is not None:
                yield located[0], position[0], position[1], "included launch file", include, resolution
        error = resolution.error
        if resolution.status == "load-error" and error is not None and error.package:
            position = ctx.source_position(resolution, error.file, error.line)
            if position is not None:
                yield (
                    error.package,
                    position[0],
                    position[1],
                    "lookup",
                    PackageLookup(found=False),
                    resolution,
                )
    for references in ctx.static_fallback().values():
        for reference in references:
            yield reference.package, reference.path, reference.line, reference.via, None, None
    # one cause, one finding: rviz2 loads no display of an RViz 1 config (rviz-ros1-config says so),
    # so the packages its displays came from are nothing it uses
    ros1_configs = {config.path for config in ctx.rviz_configs if config.ros1_classes}
    # models: $(find pkg) and package://pkg, as written and as xacro expanded them
    for reference in ctx.model.references:
        if reference.via in ("package://", "$(find)") and reference.path.name.endswith(ANY_MODEL_SUFFIXES):
            yield reference.package, reference.path, reference.line, reference.via, None, None
        elif reference.via == "rviz plugin" and reference.path not in ros1_configs:
            yield reference.package, reference.path, reference.line, "RViz display from", None, None
    for result in ctx.model_results:
        for mesh in result.robot["meshes"] if result.robot else []:
            if mesh["uri"].startswith("package://"):
                package = mesh["uri"][len("package://") :].split("/")[0]
                own = ctx.own_source(mesh.get("file") or "")
                # a mesh written in another package's file: this model's file, no line. Another
                # package's model (run by this package's launch file) needs its meshes' packages
                # itself: its own verification names them (andino_navigation runs
                # andino_gz_classic's model, whose meshes are andino_description's)
                if own:
                    yield package, own, mesh.get("line"), "package://", None, None
                elif result.source is not None:
                    yield package, result.source, None, "package://", None, None
    # a Python launch file that imports a ROS package's module needs that package at run time
    evaluated = {r.launch.source for r in ctx.resolutions if r.status == "ok" and r.launch.source}
    for reference in ctx.model.references:
        if (
            reference.via == "import"
            and reference.path in evaluated
            and reference.package not in LAUNCH_INFRASTRUCTURE
        ):
            yield reference.package, reference.path, reference.line, "import of", None, None


@register(
    "PF304",
    "unknown-package",
    "error",
    area="launch",
    bad=(
        "# launch/display.launch.py (the package is rob_description)\nFindPackageShare('robot_description')"
    ),
    good=("# launch/display.launch.py\nFindPackageShare('rob_description')"),
    summary="a launch file looks up a package that exists nowhere",
    explanation="The package is not in the workspace, not declared in package.xml, not "
    "installed and released in no active ROS 2 distro: almost always a typo or a "
    "package renamed (`robot_description` looked up where your package is named "
    "`rob_description`). Used only with argument "
    "settings other than the defaults, it is a warning: more likely an optional driver the "
    "robot's users build from source.",
    hint="fix the package name; if it is a package built from source (not released), add it to "
    "the workspace (or its .repos file) and declare it",
)
def unknown_package(ctx: CheckContext) -> Iterator[Finding]:
    if not ctx.model.manifest.valid:
        return  # with no readable manifest, nothing is known to be declared
    known = ctx.known_packages()
    nested = ctx.nested_packages()
    # a file checked statically: a lookup in a `try:` that handles its failure is optional, as in
    # ROS; a package evaluation already found missing in the file is that finding (one per cause)
    static = {(r.package, r.path, r.line): r for refs in ctx.static_fallback().values() for r in refs}
    guarded = {key for key, r in static.items() if r.guarded}
    evaluated: set[tuple[str, str]] = set()
    seen = set()
    for name, path, line, via, item, resolution in _looked_up(ctx):
        if name in known or (name, str(path), line) in seen or via in STATIC_ONLY_FOR_DEPENDENCIES:
            continue
        if resolution is None and ((name, path, line) in guarded or (name, str(path)) in evaluated):
            continue
        if resolution is not None:
            evaluated.add((name, str(path)))
        unset = ctx.none_from_unset(resolution, name) if resolution is not None else []
        if name in nested and path.is_relative_to(nested[name]):
            continue  # a template package's own files name it
        if not name or (
            resolution is not None
            and EMPTY_PART.search(name)
            and any(a.default == "" for a in resolution.arguments)
        ):
            continue  # built from a launch argument left empty (a template's caller gives it): no typo
        seen.add((name, str(path), line))
        message = (
            f"package '{name}' ({via}) is not in the workspace, not declared in package.xml "
            f"and released in no ROS 2 distro{static_note(ctx, path, item)}"
        )
        only = resolution.off_default(item) if resolution is not None and item is not None else []
        if unset:
            # dobot: get_package_share_directory(os.getenv('DOBOT_TYPE') + '_moveit') → 'None_moveit'
            yield Finding(
                f"{message} (None in it: environment variable {' or '.join(unset)} is not set here)",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"set {unset[0]} when you run verify (e.g. {unset[0]}=value pkgforge verify), "
                "or give it a default",
            )
            continue
        reference = static.get((name, path, line or 0)) if resolution is None else None
        branch = reference.python_branch if reference is not None else None
        if branch is not None and ctx.branch_on_distros(branch) is None:
            # a file read statically: used in one if/else branch of it, which runs is not known
            # (select_slam_launch.py's hector_mapping, started only when the user picks 3)
            yield Finding(
                f"{message} (only in the branch `{branch}`)",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"{_unknown_hint(ctx, name)}; if it is built from source, list it in a .repos file",
            )
            continue
        if not only:
            # one package named by many nodes or lookups of a file: one diagnostic naming them
            yield Finding(
                message,
                path,
                line,
                hint=_unknown_hint(ctx, name),
                group=Group(
                    f"unknown {name}",
                    via,
                    f"package '{name}' ({{items}}) is not in the workspace, not declared in package.xml "
                    "and released in no ROS 2 distro",
                ),
            )
            continue
        # used only with settings other than the defaults (linorobot2's sensor:=xv11 runs
        # xv_11_driver, which its users clone from source): more likely an optional driver built
        # from source than a typo
        note, detail = only_with(only)
        yield Finding(
            f"{message}{note}",
            path,
            line,
            severity=Severity.WARNING,
            hint=f"{_unknown_hint(ctx, name)}; if it is built from source, list it in a .repos file",
            detail=detail,
        )


class _OptionalUse(NamedTuple):
    """A model's use of a package that package.xml may leave out on purpose: where it stands, and
    when to declare the package all the same (the hint)."""

    where: str
    when: str


def _optional_use(ctx: CheckContext, reference: Reference, read: set[Path] | None) -> _OptionalUse | None:
    """Whether a model's reference, as written, is needed only in some uses of the package:
    inside an <xacro:if>/<xacro:unless> that does not hold at the defaults (franka's
    $(find franka_gazebo_bringup) under gazebo:=true; franka_gazebo_bringup depends on
    franka_description), or in a model file no robot model of the package reads (husky's
    urdf/accessories/sick_lms1xx_mount.urdf.xacro and its $(find lms1xx)). `read`: the package's
    files its models read, None when not known."""
    if reference.guarded:
        # a file checked statically: its `try:` handles the package's absence (an optional driver)
        return _OptionalUse(
            "inside a `try:` of a launch file checked statically that handles its absence,",
            "if the package's users need what it adds",
        )
    if reference.python_branch is not None and ctx.branch_on_distros(reference.python_branch) is None:
        # a file checked statically (not evaluated here): which branch runs is unknown (a branch
        # on $ROS_DISTRO every target distro takes is no option)
        return _OptionalUse(
            f"in the branch `{reference.python_branch}` of a launch file not evaluated here,",
            "if the package's users run that branch",
        )
    if reference.condition is not None:
        kind, _, value = reference.condition.partition(" ")
        return _OptionalUse(
            f'inside <xacro:{kind} value="{value}">',
            f"if the model is used with that setting (leave it out when {reference.package} "
            "itself depends on this package)",
        )
    if (
        reference.via in ("$(find)", "package://")
        and read is not None
        and reference.path.name.endswith(XACRO_MODEL_SUFFIXES)
        and reference.path not in read
    ):
        return _OptionalUse(
            f"in {ctx.relative(reference.path)}, which no robot model of {ctx.model.name} reads,",
            "if the file is meant to be included (an accessory for other packages' models), "
            "or remove the file",
        )
    return None


def _unknown_hint(ctx: CheckContext, name: str) -> str:
    """The package's ROS 2 name, or close names from the workspace, package.xml and the distros."""
    from pkgforge.model.distro_data import load, replacement

    renamed = replacement(name)
    if renamed is not None:
        return f"use {renamed[0]}: {renamed[1]}"
    own = ctx.model.manifest.name or ctx.model.name
    if name == ctx.model.path.name and name != own:
        return (
            f"'{name}' is the name of the folder; the package is named '{own}' (package.xml "
            f"<name>), and lookups use that: write '{own}', or rename one to match the other"
        )
    ignored = ctx.ignored_packages().get(name)
    if ignored is not None:
        folder, marker = ignored
        base = ctx.workspace_base or folder.parent
        where = (
            f"its folder {folder.relative_to(base)} holds"
            if marker.parent == folder
            else f"its folder {folder.relative_to(base)} is inside {marker.parent.relative_to(base)}, which holds"
        )
        return f"{where} a {marker.name}, so colcon does not build it: delete that file to build it, or drop the lookup"
    # candidates are package names only: a folder's name is no package (the lookup of a folder
    # named unlike its package is this very mistake), and never the wrong name itself
    candidates = sorted((set(ctx.workspace) | ctx.model.manifest.declared() | {own}) - {name})
    near = difflib.get_close_matches(name, candidates, n=3, cutoff=0.5)
    near += [n for n in load().close_names(name, n=3) if n not in near and n != name]
    return f"did you mean {', '.join(near[:3])}?" if near else "check the name against package.xml <name>"


@register(
    "PF305",
    "missing-exec-depend",
    "error",
    area="launch",
    fix="safe",
    bad=(
        "# launch/display.launch.py (package.xml has no exec_depend on rviz2)\n"
        "Node(package='rviz2', executable='rviz2')"
    ),
    good=("<!-- package.xml -->\n<exec_depend>rviz2</exec_depend>"),
    summary="a package used at run time is not an exec_depend",
    explanation="rosdep and binary packages install only what package.xml declares: on a fresh "
    "machine, your package's node, file or tool is missing. A model's use that xacro reads "
    "only inside <xacro:if>/<xacro:unless>, or in a model file no robot model of the package "
    "reads (an accessory for others to include), is a warning, with no fix: such a package is often left out on purpose (a "
    "simulation package that itself depends on the description). A package that depends on "
    "this one already gets a warning with no fix too (declaring it back is a cycle colcon "
    "refuses). A package a declared one brings along (spot_description brings robot_state_"
    "publisher) is installed on a fresh machine all the same: a warning, with the fix. A launch "
    "file's use of a viewer (rviz2, rqt, joint_state_publisher_gui, plotjuggler) only with argument "
    "settings other than the defaults (rviz:=true, default false) is a warning with an unsafe fix "
    "(--unsafe-fixes declares it): a headless robot leaves RViz out on purpose; any other package such a setting needs (the "
    "simulator under sim:=true) stays an error, with the setting named. A use in one if/else "
    "branch of a launch file pkgforge could not evaluate is a warning too (which branch runs is "
    "unknown: turtlebot3's lidar driver by $LDS_MODEL), and, in a test package (dsr_tests) or "
    "under test/, a package declared only as <test_depend>. With no target distro stated, a "
    "package that has a successor and is released for older distros only (gazebo_ros: humble) "
    "gets no fix: the hint names the successor.",
    hint="declare it with <exec_depend>",
)
def missing_exec_depend(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    if not model.manifest.valid:
        return  # with no readable manifest, nothing is known to be declared
    # a <build_export_depend> is installed with the package too (rosdep installs every kind,
    # bloom puts it in the binary's Depends): stretch_calibration declares stretch_core so
    declared = {d.name for d in model.manifest.active_dependencies() if d.tag in EXPORT_TAGS}
    tested = {d.name for d in model.manifest.active_dependencies() if d.tag == "test_depend"} - declared
    own = {model.name, model.share_name}
    known = ctx.real_packages()
    # a model's reference as written (not as xacro made it), for the uses a package may leave out
    written: dict[tuple[str, Path, int | None], Reference] = {
        (r.package, r.path, r.line): r for r in model.references
    }
    read = ctx.model_files_read()
    chosen: dict[str, tuple[Use, _OptionalUse | None]] = {}
    # a use needed whatever the settings first, then one with a line, then one of a file that
    # loads (one read statically because it does not load is the same defect, said less surely):
    # where the diagnostic points
    for use in sorted(
        _looked_up(ctx),
        key=lambda x: (x[0], x[2] is None, read_as_failed(ctx, x[1], x[4]), str(x[1]), x[2] or 0),
    ):
        name, path, line, via, item, _ = use
        if name in own or name in declared or name not in known or name in LAUNCH_INFRASTRUCTURE:
            continue
        if name in RVIZ_BUILTIN and (via == "RViz display from" or "rviz2" in declared):
            continue  # rviz2 depends on them
        reference = written.get((name, path, line)) if item is None else None
        optional = _optional_use(ctx, reference, read) if reference is not None else None
        if name not in chosen or (chosen[name][1] is not None and optional is None):
            chosen[name] = use, optional
    for (name, path, line, via, item, resolution), optional in chosen.values():
        if optional is not None:
            yield Finding(
                f"{via} '{name}' is used only {optional.where} but package.xml does not declare it",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"add <exec_depend>{name}</exec_depend> {optional.when}",
            )  # no fix: only the user knows whether that use is meant for this package's users
            continue
        note = _branch_note(item, resolution) if resolution is not None and item is not None else ""
        note += static_note(ctx, path, item)
        written_use = written.get((name, path, line)) if item is None else None
        if written_use is not None and written_use.launch_condition and path in ctx.static_fallback():
            # a file checked statically: its action given a condition= off at the defaults
            note = f" (only with condition={written_use.launch_condition})"
        if name in ctx.workspace and ctx.depends_on(name, model.name):
            # (husky_description's xacro finds husky_control, which depends on husky_description)
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}; "
                f"{name} depends on {model.name}, so declaring it here makes a cycle colcon refuses",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"install {name} beside {model.name} (its users have it), or move the use into {name}",
            )  # no fix: the dependency the hint would add breaks the build
            continue
        provider = ctx.brought_along(name, EXPORT_TAGS)
        if provider is not None:
            # spot_ros2_control exec_depends spot_description, which exec_depends rviz2: installed
            # with it, the launch file runs; declaring what it uses directly is still the rule
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}; "
                f"{provider}, which it declares, brings it along",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"add <exec_depend>{name}</exec_depend> to package.xml",
                fix={"dependency": name, "tag": "exec_depend", "manifest": str(model.manifest.path)},
            )
            continue
        if name in tested and _for_tests(model, path):
            # Doosan's dsr_tests: launch files its own tests start, their packages declared as
            # <test_depend> (rosdep installs those for a source build): right if only the tests
            # launch them. A released binary does not bring test dependencies: elsewhere, an error
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml declares it only as <test_depend>{note}",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"if the launch file runs outside the package's tests, make it <exec_depend>{name}</exec_depend>",
            )
            continue
        if (
            note
            and resolution is not None
            and item is not None
            and resolution.off_default(item)
            and _viewer(name)
        ):
            # kobuki_description's rviz2 under rviz:=true (default false): a headless robot leaves
            # it out on purpose, as unknown-package and package-not-in-distro already allow
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}",
                path,
                line,
                severity=Severity.WARNING,
                hint=f"add <exec_depend>{name}</exec_depend> if the package's users launch it with that setting",
                # unsafe: only the user knows whether that setting is meant for this package's users
                fix={
                    "dependency": name,
                    "tag": "exec_depend",
                    "manifest": str(model.manifest.path),
                    "unsafe": True,
                },
            )
            continue
        only_tests = (
            "; it declares it only as <test_depend>, which a released binary does not bring"
            if name in tested
            else ""
        )
        superseded = _superseded(ctx, name)
        if superseded is not None:
            # gazebo_ros with no target distro stated: declaring it is right on humble only, and
            # pkgforge cannot tell whether the package targets humble; the fix would pin it there
            yield Finding(
                f"{via} '{name}' is used at run time but package.xml does not declare it{note}{only_tests}",
                path,
                line,
                hint=superseded,
            )
            continue
        yield Finding(
            f"{via} '{name}' is used at run time but package.xml does not declare it{note}{only_tests}",
            path,
            line,
            hint=f"add <exec_depend>{name}</exec_depend> to package.xml"
            + (
                f" (after line {model.manifest.last_dependency_line()})"
                if model.manifest.last_dependency_line()
                else ""
            ),
            fix={"dependency": name, "tag": "exec_depend", "manifest": str(model.manifest.path)},
        )


def _superseded(ctx: CheckContext, name: str) -> str | None:
    """The hint, without a fix, for a package with a successor (distro_data.replacement) that is
    not released for every active distro its successor is, when no target distro is stated:
    `fix` would add gazebo_ros, released for humble only, to a package that may target jazzy. With
    a target, a name not released for it is package-not-in-distro's, never a fix's."""
    if ctx.distros or name in ctx.workspace:
        return None
    from pkgforge.model.distro_data import load, replacement

    better = replacement(name)
    if better is None:
        return None
    data = load()
    released = data.released_in(name)
    elsewhere = [d for d in data.released_in(better[0]) if d not in released]
    if not released or not elsewhere:
        return None
    return (
        f"use {better[0]} instead ({better[1]}); or, for a package that targets "
        f"{' or '.join(released)} only, add <exec_depend>{name}</exec_depend> to package.xml and "
        f'say so in pkgforge.toml ([verify] distro = "{released[0]}")'
    )


def _for_tests(model: PackageModel, path: Path) -> bool:
    """Whether a launch file is its package's tests' own: under a test/ folder, or in a package
    named for tests (dsr_tests, *_test, *_testing)."""
    try:
        parts = path.relative_to(model.path).parts
    except ValueError:
        parts = ()
    return any(part in ("test", "tests") for part in parts[:-1]) or model.name.endswith(
        ("_test", "_tests", "_testing")
    )


# tools a person looks through, which a headless robot's package leaves out on purpose
VIEWERS = frozenset({"joint_state_publisher_gui", "plotjuggler", "foxglove_bridge", "rviz2", "rqt_gui"})


def _viewer(name: str) -> bool:
    return name in VIEWERS or name.startswith(("rqt_", "rviz_"))
