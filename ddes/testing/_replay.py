"""What every protocol machine shares: the replay call it prints, and the mark on its plots.

A failing schedule is printed as one line of Python that reproduces it
(``replay_action_schedule(make_server, [('send_goal', {'order': 2}), ...], seed=0)``).
:func:`literal` writes a value so that the line evaluates back to it (``inf``
and ``nan`` as ``float('inf')``, bytes, nested lists and dicts);
:func:`call_text` writes the call; :func:`mark_violation` draws the violating
step on the axes of a figure (a red band from the step's start to the instant
the violation was seen, a red line there, and the step's text).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["VIOLATION_GID", "call_text", "factory_name", "literal", "mark_violation"]

#: The gid of the artists :func:`mark_violation` draws (tests find them by it).
VIOLATION_GID = "ddes-violating-step"


def literal(value: object) -> str:
    """Python source that evaluates to ``value`` (plain data: numbers, text, lists, dicts)."""
    if isinstance(value, float):
        if math.isnan(value):
            return "float('nan')"
        if math.isinf(value):
            return "float('inf')" if value > 0 else "float('-inf')"
        return repr(value)
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{literal(k)}: {literal(v)}" for k, v in value.items()) + "}"
    if isinstance(value, tuple):
        inner = ", ".join(literal(v) for v in value)
        return f"({inner},)" if len(value) == 1 else f"({inner})"
    if isinstance(value, list):
        return "[" + ", ".join(literal(v) for v in value) + "]"
    return repr(value)


def factory_name(fn: Callable[..., object] | None, default: str) -> str:
    """How a replay call names a user's function: its name, or ``default`` for a lambda."""
    name = getattr(fn, "__name__", "")
    return name if name.isidentifier() else default


def call_text(fn: str, args: Sequence[object], kwargs: Mapping[str, object]) -> str:
    """``fn(arg, ..., key=value, ...)`` with every value written by :func:`literal`.

    A value that is already source text is passed as :class:`Source`.
    """
    parts = [a.text if isinstance(a, Source) else literal(a) for a in args]
    parts += [f"{k}={v.text if isinstance(v, Source) else literal(v)}" for k, v in kwargs.items()]
    return f"{fn}({', '.join(parts)})"


class Source:
    """A piece of source text to put into a call as it is (a function's name)."""

    __slots__ = ("text",)

    def __init__(self, text: str) -> None:
        self.text = text


def mark_violation(ax: Axes, start_s: float, end_s: float, label: str) -> None:
    """Draw the violating step on ``ax``: a red band over its span, a line where it failed."""
    if end_s > start_s:
        band = ax.axvspan(start_s, end_s, color="#d62728", alpha=0.15, linewidth=0)
        band.set_gid(VIOLATION_GID)
    line = ax.axvline(end_s, color="#d62728", linestyle="--", linewidth=1.2)
    line.set_gid(VIOLATION_GID)
    lo, hi = ax.get_xlim()
    right = end_s > (lo + hi) / 2  # the text goes on the side with room, inside the axes
    text = ax.annotate(label, (end_s, 1.0), xycoords=("data", "axes fraction"),
                       xytext=(-4 if right else 4, -4), textcoords="offset points",
                       color="#d62728", fontsize=7, va="top", ha="right" if right else "left",
                       bbox={"boxstyle": "round,pad=0.2", "facecolor": "white", "alpha": 0.8,
                             "edgecolor": "none"})
    text.set_gid(VIOLATION_GID)
