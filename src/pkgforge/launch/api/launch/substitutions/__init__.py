"""pkgforge stand-in for `launch.substitutions` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

AllSubstitution = _rt.AllSubstitution
AndSubstitution = _rt.AndSubstitution
AnySubstitution = _rt.AnySubstitution
AnonName = _rt.AnonName
Command = _rt.Command
EqualsSubstitution = _rt.EqualsSubstitution
EnvironmentVariable = _rt.EnvironmentVariable
FileContent = _rt.FileContent
FindExecutable = _rt.FindExecutable
IfElseSubstitution = _rt.IfElseSubstitution
LaunchConfiguration = _rt.LaunchConfiguration
LocalSubstitution = _rt.LocalSubstitution
NotSubstitution = _rt.NotSubstitution
NotEqualsSubstitution = _rt.NotEqualsSubstitution
OrSubstitution = _rt.OrSubstitution
PathJoinSubstitution = _rt.PathJoinSubstitution
PythonExpression = _rt.PythonExpression
SubstitutionFailure = _rt.SubstitutionFailure
TextSubstitution = _rt.TextSubstitution
ThisLaunchFile = _rt.ThisLaunchFile
ThisLaunchFileDir = _rt.ThisLaunchFileDir
LaunchLogDir = _rt.unsupported('LaunchLogDir', _rt.Substitution)

__all__ = ['AllSubstitution', 'AndSubstitution', 'AnySubstitution', 'AnonName', 'Command', 'EqualsSubstitution', 'EnvironmentVariable', 'FileContent', 'FindExecutable', 'IfElseSubstitution', 'LaunchConfiguration', 'LocalSubstitution', 'NotSubstitution', 'NotEqualsSubstitution', 'OrSubstitution', 'PathJoinSubstitution', 'PythonExpression', 'SubstitutionFailure', 'TextSubstitution', 'ThisLaunchFile', 'ThisLaunchFileDir', 'LaunchLogDir']
