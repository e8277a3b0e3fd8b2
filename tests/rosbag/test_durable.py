"""Recordings are never lost, and bag files are written safely (issue 13, items 3 and 8).

* ``Recorder`` writes ``NAME.bag.active`` as it goes (chunks of ``chunksize`` KB, and on
  ``flush``); without flushes the bytes equal ``Bag.save``'s;
* a killed recorder's ``.active`` keeps every complete chunk: ``rosbag reindex`` recovers
  them; the messages of the open, unwritten chunk are lost (as in ROS);
* ``Bag.save`` writes through a temporary file and ``os.replace``, follows symlinks, refuses
  directories, FIFOs and devices; default record names are in UTC whatever ``TZ`` says;
* ``rosbag check``; real ROS reads the ``.active`` file (``rosbag reindex``/``info``).
"""

from __future__ import annotations

import datetime
import io
import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest

from ddes import Time
from ddes.errors import ROSBagException, ROSBagUnindexedException
from ddes.graph.world import World
from ddes.msg import get_message_class
from ddes.rosbag import Bag, Recorder
from ddes.rosbag.bagfile import StreamWriter, encode
from ddes.rosbag.ops import reindex_file
from ddes.rosbag.recorder import bag_filename, close_recordings, open_recordings

String = get_message_class("std_msgs/String")


def _talker(world: World, rate: float = 100.0) -> None:
    node = world.create_node("talker")
    pub = node.advertise("/chatter", String, queue_size=10)

    def talk():  # type: ignore[no-untyped-def]
        r = node.create_rate(rate)
        i = 0
        while True:
            pub.publish(data=f"hello {i}")
            i += 1
            yield r.sleep()

    node.process(talk())


def _recording(tmp_path: Path, **kwargs: object) -> tuple[World, Recorder]:
    world = World(seed=0)
    _talker(world)
    rec = Recorder(world, ["/chatter"], output_name=str(tmp_path / "run"), **kwargs)  # type: ignore[arg-type]
    return world, rec


def test_stream_writer_without_flushes_writes_what_encode_writes() -> None:
    bag = Bag()
    for i in range(300):
        bag.write("/a" if i % 3 else "/b", String(data="m" * (i % 50)), Time(1, i))
    for compression in ("none", "bz2"):
        expected = io.BytesIO()
        encode(bag._connections, bag._log, expected, compression=compression,
               chunk_threshold=2048)
        got = io.BytesIO()
        writer = StreamWriter(got, compression=compression, chunk_threshold=2048)
        for t, cid, data in bag._log:
            writer.add(t, bag._connections[cid], data)
        writer.close()
        assert got.getvalue() == expected.getvalue()


def test_recorder_file_equals_the_saved_bag(tmp_path: Path) -> None:
    world, rec = _recording(tmp_path, chunksize=1)
    world.run_for(2.0)
    rec.stop()
    data = (tmp_path / "run.bag").read_bytes()
    assert data == rec.bag.to_bytes()
    assert not (tmp_path / "run.bag.active").exists()
    assert Bag(str(tmp_path / "run.bag")).get_message_count() == 199  # 0.01 s to 1.99 s


def test_a_killed_recorder_keeps_its_complete_chunks(tmp_path: Path) -> None:
    world, rec = _recording(tmp_path, chunksize=1)
    world.run_for(2.0)
    # SIGKILL now: only what reached the file survives (copy it as the dead process left it)
    killed = tmp_path / "killed.bag.active"
    shutil.copy(tmp_path / "run.bag.active", killed)
    with pytest.raises(ROSBagUnindexedException, match="run rosbag reindex"):
        Bag(str(killed))
    assert reindex_file(str(killed)) is None
    recovered = [(m.timestamp, m.message.data) for m in Bag(str(killed)).read_messages()]
    recorded = [(m.timestamp, m.message.data) for m in rec.bag.read_messages()]
    assert len(recorded) == 199
    # every message of the chunks written before the kill, and none of the open chunk
    assert 0 < len(recovered) < len(recorded)
    assert recovered == recorded[:len(recovered)]
    chunk_messages = len(recovered) // len(Bag(str(killed))._summary().chunks)
    assert len(recorded) - len(recovered) < chunk_messages + 1
    rec.flush()  # what the console does after each command: now nothing is pending
    shutil.copy(tmp_path / "run.bag.active", killed)
    assert reindex_file(str(killed), force=True) is None
    assert [(m.timestamp, m.message.data) for m in Bag(str(killed)).read_messages()] == recorded
    rec.stop()


