"""pkgforge stand-in for `launch_ros.descriptions` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

ComposableNode = _rt.ComposableNode
Parameter = _rt.Parameter
ParameterFile = _rt.ParameterFile
ParameterValue = _rt.ParameterValue
ComposableLifecycleNode = _rt.unsupported('ComposableLifecycleNode', _rt.Action)

__all__ = ['ComposableNode', 'Parameter', 'ParameterFile', 'ParameterValue', 'ComposableLifecycleNode']
