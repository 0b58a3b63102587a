"""What a check reads: one package's model and the workspace around it."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..model.package import PackageModel


@dataclass
class CheckContext:
    model: PackageModel
    # every package of the workspace being verified: name → folder
    workspace: dict[str, Path] = field(default_factory=dict)

    def relative(self, path: Path) -> str:
        try:
            return str(path.relative_to(self.model.path))
        except ValueError:
            return str(path)