def test_close_recordings_stops_every_open_recording(tmp_path: Path) -> None:
    world, rec = _recording(tmp_path)
    other = Recorder(world, ["/chatter"], output_name=str(tmp_path / "two"))
    memory = Recorder(world, ["/chatter"], in_memory=True)
    world.run_for(1.0)
    assert open_recordings(world) == [rec, other, memory]
    assert close_recordings(world, "SIGTERM") == [rec, other, memory]
    assert rec.stop_reason == "SIGTERM" and open_recordings(world) == []
    assert Bag(str(tmp_path / "run.bag")).get_message_count() == 99
    assert Bag(str(tmp_path / "two.bag")).get_message_count() == 99
    assert close_recordings(world) == []


def test_default_record_names_are_utc_whatever_tz_says(monkeypatch: pytest.MonkeyPatch) -> None:
    try:
        for zone in ("Asia/Kolkata", "America/New_York", "UTC"):
            monkeypatch.setenv("TZ", zone)
            time.tzset()
            assert bag_filename(stamp_ns=0) == "1970-01-01-00-00-00.bag"
            assert bag_filename("run", stamp_ns=86_399 * 10**9) == "run_1970-01-01-23-59-59.bag"
    finally:
        monkeypatch.undo()
        time.tzset()
    kolkata = datetime.timezone(datetime.timedelta(hours=5, minutes=30))
    assert bag_filename(stamp_ns=0, tz=kolkata) == "1970-01-01-05-30-00.bag"


def _bag() -> Bag:
    bag = Bag()
    bag.write("/chatter", String(data="new"), Time(1, 0))
    return bag


