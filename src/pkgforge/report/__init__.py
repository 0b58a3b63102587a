"""Output formats for verify results: one module each, one `render(result, ...)` function."""

from __future__ import annotations

import os
from pathlib import Path

FORMATS = ("text", "json", "junit", "sarif", "github", "gitlab")


def relative(path: Path, root: Path) -> str:
    """A path as the user sees it: relative to the folder verify was given."""
    return Path(os.path.relpath(path, root)).as_posix()


def render(fmt: str, result, *, color: bool = False, strict: bool = False) -> str:
    from . import github, gitlab, json_report, junit, sarif, text

    module = {"text": text, "json": json_report, "junit": junit, "sarif": sarif, "github": github,
              "gitlab": gitlab}[fmt]
    return module.render(result, color=color, strict=strict)
