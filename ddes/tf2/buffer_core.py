"""``BufferCore``: tf2 Noetic's buffer_core.cpp with tf2_py's Python method names.

Every rule, text and number is tf2's (0.7.x, as Debian and ROS Noetic ship it): the frame-id
table (frame numbers in order of first sight, child before parent), one cache per child frame,
``walkToTopParent`` with its early outs and ``MAX_GRAPH_DEPTH``, ``getLatestCommonTime``, the
``TransformAccum`` arithmetic (quaternion products and ``quatRotate``, so results agree with tf2
to the last bit), and for ``lookup_transform_full_core`` the composition through
``tf2::Transform`` (a rotation matrix and ``Matrix3x3::getRotation``, which fixes the
quaternion's sign as tf2's does).  Times are integer nanoseconds inside; arguments are ddes
``Time`` values (or seconds).  Warnings and errors (tf2's texts) go through
:meth:`BufferCore._log`: the ``ddes.tf2`` logger, or, for a ``ddes.tf2_ros.Buffer`` on a node,
the node's log (/rosout and the console).

Every insertion goes through :meth:`BufferCore.set_transform` or
:meth:`BufferCore.set_transform_static`; :class:`ddes.tf2_ros.Buffer` overrides them to wake
its waiters.
"""

from __future__ import annotations

import logging
import math
from typing import Any

from ddes.tf2.cache import StaticCache, Storage, TimeCache, to_sec
from ddes.tf2.exceptions import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TransformException,
)
from ddes.time.rostime import Duration, Time
from ddes.time.units import DurationLike, TimeLike, duration_to_ns, time_to_ns

__all__ = ["DEFAULT_CACHE_TIME", "MAX_GRAPH_DEPTH", "BufferCore"]

log = logging.getLogger("ddes.tf2")

#: tf2::BufferCore::DEFAULT_CACHE_TIME, seconds.
DEFAULT_CACHE_TIME = 10
#: tf2::BufferCore::MAX_GRAPH_DEPTH: a walk longer than this is a loop.
MAX_GRAPH_DEPTH = 1000
#: buffer_core.cpp's QUATERNION_NORMALIZATION_TOLERANCE (sic: 10e-3).
QUATERNION_NORMALIZATION_TOLERANCE = 10e-3

# tf2_msgs/TF2Error codes
NO_ERROR = 0
LOOKUP_ERROR = 1
CONNECTIVITY_ERROR = 2
EXTRAPOLATION_ERROR = 3

# walk endings
_IDENTITY, _TARGET_PARENT_OF_SOURCE, _SOURCE_PARENT_OF_TARGET, _FULL_PATH = range(4)

_MESSAGE_CLASS: list[Any] = []

Vec = tuple[float, float, float]
Quat = tuple[float, float, float, float]


_new = object.__new__
_NS = 1_000_000_000


def _message_classes() -> list[Any]:
    """[TransformStamped, Header, Transform, Vector3, Quaternion]: the result's classes."""
    if not _MESSAGE_CLASS:
        from ddes.msg import get_message_class

        cls = get_message_class("geometry_msgs/TransformStamped")
        default = cls()
        _MESSAGE_CLASS.extend((cls, type(default.header), type(default.transform),
                               type(default.transform.translation),
                               type(default.transform.rotation)))
    return _MESSAGE_CLASS


def _strip_slash(name: str) -> str:
    return name[1:] if name.startswith("/") else name


