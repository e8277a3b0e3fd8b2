"""Print how long one grade of each course exercise's reference takes on this machine (wall and
CPU of the whole ``ddes grade`` process tree): issue 20 asks for <= 10 s wall per submission on
the CI machine.  A measurement for the log, not a test: it fails only if a grade fails."""

from __future__ import annotations

import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DDES = ROOT / ".venv" / "bin" / "ddes"


def main() -> int:
    exercises = sorted(p.name for p in (ROOT / "solutions").iterdir() if p.is_dir())
    print(f"{'exercise':<16} {'wall s':>7} {'cpu s':>7}  score")
    for ex in exercises:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        done = subprocess.run([str(DDES), "grade", ex, str(ROOT / "solutions" / ex)],
                              capture_output=True, text=True, check=False)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        total = [line for line in done.stdout.splitlines() if line.startswith("total:")]
        print(f"{ex:<16} {wall:7.2f} {cpu:7.2f}  {total[-1] if total else '(no total)'}",
              flush=True)
        if done.returncode != 0:
            print(done.stdout[-2000:], done.stderr[-2000:], sep="\n")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
