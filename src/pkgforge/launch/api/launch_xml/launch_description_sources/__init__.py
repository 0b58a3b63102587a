"""pkgforge stand-in for `launch_xml.launch_description_sources` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

XMLLaunchDescriptionSource = _rt.XMLLaunchDescriptionSource

__all__ = ['XMLLaunchDescriptionSource']
