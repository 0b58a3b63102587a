"""Errors the CLI turns into a clean message and an exit status, never a traceback."""


class PkgforgeError(Exception):
    """A problem with the user's input or environment; exit status 2."""

    exit_code = 2


class BuildFailed(PkgforgeError):
    """colcon ran and at least one package failed; exit status 1."""

    exit_code = 1
