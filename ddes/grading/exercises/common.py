"""Checks the course's exercises share: the student's log lines, graph facts, a driver node."""

from __future__ import annotations

import ast
import re
from typing import TYPE_CHECKING, Any

from ddes.grading.course import notes, parse_source

if TYPE_CHECKING:
    from ddes.grading.exercise import Facts
    from ddes.graph.world import World

__all__ = ["NUMBER", "add_driver", "launch_problem", "student_logs", "student_subscriptions",
           "class_names", "calls_in", "call_name", "Source", "StudentScript", "student_script",
           "argument", "bound_to_self", "rospy_subscribers", "private_param_reads",
           "read_private", "PARAM_CALLS"]

NUMBER = re.compile(r"[-+]?(?:inf|\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)")


def launch_problem(facts: Facts) -> str:
    """Why the student's launch file did not start anything ('' when it did)."""
    n = notes(facts.world)
    if n.error:
        return n.error
    if not n.student_nodes:
        extra = f" ({'; '.join(n.problems)})" if n.problems else ""
        return f"{n.launch} starts no node of the submission's packages{extra}"
    return ""


def student_logs(facts: Facts) -> list[tuple[int, str, str]]:
    """``(t_ns, node, text)`` of every /rosout line of a student node, oldest first."""
    out = []
    for t, who, msg in facts.messages("/rosout"):
        if who in facts.student_nodes:
            out.append((t, who, str(msg.msg)))
    return out


def student_subscriptions(facts: Facts) -> list[tuple[str, str, int | None]]:
    """``(node, topic, queue_size)`` of the student's subscriptions, from the grader's master."""
    out = []
    for topic, entry in sorted(facts.world.master.topics.items()):
        for sub in entry.subscribers:
            if sub.node.name in facts.student_nodes:
                out.append((sub.node.name, topic, sub.queue_size))
    return out


def add_driver(world: World, moves: list[tuple[float, float, float]], *, rate: float = 10.0) -> None:
    """A grader node publishing ``/cmd_vel``: ``moves`` are ``(until_s, v, w)`` segments."""
    import ddes
    from ddes.msg import get_message_class

    Twist = get_message_class("geometry_msgs/Twist")
    node = world.create_node("/grader_driver", disable_rosout=True)
    pub = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)

    def tick(_event: Any) -> None:
        now = world.now / 1e9
        for until, v, w in moves:
            if now < until:
                msg = Twist()
                msg.linear.x, msg.angular.z = v, w
                pub.publish(msg)
                return

    ddes.Timer(node, 1.0 / rate, tick)


def class_names(tree: ast.Module) -> list[str]:
    return [n.name for n in tree.body if isinstance(n, ast.ClassDef)]


def calls_in(node: ast.AST) -> list[ast.Call]:
    return [n for n in ast.walk(node) if isinstance(n, ast.Call)]


def call_name(call: ast.Call) -> str:
    f = call.func
    if isinstance(f, ast.Name):
        return f.id
    if isinstance(f, ast.Attribute):
        return f.attr
    return ""


# -- source facts: a node script, the classes it builds and what their code calls ------------------
#
# A source check reads the submission with :mod:`ast` (never imported).  It must accept every
# form a correct student writes: a name imported under an alias (``import rospy as r``,
# ``from rospy import Subscriber as Sub``), a class defined in another module of the package
# and imported into the script (or inherited from one), a callback bound as ``self.cb``, through
# ``functools.partial(self.cb, ...)``, a ``lambda msg: self.cb(msg)`` or a local name holding
# one of these, positional or keyword arguments.  docs/grading.md, "Source checks", lists them.

#: How far imports, re-exports and base classes are followed.
_DEPTH = 4
#: Calls that read a parameter (rospy's API, in any spelling).
PARAM_CALLS = frozenset({"get_param", "get_param_cached", "has_param", "search_param",
                         "get_param_names"})


