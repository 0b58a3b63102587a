"""pkgforge stand-in for `launch_ros.event_handlers` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

OnStateTransition = _rt.OnStateTransition

__all__ = ['OnStateTransition']
