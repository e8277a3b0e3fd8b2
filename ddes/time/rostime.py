"""ROS time values: Time, Duration and their Wall variants.

The semantics are genpy's (``genpy/rostime.py``), which rospy re-exports:

* values are ``(secs, nsecs)`` canonicalised so that ``0 <= nsecs < 1e9``
  (floor division; ``secs`` carries the sign);
* a float ``secs`` is accepted only with ``nsecs == 0`` and is truncated to
  whole nanoseconds;
* a negative ``Time`` raises ``TypeError``; a ``Duration`` may be negative;
* Time+Duration -> Time, Time-Time -> Duration, Time-Duration -> Time;
  Time+Time, Time*n and friends raise ``TypeError``;
* ordering across kinds raises ``TypeError``; ``==`` across kinds is False.

``WallTime``/``WallDuration`` follow roscpp's: the same algebra, but a
separate kind, so mixing wall and ROS values raises ``TypeError``.

Deliberate additions over genpy (documented in docs/time.md): NaN, infinite
and non-numeric seconds raise a ddes error naming the value instead of the
builtin's bare message.
"""

from __future__ import annotations

import math
import numbers
from typing import TYPE_CHECKING, ClassVar, Generic, Protocol, TypeVar, overload

from ddes.errors import DdesTypeError, DdesValueError

if TYPE_CHECKING:
    from typing_extensions import Self

__all__ = [
    "DAY",
    "Duration",
    "HOUR",
    "MICROSECOND",
    "MILLISECOND",
    "MINUTE",
    "NANOSECOND",
    "SECOND",
    "TVal",
    "Time",
    "WallDuration",
    "WallTime",
]

_NS = 1_000_000_000

_T = TypeVar("_T", bound="TVal")
#: The other kind of a time class: the span of a point (Duration of Time), the point of a span.
_K = TypeVar("_K", bound="TVal")


class HasRosTime(Protocol):
    """What :meth:`Time.now` reads: a node or a clock (anything with ``get_rostime()``)."""

    def get_rostime(self) -> Time: ...


