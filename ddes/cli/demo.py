"""``ddes demo``: a tour of what ddes can do, each part ending with its trace digest.

The demo grows with the project; every part is deterministic, so the digests it
prints are the same on every machine.  Three parts: the ROS concepts of the
lectures (:func:`run_demo`), the robot (:func:`run_robot`: the simulator in the
single-pillar world, a P controller, a top-view picture) and a graded submission
(:func:`run_graded_submission`: exercise 3's reference solution, public
scenario), which needs a checkout's ``solutions/`` (:func:`find_solutions`).
"""

from __future__ import annotations

import contextlib
import io
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

from simpy.events import ProcessGenerator

from ddes.graph.timer import TimerEvent
from ddes.graph.world import World
from ddes.msg.message import Message
from ddes.time import SimClock, Time, ns_to_sec, to_ns

__all__ = ["build_demo", "build_robot", "find_solutions", "run_demo", "run_graded_submission",
           "run_robot", "run_tour"]


def _time_section(world: World, out: Callable[[str], None]) -> None:
    """Lecture 4, ROS time: Rate, Timer, and wall vs simulated time."""
    loop = world.create_node("rate_loop")
    rate = loop.create_rate(4)

    def main() -> ProcessGenerator:
        for i in range(4):
            out(f"[{loop.get_time():7.3f}] rate_loop: cycle {i} (rospy.Rate 4 Hz)")
            if i == 1:
                yield loop.sleep(0.3)  # a slow cycle: the rate absorbs it
            yield rate.sleep()

    loop.process(main())

    def on_timer(ev: TimerEvent) -> None:
        last = "None" if ev.last_expected is None else f"{ev.last_expected.to_sec():.3f}"
        out(f"[{ev.current_real.to_sec():7.3f}] timer: expected {ev.current_expected.to_sec():.3f}"
            f" last_expected {last}")

    ticker = world.create_node("ticker")
    ticker.create_timer(0.4, on_timer)

    sim = world.create_node("sim_listener", use_sim_time=True)

    def sim_main() -> ProcessGenerator:
        out(f"[{ns_to_sec(world.now):7.3f}] sim_listener: ROS time {sim.get_time():.3f} before /clock")
        yield sim.sleep(0.5)  # waits for the first /clock, then 0.5 s of /clock time
        out(f"[{ns_to_sec(world.now):7.3f}] sim_listener: woke at ROS time {sim.get_time():.3f}, "
            f"wall {sim.get_walltime().to_sec():.3f}")

    sim.process(sim_main())

    def clock_driver() -> ProcessGenerator:
        # Stands in for `rosbag play --clock`: /clock runs at 2x from t=100 s.
        yield world.timeout(0.5)
        clock = sim.clock
        assert isinstance(clock, SimClock)
        for k in range(8):
            clock.update(Time.from_nsec(to_ns(100) + k * to_ns(0.2)))
            yield world.timeout(0.1)

    world.process(clock_driver())


def _topics_section(world: World, out: Callable[[str], None]) -> None:
    """Lectures 1-2: talker and listener on /chatter over a lossy, jittery link."""
    from ddes.msg import get_message_class

    string = get_message_class("std_msgs/String")
    talker = world.create_node("talker")
    pub = talker.advertise("chatter", string, queue_size=10)
    listener = world.create_node("listener")
    listener.subscribe("chatter", string, lambda m: listener.loginfo("I heard %s", m.data))
    # 2-20 ms of latency and 10 % loss, drawn from the world's seed: rerun with
    # the same seed and the same messages are lost at the same instants.
    world.set_link("/chatter", latency=lambda rng: rng.uniform(0.002, 0.02), loss=0.1)

    def main() -> ProcessGenerator:
        rate = talker.create_rate(5)
        while not talker.is_shutdown():
            pub.publish(f"hello world {talker.get_time():.1f}")
            yield rate.sleep()

    talker.process(main())


