"""The same derandomized draws in every checkout and every test session.

Hypothesis (since 6.131) mixes into its draws constants it reads from the
project's own modules loaded at the time (every module outside
site-packages): which modules a test session imported first, or whether ddes
is an editable install, changes the schedules a ``derandomize=True`` run
draws, and with them which bug a search finds first and how it shrinks.  A
grader's verdict and a student's run must agree, so the protocol machines and
the explorer run with that pool empty: their draws depend only on the
hypothesis version, the machine and the settings.

This reaches into hypothesis's internals (``providers._get_local_constants``
and ``providers.CONSTANTS_CACHE``); where a version lacks them (older ones
have no such pool) it does nothing.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["same_draws_everywhere"]


@contextmanager
def same_draws_everywhere() -> Iterator[None]:
    """Run the block with hypothesis's pool of local-module constants empty."""
    try:
        from hypothesis.internal.conjecture import providers as p

        original = p._get_local_constants
        cache: Any = p.CONSTANTS_CACHE
        empty = p.Constants()
        clear = cache.cache.clear
    except (ImportError, AttributeError, TypeError):  # a hypothesis without the pool
        yield
        return
    p._get_local_constants = lambda: empty  # type: ignore[assignment]
    clear()  # cached choices computed with the local pool
    try:
        yield
    finally:
        p._get_local_constants = original  # type: ignore[assignment]
        clear()
