"""The prefixes of the ament index, as ament_index_python.search_paths."""

from __future__ import annotations

import os


def get_search_paths() -> list[str]:
    return [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p and os.path.exists(p)]
