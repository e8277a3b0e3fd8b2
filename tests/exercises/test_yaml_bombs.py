"""Student YAML the trusted grader reads (answers.yaml, RViz configs, config files, service
call arguments) goes through the bounded loader: an alias bomb costs its criterion, with the
bound named, and never the grader's memory."""

from __future__ import annotations

import shutil
import tracemalloc
from pathlib import Path

from ddes.grading import REGISTRY, grade

REPO = Path(__file__).resolve().parents[2]

BOMB = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"{chr(98 + i)}: &{chr(98 + i)} [*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, "
    f"*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, "
    f"*{chr(97 + i)}]\n" for i in range(9))


def test_an_alias_bomb_in_answers_yaml_costs_the_answers_only(tmp_path: Path) -> None:
    sub = tmp_path / "submission"
    shutil.copytree(REPO / "solutions" / "ex1_console", sub,
                    ignore=shutil.ignore_patterns("mutants"))
    (sub / "answers.yaml").write_text(BOMB)
    tracemalloc.start()
    try:
        report = grade(REGISTRY.get("ex1_console"), sub, public=True)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    points = {c.id: c.points for c in report.criteria}
    assert points == {"1.1": 32, "1.2": 48, "1.3": 0}
    evidence = " ".join(report.criteria[2].evidence)
    assert "answers.yaml is not YAML" in evidence and "alias" in evidence, evidence
    assert peak < 64 * 2**20, peak  # 9**10 nodes if expanded
