"""Run every benchmark and print one JSON object per line.

Each line has at least ``name``, ``value``, ``unit``, ``baseline`` and
``ratio`` (ddes's value over the baseline's, both measured in this run, on
this machine).  Benchmarks live in ``bench_*.py`` modules beside this file,
each exposing ``benchmarks() -> list[dict]``.

    python benchmarks/run.py              # all
    python benchmarks/run.py time msg     # only bench_time.py and bench_msg.py
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv: list[str]) -> int:
    wanted = set(argv)
    for path in sorted(HERE.glob("bench_*.py")):
        short = path.stem.removeprefix("bench_")
        if wanted and short not in wanted:
            continue
        spec = importlib.util.spec_from_file_location(path.stem, path)
        assert spec and spec.loader
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        for row in module.benchmarks():
            print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
