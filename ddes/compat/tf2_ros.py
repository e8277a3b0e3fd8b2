"""tf2_ros's Python API in a rospy script: ``import tf2_ros`` (docs/tf.md).

As in tf2_ros the objects take no node: ``tf2_ros.TransformListener(buffer)``,
``tf2_ros.TransformBroadcaster()``, ``tf2_ros.StaticTransformBroadcaster()`` act on the node of
the running script (:mod:`ddes.compat.rospy`).  ``tf2_ros.Buffer(cache_time=None, debug=True)``
is :class:`ddes.tf2_ros.Buffer` with tf2_ros's default ``debug=True`` (it advertises
``~tf2_frames`` once the script has a node); its ``lookup_transform(..., timeout)``,
``can_transform(..., timeout)`` and ``transform(..., timeout)`` block the calling node on
simulated time until the transform is available or the timeout has passed, then answer as
tf2_ros does.  The exceptions are tf2's.

``Buffer.transform`` / ``transform_full`` take the types registered with the world's
:class:`TransformRegistration`, as tf2_ros's ``BufferInterface`` does: none until the script (or
another script of the world) has imported ``tf2_geometry_msgs``, which registers
``PointStamped``, ``PoseStamped``, ``Vector3Stamped`` and ``WrenchStamped``
(:mod:`ddes.compat.tf2_geometry_msgs`); another type raises tf2_ros's ``TypeException('Type
<class> if not loaded or supported')``.  Deviations: the registry is the world's, not the
process's (two worlds in one process do not share it; ROS's is a class attribute); a Buffer used
outside any ddes script or world takes the three types of :class:`ddes.tf2_ros.Buffer`;
``new_type`` other than the object's own type raises ``TypeException`` (tf2_ros's
``ConvertRegistration`` is not provided), ``new_type`` of the object's type returns a copy, as
tf2_ros's ``convert`` does.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ddes.compat.rospy import _node
from ddes.errors import DdesValueError
from ddes.graph.blocking import current_node, current_task
from ddes.tf2_ros import (
    DEFAULT_CAN_TRANSFORM_POLLING_SCALE,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
    TypeException,
)
from ddes.tf2_ros import Buffer as _Buffer
from ddes.tf2_ros import StaticTransformBroadcaster as _StaticTransformBroadcaster
from ddes.tf2_ros import TransformBroadcaster as _TransformBroadcaster
from ddes.tf2_ros import TransformListener as _TransformListener
from ddes.tf2_ros.geometry import transform_function

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["DEFAULT_CAN_TRANSFORM_POLLING_SCALE", "Buffer", "ConnectivityException",
           "ExtrapolationException", "InvalidArgumentException", "LookupException",
           "StaticTransformBroadcaster", "TimeoutException", "TransformBroadcaster",
           "TransformException", "TransformListener", "TransformRegistration", "TypeException",
           "transform_registry"]

_REGISTRY_KEY = "compat.tf2_ros.registration"


class _Registry:
    """A world's tf2_ros registrations: message class -> its ``do_transform``, and the modules
    that have registered their types (``tf2_geometry_msgs`` registers once per world, as its
    module body runs once per process on ROS)."""

    __slots__ = ("loaded", "transforms")

    def __init__(self) -> None:
        self.transforms: dict[Any, Callable[[Any, Any], Any]] = {}
        self.loaded: set[str] = set()


def transform_registry(world: World) -> _Registry:
    """The tf2_ros registrations of ``world`` (made empty on first use)."""
    return world.extension(_REGISTRY_KEY, lambda _w: _Registry())


def _running_world() -> World | None:
    task = current_task()
    return task.world if task is not None else None


def _type_exception(key: Any) -> TypeException:
    return TypeException("Type %s if not loaded or supported" % str(key))  # noqa: UP031


class TransformRegistration:
    """tf2_ros.TransformRegistration(): ``add(type, callback)``, ``get(type)`` (the running
    world's registry, where ROS keeps one per process)."""

    def __init__(self) -> None:
        world = _running_world()
        if world is None:
            raise DdesValueError(
                "tf2_ros.TransformRegistration() keeps the registrations of the running world: "
                "make it in a rospy script's code (ddes.compat.scripts.run_script)")
        self._registry = transform_registry(world)

    def print_me(self) -> None:
        """Print the registry (tf2_ros's debugging aid)."""
        print(self._registry.transforms)  # noqa: T201 - tf2_ros's own print

    def add(self, key: Any, callback: Callable[[Any, Any], Any]) -> None:
        """Register ``callback(object_stamped, transform)`` for the message class ``key``."""
        self._registry.transforms[key] = callback

    def get(self, key: Any) -> Callable[[Any, Any], Any]:
        """The callback of ``key``, or tf2_ros's TypeException."""
        fn = self._registry.transforms.get(key)
        if fn is None:
            raise _type_exception(key)
        return fn


class Buffer(_Buffer):
    """tf2_ros.Buffer(cache_time=None, debug=True): waits block the script's node."""

    def __init__(self, cache_time: Any = None, debug: bool = True) -> None:
        super().__init__(cache_time, debug, node=current_node())
        self._world = _running_world()
        self.registration: TransformRegistration | None = (
            TransformRegistration() if self._world is not None else None)

    def _transform_function(self, object_stamped: Any) -> Callable[[Any, Any], Any]:
        world = self._world or (self.node.world if self.node is not None else None)
        if world is None:
            world = _running_world()
        if world is None:  # outside any script and world: ddes.tf2_ros.Buffer's three types
            return transform_function(object_stamped)
        fn = transform_registry(world).transforms.get(type(object_stamped))
        if fn is None:
            raise _type_exception(type(object_stamped))
        return fn

    def transform(self, object_stamped: Any, target_frame: str, timeout: Any = None,
                  new_type: Any = None) -> Any:
        """tf2_ros ``transform``: a registered type in ``target_frame`` at its header's stamp."""
        do_transform = self._transform_function(object_stamped)
        t = self.lookup_transform(target_frame, object_stamped.header.frame_id,
                                  object_stamped.header.stamp, timeout)
        return _convert(do_transform(object_stamped, t), new_type)

    def transform_full(self, object_stamped: Any, target_frame: str, target_time: Any,
                       fixed_frame: str, timeout: Any = None, new_type: Any = None) -> Any:
        """tf2_ros ``transform_full`` (a target time and a fixed frame)."""
        do_transform = self._transform_function(object_stamped)
        t = self.lookup_transform_full(target_frame, target_time, object_stamped.header.frame_id,
                                       object_stamped.header.stamp, fixed_frame, timeout)
        return _convert(do_transform(object_stamped, t), new_type)


def _convert(res: Any, new_type: Any) -> Any:
    """tf2_ros's ``convert`` for the one conversion ddes has: to the same type, a copy."""
    if not new_type:
        return res
    if type(res) is new_type:
        return copy.deepcopy(res)
    raise TypeException(
        f"Type {new_type} if not loaded or supported (ddes converts to no other type: leave "
        "new_type None)")


class TransformListener(_TransformListener):
    """tf2_ros.TransformListener(buffer, queue_size=None, buff_size=65536, tcp_nodelay=False)."""

    def __init__(self, buffer: Any, queue_size: int | None = None, buff_size: int = 65536,
                 tcp_nodelay: bool = False) -> None:
        super().__init__(_node(), buffer, queue_size, buff_size, tcp_nodelay)


class TransformBroadcaster(_TransformBroadcaster):
    """tf2_ros.TransformBroadcaster(): /tf of the script's node."""

    def __init__(self) -> None:
        super().__init__(_node())


class StaticTransformBroadcaster(_StaticTransformBroadcaster):
    """tf2_ros.StaticTransformBroadcaster(): latched /tf_static of the script's node."""

    def __init__(self) -> None:
        super().__init__(_node())
