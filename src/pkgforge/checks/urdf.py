"""Checks of robot models (xacro/URDF) and the meshes they reference, in the install tree."""

from __future__ import annotations

import os
import shlex
from collections import Counter
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from pkgforge.checks.context import CheckContext, only_with
from pkgforge.checks.facts import FileFacts
from pkgforge.checks.files import read_problem_hint, undeclared_find, untree_xacro
from pkgforge.checks.install import install_fix, install_fix_data, link_hint
from pkgforge.checks.model_positions import model_item_position, model_source_position
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Group, Severity
from pkgforge.launch.records import CommandRun, LaunchFile
from pkgforge.robot_models import ModelResult
from pkgforge.tree import InstallTree
from pkgforge.urdf.meshes import MeshLookup
from pkgforge.urdf.structure import JointDict, LinkDict, MeshDict, ModelError, RobotStructure, UrdfProblem


def _path_split_at_spaces(files: FileFacts, words: list[str], model: str) -> str | None:
    """The existing path that a command line split at its spaces, starting with the word `model`."""
    if model not in words or files.exists(model):
        return None
    start = words.index(model)
    for end in range(start + 1, len(words)):
        candidate = " ".join(words[start : end + 1])
        if files.exists(candidate):
            return candidate
    return None


def _missing_file_given(ctx: CheckContext, result: ModelResult, message: str | None) -> bool:
    """Whether xacro failed on a file that a launch file gave it as an argument (xacro:arg), that
    does not exist and that the launch file's own resolution found missing (missing-file's)."""
    text = str(message or "")
    missing = {p.path for r in ctx.resolutions for p in r.paths if not p.exists}
    return any(value in missing and value in text for value in result.mappings.values())


def _split_for_the_user(tree: InstallTree | None, command: CommandRun) -> tuple[str, str] | None:
    """(the user's path, the piece of it the command gets) when the command line, with pkgforge's
    tree written as the user's install base, splits a path at a space (ROS's Command splits its
    one line shell-like): pkgforge's own run used its tree, whose path has none."""
    if tree is None or not command.text or command.runtime_only:
        return None
    users = [tree.as_users(word) for word in command.command]
    if users == command.command:
        return None
    try:
        words = shlex.split(tree.as_users(command.text))
    except ValueError:  # an unclosed quote: the user's line fails as pkgforge's did
        return None
    for mine, theirs in zip(users, words, strict=False):
        if mine != theirs:
            return mine, theirs
    return None


