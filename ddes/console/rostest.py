"""``rostest`` on simulated time: each ``<test>`` of a launch file against a fresh launch.

:func:`run_rostest` does what Noetic's ``rostest`` (``rostest/rostest_main.py``,
``rostest/runner.py``) does, in its order and with its texts, but every test runs in a world
of its own on simulated time (docs/rostest.md):

* The file is loaded once (:func:`ddes.launch.load_launch`); its ``<test>`` elements are
  :attr:`~ddes.launch.plan.LaunchPlan.tests`. rostest makes a unittest ``TestCase``
  (``rostest.runner.RosTest``) with one method ``test<test-name>`` per test and runs it with
  unittest's text runner (``--text``) or rosunit's XML runner; so does ddes.
* Each method: a fresh world (``World(seed)``), the file's parameters and ``<node>``s launched
  as roslaunch's runner launches them (no ``/rosout``: rostest starts none), then the test node
  with ``--gtest_output=xml:FILE`` (and ``--text``), ``__name:=NAME``, its args and
  remappings. The world runs until the test node ends, ``time-limit`` simulated seconds pass
  (``RLTestTimeoutException``, "max time [Ts] allotted for test ..."), or the launch shuts
  down (a ``required`` node died). The test's results file is read back
  (:mod:`ddes.compat.rosunit.junitxml`); a failed test with ``retry`` left runs again in a
  fresh world whose seed is the next one (``seed + attempt``).
* Then rostest's ``[ROSTEST]---`` SUMMARY (with ``--text`` too: a deviation, ddes always has
  the results), the launch file's warnings, and ddes's lines: the simulated time, the trace
  events and the **trace digest** of all the test worlds (the same on every run), and for each
  failed test the seed that replays it.

Output: ``out`` gets what rostest prints on standard output, in order (with ``--text`` the
unittest report, which unittest writes to standard error, is written here too, so the joined
lines read as on a terminal); ``err`` gets rostest's error lines. Exit codes are rostest's:
0 all passed, 1 a test did not run or timed out (the runner's own failure), 2 a test
reported failures or errors.
"""

from __future__ import annotations

import hashlib
import math
import os
import unittest
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ddes.compat.rosunit import (
    XML_OUTPUT_FLAG,
    rostest_name_from_path,
    test_results_dir,
    xml_results_file,
)
from ddes.compat.rosunit.junitxml import Result, read, suite_xml
from ddes.compat.rosunit.runner import LineStream, XMLResult, runner_summary, text_run
from ddes.errors import DdesError, ROSConsoleError, ROSLaunchException
from ddes.time.units import ns_to_sec

if TYPE_CHECKING:
    import simpy

    from ddes.console.tooling import ToolContext
    from ddes.graph.world import World
    from ddes.launch.plan import LaunchPlan, TestSpec
    from ddes.launch.runtime import LaunchRunner
    from ddes.rospack import RosPack

__all__ = ["RLTestTimeoutException", "RostestReport", "TOOLS", "TestRun", "package_of",
           "parse_rostest_args", "run_rostest"]

# unittest leaves the frames of a module with this global out of its tracebacks: a test's
# failure reads as rostest's does, without ddes's own frames.
__unittest = True

Print = Callable[[str], None]
WorldFactory = Callable[[int], "World"]


class RLTestTimeoutException(ROSLaunchException):
    """A test ran past its ``time-limit`` (roslaunch's exception of that name)."""


RLTestTimeoutException.__module__ = "roslaunch.launch"  # as unittest prints it: rostest's name


@dataclass
class TestRun:
    """One attempt of one ``<test>``: its world's seed, digest and what came of it."""

    __test__ = False  # not a pytest test class

    test_name: str
    attempt: int
    seed: int
    simulated_ns: int = 0
    events: int = 0
    digest: str = ""
    exit_code: int | None = None
    timed_out: bool = False
    results: Result | None = None

    @property
    def failed(self) -> bool:
        """True when the attempt timed out, wrote no results, or reported a problem."""
        return (self.timed_out or self.results is None
                or bool(self.results.num_errors or self.results.num_failures))


@dataclass
class RostestReport:
    """What a rostest run did: its exit code and counts, each attempt, the digest."""

    code: int
    file: str
    package: str
    tests: int = 0
    errors: int = 0
    failures: int = 0
    runs: list[TestRun] = field(default_factory=list)
    results_file: str | None = None
    digest: str = ""
    simulated_ns: int = 0
    events: int = 0
    summary: list[str] = field(default_factory=list)


