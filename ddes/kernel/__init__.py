"""The simulation kernel: World (SimPy on integer nanoseconds), RNG and trace."""

from ddes.kernel.trace import Trace, TraceEvent
from ddes.kernel.world import World, to_ns

__all__ = ["Trace", "TraceEvent", "World", "to_ns"]
