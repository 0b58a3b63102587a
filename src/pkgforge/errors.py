"""Errors the CLI turns into a clean message and an exit status, never a traceback."""


class PkgforgeError(Exception):
    """A problem with the user's input or environment; exit status 2."""

    exit_code = 2


class BuildFailed(PkgforgeError):
    """colcon ran and at least one package failed; exit status 1.

    `failures`: (package, its log file, the last lines of the log), one per failing
    package; empty when colcon stopped before any package ran.
    """

    exit_code = 1

    def __init__(self, message: str, failures: list | None = None, status: int | None = None):
        super().__init__(message)
        self.failures = failures or []
        self.status = status
