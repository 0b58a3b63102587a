"""pkgforge stand-in for `launch_ros.parameter_descriptions` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

Parameter = _rt.Parameter
ParameterFile = _rt.ParameterFile
ParameterValue = _rt.ParameterValue

__all__ = ['Parameter', 'ParameterFile', 'ParameterValue']
