"""A schedule explorer: property-test your own nodes under perturbed latencies and tie orders.

::

    from ddes.testing.explore import explore

    def scenario(world):            # build your nodes; return what check needs (or nothing)
        ...

    def check(world, result):       # raise AssertionError when the property is broken
        ...

    explore(scenario, check, runs=200, until=5.0)

Each run builds a fresh ``ddes.World``, runs ``scenario(world)``, runs the
world for ``until`` seconds of simulated time and calls ``check(world)`` (or
``check(world, result)`` when the scenario returned something).  Worlds are
strict: an exception in a callback fails the run too.  Between runs
hypothesis varies a :class:`Perturbation`:

* ``seed``: the world seed (every seeded stream: lossy links, drawn latencies);
* ``latencies`` / ``service_latencies``: a fixed latency for some of the
  topics and services the scenario uses (found by one unperturbed run first);
* ``jitter``: a latency drawn per message, uniform in ``[0, jitter]`` seconds,
  on every topic (FIFO per connection is kept, as TCP keeps it);
* ``connect_delay``: how long a new topic connection takes to form;
* ``ties``: the order of events due at the same instant (below).

A failure shrinks to the smallest perturbation that still fails (latencies
back to none, ties back to first-scheduled-first), and the
:class:`ExplorationFailure` message holds the one-line call that replays it::

    replay(scenario, check, seed=0, latencies={'/config': 0.001}, until=5.0)

**Same-instant ties.**  ddes fires events due at the same instant in the
order they were scheduled (docs/determinism.md); the kernel has no knob to
change that order, and this module does not edit the kernel.  It installs,
on the one world of a run, a step function that looks at the events due
next (same time, same priority) before the kernel's own step takes one:
where two or more of them could go first, it takes the ``ties``' next
number (modulo the number of candidates) to pick which (0: the kernel's own
order), then lets the kernel step as usual.  Candidates are the first event
of each *owner* (the object whose method the event calls: a connection, a
timer, a process, a service proxy), so what ROS keeps in order stays in
order: messages of one connection, the steps of one process, the hops of
one service connection; a publisher's batched deliveries (one event for
all its connections of one latency) keep their order.  Events of one plain
function keep their order among themselves, and an instant that holds
the stop of a ``run(until=...)`` is never perturbed.  The choices depend
only on ``ties`` and the program, so a given perturbation replays exactly.
Once the ``ties`` run out, the kernel's order applies.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from heapq import heappop, heappush
from typing import Any

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from simpy.core import StopSimulation

from ddes.errors import DdesTypeError, DdesValueError
from ddes.graph.topics import Subscriber, _arrive_batch
from ddes.testing._draws import same_draws_everywhere
from ddes.testing._replay import Source, call_text, factory_name
from ddes.time.units import duration_to_ns
from ddes.world import World

__all__ = ["LATENCIES", "ExplorationFailure", "Perturbation", "TieBreaker", "explore",
           "replay", "run_perturbed"]

Scenario = Callable[[World], object]
Check = Callable[..., object]

#: Fixed latencies (seconds) the explorer puts on a topic or service (0: ddes's default).
LATENCIES: tuple[float, ...] = (0.0, 0.0005, 0.002, 0.01, 0.05)
_JITTERS: tuple[float, ...] = (0.0, 0.0005, 0.005)
_CONNECT: tuple[float | None, ...] = (None, 0.0, 0.005, 0.05)


_arrive_one = Subscriber._arrive_one


class ExplorationFailure(AssertionError):
    """A perturbed run broke the property; ``perturbation`` and ``replay`` say how to see it again."""

    perturbation: Perturbation
    replay: str = ""


@dataclass(frozen=True)
class Perturbation:
    """What one run varies (see the module docstring); the default perturbs nothing."""

    seed: int = 0
    latencies: Mapping[str, float] = field(default_factory=dict)
    service_latencies: Mapping[str, float] = field(default_factory=dict)
    jitter: float = 0.0
    connect_delay: float | None = None
    ties: tuple[int, ...] = ()

    def apply(self, world: World) -> TieBreaker | None:
        """Set the world's links and install the tie order (before the scenario runs)."""
        jitter = self.jitter
        if jitter:
            world.set_link(None, latency=_Jittered(0.0, jitter))
        for topic, latency in self.latencies.items():
            if jitter:
                world.set_link(topic, latency=_Jittered(latency, jitter))
            else:
                world.set_link(topic, latency=latency)
        for service, latency in self.service_latencies.items():
            world.set_service_link(service, latency=latency)
        if self.connect_delay is not None:
            world.connect_delay_ns = duration_to_ns(self.connect_delay, "connect_delay")
        return TieBreaker(world, self.ties) if any(self.ties) else None

    def replay_kwargs(self) -> dict[str, object]:
        """The fields that differ from the default, tied choices without trailing zeros."""
        out: dict[str, object] = {"seed": self.seed}
        lat = {k: v for k, v in self.latencies.items() if v}
        if lat:
            out["latencies"] = lat
        slat = {k: v for k, v in self.service_latencies.items() if v}
        if slat:
            out["service_latencies"] = slat
        if self.jitter:
            out["jitter"] = self.jitter
        if self.connect_delay is not None:
            out["connect_delay"] = self.connect_delay
        ties = list(self.ties)
        while ties and ties[-1] == 0:
            ties.pop()
        if ties:
            out["ties"] = tuple(ties)
        return out


