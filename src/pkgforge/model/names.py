"""Package-name rules of REP 144, shared by `new` and the checks."""

from __future__ import annotations

import re

REP144_PATTERN = re.compile(r"^[a-z][a-z0-9_]*$")

REP144_RULE = (
    "a ROS package name (REP 144) starts with a lower-case letter, holds only "
    "lower-case letters, digits and underscores, has no '__' and does not end with '_'"
)


def rep144_problem(name: str) -> str | None:
    """Return why `name` breaks REP 144, or None when it is a valid package name."""
    if not name:
        return "the name is empty"
    if "/" in name or "\\" in name or name in (".", ".."):
        return f"'{name}' is a path, not a package name (use --destination for the folder)"
    if not REP144_PATTERN.match(name):
        if name[0].isdigit():
            return f"'{name}' starts with a digit"
        suggestion = _suggestion(name)
        try_it = f" (try '{suggestion}')" if suggestion else ""
        if name != name.lower():
            return f"'{name}' has upper-case letters{try_it}"
        if "-" in name:
            return f"'{name}' has '-'{try_it}"
        return f"'{name}' has characters other than a-z, 0-9 and '_'"
    if "__" in name:
        return f"'{name}' has a double underscore"
    return None


def rep144_advice(name: str) -> str | None:
    """Why `name`, valid by REP 144's mandatory rules, is still a poor one (`new` refuses it,
    verify warns), or None. A trailing '_': REP 144 calls '_' a separator without forbidding it
    at the end, and catkin_pkg and colcon take it (a composition_ package builds)."""
    if name.endswith("_") and rep144_problem(name) is None:
        return f"'{name}' ends with '_'"
    return None


def _suggestion(name: str) -> str | None:
    """A valid name close to `name` (lower case, '-' as '_'), or None when that is not valid either:
    a hint must never suggest another invalid name."""
    candidate = name.lower().replace("-", "_")
    return (
        candidate
        if REP144_PATTERN.match(candidate) and "__" not in candidate and not candidate.endswith("_")
        else None
    )
