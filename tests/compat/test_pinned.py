"""A rospy script's ``random`` and ``datetime`` (ddes.compat.pinned), like its ``time``, are the
world's: two runs of one seed draw and stamp the same, as ddes run and roslaunch run scripts
in-process."""

from __future__ import annotations

import datetime as real_datetime
import json
import random as real_random
import textwrap
from pathlib import Path

import ddes
from ddes.compat.pinned import datetime_classes
from ddes.compat.scripts import run_script

SCRIPT = """
    import datetime
    import json
    import random
    import time
    from datetime import date

    import rospy

    rospy.init_node("drawer")
    rospy.sleep(1.25)
    rospy.loginfo(json.dumps({
        "random": [random.random(), random.randint(0, 10 ** 9), random.Random().random()],
        "seeded": random.Random(4).random(),
        "system": random.SystemRandom().random(),
        "now": [datetime.datetime.now().isoformat(), datetime.datetime.utcnow().isoformat(),
                date.today().isoformat(), datetime.datetime.fromtimestamp(time.time()).isoformat()],
        "time": [time.ctime(), time.strftime("%H:%M:%S"), list(time.localtime()[:6])],
    }))
"""


def _run(tmp_path: Path, name: str = "drawer.py", *args: str) -> dict[str, list[object]]:
    path = tmp_path / name
    path.write_text(textwrap.dedent(SCRIPT))
    lines: list[str] = []
    world = ddes.World(seed=3)
    world.log_output = lambda line, _level: lines.append(line)
    run_script(world, path, args)
    world.run(until=2.0)
    (line,) = lines
    got: dict[str, list[object]] = json.loads(line.split(": ", 1)[1])
    return got


def test_a_script_draws_and_stamps_the_same_on_every_run(tmp_path: Path) -> None:
    first, second = _run(tmp_path), _run(tmp_path)
    assert first == second
    assert first["seeded"] == real_random.Random(4).random()  # a seed given is the seed
    assert first["now"] == ["1970-01-01T00:00:01.250000"] * 2 + ["1970-01-01",
                                                                 "1970-01-01T00:00:01.250000"]
    assert first["time"] == ["Thu Jan  1 00:00:01 1970", "00:00:01", [1970, 1, 1, 0, 0, 1]]


def test_two_scripts_draw_apart(tmp_path: Path) -> None:
    assert _run(tmp_path)["random"] != _run(tmp_path, "other.py")["random"]
    assert _run(tmp_path)["random"] != _run(tmp_path, "drawer.py", "__name:=second")["random"]


def test_the_datetime_classes_mix_with_the_real_ones() -> None:
    date, datetime = datetime_classes(lambda: 86_400_000_000_000 + 1_500)
    now = datetime.now()
    assert repr(now) == "datetime.datetime(1970, 1, 2, 0, 0, 0, 1)"
    assert isinstance(now, real_datetime.datetime) and isinstance(real_datetime.datetime(1, 1, 1),
                                                                  datetime)
    assert isinstance(now.date(), date) and repr(date.today()) == "datetime.date(1970, 1, 2)"
    assert now - real_datetime.datetime(1970, 1, 1) == real_datetime.timedelta(days=1,
                                                                              microseconds=1)
    assert datetime.now(real_datetime.timezone.utc).isoformat() == \
        "1970-01-02T00:00:00.000001+00:00"