def _split_float(value: object) -> tuple[int, int]:
    """Split float seconds the way genpy does: truncate towards zero."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise DdesTypeError(
            f"time value must be a number of seconds, got {value!r} "
            f"({type(value).__name__}); pass an int or float"
        )
    f = float(value)
    if math.isnan(f) or math.isinf(f):
        raise DdesValueError(f"time value must be finite, got {value!r}")
    secs = int(f)
    nsecs = int((f - secs) * 1000000000)
    return secs, nsecs


class TVal:
    """Base of Time and Duration: ``secs``/``nsecs`` with genpy's canonical form."""

    __slots__ = ("secs", "nsecs")

    secs: int
    nsecs: int

    _kind: ClassVar[str] = "TVal"

    def __init__(self, secs: float = 0, nsecs: int = 0) -> None:
        if type(secs) is int and type(nsecs) is int:  # the common case, without ABC checks
            whole = secs
        elif isinstance(secs, numbers.Integral) and not isinstance(secs, bool):
            whole = int(secs)
            if not isinstance(nsecs, numbers.Integral) or isinstance(nsecs, bool):
                raise DdesTypeError(
                    f"nsecs must be an integer number of nanoseconds, got {nsecs!r}"
                )
            nsecs = int(nsecs)
        else:
            if nsecs != 0:
                raise DdesValueError(
                    f"if secs is a float, nsecs cannot be set (secs={secs!r}, "
                    f"nsecs={nsecs!r}); use {type(self).__name__}(secs) or "
                    f"{type(self).__name__}(int_secs, nsecs)"
                )
            whole, nsecs = _split_float(secs)
        if 0 <= nsecs < _NS:
            self.secs = whole
        else:
            carry, nsecs = divmod(nsecs, _NS)
            self.secs = whole + carry
        self.nsecs = nsecs

    # -- construction -----------------------------------------------------
    @classmethod
    def from_sec(cls: type[_T], float_secs: float) -> _T:
        """Build from float seconds (truncating to whole nanoseconds, as genpy)."""
        secs, nsecs = _split_float(float_secs)
        return cls(secs, nsecs)

    @classmethod
    def from_nsec(cls: type[_T], nsec: int) -> _T:
        """Build from an integer number of nanoseconds (exact)."""
        if type(nsec) is not int and (
                not isinstance(nsec, numbers.Integral) or isinstance(nsec, bool)):
            raise DdesTypeError(f"nanoseconds must be an int, got {nsec!r}")
        secs, nsecs = divmod(int(nsec), _NS)
        return cls(secs, nsecs)

    @classmethod
    def _from_ns(cls: type[_T], ns: int) -> _T:
        """Fast internal constructor from canonical integer nanoseconds."""
        obj = cls.__new__(cls)
        obj.secs, obj.nsecs = divmod(ns, _NS)
        return obj

    def set(self, secs: int, nsecs: int) -> None:
        """Set the fields as given (genpy ``TVal.set``; call :meth:`canon` after)."""
        self.secs = secs
        self.nsecs = nsecs

    def canon(self) -> None:
        """Bring ``nsecs`` into ``[0, 1e9)`` by carrying into ``secs``."""
        carry, self.nsecs = divmod(self.nsecs, _NS)
        self.secs += carry

    # -- conversion -----------------------------------------------------------
    def to_sec(self) -> float:
        """Float seconds."""
        return float(self.secs) + float(self.nsecs) / 1e9

    def to_nsec(self) -> int:
        """Integer nanoseconds (exact)."""
        return self.secs * _NS + self.nsecs

    def is_zero(self) -> bool:
        """True iff both fields are zero."""
        return self.secs == 0 and self.nsecs == 0

    def __bool__(self) -> bool:
        return bool(self.secs or self.nsecs)

    def __str__(self) -> str:
        return str(self.to_nsec())

    def __repr__(self) -> str:
        return f"ddes.{type(self).__name__}[{self.to_nsec()}]"

    def __hash__(self) -> int:
        return hash((self.secs, self.nsecs))

    def __reduce__(self: _T) -> tuple[type[_T], tuple[int, int]]:
        return (type(self), (self.secs, self.nsecs))

    def __copy__(self: _T) -> _T:
        return type(self)._from_ns(self.to_nsec())

    def __deepcopy__(self: _T, memo: dict[int, object]) -> _T:
        return type(self)._from_ns(self.to_nsec())

    # -- comparison ---------------------------------------------------------
    @classmethod
    def _same_kind(cls) -> type[TVal]:
        return cls

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, self._same_kind()):
            return False
        return self.secs == other.secs and self.nsecs == other.nsecs

    def __ne__(self, other: object) -> bool:
        return not self.__eq__(other)

    def __lt__(self: _T, other: _T) -> bool:
        if not isinstance(other, self._same_kind()):
            return NotImplemented
        return self.to_nsec() < other.to_nsec()

    def __le__(self: _T, other: _T) -> bool:
        if not isinstance(other, self._same_kind()):
            return NotImplemented
        return self.to_nsec() <= other.to_nsec()

    def __gt__(self: _T, other: _T) -> bool:
        if not isinstance(other, self._same_kind()):
            return NotImplemented
        return self.to_nsec() > other.to_nsec()

    def __ge__(self: _T, other: _T) -> bool:
        if not isinstance(other, self._same_kind()):
            return NotImplemented
        return self.to_nsec() >= other.to_nsec()


