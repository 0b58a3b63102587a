"""Where in the user's files a robot model's items are: the xacro or URDF file and line a model,
an included file, a link or a joint comes from, or the launch file that fed the model."""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pkgforge.checks.context import CheckContext
from pkgforge.launch.records import Resolution
from pkgforge.robot_models import ModelResult


def model_source_position(
    ctx: CheckContext, result: ModelResult, file: str | None, line: int | None, elsewhere: bool = True
) -> tuple[Path, int | None]:
    """(source path, line) in this package, or in another package verified in the same run whose
    file it is (the line a person edits, whichever package's launch file led there), falling back
    to the model's own source file, and for another package's model to the launch line of this
    package that feeds it to xacro (pkgforge's tree is no place a person edits)."""
    own = (ctx.own_source(file) or (_verified_elsewhere(ctx, file) if elsewhere else None)) if file else None
    if own is not None:
        return own, line
    if result.source is None:
        for origin in result.origins:
            resolution = next((r for r in ctx.resolutions if r.launch == origin["launch"]), None)
            position = (
                None if resolution is None else _fed_from(ctx, resolution, origin["file"], origin["line"])
            )
            if position is not None:
                return position
    if result.source is not None and file:
        # a link or joint written in another package's file this model includes (roarm_moveit's
        # model includes roarm_description's URDF): the include's line, not none
        return result.source, _include_line(ctx, result.source, file)
    return (result.source or result.installed), None


def _verified_elsewhere(ctx: CheckContext, installed: str) -> Path | None:
    """The source of an installed file of another package this run verifies, else None."""
    from pkgforge.launch.resolve import source_of

    located = ctx.tree.locate(installed) if ctx.tree is not None else None
    other = ctx.models.get(located[0]) if located is not None else None
    if other is None or other is ctx.model or ctx.tree is None:
        return None
    return source_of(Path(installed), ctx.tree, other)


def _include_line(ctx: CheckContext, model: Path, included: str) -> int | None:
    """The line of `model` whose <xacro:include> names `included` by its package and its path
    there ($(find pkg)/urdf/parts.xacro), else None (named otherwise, or on two lines)."""
    located = ctx.tree.locate(included) if ctx.tree is not None else None
    if located is None:
        return None
    package, relative = located[0], located[1]
    texts = [re.sub(r"<!--.*?(-->|$)", "", text) for text in ctx.files.lines(model)]  # (comments out)
    exact = [
        n
        for n, text in enumerate(texts, start=1)
        if "include" in text and f"$(find {package})/{relative}" in text
    ]
    if exact:
        return exact[0] if len(exact) == 1 else None
    loose = [
        n
        for n, text in enumerate(texts, start=1)
        if "include" in text and package in text and relative in text
    ]
    return loose[0] if len(loose) == 1 else None


def _fed_from(
    ctx: CheckContext, resolution: Resolution, file: str | None, line: int | None
) -> tuple[Path, int | None] | None:
    """The line of this package's launch file that leads to a construct: the construct's own
    line, else the include line that (through other packages' launch files) brings in the file
    it stands in (arduinobot_bringup includes arduinobot_description's gazebo.launch.py, which
    runs xacro)."""
    seen: set[str | None] = set()
    while file not in seen:
        seen.add(file)
        position = ctx.source_position(resolution, file, line)
        if position is not None:
            return position
        include = next((i for i in resolution.includes if i.path == file), None)
        if include is None:
            return None
        file, line = include.file, include.line
    return None


def model_item_position(
    ctx: CheckContext, result: ModelResult, item: Mapping[str, Any], line: int | None = None
) -> tuple[Path, int | None]:
    """model_source_position of an item of a model's structure or error (a link, joint, mesh):
    its own file, at `line` when given (a line inside it, e.g. its <inertial>), else its own line.
    A model's error in another package's file stays at this package's launch line: the arguments
    that launch gave xacro may be its cause (dof:=9 naming no folder), not that file."""
    return model_source_position(
        ctx, result, item.get("file"), line or item.get("line"), elsewhere=item is not result.error
    )