class _Jittered:
    """A latency drawn per message: ``base`` plus uniform ``[0, jitter]`` seconds."""

    def __init__(self, base: float, jitter: float) -> None:
        self.base, self.jitter = base, jitter

    def __call__(self, rng: Any) -> float:
        return self.base + float(rng.uniform(0.0, self.jitter))


class TieBreaker:
    """The seeded order of same-instant events on one world (see the module docstring).

    ``contested`` counts the instants where a choice was made; ``choices``
    lists ``(kernel ns, candidates, chosen index)`` for each.
    """

    def __init__(self, world: World, ties: Sequence[int]) -> None:
        self.env = world.env
        self.ties = tuple(ties)
        self.used = 0
        self.choices: list[tuple[int, int, int]] = []
        self._kernel_step = world.env.step
        world.env.step = self.step  # type: ignore[method-assign]  # this world only

    @staticmethod
    def _owner(event: Any) -> object:
        callbacks = event.callbacks or ()
        if not callbacks:
            return event
        cb = callbacks[0]
        func = getattr(cb, "__func__", cb)
        if func is _arrive_batch or func is _arrive_one:
            # one publisher's connections of one latency (a list, or the one connection)
            return event.payload[2]
        owner = getattr(cb, "__self__", None)
        if owner is not None:
            return owner
        return cb

    def step(self) -> None:
        """Pick which of the events due next goes first, then let the kernel step."""
        if self.used < len(self.ties):
            self._choose()
        self._kernel_step()

    def _choose(self) -> None:
        queue = self.env._queue
        if len(queue) < 2:
            return
        t: int = queue[0][0]  # type: ignore[assignment]  # ddes schedules int times only
        prio = queue[0][1]
        if not (queue[1][0] == t and queue[1][1] == prio) and not (
                len(queue) > 2 and queue[2][0] == t and queue[2][1] == prio):
            return
        group: list[Any] = []
        while queue and queue[0][0] == t and queue[0][1] == prio:
            group.append(heappop(queue))
        candidates: list[int] = []
        owners: list[object] = []
        stop = StopSimulation.callback
        blocked = False
        for i, entry in enumerate(group):
            callbacks = entry[3].callbacks or ()
            if any(cb == stop for cb in callbacks):
                blocked = True
            owner = self._owner(entry[3])
            if not any(owner is o for o in owners):
                owners.append(owner)
                candidates.append(i)
        if len(candidates) > 1 and not blocked:
            pick = self.ties[self.used] % len(candidates)
            self.used += 1
            self.choices.append((t, len(candidates), pick))
            if pick:
                chosen = group[candidates[pick]]
                group[candidates[pick]] = (t, prio, group[0][2] - 0.5, chosen[3])
        for entry in group:
            heappush(queue, entry)


def _call_check(check: Check, world: World, result: object) -> None:
    if result is None:
        outcome = check(world)
    else:
        outcome = check(world, result)
    if outcome is False:
        raise AssertionError("check returned False")


