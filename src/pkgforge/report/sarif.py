"""SARIF 2.1.0 for code scanning (GitHub, GitLab, Azure DevOps)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pkgforge import __version__
from pkgforge.checks.catalogue import help_uri
from pkgforge.checks.registry import all_checks
from pkgforge.diagnostics import Severity
from pkgforge.report import InRepository, printable, relative

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
# what a URI's path may hold as it is (RFC 3986 pchar and "/"; quote() keeps letters, digits, -._~),
# less ":": in a relative reference's first segment it would read as a scheme ("a:b.py")
_URI_PATH_SAFE = "/!$&'()*+,;=@"


def artifact_uri(path: str) -> str:
    """A relative path as the URI reference SARIF requires: a space, %, :, #, ?, a non-ASCII or
    control character percent-encoded (as UTF-8; a byte that was not UTF-8 as itself), so that
    viewers decode it to the file's name."""
    from urllib.parse import quote

    return quote(path, safe=_URI_PATH_SAFE, errors="surrogateescape")


def render(result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    checks = all_checks()
    index = {c.code: i for i, c in enumerate(checks)}
    rules = [
        {
            "id": c.code,
            "name": c.name,
            "shortDescription": {"text": c.summary},
            "fullDescription": {"text": c.explanation},
            "help": {"text": c.hint},
            "helpUri": help_uri(c),
            "defaultConfiguration": {"level": LEVELS[c.severity]},
        }
        for c in checks
    ]
    results = []
    # code scanning matches a result's file against the repository's paths: each relative to the
    # root of the git repository that holds it (SRCROOT the first, then SRCROOT2 ...)
    in_repository = InRepository(result.root)
    bases: dict[Path, str] = {}
    for d in result.diagnostics:
        base = in_repository.root(d.path) or result.root
        base_id = bases.setdefault(base, "SRCROOT" if not bases else f"SRCROOT{len(bases) + 1}")
        physical: dict[str, Any] = {
            "artifactLocation": {"uri": artifact_uri(relative(d.path, base)), "uriBaseId": base_id}
        }
        if d.line is not None:
            region = {"startLine": d.line}
            if d.column is not None:
                region["startColumn"] = d.column
            physical["region"] = region
        results.append(
            {
                "ruleId": d.code,
                "ruleIndex": index[d.code],
                "level": LEVELS[d.severity],
                # the message as code scanning shows it: printable, like every report's
                "message": {"text": printable(f"{d.message} (hint: {d.hint})")},
                "locations": [{"physicalLocation": physical}],
            }
        )
    document = {
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [
            {
                "tool": {"driver": {"name": "pkgforge", "version": __version__, "rules": rules}},
                "originalUriBaseIds": {
                    base_id: {"uri": base.as_uri() + "/"}
                    for base, base_id in (bases or {result.root: "SRCROOT"}).items()
                },
                "results": results,
            }
        ],
    }
    return json.dumps(document, indent=2) + "\n"
