"""roslaunch substitution args: ``$(arg x)``, ``$(find pkg)``, ``$(eval ...)`` ...

:func:`resolve_args` follows ``roslaunch/substitution_args.py``:

* The text is scanned for ``$(...)`` with roslaunch's state machine: no
  escapes, and a ``$`` or ``(`` inside a substitution is an error.  So
  ``$(find $(arg pkg))`` is rejected exactly as roslaunch rejects it; write
  ``$(eval find(arg('pkg')))`` instead.
* ``$(env)``, ``$(optenv)``, ``$(dirname)``, ``$(anon)`` and ``$(arg)`` are
  replaced first (every occurrence of the same text at once), then
  ``$(find pkg)`` (so an argument value may hold a ``$(find)``).
* ``$(eval expr)`` is special: it must be the whole attribute value
  (``$(eval 1) x`` is an "Unknown substitution command").  ``expr`` is a
  Python expression; bare names are the launch args (converted like
  ``type="auto"`` params), shadowed by ``true``/``false``, the ``math``
  module's names and the functions ``arg()``, ``anon()``, ``dirname()``,
  ``env()``, ``optenv()`` and ``find()``.  ``__`` is forbidden, as in
  roslaunch.

Deviations, on purpose (see docs/launch.md):

* ``$(anon id)`` draws from the loader's seeded generator, never the host
  name, pid or clock; as in roslaunch, the same id gives the same name
  within one scope and the scopes nested in it.
* ``$(env)``, ``$(optenv)`` read the environment mapping the loader was
  given (``os.environ`` by default).
* ``$(eval)`` is evaluated by :mod:`ddes.expr`, a safe subset of Python
  walked without ``eval``: side-effect-free builtins (``len``, ``abs``,
  ``min``, ``max``, ``round``, ``range``, ``str``, ``int`` ...), no names or
  attributes starting with ``_``, no lambda or comprehensions, and cost
  limits (``9**9**9`` is refused at once).  roslaunch ``eval``s the text with
  every builtin reachable, ``open`` included.  A refusal is a
  ``ROSLaunchException`` that is also an ``UnsafeExpressionError`` (or a
  ``ResourceLimitError``).
* ``$(find pkg)/path`` joins ``path`` to the package folder from the ddes
  :class:`~ddes.rospack.RosPack`; catkin's devel/install spaces do not exist.
* Sizes are bounded before a value is built: a substituted value may hold at
  most :data:`MAX_VALUE_CHARS` characters (or as many as the text it was
  written as, if more), and the substitutions of one load, its includes
  too, may add at most :data:`MAX_EXPANSION_CHARS` characters in all; past
  either a :class:`LaunchLimitError` (a ``ROSLaunchException`` and a
  ``ResourceLimitError``).  The ``$(eval)``s of one load may touch
  :data:`MAX_EVAL_WORK` items together (each at most ``ddes.expr.MAX_WORK``).  Args defined as ``$(arg a)$(arg a)`` double at
  every step: 40 of them would make a terabyte, and roslaunch hangs on them.
"""

from __future__ import annotations

import math
import os
import random
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

from ddes import expr as safe_expr
from ddes.errors import DdesError, ResourceLimitError, ROSLaunchException, UnsafeExpressionError
from ddes.graph.names import anonymous_name
from ddes.launch.values import convert_value
from ddes.rospack import PackageNotFound

__all__ = ["COMMANDS", "MAX_EVAL_WORK", "MAX_EXPANSION_CHARS", "MAX_VALUE_CHARS", "ExpansionBudget",
           "LaunchLimitError", "PackageFinder", "SubstitutionContext", "resolve_args"]

#: The substitution commands, in the order roslaunch lists them in its error message.
COMMANDS = ("find", "env", "optenv", "dirname", "anon", "arg")

#: The longest value substitutions may make, in characters (1 MiB), unless the text it was
#: written as is longer (a ``<rosparam subst_value="true">`` body of a large file).
MAX_VALUE_CHARS = 1 << 20
#: The characters the substitutions of one load (the file and every file it includes) may add
#: in all (16 MiB): a value's length beyond the text it was written as, summed.
MAX_EXPANSION_CHARS = 16 << 20
#: The items all ``$(eval)``s of one load may touch together (each at most
#: ``ddes.expr.MAX_WORK``): a file of thousands of costly expressions ends, not only each one.
MAX_EVAL_WORK = 4 * safe_expr.MAX_WORK


