"""pkgforge stand-in for `launch.event_handlers` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

OnActionEventBase = _rt.OnActionEventBase
OnExecutionComplete = _rt.OnExecutionComplete
OnIncludeLaunchDescription = _rt.OnIncludeLaunchDescription
OnProcessExit = _rt.OnProcessExit
OnProcessIO = _rt.OnProcessIO
OnProcessStart = _rt.OnProcessStart
OnShutdown = _rt.OnShutdown
event_named = _rt.unsupported('event_named', _rt.Action)
matches_action = _rt.unsupported('matches_action', _rt.Action)

__all__ = ['OnActionEventBase', 'OnExecutionComplete', 'OnIncludeLaunchDescription', 'OnProcessExit', 'OnProcessIO', 'OnProcessStart', 'OnShutdown', 'event_named', 'matches_action']
