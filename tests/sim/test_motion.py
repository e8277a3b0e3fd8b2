"""Motion follows the SMB's limits and the 0.25 s command timeout (hypothesis over commands)."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.msg import get_message_class
from ddes.sim import Simulator, WorldSpec

TWIST = get_message_class("geometry_msgs/Twist")
VEC = get_message_class("geometry_msgs/Vector3")
TOL = 1e-12
DT = 0.01

command = st.tuples(
    st.floats(-3.0, 3.0, allow_nan=False),          # v
    st.floats(-3.0, 3.0, allow_nan=False),          # w
    st.integers(0, 60),                              # steps until the next command (10 ms each)
)


def drive(commands: list[tuple[float, float, int]], tail_steps: int = 120
          ) -> tuple[list[tuple[float, float, float, float, float]], list[int]]:
    """Run the commands in the empty world; the truth after every step and the publish steps."""
    world = ddes.World(seed=0)
    world.connect_delay_ns = 0
    sim = Simulator(world, WorldSpec.load("empty"), noise=False)
    driver = world.create_node("driver")
    pub = driver.advertise("/cmd_vel", TWIST, queue_size=1)
    states = [tuple(sim.truth)]
    sent: list[int] = []
    step = 0

    def advance(n: int) -> None:
        nonlocal step
        for _ in range(n):
            step += 1
            world.run(until=ddes.Time._from_ns(step * 10_000_000 + 5_000_000))
            states.append(tuple(sim.truth))

    advance(1)
    for v, w, gap in commands:
        pub.publish(TWIST(linear=VEC(x=v), angular=VEC(z=w)))
        sent.append(step)  # received before the next physics step
        advance(gap)
    advance(tail_steps)
    return states, sent  # type: ignore[return-value]


def last_command(sent: list[int], commands: list[tuple[float, float, int]], k: int
                 ) -> tuple[float, float, int] | None:
    """The command in force at physics step k (published after step s, used at s+1...)."""
    found = None
    for s, (v, w, _gap) in zip(sent, commands):
        if s < k:
            found = (v, w, s)
    return found


@settings(max_examples=40, deadline=None)
@given(st.lists(command, min_size=1, max_size=6))
def test_limits_slew_and_timeout(commands: list[tuple[float, float, int]]) -> None:
    states, sent = drive(commands)
    for k in range(1, len(states)):
        x0, y0, yaw0, v0, w0 = states[k - 1]
        x1, y1, yaw1, v1, w1 = states[k]
        assert abs(v1) <= 1.1 + TOL and abs(w1) <= 1.1 + TOL
        assert abs(v1 - v0) <= 2.0 * DT + TOL and abs(w1 - w0) <= 3.0 * DT + TOL
        cmd = last_command(sent, commands, k)
        if cmd is None or (k - cmd[2]) * DT > 0.25 + 1e-9:
            tv, tw = 0.0, 0.0     # no command, or it timed out
        else:
            tv = max(-1.1, min(1.1, cmd[0]))
            tw = max(-1.1, min(1.1, cmd[1]))
        # each step moves as far toward the target as the acceleration limit allows
        assert math.isclose(abs(tv - v1), max(abs(tv - v0) - 0.02, 0.0), abs_tol=1e-9)
        assert math.isclose(abs(tw - w1), max(abs(tw - w0) - 0.03, 0.0), abs_tol=1e-9)
        # midpoint unicycle integration
        mid = yaw0 + w1 * DT / 2
        assert math.isclose(x1, x0 + v1 * math.cos(mid) * DT, abs_tol=1e-12)
        assert math.isclose(y1, y0 + v1 * math.sin(mid) * DT, abs_tol=1e-12)
        dyaw = math.remainder(yaw1 - yaw0 - w1 * DT, 2 * math.pi)
        assert abs(dyaw) < 1e-12 and -math.pi < yaw1 <= math.pi
    # long after the last command the robot is at rest, exactly
    assert states[-1][3] == 0.0 and states[-1][4] == 0.0


def test_one_shot_command_moves_briefly() -> None:
    """A single message (rostopic pub -1) drives for 0.25 s, then the robot brakes to rest."""
    states, _ = drive([(1.0, 0.0, 0)], tail_steps=200)
    v = [s[3] for s in states]
    assert max(v) == max(v[:30]) and 0.49 < max(v) <= 0.5 + 1e-12  # 25 steps of 0.02 m/s
    assert v[-1] == 0.0
    assert 0.12 < states[-1][0] < 0.13  # accelerate 0.25 s, brake 0.25 s: 0.125 m


def test_console_one_shot_pub_and_services() -> None:
    console = ddes.Console(seed=0)
    console.run("rosrun ddes_sim simulator _world:=empty _noise:=false &")
    console.run('rostopic pub -1 /cmd_vel geometry_msgs/Twist "{linear: {x: 1.0}}"')
    world = console.world
    node = world.master.lookup_node("/simulator")
    assert node is not None
    sims = [e for e in node.entities if isinstance(e, Simulator)]
    assert len(sims) == 1
    sim = sims[0]
    assert 0.12 < sim.truth.x < 0.13 and sim.truth.v == 0.0
    console.run("rosservice call /simulator/pause_physics")
    t = sim.sim_time
    console.run("rostopic pub -1 /cmd_vel geometry_msgs/Twist \"{linear: {x: 1.0}}\"")
    assert sim.sim_time == t and sim.paused
    console.run("rosservice call /simulator/unpause_physics")
    console.run("rosservice call /simulator/reset_world")
    assert sim.truth == (0.0, 0.0, 0.0, 0.0, 0.0)
