"""What a launch file tried to change at run time: the worker's guard refused it, or let it
change only pkgforge's private copy of the install tree (sandbox/guard.py, tree.py)."""

from __future__ import annotations

from collections.abc import Iterator

from pkgforge.checks.context import CheckContext
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding
from pkgforge.launch.records import Error, Resolution

SANDBOX_TYPES = ("RefusedWrite", "RefusedSignal", "TreeWrite")
CHILD = " (in a process it started)"
MARKER = "pkgforge refused"  # sandbox/guard.py's PermissionError


def stopped_by_guard(resolution: Resolution) -> bool:
    """Loading failed on a PermissionError of the guard (not caught by the launch file)."""
    error = resolution.error
    return (
        resolution.status == "load-error"
        and error is not None
        and error.type == "PermissionError"
        and MARKER in (error.message or "")
    )


def sandbox_records(resolution: Resolution) -> Iterator[tuple[str, str, str, bool, Error]]:
    """(type, operation, path, started by a child process, item) of the guard's records."""
    for item in resolution.errors:
        kind = item.type
        if kind not in SANDBOX_TYPES:
            continue
        message = item.message or ""
        child = message.endswith(CHILD)
        operation, _, path = message.removesuffix(CHILD).partition(": ")
        yield kind, operation, path, child, item


@register(
    "PF316",
    "launch-writes-files",
    "warning",
    area="launch",
    bad=(
        "# launch/display.launch.py\n"
        "with open(os.path.join(share, 'urdf', 'robot.urdf'), 'w') as f:\n"
        "    f.write(urdf)"
    ),
    good=(
        "# launch/display.launch.py\nparameters=[{'robot_description': urdf}]  # the content, no file written"
    ),
    summary="a launch file writes files or signals processes while it is loaded",
    explanation="Whatever a launch file does at load time happens on every `ros2 launch`: "
    "writing into its package's share folder changes install/ (and, with "
    "`colcon build --symlink-install`, the source file in src/ it links to); "
    "writing elsewhere changes the user's files; a signal to its parent kills "
    "`ros2 launch`. During verify, pkgforge refuses writes outside its own "
    "temporary install tree and signals to processes the launch file did not "
    "start, and gives it private copies of the installed files, so nothing of "
    "the user's changes.",
    hint="write generated files to a temporary folder (tempfile) or pass the content directly "
    "(robot_description as a parameter); never write into src/ or install/",
)
def launch_writes_files(ctx: CheckContext) -> Iterator[Finding]:
    for resolution in ctx.resolutions:
        name = resolution.launch.installed.name
        stopped = stopped_by_guard(resolution)
        error = resolution.error
        for kind, operation, path, child, item in sandbox_records(resolution):
            position = ctx.source_position(resolution, item.file, item.line)
            if position is None:
                position = (resolution.launch.source or resolution.launch.installed, None)
            who = f"{name} (through a process it starts)" if child else name
            if kind == "RefusedSignal":
                message = (
                    f"{who} tries to {operation} {path} at run time, not a process it started "
                    f"(its parent is `ros2 launch`): pkgforge refused it"
                )
            elif kind == "RefusedWrite":
                message = (
                    f"{who} tries to {operation} {path} at run time: pkgforge refused it and "
                    f"kept the file unchanged"
                )
            else:
                located = ctx.tree.locate(path) if ctx.tree is not None else None
                shown = f"share/{located[0]}/{located[1]}" if located else path
                message = (
                    f"{who} tries to {operation} the installed {shown} at run time: `ros2 launch` "
                    f"would change install/ (and, through --symlink-install, the file in src/); "
                    f"pkgforge refused it and kept the file unchanged"
                )
            if stopped and error is not None and item.line == error.line and item.file == error.file:
                message += "; loading stopped there, so nothing after it was checked"
            yield Finding(message, *position)
