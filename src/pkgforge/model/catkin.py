"""catkin_pkg's package module, imported without building a pyparsing grammar first.

catkin_pkg.package imports catkin_pkg.condition, whose import builds the grammar
of REP 149 conditions with pyparsing: ~25 ms, a tenth of verifying one package.
Its evaluate_condition needs that grammar only for a dependency that has a
condition, which few package.xml files do. `defer()` puts a stand-in in its place
until then: the same evaluate_condition, which imports the real module on the
first condition that is not None. colcon's ROS extension and pkgforge's loaders
both read manifests through catkin_pkg, so both are spared the grammar.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any

CONDITION_MODULE = "catkin_pkg.condition"
_DEFERRED = "__pkgforge_deferred__"


def _real_condition_module() -> types.ModuleType:
    module = sys.modules.get(CONDITION_MODULE)
    if module is None or getattr(module, _DEFERRED, False):
        sys.modules.pop(CONDITION_MODULE, None)
        module = importlib.import_module(CONDITION_MODULE)
    return module


def _evaluate_condition(condition: str | None, context: Any) -> Any:
    if condition is None:
        return True  # what catkin_pkg's own function answers before it builds the grammar
    return _real_condition_module().evaluate_condition(condition, context)


def _attribute(name: str) -> Any:
    # any other name of the module (PEP 562): the real one's; the import system's own questions
    # (`__path__`: is it a package?) are answered here, or asking them would build the grammar
    if name.startswith("__") and name.endswith("__"):
        raise AttributeError(name)
    return getattr(_real_condition_module(), name)


def defer() -> None:
    """Stand in for catkin_pkg.condition until a real condition is evaluated; nothing when
    catkin_pkg.package (or the condition module) is imported already."""
    if CONDITION_MODULE in sys.modules or "catkin_pkg.package" in sys.modules:
        return
    stand_in = types.ModuleType(CONDITION_MODULE, "catkin_pkg.condition until a condition is evaluated")
    # the module's names, as its namespace holds them (a module object types no attributes)
    vars(stand_in).update(
        {_DEFERRED: True, "evaluate_condition": _evaluate_condition, "__getattr__": _attribute}
    )
    sys.modules[CONDITION_MODULE] = stand_in


defer()
from catkin_pkg.package import InvalidPackage, parse_package_string  # noqa: E402

if not hasattr(sys.modules["catkin_pkg"], "condition"):  # `catkin_pkg.condition` as an attribute too
    sys.modules["catkin_pkg"].condition = sys.modules[CONDITION_MODULE]  # type: ignore[attr-defined]

__all__ = ["InvalidPackage", "defer", "parse_package_string"]
