"""pkgforge stand-in for `launch` (only inside the launch worker): the real public names."""

from pkgforge.launch import runtime as _rt
from . import actions  # noqa: F401
from . import substitutions  # noqa: F401
from . import conditions  # noqa: F401
from . import launch_description_sources  # noqa: F401
from . import event_handlers  # noqa: F401
from . import events  # noqa: F401
from . import utilities  # noqa: F401

Action = _rt.Action
Condition = _rt.Condition
Event = _rt.unsupported('Event', _rt.Action)
EventHandler = _rt.EventHandler
InvalidLaunchFileError = _rt.InvalidLaunchFileError
LaunchContext = _rt.LaunchContext
LaunchDescription = _rt.LaunchDescription
LaunchDescriptionEntity = _rt.LaunchDescriptionEntity
LaunchDescriptionSource = _rt.LaunchDescriptionSource
LaunchIntrospector = _rt.unsupported('LaunchIntrospector', _rt.Action)
LaunchService = _rt.unsupported('LaunchService', _rt.Action)
SomeEntitiesType = object
SomeEntitiesType_types_tuple = tuple
SomeSubstitutionsType = object
SomeSubstitutionsType_types_tuple = tuple
Substitution = _rt.Substitution

__all__ = ['Action', 'Condition', 'Event', 'EventHandler', 'InvalidLaunchFileError', 'LaunchContext', 'LaunchDescription', 'LaunchDescriptionEntity', 'LaunchDescriptionSource', 'LaunchIntrospector', 'LaunchService', 'SomeEntitiesType', 'SomeEntitiesType_types_tuple', 'SomeSubstitutionsType', 'SomeSubstitutionsType_types_tuple', 'Substitution', 'actions', 'substitutions', 'conditions', 'launch_description_sources', 'event_handlers', 'events', 'utilities']