def _qmul(a: Quat, b: Quat) -> Quat:
    """tf2 ``operator*(Quaternion, Quaternion)``."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by + ay * bw + az * bx - ax * bz,
            aw * bz + az * bw + ax * by - ay * bx,
            aw * bw - ax * bx - ay * by - az * bz)


def _quat_rotate(q: Quat, v: Vec) -> Vec:
    """tf2 ``quatRotate``: (q * v) *= q.inverse(), term for term."""
    qx, qy, qz, qw = q
    vx, vy, vz = v
    px = qw * vx + qy * vz - qz * vy
    py = qw * vy + qz * vx - qx * vz
    pz = qw * vz + qx * vy - qy * vx
    pw = -qx * vx - qy * vy - qz * vz
    ix, iy, iz = -qx, -qy, -qz
    return (pw * ix + px * qw + py * iz - pz * iy,
            pw * iy + py * qw + pz * ix - px * iz,
            pw * iz + pz * qw + px * iy - py * ix)


def _accumulate(st: Storage, acc_q: Quat, acc_v: Vec) -> tuple[Quat, Vec]:
    """TransformAccum's step: v = quatRotate(q, v) + t, q = q * q_acc (``_quat_rotate`` and
    ``_qmul`` written out term for term, same operations in the same order)."""
    qx, qy, qz, qw = st[6], st[7], st[8], st[9]
    vx, vy, vz = acc_v
    px = qw * vx + qy * vz - qz * vy
    py = qw * vy + qz * vx - qx * vz
    pz = qw * vz + qx * vy - qy * vx
    pw = -qx * vx - qy * vy - qz * vz
    ix, iy, iz = -qx, -qy, -qz
    bx, by, bz, bw = acc_q
    return ((qw * bx + qx * bw + qy * bz - qz * by,
             qw * by + qy * bw + qz * bx - qx * bz,
             qw * bz + qz * bw + qx * by - qy * bx,
             qw * bw - qx * bx - qy * by - qz * bz),
            (pw * ix + px * qw + py * iz - pz * iy + st[3],
             pw * iy + py * qw + pz * ix - px * iz + st[4],
             pw * iz + pz * qw + px * iy - py * ix + st[5]))


def _matrix(q: Quat) -> list[Vec]:
    """``Matrix3x3::setRotation``."""
    x, y, z, w = q
    d = x * x + y * y + z * z + w * w
    s = 2.0 / d
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return [(1.0 - (yy + zz), xy - wz, xz + wy),
            (xy + wz, 1.0 - (xx + zz), yz - wx),
            (xz - wy, yz + wx, 1.0 - (xx + yy))]


def _get_rotation(m: list[Vec]) -> Quat:
    """``Matrix3x3::getRotation``."""
    trace = m[0][0] + m[1][1] + m[2][2]
    temp = [0.0, 0.0, 0.0, 0.0]
    if trace > 0.0:
        s = math.sqrt(trace + 1.0)
        temp[3] = s * 0.5
        s = 0.5 / s
        temp[0] = (m[2][1] - m[1][2]) * s
        temp[1] = (m[0][2] - m[2][0]) * s
        temp[2] = (m[1][0] - m[0][1]) * s
    else:
        if m[0][0] < m[1][1]:
            i = 2 if m[1][1] < m[2][2] else 1
        else:
            i = 2 if m[0][0] < m[2][2] else 0
        j = (i + 1) % 3
        k = (i + 2) % 3
        s = math.sqrt(m[i][i] - m[j][j] - m[k][k] + 1.0)
        temp[i] = s * 0.5
        s = 0.5 / s
        temp[3] = (m[k][j] - m[j][k]) * s
        temp[j] = (m[j][i] + m[i][j]) * s
        temp[k] = (m[k][i] + m[i][k]) * s
    return temp[0], temp[1], temp[2], temp[3]


def _compose(q2: Quat, v2: Vec, q1: Quat, v1: Vec) -> tuple[Quat, Vec]:
    """``tf2::Transform(q2, v2) * tf2::Transform(q1, v1)``, read back as quaternion + origin."""
    b2 = _matrix(q2)
    b1 = _matrix(q1)
    prod = [tuple(b2[r][0] * b1[0][c] + b2[r][1] * b1[1][c] + b2[r][2] * b1[2][c]
                  for c in range(3)) for r in range(3)]
    origin = tuple(b2[r][0] * v1[0] + b2[r][1] * v1[1] + b2[r][2] * v1[2] + v2[r]
                   for r in range(3))
    return _get_rotation(prod), origin  # type: ignore[arg-type,return-value]


def _raise(code: int, text: str) -> None:
    """Raise the exception of a tf2_msgs/TF2Error code, as tf2's lookups do."""
    if code == CONNECTIVITY_ERROR:
        raise ConnectivityException(text)
    if code == EXTRAPOLATION_ERROR:
        raise ExtrapolationException(text)
    raise LookupException(text)


def _stamp_ns(stamp: Any) -> int:
    if isinstance(stamp, Time):
        return stamp.secs * 1_000_000_000 + stamp.nsecs
    return time_to_ns(stamp, "header.stamp")