@register(
    "PF308",
    "xacro-error",
    "error",
    area="launch",
    bad=(
        "<!-- urdf/robot.urdf.xacro -->\n"
        '<xacro:include filename="$(find rob_description)/urdf/arm.xacro"/>  <!-- no such file -->'
    ),
    good=(
        "<!-- urdf/robot.urdf.xacro -->\n"
        '<xacro:include filename="$(find rob_description)/urdf/arm.urdf.xacro"/>'
    ),
    summary="xacro fails on the model a launch file processes",
    explanation="robot_state_publisher gets no description and RViz shows nothing; xacro's own "
    "message says why (an include that does not resolve, an undefined property, "
    "a $(find) of an unknown package). When launch files feed the model to xacro with those "
    "arguments only under settings other than their defaults (a choice that needs more "
    "arguments given with it), it is a warning that names the setting.",
    hint="fix the model as xacro's message says",
)
def xacro_error(ctx: CheckContext) -> Iterator[Finding]:
    covered = set()
    for result in ctx.model_results:
        error: ModelError = result.error or {}
        if error.get("stage") == "ros1-xacro":
            covered.add(str(result.installed))  # xacro-ros1-tag names the tags
            continue
        if result.status in ("error", "timeout", "crashed") and error.get("stage", "xacro") == "xacro":
            covered.add(str(result.installed))
            if ctx.absent_include(error.get("message")) is not None:
                continue  # model-unevaluated (declared) or missing-exec-depend (not) names the package
            if ctx.unpredicted_file(error.get("message")) is not None:
                continue  # a file of a package whose install is not known (unpredicted-lookup)
            if undeclared_find(ctx, error.get("message")):
                continue  # one defect, one diagnostic: missing-exec-depend names the package
            if _missing_file_given(ctx, result, error.get("message")):
                continue  # one defect, one diagnostic: missing-file names the path the launch file gave
            given = "".join(f" {name}:={value}" for name, value in sorted(result.mappings.items()))
            message = f"xacro {result.installed.name}{given}: {untree_xacro(ctx, error.get('message'))}"
            hint = error.get("hint") or read_problem_hint(error.get("message"))
            # fed to xacro only by argument settings other than the defaults (kortex's
            # robot_type:=gen3_lite with the default dof:=7, where gen3_lite has 6), and xacro
            # processed the same model with other arguments fine: the setting works when the user
            # gives more arguments with it, so a warning that says which. A model broken whatever
            # it is given stays an error
            if (
                result.status == "error"
                and result.origins
                and all(o["only_with"] for o in result.origins)
                and any(r.installed == result.installed and r.status == "ok" for r in ctx.model_results)
            ):
                settings = sorted({s for o in result.origins for s in o["only_with"]})
                note, detail = only_with(settings)
                yield Finding(
                    f"{message}{note}",
                    *model_item_position(ctx, result, error),
                    severity=Severity.WARNING,
                    hint=f"with {settings[0]}, the user must give other arguments too: say which in "
                    "the arguments' descriptions, or make the model work with that setting alone"
                    + (f" ({hint})" if hint else ""),
                    detail=detail,
                )
                continue
            yield Finding(message, *model_item_position(ctx, result, error), hint=hint)
    # a launch file's xacro run on a model not processed above (failures above are at the model's line)
    seen: set[tuple[Path, int | None]] = set()
    for resolution in ctx.resolutions:
        for command in resolution.commands:
            if command.model in covered:
                continue
            split = _split_for_the_user(ctx.tree, command)
            if split is None and (command.ok or command.model is None):
                continue
            model = command.model
            # a path of the user's own files with a space (the tree has it too)
            if split is None and model is not None:
                spaced = _path_split_at_spaces(ctx.files, command.command or [], model)
                split = (
                    None
                    if spaced is None or ctx.tree is None
                    else (ctx.tree.as_users(spaced), ctx.tree.as_users(model))
                )
            if split is None and model is not None and not ctx.files.exists(model):
                continue  # one defect, one diagnostic: missing-file or uninstalled-reference names it
            if ctx.absent_include(command.message) is not None:
                continue  # model-unevaluated
            if ctx.unpredicted_file(command.message) is not None:
                continue  # unpredicted-lookup
            position = ctx.source_position(resolution, command.file, command.line)
            if position is None or position in seen:
                continue
            seen.add(position)
            if split is not None:
                spaced, piece = split
                program = os.path.basename(command.command[0]) if command.command else "the command"
                yield Finding(
                    # (what the program got first: a long path would cut the message before it)
                    f"{program} {Path(spaced).name} got '{piece}': Command joins its parts into one "
                    f"line that it splits at spaces (ROS's Command does too), and the path '{spaced}' "
                    "has a space",
                    *position,
                    hint="quote the path inside the command line, e.g. Command(['xacro \"', "
                    "path, '\"']), or use a workspace path without spaces",
                )
                continue
            if undeclared_find(ctx, command.message):
                continue
            lines = untree_xacro(ctx, command.message).strip().splitlines()
            yield Finding(f"xacro {Path(model or '').name}: {lines[0] if lines else 'failed'}", *position)
        load_error = resolution.error
        models = {c.model for c in resolution.commands}
        if ctx.load_error_kind(resolution) == "xacro" and load_error is not None and not models & covered:
            position = ctx.source_position(resolution, load_error.file, load_error.line)
            if position is not None and not undeclared_find(ctx, load_error.message):
                yield Finding(f"xacro: {untree_xacro(ctx, load_error.message)}", *position)