def run_perturbed(scenario: Scenario, check: Check, perturbation: Perturbation = Perturbation(),
                  *, until: float = 10.0) -> World:
    """One run: a strict world with the perturbation, the scenario, ``until`` seconds, the check.

    Returns the world; raises what the scenario, a callback or the check raised.
    """
    world = World(perturbation.seed, strict=True)
    perturbation.apply(world)
    result = scenario(world)
    world.run(until=until)
    _call_check(check, world, result)
    return world


def replay(scenario: Scenario, check: Check, *, seed: int = 0,
           latencies: Mapping[str, float] | None = None,
           service_latencies: Mapping[str, float] | None = None, jitter: float = 0.0,
           connect_delay: float | None = None, ties: Sequence[int] = (),
           until: float = 10.0) -> World:
    """Run one perturbation again (what an :class:`ExplorationFailure` prints); raises as it did."""
    p = Perturbation(seed, dict(latencies or {}), dict(service_latencies or {}), jitter,
                     connect_delay, tuple(ties))
    return run_perturbed(scenario, check, p, until=until)


def _check_callables(scenario: object, check: object) -> None:
    for what, fn in (("scenario", scenario), ("check", check)):
        if not callable(fn):
            raise DdesTypeError(f"{what} must be callable, got {fn!r}")
    params = inspect.signature(check).parameters  # type: ignore[arg-type]
    if not 1 <= len(params) <= 2 and not any(p.kind == p.VAR_POSITIONAL for p in params.values()):
        raise DdesTypeError("check takes (world) or (world, result)")


def explore(scenario: Scenario, check: Check, *, runs: int = 100, until: float = 10.0,
            max_ties: int = 32, latencies: Sequence[float] = LATENCIES,
            **settings_kw: Any) -> None:
    """Run ``scenario`` under ``runs`` perturbations; raise :class:`ExplorationFailure`, shrunk.

    One unperturbed run first finds the topics and services the scenario uses
    (and fails at once if the property does not even hold there).  ``max_ties``
    bounds the same-instant choices one run may perturb; ``latencies`` are the
    values a topic or service may get.  Other keywords are hypothesis settings
    (``derandomize=True``, ``database=None`` ...).
    """
    _check_callables(scenario, check)
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise DdesValueError(f"runs must be an int >= 1, got {runs!r}")
    base = World(0, strict=True)
    result = scenario(base)
    base.run(until=until)
    topics = sorted(base.master.topics)
    services = sorted(base.master.services)
    try:
        _call_check(check, base, result)
    except AssertionError as exc:
        raise _failure(scenario, check, Perturbation(), until, exc) from exc
    values = st.sampled_from(tuple(latencies))
    strategy = st.builds(
        Perturbation,
        seed=st.integers(0, 2**16),
        latencies=st.fixed_dictionaries({t: values for t in topics}),
        service_latencies=st.fixed_dictionaries({s: values for s in services}),
        jitter=st.sampled_from(_JITTERS),
        connect_delay=st.sampled_from(_CONNECT),
        ties=st.lists(st.integers(0, 3), max_size=max_ties).map(tuple),
    )
    settings_kw.setdefault("deadline", None)
    settings_kw.setdefault("suppress_health_check", [HealthCheck.too_slow,
                                                     HealthCheck.data_too_large])

    @settings(max_examples=runs, **settings_kw)
    @given(strategy)
    def run(perturbation: Perturbation) -> None:
        try:
            run_perturbed(scenario, check, perturbation, until=until)
        except Exception as exc:  # noqa: BLE001 - any failure of the run is the finding
            raise _failure(scenario, check, perturbation, until, exc) from exc

    with same_draws_everywhere():
        run()


def _failure(scenario: Scenario, check: Check, p: Perturbation, until: float,
             exc: BaseException) -> ExplorationFailure:
    kwargs = p.replay_kwargs()
    kwargs["until"] = until
    call = call_text("replay", [Source(factory_name(scenario, "scenario")),
                                Source(factory_name(check, "check"))], kwargs)
    first = str(exc).splitlines()[0] if str(exc) else ""
    failure = ExplorationFailure(
        f"the property broke under a perturbation: {type(exc).__name__}: {first}\n"
        f"  perturbation: {p.replay_kwargs()}\n"
        f"replay it (ddes.testing.explore):\n  {call}")
    failure.perturbation, failure.replay = p, call
    return failure
