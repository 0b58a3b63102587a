"""GitHub Actions workflow commands: annotations on the pull request's files."""

from __future__ import annotations

from typing import TYPE_CHECKING

from pkgforge.diagnostics import Severity
from pkgforge.report import InRepository, printable
from pkgforge.report.text import summary

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

COMMANDS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def _data(text: str) -> str:
    """A workflow command's message as GitHub documents its escaping, after control characters are
    made printable (an escape sequence would act in the log; a newline is shown, not a line break)."""
    return printable(text).replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _property(text: str) -> str:
    return _data(text).replace(":", "%3A").replace(",", "%2C")


def render(result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    lines = []
    # GitHub matches an annotation's file against the repository's paths: actions/checkout puts
    # the repository in src/<package> of the workspace pkgforge's workflow verifies
    in_repository = InRepository(result.root)
    for d in result.diagnostics:
        props = [f"file={_property(in_repository(d.path))}"]
        if d.line is not None:
            props.append(f"line={d.line}")
            if d.column is not None:
                props.append(f"col={d.column}")
        props.append(f"title={_property(f'{d.code} {d.name}')}")
        lines.append(
            f"::{COMMANDS[d.severity]} {','.join(props)}::{_data(d.message)}%0Ahint: {_data(d.hint)}"
        )
    lines.append(summary(result))
    return "\n".join(lines) + "\n"