def _services_section(world: World, out: Callable[[str], None]) -> None:
    """Lecture 4, services: the add_two_ints server, a client, and a call timeout."""
    from ddes.errors import ServiceException
    from ddes.msg import get_service_class
    from ddes.services import Service, ServiceProxy, wait_for_service

    two_ints = get_service_class("roscpp_tutorials/TwoInts")
    server = world.create_node("add_two_ints_server")

    def add(req: Message) -> ProcessGenerator:
        if req.a < 0:
            raise ServiceException("negative numbers are not supported")
        yield server.sleep(0.05)  # the handler takes 50 ms of simulated time
        return req.a + req.b

    Service(server, "add_two_ints", two_ints, add)
    client = world.create_node("add_two_ints_client")

    def main() -> ProcessGenerator:
        yield client.sleep(1.0)
        yield wait_for_service(client, "add_two_ints", timeout=1.0)
        proxy = ServiceProxy(client, "add_two_ints", two_ints)
        resp = yield proxy(10, 5)
        out(f"[{ns_to_sec(world.now):7.3f}] client: 10 + 5 = {resp.sum}")
        try:
            yield proxy(-1, 5)
        except ServiceException as exc:
            out(f"[{ns_to_sec(world.now):7.3f}] client: ServiceException: {exc}")
        try:
            yield proxy.call(two_ints._request_class(1, 2), timeout=0.01)
        except ServiceException as exc:
            out(f"[{ns_to_sec(world.now):7.3f}] client: {type(exc).__name__}: {exc}")

    client.process(main())


def _actions_section(world: World, out: Callable[[str], None]) -> None:
    """Lecture 4, actions: a Fibonacci SimpleActionServer preempted by a newer goal."""
    from ddes.actionlib import GoalStatus, SimpleActionClient, SimpleActionServer
    from ddes.msg import get_message_class

    action = get_message_class("actionlib_tutorials/FibonacciAction")
    goal_cls = get_message_class("actionlib_tutorials/FibonacciGoal")
    feedback_cls = get_message_class("actionlib_tutorials/FibonacciFeedback")
    result_cls = get_message_class("actionlib_tutorials/FibonacciResult")
    node = world.create_node("fibonacci")

    def execute(goal: Message) -> ProcessGenerator:
        seq = [0, 1]
        for i in range(1, goal.order):
            if server.is_preempt_requested():
                server.set_preempted()
                return
            seq.append(seq[i] + seq[i - 1])
            server.publish_feedback(feedback_cls(sequence=seq))
            yield node.sleep(0.1)
        server.set_succeeded(result_cls(sequence=seq))

    server = SimpleActionServer(node, "fibonacci", action, execute, auto_start=False)
    server.start()
    first = SimpleActionClient(world.create_node("first_client"), "fibonacci", action)
    second = SimpleActionClient(world.create_node("second_client"), "fibonacci", action)

    def report(who: str) -> Callable[[int, Message | None], None]:
        def done(state: int, result: Message | None) -> None:
            n = len(result.sequence) if result is not None else 0
            out(f"[{ns_to_sec(world.now):7.3f}] {who}: goal {GoalStatus(state).name}, "
                f"{n} numbers")
        return done

    def main() -> ProcessGenerator:
        yield first.wait_for_server(1.0)
        first.send_goal(goal_cls(order=8), done_cb=report("first_client"))
        yield world.timeout(0.35)
        second.send_goal(goal_cls(order=4), done_cb=report("second_client"))

    world.process(main())


def _bags_section(world: World, out: Callable[[str], None]) -> None:
    """Lecture 4, bags: record /chatter in memory while the demo runs."""
    from ddes.rosbag import Recorder

    rec = Recorder(world, ["/chatter"], duration=1.5, in_memory=True, quiet=True)

    def report() -> ProcessGenerator:
        yield rec.done
        bag = rec.bag
        out(f"[{ns_to_sec(world.now):7.3f}] rosbag record: {bag.get_message_count()} messages on "
            f"/chatter between {bag.get_start_time():.3f} s and {bag.get_end_time():.3f} s")

    world.process(report())