@register(
    "PF407",
    "model-unevaluated",
    "info",
    area="model",
    bad=(
        "<!-- urdf/robot.urdf.xacro (realsense2_description is declared, not installed here) -->\n"
        '<xacro:include filename="$(find realsense2_description)/urdf/_d435.urdf.xacro"/>'
    ),
    good="$ pkgforge verify . --install-base install   # on a machine with realsense2_description",
    summary="a model includes a file of a declared package that is not installed here",
    explanation="Not the model's fault: the package is declared and ROS has it, but it is not on "
    "this machine, so xacro cannot expand the model here and nothing of it is checked.",
    hint="verify on a machine with the dependency installed (or --install-base) to check the model",
)
def model_unevaluated(ctx: CheckContext) -> Iterator[Finding]:
    covered = set()
    said: set[tuple[str, str]] = set()  # (package, file) already named at a model's own line
    for result in ctx.model_results:
        error: ModelError = result.error or {}
        if result.status not in ("error", "timeout", "crashed"):
            continue
        covered.add(str(result.installed))
        absent = ctx.absent_include(error.get("message"))
        if absent is not None and absent[0] in ctx.model.manifest.declared():
            said.add(absent)
            yield Finding(
                f"{result.installed.name} includes {absent[1]} of {absent[0]}, a declared package "
                "not installed here; the model is not checked",
                *model_item_position(ctx, result, error),
            )
    seen: set[tuple[Path, int | None]] = set()
    for resolution in ctx.resolutions:
        for command in resolution.commands:
            if command.ok or command.model is None or command.model in covered:
                continue
            absent = ctx.absent_include(command.message)
            position = ctx.source_position(resolution, command.file, command.line)
            if (
                absent is not None
                and absent[0] in ctx.model.manifest.declared()
                and position is not None
                and position not in seen
            ):
                seen.add(position)
                yield Finding(
                    f"{Path(command.model).name} includes {absent[1]} of {absent[0]}, a declared "
                    "package not installed here; the model is not checked",
                    *position,
                )
        # xacro.process_file() in the launch file's own code (an OpaqueFunction) failing so
        for item in resolution.errors:
            absent = ctx.absent_include(item.message)  # (xacro's own, or its stderr in an action's error)
            position = ctx.source_position(resolution, item.file, item.line)
            if absent is None or absent[0] not in ctx.model.manifest.declared() or position is None:
                continue
            if position not in seen and absent not in said:
                seen.add(position)
                yield Finding(
                    f"a model includes {absent[1]} of {absent[0]}, a declared package not installed "
                    "here; the model is not checked",
                    *position,
                )


@register(
    "PF401",
    "urdf-invalid",
    "error",
    area="model",
    bad=(
        "<!-- urdf/robot.urdf -->\n"
        '<robot name="rob">\n'
        '  <link name="base"/>\n'
        '  <joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint>\n'
        "</robot>"
    ),
    good=(
        "<!-- urdf/robot.urdf -->\n"
        '<robot name="rob">\n'
        '  <link name="base"/>\n'
        '  <link name="arm"/>\n'
        '  <joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint>\n'
        "</robot>"
    ),
    summary="a processed model is not a usable URDF",
    explanation="robot_state_publisher refuses it (or publishes a broken TF tree): no <robot>, "
    "duplicate names, a joint whose parent or child link does not exist, more than "
    "one root link, a cycle, or not XML at all. urdfdom (the parser of robot_state_publisher, "
    "RViz and Gazebo) refuses the whole model for one joint it cannot read (an <origin> or "
    "<axis> without 3 numbers, a <limit> without effort= or velocity=, an unknown type, a "
    "<mimic> without joint=, a <dynamics> with neither damping nor friction), a material "
    "defined twice under <robot>, or a <robot> without a name.",
    hint="fix the element named in the message",
)
def urdf_invalid(ctx: CheckContext) -> Iterator[Finding]:
    for result in ctx.model_results:
        error: ModelError = result.error or {}
        if result.status == "error" and error.get("stage") == "xml":
            yield Finding(
                f"{result.installed.name}: {error['message']}",
                *model_item_position(ctx, result, error),
            )
            continue
        robot = result.robot
        if result.status != "ok" or robot is None:
            continue
        if robot.get("root_tag") == "sdf" and not result.installed.name.endswith((".urdf", ".urdf.xacro")):
            continue  # an SDF through xacro (nav2's gz_waffle.sdf.xacro, spawned in Gazebo): no URDF
        if robot.get("root_tag") != "robot":
            yield Finding(
                f"{result.installed.name} has <{robot.get('root_tag')}> at its root, not <robot>",
                *model_source_position(ctx, result, str(result.installed), 1),
            )
            continue
        yield from _structure_problems(ctx, result, robot)


