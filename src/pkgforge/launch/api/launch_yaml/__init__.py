"""pkgforge stand-in for `launch_yaml` (only inside the launch worker): the real public names."""

from . import launch_description_sources  # noqa: F401


__all__ = ['launch_description_sources']
