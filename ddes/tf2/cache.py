"""tf2's per-frame caches: ``TimeCache`` (cache.cpp) and ``StaticCache`` (static_cache.cpp).

A stored transform is a :data:`Storage` tuple ``(stamp_ns, parent_id, child_id, tx, ty, tz, qx,
qy, qz, qw)``.  tf2 keeps a list sorted newest first; here the stamps are kept oldest first in a
plain list (for ``bisect``), with the same answers.  Interpolation is tf2's to the bit: the ratio
from ``ros::Duration::toSec()``, ``Vector3::setInterpolate3`` for the translation and
``Quaternion::slerp`` for the rotation, with the deterministic sin/acos of ddes.transformations.
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from math import sqrt

from ddes.transformations import acos, sin

Storage = tuple[int, int, int, float, float, float, float, float, float, float]

_NS = 1_000_000_000

OLD_DATA = ("TF_OLD_DATA ignoring data from the past (Possible reasons are listed at "
            "http://wiki.ros.org/tf/Errors%20explained)")
REPEATED_DATA = "TF_REPEATED_DATA ignoring data with redundant timestamp"


def to_sec(ns: int) -> float:
    """``ros::Time::toSec()`` / ``ros::Duration::toSec()``: sec + 1e-9 * nsec, nsec in [0, 1e9)."""
    sec, nsec = divmod(ns, _NS)
    return float(sec) + 1e-9 * float(nsec)


def _extrapolation_at(t0: int, t1: int) -> str:
    return (f"Lookup would require extrapolation at time {to_sec(t0):.9f}, "
            f"but only time {to_sec(t1):.9f} is in the buffer")


def _extrapolation_future(t0: int, t1: int) -> str:
    return (f"Lookup would require extrapolation {to_sec(t0 - t1):.9f}s into the future.  "
            f"Requested time {to_sec(t0):.9f} but the latest data is at time {to_sec(t1):.9f}")


def _extrapolation_past(t0: int, t1: int) -> str:
    return (f"Lookup would require extrapolation {to_sec(t1 - t0):.9f}s into the past.  "
            f"Requested time {to_sec(t0):.9f} but the earliest data is at time {to_sec(t1):.9f}")


def slerp(q1: tuple[float, float, float, float], q2: tuple[float, float, float, float],
          t: float) -> tuple[float, float, float, float]:
    """``tf2::Quaternion::slerp`` (LinearMath/Quaternion.h), operation for operation."""
    x1, y1, z1, w1 = q1
    x2, y2, z2, w2 = q2
    dot = x1 * x2 + y1 * y2 + z1 * z2 + w1 * w2
    s = sqrt((x1 * x1 + y1 * y1 + z1 * z1 + w1 * w1) * (x2 * x2 + y2 * y2 + z2 * z2 + w2 * w2))
    c = (-x1 * x2 + -y1 * y2 + -z1 * z2 + -w1 * w2) / s if dot < 0 else dot / s
    c = -1.0 if c < -1.0 else (1.0 if c > 1.0 else c)
    theta = (acos(c) * 2.0) / 2.0
    if theta == 0.0:
        return q1
    d = 1.0 / sin(theta)
    s0 = sin((1.0 - t) * theta)
    s1 = sin(t * theta)
    if dot < 0:
        return ((x1 * s0 + -x2 * s1) * d, (y1 * s0 + -y2 * s1) * d,
                (z1 * s0 + -z2 * s1) * d, (w1 * s0 + -w2 * s1) * d)
    return ((x1 * s0 + x2 * s1) * d, (y1 * s0 + y2 * s1) * d,
            (z1 * s0 + z2 * s1) * d, (w1 * s0 + w2 * s1) * d)


def interpolate(one: Storage, two: Storage, time: int) -> Storage:
    """``TimeCache::interpolate``: lerp the translation, slerp the rotation."""
    t0 = one[0]
    if two[0] == t0:
        return two
    # to_sec(time - t0) / to_sec(two[0] - t0), inline (int + float converts as float() does)
    sec_a, ns_a = divmod(time - t0, _NS)
    sec_b, ns_b = divmod(two[0] - t0, _NS)
    ratio = (sec_a + 1e-9 * ns_a) / (sec_b + 1e-9 * ns_b)
    s = 1.0 - ratio
    # slerp(one's rotation, two's, ratio), written out: the same operations as slerp() above
    x1, y1, z1, w1 = one[6], one[7], one[8], one[9]
    x2, y2, z2, w2 = two[6], two[7], two[8], two[9]
    dot = x1 * x2 + y1 * y2 + z1 * z2 + w1 * w2
    norms = sqrt((x1 * x1 + y1 * y1 + z1 * z1 + w1 * w1) * (x2 * x2 + y2 * y2 + z2 * z2 + w2 * w2))
    c = (-x1 * x2 + -y1 * y2 + -z1 * z2 + -w1 * w2) / norms if dot < 0 else dot / norms
    c = -1.0 if c < -1.0 else (1.0 if c > 1.0 else c)
    theta = (acos(c) * 2.0) / 2.0
    if theta != 0.0:
        d = 1.0 / sin(theta)
        s0 = sin((1.0 - ratio) * theta)
        s1 = sin(ratio * theta)
        if dot < 0:
            x2, y2, z2, w2 = -x2, -y2, -z2, -w2
        x1, y1, z1, w1 = ((x1 * s0 + x2 * s1) * d, (y1 * s0 + y2 * s1) * d,
                          (z1 * s0 + z2 * s1) * d, (w1 * s0 + w2 * s1) * d)
    return (t0, one[1], one[2],
            s * one[3] + ratio * two[3], s * one[4] + ratio * two[4], s * one[5] + ratio * two[5],
            x1, y1, z1, w1)


class TimeCache:
    """One child frame's history (``tf2::TimeCache``), pruned to ``cache_time_ns``."""

    __slots__ = ("max_storage_ns", "stamps", "entries")

    def __init__(self, max_storage_ns: int) -> None:
        self.max_storage_ns = max_storage_ns
        self.stamps: list[int] = []  # oldest first
        self.entries: list[Storage] = []

    def insert(self, new: Storage) -> str | None:
        """Insert; None on success, else tf2's error text (old or repeated data)."""
        stamps = self.stamps
        stamp = new[0]
        if stamps and stamp > stamps[-1]:
            # the usual case, a newer stamp: appended; pruneList drops what fell out of the window
            stamps.append(stamp)
            self.entries.append(new)
            oldest = stamp - self.max_storage_ns
            if stamps[0] < oldest:
                cut = bisect_left(stamps, oldest)
                del stamps[:cut]
                del self.entries[:cut]
            return None
        if stamps and stamps[-1] > stamp + self.max_storage_ns:
            return OLD_DATA
        i = bisect_right(stamps, stamp)
        if i and stamps[i - 1] == stamp:
            return REPEATED_DATA
        stamps.insert(i, stamp)
        self.entries.insert(i, new)
        # pruneList
        latest = stamps[-1]
        cut = 0
        limit = len(stamps)
        while cut < limit and stamps[cut] + self.max_storage_ns < latest:
            cut += 1
        if cut:
            del stamps[:cut]
            del self.entries[:cut]
        return None

    def find_closest(self, time: int) -> tuple[int, Storage | None, Storage | None, str]:
        """``TimeCache::findClosest``: (number of nodes, older, newer, error text)."""
        stamps = self.stamps
        if not stamps:
            return 0, None, None, ""
        if time == 0:
            return 1, self.entries[-1], None, ""
        if len(stamps) == 1:
            if stamps[0] == time:
                return 1, self.entries[0], None, ""
            return 0, None, None, _extrapolation_at(time, stamps[0])
        latest = stamps[-1]
        earliest = stamps[0]
        if time == latest:
            return 1, self.entries[-1], None, ""
        if time == earliest:
            return 1, self.entries[0], None, ""
        if time > latest:
            return 0, None, None, _extrapolation_future(time, latest)
        if time < earliest:
            return 0, None, None, _extrapolation_past(time, earliest)
        i = bisect_right(stamps, time) - 1
        return 2, self.entries[i], self.entries[i + 1], ""

    def get_data(self, time: int) -> tuple[Storage | None, str]:
        """``TimeCache::getData``: :meth:`find_closest`, then the entry or the interpolation
        (written out here: this is the lookup's inner loop)."""
        stamps = self.stamps
        if not stamps:
            return None, ""
        entries = self.entries
        if time == 0:
            return entries[-1], ""
        if len(stamps) == 1:
            if stamps[0] == time:
                return entries[0], ""
            return None, _extrapolation_at(time, stamps[0])
        latest = stamps[-1]
        if time == latest:
            return entries[-1], ""
        earliest = stamps[0]
        if time == earliest:
            return entries[0], ""
        if time > latest:
            return None, _extrapolation_future(time, latest)
        if time < earliest:
            return None, _extrapolation_past(time, earliest)
        i = bisect_right(stamps, time)
        one = entries[i - 1]
        two = entries[i]
        if one[1] == two[1]:
            return interpolate(one, two, time), ""
        return one, ""

    def get_parent(self, time: int) -> tuple[int, str]:
        """``TimeCache::getParent``: the parent of the entry :meth:`find_closest` finds first."""
        stamps = self.stamps
        if stamps and (time == 0 or stamps[0] <= time <= stamps[-1]):
            if time == 0 or time == stamps[-1]:
                return self.entries[-1][1], ""
            if time == stamps[0]:
                return self.entries[0][1], ""
            return self.entries[bisect_right(stamps, time) - 1][1], ""
        n, one, _two, error = self.find_closest(time)
        if n == 0 or one is None:
            return 0, error
        return one[1], ""

    def latest_time_and_parent(self) -> tuple[int, int]:
        if not self.stamps:
            return 0, 0
        e = self.entries[-1]
        return e[0], e[1]

    def latest_timestamp(self) -> int:
        return self.stamps[-1] if self.stamps else 0

    def oldest_timestamp(self) -> int:
        return self.stamps[0] if self.stamps else 0

    def list_length(self) -> int:
        return len(self.stamps)

    def clear(self) -> None:
        self.stamps.clear()
        self.entries.clear()


class StaticCache:
    """A static frame (``tf2::StaticCache``): one transform, valid at every time."""

    __slots__ = ("storage",)

    def __init__(self) -> None:
        self.storage: Storage = (0, 0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)

    def insert(self, new: Storage) -> str | None:
        self.storage = new
        return None

    def get_data(self, time: int) -> tuple[Storage | None, str]:
        s = self.storage
        return (time,) + s[1:], ""  # type: ignore[return-value]

    def get_parent(self, time: int) -> tuple[int, str]:
        return self.storage[1], ""

    def latest_time_and_parent(self) -> tuple[int, int]:
        return 0, self.storage[1]

    def latest_timestamp(self) -> int:
        return 0

    def oldest_timestamp(self) -> int:
        return 0

    def list_length(self) -> int:
        return 1

    def clear(self) -> None:
        """tf2's StaticCache::clearList does nothing: static transforms survive clear()."""