class Source:
    """One Python file of the submission, parsed, with the names its imports bind."""

    def __init__(self, rel: str, tree: ast.Module, package: str) -> None:
        self.rel = rel
        self.tree = tree
        #: local name -> the dotted name it stands for (``r`` -> ``rospy``, ``Sub`` ->
        #: ``rospy.Subscriber``, ``alg`` -> ``smb.algorithm``)
        self.aliases: dict[str, str] = {}
        #: modules imported with ``from M import *``
        self.stars: list[str] = []
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for a in node.names:
                    if a.asname:
                        self.aliases[a.asname] = a.name
                    else:
                        top = a.name.split(".")[0]
                        self.aliases.setdefault(top, top)
            elif isinstance(node, ast.ImportFrom):
                module = node.module or ""
                if node.level:
                    parts = package.split(".") if package else []
                    parts = parts[:len(parts) - (node.level - 1)] if node.level > 1 else parts
                    module = ".".join([*parts, *([module] if module else [])])
                for a in node.names:
                    if a.name == "*":
                        self.stars.append(module)
                    else:
                        self.aliases[a.asname or a.name] = f"{module}.{a.name}" if module \
                            else a.name
        self.defs = {n.name: n for n in tree.body
                     if isinstance(n, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))}

    def origin(self, expr: ast.AST) -> str:
        """The dotted name ``expr`` stands for ('' if it is not a name or attribute chain)."""
        if isinstance(expr, ast.Name):
            return self.aliases.get(expr.id, expr.id)
        if isinstance(expr, ast.Attribute):
            base = self.origin(expr.value)
            return f"{base}.{expr.attr}" if base else ""
        return ""

    def called(self, call: ast.Call) -> str:
        """The name a call's target stands for, its last part: ``call_name`` through the
        imports' aliases (``Sub(...)`` of ``from rospy import Subscriber as Sub`` is
        ``Subscriber``; a call of a call's result, ``f()()``, is '')."""
        name = self.origin(call.func)
        return name.rsplit(".", 1)[-1] if name else call_name(call)


