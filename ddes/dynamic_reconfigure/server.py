"""dynamic_reconfigure on the graph: ``Server(node, config_type, callback)``.

The pure rules (defaults overridden by parameters, clamping, the level
bitmask, the start-up call with all levels set, the None-return error) live
in :mod:`ddes.dynamic_reconfigure.core`; this module wires them to ROS as
``dynamic_reconfigure/server.py`` does, under the namespace (``~`` by
default):

* ``parameter_descriptions`` (latched ``dynamic_reconfigure/ConfigDescription``),
* ``parameter_updates`` (latched ``dynamic_reconfigure/Config``, after every change),
* ``set_parameters`` (service ``dynamic_reconfigure/Reconfigure``; the response
  carries the resulting config),
* the parameters themselves, written back to the parameter server.

This is the lecture's "dynamic reconfigure: local, changeable parameters".
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from ddes.dynamic_reconfigure.core import (
    Config,
    ConfigDescriptionDict,
    ConfigMsgDict,
    ConfigType,
    ParamValue,
    ReconfigureCallback,
    ReconfigureCore,
    encode_config,
    encode_description,
    reconfigure_namespace,
)
from ddes.services.server import Service

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.msg.message import Message

__all__ = ["DynamicReconfigureServer", "config_to_message"]


def _config_msg(shape: ConfigMsgDict) -> Message:
    from ddes.msg import get_message_class

    cfg = get_message_class("dynamic_reconfigure/Config")
    bp = get_message_class("dynamic_reconfigure/BoolParameter")
    ip = get_message_class("dynamic_reconfigure/IntParameter")
    sp = get_message_class("dynamic_reconfigure/StrParameter")
    dp = get_message_class("dynamic_reconfigure/DoubleParameter")
    gs = get_message_class("dynamic_reconfigure/GroupState")
    return cfg(
        bools=[bp(name=n, value=bool(v)) for n, v in shape["bools"]],
        ints=[ip(name=n, value=int(v)) for n, v in shape["ints"]],
        strs=[sp(name=n, value=str(v)) for n, v in shape["strs"]],
        doubles=[dp(name=n, value=float(v)) for n, v in shape["doubles"]],
        groups=[gs(name=g[0], state=g[1], id=g[2], parent=g[3]) for g in shape["groups"]],
    )


def config_to_message(config: Mapping[str, ParamValue], config_type: ConfigType) -> Message:
    """A ``dynamic_reconfigure/Config`` message of ``config``."""
    return _config_msg(encode_config(config, config_type))


def _description_msg(descr: ConfigDescriptionDict) -> Message:
    from ddes.msg import get_message_class

    cd = get_message_class("dynamic_reconfigure/ConfigDescription")
    group = get_message_class("dynamic_reconfigure/Group")
    pd = get_message_class("dynamic_reconfigure/ParamDescription")
    groups = [
        group(name=g["name"], type=g["type"], parent=g["parent"], id=g["id"],
              parameters=[pd(**p) for p in g["parameters"]])
        for g in descr["groups"]
    ]
    return cd(groups=groups, max=_config_msg(descr["max"]), min=_config_msg(descr["min"]),
              dflt=_config_msg(descr["dflt"]))


class DynamicReconfigureServer:
    """``dynamic_reconfigure.server.Server`` for a node (see module docstring)."""

    def __init__(self, node: Node, config_type: ConfigType, callback: ReconfigureCallback,
                 namespace: str = "~") -> None:
        from ddes.msg import get_message_class, get_service_class

        node.check_alive("create a dynamic_reconfigure server")
        self.node = node
        self.ns = node.resolve_name(reconfigure_namespace(namespace)).rstrip("/") + "/"
        self.type = config_type
        descr_cls = get_message_class("dynamic_reconfigure/ConfigDescription")
        cfg_cls = get_message_class("dynamic_reconfigure/Config")
        self._descr_pub = node.advertise(self.ns + "parameter_descriptions", descr_cls,
                                         latch=True, queue_size=1)
        self._update_pub = node.advertise(self.ns + "parameter_updates", cfg_cls,
                                          latch=True, queue_size=1)
        params = node.world.master.params
        self._descr_pub.publish(_description_msg(encode_description(config_type)))
        self.core = ReconfigureCore(
            config_type,
            callback,
            param_get=lambda name: params.get_param(self.ns + name),
            param_set=lambda name, value: params.set_param(self.ns + name, value,
                                                           caller_id=node.name),
            on_update=self._published,
        )
        self._service = Service(
            node, self.ns + "set_parameters", get_service_class("dynamic_reconfigure/Reconfigure"),
            self._handle)
        node.add_entity(self)

    @property
    def config(self) -> Config:
        """The current configuration."""
        return self.core.config

    def update_configuration(self, changes: Mapping[str, object]) -> Config:
        """Change parameters from code (rospy Server.update_configuration)."""
        return self.core.update_configuration(changes)

    def _published(self, config: Config) -> None:
        self.node.world.record("reconfigure.update", self.node.name, ns=self.ns,
                               config=dict(config))
        self._update_pub.publish(config_to_message(config, self.type))

    def _handle(self, req: Message) -> dict[str, Message]:
        shape = self.core.set_parameters(req.config)
        return {"config": _config_msg(shape)}

    def shutdown(self) -> None:
        """Remove the topics and the service (the node's shutdown does this)."""
        self._service.shutdown()
        self._descr_pub.unregister()
        self._update_pub.unregister()
        self.node.remove_entity(self)

