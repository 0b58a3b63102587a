"""pkgforge stand-in for `launch_ros` (only inside the launch worker): the real public names."""

from . import actions  # noqa: F401
from . import substitutions  # noqa: F401
from . import parameter_descriptions  # noqa: F401
from . import descriptions  # noqa: F401
from . import event_handlers  # noqa: F401


__all__ = ['actions', 'substitutions', 'parameter_descriptions', 'descriptions', 'event_handlers']
