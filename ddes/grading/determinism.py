"""The grading child's clocks and entropy: the same answers on every grade of a submission.

A grade of the same submission must give the same score and the same digest every time, so
what the student's code can read of the machine (its clock, its entropy, where objects lie in
memory) is pinned in the child (:mod:`ddes.grading.child`), for every module of the process:

* **clocks**: ``time.time()``, ``time_ns()``, ``monotonic()``, ``perf_counter()``,
  ``process_time()``, ``thread_time()`` and ``clock_gettime()`` (and their ``_ns`` forms),
  ``localtime()``, ``gmtime()``, ``ctime()``, ``asctime()``, ``strftime(fmt)`` without a time,
  ``datetime.datetime.now()``, ``utcnow()``, ``today()``, ``datetime.date.today()`` answer from
  the child's kernel clock: the grader's simulated instant of the step, in seconds from the
  world's start, which a date reads as 1970-01-01 00:00 UTC; the zone is UTC (``TZ=UTC``).
  The same clock a script's own ``import time`` reads (:mod:`ddes.compat.walltime`).
  ``time.sleep`` stays real (a script's own ``time.sleep`` is the kernel's).
* **entropy**: ``os.urandom``, ``os.getrandom``, ``random.SystemRandom`` and so ``secrets``,
  ``uuid.uuid4()``, NumPy's seeding (``default_rng()``, ``RandomState()``, the legacy global
  ``numpy.random.rand()``), ``random.Random()`` and ``random.seed()`` without a seed, and
  ``open("/dev/urandom")`` / ``os.open`` of it or of ``/dev/random`` answer from streams of
  the child's world (``world.rng_for("grading child <scripts> <source>")``, a stream per
  source); ``uuid.uuid1()`` takes its node from one and its time from the clock above.
* **hash order**: the child runs with ``PYTHONHASHSEED=0`` (:class:`~ddes.grading.sandbox.Sandbox`).
* **id() order**: :func:`aslr_off` (the sandbox's pre-exec step) switches address-space
  randomisation off for the child, so objects lie at the same addresses on every grade and
  ``id()``, a default ``hash()`` and a ``<... at 0x...>`` repr repeat.

The trusted code keeps the machine's clocks it needs: :mod:`ddes.kernel.runaway` took
``time.monotonic`` when ddes was imported, the sandbox's budgets run in the grader.  This is
not a boundary: code that goes looking finds the machine's clock (``threading`` took
``time.monotonic`` at its import); what is pinned is what a node reads the ordinary way.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["DEVICE_BYTES", "aslr_off", "disable_aslr", "install"]

#: What one ``open("/dev/urandom")`` reads before its end: the next bytes of its stream.
DEVICE_BYTES = 64 * 1024
_DEVICES = ("/dev/urandom", "/dev/random")
_ADDR_NO_RANDOMIZE = 0x0040000


def install(world: World, scripts: Sequence[tuple[str, Sequence[str]]]) -> None:
    """Pin the clocks and entropy of this process to ``world`` (see the module docstring);
    ``scripts`` (path in the submission, arguments) name its streams, so two nodes of one
    submission draw apart."""
    import time

    from ddes.compat import pinned, walltime

    who = " ".join(f"{path} {' '.join(args)}".strip() for path, args in scripts)

    def stream(source: str) -> Any:
        return world.rng_for(f"grading child {who} {source}")

    env = world.env

    def now_ns() -> int:
        return int(env.now)

    # -- clocks
    os.environ["TZ"] = "UTC"
    time.tzset()
    for name, fn in walltime.clock_functions(now_ns).items():
        setattr(time, name, fn)
    import _datetime
    import datetime

    date, datetime_ = pinned.datetime_classes(now_ns)
    for module in (datetime, _datetime):
        setattr(module, "date", date)  # noqa: B010 - a module's class replaced
        setattr(module, "datetime", datetime_)  # noqa: B010

    # -- entropy
    import posix
    import random

    urandom = pinned.stream_bytes(stream("os.urandom"))
    os.urandom = posix.urandom = urandom
    os.getrandom = posix.getrandom = _getrandom(pinned.stream_bytes(stream("os.getrandom")))
    random._urandom = pinned.stream_bytes(stream("random.SystemRandom"))  # type: ignore[attr-defined]
    seeds = stream("random.seed")
    real_seed = random.Random.seed

    def seed(self: random.Random, a: Any = None, version: int = 2) -> None:
        real_seed(self, seeds.getrandbits(128) if a is None else a, version)

    random.Random.seed = seed  # type: ignore[method-assign]
    random.seed = random._inst.seed  # type: ignore[attr-defined]  # bound to the old one
    _devices(stream("/dev/urandom"))
    import uuid

    uuid._generate_time_safe = None  # type: ignore[attr-defined]  # libuuid reads the machine
    uuid._node = stream("uuid.getnode").getrandbits(48) | (1 << 40)  # type: ignore[attr-defined]
    numpy_random = sys.modules.get("numpy.random")
    if numpy_random is not None:  # imported already: its global generator was seeded by then
        numpy_random.seed(stream("numpy.random").getrandbits(32))


def _getrandom(draw: Callable[[int], bytes]) -> Callable[..., bytes]:
    def getrandom(size: int, flags: int = 0) -> bytes:
        flags.__index__()
        return draw(size)

    return getrandom


def _devices(rng: Any) -> None:
    """``open`` and ``os.open`` of /dev/urandom or /dev/random: a file of the next
    :data:`DEVICE_BYTES` of ``rng`` (a memfd; a pipe where there is none)."""
    import builtins
    import io
    import posix

    real_open, real_os_open = io.open, os.open

    def device() -> int:
        data = rng.randbytes(DEVICE_BYTES)
        try:
            fd = os.memfd_create("urandom", os.MFD_CLOEXEC)
        except (AttributeError, OSError):
            r, w = os.pipe()
            os.set_inheritable(r, False)
            os.write(w, data[:65536])
            os.close(w)
            return r
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        os.lseek(fd, 0, os.SEEK_SET)
        return fd

    def open(file: Any, mode: str = "r", buffering: int = -1, encoding: str | None = None,  # noqa: A001
             errors: str | None = None, newline: str | None = None, closefd: bool = True,
             opener: Any = None) -> Any:
        if _is_device(file):
            return real_open(device(), mode, buffering, encoding, errors, newline)
        return real_open(file, mode, buffering, encoding, errors, newline, closefd, opener)

    def os_open(path: Any, flags: int, mode: int = 0o777, *, dir_fd: int | None = None) -> int:
        if dir_fd is None and _is_device(path):
            return device()
        return real_os_open(path, flags, mode, dir_fd=dir_fd)

    open.__doc__ = real_open.__doc__
    os_open.__name__ = os_open.__qualname__ = "open"
    builtins.open = io.open = open
    os.open = posix.open = os_open


def _is_device(file: Any) -> bool:
    if isinstance(file, int):
        return False
    try:
        path = os.fspath(file)
    except TypeError:
        return False
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    return "random" in path and os.path.realpath(path) in _DEVICES


def aslr_off() -> Callable[[], bool]:
    """The pre-exec step that switches address-space randomisation off for the child
    (``personality(ADDR_NO_RANDOMIZE)``, kept across ``exec``): returns True when the kernel
    took it.  libc is looked up here, before the fork, so the step itself only calls it."""
    import ctypes

    personality = ctypes.CDLL(None, use_errno=True).personality
    personality.restype = ctypes.c_int
    personality.argtypes = [ctypes.c_ulong]

    def step() -> bool:
        current = personality(0xFFFFFFFF)
        return current != -1 and personality(current | _ADDR_NO_RANDOMIZE) != -1

    return step


def disable_aslr() -> bool:
    """:func:`aslr_off`'s step, looked up and called at once."""
    return aslr_off()()
