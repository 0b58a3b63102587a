"""launch's failures as the built-in engine raises them, and how both engines mark and name them.

Real: launch/substitutions/substitution_failure.py, launch/invalid_launch_file_error.py,
ament_index_python's PackageNotFoundError; Unresolved and the failure marks are pkgforge's.
"""

from __future__ import annotations

import re
from typing import TypeVar


class SubstitutionFailure(RuntimeError):
    pass


# what a substitution's failure carries of its cause, for the record (failures.error_record,
# failures.record_visit_failure); both engines set it, on their own SubstitutionFailure
FAILURE_PROGRAM = "_pkgforge_program"  # FindExecutable: the program not found on PATH
FAILURE_VARIABLE = "_pkgforge_variable"  # EnvironmentVariable without a default: the variable not set
FAILURE_CONFIGURATION = "_pkgforge_configuration"  # LaunchConfiguration not set: its name (ros_engine)
FAILURE_CONFIGURATION_AT = "_pkgforge_configuration_at"  # and its place
FAILURE_MARKS = (FAILURE_PROGRAM, FAILURE_VARIABLE, FAILURE_CONFIGURATION)
_Failure = TypeVar("_Failure", bound=BaseException)


def marked(error: _Failure, mark: str, value: str) -> _Failure:
    """`error`, carrying `value` under `mark` (one of FAILURE_MARKS) unless it carries one
    already (the innermost substitution's failure is the cause)."""
    if all(failure_mark(error, known) is None for known in FAILURE_MARKS):
        try:
            setattr(error, mark, value)
        except AttributeError:  # an exception type without a __dict__: no mark
            pass
    return error


def failure_mark(error: BaseException, mark: str) -> str | None:
    value = getattr(error, mark, None)
    return value if isinstance(value, str) else None


class InvalidLaunchFileError(Exception):
    pass


class InvalidPythonLaunchFileError(InvalidLaunchFileError):
    pass


class InvalidFrontendLaunchFileError(InvalidLaunchFileError):
    pass


class PackageNotFoundError(KeyError):
    """ament_index_python's error, re-raised by FindPackageShare as in launch_ros."""


class Unresolved(Exception):
    """A launch configuration with no value: what depends on it is skipped, not guessed."""

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.name = name


class MissingConfiguration(SubstitutionFailure, Unresolved):
    """LaunchConfiguration's failure in launch: no value set and no default. Launch's own
    SubstitutionFailure (a launch file's `except SubstitutionFailure` catches it, as in ROS), and
    Unresolved: verify has no value for a launch argument declared without a default either,
    and what needs one is skipped then (deferred.settle_unset_uses tells the two apart). `where`:
    the LaunchConfiguration's place in the launch file."""

    def __init__(self, name: str, where: tuple[str | None, int | None]) -> None:
        SubstitutionFailure.__init__(self, f"launch configuration '{name}' does not exist")
        self.name, self.where = name, where


MISSING_CONFIGURATION_TEXT = re.compile(r"launch configuration '([^']*)' does not exist")


def missing_configuration(error: BaseException) -> tuple[str, tuple[str | None, int | None]] | None:
    """(name, the LaunchConfiguration's place or (None, None)) when `error` is launch's failure
    of a launch configuration not set (both engines), else None."""
    if isinstance(error, MissingConfiguration):
        return error.name, error.where
    name = getattr(error, FAILURE_CONFIGURATION, None)
    if isinstance(name, str):
        where = getattr(error, FAILURE_CONFIGURATION_AT, (None, None))
        return name, where
    match = MISSING_CONFIGURATION_TEXT.search(str(error))
    return (match.group(1), (None, None)) if match else None


def failure_type(error: BaseException) -> str:
    """The failure's type as launch names it (both engines: MissingConfiguration is launch's
    SubstitutionFailure)."""
    return "SubstitutionFailure" if isinstance(error, MissingConfiguration) else type(error).__name__


def failure_text(error: BaseException) -> str:
    """An action's failure as both engines write it: launch's exception type and message."""
    return f"{failure_type(error)}: {error}"