def test_save_is_atomic(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "x.bag"
    old = Bag()
    old.write("/chatter", String(data="old"), Time(1, 0))
    old.save(str(target))
    before = target.read_bytes()
    bag = _bag()

    def disk_full(out: io.BufferedWriter, fmt: str, compression: str | None) -> None:
        out.write(b"#ROSBAG V2.0\n half a bag")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(bag, "_write_to", disk_full)
    with pytest.raises(ROSBagException, match=r"x\.bag: cannot write the bag \(No space left on "
                                              r"device\); the file .*x\.bag is unchanged"):
        bag.save(str(target))
    assert target.read_bytes() == before


def test_save_follows_a_symlink(tmp_path: Path) -> None:
    (tmp_path / "data").mkdir()
    real = tmp_path / "data" / "real.bag"
    link = tmp_path / "link.bag"
    link.symlink_to(real)  # dangling: the target is created
    _bag().save(str(link))
    assert link.is_symlink() and real.is_file()
    assert Bag(str(link)).get_message_count() == 1
    with Bag(str(link), "w") as bag:
        bag.write("/a", String(data="a"), Time(2, 0))
        bag.write("/a", String(data="b"), Time(3, 0))
    assert link.is_symlink() and Bag(str(real)).get_message_count() == 2
    assert sorted(p.name for p in (tmp_path / "data").iterdir()) == ["real.bag"]


def test_save_refuses_directories_fifos_and_devices(tmp_path: Path) -> None:
    (tmp_path / "d.bag").mkdir()
    os.mkfifo(tmp_path / "f.bag")
    (tmp_path / "l.bag").symlink_to(tmp_path / "f.bag")
    cases = [(tmp_path / "d.bag", "a directory"), (tmp_path / "f.bag", r"a FIFO \(named pipe\)"),
             (tmp_path / "l.bag", r"a link to .*f\.bag\) is a FIFO"),
             (Path("/dev/null"), "a character device")]
    for path, what in cases:
        with pytest.raises(ROSBagException, match=f"{what}.*not a regular file.*such as run.bag"):
            _bag().save(str(path))
        with pytest.raises(ROSBagException, match=what):
            Bag(str(path), "w")
    world = World(seed=0)
    with pytest.raises(ROSBagException, match=r"Error writing: .*d\.bag\.active: .*a directory"):
        Recorder(world, ["/chatter"], output_name=str(tmp_path / "d"))
    assert (tmp_path / "f.bag").exists() and not (tmp_path / "f.bag").is_file()


def test_save_replaces_a_symlinked_active_name_instead_of_writing_through_it(
        tmp_path: Path) -> None:
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    (tmp_path / "x.bag.active").symlink_to(victim)
    _bag().save(str(tmp_path / "x.bag"))
    assert victim.read_text() == "keep me"
    assert Bag(str(tmp_path / "x.bag")).get_message_count() == 1


def test_rosbag_check(tmp_path: Path) -> None:
    from ddes.console.rosbag import run

    out: list[str] = []
    good = tmp_path / "good.bag"
    _bag().save(str(good))
    assert run(["check", str(good)], out.append, out.append) == 0
    assert out == ["Bag file does not need any migrations."]
    out.clear()
    (tmp_path / "open.bag.active").write_bytes(good.read_bytes()[:4117])
    assert run(["check", str(tmp_path / "open.bag.active")], out.append, out.append) == 1
    assert out == [f"ERROR bag unindexed: {tmp_path / 'open.bag.active'}.  Run rosbag reindex."]
    out.clear()
    assert run(["check"], out.append, out.append) == 2
    assert out[-1] == "rosbag check: error: You must specify a bag file to check."
    out.clear()
    old = Bag()
    with pytest.warns(UserWarning, match="md5sum"):
        old.write("/chatter", ("std_msgs/String", b"\x00\x00\x00\x00", "0" * 32, None),
                  Time(1, 0), raw=True)
    old.save(str(tmp_path / "old.bag"))
    assert run(["check", str(tmp_path / "old.bag")], out.append, out.append) == 1
    assert out[0] == "The following migrations need to occur:"
    assert "std_msgs/String [00000000000000000000000000000000]" in out[1]


# -- real ROS ----------------------------------------------------------------------------------

def _ros_rosbag() -> str:
    from tests.conftest import ros_interpreter

    exe = shutil.which("rosbag")
    if exe is None or ros_interpreter() is None:
        pytest.skip("real ROS 1 Noetic is not installed (bash .ci/install-ros installs it)")
    return exe


@pytest.mark.ros
def test_real_rosbag_reindexes_the_active_file_ddes_leaves(tmp_path: Path) -> None:
    exe = _ros_rosbag()
    world, rec = _recording(tmp_path, chunksize=1)
    world.run_for(2.0)
    rec.flush()
    active = tmp_path / "killed.bag.active"
    shutil.copy(tmp_path / "run.bag.active", active)
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env["TZ"] = "UTC"
    info = subprocess.run([exe, "info", str(active)], capture_output=True, text=True, env=env,
                          timeout=120)
    assert "unindexed" in info.stdout + info.stderr
    done = subprocess.run([exe, "reindex", str(active)], capture_output=True, text=True,
                          env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    info = subprocess.run([exe, "info", str(active)], capture_output=True, text=True, env=env,
                          timeout=120)
    assert info.returncode == 0, info.stderr
    assert "messages:    199" in info.stdout
    assert "/chatter   199 msgs    : std_msgs/String" in info.stdout
    recorded = [(m.timestamp, m.message.data) for m in rec.bag.read_messages()]
    assert [(m.timestamp, m.message.data) for m in Bag(str(active)).read_messages()] == recorded
    rec.stop()
