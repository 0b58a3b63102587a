"""pkgforge stand-in for `launch.events` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

Shutdown = _rt.unsupported('Shutdown', _rt.Action)
TimerEvent = _rt.unsupported('TimerEvent', _rt.Action)
IncludeLaunchDescription = _rt.unsupported('IncludeLaunchDescription', _rt.Action)
ExecutionComplete = _rt.unsupported('ExecutionComplete', _rt.Action)

__all__ = ['Shutdown', 'TimerEvent', 'IncludeLaunchDescription', 'ExecutionComplete']