class LaunchLimitError(ROSLaunchException, ResourceLimitError):
    """A launch file past one of ddes's size limits (both error kinds at once)."""


@dataclass
class ExpansionBudget:
    """What substitutions have cost so far in one load (shared by every scope): characters
    added, and items touched by ``$(eval)``."""

    added: int = 0
    eval_work: int = 0


class PackageFinder(Protocol):
    """Anything with ``get_path(name)``, e.g. :class:`ddes.rospack.RosPack`."""

    def get_path(self, name: str) -> Path: ...


@dataclass
class SubstitutionContext:
    """What substitutions can see: the args in scope, the anon names made so far, the file.

    ``child()`` copies ``args`` and ``anon`` (roslaunch deep-copies its
    resolve dict for every child scope), so names made or args declared in
    a ``<group>`` do not leak out of it.  ``anon_source`` is shared by all
    scopes of one load.
    """

    rospack: PackageFinder
    environ: Mapping[str, str]
    anon_source: random.Random
    filename: str | None = None
    args: dict[str, str] = field(default_factory=dict)
    anon: dict[str, str] = field(default_factory=dict)
    expansion: ExpansionBudget = field(default_factory=ExpansionBudget)

    def child(self) -> SubstitutionContext:
        """A copy for a nested scope (args and anon names copied, the rest shared)."""
        return SubstitutionContext(self.rospack, self.environ, self.anon_source, self.filename,
                                   dict(self.args), dict(self.anon), self.expansion)

    # -- the values behind each command ------------------------------------------------

    def arg(self, name: str) -> str:
        """The value of launch arg ``name``."""
        try:
            return self.args[name]
        except KeyError:
            raise ROSLaunchException(
                f"arg '{name}' is not defined. Declare it with <arg name=\"{name}\" "
                f"default=\"...\"/> or pass {name}:=VALUE (an <arg> declared without "
                "value or default must be given a value)"
            ) from None

    def env(self, name: str) -> str:
        """The environment variable ``name``; an error if unset."""
        try:
            return self.environ[name]
        except KeyError:
            raise ROSLaunchException(
                f"environment variable '{name}' is not set; set it, or use "
                f"$(optenv {name} default)"
            ) from None

    def optenv(self, name: str, default: str = "") -> str:
        """The environment variable ``name``, or ``default``."""
        return self.environ.get(name, default)

    def anon_name(self, id: str) -> str:
        """The anonymous name for ``id`` in this scope, made on first use."""
        if id not in self.anon:
            self.anon[id] = anonymous_name(id, self.anon_source)
        return self.anon[id]

    def dirname(self) -> str:
        """The absolute folder of the launch file being read."""
        if not self.filename:
            raise ROSLaunchException(
                "Cannot substitute $(dirname), no file/directory information available. "
                "Load the launch file from a file, not from a string"
            )
        return os.path.abspath(os.path.dirname(self.filename))

    def find(self, pkg: str) -> str:
        """The folder of package ``pkg``."""
        try:
            return str(self.rospack.get_path(pkg))
        except PackageNotFound as exc:
            raise ROSLaunchException(f"$(find {pkg}): {exc}") from None


def resolve_args(text: str, ctx: SubstitutionContext) -> str:
    """Resolve every substitution in ``text`` (roslaunch ``resolve_args``).

    Sizes are checked before each value is built (see :data:`MAX_VALUE_CHARS`
    and :data:`MAX_EXPANSION_CHARS`); past them :class:`LaunchLimitError`.
    """
    if not text or "$" not in text:
        return text
    size = _Size(text, ctx)
    if text.startswith("$(eval ") and text.endswith(")"):
        resolved = _eval(text[7:-1], ctx, size)
    else:
        resolved = _resolve_pass(text, ctx, ("env", "optenv", "dirname", "anon", "arg"), size)
        if "$(" in resolved:  # a value may hold a $(find); without one the pass finds nothing
            resolved = _resolve_pass(resolved, ctx, ("find",), size)
    ctx.expansion.added += max(len(resolved) - len(text), 0)
    return resolved