class _TimeBase(TVal, Generic[_K]):
    """Shared algebra of points in time (Time, WallTime); ``_K`` is the span kind."""

    __slots__ = ()

    _duration: ClassVar[type[TVal]]  # the class of _K

    def __init__(self, secs: float = 0, nsecs: int = 0) -> None:
        if type(secs) is int and type(nsecs) is int and secs >= 0 and 0 <= nsecs < _NS:
            self.secs = secs  # the common case: already canonical and not negative
            self.nsecs = nsecs
            return
        super().__init__(secs, nsecs)
        if self.secs < 0:
            raise DdesTypeError(
                f"time values must be positive (got {type(self).__name__} with "
                f"secs={self.secs}, nsecs={self.nsecs}); use a Duration for negative spans"
            )

    @classmethod
    def from_seconds(cls: type[_T], float_secs: float) -> _T:
        """Alias of :meth:`from_sec` (rospy.Time.from_seconds)."""
        return cls.from_sec(float_secs)

    def to_time(self) -> float:
        """Alias of :meth:`to_sec` (genpy.Time.to_time)."""
        return self.to_sec()

    @classmethod
    def _from_ns(cls: type[_T], ns: int) -> _T:
        if ns < 0:
            raise DdesTypeError(
                f"time values must be positive (got {ns} ns); the result of this "
                "arithmetic would be before time zero"
            )
        obj = cls.__new__(cls)
        obj.secs, obj.nsecs = divmod(ns, _NS)
        return obj

    def __add__(self, other: _K) -> Self:
        if not isinstance(other, self._duration):
            return NotImplemented
        return type(self)._from_ns(self.to_nsec() + other.to_nsec())

    __radd__ = __add__

    @overload
    def __sub__(self, other: _K) -> Self: ...
    @overload
    def __sub__(self, other: Self) -> _K: ...
    def __sub__(self, other: _K | Self) -> Self | _K:
        if isinstance(other, type(self)._same_kind()):
            return self._duration._from_ns(self.to_nsec() - other.to_nsec())  # type: ignore[return-value]
        if isinstance(other, self._duration):
            return type(self)._from_ns(self.to_nsec() - other.to_nsec())
        return NotImplemented


