"""Locating the Jinja2 templates, from an installed wheel or from a checkout."""

from __future__ import annotations

from pathlib import Path


def templates_dir() -> Path:
    """The folder holding pkgforge's templates.

    The wheel ships them inside the package (pkgforge/templates); an editable
    install or a plain checkout finds them at the repository's top level.
    """
    here = Path(__file__).resolve().parent
    for candidate in (here / "templates", here.parent.parent / "templates"):
        if (candidate / "package").is_dir():
            return candidate
    raise FileNotFoundError(
        f"pkgforge templates not found beside {here}; reinstall pkgforge"
    )
