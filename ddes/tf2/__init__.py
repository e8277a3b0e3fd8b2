"""TF: tf2's BufferCore (buffer_core.cpp, cache.cpp, static_cache.cpp of tf2 Noetic) on ddes time.

``BufferCore`` is a pure data structure (no world, no clock): the ROS side (listener, the
``Buffer`` with waits, broadcasters, tf_echo) lives in :mod:`ddes.tf2_ros`.  See docs/tf.md.
"""

from ddes.tf2.buffer_core import DEFAULT_CACHE_TIME, MAX_GRAPH_DEPTH, BufferCore
from ddes.tf2.exceptions import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
)

__all__ = [
    "DEFAULT_CACHE_TIME",
    "MAX_GRAPH_DEPTH",
    "BufferCore",
    "ConnectivityException",
    "ExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "TimeoutException",
    "TransformException",
]
