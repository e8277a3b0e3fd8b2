"""The texts of the TF console tools: ``tf_echo``'s block and ``view_frames``'s ``frames.gv``.

``echo_lines`` prints what ``tf/src/tf_echo.cpp`` prints for one transform: tf1 keeps the
rotation as a LinearMath matrix, so the quaternion shown is the matrix's (``getRotation``: w
positive when the trace is), the angles ``getRPY``'s, every number ``std::fixed`` with 3 decimals.
``generate_dot`` is ``tf2_tools/scripts/view_frames.py``'s function of the same name, on the
mapping ``yaml.safe_load(buffer.all_frames_as_yaml())`` gives.
"""

from __future__ import annotations

import math
import re
from typing import Any

from ddes.tf2_ros.linmath import tf_matrix_to_quat, tf_quat_to_matrix, tf_rpy

__all__ = ["atof", "echo_failure_lines", "echo_lines", "frames_data", "generate_dot", "ros_time_text"]


def _f3(x: float) -> str:
    return f"{x:.3f}"


def echo_lines(transform: Any) -> list[str]:
    """tf_echo's five lines for one TransformStamped (``At time``, Translation, Rotation...)."""
    stamp = transform.header.stamp
    secs = stamp.secs + 1e-9 * stamp.nsecs  # ros::Time::toSec
    r, t = transform.transform.rotation, transform.transform.translation
    m = tf_quat_to_matrix(r.x, r.y, r.z, r.w)
    q = tf_matrix_to_quat(m)
    roll, pitch, yaw = tf_rpy(m)
    deg = [a * 180.0 / math.pi for a in (roll, pitch, yaw)]
    return [
        f"At time {_f3(secs)}",
        f"- Translation: [{_f3(t.x)}, {_f3(t.y)}, {_f3(t.z)}]",
        f"- Rotation: in Quaternion [{_f3(q[0])}, {_f3(q[1])}, {_f3(q[2])}, {_f3(q[3])}]",
        f"            in RPY (radian) [{_f3(roll)}, {_f3(pitch)}, {_f3(yaw)}]",
        f"            in RPY (degree) [{_f3(deg[0])}, {_f3(deg[1])}, {_f3(deg[2])}]",
    ]


def ros_time_text(t: Any) -> str:
    """``std::ostream << ros::Time``: seconds, a dot, nine digits of nanoseconds."""
    return f"{t.secs}.{t.nsecs:09d}"


def echo_failure_lines(now: Any, error: BaseException, frames_text: str) -> list[str]:
    """tf_echo's lines after a failed lookup: the time, the exception, the frames, a blank line."""
    return [f"Failure at {ros_time_text(now)}", f"Exception thrown:{error}",
            "The current list of frames is:", *(frames_text + "\n").split("\n")[:-1]]


def frames_data(buffer: Any) -> dict[str, dict[str, Any]]:
    """``yaml.safe_load(buffer.all_frames_as_yaml())`` as a dict ({} for no frames)."""
    import yaml

    data = yaml.safe_load(buffer.all_frames_as_yaml())
    return data if isinstance(data, dict) else {}


def generate_dot(data: dict[str, dict[str, Any]], now_sec: float) -> str:
    """view_frames.py's ``generate_dot(data)``, the recording time given (``Time.now().to_sec()``)."""
    if len(data) == 0:
        return 'digraph G { "No tf data received" }'
    dot = "digraph G {\n"
    root = ""
    for el in data:
        m = data[el]
        dot += '"' + m["parent"] + '" -> "' + str(el) + '"'
        dot += '[label=" '
        dot += "Broadcaster: " + m["broadcaster"] + "\\n"
        dot += "Average rate: " + str(m["rate"]) + "\\n"
        dot += "Buffer length: " + str(m["buffer_length"]) + "\\n"
        dot += "Most recent transform: " + str(m["most_recent_transform"]) + "\\n"
        dot += "Oldest transform: " + str(m["oldest_transform"]) + "\\n"
        dot += '"];\n'
        if m["parent"] not in data:
            root = m["parent"]
    dot += "edge [style=invis];\n"
    dot += ' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n'
    dot += '"Recorded at time: ' + str(now_sec) + '"[ shape=plaintext ] ;\n'
    dot += '}->"' + root + '";\n}'
    return dot


_FLOAT = re.compile(r"\s*([+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf(?:inity)?|nan))",
                    re.IGNORECASE)


def atof(text: str) -> float:
    """C ``atof``: the leading number of ``text``, 0.0 if there is none (``"1.5m"`` is 1.5)."""
    m = _FLOAT.match(text)
    return float(m.group(1)) if m else 0.0
