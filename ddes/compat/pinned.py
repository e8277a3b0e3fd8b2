"""Clocks and entropy pinned to a world: what a script's ``random`` and ``datetime`` answer.

A script's ``time`` is the kernel clock (:mod:`ddes.compat.walltime`); its ``random`` and
``datetime`` follow the same rule here, so a node that draws a number or stamps a date does the
same on every run of the same seed (docs/determinism.md):

* :func:`random_module`: ``random`` of one script: its module-level functions (``random()``,
  ``randint``, ``choice``, ``gauss``, ``seed`` ...) draw from a stream of the world
  (``world.rng_for("script random <name>")``); ``Random()`` with no seed and ``seed()`` with no
  argument take their seed from the next draw of a stream instead of the operating system;
  ``SystemRandom`` draws from a stream too.  Everything else is the real module.
* :func:`datetime_module`: ``datetime`` of one script: ``datetime.now()``, ``utcnow()``,
  ``today()``, ``date.today()`` and ``fromtimestamp(t)`` read the kernel clock, counted from
  1970-01-01, in UTC (the local zone of a view is UTC, so no machine's zone reaches a trace).
  ``isinstance`` and arithmetic mix with the real classes' objects.

The grading child (:mod:`ddes.grading.determinism`) builds its process-wide answers from the
same pieces: :func:`datetime_classes`, :func:`stream_bytes`, :func:`seeding_random`.
"""

from __future__ import annotations

import _datetime
import random as _random
import types

# the real classes, taken at import (the grading child puts its own in the modules' place)
from _datetime import date as _RealDate
from _datetime import datetime as _RealDatetime
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["datetime_classes", "datetime_module", "random_module", "seeding_random",
           "stream_bytes", "system_random"]

_REAL_DATETIME = _RealDatetime
_REAL_DATE = _RealDate
_TIMEDELTA = _datetime.timedelta
_EPOCH = _REAL_DATETIME(1970, 1, 1)


def stream_bytes(rng: _random.Random) -> Callable[[int], bytes]:
    """``urandom(n)`` answered from ``rng``: its next ``n`` bytes, as ``os.urandom`` checks
    its argument."""

    def urandom(size: int, /) -> bytes:
        n = size.__index__()
        if n < 0:
            raise ValueError("negative argument not allowed")
        return rng.randbytes(n)

    urandom.__name__ = urandom.__qualname__ = "urandom"
    return urandom


def seeding_random(seeds: _random.Random) -> type[_random.Random]:
    """A ``random.Random`` whose ``seed()`` with no value (and so ``Random()``) takes the next
    draw of ``seeds`` instead of the operating system's entropy."""

    class Random(_random.Random):
        def seed(self, a: Any = None, version: int = 2) -> None:
            super().seed(seeds.getrandbits(128) if a is None else a, version)

    Random.__module__ = "random"
    return Random


def system_random(rng: _random.Random) -> type[_random.SystemRandom]:
    """``random.SystemRandom`` drawing from ``rng`` instead of the operating system."""
    urandom = stream_bytes(rng)

    class SystemRandom(_random.SystemRandom):
        def random(self) -> float:
            return (int.from_bytes(urandom(7), "big") >> 3) * (2.0 ** -53)

        def getrandbits(self, k: int) -> int:
            if k < 0:
                raise ValueError("number of bits must be non-negative")
            numbytes = (k + 7) // 8
            return int.from_bytes(urandom(numbytes), "big") >> (numbytes * 8 - k)

        def randbytes(self, n: int) -> bytes:
            return urandom(n)

    SystemRandom.__module__ = "random"
    return SystemRandom


class _ModuleView(types.ModuleType):
    """A module whose missing attributes are those of the real one."""

    def __init__(self, name: str, real: types.ModuleType) -> None:
        super().__init__(name)
        self.__dict__["_real"] = real

    def __getattr__(self, name: str) -> Any:
        return getattr(self.__dict__["_real"], name)


