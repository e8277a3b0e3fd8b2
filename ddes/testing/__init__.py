"""Testing helpers shipped with ddes: hypothesis strategies for messages, protocol machines,
and :func:`strict_worlds` (worlds whose ``run()`` raises the first error of user code)."""

from ddes.graph.failures import strict_worlds
from ddes.testing.actions import ActionProtocolMachine, ProtocolViolation, run_protocol_machine
from ddes.testing.strategies import durations, field_values, messages, times

__all__ = ["ActionProtocolMachine", "ProtocolViolation", "durations", "field_values", "messages",
           "run_protocol_machine", "strict_worlds", "times"]
