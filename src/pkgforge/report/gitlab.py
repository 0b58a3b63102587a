"""GitLab code quality report (the JSON array GitLab shows on a merge request's changes).

Paths are relative to the repository that holds the file (the nearest folder with `.git`
above it), as GitLab matches them to the merge request's files; outside a repository,
relative to the folder verify was given.
"""

from __future__ import annotations

import hashlib
import json
from typing import TYPE_CHECKING, Any

from pkgforge.diagnostics import Severity
from pkgforge.report import InRepository, printable

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

SEVERITIES = {Severity.ERROR: "major", Severity.WARNING: "minor", Severity.INFO: "info"}


def render(result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    in_repository = InRepository(result.root)
    issues: list[dict[str, Any]] = []
    seen: dict[str, int] = {}
    for d in result.diagnostics:
        path = in_repository(d.path)
        key = f"{d.code}\0{path}\0{d.line or 0}\0{d.message}"
        # GitLab needs a fingerprint unique per issue and stable across runs: what and where
        seen[key] = seen.get(key, -1) + 1
        # (surrogateescape: a file name's bytes that are not UTF-8, as they are)
        fingerprint = hashlib.sha256(f"{key}\0{seen[key]}".encode("utf-8", "surrogateescape")).hexdigest()
        issues.append(
            {
                "type": "issue",
                "check_name": f"{d.code} {d.name}",
                # shown on the merge request as it is: printable; the path stays the file's own
                # (JSON escapes it), which GitLab matches to the changed files
                "description": printable(f"{d.code} {d.message} (hint: {d.hint})"),
                "categories": ["Bug Risk"],
                "severity": SEVERITIES[d.severity],
                "fingerprint": fingerprint,
                "location": {"path": path, "lines": {"begin": d.line or 1}},
            }
        )
    return json.dumps(issues, indent=2) + "\n"