class _DurationBase(TVal, Generic[_K]):
    """Shared algebra of spans of time (Duration, WallDuration); ``_K`` is the point kind."""

    __slots__ = ()

    _time: ClassVar[type[TVal]]  # the class of _K

    def __neg__(self: _T) -> _T:
        return type(self)._from_ns(-self.to_nsec())

    def __pos__(self: _T) -> _T:
        return self

    def __abs__(self: _T) -> _T:
        if self.secs >= 0:
            return self
        return type(self)._from_ns(-self.to_nsec())

    @overload
    def __add__(self, other: _K) -> _K: ...
    @overload
    def __add__(self, other: Self) -> Self: ...
    def __add__(self, other: _K | Self) -> _K | Self:
        if isinstance(other, self._time):
            return other.__add__(self)  # type: ignore[operator]  # other is a _K: self._time
        if isinstance(other, type(self)._same_kind()):
            return type(self)._from_ns(self.to_nsec() + other.to_nsec())
        return NotImplemented

    __radd__ = __add__

    def __sub__(self: _T, other: _T) -> _T:
        if not isinstance(other, type(self)._same_kind()):
            return NotImplemented
        return type(self)._from_ns(self.to_nsec() - other.to_nsec())

    def __mul__(self: _T, val: float) -> _T:
        if isinstance(val, numbers.Integral):
            return type(self)._from_ns(self.to_nsec() * int(val))
        if isinstance(val, numbers.Real):
            return type(self).from_sec(self.to_sec() * float(val))
        return NotImplemented

    __rmul__ = __mul__

    @overload
    def __floordiv__(self: _T, val: _T) -> int: ...
    @overload
    def __floordiv__(self: _T, val: float) -> _T: ...
    def __floordiv__(self: _T, val: _T | float) -> int | _T:
        if isinstance(val, type(self)._same_kind()):
            return int(self.to_sec() // val.to_sec())
        if isinstance(val, numbers.Real):
            return type(self).from_sec(self.to_sec() // float(val))
        return NotImplemented

    @overload
    def __truediv__(self: _T, val: _T) -> float: ...
    @overload
    def __truediv__(self: _T, val: float) -> _T: ...
    def __truediv__(self: _T, val: _T | float) -> float | _T:
        if isinstance(val, type(self)._same_kind()):
            return self.to_sec() / val.to_sec()
        if isinstance(val, numbers.Real):
            return type(self).from_sec(self.to_sec() / float(val))
        return NotImplemented

    # % and divmod go through float seconds, exactly as genpy does.
    def __mod__(self: _T, val: _T) -> _T:
        if isinstance(val, type(self)._same_kind()):
            return type(self).from_sec(self.to_sec() % val.to_sec())
        return NotImplemented

    def __divmod__(self: _T, val: _T) -> tuple[int, _T]:
        if isinstance(val, type(self)._same_kind()):
            q, r = divmod(self.to_sec(), val.to_sec())
            return int(q), type(self).from_sec(r)
        return NotImplemented


class Time(_TimeBase["Duration"]):
    """A point in ROS time (rospy.Time / genpy.Time)."""

    __slots__ = ()

    ZERO: ClassVar[Time]
    MIN: ClassVar[Time]
    MAX: ClassVar[Time]

    @classmethod
    def _same_kind(cls) -> type[TVal]:
        return Time

    @classmethod
    def now(cls, clock: HasRosTime | None = None) -> Time:
        """Current ROS time of ``clock`` (a node, a clock or a world).

        rospy's ``Time.now()`` reads a process-wide clock; ddes has none, so
        the node (or its clock) must be passed, except in blocking code (a
        rospy script): there the node of the running greenlet is used.
        """
        if clock is None:
            # In blocking code (a rospy script, ddes.graph.blocking) the running greenlet knows
            # its node: rospy's Time.now() works there as in rospy.
            from greenlet import getcurrent

            task = getcurrent()
            clock = getattr(task, "node", None)
            if clock is None:
                if hasattr(task, "node"):  # a script before rospy.init_node: rospy's text
                    from ddes.errors import ROSInitException

                    raise ROSInitException(
                        "time is not initialized. Have you called init_node()?")
                from ddes.time.rospy_calls import missing_node

                raise missing_node("ddes.Time.now()",
                                   "ddes.Time.now(node)    # or node.get_rostime()")
        return clock.get_rostime()


class Duration(_DurationBase[Time]):
    """A span of ROS time (rospy.Duration / genpy.Duration); may be negative."""

    __slots__ = ()

    ZERO: ClassVar[Duration]
    MIN: ClassVar[Duration]
    MAX: ClassVar[Duration]

    @classmethod
    def _same_kind(cls) -> type[TVal]:
        return Duration


class WallTime(_TimeBase["WallDuration"]):
    """A point in wall time (roscpp ros::WallTime); in ddes, kernel time."""

    __slots__ = ()

    @classmethod
    def _same_kind(cls) -> type[TVal]:
        return WallTime


class WallDuration(_DurationBase[WallTime]):
    """A span of wall time (roscpp ros::WallDuration)."""

    __slots__ = ()

    @classmethod
    def _same_kind(cls) -> type[TVal]:
        return WallDuration


Time._duration = Duration
Duration._time = Time
WallTime._duration = WallDuration
WallDuration._time = WallTime

# roscpp-style constants (ros/duration.h, ros/time.h)
NANOSECOND = Duration(0, 1)
MICROSECOND = Duration(0, 1_000)
MILLISECOND = Duration(0, 1_000_000)
SECOND = Duration(1)
MINUTE = Duration(60)
HOUR = Duration(3600)
DAY = Duration(86400)

Time.ZERO = Time(0)
Time.MIN = Time(0, 1)
Time.MAX = Time(2**32 - 1, 999_999_999)
Duration.ZERO = Duration(0)
Duration.MIN = Duration(-(2**31), 0)
Duration.MAX = Duration(2**31 - 1, 999_999_999)