class BufferCore:
    """tf2's ``BufferCore(cache_time=Duration(10))`` (tf2_py's methods), on ddes time."""

    def __init__(self, cache_time: DurationLike | None = None) -> None:
        if cache_time is None:
            cache_time = Duration(DEFAULT_CACHE_TIME)
        self._cache_ns = duration_to_ns(cache_time, "cache_time")
        self._ids: dict[str, int] = {"NO_PARENT": 0}
        self._names: list[str] = ["NO_PARENT"]
        self._frames: list[TimeCache | StaticCache | None] = [None]
        self._authority: dict[int, str] = {}

    # -- insertion ------------------------------------------------------------------------
    def set_transform(self, transform: Any, authority: str) -> bool:
        """Insert a transform (tf2 ``setTransform``); False (and tf2's log line) if rejected.

        tf2_py returns None; the C++ bool is returned here.
        """
        return self._set_transform(transform, authority, False)

    def set_transform_static(self, transform: Any, authority: str) -> bool:
        """Insert a static transform, valid at every time (tf2 ``setTransform(..., true)``)."""
        return self._set_transform(transform, authority, True)

    def _set_transform(self, transform: Any, authority: str, is_static: bool) -> bool:
        header = transform.header
        frame_id = _strip_slash(header.frame_id)
        child = _strip_slash(transform.child_frame_id)
        tr = transform.transform.translation
        rot = transform.transform.rotation
        tx, ty, tz = float(tr.x), float(tr.y), float(tr.z)
        qx, qy, qz, qw = float(rot.x), float(rot.y), float(rot.z), float(rot.w)
        error = False
        if child == frame_id:
            self._log(logging.ERROR,
                      f'TF_SELF_TRANSFORM: Ignoring transform from authority "{authority}" with '
                      f'frame_id and child_frame_id  "{child}" because they are the same')
            error = True
        if child == "":
            self._log(logging.ERROR,
                      f'TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "{authority}" '
                      'because child_frame_id not set ')
            error = True
        if frame_id == "":
            self._log(logging.ERROR,
                      f'TF_NO_FRAME_ID: Ignoring transform with child_frame_id "{child}"  from '
                      f'authority "{authority}" because frame_id not set')
            error = True
        if tx != tx or ty != ty or tz != tz or qx != qx or qy != qy or qz != qz or qw != qw:
            self._log(logging.ERROR,
                      f'TF_NAN_INPUT: Ignoring transform for child_frame_id "{child}" from '
                      f'authority "{authority}" because of a nan value in the transform '
                      f"({tx:f} {ty:f} {tz:f}) ({qx:f} {qy:f} {qz:f} {qw:f})")
            error = True
        if not abs((qw * qw + qx * qx + qy * qy + qz * qz) - 1.0) < \
                QUATERNION_NORMALIZATION_TOLERANCE:
            self._log(logging.ERROR,
                      f'TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id '
                      f'"{child}" from authority "{authority}" because of an invalid quaternion '
                      f"in the transform ({qx:f} {qy:f} {qz:f} {qw:f})")
            error = True
        if error:
            return False
        stamp = _stamp_ns(header.stamp)
        child_id = self._lookup_or_insert(child)
        cache = self._frames[child_id]
        if cache is None:
            cache = StaticCache() if is_static else TimeCache(self._cache_ns)
            self._frames[child_id] = cache
        parent_id = self._lookup_or_insert(frame_id)
        problem = cache.insert((stamp, parent_id, child_id, tx, ty, tz, qx, qy, qz, qw))
        if problem is None:
            self._authority[child_id] = authority
            return True
        self._log(logging.WARNING, f"{problem} for frame {child} at time {to_sec(stamp):f} "
                  f"according to authority {authority}")
        return False

    def _log(self, level: int, text: str) -> None:
        """Where tf2's ``CONSOLE_BRIDGE_logWarn``/``logError`` lines go: ``level`` is
        ``logging.WARNING`` or ``logging.ERROR``, ``text`` tf2's line.  This logs to the
        ``ddes.tf2`` logger; :class:`ddes.tf2_ros.Buffer` overrides it to log on its node."""
        log.log(level, "%s", text)

    def _lookup_or_insert(self, name: str) -> int:
        fid = self._ids.get(name)
        if fid is None:
            fid = len(self._names)
            self._ids[name] = fid
            self._names.append(name)
            self._frames.append(None)
        return fid

    def clear(self) -> None:
        """Empty every dynamic frame's cache (static transforms and frame names stay, as tf2)."""
        for cache in self._frames[1:]:
            if cache is not None:
                cache.clear()

    # -- validation -----------------------------------------------------------------------
    def _validate(self, what: str, frame: str) -> int:
        fid = self._ids.get(frame)
        if fid and frame[0] != "/":  # a known frame (a stored id may start with '/': "//a")
            return fid
        if not frame:
            raise InvalidArgumentException(
                f"Invalid argument passed to {what} in tf2 frame_ids cannot be empty")
        if frame.startswith("/"):
            raise InvalidArgumentException(
                f'Invalid argument "{frame}" passed to {what} in tf2 frame_ids cannot start '
                "with a '/' like: ")
        fid = self._ids.get(frame, 0)
        if fid == 0:
            raise LookupException(f'"{frame}" passed to {what} does not exist. ')
        return fid

    def _warn_frame_id(self, what: str, frame: str) -> bool:
        if not frame:
            self._log(logging.WARNING,
                      f"Invalid argument passed to {what} in tf2 frame_ids cannot be empty")
            return True
        if frame.startswith("/"):
            self._log(logging.WARNING, f'Invalid argument "{frame}" passed to {what} in tf2 '
                      "frame_ids cannot start with a '/' like: ")
            return True
        return False

    # -- the walk -------------------------------------------------------------------------
    def _loop_text(self) -> str:
        return "The tf tree is invalid because it contains a loop.\n" + \
            self._all_frames_as_string() + "\n"

    def _connectivity_text(self, source_id: int, target_id: int) -> str:
        return (f"Could not find a connection between '{self._names[target_id]}' and "
                f"'{self._names[source_id]}' because they are not part of the same tree."
                "Tf has two or more unconnected trees.")

    def _latest_common_time(self, target_id: int, source_id: int) -> tuple[int, int, str]:
        """``getLatestCommonTime``: (error code, time ns, error text)."""
        if source_id == 0 or target_id == 0:
            return LOOKUP_ERROR, 0, ""
        frames = self._frames
        if source_id == target_id:
            cache = frames[source_id]
            return NO_ERROR, (cache.latest_timestamp() if cache is not None else 0), ""
        lct: list[tuple[int, int]] = []
        frame = source_id
        depth = 0
        common = -1  # TIME_MAX
        while frame != 0:
            cache = frames[frame]
            if cache is None:
                break
            latest = cache.latest_time_and_parent()
            if latest[1] == 0:
                break
            if latest[0] != 0:
                common = latest[0] if common < 0 else min(latest[0], common)
            lct.append(latest)
            frame = latest[1]
            if frame == target_id:
                return NO_ERROR, max(common, 0), ""
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                return LOOKUP_ERROR, 0, self._loop_text()
        frame = target_id
        depth = 0
        common = -1
        common_parent = 0
        parents = [p for _, p in lct]
        while True:
            cache = frames[frame]
            if cache is None:
                break
            latest = cache.latest_time_and_parent()
            if latest[1] == 0:
                break
            if latest[0] != 0:
                common = latest[0] if common < 0 else min(latest[0], common)
            if latest[1] in parents:
                common_parent = latest[1]
                break
            frame = latest[1]
            if frame == source_id:
                return NO_ERROR, max(common, 0), ""
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                return LOOKUP_ERROR, 0, self._loop_text()
        if common_parent == 0:
            return CONNECTIVITY_ERROR, 0, self._connectivity_text(source_id, target_id)
        for t, parent in lct:
            if t != 0:
                common = t if common < 0 else min(common, t)
            if parent == common_parent:
                break
        return NO_ERROR, max(common, 0), ""

    def _walk(self, target_id: int, source_id: int, time: int, accumulate: bool
              ) -> tuple[int, str, int, Quat, Vec]:
        """``walkToTopParent`` with TransformAccum (accumulate) or CanTransformAccum.

        Returns (error code, error text, time used, rotation, translation).
        """
        identity_q: Quat = (0.0, 0.0, 0.0, 1.0)
        zero: Vec = (0.0, 0.0, 0.0)
        if source_id == target_id:
            return NO_ERROR, "", time, identity_q, zero
        if time == 0:
            code, time, text = self._latest_common_time(target_id, source_id)
            if code != NO_ERROR:
                return code, text, time, identity_q, zero
        frames = self._frames
        src_q, src_v = identity_q, zero
        frame = source_id
        top_parent = frame
        depth = 0
        extrapolation_text = ""
        extrapolation_might_have_occurred = False
        while frame != 0:
            cache = frames[frame]
            if cache is None:
                top_parent = frame
                break
            if accumulate:
                st, err = cache.get_data(time)
                parent = st[1] if st is not None else 0
            else:
                parent, err = cache.get_parent(time)
                st = None
            if parent == 0:
                top_parent = frame
                extrapolation_text = err
                extrapolation_might_have_occurred = True
                break
            if frame == target_id:
                return NO_ERROR, "", time, src_q, src_v
            if st is not None:
                src_q, src_v = _accumulate(st, src_q, src_v)
            top_parent = frame
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                return LOOKUP_ERROR, self._loop_text(), time, identity_q, zero
        tgt_q, tgt_v = identity_q, zero
        frame = target_id
        depth = 0
        while frame != top_parent:
            cache = frames[frame]
            if cache is None:
                break
            if accumulate:
                st, err = cache.get_data(time)
                parent = st[1] if st is not None else 0
            else:
                parent, err = cache.get_parent(time)
                st = None
            if parent == 0:
                text = (f"{err}, when looking up transform from frame [{self._names[source_id]}]"
                        f" to frame [{self._names[target_id]}]")
                return EXTRAPOLATION_ERROR, text, time, identity_q, zero
            if frame == source_id:
                inv_q = (-tgt_q[0], -tgt_q[1], -tgt_q[2], tgt_q[3])
                inv_v = _quat_rotate(inv_q, (-tgt_v[0], -tgt_v[1], -tgt_v[2]))
                return NO_ERROR, "", time, inv_q, inv_v
            if st is not None:
                tgt_q, tgt_v = _accumulate(st, tgt_q, tgt_v)
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                return LOOKUP_ERROR, self._loop_text(), time, identity_q, zero
        if frame != top_parent:
            if extrapolation_might_have_occurred:
                text = (f"{extrapolation_text}, when looking up transform from frame "
                        f"[{self._names[source_id]}] to frame [{self._names[target_id]}]")
                return EXTRAPOLATION_ERROR, text, time, identity_q, zero
            return CONNECTIVITY_ERROR, self._connectivity_text(source_id, target_id), time, \
                identity_q, zero
        inv_q = (-tgt_q[0], -tgt_q[1], -tgt_q[2], tgt_q[3])
        inv_v = _quat_rotate(inv_q, (-tgt_v[0], -tgt_v[1], -tgt_v[2]))
        rv = _quat_rotate(inv_q, src_v)
        return NO_ERROR, "", time, _qmul(inv_q, src_q), \
            (rv[0] + inv_v[0], rv[1] + inv_v[1], rv[2] + inv_v[2])

    def _walk_chain(self, target_id: int, source_id: int, time: int) -> list[int]:
        """``walkToTopParent`` with a ``frame_chain``: the frame ids walked (tf2 0.7's pruning
        and ordering, its oddities included); raises tf2's exceptions."""
        if source_id == target_id:
            return []
        if time == 0:
            code, time, text = self._latest_common_time(target_id, source_id)
            if code != NO_ERROR:
                _raise(code, text)
        frames = self._frames
        chain: list[int] = []
        frame = source_id
        top_parent = frame
        depth = 0
        extrapolation_text = ""
        extrapolation_might_have_occurred = False
        while frame != 0:
            cache = frames[frame]
            chain.append(frame)
            if cache is None:
                top_parent = frame
                break
            st, err = cache.get_data(time)
            parent = st[1] if st is not None else 0
            if parent == 0:
                top_parent = frame
                extrapolation_text = err
                extrapolation_might_have_occurred = True
                break
            if frame == target_id:
                return chain
            top_parent = frame
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                _raise(LOOKUP_ERROR, self._loop_text())
        frame = target_id
        depth = 0
        reverse: list[int] = []
        while frame != top_parent:
            cache = frames[frame]
            reverse.append(frame)
            if cache is None:
                break
            st, err = cache.get_data(time)
            parent = st[1] if st is not None else 0
            if parent == 0:
                _raise(EXTRAPOLATION_ERROR,
                       f"{err}, when looking up transform from frame [{self._names[source_id]}]"
                       f" to frame [{self._names[target_id]}]")
            if frame == source_id:
                reverse.reverse()  # tf2: "the reverse walk", returned reversed
                return reverse
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                _raise(LOOKUP_ERROR, self._loop_text())
        if frame != top_parent:
            if extrapolation_might_have_occurred:
                _raise(EXTRAPOLATION_ERROR,
                       f"{extrapolation_text}, when looking up transform from frame "
                       f"[{self._names[source_id]}] to frame [{self._names[target_id]}]")
            _raise(CONNECTIVITY_ERROR, self._connectivity_text(source_id, target_id))
        reverse.append(frame)
        # pruning: compare the chains from the parent end until they differ
        m = len(reverse) - 1
        n = len(chain) - 1
        while m >= 0 and n >= 0:
            if chain[n] != reverse[m]:
                break
            m -= 1
            n -= 1
        if n > 0:
            del chain[n + 2:]  # tf2: "N is offset by 1 and leave the common parent"
        for i in range(m, -1, -1):
            chain.append(reverse[i])
        return chain

    def _chain(self, target_frame: str, target_time: TimeLike, source_frame: str,
               source_time: TimeLike, fixed_frame: str) -> list[str]:
        """tf2_py's ``_chain`` (``BufferCore::_chainAsVector``): the frames walked from
        ``source_frame`` (at ``source_time``) through ``fixed_frame`` to ``target_frame`` (at
        ``target_time``), as tf2 0.7.6 lists them; tf2's exceptions when a walk fails."""
        source_id = self._ids.get(source_frame, 0)
        fixed_id = self._ids.get(fixed_frame, 0)
        target_id = self._ids.get(target_frame, 0)
        source_chain = self._walk_chain(fixed_id, source_id, self._time_ns(source_time))
        target_chain = self._walk_chain(target_id, fixed_id, self._time_ns(target_time))
        if source_chain and target_chain and source_chain[-1] == target_chain[0]:
            source_chain.pop()
        return [self._names[f] for f in source_chain + target_chain]

    # -- lookups --------------------------------------------------------------------------
    @staticmethod
    def _time_ns(time: TimeLike) -> int:
        if isinstance(time, Time):
            return time.secs * 1_000_000_000 + time.nsecs
        return time_to_ns(time)

    @staticmethod
    def _message(target: str, source: str, time: int, q: Quat, v: Vec) -> Any:
        """The TransformStamped result, built slot by slot (what ``TransformStamped()`` and
        field assignments make, without building the default fields first)."""
        ts_cls, header_cls, transform_cls, vector_cls, quaternion_cls = \
            _MESSAGE_CLASS or _message_classes()
        stamp = _new(Time)
        stamp.secs, stamp.nsecs = divmod(time, _NS)
        header = _new(header_cls)
        header.seq = 0
        header.stamp = stamp
        header.frame_id = target
        tr = _new(vector_cls)
        tr.x, tr.y, tr.z = v
        rot = _new(quaternion_cls)
        rot.x, rot.y, rot.z, rot.w = q
        transform = _new(transform_cls)
        transform.translation = tr
        transform.rotation = rot
        msg = _new(ts_cls)
        msg.header = header
        msg.child_frame_id = source
        msg.transform = transform
        return msg

    def _lookup(self, target_frame: str, source_frame: str, time: int) -> tuple[int, Quat, Vec]:
        if target_frame == source_frame:
            stamp = time
            if time == 0:
                cache = self._frames[self._ids.get(target_frame, 0)]
                stamp = cache.latest_timestamp() if cache is not None else 0
            return stamp, (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
        target_id = self._validate("lookupTransform argument target_frame", target_frame)
        source_id = self._validate("lookupTransform argument source_frame", source_frame)
        code, text, used, q, v = self._walk(target_id, source_id, time, True)
        if code == CONNECTIVITY_ERROR:
            raise ConnectivityException(text)
        if code == EXTRAPOLATION_ERROR:
            raise ExtrapolationException(text)
        if code == LOOKUP_ERROR:
            raise LookupException(text)
        return used, q, v

    def lookup_transform_core(self, target_frame: str, source_frame: str,
                              time: TimeLike) -> Any:
        """The transform from ``source_frame`` to ``target_frame`` at ``time`` (0 = latest
        common time), as a geometry_msgs/TransformStamped; raises tf2's exceptions."""
        ns = time.secs * _NS + time.nsecs if type(time) is Time else self._time_ns(time)
        stamp, q, v = self._lookup(target_frame, source_frame, ns)
        return self._message(target_frame, source_frame, stamp, q, v)

    def lookup_transform_full_core(self, target_frame: str, target_time: TimeLike,
                                   source_frame: str, source_time: TimeLike,
                                   fixed_frame: str) -> Any:
        """source at ``source_time`` -> fixed frame -> target at ``target_time`` (time travel)."""
        self._validate("lookupTransform argument target_frame", target_frame)
        self._validate("lookupTransform argument source_frame", source_frame)
        self._validate("lookupTransform argument fixed_frame", fixed_frame)
        _, q1, v1 = self._lookup(fixed_frame, source_frame, self._time_ns(source_time))
        stamp2, q2, v2 = self._lookup(target_frame, fixed_frame, self._time_ns(target_time))
        q, v = _compose(q2, v2, q1, v1)
        return self._message(target_frame, source_frame, stamp2, q, v)

    def _can_transform_ids(self, target_id: int, source_id: int, time: int) -> tuple[bool, str]:
        if target_id == 0 or source_id == 0:
            msg = ""
            if target_id == 0:
                msg += f"target_frame: {self._names[target_id]} does not exist."
            if source_id == 0:
                if target_id == 0:
                    msg += " "
                name = self._names[source_id]
                msg += f"source_frame: {name} {name} does not exist."
            return False, msg
        if target_id == source_id:
            return True, ""
        code, text, _, _, _ = self._walk(target_id, source_id, time, False)
        return code == NO_ERROR, text

    def can_transform_core(self, target_frame: str, source_frame: str,
                           time: TimeLike) -> tuple[bool, str]:
        """(whether the lookup would succeed, tf2's error text)."""
        if target_frame == source_frame:
            return True, ""
        if self._warn_frame_id("canTransform argument target_frame", target_frame):
            return False, ""
        if self._warn_frame_id("canTransform argument source_frame", source_frame):
            return False, ""
        target_id = self._ids.get(target_frame, 0)
        source_id = self._ids.get(source_frame, 0)
        if target_id == 0 or source_id == 0:
            msg = ""
            if target_id == 0:
                msg += f"canTransform: target_frame {target_frame} does not exist."
            if source_id == 0:
                if target_id == 0:
                    msg += " "
                msg += f"canTransform: source_frame {source_frame} does not exist."
            return False, msg
        ns = time.secs * _NS + time.nsecs if type(time) is Time else self._time_ns(time)
        return self._can_transform_ids(target_id, source_id, ns)

    def can_transform_full_core(self, target_frame: str, target_time: TimeLike,
                                source_frame: str, source_time: TimeLike,
                                fixed_frame: str) -> tuple[bool, str]:
        """The full (fixed-frame) form of :meth:`can_transform_core`, with tf2's texts."""
        if self._warn_frame_id("canTransform argument target_frame", target_frame):
            return False, ""
        if self._warn_frame_id("canTransform argument source_frame", source_frame):
            return False, ""
        if self._warn_frame_id("canTransform argument fixed_frame", fixed_frame):
            return False, ""
        target_id = self._ids.get(target_frame, 0)
        source_id = self._ids.get(source_frame, 0)
        fixed_id = self._ids.get(fixed_frame, 0)
        if target_id == 0 or source_id == 0 or fixed_id == 0:
            msg = ""
            if target_id == 0:
                msg += f"canTransform: target_frame {target_frame} does not exist."
            if source_id == 0:
                if target_id == 0:
                    msg += " "
                msg += f"canTransform: source_frame {source_frame} does not exist."
            if source_id == 0:  # sic: tf2 tests source_id twice
                msg += " "
                msg += f"fixed_frame: {fixed_frame}does not exist."
            return False, msg
        ok, text = self._can_transform_ids(target_id, fixed_id, self._time_ns(target_time))
        if not ok:
            return False, text
        ok2, text2 = self._can_transform_ids(fixed_id, source_id, self._time_ns(source_time))
        return ok2, text2

    def get_latest_common_time(self, target_frame: str, source_frame: str) -> Time:
        """The latest time at which both frames' chains have data (Time(0) if all static)."""
        target_id = self._validate("get_latest_common_time", target_frame)
        source_id = self._validate("get_latest_common_time", source_frame)
        code, time, text = self._latest_common_time(target_id, source_id)
        if code != NO_ERROR:
            raise TransformException(text)
        return Time._from_ns(time)

    # -- introspection ----------------------------------------------------------------------
    def _all_frames_as_string(self) -> str:
        out = []
        for fid in range(1, len(self._frames)):
            cache = self._frames[fid]
            if cache is None:
                continue
            st, _ = cache.get_data(0)
            parent = st[1] if st is not None else 0
            out.append(f"Frame {self._names[fid]} exists with parent {self._names[parent]}.\n")
        return "".join(out)

    def all_frames_as_string(self) -> str:
        """One line per frame with a parent: ``Frame X exists with parent Y.``."""
        return self._all_frames_as_string()

    def all_frames_as_yaml(self, current_time: TimeLike | None = None) -> str:
        """tf2's YAML of the tree (parent, broadcaster, rate, most_recent_transform,
        oldest_transform, transform_delay when ``current_time`` is given, buffer_length)."""
        now = 0.0 if current_time is None else to_sec(self._time_ns(current_time))
        out = []
        if len(self._frames) == 1:
            out.append("{}")
        for fid in range(1, len(self._frames)):
            cache = self._frames[fid]
            if cache is None:
                continue
            st, _ = cache.get_data(0)
            if st is None:
                continue
            authority = self._authority.get(fid, "no recorded authority")
            latest = cache.latest_timestamp()
            oldest = cache.oldest_timestamp()
            rate = cache.list_length() / max(to_sec(latest) - to_sec(oldest), 0.0001)
            out.append(f"{self._names[fid]}: \n")
            out.append(f"  parent: '{self._names[st[1]]}'\n")
            out.append(f"  broadcaster: '{authority}'\n")
            out.append(f"  rate: {rate:.3f}\n")
            out.append(f"  most_recent_transform: {to_sec(latest):.3f}\n")
            out.append(f"  oldest_transform: {to_sec(oldest):.3f}\n")
            if now > 0:
                out.append(f"  transform_delay: {now - to_sec(latest):.3f}\n")
            out.append(f"  buffer_length: {to_sec(latest - oldest):.3f}\n")
        return "".join(out)

    def _allFramesAsDot(self, time: TimeLike | None = None) -> str:  # noqa: N802 - tf2_py's
        """tf2's ``allFramesAsDot``: the tree as graphviz dot text, one edge per frame with its
        broadcaster, average rate, latest stamp and buffer length; with ``time`` (tf2_py's
        ``time`` argument, seconds > 0) each edge says how old its transform is and every root
        gets tf2's "view_frames Result" legend."""
        current = 0.0 if time is None else to_sec(self._time_ns(time))
        out = ["digraph G {\n"]
        frames = self._frames
        names = self._names
        if len(frames) == 1:
            out.append('"no tf data recieved"')  # sic
        for fid in range(1, len(frames)):
            cache = frames[fid]
            if cache is None:
                continue
            st, _ = cache.get_data(0)
            if st is None:
                continue
            authority = self._authority.get(fid, "no recorded authority")
            latest = to_sec(cache.latest_timestamp())
            oldest = to_sec(cache.oldest_timestamp())
            rate = cache.list_length() / max(latest - oldest, 0.0001)
            out.append(f'"{names[st[1]]}" -> "{names[fid]}"[label="Broadcaster: {authority}\\n'
                       f"Average rate: {rate:.3f} Hz\\nMost recent transform: {latest:.3f} ")
            if current > 0:
                out.append(f"( {current - latest:.3f} sec old)")
            buffer_length = to_sec(cache.latest_timestamp() - cache.oldest_timestamp())
            out.append(f'\\nBuffer length: {buffer_length:.3f} sec\\n"];\n')
        legend = (' subgraph cluster_legend { style=bold; color=black; label ="view_frames '
                  'Result";\n')
        recorded = f'"Recorded at time: {current:.3f}"[ shape=plaintext ] ;\n ' \
            if current > 0 else ""
        for fid in range(1, len(frames)):
            cache = frames[fid]
            if cache is None:
                if current > 0:
                    out.append(f'edge [style=invis];\n{legend}{recorded}}}->"{names[fid]}";\n')
                continue
            st, _ = cache.get_data(0)
            if st is None or st[1] == 0:
                out.append(f'edge [style=invis];\n{legend}{recorded}}}->"{names[fid]}";\n')
        out.append("}")
        return "".join(out)

    def _frameExists(self, frame_id: str) -> bool:  # noqa: N802 - tf2_py's name
        """Whether the frame id has been seen (as a child or a parent)."""
        return frame_id in self._ids

    def _getParent(self, frame_id: str, time: TimeLike) -> str | None:  # noqa: N802
        """The parent of ``frame_id`` at ``time``, or None (tf2's ``_getParent`` returning
        false)."""
        fid = self._ids.get(frame_id, 0)
        cache = self._frames[fid] if fid else None
        if cache is None:
            return None
        parent, _ = cache.get_parent(self._time_ns(time))
        return self._names[parent] if parent else None

    def _getFrameStrings(self) -> list[str]:  # noqa: N802 - tf2_py's name
        """Every frame id seen, in order of first sight (child before parent)."""
        return self._names[1:]

    def _storage(self, frame_id: str) -> list[Storage]:
        """The cached entries of a frame, oldest first (for tests and plots)."""
        cache = self._frames[self._ids.get(frame_id, 0)]
        if cache is None:
            return []
        if isinstance(cache, StaticCache):
            return [cache.storage]
        return list(cache.entries)

    def _set_transform_fast(self, frame_id: str, child: str, stamp: int, tx: float, ty: float,
                            tz: float, qx: float, qy: float, qz: float, qw: float,
                            authority: str) -> bool:
        """The insertion of :meth:`set_transform` from plain values (a TransformListener's parsed
        /tf bytes), when every check passes: True if inserted; False, with nothing changed and
        nothing logged, when a check or the cache refuses it (the caller then goes the checked way,
        which logs tf2's line)."""
        slot = self._fast_slot(frame_id, child)
        return slot is not None and self._insert_fast(slot, stamp, tx, ty, tz, qx, qy, qz, qw,
                                                      authority)

    def _fast_slot(self, frame_id: str, child: str) -> tuple[int, int, TimeCache] | None:
        """Where :meth:`_set_transform_fast` puts a transform from ``frame_id`` to ``child``:
        (parent id, child id, the child's TimeCache) when the names pass tf2's checks, both
        frames are known and the child has a TimeCache; else None (the checked way decides).
        A slot holds for the buffer's life: frame ids are never renumbered, and a frame's cache,
        once made, is never replaced (``clear`` empties it)."""
        if frame_id[:1] == "/":
            frame_id = frame_id[1:]
        if child[:1] == "/":
            child = child[1:]
        if child == frame_id or not child or not frame_id:
            return None
        ids = self._ids
        child_id = ids.get(child)
        parent_id = ids.get(frame_id)
        if child_id is None or parent_id is None:
            return None  # a new frame: the checked way numbers the frames in tf2's order
        cache = self._frames[child_id]
        if cache is None or cache.__class__ is not TimeCache:
            return None
        return parent_id, child_id, cache

    def _insert_fast(self, slot: tuple[int, int, TimeCache], stamp: int, tx: float, ty: float,
                     tz: float, qx: float, qy: float, qz: float, qw: float,
                     authority: str) -> bool:
        """The values' checks and the insertion into a :meth:`_fast_slot`: True if inserted;
        False, with nothing changed and nothing logged, if a check or the cache refuses."""
        if (tx != tx or ty != ty or tz != tz or qx != qx or qy != qy or qz != qz or qw != qw
                or not abs((qw * qw + qx * qx + qy * qy + qz * qz) - 1.0)
                < QUATERNION_NORMALIZATION_TOLERANCE):
            return False
        parent_id, child_id, cache = slot
        if cache.insert((stamp, parent_id, child_id, tx, ty, tz, qx, qy, qz, qw)) is not None:
            return False  # the cache changed nothing (old or repeated data)
        self._authority[child_id] = authority
        return True

    def __repr__(self) -> str:
        return f"<ddes.tf2.BufferCore {len(self._names) - 1} frames>"
