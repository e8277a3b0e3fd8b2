"""Same scenario + same seed = same trace, whatever PYTHONHASHSEED is."""

from __future__ import annotations

import os
import subprocess
import sys

SCRIPT = "from ddes.cli.demo import run_demo; print(run_demo(seed=3, out=lambda s: None))"


def _digest(hashseed: str) -> str:
    env = dict(os.environ, PYTHONHASHSEED=hashseed)
    out = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True,
                         check=True)
    return out.stdout.strip()


def test_demo_digest_is_independent_of_hash_seed() -> None:
    digests = {seed: _digest(seed) for seed in ("0", "1", "4242")}
    assert len(set(digests.values())) == 1, digests
    assert len(digests["0"]) == 64


def test_same_seed_same_digest_in_process() -> None:
    from ddes.cli.demo import run_demo

    assert run_demo(seed=5, out=lambda s: None) == run_demo(seed=5, out=lambda s: None)