def _urdfdom(
    ctx: CheckContext, effects: tuple[str, ...]
) -> Iterator[tuple[ModelResult, UrdfProblem, tuple[Path, int | None]]]:
    """(result, problem, position) of what urdfdom refuses or drops in the processed models, one
    per place and message (a macro used four times is one defect)."""
    seen: set[tuple[str, Path, int | None]] = set()
    for result in ctx.model_results:
        robot = result.robot
        if result.status != "ok" or robot is None or robot.get("root_tag") != "robot":
            continue
        for problem in robot.get("urdfdom", []):
            if problem["effect"] not in effects:
                continue
            position = model_item_position(ctx, result, problem)
            if (problem["message"], *position) not in seen:
                seen.add((problem["message"], *position))
                yield result, problem, position


def _structure_problems(ctx: CheckContext, result: ModelResult, robot: RobotStructure) -> Iterator[Finding]:
    for problem in robot.get("urdfdom", []):
        if problem["effect"] == "model":
            yield Finding(problem["message"], *model_item_position(ctx, result, problem))
    links, joints = robot.get("links", []), robot.get("joints", [])
    items: list[LinkDict] | list[JointDict]
    if not links:
        yield Finding(
            f"{result.installed.name} defines no link", *model_source_position(ctx, result, None, None)
        )
        return
    for kind, items in (("link", links), ("joint", joints)):
        counts = Counter(item["name"] for item in items)
        for item in items:
            if counts[item["name"]] > 1:
                counts[item["name"]] = 0  # report each name once
                yield Finding(
                    f"{kind} name '{item['name']}' is used more than once",
                    *model_item_position(ctx, result, item),
                )
    names = {link["name"] for link in links}
    parents: dict[str | None, str | None] = {}
    for joint in joints:
        for role in ("parent", "child"):
            if joint.get(role) not in names:
                yield Finding(
                    f"joint '{joint['name']}' has {role} link '{joint.get(role)}', which does not exist",
                    *model_item_position(ctx, result, joint),
                    hint=f"add a link named '{joint.get(role)}' or fix the joint's <{role} link=...>",
                )
        if joint.get("child") in parents:
            yield Finding(
                f"link '{joint['child']}' is the child of two joints",
                *model_item_position(ctx, result, joint),
            )
        parents[joint.get("child")] = joint.get("parent")
    roots = [link for link in links if link["name"] not in parents]
    if len(roots) > 1:
        yield Finding(
            f"more than one root link: {', '.join(str(r['name']) for r in roots)} "
            "(every link but one must be a joint's child)",
            *model_item_position(ctx, result, roots[1]),
        )
    elif not roots:
        yield Finding(
            "the joints form a cycle: no link is the root", *model_source_position(ctx, result, None, None)
        )


def _meshes(ctx: CheckContext) -> Iterator[tuple[ModelResult, MeshDict, MeshLookup]]:
    """(result, mesh item, lookup) for every mesh URI of every processed model."""
    for result in ctx.model_results:
        if result.status != "ok" or not result.robot:
            continue
        seen = set()
        for mesh in result.robot.get("meshes", []):
            if mesh["uri"] in seen:
                continue
            seen.add(mesh["uri"])
            yield result, mesh, ctx.mesh(mesh["uri"], result.installed)