def package_of(path: str | os.PathLike[str], rospack: RosPack) -> tuple[str, Path]:
    """The package holding ``path`` (rospkg's ``get_package_name``: the nearest folder above it
    with a ``package.xml``) and its folder; a file in no package counts as a package named
    after its folder."""
    start = Path(path).resolve().parent
    for folder in (start, *start.parents):
        if (folder / "package.xml").is_file():
            for name in rospack.list():
                try:
                    if rospack.get_path(name).resolve() == folder:
                        return name, folder
                except DdesError:
                    continue
            return folder.name, folder
    return start.name, start


@dataclass
class _Options:
    text: bool = False
    seed: int = 0
    results_filename: str | None = None
    results_dir: str | None = None
    instant_budget: int | None = None
    #: ``--latency S``: every topic connection's latency in the test worlds (seconds).
    latency: float = 0.0
    help: bool = False
    words: list[str] = field(default_factory=list)


_USAGE = ("usage: rostest [options] [package] <filename> [arg:=value ...]\n"
          "options: -t/--text, --seed N, --results-filename NAME, --results-dir DIR "
          "(--results-base-dir DIR), --instant-budget N, --latency S, --package PKG "
          "--pkgdir DIR")


def parse_rostest_args(argv: Sequence[str]) -> _Options:
    """rostest's options (plus ddes's ``--seed`` and ``--results-dir``); the rest are words."""
    opts = _Options()
    it = iter(argv)
    for word in it:
        key, eq, value = word.partition("=")
        if word in ("-t", "--text"):
            opts.text = True
        elif key in ("--seed", "--results-filename", "--results-dir", "--results-base-dir",
                     "--package", "--pkgdir", "--instant-budget", "--latency"):
            if not eq:
                given = next(it, None)
                if given is None:
                    raise ROSConsoleError(f"{key} needs a value\n{_USAGE}")
                value = given
            if key == "--latency":
                try:
                    latency = float(value)
                except ValueError:
                    raise ROSConsoleError(f"--latency needs seconds, got {value!r}") from None
                if not 0 <= latency <= 60:
                    raise ROSConsoleError(f"--latency must be between 0 and 60 seconds, got "
                                          f"{value}")
                opts.latency = latency
            elif key in ("--seed", "--instant-budget"):
                try:
                    number = int(value)
                except ValueError:
                    raise ROSConsoleError(f"{key} needs an integer, got {value!r}") from None
                if key == "--seed":
                    opts.seed = number
                elif number < 1:
                    raise ROSConsoleError(f"--instant-budget must be >= 1, got {number}")
                else:
                    opts.instant_budget = number
            elif key == "--results-filename":
                opts.results_filename = value
            elif key in ("--results-dir", "--results-base-dir"):
                opts.results_dir = value
            # --package/--pkgdir: rosbuild2's hints; ddes finds the package itself
        elif word in ("-r", "--reuse-master", "-c", "--clear"):
            raise ROSConsoleError(f"{word}: ddes has no master to reuse: every test runs in a "
                                  "fresh world of its own")
        elif word in ("-h", "--help"):
            opts.help = True
        elif word.startswith("-") and ":=" not in word:
            raise ROSConsoleError(f"no such option: {word}\n{_USAGE}")
        else:
            opts.words.append(word)
    return opts


class _Output:
    """rostest's two kinds of lines: its own (shown with ``--text``, else kept for its XML
    file's ``system-out``) and the nodes' (always shown), joined to an open unittest line."""

    def __init__(self, out: Print, err: Print, text: bool) -> None:
        self.out = out
        self.err = err
        self.text = text
        self.stream = LineStream(out)
        self.kept_out: list[str] = []
        self.kept_err: list[str] = []

    def log(self, line: str) -> None:
        """One of rostest's or roslaunch's own lines (standard output)."""
        if self.text:
            self.out(self.stream.take() + line)
        else:
            self.kept_out.append(line)

    def logerr(self, line: str) -> None:
        """One of rostest's error lines (standard error)."""
        if self.text:
            self.err(line)
        else:
            self.kept_err.append(line)

    def screen(self, line: str) -> None:
        """A line of a node's output that reaches the terminal."""
        self.out(self.stream.take() + line)


