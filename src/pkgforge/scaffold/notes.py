"""What migrate and new --from-urdf changed or left out: diagnostics with the registry's codes."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pkgforge.diagnostics import Diagnostic, Finding


@dataclass
class Notes:
    package: str
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def add(
        self, name: str, message: str, path: Path, line: int | None = None, hint: str | None = None
    ) -> None:
        from pkgforge.checks.registry import REGISTRY, all_checks

        all_checks()
        check = next(c for c in REGISTRY.values() if c.name == name)
        diagnostic = check.diagnostic(self.package, Finding(message, Path(path), line, hint=hint))
        if diagnostic not in self.diagnostics:  # said once (a step run again says it again)
            self.diagnostics.append(diagnostic)

    def render(self, root: Path) -> str:
        import os

        lines = []
        for d in sorted(self.diagnostics, key=Diagnostic.sort_key):
            shown = os.path.relpath(d.path, root)
            where = ":".join(
                [
                    d.path.as_posix() if shown.startswith("../../") else shown,
                    *([str(d.line)] if d.line is not None else []),
                ]
            )
            lines.append(f"{where}: {d.code} [{d.severity.label}] {d.message} ({d.name})")
        return "\n".join(lines) + ("\n" if lines else "")
