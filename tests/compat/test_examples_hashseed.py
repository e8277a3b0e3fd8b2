"""examples/rospy_scripts.py's rospy pairs print the same under three PYTHONHASHSEEDs.

Each pair (talker/listener, add_two_ints server/client, Fibonacci action server/client: the
bundled tutorial scripts, which run unchanged under real rospy, see test_rospy_interop.py) runs
alone in a subprocess, ``python examples/rospy_scripts.py <pair>``, under each seed; every
line its scripts print or log and the world's trace digest must be identical.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "rospy_scripts.py"
SEEDS = ("0", "1", "12345")


def _run(pair: str, seed: str) -> str:
    return subprocess.run([sys.executable, str(EXAMPLE), pair], capture_output=True, text=True,
                          env={"PYTHONHASHSEED": seed, "PATH": "/usr/bin"}, check=True,
                          timeout=300).stdout


@pytest.mark.parametrize(("pair", "expected"), [
    ("chatter", ["talker.py (log) [INFO] [0.000000]: hello world 0.0",
                 "talker.py (log) [INFO] [0.100000]: hello world 0.1",
                 "listener.py (log) [INFO] [0.100000]: /listenerI heard hello world 0.1",
                 "talker.py (log) [INFO] [0.200000]: hello world 0.2",
                 "listener.py (log) [INFO] [0.200000]: /listenerI heard hello world 0.2",
                 "talker.py (log) [INFO] [0.300000]: hello world 0.3",
                 "listener.py (log) [INFO] [0.300000]: /listenerI heard hello world 0.3"]),
    ("add_two_ints", ["add_two_ints_server.py (print) Ready to add two ints.",
                      "add_two_ints_client.py (print) Requesting 3+4",
                      "add_two_ints_server.py (print) Returning [3 + 4 = 7]",
                      "add_two_ints_client.py (print) 3 + 4 = 7"]),
    ("fibonacci", ["fibonacci_server.py (log) [INFO] [0.001000]: /fibonacci: Executing, "
                   "creating fibonacci sequence of order 20 with seeds 0, 1",
                   "fibonacci_server.py (log) [INFO] [19.001000]: /fibonacci: Succeeded",
                   "fibonacci_client.py (print) Result: 0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55, "
                   "89, 144, 233, 377, 610, 987, 1597, 2584, 4181, 6765"]),
])
def test_each_pair_prints_the_same_under_three_hash_seeds(pair: str, expected: list[str]
                                                          ) -> None:
    outs = {_run(pair, seed) for seed in SEEDS}
    assert len(outs) == 1, outs
    *lines, digest = outs.pop().splitlines()
    assert lines == expected
    assert digest.startswith(f"{pair}: trace digest ") and len(digest.split()[-1]) == 16
