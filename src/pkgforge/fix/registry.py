"""The fixers' registry: one fixer per check name (`fixer`), what a fix is (`Fix`), what fixers
share (`FixContext`). The fixers themselves are in fixers, rviz_fixers, launch_fixers and
sim_fixers."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.diagnostics import Diagnostic
from pkgforge.fix.edits import Edit, FileSet, Unfixable

if TYPE_CHECKING:
    from pkgforge.model.package import PackageModel


@dataclass
class Fix:
    """What one diagnostic's fix does: edits per file, and a few words for the report."""

    description: str
    edits: dict[Path, list[Edit]] = field(default_factory=dict)
    # a dependency it declares: (the package.xml, the name), so a run adds no cycle (run.py)
    declares: tuple[Path, str] | None = None
    # new files (an environment hook): written only where no file is; the fixer checks first
    creates: dict[Path, str] = field(default_factory=dict)

    def add(self, path: Path, edit: Edit) -> None:
        self.edits.setdefault(Path(path), []).append(edit)

    def create(self, path: Path, text: str) -> None:
        if Path(path).exists() or Path(path).is_symlink():
            raise Unfixable(f"{Path(path).name} exists already: pkgforge does not overwrite it")
        self.creates[Path(path)] = text

    @property
    def paths(self) -> list[Path]:
        """Every file the fix writes: edited or created."""
        return [*self.edits, *self.creates]


class FixContext:
    """What fixers share: the files read, and package models loaded again in this process."""

    def __init__(self, files: FileSet):
        self.files = files
        self._models: dict[Path, PackageModel] = {}

    def model(self, path: Path) -> PackageModel:
        from pkgforge.model.package import load_package

        path = Path(path)
        if path not in self._models:
            self._models[path] = load_package(path)
        return self._models[path]


Fixer = Callable[[Diagnostic, FixContext], Fix]
FIXERS: dict[str, Fixer] = {}


def fixer(*names: str) -> Callable[[Fixer], Fixer]:
    def decorate(function: Fixer) -> Fixer:
        for name in names:
            FIXERS[name] = function
        return function

    return decorate


def given(diagnostic: Diagnostic, key: str, missing: str) -> str:
    """The text the finding's fix data holds under `key`; Unfixable(missing) when there is none."""
    value = (diagnostic.fix or {}).get(key)
    if not isinstance(value, str) or not value:
        raise Unfixable(missing)
    return value


def all_fixers() -> dict[str, Fixer]:
    """Every fixer, by check name."""
    from pkgforge.fix import (  # noqa: F401  (importing registers them)
        fixers,
        launch_fixers,
        rviz_fixers,
        sim_fixers,
    )

    return FIXERS
