"""Operator sweeps: mechanical mutants of a reference solution and their kill rate.

:func:`generate` makes mutants of the Python files of a solution folder (``mutants/`` left out)
with four operators, applied only to code inside the ``### BEGIN SOLUTION`` … ``### END
SOLUTION`` blocks (a ``### BEGIN SOLUTION stub: …`` line opens one too; the edited text must lie
on the lines between the two markers):

* ``flip``: one comparison operator replaced by its negation (``<``/``>=``, ``>``/``<=``,
  ``==``/``!=``, ``is``/``is not``, ``in``/``not in``), one mutant per operator of a chain;
* ``constant``: a numeric literal replaced (an int ``n`` by ``n + 1``; a float by ``0.0``, or
  ``1.0`` when it is 0; booleans are left alone);
* ``delete``: a statement that is a bare call (``ast.Expr`` of an ``ast.Call``) replaced by
  ``pass``;
* ``swap``: the first two positional arguments of a call exchanged (not when their source texts
  are the same, nor when either is ``*args``).

Each edit replaces the source text at the AST node's exact positions (lines and columns), so the
rest of the file keeps its formatting; every mutant is checked to parse.  A mutant's id is
``path:line:col:operator``: the path relative to the solution folder, the line (1-based) and
the column (0-based, in characters, as ``ast``'s ``col_offset`` for ASCII text) of what is
edited: the operator token (flip), the literal (constant), the statement (delete), the first
argument (swap; unique even for chained calls ``f(a, b)(c, d)``).  Mutants are ordered by path,
line, column and operator; :func:`sample` takes an evenly spaced deterministic sample.

:func:`sweep` grades the reference and every mutant on the engine of ``ddes grade
sensitivity`` (:func:`~ddes.grading.batch.grade_all`, the same seed and scenarios: the public
one and the hidden ones).  A mutant is *killed* when any criterion loses points against the
reference, or when it could not be graded (its submission refused, a grader error); else it
*survived*.  ``solutions/<ex>/mutants/operators.yaml`` maps the ids of equivalent mutants
(they cannot change behaviour) to the reason; an id there that is not generated is an error.
Kill rate = killed / (generated - equivalent).
"""

from __future__ import annotations

import ast
import io
import random
import re
import shutil
import tempfile
import tokenize
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

from ddes.errors import GradingError
from ddes.grading.batch import Job, grade_all
from ddes.grading.exercise import Exercise
from ddes.grading.mutants import solution_dir
from ddes.grading.report import GradeReport
from ddes.grading.sandbox import Limits

__all__ = ["OPERATORS", "OpMutant", "OperatorRow", "OperatorSweep", "generate", "generate_file",
           "load_equivalents", "sample", "solution_blocks", "sweep"]

OPERATORS = ("flip", "constant", "delete", "swap")
EQUIVALENTS = "operators.yaml"

_BEGIN = re.compile(r"^\s*### BEGIN SOLUTION\b")
_END = re.compile(r"^\s*### END SOLUTION\b")
#: A comparison operator's tokens -> its negation.
_NEGATION = {"<": ">=", ">=": "<", ">": "<=", "<=": ">", "==": "!=", "!=": "==",
             "is": "is not", "is not": "is", "in": "not in", "not in": "in"}


@dataclass(frozen=True)
class OpMutant:
    """One mechanical mutant: ``path`` (relative to the solution folder, POSIX), the position
    of the edit, the operator, a one-line description and the mutated file's whole text."""

    path: str
    line: int
    col: int
    operator: str
    description: str
    source: str = field(repr=False, compare=False)

    @property
    def id(self) -> str:
        return f"{self.path}:{self.line}:{self.col}:{self.operator}"

    @property
    def key(self) -> tuple[str, int, int, int]:
        return (self.path, self.line, self.col, OPERATORS.index(self.operator))


