"""pkgforge stand-in for `launch_ros.actions` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

ComposableNodeContainer = _rt.ComposableNodeContainer
LifecycleNode = _rt.LifecycleNode
LoadComposableNodes = _rt.LoadComposableNodes
Node = _rt.Node
PushRosNamespace = _rt.PushRosNamespace
RosTimerAction = _rt.RosTimerAction
SetParameter = _rt.SetParameter
SetParametersFromFile = _rt.SetParametersFromFile
SetRemap = _rt.SetRemap
SetUseSimTime = _rt.SetUseSimTime
PushROSNamespace = _rt.PushRosNamespace
LifecycleTransition = _rt.unsupported('LifecycleTransition', _rt.Action)

__all__ = ['ComposableNodeContainer', 'LifecycleNode', 'LoadComposableNodes', 'Node', 'PushRosNamespace', 'RosTimerAction', 'SetParameter', 'SetParametersFromFile', 'SetRemap', 'SetUseSimTime', 'PushROSNamespace', 'LifecycleTransition']
