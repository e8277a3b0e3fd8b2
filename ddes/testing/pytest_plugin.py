"""ddes's pytest plugin: seeded worlds and consoles as fixtures, and failures that replay.

pytest loads it by itself wherever ddes is installed (the ``pytest11`` entry
point ``ddes``; ``-p no:ddes`` turns it off).  It gives

* the fixtures ``ddes_seed`` (the seed, 0 unless ``--ddes-seed N`` says
  otherwise), ``world`` (a fresh strict ``ddes.World`` on that seed) and
  ``console`` (a ``ddes.Console`` on that world, closed after the test);
  a project's own fixture of the same name wins over the plugin's, as pytest
  ranks a conftest's fixtures above a plugin's;
* the option ``--ddes-seed N``;
* on a failing test that used the seed, a report section ``ddes`` with the
  seed and the one-line command that replays the test on it::

      ---------------------------------- ddes ----------------------------------
      seed: 3
      replay: pytest tests/test_robot.py::test_odometry --ddes-seed 3

  (and ``ddes_seed``/``ddes_replay`` in the test's ``user_properties``, which
  ``--junitxml`` writes);
* the hypothesis settings profile ``ddes-protocols`` (:data:`PROTOCOL_PROFILE`)
  for the protocol machines of :mod:`ddes.testing`: derandomized (every run
  draws the same schedules, so CI fails or passes the same way each time), no
  deadline and no "too slow" health checks (wall-clock speed is not what a
  test on simulated time checks), and ``print_blob`` (the
  ``@reproduce_failure`` line).  Load it with
  ``pytest --hypothesis-profile ddes-protocols``.
"""

from __future__ import annotations

import os
import shlex
from collections.abc import Generator, Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, settings

import ddes

__all__ = ["PROTOCOL_PROFILE", "console", "ddes_seed", "replay_command", "world"]

#: The hypothesis settings profile for protocol machines (registered when pytest loads the
#: plugin, so ``--hypothesis-profile ddes-protocols`` finds it).
PROTOCOL_PROFILE = "ddes-protocols"

settings.register_profile(
    PROTOCOL_PROFILE,
    derandomize=True,
    database=None,  # what derandomize implies; said here for hypothesis versions that do not
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                           HealthCheck.filter_too_much],
)


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("ddes", "ddes: deterministic ROS worlds")
    group.addoption(
        "--ddes-seed", type=int, default=0, metavar="N", dest="ddes_seed",
        help="seed of the ddes_seed, world and console fixtures (default 0); a failing test "
             "that used it prints the command that replays it")


def pytest_report_header(config: pytest.Config) -> str | None:
    seed = config.getoption("ddes_seed")
    return f"ddes {ddes.__version__}: --ddes-seed {seed}" if seed else None


@pytest.fixture(scope="session")
def ddes_seed(request: pytest.FixtureRequest) -> int:
    """The seed of this run's worlds: ``--ddes-seed N``, 0 without it.

    ``@pytest.mark.parametrize("ddes_seed", [1, 2, 3])`` runs a test on several.
    """
    return int(request.config.getoption("ddes_seed"))


@pytest.fixture
def world(ddes_seed: int) -> ddes.World:
    """A fresh ``ddes.World(seed=ddes_seed, strict=True)``.

    Strict: an exception raised in a callback or a node's main (a failed
    ``assert`` too) ends ``world.run()`` with that exception, so it fails the test.
    """
    return ddes.World(seed=ddes_seed, strict=True)


@pytest.fixture
def console(world: ddes.World) -> Iterator[ddes.Console]:
    """A ``ddes.Console`` on the ``world`` fixture, with ``/rosout`` running.

    ``console.run(line)`` returns what a command printed; what nodes print
    between commands goes to standard output, which pytest captures.  The
    console's world follows rospy's rule as ``ddes console`` does: a failing
    callback is reported after the command (``ERROR: bad callback ...``).
    Recordings still open at the end are closed (their bags written).
    """
    session = ddes.Console(world)
    try:
        yield session
    finally:
        session.close()


def replay_command(item: pytest.Item, seed: int | None) -> str:
    """``pytest 'tests/x.py::test_y' --ddes-seed 3``: run ``item`` alone on ``seed``.

    The test's path is written from the directory pytest was started in;
    ``seed`` None leaves the option out (a test parametrized over ``ddes_seed``
    carries its seed in its id).
    """
    where, sep, rest = item.nodeid.partition("::")
    try:
        where = Path(os.path.relpath(item.path, item.config.invocation_params.dir)).as_posix()
    except ValueError:  # another drive: the path from the rootdir
        pass
    line = f"pytest {shlex.quote(where + sep + rest)}"
    return line if seed is None else f"{line} --ddes-seed {seed}"


def _seed_of(item: pytest.Item) -> tuple[int, bool] | None:
    """The seed a test ran on and whether it was parametrized, or None: it used none."""
    if "ddes_seed" not in getattr(item, "fixturenames", ()):
        return None
    callspec = getattr(item, "callspec", None)
    if callspec is not None and "ddes_seed" in callspec.params:
        return int(callspec.params["ddes_seed"]), True
    funcargs: dict[str, Any] = getattr(item, "funcargs", {})
    seed = funcargs.get("ddes_seed", item.config.getoption("ddes_seed"))
    return int(seed), False


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item,
                              call: pytest.CallInfo[None]) -> Generator[None, Any, None]:
    outcome = yield
    report: pytest.TestReport = outcome.get_result()
    if not report.failed:
        return
    found = _seed_of(item)
    if found is None:
        return
    seed, parametrized = found
    command = replay_command(item, None if parametrized else seed)
    report.sections.append(("ddes", f"seed: {seed}\nreplay: {command}\n"))
    if ("ddes_seed", seed) not in item.user_properties:
        item.user_properties.append(("ddes_seed", seed))
        item.user_properties.append(("ddes_replay", command))
