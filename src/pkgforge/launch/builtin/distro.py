"""The distro whose launch API the built-in engine stands for (api_names.json has humble's and jazzy's)."""

from __future__ import annotations

import os

LISTS = {"humble": "humble", "jazzy": "jazzy", "kilted": "jazzy", "lyrical": "jazzy", "rolling": "jazzy"}
DEFAULT_DISTRO = "jazzy"


def distro() -> str:
    """The list of names used: the target distro's (PKGFORGE_LAUNCH_DISTRO), or the nearest one
    generated."""
    wanted = os.environ.get("PKGFORGE_LAUNCH_DISTRO", "").strip().lower() or DEFAULT_DISTRO
    return LISTS.get(wanted, DEFAULT_DISTRO)
