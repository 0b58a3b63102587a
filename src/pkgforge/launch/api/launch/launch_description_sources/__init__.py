"""pkgforge stand-in for `launch.launch_description_sources` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

AnyLaunchDescriptionSource = _rt.AnyLaunchDescriptionSource
FrontendLaunchDescriptionSource = _rt.FrontendLaunchDescriptionSource
PythonLaunchDescriptionSource = _rt.PythonLaunchDescriptionSource
InvalidLaunchFileError = _rt.InvalidLaunchFileError
InvalidFrontendLaunchFileError = _rt.InvalidLaunchFileError
InvalidPythonLaunchFileError = _rt.InvalidLaunchFileError
get_launch_description_from_any_launch_file = _rt.load_description_function
get_launch_description_from_python_launch_file = _rt.load_description_function
get_launch_description_from_frontend_launch_file = _rt.load_description_function
load_python_launch_file_as_module = _rt.unsupported('load_python_launch_file_as_module', _rt.Action)

__all__ = ['AnyLaunchDescriptionSource', 'FrontendLaunchDescriptionSource', 'PythonLaunchDescriptionSource', 'InvalidLaunchFileError', 'InvalidFrontendLaunchFileError', 'InvalidPythonLaunchFileError', 'get_launch_description_from_any_launch_file', 'get_launch_description_from_python_launch_file', 'get_launch_description_from_frontend_launch_file', 'load_python_launch_file_as_module']
