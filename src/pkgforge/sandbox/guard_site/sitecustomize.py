"""Loaded by every Python process the launch worker starts (this folder leads its PYTHONPATH):
installs pkgforge's write and signal guard (../guard.py), then the sitecustomize it shadows."""

import importlib.util
import os
import sys
from types import ModuleType


def _load(name: str, path: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _install() -> None:
    here = os.path.dirname(os.path.abspath(__file__))
    guard = sys.modules.get("pkgforge.sandbox.guard") or _load(
        "_pkgforge_guard", os.path.join(os.path.dirname(here), "guard.py")
    )
    guard.install()
    for folder in sys.path:  # the sitecustomize this one hides (a distribution's), if any
        candidate = os.path.join(folder or ".", "sitecustomize.py")
        if os.path.abspath(folder or ".") != here and os.path.isfile(candidate):
            _load("_pkgforge_shadowed_sitecustomize", candidate)
            break


try:
    _install()
except Exception:  # noqa: BLE001 - never stop the interpreter from starting; worker.py installs it again
    pass
