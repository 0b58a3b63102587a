"""Checks about the files themselves."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from pkgforge.checks.context import CheckContext
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding


@register(
    "PF901",
    "file-not-read",
    "info",
    area="run",
    bad="# urdf/robot.urdf: 20 MB (a mesh pasted into the model) or mode 000",
    good="# urdf/robot.urdf: the mesh as a file in meshes/, the model readable and small",
    summary="a file pkgforge would read is too large, unreadable, or no regular file",
    explanation="pkgforge reads launch files, models and RViz configs to find what they "
    "refer to; a file it cannot read is left out of those checks. It reads only regular "
    "files (or links to them), never a FIFO or a device: a read of a FIFO waits for ever, "
    "one of /dev/zero never ends.",
    hint="make the file readable, or smaller than 8 MB",
)
def file_not_read(ctx: CheckContext) -> Iterator[Finding]:
    from pkgforge.model.references import launch_kind

    for source in ctx.model.skipped:
        if source.problem_line is not None:
            kind = launch_kind(source.path)
            if kind is not None and not _refused_there(ctx, source.path, source.problem_line):
                # not UTF-8, and launch did not refuse it at that byte (it was not evaluated, or
                # Python skips a comment's bytes or follows a coding line): pkgforge does not read it
                yield Finding(
                    f"{ctx.relative(source.path)} not read: {source.problem}",
                    source.path,
                    source.problem_line,
                    hint="save the file as UTF-8: Python accepts other bytes only in comments or "
                    "under a coding line, and pkgforge reads only UTF-8"
                    if kind == "py"
                    else "save the file as UTF-8: ros2 launch reads XML and YAML launch files as UTF-8",
                )
            continue  # not UTF-8: the check that parses the file (model, RViz, launch) reports it
        yield Finding(
            f"{ctx.relative(source.path)} not read: {source.problem}",
            source.path,
            source.problem_line,
            hint=read_problem_hint(source.problem),
        )


def _refused_there(ctx: CheckContext, path: Path, line: int) -> bool:
    """Whether loading the launch file failed at that line (launch-load-error reports the bytes
    that are not UTF-8 there: ros2 launch refuses the file)."""
    for resolution in ctx.resolutions:
        error = resolution.error
        if resolution.status != "load-error" or error is None:
            continue
        if ctx.source_position(resolution, error.file, error.line) == (path, line):
            return True
    return False


def read_problem_hint(problem: str | None) -> str | None:
    """The fix for why read_source could not read a file (None: the check's own hint)."""
    problem = problem or ""
    if "limit for reading" in problem:
        return (
            "pkgforge reads files up to 8 MB: split it (xacro:include) or generate it at build "
            "time; the file is not checked"
        )
    if "Permission denied" in problem or "Operation not permitted" in problem:
        return "give read permission (chmod a+r FILE, and a+x on its folders): colcon and ROS read it too"
    if "not valid UTF-8" in problem:
        return "save the file as UTF-8"
    if "reads only regular files" in problem:
        return (
            "put the file itself there (or a link to one): a FIFO or a device has no end (or no start) "
            "to read, and colcon installs and ROS loads files"
        )
    if "pkgforge reads YAML up to" in problem or "expanding it never ends" in problem:
        return "nest it less deeply, or write out what the aliases repeat: no real config comes near this"
    return None


@register(
    "PF903",
    "folder-not-walked",
    "warning",
    area="run",
    bad="# meshes/meshes/meshes/...: a folder copied into itself, 64 levels deep",
    good="# meshes/: the accidental copy removed",
    summary="a folder cannot be read, or nests too deep or holds too many files to look at all of it",
    explanation="pkgforge walks a package (and its installed share folder) at most 64 folders "
    "deep and over at most 100000 files, so that a folder copied into itself or a "
    "runaway export cannot stall a verify; what lies beyond is not checked. A "
    "folder it may not read is not checked either (and colcon cannot install it).",
    hint="remove the accidental nesting or the stray files, or move them out of the package "
    "(or mark a folder with COLCON_IGNORE)",
)
def folder_not_walked(ctx: CheckContext) -> Iterator[Finding]:
    model = ctx.model
    shown: set[Path] = set()
    for limit in [*model.walk_limits, *model.layout.walk_limits]:
        path = Path(limit.path)
        if ctx.tree is not None:  # a folder of the install tree: name its source when it has one
            located = ctx.tree.locate(limit.path)
            if (
                located is not None
                and located[0] in (model.name, model.share_name)
                and ctx.files.is_dir(model.path / located[1])
            ):
                path = model.path / located[1]
            else:  # the folder of the user's install base, not of pkgforge's copy of it
                path = Path(ctx.tree.origin(limit.path))
        if any(path == seen or seen in path.parents or path in seen.parents for seen in shown):
            continue  # the same nesting, met by another walk
        shown.add(path)
        yield Finding(limit.why, path, hint=limit.hint)


def untree(ctx: CheckContext, text: str) -> str:
    """text with paths in pkgforge's temporary install tree of this package shown as the source
    files they come from (a message names the user's file, not a folder that is gone)."""
    import re

    share = ctx.tree.share(ctx.model.share_name) if ctx.tree is not None else None
    if share is None or str(share) not in text:
        return text

    def source(match: re.Match[str]) -> str:
        found = ctx.own_source(match.group(0))
        return ctx.relative(found) if found is not None else match.group(0)

    return re.sub(re.escape(str(share)) + r"/[^\s'\"\]]+", source, text)