class _Size:
    """The size checks of one :func:`resolve_args`: each new value, before it is built."""

    def __init__(self, text: str, ctx: SubstitutionContext) -> None:
        self.text_len = len(text)
        self.limit = max(MAX_VALUE_CHARS, self.text_len)
        self.ctx = ctx

    def check(self, new_len: int, what: str) -> None:
        if new_len > self.limit:
            raise LaunchLimitError(
                f"{what} would make a value of {new_len} characters, more than the "
                f"{self.limit} a substitution may make (ddes.launch.substitution."
                "MAX_VALUE_CHARS, or the length of the text written); args that repeat each "
                "other ($(arg a)$(arg a)) double at every step: write the value out instead")
        total = self.ctx.expansion.added + max(new_len - self.text_len, 0)
        if total > MAX_EXPANSION_CHARS:
            raise LaunchLimitError(
                f"{what} would take the characters substitutions add in this launch (its "
                f"includes too) to {total}, more than the {MAX_EXPANSION_CHARS} ddes allows in "
                "all (ddes.launch.substitution.MAX_EXPANSION_CHARS); args expanding each other "
                "or a large value repeated many times: write the values out instead")


def _resolve_pass(text: str, ctx: SubstitutionContext, active: tuple[str, ...],
                  size: _Size) -> str:
    resolved = text
    for sub in _collect(text):
        words = [w for w in sub.split(" ") if w]
        if not words or words[0] not in COMMANDS:
            hint = (" ($(eval ...) must be the whole attribute value)"
                    if words and words[0] == "eval" else "")
            raise ROSLaunchException(
                f"Unknown substitution command [{sub}]. Valid commands are "
                f"{list(COMMANDS)}{hint}"
            )
        command, params = words[0], words[1:]
        if command in active:
            resolved = _APPLY[command](resolved, sub, params, ctx, size)
    return resolved


def _collect(text: str) -> list[str]:
    """The bodies of the ``$(...)`` in ``text``, in order (roslaunch ``_collect_args``).

    roslaunch's character state machine, stepping from one ``$``, ``(`` or ``)`` to the next
    (a run of other characters only moves ``$`` and ``$(`` on), so a long value costs one scan.
    """
    out, dollar, lparen, inside = 0, 1, 2, 3
    state = out
    found: list[str] = []
    start = prev = 0
    for m in _SPECIAL.finditer(text):
        i = m.start()
        if i > prev:  # ordinary characters text[prev:i]
            if state == dollar:
                state = out
            elif state == lparen:
                state, start = inside, prev
        c = text[i]
        if c == "$":
            if state in (lparen, inside):
                raise ROSLaunchException(
                    f"Dollar signs '$' cannot be inside of substitution args [{text}]; "
                    "roslaunch does not nest substitutions: use $(eval ...) with arg(), "
                    "find(), env() instead"
                )
            state = dollar
        elif c == "(":
            if state == dollar:
                state = lparen
            elif state != out:
                raise ROSLaunchException(
                    f"Invalid left parenthesis '(' in substitution args [{text}]"
                )
        else:  # ")"
            if state == inside:
                found.append(text[start:i])
            state = out
        prev = i + 1
    return found


_SPECIAL = re.compile(r"[$()]")


_Apply = Callable[[str, str, list[str], SubstitutionContext, _Size], str]


def _simple(value: Callable[[list[str], SubstitutionContext, str], str]) -> _Apply:
    def apply(resolved: str, sub: str, params: list[str], ctx: SubstitutionContext,
              size: _Size) -> str:
        token = f"$({sub})"
        new = value(params, ctx, sub)
        size.check(len(resolved) + resolved.count(token) * (len(new) - len(token)), token)
        return resolved.replace(token, new)
    return apply


def _env_value(params: list[str], ctx: SubstitutionContext, sub: str) -> str:
    if len(params) != 1:
        raise ROSLaunchException(f"$(env var) command only accepts one argument [{sub}]")
    return ctx.env(params[0])


def _optenv_value(params: list[str], ctx: SubstitutionContext, sub: str) -> str:
    if not params:
        raise ROSLaunchException(f"$(optenv var) must specify an environment variable [{sub}]")
    return ctx.optenv(params[0], " ".join(params[1:]))


def _anon_value(params: list[str], ctx: SubstitutionContext, sub: str) -> str:
    if not params:
        raise ROSLaunchException(f"$(anon var) must specify a name [{sub}]")
    if len(params) > 1:
        raise ROSLaunchException(f"$(anon var) may only specify one name [{sub}]")
    return ctx.anon_name(params[0])


def _arg_value(params: list[str], ctx: SubstitutionContext, sub: str) -> str:
    if not params:
        raise ROSLaunchException(f"$(arg var) must specify a variable name [{sub}]")
    if len(params) > 1:
        raise ROSLaunchException(f"$(arg var) may only specify one arg [{sub}]")
    return ctx.arg(params[0])


def _dirname_value(params: list[str], ctx: SubstitutionContext, sub: str) -> str:
    return ctx.dirname()