@register(
    "PF402",
    "mesh-not-found",
    "error",
    area="model",
    fix="safe",
    bad=(
        "<!-- urdf/robot.urdf (meshes/ is not installed) -->\n"
        '<mesh filename="package://rob_description/meshes/base.stl"/>'
    ),
    good=("# CMakeLists.txt\ninstall(DIRECTORY launch meshes urdf DESTINATION share/${PROJECT_NAME})"),
    summary="a mesh or texture URI does not resolve to a file in the install tree",
    explanation="RViz and simulators load package:// URIs from install/share/<pkg>/: a meshes "
    "folder never installed, a typo, or a path leaving its package shows an empty "
    "or broken model.",
    hint="install the mesh, or fix the URI",
)
def mesh_not_found(ctx: CheckContext) -> Iterator[Finding]:
    for result, mesh, lookup in _meshes(ctx):
        position = model_item_position(ctx, result, mesh)
        where = f"{mesh['kind']} of link '{mesh['link']}'" if mesh.get("link") else mesh["kind"]
        item = f"{mesh['uri']} ({where})"
        if lookup.status == "escapes":
            yield Finding(
                f"{item} leaves package {lookup.package} with '..'",
                *position,
                hint=f"name a file inside {lookup.package}, or use package://<other>/... for "
                "another package's file",
                group=Group(
                    f"escapes {lookup.package}",
                    mesh["uri"],
                    f"{{count}} mesh URIs leave package {lookup.package} with '..': {{items}}",
                ),
            )
        elif lookup.status == "unknown-package" and not lookup.package:
            fixed = "package://" + mesh["uri"][len("package://") :].lstrip("/")
            yield Finding(
                f"{item} names no package: 'package:///' has three slashes, and "
                "RViz's resource retriever reads an empty package name",
                *position,
                hint=f"write {fixed}",
            )
        elif lookup.status == "unknown-package":
            yield Finding(
                f"{item}: package '{lookup.package}' is not installed anywhere",
                *position,
                hint="fix the package name in the URI",
                group=Group(
                    f"unknown {lookup.package}",
                    mesh["uri"],
                    f"{{count}} mesh URIs name package '{lookup.package}', which is not installed "
                    "anywhere: {items}",
                ),
            )
        elif lookup.status == "missing":
            owner = ctx.model_for_share(lookup.package) if lookup.package else None
            relative = lookup.relative or ""
            in_source = owner is not None and ctx.files.is_file(owner.path / relative)
            linked = link_hint(ctx.files, owner, relative) if owner is not None else None
            if linked is not None:
                yield Finding(f"{item} is not in the install tree: {linked[0]}", *position, hint=linked[1])
            elif in_source and owner is not None:
                top = relative.split("/")[0]
                yield Finding(
                    f"{item} is not installed: {relative} is in the source of "
                    f"{lookup.package} but no install rule covers it",
                    *position,
                    hint=install_fix(owner, top, relative),
                    fix=install_fix_data(owner, top),
                    group=Group(
                        f"not installed {lookup.package}/{top}",
                        mesh["uri"],
                        f"{{count}} meshes are not installed: they are in {top}/ of {lookup.package}'s "
                        "source but no install rule covers them: {items}",
                    ),
                )
            else:
                yield Finding(
                    f"{item} does not exist",
                    *position,
                    hint="fix the file name in the URI",
                    group=Group("missing", mesh["uri"], "{count} mesh files do not exist: {items}"),
                )


@register(
    "PF403",
    "mesh-case-mismatch",
    "error",
    area="model",
    fix="safe",
    bad=(
        "<!-- urdf/robot.urdf (the file is meshes/base.STL) -->\n"
        '<mesh filename="package://rob_description/meshes/base.stl"/>'
    ),
    good=('<!-- urdf/robot.urdf -->\n<mesh filename="package://rob_description/meshes/base.STL"/>'),
    summary="a mesh URI differs from the file's name only in letter case",
    explanation="Exporters write part.STL; models say part.stl. Windows and macOS forgive it; "
    "Linux does not, and the link shows nothing.",
    hint="use the file's real name in the URI",
)
def mesh_case_mismatch(ctx: CheckContext) -> Iterator[Finding]:
    for result, mesh, lookup in _meshes(ctx):
        if lookup.status == "case":
            yield Finding(
                f"{mesh['uri']}: no such file, but '{lookup.real_name}' exists (case differs)",
                *model_item_position(ctx, result, mesh),
                hint=f"write {lookup.real_name} in the URI (or rename the file)",
                fix={"uri": mesh["uri"], "real_name": lookup.real_name},
            )


