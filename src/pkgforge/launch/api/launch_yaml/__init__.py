"""pkgforge stand-in for `launch_yaml` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt
from . import launch_description_sources  # noqa: F401


__all__ = ['launch_description_sources']
