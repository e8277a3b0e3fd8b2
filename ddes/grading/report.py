"""A grade and its formats: text, Gradescope's ``results.json``, JUnit XML.

``results.json`` follows Gradescope's autograder spec: top-level ``score``,
``execution_time``, ``output``, ``visibility``, ``extra_data`` and ``tests[]``, each test with
``name``, ``number``, ``score``, ``max_score``, ``status``, ``output`` and ``visibility``.
JUnit XML has no points field: each criterion is a ``<testcase>`` whose ``<properties>`` carry
``points`` and ``max_points``, failed when it earned less than its maximum, with the evidence
and the replay command in the failure.
"""

from __future__ import annotations

import json
import math
import os
import re
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

from ddes._floats import left_sum

__all__ = ["CriterionReport", "GradeReport", "utf8_safe", "write_atomic"]

_SURROGATE = re.compile("[\ud800-\udfff]")


def utf8_safe(text: str) -> str:
    """``text`` with each lone surrogate replaced by U+FFFD, so that it encodes as UTF-8: a file
    name that is not UTF-8 (read with ``surrogateescape``), a JSON ``\\udcff`` of a notebook or
    of the student's output, wherever it reaches a report, prints and writes."""
    return _SURROGATE.sub("\ufffd", text)


def _utf8_safe_all(value: object) -> object:
    """``value`` (JSON-like: dicts, lists, strings, numbers) with every string utf8_safe."""
    if isinstance(value, str):
        return utf8_safe(value)
    if isinstance(value, dict):
        return {(utf8_safe(k) if isinstance(k, str) else k): _utf8_safe_all(v)
                for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_utf8_safe_all(v) for v in value]
    return value


@dataclass
class CriterionReport:
    """One criterion's outcome."""

    id: str
    name: str
    points: float
    max_points: float
    visibility: str = "visible"
    evidence: list[str] = field(default_factory=list)
    replay: str = ""

    @property
    def passed(self) -> bool:
        return self.points >= self.max_points

    def output(self) -> str:
        lines = list(self.evidence)
        if self.replay and not self.passed:
            lines.append(f"replay: {self.replay}")
        return "\n".join(lines)


def _round(x: float) -> float:
    return float(round(x, 4))


