"""Node types of ``ddes_sim``: the deterministic 2D robot (``rosrun ddes_sim simulator``).

``simulator`` reads its private parameters as Gazebo's launch arguments are passed to it::

    rosrun ddes_sim simulator _world:=single_pillar _x:=0 _y:=0 _yaw:=0 _noise:=false

``~world`` (a bundled world's name, default ``empty``) or ``~world_file`` (a ``.yaml`` or
Gazebo ``.world`` path; wins when set), ``~x``, ``~y``, ``~yaw`` (start pose), ``~noise``
(default true), ``~real_time_factor`` (1.0), ``~laser_enabled`` (true), ``~imu_rate`` (100),
``~publish_odom_tf`` (true), ``~ground_truth`` (false), ``~odom_topic`` (``odom``),
``~paused`` (false).  See docs/sim.md.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ddes.errors import DdesValueError
from ddes.nodes import NodeType
from ddes.sim import Simulator, WorldSpec

if TYPE_CHECKING:
    from ddes.graph.node import Node


def _bool(node: Node, name: str, default: bool) -> bool:
    value: Any = node.get_param("~" + name, default)
    if isinstance(value, str) and value.lower() in ("true", "false", "1", "0"):
        return value.lower() in ("true", "1")
    if isinstance(value, (bool, int)) and not isinstance(value, float):
        return bool(value)
    raise DdesValueError(f"{node.name}: parameter ~{name} must be true or false, got {value!r}")


def _float(node: Node, name: str, default: float) -> float:
    value: Any = node.get_param("~" + name, default)
    if isinstance(value, bool):
        raise DdesValueError(f"{node.name}: parameter ~{name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise DdesValueError(f"{node.name}: parameter ~{name} must be a number, "
                             f"got {value!r}") from None


def simulator(node: Node) -> None:
    """Start the simulator on ``node`` (then it spins, as gazebo does)."""
    world_file = str(node.get_param("~world_file", "") or "")
    spec = WorldSpec.load(world_file or str(node.get_param("~world", "empty")))
    Simulator(
        node.world, spec,
        x=_float(node, "x", 0.0), y=_float(node, "y", 0.0), yaw=_float(node, "yaw", 0.0),
        noise=_bool(node, "noise", True), node=node,
        real_time_factor=_float(node, "real_time_factor", 1.0),
        laser=_bool(node, "laser_enabled", True),
        imu_rate=_float(node, "imu_rate", 100.0),
        publish_odom_tf=_bool(node, "publish_odom_tf", True),
        ground_truth=_bool(node, "ground_truth", False),
        odom_topic=str(node.get_param("~odom_topic", "odom")),
        paused=_bool(node, "paused", False),
    )
    node.loginfo("ddes_sim: world %s (%d obstacles), robot at (%s, %s, yaw %s)", spec.name,
                 len(spec), node.get_param("~x", 0.0), node.get_param("~y", 0.0),
                 node.get_param("~yaw", 0.0))


NODES = {
    "simulator": NodeType(simulator, name="simulator",
                          doc="the deterministic 2D SMB: /cmd_vel in; /scan, /odom, /imu/data, "
                              "/tf, /tf_static, /clock out"),
}
