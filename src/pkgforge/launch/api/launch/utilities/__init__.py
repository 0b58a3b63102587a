"""pkgforge stand-in for `launch.utilities` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt

perform_substitutions = _rt.perform
normalize_to_list_of_substitutions = _rt.normalize

__all__ = ['perform_substitutions', 'normalize_to_list_of_substitutions']
