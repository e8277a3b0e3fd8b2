"""Testing helpers shipped with ddes: hypothesis strategies for messages."""

from ddes.testing.strategies import durations, field_values, messages, times

__all__ = ["durations", "field_values", "messages", "times"]
