"""GitLab code quality report (the JSON array GitLab shows on a merge request's changes).

Paths are relative to the repository that holds the file (the nearest folder with `.git`
above it), as GitLab matches them to the merge request's files; outside a repository,
relative to the folder verify was given.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pkgforge.diagnostics import Severity
from pkgforge.report import printable, relative

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

SEVERITIES = {Severity.ERROR: "major", Severity.WARNING: "minor", Severity.INFO: "info"}


def _repository(folder: Path, known: dict[Path, Path | None]) -> Path | None:
    trail = []
    while folder not in known:
        trail.append(folder)
        if (folder / ".git").exists():
            known[folder] = folder
            break
        if folder.parent == folder:
            known[folder] = None
            break
        folder = folder.parent
    found = known[folder]
    for seen in trail:
        known[seen] = found
    return found


def render(result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    known: dict[Path, Path | None] = {}
    issues: list[dict[str, Any]] = []
    seen: dict[str, int] = {}
    for d in result.diagnostics:
        base = _repository(Path(os.path.abspath(d.path)).parent, known) or result.root
        path = relative(d.path, base)
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