@register(
    "PF404",
    "mesh-source-path",
    "warning",
    area="model",
    bad=(
        '<!-- urdf/robot.urdf -->\n<mesh filename="file:///home/me/ws/src/rob_description/meshes/base.stl"/>'
    ),
    good=('<!-- urdf/robot.urdf -->\n<mesh filename="package://rob_description/meshes/base.stl"/>'),
    summary="a file:// mesh URI points into a source tree",
    explanation="It works on the machine that built the package and nowhere else: installed "
    "packages must not refer to src/.",
    hint="use package://<package>/<path> for an installed mesh",
)
def mesh_source_path(ctx: CheckContext) -> Iterator[Finding]:
    sources: list[Path] | None = None  # built only for a file:// URI: not once per package of the workspace
    for result, mesh, lookup in _meshes(ctx):
        if mesh["uri"].startswith("file://") and lookup.path is not None:
            if sources is None:
                sources = [m.path for m in ctx.models.values()] + [ctx.model.path]
            for folder in sources:
                try:
                    relative = lookup.path.relative_to(folder)
                except ValueError:
                    continue
                yield Finding(
                    f"{mesh['uri']} points into the source of {folder.name}",
                    *model_item_position(ctx, result, mesh),
                    hint=f"install it and write package://{folder.name}/{relative.as_posix()}",
                )
                break


@register(
    "PF405",
    "mesh-unreadable",
    "error",
    area="model",
    bad="# meshes/base.stl: an STL cut short (fewer triangles than its header says)",
    good="# meshes/base.stl: exported again from the CAD tool",
    summary="a mesh file is not a readable mesh of its kind",
    explanation="A truncated STL, a .dae that is not COLLADA, an OBJ with no vertices: the "
    "visualizer fails on it or shows nothing.",
    hint="export the mesh again",
)
def mesh_unreadable(ctx: CheckContext) -> Iterator[Finding]:
    for result, mesh, lookup in _meshes(ctx):
        if lookup.status == "found" and lookup.path is not None:
            problem = ctx.mesh_problem(lookup.path)
            if problem:
                yield Finding(
                    f"{mesh['uri']}: {problem}",
                    *model_item_position(ctx, result, mesh),
                    hint=read_problem_hint(problem),
                )


@register(
    "PF406",
    "model-needs-arguments",
    "info",
    area="model",
    bad=('<!-- urdf/robot.urdf.xacro -->\n<xacro:arg name="prefix"/>'),
    good=('<!-- urdf/robot.urdf.xacro -->\n<xacro:arg name="prefix" default=""/>'),
    summary="a model needs xacro arguments that nothing gives it",
    explanation="It was checked only with the values a launch file passes; on its own it cannot "
    "be processed: an argument with no value, or declared with an empty default that "
    "xacro fails without (an include built from it, e.g. arms/$(arg dof)dof/... that "
    "its launch files always set with dof:=7).",
    hint="give the xacro:arg a default, or check it through the launch file that passes it",
)
def model_needs_arguments(ctx: CheckContext) -> Iterator[Finding]:
    for result in ctx.model_results:
        if result.status == "needs-arguments":
            error: ModelError = result.error or {}
            position = model_item_position(ctx, result, error)
            if error.get("arguments"):  # declared with an empty default, and xacro fails without a value
                declared: Mapping[str, Any] = error.get("declared") or {}
                position = model_item_position(ctx, result, declared)
                names = ", ".join(error["arguments"])
                first = untree_xacro(ctx, error.get("message")).strip().splitlines()
                yield Finding(
                    f"{result.installed.name} needs values for the xacro argument(s) {names} (empty "
                    "default; on its own xacro fails: "
                    f"{first[0] if first else 'failed'}); evaluated only through launch files that "
                    "set them",
                    *position,
                    hint=f"check it through a launch file that passes {error['arguments'][0]}:=..., "
                    "or give the xacro:arg a default that works",
                )
                continue
            yield Finding(
                f"{result.installed.name} needs the xacro argument '{error.get('argument')}'; "
                "skipped on its own",
                *position,
            )
    # a model too large to process is reported by file-not-read


