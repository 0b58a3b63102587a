"""Checks about the files themselves."""

from __future__ import annotations

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
