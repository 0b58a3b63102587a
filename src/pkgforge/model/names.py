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
        return f"'{name}' has characters other than a-z, 0-9 and '_'{try_it}"
    if "__" in name:
        suggestion = _suggestion(name)
        return f"'{name}' has a double underscore" + (f" (try '{suggestion}')" if suggestion else "")
    return None


def rep144_advice(name: str) -> str | None:
    """Why `name`, valid by REP 144's mandatory rules, is still a poor one (`new` refuses it,
    verify warns), or None. A trailing '_': REP 144 calls '_' a separator without forbidding it
    at the end, and catkin_pkg and colcon take it (a composition_ package builds)."""
    if name.endswith("_") and rep144_problem(name) is None:
        return f"'{name}' ends with '_'"
    return None


def suggested_name(name: str) -> str | None:
    """A valid package name close to `name`, or None when none is near: the name CAD exporters take
    from the assembly made valid (BellPepperGripperPrototype → bell_pepper_gripper_prototype,
    er20-1780 → er20_1780, Arm_Assembly_URDF.SLDASM → arm_assembly_urdf_sldasm). Words of a camel-case
    name are joined by '_', every other character that is not a letter or digit becomes one '_'.
    A hint must never suggest another invalid name: None when the result is not valid (a name
    starting with a digit)."""
    words = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", "_", name)
    candidate = re.sub(r"[^a-z0-9]+", "_", words.lower()).strip("_")
    if candidate == name or not candidate:
        return None
    return candidate if rep144_problem(candidate) is None and rep144_advice(candidate) is None else None


def _suggestion(name: str) -> str | None:
    return suggested_name(name)