class _Rostest:
    """One rostest run: the plan, the options, the worlds (see the module docstring)."""

    def __init__(self, path: str, args: dict[str, str], plan: LaunchPlan, package: str,
                 rospack: RosPack, make_world: WorldFactory, opts: _Options, output: _Output,
                 results_base: Path) -> None:
        self.path = path
        self.args = args
        self.plan = plan
        self.fixture = replace(plan, tests=[], warnings=[])
        self.package = package
        self.rospack = rospack
        self.make_world = make_world
        self.opts = opts
        self.o = output
        self.results_base = results_base
        self.runs: list[TestRun] = []
        self.results = Result("rostest")
        self.done_ns = 0
        self.world: World | None = None
        self.runner: LaunchRunner | None = None

    # -- the clock of the unittest runners: simulated seconds of every test world so far ----------
    def clock(self) -> float:
        now = int(self.world.env.now) if self.world is not None else 0
        return (self.done_ns + now) / 1e9

    def printlog(self, text: str) -> None:
        self.o.log("[ROSTEST]" + text)

    # -- the TestCase ---------------------------------------------------------------------------
    def test_case(self) -> type[unittest.TestCase]:
        from ddes.nodes import find_script, load_node_types

        run = self
        names: list[str] = []
        methods: dict[str, Any] = {"__module__": "rostest.runner"}

        def set_up(case: unittest.TestCase) -> None:
            run.set_up(0)

        def tear_down(case: unittest.TestCase) -> None:
            run.tear_down()

        methods["setUp"] = set_up
        methods["tearDown"] = tear_down
        for test in self.plan.tests:
            problem = None
            try:
                folder = self.rospack.get_path(test.pkg)
            except DdesError:
                problem = (f"Package [{test.pkg}] for test node [{test.pkg}/{test.type}] does "
                           "not exist")
            else:
                try:
                    found = (test.type in load_node_types(folder)
                             or find_script(folder, test.type, test.pkg) is not None)
                except DdesError:
                    found = False
                if not found:
                    problem = (f"Test node [{test.pkg}/{test.type}] does not exist or is not "
                               "executable")
            name = f"test{test.test_name}"
            if problem is not None:
                methods[name] = _fail_runner(problem, self.o)
            elif name in names:
                methods[name] = _fail_duplicate(test.test_name, self.o)
            else:
                methods[name] = _test_runner(self, test)
                names.append(name)
        return type("RosTest", (unittest.TestCase,), methods)

    # -- set-up and tear-down: a fresh world per attempt ------------------------------------------
    def set_up(self, attempt: int) -> None:
        from ddes.launch.runtime import LaunchRunner, LogRouter, run_id

        seed = self.opts.seed + attempt
        world = self.make_world(seed)
        world.raise_callback_errors = False
        if self.opts.instant_budget is not None:
            world.instant_budget = self.opts.instant_budget
        if self.opts.latency:
            world.set_link(latency=self.opts.latency)
        self.world = world
        self.seed = seed
        router = LogRouter(world, self.o.screen).install()
        self.runner = LaunchRunner(world, self.fixture, rospack=self.rospack, out=self.o.log,
                                   router=router)
        self.run_id = run_id(world)
        self.printlog(f"setup[{self.path}] run_id[{self.run_id}] starting")
        self.o.log(self.runner.summary())
        self.printlog(f"setup[{self.path}] run_id[{self.run_id}] done")

    def tear_down(self) -> None:
        runner, world = self.runner, self.world
        self.printlog(f"tearDown[{self.path}]")
        if runner is not None and world is not None:
            runner.teardown()
            self.done_ns += int(world.env.now)
        self.runner = self.world = None
        self.printlog(f"rostest teardown {self.path} complete")

    def launch(self) -> list[str]:
        """roslaunch's ``launch()`` for rostest: core parameters, the parameters, the nodes."""
        from ddes.launch.runtime import CORE_PARAMS, node_uri

        runner, world = self.runner, self.world
        assert runner is not None and world is not None
        from ddes.launch.runtime import LaunchRunner

        failed: list[str] = []
        for spec in self.fixture.nodes:  # each on its own, to name the ones that fail
            one = LaunchRunner(world, replace(self.fixture, nodes=[spec]), rospack=self.rospack,
                               out=self.o.log, router=runner.router)
            try:
                one.validate()
            except ROSLaunchException as exc:
                self.o.logerr(str(exc))
                failed.append(spec.name)
        if failed:
            return failed
        params = world.master.params
        self.o.log(f"ROS_MASTER_URI={node_uri('/master')}")
        for key, value in CORE_PARAMS.items():
            params.set_param(key, value)
        params.set_param("/run_id", self.run_id)
        self.o.log(f"setting /run_id to {self.run_id}")
        runner.setup_params()
        runner.launch_nodes()
        return []

    def run_test(self, test: TestSpec, results_file: str, record: TestRun) -> None:
        """Start the test node and run the world until it ends, times out or the launch ends."""
        from ddes.compat.scripts import run_script
        from ddes.graph.rosout import DEBUG, WARN
        from ddes.nodes import find_script, load_node_types, start_node

        runner, world = self.runner, self.world
        assert runner is not None and world is not None
        args = [*test.args, f"{XML_OUTPUT_FLAG}{results_file}"]
        if self.o.text:
            args.append("--text")
        args += [f"{src}:={dst}" for src, dst in test.remappings]
        args.append(f"__name:={test.name}")
        proc = runner.add_process(test)
        runner.router.levels[test.full_name] = DEBUG if self.o.text else WARN
        self.o.log(f"process[{proc.label}]: started with pid [{_pid(test.full_name)}]")
        env = world.env
        folder = self.rospack.get_path(test.pkg)
        live = [True]  # off once the world is left behind: a test node stuck in it is silent
        done: simpy.Event
        ctx = None
        if test.type in load_node_types(folder):  # a node type of a nodes.py
            done = env.event()
            try:
                node = start_node(world, test.pkg, test.type, rospack=self.rospack,
                                  name=test.name, namespace=test.namespace, argv=args)
            except Exception as exc:  # noqa: BLE001 - the node's own start-up failed
                self.o.screen(f"{type(exc).__name__}: {exc}")
                done.fail(exc)
                done.defused = True
            else:
                proc.node = node
                node.on_shutdown(lambda _reason: None if done.triggered else _succeed(done, 0))
        else:
            script = find_script(folder, test.type, test.pkg)
            assert script is not None  # checked when the TestCase was made
            text = self.o.text

            def printed(line: str, stderr: bool) -> None:
                if live[0] and (text or stderr):
                    self.o.screen(line)

            done, ctx = run_script(world, script, args, namespace=test.namespace,
                                   print_line=printed)
            proc.node = ctx.node
        started = int(env.now)
        # time-limit="inf" never times out
        limit = (env.timeout(max(1, round(test.time_limit * 1e9)))
                 if math.isfinite(test.time_limit) else env.event())
        ended = env.event()  # succeeds when done does either way (a crash is the exit code 1)
        done.callbacks.append(lambda _ev: _succeed(ended))
        try:
            world.run(env.any_of([ended, limit, runner.finished]))
        finally:
            record.simulated_ns = int(env.now) - started
        if proc.node is None and ctx is not None:
            proc.node = ctx.node  # the script called init_node after its first wait
        if done.triggered:
            code = done.value if done.ok and isinstance(done.value, int) else (
                0 if done.ok else 1)
            if not done.ok:
                done.defused = True
            record.exit_code = code
            runner.process_exited(proc, code)
            return
        live[0] = False
        if runner.finished.triggered:
            return  # the launch shut down (a required node died): no results
        record.timed_out = True
        raise RLTestTimeoutException(
            f"max time [{test.time_limit}s] allotted for test [{test.test_name}] of type "
            f"[{test.pkg}/{test.type}]")

    def finish_attempt(self, record: TestRun) -> None:
        world = self.world
        if world is not None:
            record.digest = world.digest()
            record.events = len(world.trace)
        self.runs.append(record)


