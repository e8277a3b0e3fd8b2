"""The simulation kernel: SimPy on integer nanoseconds, random streams, ids, trace.

It knows nothing of ROS; :class:`ddes.graph.World` builds the graph on it.
"""

from ddes.kernel.kernel import Kernel
from ddes.kernel.trace import Trace, TraceEvent

__all__ = ["Kernel", "Trace", "TraceEvent"]