@dataclass
class GradeReport:
    """The grade of one submission for one exercise."""

    exercise: str
    title: str
    submission: str
    seed: int
    public: bool
    criteria: list[CriterionReport] = field(default_factory=list)
    #: Problems with the submission or the run, each naming what it costs.
    problems: list[str] = field(default_factory=list)
    #: What the sandbox enforced on the student's process.
    enforced: list[str] = field(default_factory=list)
    execution_time: float = 0.0
    submission_sha256: str = ""
    ddes_version: str = ""
    #: The trace digest of each scenario's trusted world, by scenario name (what
    #: ``ddes grade replay`` reproduces).
    digests: dict[str, str] = field(default_factory=dict)

    @property
    def score(self) -> float:
        return _round(left_sum(c.points for c in self.criteria))

    @property
    def max_score(self) -> float:
        return _round(left_sum(c.max_points for c in self.criteria))

    @property
    def percent(self) -> float:
        return 100.0 * self.score / self.max_score if self.max_score else 0.0

    # -- text -----------------------------------------------------------------------------------
    def to_text(self) -> str:
        out = [f"{self.exercise} — {self.title}", f"submission: {self.submission}"]
        for p in self.problems:
            out.append(f"problem: {p}")
        for c in self.criteria:
            head = f"{c.id} {c.name} "
            out.append(f"{head:.<60} {c.points:g}/{c.max_points:g}")
            out += [f"  {line}" for line in c.evidence]
            if c.replay and not c.passed:
                out.append(f"  replay: {c.replay}")
        scope = "public scenarios only" if self.public else "all scenarios"
        out.append(f"total: {self.score:g}/{self.max_score:g} ({self.percent:.1f} %, {scope})")
        return utf8_safe("\n".join(out) + "\n")

    # -- Gradescope -------------------------------------------------------------------------------
    def to_gradescope(self) -> dict[str, object]:
        summary = [f"{self.exercise}: {self.score:g}/{self.max_score:g}"]
        if self.public:
            summary.append("Public scenarios only: hidden scenarios are not graded in this run.")
        summary += [f"Problem: {p}" for p in self.problems]
        tests = []
        for c in self.criteria:
            tests.append({
                "name": f"{c.id} {c.name}",
                "number": c.id,
                "score": _round(c.points),
                "max_score": _round(c.max_points),
                "status": "passed" if c.passed else "failed",
                "output": c.output(),
                "visibility": c.visibility,
            })
        results: dict[str, object] = {
            "score": self.score,
            "execution_time": _round(self.execution_time),
            "output": "\n".join(summary),
            "visibility": "visible",
            "extra_data": {"ddes_version": self.ddes_version, "exercise": self.exercise,
                           "seed": self.seed, "public": self.public,
                           "submission_sha256": self.submission_sha256,
                           "enforced": list(self.enforced), "digests": dict(self.digests)},
            "tests": tests,
        }
        return _utf8_safe_all(results)  # type: ignore[return-value]

    def write_results(self, path: str | os.PathLike[str]) -> None:
        write_atomic(path, json.dumps(self.to_gradescope(), indent=2, ensure_ascii=False) + "\n")

    # -- JUnit ------------------------------------------------------------------------------------
    def to_junit(self) -> str:
        failures = sum(1 for c in self.criteria if not c.passed)
        suite = ET.Element("testsuite", {
            "name": _xml_safe(f"ddes.{self.exercise}"), "tests": str(len(self.criteria)),
            "failures": str(failures), "errors": "0", "skipped": "0",
            "time": f"{self.execution_time:.3f}"})
        props = ET.SubElement(suite, "properties")
        for name, value in (("score", f"{self.score:g}"), ("max_score", f"{self.max_score:g}"),
                            ("seed", str(self.seed)), ("public", str(self.public).lower())):
            ET.SubElement(props, "property", {"name": name, "value": value})
        for c in self.criteria:
            case = ET.SubElement(suite, "testcase", {"classname": _xml_safe(self.exercise),
                                                     "name": _xml_safe(f"{c.id} {c.name}"),
                                                     "time": "0"})
            cprops = ET.SubElement(case, "properties")
            ET.SubElement(cprops, "property", {"name": "points", "value": f"{c.points:g}"})
            ET.SubElement(cprops, "property", {"name": "max_points", "value": f"{c.max_points:g}"})
            if not c.passed:
                fail = ET.SubElement(case, "failure", {
                    "message": f"{c.points:g}/{c.max_points:g}", "type": "CriterionFailed"})
                fail.text = _xml_safe(c.output())
        if self.problems:
            err = ET.SubElement(suite, "system-err")
            err.text = _xml_safe("\n".join(self.problems))
        root = ET.Element("testsuites")
        root.append(suite)
        ET.indent(root)
        return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"

    def write_junit(self, path: str | os.PathLike[str]) -> None:
        write_atomic(path, self.to_junit())


def _xml_safe(text: str) -> str:
    """Text without the characters XML 1.0 cannot hold (a student's output may carry any)."""
    return "".join(ch if ch in "\t\n\r" or (" " <= ch <= "\ud7ff") or ("\ue000" <= ch <= "\ufffd")
                   or ch >= "\U00010000" else "\ufffd" for ch in text)


def write_atomic(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and a rename: whatever was there
    before (a file the student's process wrote, say) is replaced whole.  ``text`` is written as
    UTF-8, each lone surrogate as U+FFFD (:func:`utf8_safe`)."""
    text = utf8_safe(text)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        if path.is_symlink() or path.is_dir():
            raise OSError(f"{path} is a link or a folder: refusing to write results there")
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def finite_points(value: object, max_points: float) -> float:
    """Points clamped to [0, max]; anything not a finite number earns 0 (fail closed)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return 0.0
    return float(min(max(float(value), 0.0), max_points))
