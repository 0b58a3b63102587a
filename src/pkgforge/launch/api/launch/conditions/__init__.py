"""pkgforge stand-in for `launch.conditions` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

IfCondition = _rt.IfCondition
UnlessCondition = _rt.UnlessCondition
LaunchConfigurationEquals = _rt.LaunchConfigurationEquals
LaunchConfigurationNotEquals = _rt.LaunchConfigurationNotEquals
evaluate_condition_expression = _rt.evaluate_condition_expression

__all__ = ['IfCondition', 'UnlessCondition', 'LaunchConfigurationEquals', 'LaunchConfigurationNotEquals', 'evaluate_condition_expression']