def _succeed(event: simpy.Event, value: object = None) -> None:
    event.succeed(value)


def _pid(name: str) -> int:
    from ddes.launch.runtime import node_pid

    return node_pid(name)


def _fail_runner(message: str, o: _Output) -> Callable[[unittest.TestCase], None]:
    def fn(case: unittest.TestCase) -> None:
        o.logerr(message)
        case.fail(message)

    return fn


def _fail_duplicate(test_name: str, o: _Output) -> Callable[[unittest.TestCase], None]:
    def fn(case: unittest.TestCase) -> None:
        o.log(f"Duplicate tests named [{test_name}] in rostest suite")
        case.fail(f"Duplicate tests named [{test_name}] in rostest suite")

    return fn


def _test_runner(run: _Rostest, test: TestSpec) -> Callable[[unittest.TestCase], None]:
    """rostest's ``rostestRunner``: launch, run the test, read its results, retry."""

    def fn(case: unittest.TestCase) -> None:
        retry = test.retry
        attempt = 0
        while True:
            name = test.test_name
            run.printlog(f"Running test [{name}]")
            record = TestRun(name, attempt, run.seed)
            failed = run.launch()
            if failed:
                run.finish_attempt(record)
                case.fail(f"Test Fixture Nodes {failed} failed to launch")
            results_file = xml_results_file(run.package, name, False, base=run.results_base)
            if os.path.exists(results_file):
                run.printlog(f"removing previous test results file [{results_file}]")
                os.remove(results_file)
            run.printlog(f"running test {name}")
            timeout = False
            try:
                run.run_test(test, results_file, record)
            except RLTestTimeoutException:
                if retry <= 0:
                    run.finish_attempt(record)
                    raise
                timeout = True
            except Exception:  # the world's run failed (a zero-time livelock): an error
                run.finish_attempt(record)
                raise
            if timeout:
                run.o.logerr(f"[ROSTEST]test [{name}] timed out")
                results = Result(name)
            else:
                run.printlog(f"test [{name}] finished")
                if not os.path.isfile(results_file):
                    run.finish_attempt(record)
                    case.fail(f"test [{name}] did not generate test results")
                run.printlog(f"test [{name}] results are in [{results_file}]")
                results = read(results_file, name, warn=run.o.log)
                record.results = results
            run.finish_attempt(record)
            if retry > 0 and record.failed:
                retry -= 1
                run.printlog(f"test [{name}] failed, retrying. Retries left: {retry}")
                run.printlog(f"test [{name}] failed on seed {run.seed}; the retry runs on "
                             f"seed {run.seed + 1}")
                run.tear_down()
                attempt += 1
                run.set_up(attempt)
                continue
            run.results.accumulate(results)
            run.printlog(f"test [{name}] results summary: {results.num_errors} errors, "
                         f"{results.num_failures} failures, {results.num_tests} tests")
            break
        run.printlog(f"[ROSTEST] test [{test.test_name}] done")

    return fn


