"""One JSON object: packages, diagnostics, summary."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

from pkgforge.diagnostics import Severity
from pkgforge.report import relative

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

SCHEMA_VERSION = 1


def as_dict(result: VerifyResult) -> dict[str, Any]:
    return {
        "version": SCHEMA_VERSION,
        "packages": [
            {"name": r.name, "path": relative(r.path, result.root), "build_type": r.build_type}
            for r in result.reports
        ],
        "diagnostics": [
            {
                "code": d.code,
                "name": d.name,
                "severity": d.severity.label,
                "package": d.package,
                "path": relative(d.path, result.root),
                "line": d.line,
                "column": d.column,
                "message": d.message,
                "hint": d.hint,
                # the full text when the message is short for it (an error's whole output,
                # the items and lines of a grouped finding); null: the message says it all
                "detail": d.detail,
            }
            for d in result.diagnostics
        ],
        "summary": {
            "errors": result.count(Severity.ERROR),
            "warnings": result.count(Severity.WARNING),
            "infos": result.count(Severity.INFO),
            "packages": len(result.reports),
        },
        "launch": launch_note(result),
        # what confined the processes that ran launch files and xacro (null: none ran)
        "sandbox": result.sandbox,
    }


def launch_note(result: VerifyResult) -> dict[str, Any]:
    """The engine; for the built-in one, the distro whose launch API it followed and where that
    came from (`from`), or, when packages target different distros, null and each in `distros`."""
    if result.engine == "ros":
        return {"engine": result.engine, "distro": result.distro}
    chosen = result.launch_distros
    single = len(chosen) == 1
    distro, source = next(iter(chosen)) if single else (result.distro if not chosen else None, None)
    return {
        "engine": result.engine,
        "distro": distro,
        "from": source,
        "distros": [{"distro": d, "from": s, "packages": names} for (d, s), names in chosen.items()],
    }


def render(result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    return json.dumps(as_dict(result), indent=2) + "\n"
