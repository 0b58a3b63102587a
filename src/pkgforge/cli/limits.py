"""The values of the launch sandbox's options that both command lines take (`pkgforge verify`
with click, `colcon verify` with argparse), without click: colcon imports every verb it has on
each run, `colcon build` too."""

from __future__ import annotations

LAUNCH_ENGINES = ("auto", "ros", "builtin")
WORKER_MEMORY_MINIMUM = 256 * 2**20  # bytes: what a launch worker needs to start


def parse_worker_memory(text: str) -> int | None:
    """--worker-memory: a size such as 2G or 512M (bytes), or None for `unlimited`; a ValueError
    says what is wrong with `text`."""
    from pkgforge.sandbox.processes import format_size, parse_size

    if text.strip().lower() in ("unlimited", "none"):
        return None
    size = parse_size(text)
    if size < WORKER_MEMORY_MINIMUM:
        raise ValueError(
            f"{text} is below the {format_size(WORKER_MEMORY_MINIMUM)} a launch worker needs to start"
        )
    return size
