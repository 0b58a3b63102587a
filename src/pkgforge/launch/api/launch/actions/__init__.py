"""pkgforge stand-in for `launch.actions` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

AppendEnvironmentVariable = _rt.AppendEnvironmentVariable
DeclareLaunchArgument = _rt.DeclareLaunchArgument
EmitEvent = _rt.EmitEvent
ExecuteLocal = _rt.ExecuteLocal
ExecuteProcess = _rt.ExecuteProcess
GroupAction = _rt.GroupAction
IncludeLaunchDescription = _rt.IncludeLaunchDescription
ScopedIncludeLaunchDescription = _rt.ScopedIncludeLaunchDescription
LogInfo = _rt.LogInfo
OpaqueFunction = _rt.OpaqueFunction
PopLaunchConfigurations = _rt.PopLaunchConfigurations
PushLaunchConfigurations = _rt.PushLaunchConfigurations
ResetLaunchConfigurations = _rt.ResetLaunchConfigurations
RegisterEventHandler = _rt.RegisterEventHandler
SetEnvironmentVariable = _rt.SetEnvironmentVariable
SetLaunchConfiguration = _rt.SetLaunchConfiguration
Shutdown = _rt.Shutdown
TimerAction = _rt.TimerAction
UnsetEnvironmentVariable = _rt.UnsetEnvironmentVariable
UnsetLaunchConfiguration = _rt.UnsetLaunchConfiguration
ForEach = _rt.unsupported('ForEach', _rt.Action)
ForLoop = _rt.unsupported('ForLoop', _rt.Action)
OpaqueCoroutine = _rt.unsupported('OpaqueCoroutine', _rt.Action)
PopEnvironment = _rt.unsupported('PopEnvironment', _rt.Action)
PushEnvironment = _rt.unsupported('PushEnvironment', _rt.Action)
ResetEnvironment = _rt.unsupported('ResetEnvironment', _rt.Action)
UnregisterEventHandler = _rt.unsupported('UnregisterEventHandler', _rt.Action)

__all__ = ['AppendEnvironmentVariable', 'DeclareLaunchArgument', 'EmitEvent', 'ExecuteLocal', 'ExecuteProcess', 'GroupAction', 'IncludeLaunchDescription', 'ScopedIncludeLaunchDescription', 'LogInfo', 'OpaqueFunction', 'PopLaunchConfigurations', 'PushLaunchConfigurations', 'ResetLaunchConfigurations', 'RegisterEventHandler', 'SetEnvironmentVariable', 'SetLaunchConfiguration', 'Shutdown', 'TimerAction', 'UnsetEnvironmentVariable', 'UnsetLaunchConfiguration', 'ForEach', 'ForLoop', 'OpaqueCoroutine', 'PopEnvironment', 'PushEnvironment', 'ResetEnvironment', 'UnregisterEventHandler']