class StudentScript:
    """A node script and the classes of the submission it builds, read with :mod:`ast`.

    ``classes`` are the classes the script defines, those it imports from a module of the
    submission (``from pkg.controller import Controller``, ``import pkg.controller as c``,
    re-exported by a package's ``__init__``), and their base classes found in the submission.
    ``main`` is everything of the script outside its own classes (its main part, its top-level
    functions); ``built`` is whether the main part calls one of ``classes``."""

    def __init__(self, facts: Facts, rel: str, tree: ast.Module) -> None:
        self.facts = facts
        self.rel = rel
        top = rel.split("/")[0] if "/" in rel else ""
        here = rel.rsplit("/", 1)[0] if "/" in rel else ""
        roots = [here, f"{top}/src" if top else "src", top, ""]
        try:
            roots += sorted(str(p.relative_to(facts.submission)) for p in
                            facts.submission.glob("*/src") if p.is_dir())
        except (OSError, ValueError):
            pass
        self.roots = list(dict.fromkeys(r.strip("/") for r in roots))
        self._cache: dict[str, Source | None] = {}
        self.script = Source(rel, tree, "")
        self.main = [n for n in tree.body if not isinstance(n, ast.ClassDef)]
        self.classes: list[tuple[Source, ast.ClassDef]] = []
        own = [(self.script, n) for n in tree.body if isinstance(n, ast.ClassDef)]
        built: list[tuple[Source, ast.ClassDef]] = []
        for n in self.main:
            for c in calls_in(n):
                found = self.resolve_call(self.script, c)
                if found is not None and isinstance(found[1], ast.ClassDef):
                    built.append((found[0], found[1]))
        self.built = bool(built)
        for src, cls in [*own, *built]:
            self._add(src, cls, _DEPTH)
        #: names the main part binds to an instance of one of ``classes``
        self.instances = {t.id for n in self.main for a in ast.walk(n)
                          if isinstance(a, (ast.Assign, ast.AnnAssign)) and a.value is not None
                          and isinstance(a.value, ast.Call) and self.builds(self.script, a.value)
                          for t in (a.targets if isinstance(a, ast.Assign) else [a.target])
                          if isinstance(t, ast.Name)}

    # -- modules of the submission ---------------------------------------------------------------
    def module(self, dotted: str) -> Source | None:
        """The submission's module ``dotted`` (``pkg.algorithm``) found under the script's
        directory, its package's ``src/``, the package, the submission, or any ``*/src``."""
        if dotted in self._cache:
            return self._cache[dotted]
        self._cache[dotted] = None
        parts = dotted.split(".")
        if not dotted or not all(p.isidentifier() for p in parts):
            return None
        for root in self.roots:
            base = "/".join([*([root] if root else []), *parts])
            for rel, package in ((f"{base}.py", ".".join(parts[:-1])),
                                 (f"{base}/__init__.py", dotted)):
                text = self.facts.read_text(rel)
                if text is None:
                    continue
                try:
                    tree = ast.parse(text, rel)
                except (SyntaxError, ValueError, RecursionError, MemoryError):  # too deep to parse
                    continue
                self._cache[dotted] = Source(rel, tree, package)
                return self._cache[dotted]
        return None

    def resolve(self, src: Source, dotted: str, depth: int = _DEPTH
                ) -> tuple[Source, ast.AST] | None:
        """The class or function of the submission that ``dotted``, read in ``src``, names."""
        if depth <= 0 or not dotted:
            return None
        if "." not in dotted:
            if dotted in src.defs and src.aliases.get(dotted, dotted) == dotted:
                return src, src.defs[dotted]
            for star in src.stars:
                mod = self.module(star)
                if mod is not None and dotted in mod.defs:
                    return mod, mod.defs[dotted]
            return None
        module, name = dotted.rsplit(".", 1)
        mod = self.module(module)
        if mod is None:
            return None
        if name in mod.defs:
            return mod, mod.defs[name]
        if name in mod.aliases:   # re-exported: ``from .controller import Controller``
            return self.resolve(mod, mod.aliases[name], depth - 1)
        return None

    def resolve_call(self, src: Source, call: ast.Call) -> tuple[Source, ast.AST] | None:
        """The submission's class or function a call in ``src`` calls, if any."""
        return self.resolve(src, src.origin(call.func))

    def target_file(self, src: Source, call: ast.Call) -> str:
        """The submission's file defining what a call in ``src`` calls ('' if none)."""
        found = self.resolve_call(src, call)
        return found[0].rel if found is not None else ""

    def builds(self, src: Source, call: ast.Call) -> bool:
        """Whether ``call`` (in ``src``) builds a class of the submission."""
        found = self.resolve_call(src, call)
        return found is not None and isinstance(found[1], ast.ClassDef)

    def _add(self, src: Source, cls: ast.ClassDef, depth: int) -> None:
        if depth <= 0 or any(c is cls for _s, c in self.classes):
            return
        self.classes.append((src, cls))
        for base in cls.bases:
            found = self.resolve(src, src.origin(base))
            if found is not None and isinstance(found[1], ast.ClassDef):
                self._add(found[0], found[1], depth - 1)

    # -- what the code calls ---------------------------------------------------------------------
    def class_calls(self) -> list[tuple[Source, ast.Call, ast.AST | None]]:
        """Every call in the classes' code: ``(its module, the call, its method)``."""
        out: list[tuple[Source, ast.Call, ast.AST | None]] = []
        for src, cls in self.classes:
            for item in cls.body:
                method = item if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) \
                    else None
                out += [(src, c, method) for c in calls_in(item)]
        return out

    def main_calls(self) -> list[ast.Call]:
        """The main part's calls, without those of a method of one of ``classes`` on an
        instance of it (``controller.send_goal()`` on the student's own class is the class's
        logic, not the main part's)."""
        out = []
        for n in self.main:
            for c in calls_in(n):
                f = c.func
                if isinstance(f, ast.Attribute) and (
                        (isinstance(f.value, ast.Name) and f.value.id in self.instances)
                        or (isinstance(f.value, ast.Call) and self.builds(self.script, f.value))):
                    continue
                out.append(c)
        return out

    def main_called(self) -> set[str]:
        return {self.script.called(c) for c in self.main_calls()}


def student_script(facts: Facts, rel: str) -> StudentScript | None:
    """``rel`` of the submission read as a :class:`StudentScript`, or None when it is missing
    or does not parse."""
    tree = parse_source(facts, rel)
    return None if tree is None else StudentScript(facts, rel, tree)


