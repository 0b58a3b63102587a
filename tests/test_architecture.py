"""docs/architecture.md against the code: what it names exists, where it says."""

from __future__ import annotations

import importlib
import importlib.util
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
PAGE = (REPO / "docs" / "architecture.md").read_text()
SRC = REPO / "src" / "pkgforge"


def _rooms() -> dict[str, str]:
    """Each row of the Rooms table: its first cell's module, the rest of the row."""
    rows = {}
    for line in PAGE.splitlines():
        match = re.match(r"\| `(pkgforge(?:\.\w+)?)`(?:, `pkgforge\.\w+`)* \| (.*) \|$", line)
        if match:
            rows[match.group(1)] = match.group(2)
    return rows


def _exists(dotted: str) -> bool:
    """A module, or a name defined in a module."""
    try:
        importlib.import_module(dotted)
        return True
    except ImportError:
        module, _, name = dotted.rpartition(".")
        return bool(module) and hasattr(importlib.import_module(module), name)


def test_every_package_of_pkgforge_is_a_room_and_names_each_of_its_modules():
    rooms = _rooms()
    packages = sorted(p.parent.name for p in SRC.glob("*/__init__.py"))
    assert packages and all(f"pkgforge.{name}" in rooms for name in packages), sorted(rooms)
    for name in packages:
        named = set(re.findall(r"`(\w+)`", rooms[f"pkgforge.{name}"]))
        modules = {p.stem for p in (SRC / name).glob("*.py") if p.stem != "__init__"}
        assert modules <= named, f"pkgforge.{name}: not on the page: {sorted(modules - named)}"


def test_every_module_a_room_names_exists():
    for room, text in _rooms().items():
        if importlib.util.find_spec(room).submodule_search_locations is None:
            continue  # a module's row names what it does, not submodules
        for name in re.findall(r"`([a-z_]+)`", text):
            assert importlib.util.find_spec(f"{room}.{name}") is not None, f"{room}.{name}"


def test_every_type_of_the_flow_is_defined_where_the_page_says():
    pairs = re.findall(r"`(\w+)`s? \[`(pkgforge[\w.]*)`\]", PAGE)
    assert len(pairs) >= 12
    for name, module in pairs:
        assert hasattr(importlib.import_module(module), name), f"{name} is not in {module}"


@pytest.mark.parametrize(
    "dotted", sorted(set(re.findall(r"`((?:pkgforge\.)?[a-z_]+(?:\.[a-z_]+)+)(?:\([^`]*\))?`", PAGE)))
)
def test_every_dotted_name_on_the_page_exists(dotted):
    if dotted == "pkgforge.toml":
        return  # the configuration file's name, not a module
    assert _exists(dotted if dotted.startswith("pkgforge.") else f"pkgforge.{dotted}"), dotted
