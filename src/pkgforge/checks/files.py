"""Checks about the files themselves."""

from __future__ import annotations

from pathlib import Path

from ..diagnostics import Finding
from .context import CheckContext
from .registry import register


@register("PF901", "file-not-read", "info", area="files",
          summary="a file pkgforge would read is too large or unreadable",
          explanation="pkgforge reads launch files, models and RViz configs to find what they "
                      "refer to; a file it cannot read is left out of those checks.",
          hint="check the file; a model over 8 MB is usually an ASCII mesh export by mistake")
def file_not_read(ctx: CheckContext):
    for source in ctx.model.skipped:
        if source.problem_line is not None:
            continue  # not UTF-8: the check that parses the file (launch, model, RViz) reports it
        yield Finding(f"{ctx.relative(source.path)} not read: {source.problem}", source.path,
                      source.problem_line)


@register("PF902", "folder-not-walked", "warning", area="files",
          summary="a folder nests too deep or holds too many files for pkgforge to look at all of it",
          explanation="pkgforge walks a package (and its installed share folder) at most 64 folders "
                      "deep and over at most 100000 files, so that a folder copied into itself or a "
                      "runaway export cannot stall a verify; what lies beyond is not checked.",
          hint="remove the accidental nesting or the stray files, or move them out of the package "
               "(or mark a folder with COLCON_IGNORE)")
def folder_not_walked(ctx: CheckContext):
    model = ctx.model
    shown = set()
    for limit in [*model.walk_limits, *model.layout.walk_limits]:
        path = Path(limit.path)
        if ctx.tree is not None:  # a folder of the install tree: name its source when it has one
            located = ctx.tree.locate(limit.path)
            if located is not None and located[0] in (model.name, model.share_name) \
                    and (model.path / located[1]).is_dir():
                path = model.path / located[1]
        if any(path == seen or seen in path.parents or path in seen.parents for seen in shown):
            continue  # the same nesting, met by another walk
        shown.add(path)
        yield Finding(limit.why, path)