def argument(call: ast.Call, index: int, keyword: str) -> ast.AST | None:
    """A call's argument by position or keyword (None when absent, or hidden in ``*args``)."""
    if any(isinstance(a, ast.Starred) for a in call.args[:index + 1]):
        return None
    if len(call.args) > index:
        return call.args[index]
    return next((k.value for k in call.keywords if k.arg == keyword), None)


def bound_to_self(src: Source, expr: ast.AST | None, method: ast.AST | None,
                  depth: int = 3) -> bool:
    """Whether a callback expression is one of the object's own methods: ``self.cb``,
    ``getattr(self, "cb")``, ``functools.partial(self.cb, ...)``, ``lambda msg: self.cb(msg,
    ...)``, or a local name of the method assigned one of these (``self`` is the method's first
    parameter, whatever it is called)."""
    if expr is None or depth <= 0:
        return False
    args = getattr(method, "args", None)
    me = args.args[0].arg if args is not None and args.args else "self"
    if isinstance(expr, ast.Attribute):
        return isinstance(expr.value, ast.Name) and expr.value.id == me
    if isinstance(expr, ast.Lambda):
        return isinstance(expr.body, ast.Call) and bound_to_self(src, expr.body.func, method,
                                                                 depth - 1)
    if isinstance(expr, ast.Call):
        name = src.called(expr)
        if name in ("partial", "partialmethod") and expr.args:
            return bound_to_self(src, expr.args[0], method, depth - 1)
        return (name == "getattr" and len(expr.args) >= 2 and isinstance(expr.args[0], ast.Name)
                and expr.args[0].id == me)
    if isinstance(expr, ast.Name) and method is not None:
        values = [a.value for a in ast.walk(method) if isinstance(a, ast.Assign)
                  and any(isinstance(t, ast.Name) and t.id == expr.id for t in a.targets)]
        return bool(values) and all(bound_to_self(src, v, method, depth - 1) for v in values)
    return False


def rospy_subscribers(script: StudentScript) -> list[tuple[Source, ast.Call, ast.AST | None]]:
    """The classes' ``rospy.Subscriber`` calls in any spelling (message_filters' Subscriber,
    which takes no callback, is not one)."""
    return [(s, c, m) for s, c, m in script.class_calls() if s.called(c) == "Subscriber"
            and not s.origin(c.func).startswith("message_filters")]


def private_param_reads(facts: Facts) -> tuple[list[str], list[str]]:
    """Every parameter the student's nodes read, found or not, by resolved name: ``(those in
    the reading node's own private namespace, the others)``; ``/use_sim_time`` (read by
    rospy's clock machinery) is left out."""
    private: list[str] = []
    other: list[str] = []
    nodes = set(facts.student_nodes)
    for _t, node, key, _found in facts.param_reads:
        if node not in nodes or key == "/use_sim_time":
            continue
        me = node.rstrip("/")
        (private if key.rstrip("/") == me or key.startswith(me + "/") else other).append(key)
    return list(dict.fromkeys(private)), list(dict.fromkeys(other))


def read_private(facts: Facts, name: str) -> bool:
    """Whether a student node read its private parameter ``name`` (``~name``, the node's name
    joined with it, or the node's whole private namespace, ``get_param("~")``, holding it)."""
    n = notes(facts.world)
    plan = n.plan.params if n.plan is not None else {}
    for _t, node, key, found in facts.param_reads:
        if node not in facts.student_nodes:
            continue
        me = node.rstrip("/")
        if key == f"{me}/{name}" or (key.rstrip("/") == me and found
                                     and f"{me}/{name}" in plan):
            return True
    return False


def relative(dt_ns: int, event: str) -> str:
    """How far from ``event`` something happened, never as a negative duration: ``"1.50 s
    after the cancel"``, ``"0.20 s before the cancel"``, ``"at the cancel"`` (within 5 ms)."""
    if abs(dt_ns) < 5_000_000:
        return f"at {event}"
    return f"{abs(dt_ns) / 1e9:.2f} s {'after' if dt_ns > 0 else 'before'} {event}"