def build_demo(seed: int = 0, out: Callable[[str], None] = print) -> World:
    """Create the demo world (not yet run)."""
    world = World(seed=seed)
    world.log_output = lambda line, level: out(line)
    _time_section(world, out)
    _topics_section(world, out)
    _services_section(world, out)
    _actions_section(world, out)
    _bags_section(world, out)
    return world


def run_demo(seed: int = 0, until: float = 2.0, out: Callable[[str], None] = print) -> str:
    """Run the demo, print its story and return the trace digest."""
    out(f"ddes demo (seed {seed}): everything below runs on simulated time\n")
    world = build_demo(seed, out)
    world.run(until=until)
    out("")
    stats = world.topic_stats("/chatter")
    out(f"/chatter: published {stats['published']}, lost {stats['lost']}, "
        f"delivered {stats['delivered']}")
    out(f"simulated {ns_to_sec(world.now):.3f} s; {len(world.trace)} trace events")
    digest = world.digest()
    out(f"trace digest: {digest}")
    return digest


#: Where the robot starts in the single-pillar world (pillar of radius 1 m at (20, 5)).
ROBOT_START = (15.0, 3.5, 0.0)
#: The P controller's gain and forward speed, as exercise 3's parameters.
P_GAIN, SPEED = 1.0, 1.0


def build_robot(seed: int = 0, out: Callable[[str], None] = print) -> tuple[World, object]:
    """The robot's world (not yet run): the simulator in ``single_pillar`` and a yield-style
    P controller steering to the closest laser return, with a reporter printing the true pose
    each simulated second.  Returns the world and the simulator."""
    from ddes.msg import get_message_class
    from ddes.sim import Simulator, WorldSpec

    world = World(seed=seed)
    world.log_output = lambda line, level: out(line)  # the simulator's collision warning
    x, y, yaw = ROBOT_START
    sim = Simulator(world, WorldSpec.load("single_pillar"), x=x, y=y, yaw=yaw, noise=True)
    twist = get_message_class("geometry_msgs/Twist")
    vector3 = get_message_class("geometry_msgs/Vector3")
    laser_scan = get_message_class("sensor_msgs/LaserScan")
    node = world.create_node("pillar_controller")
    cmd = node.advertise("/cmd_vel", twist, queue_size=1)
    latest: list[Message] = []  # the last scan received

    def on_scan(scan: Message) -> None:
        latest[:] = [scan]

    node.subscribe("/scan", laser_scan, on_scan, queue_size=1)

    def control() -> ProcessGenerator:
        rate = node.create_rate(10)
        while not node.is_shutdown():
            if latest:
                scan = latest[-1]
                best, index = float("inf"), -1
                for i, r in enumerate(scan.ranges):  # the closest valid return: the pillar
                    if scan.range_min <= r < best:
                        best, index = r, i
                if index >= 0:
                    bearing = scan.angle_min + index * scan.angle_increment
                    cmd.publish(twist(linear=vector3(x=SPEED),
                                      angular=vector3(z=P_GAIN * bearing)))
            yield rate.sleep()

    node.process(control())

    def report() -> ProcessGenerator:
        while True:
            out(_pose_line(world, sim))
            yield world.timeout(1.0)

    world.process(report())
    return world, sim


def _pose_line(world: World, sim: object) -> str:
    from ddes.sim import Simulator

    assert isinstance(sim, Simulator)
    t = sim.truth
    return (f"[{ns_to_sec(world.now):7.3f}] robot: x {t.x:6.3f} m  y {t.y:6.3f} m  "
            f"yaw {t.yaw:+.3f} rad  v {t.v:.3f} m/s")


