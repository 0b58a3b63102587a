"""pkgforge stand-in for `launch_ros.substitutions` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

ExecutableInPackage = _rt.ExecutableInPackage
FindPackage = _rt.FindPackage
FindPackagePrefix = _rt.FindPackagePrefix
FindPackageShare = _rt.FindPackageShare
FindPackageFile = _rt.FindPackageFile
Parameter = _rt.unsupported('Parameter', _rt.Action)

__all__ = ['ExecutableInPackage', 'FindPackage', 'FindPackagePrefix', 'FindPackageShare', 'FindPackageFile', 'Parameter']
