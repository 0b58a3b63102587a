"""Importing this module imports every check module, so all checks are registered."""

from . import build, files, install, launch, manifest, migrate, model, nodes, physics, rviz, sandbox  # noqa: F401