def random_module(world: World, name: str) -> types.ModuleType:
    """``random`` as the script ``name`` of ``world`` sees it (see the module docstring)."""
    view = _ModuleView("random", _random)
    Random = seeding_random(world.rng_for(f"script random {name} seeds"))  # noqa: N806
    inst = Random(world.rng_for(f"script random {name}").getrandbits(128))
    real = _random._inst  # type: ignore[attr-defined]  # the module's hidden instance
    for attr in dir(_random):
        fn = getattr(_random, attr)
        if getattr(fn, "__self__", None) is real:
            setattr(view, attr, getattr(inst, attr))
    view.Random = Random  # type: ignore[attr-defined]
    view.SystemRandom = system_random(world.rng_for(f"script random {name} system"))  # type: ignore[attr-defined]
    return view


def _module_class(name: str) -> Any:
    """``datetime.<name>`` as the ``datetime`` module has it now (what pickle looks up)."""
    import datetime

    return getattr(datetime, name)


def datetime_classes(now_ns: Callable[[], int]) -> tuple[type[_datetime.date],
                                                          type[_datetime.datetime]]:
    """``(date, datetime)``: subclasses of the real classes whose ``now()``, ``utcnow()``,
    ``today()`` and ``fromtimestamp(t)`` (without a zone) answer from ``now_ns()`` (ns since
    1970-01-01) in UTC.  ``isinstance(x, date)`` holds for real dates too (as
    freezegun does it), and their objects compute with the real classes' ones."""

    class _Meta(type):
        def __instancecheck__(cls, obj: object) -> bool:
            return isinstance(obj, cls._real)  # type: ignore[attr-defined]

        def __subclasscheck__(cls, sub: type) -> bool:
            return issubclass(sub, cls._real)  # type: ignore[attr-defined]

    def _utc(ns: int) -> _datetime.datetime:
        return _EPOCH + _TIMEDELTA(microseconds=ns // 1000)

    class date(_RealDate, metaclass=_Meta):  # noqa: N801 - the real class's name
        _real = _REAL_DATE

        @classmethod
        def today(cls) -> Any:
            d = _utc(now_ns())
            return cls(d.year, d.month, d.day)

        @classmethod
        def fromtimestamp(cls, t: float) -> Any:
            d = _REAL_DATETIME.utcfromtimestamp(t)
            return cls(d.year, d.month, d.day)

        def __repr__(self) -> str:  # the real class's: datetime.date(...)
            return "datetime." + super().__repr__()

        def __reduce_ex__(self, protocol: Any) -> Any:  # pickled as datetime.date
            return (_module_class("date"), super().__reduce_ex__(protocol)[1])

    class datetime(_RealDatetime, metaclass=_Meta):  # noqa: N801 - the real class's name
        _real = _REAL_DATETIME

        @classmethod
        def _make(cls, d: _datetime.datetime) -> Any:
            return cls(d.year, d.month, d.day, d.hour, d.minute, d.second, d.microsecond,
                       d.tzinfo, fold=d.fold)

        @classmethod
        def now(cls, tz: _datetime.tzinfo | None = None) -> Any:
            d = _utc(now_ns())
            return cls._make(d if tz is None else tz.fromutc(d.replace(tzinfo=tz)))

        @classmethod
        def utcnow(cls) -> Any:
            return cls._make(_utc(now_ns()))

        @classmethod
        def today(cls) -> Any:
            return cls.now()

        @classmethod
        def fromtimestamp(cls, t: float, tz: _datetime.tzinfo | None = None) -> Any:
            if tz is None:
                return cls._make(_REAL_DATETIME.utcfromtimestamp(t))
            return cls._make(_REAL_DATETIME.fromtimestamp(t, tz))

        def __repr__(self) -> str:  # the real class's: datetime.datetime(...)
            return "datetime." + super().__repr__()

        def __reduce_ex__(self, protocol: Any) -> Any:  # pickled as datetime.datetime
            return (_module_class("datetime"), super().__reduce_ex__(protocol)[1])

    for cls in (date, datetime):  # pickled (and named) as the real class
        cls.__module__ = "datetime"
        cls.__qualname__ = cls.__name__
    return date, datetime


def datetime_module(now_ns: Callable[[], int]) -> types.ModuleType:
    """``datetime`` of a script: the real module with :func:`datetime_classes`."""
    import datetime as real

    view = _ModuleView("datetime", real)
    view.date, view.datetime = datetime_classes(now_ns)  # type: ignore[attr-defined]
    return view
