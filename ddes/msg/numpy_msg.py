"""rospy's ``numpy_msg``: a message class whose numeric arrays are numpy arrays.

``numpy_msg(LaserScan)`` returns a subclass (same ``_type``, ``_md5sum`` and
wire bytes) whose generated deserializer reads every numeric array field
(``float32[]``, ``int16[3]``, ... in nested messages too; not ``bool[]`` and
not ``uint8[]``/``char[]``, which stay ``bytes`` as in rospy) as a read-only
``numpy.frombuffer`` view of the received bytes, and whose serializer writes
such a field with ``numpy.asarray(value, dtype).tobytes()``.  It is opt-in:
numpy is imported only when ``numpy_msg`` is first called (numpy is not a
dependency of ddes; ``pip install numpy``).  Deviation from plain classes: a
float64 value outside float32's range is written as ``inf`` by numpy where the
plain class raises, as rospy's numpy_msg does.
"""

from __future__ import annotations

from typing import TypeVar

from ddes.errors import DdesTypeError
from ddes.msg.message import Message

__all__ = ["numpy_msg"]

M = TypeVar("M", bound=Message)

_CACHE: dict[type[Message], type[Message]] = {}


def numpy_msg(cls: type[M]) -> type[M]:
    """The numpy form of message class ``cls`` (built once, then cached)."""
    if not (isinstance(cls, type) and issubclass(cls, Message)):
        raise DdesTypeError(f"numpy_msg({cls!r}): expected a message class such as "
                            "sensor_msgs.msg.LaserScan")
    done = _CACHE.get(cls)
    if done is not None:
        return done  # type: ignore[return-value]
    if getattr(cls, "_numpy", False):
        return cls
    import numpy  # optional: only this opt-in path needs it

    from ddes.msg.codegen import generate_message_class

    spec = cls._spec
    if spec is None:
        raise DdesTypeError(f"numpy_msg({cls.__name__}): it has no message definition; pass "
                            "a class from get_message_class or a msg module")
    nested = {i.base_type: i.cls for i in cls._fields_info if i.cls is not None}
    built = generate_message_class(spec, cls._md5sum, cls._full_text,
                                   nested.__getitem__, numpy)
    built._numpy = True  # type: ignore[attr-defined]
    _CACHE[cls] = built
    return built  # type: ignore[return-value]