def run_robot(seed: int = 0, until: float = 5.0, pictures: str | Path | None = None,
              out: Callable[[str], None] = print) -> str:
    """Drive the robot into the pillar, print its story, write its top view (into ``pictures``,
    else a new temporary folder, never the current one) and return the trace digest."""
    from ddes.sim import Simulator
    from ddes.sim.view import top_view

    out(f"The robot (seed {seed}): the SMB simulator in the world single_pillar, a P controller "
        f"on the closest laser return, {until:g} simulated seconds\n")
    world, sim = build_robot(seed, out)
    assert isinstance(sim, Simulator)
    world.run(until=until)
    out(_pose_line(world, sim))
    out("")
    for c in sim.collisions:
        out(f"collision: {c.obstacle} at t={ns_to_sec(c.stamp_ns):.3f} s, {c.speed:.3f} m/s, "
            f"robot at ({c.pose.x:.3f}, {c.pose.y:.3f})")
    if not sim.collisions:
        out("collision: none")
    folder = Path(pictures) if pictures is not None else Path(
        tempfile.mkdtemp(prefix="ddes-demo-"))
    folder.mkdir(parents=True, exist_ok=True)
    picture = folder / "top_view.png"
    top_view(sim).savefig(picture)
    out(f"top view: {picture}")
    out(f"simulated {ns_to_sec(world.now):.3f} s; {len(world.trace)} trace events")
    digest = world.digest()
    out(f"trace digest: {digest}")
    return digest


#: The submission the demo grades, inside a checkout.
DEMO_EXERCISE = "ex3_pillar"


def find_solutions(exercise: str = DEMO_EXERCISE,
                   roots: Sequence[Path] | None = None) -> Path | None:
    """The reference solution of ``exercise`` in a checkout: ``solutions/<exercise>`` next to
    the ``ddes`` package (a source checkout, or an editable install), else in the current
    directory (README's set-up command runs the demo from the repository root); None when
    neither holds one.  ``roots`` replaces those two folders."""
    import ddes

    if roots is None:
        roots = [Path(ddes.__file__).resolve().parent.parent, Path.cwd()]
    for root in roots:
        folder = root / "solutions" / exercise
        if (folder / "smb_highlevel_controller" / "package.xml").is_file():
            return folder
    return None


def run_graded_submission(solution: Path | None = None,
                          out: Callable[[str], None] = print) -> float | None:
    """Grade the reference solution of exercise 3 on its public scenario, as ``ddes grade
    ex3_pillar solutions/ex3_pillar --public`` does, and print the report; returns the
    percentage (None, with a line saying where the exercises are, without a checkout)."""
    from ddes.grading.exercise import REGISTRY
    from ddes.grading.grader import grade

    folder = solution if solution is not None else find_solutions()
    if folder is None:
        out(f"A graded submission: the exercises and their reference solutions are in the "
            f"source checkout (exercises/, solutions/); run `ddes demo` from its root, or "
            f"`ddes grade {DEMO_EXERCISE} SUBMISSION --public` on your own.")
        return None
    shown = _relative(folder)
    out(f"A graded submission: `ddes grade {DEMO_EXERCISE} {shown} --public` (the reference "
        f"solution; the student's nodes run in a confined process, the score is computed "
        f"outside it)\n")
    # The grader's world logs the simulator's collision warning on standard error; the report
    # says what counts.
    with contextlib.redirect_stderr(io.StringIO()):
        report = grade(REGISTRY.get(DEMO_EXERCISE), shown, public=True)
    out(report.to_text().rstrip("\n"))
    return report.percent


def _relative(folder: Path) -> str:
    """``folder`` relative to the current directory when it lies below it."""
    try:
        return str(folder.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(folder)


def run_tour(seed: int = 0, until: float = 2.0, pictures: str | Path | None = None,
             out: Callable[[str], None] = print) -> tuple[str, str, float | None]:
    """``ddes demo``: the three parts one after the other; returns the two digests and the
    graded percentage (None without a checkout)."""
    digest = run_demo(seed=seed, until=until, out=out)
    out("")
    robot = run_robot(seed=seed, pictures=pictures, out=out)
    out("")
    percent = run_graded_submission(out=out)
    return digest, robot, percent