def solution_blocks(text: str) -> list[tuple[int, int]]:
    """The ``(first, last)`` line numbers (1-based, inclusive) of the code inside each SOLUTION
    block: the lines strictly between a BEGIN and its END marker.  An unclosed block reaches the
    end of the file."""
    out: list[tuple[int, int]] = []
    start: int | None = None
    lines = text.splitlines()
    for n, line in enumerate(lines, 1):
        if start is None and _BEGIN.match(line):
            start = n + 1
        elif start is not None and _END.match(line):
            if n - 1 >= start:
                out.append((start, n - 1))
            start = None
    if start is not None and len(lines) >= start:
        out.append((start, len(lines)))
    return out


class _Source:
    """A file's text with (line, byte column) -> character offset conversion."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.lines = text.splitlines(keepends=True)
        self.starts = [0]
        for line in self.lines:
            self.starts.append(self.starts[-1] + len(line))

    def char_col(self, line: int, byte_col: int) -> int:
        return len(self.lines[line - 1].encode("utf-8")[:byte_col].decode("utf-8", "replace"))

    def offset(self, line: int, char_col: int) -> int:
        return self.starts[line - 1] + char_col

    def span(self, node: ast.expr | ast.stmt) -> tuple[int, int]:
        """The character offsets ``[start, end)`` of a node."""
        lineno, col = node.lineno, node.col_offset
        end_line = node.end_lineno if node.end_lineno is not None else lineno
        end_col = node.end_col_offset if node.end_col_offset is not None else col
        return (self.offset(lineno, self.char_col(lineno, col)),
                self.offset(end_line, self.char_col(end_line, end_col)))

    def segment(self, node: ast.expr | ast.stmt) -> str:
        a, b = self.span(node)
        return self.text[a:b]


def _short(text: str, width: int = 60) -> str:
    """One line of at most ``width`` characters."""
    text = " ".join(text.split())
    return text if len(text) <= width else text[:width - 3] + "..."


def _inside(blocks: list[tuple[int, int]], first: int, last: int) -> bool:
    return any(a <= first and last <= b for a, b in blocks)


def _op_tokens(text: str) -> Iterator[tuple[int, int, int, int, str]]:
    """``(line, col, end_line, end_col, text)`` of every comparison-operator token (``not in``
    and ``is not`` as one), in characters."""
    toks = [t for t in tokenize.generate_tokens(io.StringIO(text).readline)
            if t.type in (tokenize.OP, tokenize.NAME)]
    i = 0
    while i < len(toks):
        t = toks[i]
        nxt = toks[i + 1] if i + 1 < len(toks) else None
        if t.string == "not" and nxt is not None and nxt.string == "in":
            yield (*t.start, *nxt.end, "not in")
            i += 2
            continue
        if t.string == "is" and nxt is not None and nxt.string == "not":
            yield (*t.start, *nxt.end, "is not")
            i += 2
            continue
        if t.string in _NEGATION:
            yield (*t.start, *t.end, t.string)
        i += 1


def generate_file(path: str, text: str) -> list[OpMutant]:
    """The mutants of one Python file's ``text`` (``path`` names it in the ids), in order.
    A file that does not parse has none (the grader reports it as it is)."""
    try:
        tree = ast.parse(text)
    except SyntaxError:
        return []
    blocks = solution_blocks(text)
    if not blocks:
        return []
    src = _Source(text)
    ops: dict[tuple[int, int], tuple[int, int, int, int, str]] = {}
    try:
        ops = {(t[0], t[1]): t for t in _op_tokens(text)}
    except (tokenize.TokenError, SyntaxError):
        ops = {}
    out: list[OpMutant] = []

    def add(start: int, end: int, new: str, line: int, col: int, operator: str,
            description: str) -> None:
        mutated = text[:start] + new + text[end:]
        try:
            ast.parse(mutated)
        except SyntaxError as exc:  # a generator bug, never a student's
            raise GradingError(f"operator {operator} at {path}:{line}:{col} makes a mutant "
                               f"that does not parse: {exc}") from None
        out.append(OpMutant(path, line, col, operator, description, mutated))

    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            left: ast.expr = node.left
            for right in node.comparators:
                _, a = src.span(left)
                b, _ = src.span(right)
                found = [t for (ln, c), t in ops.items() if a <= src.offset(ln, c) < b]
                if len(found) == 1:
                    ln, c, eln, ec, op = found[0]
                    if _inside(blocks, ln, eln):
                        add(src.offset(ln, c), src.offset(eln, ec), _NEGATION[op], ln, c, "flip",
                            f"{_short(src.segment(left), 28)} {op} {_short(src.segment(right), 28)}"
                            f" -> {_short(src.segment(left), 28)} {_NEGATION[op]} "
                            f"{_short(src.segment(right), 28)}")
                left = right
        elif isinstance(node, ast.Constant) and type(node.value) in (int, float):
            a, b = src.span(node)
            old = text[a:b]
            try:
                same = ast.literal_eval(old) == node.value
            except (ValueError, SyntaxError):
                same = False
            if not same or not _inside(blocks, node.lineno, node.end_lineno or node.lineno):
                continue  # positions that do not name the literal (f-strings of old Pythons)
            if isinstance(node.value, int):
                new = repr(node.value + 1)
            else:
                new = "0.0" if node.value != 0 else "1.0"
            add(a, b, new, node.lineno, src.char_col(node.lineno, node.col_offset), "constant",
                f"{old} -> {new}")
        elif isinstance(node, ast.Expr) and isinstance(node.value, ast.Call):
            if _inside(blocks, node.lineno, node.end_lineno or node.lineno):
                a, b = src.span(node)
                add(a, b, "pass", node.lineno, src.char_col(node.lineno, node.col_offset),
                    "delete", f"{_short(src.segment(node))} -> pass")
        if isinstance(node, ast.Call) and len(node.args) >= 2:
            x, y = node.args[0], node.args[1]
            if isinstance(x, ast.Starred) or isinstance(y, ast.Starred):
                continue
            sx, sy = src.segment(x), src.segment(y)
            if sx == sy or not _inside(blocks, x.lineno, y.end_lineno or y.lineno):
                continue
            (ax, bx), (ay, by) = src.span(x), src.span(y)
            func = _short(src.segment(node.func), 30)
            more = ", ..." if len(node.args) > 2 else ""
            add(ax, by, sy + text[bx:ay] + sx, x.lineno, src.char_col(x.lineno, x.col_offset),
                "swap", f"{func}({_short(sx, 24)}, {_short(sy, 24)}{more}) -> "
                        f"{func}({_short(sy, 24)}, {_short(sx, 24)}{more})")
    out.sort(key=lambda m: m.key)
    return out


def generate(solution: Path) -> list[OpMutant]:
    """The mutants of every ``.py`` file under ``solution`` (``mutants/`` and ``__pycache__``
    left out), ordered by path, line, column and operator."""
    out: list[OpMutant] = []
    for path in sorted(solution.rglob("*.py")):
        rel = path.relative_to(solution)
        if rel.parts[0] == "mutants" or "__pycache__" in rel.parts:
            continue
        out += generate_file(rel.as_posix(), path.read_text(encoding="utf-8"))
    out.sort(key=lambda m: m.key)
    return out


def sample(mutants: list[OpMutant], n: int | None, seed: int = 0) -> list[OpMutant]:
    """An evenly spaced sample of ``n`` mutants (all of them when ``n`` is None or not below
    their number): every ``len/n``-th one from an offset ``random.Random(seed)`` draws."""
    if n is None or n >= len(mutants):
        return list(mutants)
    if n <= 0:
        return []
    step = len(mutants) / n
    offset = random.Random(seed).random() * step
    return [mutants[min(int(offset + k * step), len(mutants) - 1)] for k in range(n)]


def load_equivalents(solution: Path, generated: list[OpMutant]) -> dict[str, str]:
    """``solution/mutants/operators.yaml``: the equivalent mutants' ids -> reasons ({} when the
    file is absent); an id that ``generated`` lacks is a :class:`GradingError` naming it."""
    import yaml

    path = solution / "mutants" / EQUIVALENTS
    if not path.is_file():
        return {}
    try:
        meta = yaml.safe_load(path.read_text(encoding="utf-8"))
    except yaml.YAMLError as exc:
        raise GradingError(f"{path} is not YAML: {exc}") from None
    if meta is None:
        return {}
    if not isinstance(meta, dict):
        raise GradingError(f"{path} must map each equivalent mutant's id "
                           "(path:line:col:operator) to the reason it is equivalent")
    known = {m.id for m in generated}
    unknown = sorted(str(k) for k in meta if str(k) not in known)
    if unknown:
        raise GradingError(f"{path}: {', '.join(unknown)} is not a generated mutant (any more): "
                           "the solution changed; run ddes grade operators to see the ids")
    for k, v in meta.items():
        if not isinstance(v, str) or not v.strip():
            raise GradingError(f"{path}: {k}: give the reason it is equivalent (a string)")
    return {str(k): str(v) for k, v in meta.items()}


@dataclass
class OperatorRow:
    """One graded mutant: its points lost per criterion and its status (``killed``,
    ``survived``, ``equivalent`` or ``KILLED (listed equivalent)``)."""

    mutant: OpMutant
    lost: dict[str, float]
    status: str
    error: str = ""


@dataclass
class OperatorSweep:
    """The result of :func:`sweep`."""

    exercise: str
    criteria: list[str]
    seed: int
    total: int  # mutants generated before sampling
    rows: list[OperatorRow] = field(default_factory=list)
    reference_lost: dict[str, float] = field(default_factory=dict)
    reference_error: str = ""
    min_rate: float = 95.0

    def count(self, status: str) -> int:
        return sum(1 for r in self.rows if r.status == status)

    @property
    def rate(self) -> float:
        killable = len(self.rows) - self.count("equivalent") - self.count(_WRONG)
        killed = self.count("killed")
        return 100.0 if killable <= 0 else 100.0 * killed / killable

    @property
    def wrong_equivalents(self) -> list[str]:
        return [r.mutant.id for r in self.rows if r.status == _WRONG]

    @property
    def reference_ok(self) -> bool:
        return not self.reference_error and not any(v > 0 for v in self.reference_lost.values())

    @property
    def ok(self) -> bool:
        return (self.reference_ok and not self.wrong_equivalents
                and self.rate >= self.min_rate)

    def summary(self) -> str:
        killed = self.count("killed")
        eq = self.count("equivalent") + self.count(_WRONG)
        return (f"operators {self.exercise}: {len(self.rows)} generated, {killed} killed, "
                f"{eq} equivalent, {self.count('survived')} survived: kill rate "
                f"{self.rate:.1f} %")

    def to_text(self) -> str:
        id_w = max([len(r.mutant.id) for r in self.rows] + [2])
        desc_w = min(max([len(r.mutant.description) for r in self.rows] + [11]), 70)
        col_w = max([len(c) for c in self.criteria] + [5])
        head = (f"{'id':<{id_w}}  {'operator':<8}  {'description':<{desc_w}}  "
                + " ".join(f"{c:>{col_w}}" for c in self.criteria))
        sampled = "" if len(self.rows) == self.total else f"; a sample of {len(self.rows)} " \
            f"of {self.total} mutants"
        out = [f"{self.exercise}: operator mutants (points lost against the reference; seed "
               f"{self.seed}{sampled})", head]
        if not self.reference_ok:
            why = self.reference_error or "loses " + ", ".join(
                f"{c} {v:g}" for c, v in self.reference_lost.items() if v > 0)
            out.append(f"(reference): {why}")
        for r in self.rows:
            if r.status == "killed" and not r.error:
                cells = " ".join(f"{(f'{r.lost[c]:.4g}' if r.lost.get(c) else '.'):>{col_w}}"
                                 for c in self.criteria)
            elif r.error:
                cells = f"killed: not graded ({_short(r.error, 80)})"
            elif r.status == _WRONG:
                cells = " ".join(f"{(f'{r.lost[c]:.4g}' if r.lost.get(c) else '.'):>{col_w}}"
                                 for c in self.criteria) + f"  {_WRONG}"
            else:
                cells = r.status
            desc = r.mutant.description
            desc = desc if len(desc) <= desc_w else desc[:desc_w - 3] + "..."
            out.append(f"{r.mutant.id:<{id_w}}  {r.mutant.operator:<8}  {desc:<{desc_w}}  "
                       f"{cells}")
        out.append(self.summary())
        return "\n".join(out) + "\n"


_WRONG = "KILLED (listed equivalent)"


def _copy_solution(solution: Path, dest: Path) -> None:
    shutil.copytree(solution, dest, ignore=shutil.ignore_patterns("mutants", "__pycache__"))


def sweep(exercise: Exercise, solutions: Path, *, n: int | None = None, sample_seed: int = 0,
          seed: int = 0, limits: Limits | None = None, min_rate: float = 95.0,
          progress: Callable[[str], None] | None = None, workers: int = 0,
          scheduler: str | None = None, retries: int | None = None,
          bar: TextIO | None = None) -> OperatorSweep:
    """Generate the mutants of ``solutions/<exercise id>/`` (a sample of ``n`` drawn with
    ``sample_seed``), grade the reference and each of them with scenario seed ``seed``, and
    judge each against the reference (see the module text)."""
    solution = solution_dir(solutions, exercise)
    generated = generate(solution)
    equivalents = load_equivalents(solution, generated)
    chosen = sample(generated, n, sample_seed)
    criteria = [c.id for c in exercise.criteria]
    result = OperatorSweep(exercise=exercise.id, criteria=criteria, seed=seed,
                           total=len(generated), min_rate=min_rate)
    tmp = Path(tempfile.mkdtemp(prefix="ddes-operators-"))
    try:
        _copy_solution(solution, tmp / "reference")
        jobs = [Job("reference", tmp / "reference", seed=seed)]
        for i, m in enumerate(chosen):
            folder = tmp / "mutants" / f"op{i:05d}"
            _copy_solution(solution, folder)
            (folder / m.path).write_text(m.source, encoding="utf-8")
            jobs.append(Job(f"op{i:05d}", folder, seed=seed))
        reports: list[GradeReport | str | None] = [None] * len(jobs)

        def got(j: int, report: GradeReport | str) -> None:
            reports[j] = report
            if progress is not None:
                name = "(reference)" if j == 0 else chosen[j - 1].id
                progress(f"{name}: " + (f"not graded: {report}" if isinstance(report, str)
                                        else f"{report.score:g}/{report.max_score:g}"))

        grade_all(exercise, jobs, limits=limits, workers=workers, scheduler=scheduler,
                  retries=retries, on_report=got, progress=bar)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    ref = reports[0]
    if isinstance(ref, str) or ref is None:
        result.reference_error = f"not graded: {ref}"
        ref_points: dict[str, float] = {c.id: c.max_points for c in exercise.criteria}
    else:
        ref_points = {c.id: c.points for c in ref.criteria}
        result.reference_lost = {c.id: float(round(c.max_points - c.points, 4))
                                 for c in ref.criteria}
    for m, report in zip(chosen, reports[1:]):
        if isinstance(report, str) or report is None:
            row = OperatorRow(m, {}, "killed", error=str(report))
        else:
            lost = {c.id: max(0.0, float(round(ref_points.get(c.id, c.max_points) - c.points, 4)))
                    for c in report.criteria}
            row = OperatorRow(m, lost, "killed" if any(v > 0 for v in lost.values())
                              else "survived")
        if m.id in equivalents:
            row.status = _WRONG if row.status == "killed" else "equivalent"
        result.rows.append(row)
    return result
