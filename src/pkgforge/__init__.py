"""pkgforge: scaffold and verify ROS 2 robot description packages."""

__version__ = "0.1.0"
