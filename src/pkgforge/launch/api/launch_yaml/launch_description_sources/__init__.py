"""pkgforge stand-in for `launch_yaml.launch_description_sources` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

YAMLLaunchDescriptionSource = _rt.YAMLLaunchDescriptionSource

__all__ = ['YAMLLaunchDescriptionSource']
