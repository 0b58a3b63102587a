"""pkgforge: scaffold and verify ROS 2 robot description packages."""

__version__ = "0.1.0"
# The distribution's name on PyPI (the command and the import package are `pkgforge`; the PyPI
# name `pkgforge` belongs to an unrelated project). Generated CI files install DISTRIBUTION==__version__.
DISTRIBUTION = "ros-pkgforge"
