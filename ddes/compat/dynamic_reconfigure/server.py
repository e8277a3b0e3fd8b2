"""``dynamic_reconfigure.server.Server`` in a rospy script, on the node of the running script.

``Server(type, callback, namespace="")`` as dynamic_reconfigure's ``server.py``: the config
starts from the type's defaults overridden by the parameters under the namespace (``~`` by
default) and clamped; ``callback(config, level)`` runs once with ``level = ~0`` (-1, rospy's
start-up level) and after every change with the OR of the changed parameters' levels; the
config it returns is written back to the parameter server and published on the latched
``parameter_updates``; ``parameter_descriptions`` is latched at start; the ``set_parameters``
service (``dynamic_reconfigure/Reconfigure``) and ``update_configuration(dict)`` change it.
A callback returning None logs rospy's error and raises ``DynamicReconfigureCallbackException``.
Built on :class:`ddes.dynamic_reconfigure.DynamicReconfigureServer` (its deviations hold:
typed values, no parameter groups).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ddes.dynamic_reconfigure.core import ALL_LEVELS, Config, ConfigType
from ddes.dynamic_reconfigure.server import DynamicReconfigureServer
from ddes.errors import DynamicReconfigureCallbackException

__all__ = ["DynamicReconfigureCallbackException", "Server"]

_REPLY_NONE = "Reconfigure callback should return a possibly updated configuration."


class Server(DynamicReconfigureServer):
    """dynamic_reconfigure.server.Server on this script's node."""

    def __init__(self, type: ConfigType,  # noqa: A002 - dynamic_reconfigure's own name
                 callback: Callable[[Config, int], Any], namespace: str = "") -> None:
        from ddes.compat import rospy

        node = rospy._node()
        started = False

        def rospy_callback(config: Config, level: int) -> Any:
            result = callback(config, -1 if not started and level == ALL_LEVELS else level)
            if result is None:
                rospy.logerr(_REPLY_NONE)
            return result

        #: The user's callback (rospy's ``server.callback``).
        self.callback = callback
        super().__init__(node, type, rospy_callback, namespace)
        started = True