def _combined_digest(runs: Sequence[TestRun]) -> str:
    lines = "".join(f"{r.test_name} {r.attempt} {r.seed} {r.digest}\n" for r in runs)
    return hashlib.sha256(lines.encode("utf-8")).hexdigest()


def run_rostest(argv: Sequence[str], *, rospack: RosPack, world_class: type[World],
                out: Print = print, err: Print = print,
                environ: Mapping[str, str] | None = None, command: str = "ddes rostest"
                ) -> RostestReport:
    """Run a rostest file: ``argv`` are rostest's words (``[--text] PKG FILE`` or ``PATH``,
    ``--seed N``, ``--results-filename``, ``--results-dir``). See the module docstring.

    Each test's world is a ``world_class`` on the package path of ``rospack`` (with the
    test file's own package added after it when the path does not hold it); ``environ`` is read for ``ROS_TEST_RESULTS_DIR`` / ``ROS_HOME`` (default ``os.environ``).
    """
    from ddes.launch import load_launch, resolve_launch_args

    opts = parse_rostest_args(argv)
    if opts.help:
        out(_USAGE)
        return RostestReport(code=0, file="", package="")
    if not opts.words:
        raise ROSConsoleError(f"You must supply a test file argument to rostest.\n{_USAGE}")
    path, args = resolve_launch_args(opts.words, rospack)
    path = os.path.abspath(path)
    package, pkg_dir = package_of(path, rospack)
    if package not in rospack or rospack.get_path(package).resolve() != pkg_dir:
        rospack = _with_package(rospack, pkg_dir)  # the file's own package, found as rostest does
    make_world = world_factory(world_class, rospack)
    if opts.results_filename:
        outname = opts.results_filename
        if "." in outname:
            outname = outname[:outname.rfind(".")]
    else:
        outname = rostest_name_from_path(str(pkg_dir), path)
    base = Path(opts.results_dir) if opts.results_dir else test_results_dir(environ)
    import random

    plan = load_launch(path, args, rospack, anon_seed=random.Random(opts.seed))
    output = _Output(out, err, opts.text)
    run = _Rostest(path, args, plan, package, rospack, make_world, opts, output, base)
    suite = unittest.TestLoader().loadTestsFromTestCase(run.test_case())
    report = RostestReport(code=0, file=path, package=package)
    if opts.text:
        runner_result: unittest.TestResult = text_run(suite, output.stream, run.clock)
        output.stream.close()
    else:
        results_file = xml_results_file(package, outname, True, base=base)
        report.results_file = results_file
        out(f"[ROSUNIT] Outputting test results to {results_file}")
        xml_result = XMLResult(run.clock)
        start = run.clock()
        suite(xml_result)
        text = suite_xml(f"{type(suite).__module__}.{type(suite).__name__}", xml_result.records,
                         xml_result.testsRun, len(xml_result.errors), len(xml_result.failures),
                         run.clock() - start, "".join(x + "\n" for x in output.kept_out),
                         "".join(x + "\n" for x in output.kept_err))
        with open(results_file, "w", encoding="utf-8") as f:
            f.write(text)
        for line in xml_result.report_lines():
            out(line)
        runner_result = xml_result
    warnings = [w for w in plan.warnings if w not in {t.warning for t in plan.tests}]
    if warnings:
        err("\n[ROSTEST WARNINGS]" + "-" * 62 + "\n")
        for w in warnings:
            err(f" * {w}")
    out("")
    results = run.results
    report.summary = runner_summary(runner_result, results)
    for line in report.summary:
        out(line)
    report.tests = results.num_tests
    report.errors = results.num_errors + len(runner_result.errors)
    report.failures = results.num_failures + len(runner_result.failures)
    report.runs = run.runs
    report.simulated_ns = sum(r.simulated_ns for r in run.runs)
    report.events = sum(r.events for r in run.runs)
    report.digest = _combined_digest(run.runs)
    worlds = len(run.runs)
    out(f"simulated {ns_to_sec(report.simulated_ns):.3f} s in {worlds} "
        f"world{'s' if worlds != 1 else ''}; {report.events} trace events")
    out(f"trace digest: {report.digest}")
    final: dict[str, TestRun] = {}
    for r in run.runs:
        final[r.test_name] = r
    words = " ".join(_quote(w) for w in opts.words)
    for name, r in final.items():
        if r.failed:
            out(f"test [{name}] failed on seed {r.seed}; replay it with: {command} "
                f"--seed {r.seed}{' --text' if opts.text else ''} {words}")
    if not runner_result.wasSuccessful():
        report.code = 1
    elif results.num_errors or results.num_failures:
        report.code = 2
    return report


