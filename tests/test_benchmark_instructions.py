"""benchmarks/instructions.py: every case resolves, and callgrind's counts are repeatable.

The counts are only asserted to be repeatable and consistent with their ratios (no figure is
asserted: a tiny run's figures mean nothing).  The runs need valgrind; they skip where it is
not installed, as the ROS interop tests skip without ROS.
"""

from __future__ import annotations

import importlib
import importlib.util
import re
import shutil
import sys
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parent.parent
BENCH = ROOT / "benchmarks"


@pytest.fixture(scope="module")
def instructions() -> Any:
    sys.path.insert(0, str(BENCH))
    try:
        yield importlib.import_module("instructions")
    finally:
        sys.path.remove(str(BENCH))


def test_every_case_names_a_figure_and_functions_that_exist(instructions: Any) -> None:
    spec = importlib.util.spec_from_file_location("_figures", ROOT / "tests" / "test_benchmarks.py")
    assert spec is not None and spec.loader is not None
    figures = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(figures)
    FIGURES = figures.FIGURES

    for name, case in instructions.CASES.items():
        assert name in FIGURES or name.removesuffix("_numpy") in FIGURES, name
        assert {"ddes", "base"} <= set(case), name
        for role in ("ddes", "base", "fair"):
            if role not in case:
                continue
            module, attr, args = case[role]
            mod = importlib.import_module(module)
            fn = getattr(mod, attr)
            assert callable(fn), (name, role)
            assert args is None or isinstance(args, list), (name, role)
        if "ops" in case:
            assert isinstance(getattr(importlib.import_module(case["ddes"][0]), case["ops"]),
                              float)


def test_nothing_measured_calls_the_counting_toggle() -> None:
    # callgrind toggles counting on entering and leaving operator.call: a call inside the code
    # being counted would switch it off for the rest of that call
    for path in sorted((ROOT / "ddes").rglob("*.py")) + sorted(BENCH.glob("bench_*.py")):
        text = path.read_text(encoding="utf-8")
        assert not re.search(r"\boperator\.call\b|from operator import [^\n]*\bcall\b", text), path


needs_valgrind = pytest.mark.skipif(shutil.which("valgrind") is None,
                                    reason="valgrind is not installed")


WORK = """
def loop(n, warm_n):
    calls = [0]

    def run():
        calls[0] += 1
        k = warm_n if calls[0] == 1 else n  # the first call is the warm-up
        s = 0
        for i in range(k):
            s += i
        return n

    return run
"""


@pytest.fixture()
def work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "work.py").write_text(WORK)
    monkeypatch.setenv("PYTHONPATH", str(tmp_path))  # the children import it
    return tmp_path


@needs_valgrind
def test_only_the_warm_call_is_counted_and_counts_repeat(instructions: Any, work: Path) -> None:
    small, ops = instructions.count("work", "loop", [1000, 0])
    assert ops == 1000
    again, _ = instructions.count("work", "loop", [1000, 0])
    assert abs(again - small) <= 0.001 * small  # repeatable
    double, _ = instructions.count("work", "loop", [2000, 0])
    # twice the loop, twice the count: the imports and the set-up are not in it
    assert 1.9 < double / small < 2.1
    # a heavy warm-up call (200 times the counted loop) is not in it either; what it leaves
    # behind (the allocator's state) moves the count by a few per cent at most
    warm_heavy, _ = instructions.count("work", "loop", [1000, 200_000])
    assert abs(warm_heavy - small) <= 0.05 * small


@needs_valgrind
def test_measure_gives_the_ratios_of_its_counts(instructions: Any, work: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(instructions.CASES, "work_case", {
        "ddes": ("work", "loop", [2000, 0]), "base": ("work", "loop", [1000, 0]),
        "fair": ("work", "loop", [1500, 0])})
    (row,) = instructions.measure(["work_case"], jobs=3)
    assert row["name"] == "work_case" and row["unit"] == "instructions/op"
    # per operation (the function returns n) the three loops cost about the same
    assert 0.9 < row["ratio"] < 1.1 and 0.9 < row["fair_ratio"] < 1.1
    assert abs(row["ratio"] - row["base"] / row["ddes"]) < 0.005  # of the unrounded counts
    assert abs(row["fair_ratio"] - row["fair"] / row["ddes"]) < 0.005


@needs_valgrind
@pytest.mark.slow
@pytest.mark.ci  # about a minute and a half on two cores: CI runs it (.ci/run)
def test_a_real_case_runs_at_the_tiny_size(instructions: Any,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DDES_BENCH_TINY", "1")
    (row,) = instructions.measure(["rate_sleeps"], jobs=3)
    assert row["ddes"] > 0 and row["base"] > 0 and row["fair"] > 0
    total, ops = instructions.count("bench_time", "raw_simpy", None)
    assert ops == 100  # the tiny size of bench_time.N
    assert abs(total / ops - row["base"]) <= 0.001 * row["base"]


@needs_valgrind
def test_a_failing_child_raises_with_its_output(instructions: Any, work: Path) -> None:
    with pytest.raises(instructions.InstructionCountError, match="no_such_function"):
        instructions.count("work", "no_such_function", None)


@pytest.mark.parametrize(("argv", "says"), [
    (["nosuch"], "no case matches nosuch; cases: topic_delivery_1to1"),
    (["-j", "0"], "--jobs must be 1 or more, got 0"),
    (["--bogus"], "unrecognized arguments: --bogus"),
])
def test_bad_arguments_are_named(argv: list[str], says: str) -> None:
    import subprocess

    proc = subprocess.run([sys.executable, str(BENCH / "instructions.py"), *argv],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert says in proc.stderr