@register(
    "PF408",
    "xacro-ros1-tag",
    "error",
    area="model",
    bad=(
        "<!-- urdf/robot.urdf.xacro -->\n"
        '<macro name="wheel" params="side">\n'
        '  <link name="${side}_wheel"/>\n'
        "</macro>"
    ),
    good=(
        "<!-- urdf/robot.urdf.xacro -->\n"
        '<xacro:macro name="wheel" params="side">\n'
        '  <link name="${side}_wheel"/>\n'
        "</xacro:macro>"
    ),
    summary="a model uses ROS 1's xacro tags without the xacro: prefix (<macro>, <property>, "
    "<include>, <arg>, <if>, <unless>)",
    explanation="ROS 1's xacro took them (deprecated since ROS Jade); ROS 2's xacro processes only "
    "xacro:-prefixed tags and keeps the others as plain elements: a bare <macro>'s body is "
    "evaluated where it stands (xacro fails with a Python NameError about a macro parameter), a "
    "bare <property> defines nothing, <include> includes nothing, and <if> keeps its content "
    "whatever the condition, inside an element urdfdom does not read.",
    hint="add the xacro: prefix to each tag (<xacro:macro>, <xacro:property> ...), with "
    'xmlns:xacro="http://www.ros.org/wiki/xacro" on <robot>',
)
def xacro_ros1_tag(ctx: CheckContext) -> Iterator[Finding]:
    from pkgforge.urdf.ros1_xacro import describe

    seen: set[tuple[Path, int | None]] = set()
    for result in ctx.model_results:
        error: ModelError = result.error or {}
        robot = result.robot
        if error.get("stage") == "ros1-xacro":
            position = model_item_position(ctx, result, error)
            if position not in seen:
                seen.add(position)
                yield Finding(
                    f"xacro {result.installed.name}: {untree_xacro(ctx, error.get('message'))}",
                    *position,
                    hint=error.get("hint"),
                )
        elif result.status == "ok" and robot is not None and robot.get("ros1_tags"):
            tags = robot["ros1_tags"]
            position = model_item_position(ctx, result, tags[0])
            if position in seen:
                continue
            seen.add(position)
            yield Finding(
                f"{describe(tags, str(result.installed))}: ROS 1's xacro tags without the xacro: prefix, "
                "which ROS 2's xacro keeps as plain elements: what they define, include or make "
                f"conditional is not in {result.installed.name}'s robot",
                *position,
                hint=f"write <xacro:{tags[0]['tag']}> (each of them with the xacro: prefix), with "
                'xmlns:xacro="http://www.ros.org/wiki/xacro" on <robot>',
            )


@register(
    "PF409",
    "urdf-part-dropped",
    "error",
    area="model",
    bad=(
        "<!-- urdf/robot.urdf -->\n"
        "<visual>\n"
        '  <origin xyz="0 0.1"/>\n'
        '  <geometry><box size="0.1 0.1 0.1"/></geometry>\n'
        "</visual>"
    ),
    good=(
        "<!-- urdf/robot.urdf -->\n"
        "<visual>\n"
        '  <origin xyz="0 0.1 0"/>\n'
        '  <geometry><box size="0.1 0.1 0.1"/></geometry>\n'
        "</visual>"
    ),
    summary="urdfdom cannot read a link's <inertial>, <visual> or <collision> and drops it, and "
    "what follows it in the link",
    explanation="urdfdom (robot_state_publisher, RViz, Gazebo's URDF import) logs the error and "
    "keeps the link without it: a part with an <origin> or <box size> or <mesh scale> without "
    "3 numbers, no <geometry> or a shape it does not know (a capsule), a <sphere> or <cylinder> "
    "without its numbers, a <mesh> without filename, a visual <material> without name, an "
    "<inertial> without <mass> or with an <inertia> attribute missing. It stops reading the "
    "link there: a failing <inertial> drops every visual and collision, a failing visual the "
    "visuals after it and every collision, a failing collision the collisions after it. The "
    "link is not drawn, or does not collide.",
    hint="write the element as the URDF specification says: 3 numbers separated by spaces for xyz, "
    "rpy, size and scale; a box, cylinder, sphere or mesh as the shape; <mass value> and all six "
    "<inertia> attributes; a name on a visual's <material>",
)
def urdf_part_dropped(ctx: CheckContext) -> Iterator[Finding]:
    for _, problem, position in _urdfdom(ctx, ("part",)):
        yield Finding(problem["message"], *position)