def _quote(word: str) -> str:
    import shlex

    return shlex.quote(word)


def _with_package(rospack: RosPack, pkg_dir: Path) -> RosPack:
    from ddes.rospack import RosPack as _RosPack

    return _RosPack([*_paths_of(rospack), pkg_dir])


def _paths_of(rospack: RosPack) -> list[Path]:
    from ddes.rospack import BUNDLED_PATH

    return [p for p in rospack.paths if p != BUNDLED_PATH]


def world_factory(world_class: type[World], rospack: RosPack) -> WorldFactory:
    """``make_world`` for :func:`run_rostest`: a ``world_class`` on the package path of
    ``rospack``, not strict (a failing callback is logged, as rospy does)."""
    paths = _paths_of(rospack)

    def make(seed: int) -> World:
        return world_class(seed=seed, package_path=paths, strict=False)

    return make


def rostest_tool(ctx: ToolContext, argv: list[str]) -> int:
    """The console's ``rostest``: runs in worlds of its own, not the console's."""
    rospack = ctx.rospack
    assert rospack is not None
    argv = [ctx.resolve_path(w) if w.endswith((".test", ".launch", ".xml"))
            and os.path.isfile(ctx.resolve_path(w)) else w for w in argv]  # after roscd
    report = run_rostest(argv, rospack=rospack, world_class=type(ctx.world), out=ctx.print,
                         err=ctx.eprint, command="rostest")
    return report.code


#: World-bound tools of this module.
TOOLS = {"rostest": rostest_tool}
