"""dynamic_reconfigure: local, changeable parameters (lecture 3).

:mod:`ddes.dynamic_reconfigure.core` is the pure server (config types, clamping,
levels, the message shapes); :mod:`ddes.dynamic_reconfigure.server` wires it
to the latched ``parameter_descriptions``/``parameter_updates`` topics and the
``set_parameters`` service of a node.  See docs/parameters.md.
"""

from ddes.dynamic_reconfigure.core import (
    ALL_LEVELS,
    ConfigType,
    ParameterGenerator,
    ReconfigureCore,
    bool_t,
    double_t,
    int_t,
    str_t,
)
from ddes.dynamic_reconfigure.server import DynamicReconfigureServer, config_to_message

__all__ = [
    "ALL_LEVELS",
    "ConfigType",
    "DynamicReconfigureServer",
    "ParameterGenerator",
    "ReconfigureCore",
    "bool_t",
    "config_to_message",
    "double_t",
    "int_t",
    "str_t",
]