def _apply_find(resolved: str, sub: str, params: list[str], ctx: SubstitutionContext,
                size: _Size) -> str:
    # roslaunch joins the path that follows $(find pkg) (up to the next space) to the
    # package folder with os.path.join, after dropping one leading separator.
    if len(params) != 1:
        raise ROSLaunchException(f"$(find pkg) command only accepts one argument [{sub}]")
    token = f"$({sub})"
    i = resolved.find(token)
    before, after = resolved[:i], resolved[i + len(token):]
    space = after.find(" ")
    path, rest = (after, "") if space < 0 else (after[:space], after[space:])
    path = path.replace("\\", "/")
    if path.startswith("/"):
        path = path[1:]
    pkg_path = ctx.find(params[0])
    if path:
        pkg_path = os.path.join(pkg_path, path)
    size.check(len(before) + len(pkg_path) + len(rest), token)
    return before + pkg_path + rest


_APPLY: dict[str, _Apply] = {
    "env": _simple(_env_value),
    "optenv": _simple(_optenv_value),
    "anon": _simple(_anon_value),
    "arg": _simple(_arg_value),
    "dirname": _simple(_dirname_value),
    "find": _apply_find,
}

# -- $(eval ...) ---------------------------------------------------------------------------

#: The builtins of $(eval): ddes.expr's, less set/frozenset (their print order is not stable).
_EVAL_BUILTINS = {k: v for k, v in safe_expr.SAFE_FUNCTIONS.items()
                  if k not in ("set", "frozenset")}


class UnsafeLaunchExpression(ROSLaunchException, UnsafeExpressionError):
    """A ``$(eval ...)`` outside ddes's safe expression subset (both error kinds at once)."""


class CostlyLaunchExpression(ROSLaunchException, ResourceLimitError):
    """A ``$(eval ...)`` that would cost more than ddes allows."""


_MATH: dict[str, object] = {k: v for k, v in vars(math).items() if not k.startswith("_")}


class _EvalNames(Mapping[str, object]):
    """Name lookup for $(eval): functions and math first, then the args (auto-converted)."""

    def __init__(self, ctx: SubstitutionContext) -> None:
        self._ctx = ctx
        self._functions: dict[str, object] = {
            "true": True, "false": False, "True": True, "False": False,
            "env": ctx.env, "optenv": ctx.optenv, "find": ctx.find,
            "anon": ctx.anon_name,
            "arg": lambda name: convert_value(ctx.arg(name), "auto"),
            "dirname": ctx.dirname,
        }
        self._functions.update(_MATH)

    def __getitem__(self, key: str) -> object:
        if key in self._functions:
            return self._functions[key]
        return convert_value(self._ctx.args[key], "auto")

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self._functions)

    def __len__(self) -> int:
        return len(self._functions)


def _eval(expr: str, ctx: SubstitutionContext, size: _Size) -> str:
    if "__" in expr:
        raise UnsafeLaunchExpression(
            f"$(eval {expr}): $(eval ...) may not contain double underscore expressions")
    names = _EvalNames(ctx)
    try:
        parsed = safe_expr.parse(expr, functions=[f for f in names._functions.values() if callable(f)],
                                 builtins=_EVAL_BUILTINS)
        left = MAX_EVAL_WORK - ctx.expansion.eval_work
        try:
            value, work = parsed.evaluate_counted(names, budget=max(left, 0))
        except ResourceLimitError as exc:
            if left < safe_expr.MAX_WORK and "items touched" in str(exc):
                raise ResourceLimitError(
                    f"{exc} (the $(eval)s of one launch, its includes too, may touch "
                    f"{MAX_EVAL_WORK} items in all, ddes.launch.substitution.MAX_EVAL_WORK; "
                    f"{ctx.expansion.eval_work} are spent)") from None
            raise
        ctx.expansion.eval_work += work
        text = safe_expr.to_text(value, size.limit)
        size.check(len(text), "$(eval ...)")
        return text
    except ROSLaunchException:
        raise
    except DdesError as exc:  # any error of the user's expression, or a refusal
        message = (f"$(eval {expr}) failed: {exc}. Bare names are launch args or math "
                   "functions; use arg('name') to read an arg")
        if isinstance(exc, UnsafeExpressionError):
            raise UnsafeLaunchExpression(message) from None
        if isinstance(exc, ResourceLimitError):
            raise CostlyLaunchExpression(message) from None
        raise ROSLaunchException(message) from None