@register(
    "PF410",
    "urdf-material-color",
    "warning",
    area="model",
    bad=(
        "<!-- urdf/robot.urdf -->\n"
        '<material name="red"><color rgba="1 0 0 1"/></material>\n'
        '<link name="arm"><visual>...<material name="red"><color rgba="0 1 0 1"/></material></visual></link>'
    ),
    good=(
        "<!-- urdf/robot.urdf -->\n"
        '<material name="red"><color rgba="1 0 0 1"/></material>\n'
        '<link name="arm"><visual>...<material name="green"><color rgba="0 1 0 1"/></material></visual></link>'
    ),
    summary="a link is drawn in another colour than its material says",
    explanation="urdfdom keeps the first material of a name (under <robot> or in an earlier "
    "visual) and gives it to every visual using the name, whatever colour the visual writes; it "
    "reads an rgba with other than 4 numbers as black, drops a material whose rgba has a value "
    "that is not a number from 0 to 1, and a visual naming a material no <material> before it "
    "defines gets none: RViz draws those links in its default colour.",
    hint="give each colour its own material name, and write rgba as 4 numbers from 0 to 1",
)
def urdf_material_color(ctx: CheckContext) -> Iterator[Finding]:
    for _, problem, position in _urdfdom(ctx, ("color",)):
        yield Finding(problem["message"], *position)


@register(
    "PF411",
    "mimic-joint-unknown",
    "error",
    area="model",
    bad=(
        "<!-- urdf/robot.urdf (no joint is named finger_joint) -->\n"
        '<joint name="finger2_joint" type="revolute">\n'
        '  <mimic joint="finger_joint"/>'
    ),
    good=(
        "<!-- urdf/robot.urdf -->\n"
        '<joint name="finger2_joint" type="revolute">\n'
        '  <mimic joint="finger1_joint"/>'
    ),
    summary="a joint's <mimic> names no moving joint of the model",
    explanation="urdfdom does not check the name. joint_state_publisher takes the mimic joint's "
    "position from the joint it names among those it publishes (a KeyError ends it when there is "
    "none: a missing or fixed joint), and robot_state_publisher publishes the mimic joint's "
    "transform only with that joint's position: its child link has no transform and RViz "
    "shows it at the origin with an error.",
    hint="name an existing revolute, continuous or prismatic joint in <mimic joint=...>",
)
def mimic_joint_unknown(ctx: CheckContext) -> Iterator[Finding]:
    for _, problem, position in _urdfdom(ctx, ("mimic",)):
        yield Finding(problem["message"], *position)


def root_link(ctx: CheckContext, launch: LaunchFile) -> str | None:
    for result in ctx.model_results:
        robot = result.robot
        if result.status == "ok" and robot is not None and any(o["launch"] == launch for o in result.origins):
            children = {j.get("child") for j in robot.get("joints", [])}
            return next(
                (link["name"] for link in robot.get("links", []) if link["name"] not in children), None
            )
    return None


def link_names(ctx: CheckContext, launch: LaunchFile) -> set[str | None] | None:
    """Links of the models the given launch file feeds to xacro (None when it feeds none)."""
    found = [r for r in ctx.model_results if any(o["launch"] == launch for o in r.origins)]
    if not found or any(r.status != "ok" for r in found):
        return None  # nothing to compare with: xacro-error or urdf-invalid says why
    return {name for r in found for name in r.links}
