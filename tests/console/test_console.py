"""The console: transcripts, script mode, bad inputs, the Python API, completion."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.console.shell import Console, run_script
from ddes.errors import ROSConsoleError

LECTURE_1 = """\
# lecture 1: a talker, a listener, and the console tools
rosrun --quiet rospy_tutorials talker &
rosrun rospy_tutorials listener &
rosnode list
rostopic list
rostopic info /chatter
rostopic echo -n 2 /chatter
rostopic hz -n 1 /chatter
rosnode kill /listener_2
rostopic pub -1 /greeting std_msgs/String "data: hello"
time
"""


def test_transcript_is_identical_run_after_run() -> None:
    code1, text1 = Console(seed=0).transcript(LECTURE_1.splitlines())
    code2, text2 = Console(seed=0).transcript(LECTURE_1.splitlines())
    assert code1 == code2 == 0
    assert text1 == text2
    assert text1.startswith("$ rosrun --quiet rospy_tutorials talker &\n"
                            "[1] rosrun --quiet rospy_tutorials talker\n"
                            "$ rosrun rospy_tutorials listener &\n"
                            "[2] rosrun rospy_tutorials listener\n"
                            "$ rosnode list\n/listener_2\n/rosout\n/talker_1\n")
    assert text1.endswith("$ time\nsimulated time: 4.200000000 s\n")


def test_script_mode_twice_from_the_command_line(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    script = tmp_path / "lecture1.txt"
    script.write_text(LECTURE_1)
    outs = []
    for _ in range(2):
        assert main(["console", "--script", str(script)]) == 0
        outs.append(capsys.readouterr().out)
    assert outs[0] == outs[1]
    assert outs[0] == Console(seed=0).transcript(LECTURE_1.splitlines())[1]


def test_commands_on_standard_input(monkeypatch: pytest.MonkeyPatch,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO("rosnode list\nrosparam get /rosversion\n"))
    assert main(["console"]) == 0
    assert capsys.readouterr().out == ("$ rosnode list\n/rosout\n"
                                       "$ rosparam get /rosversion\n'1.16.0\n\n  '\n\n")


BAD_INPUTS = [
    ("frobnicate", "unknown command 'frobnicate'"),
    ("rostopic echo -n 1 /no_topic", "topic [/no_topic] does not appear to be published yet"),
    ("rostopic info /no_topic", "Unknown topic /no_topic"),
    ("rostopic pub -1 /x no_pkg/NoType 1", "invalid message type: no_pkg/NoType"),
    ("rosrun no_pkg talker &", "package 'no_pkg' not found"),
    ("rosrun rospy_tutorials no_node", "Couldn't find executable named no_node"),
    ("roslaunch no_pkg x.launch", "[x.launch] is neither a launch file in package [no_pkg]"),
    ("roslaunch {bad_xml}", "bad.launch:2: <node pkg=\"rospy_tutorials\" name=\"t\">: <node> "
                            "tag is missing required attribute: 'type'"),
    ("roslaunch {needs_arg}", "needs_arg.launch:3: <param name=\"r\" value=\"$(arg robot)\">"),
    ("roslaunch {bad_find}", "no_such_pkg"),
    ("rosparam get /no_param", "Parameter [/no_param] is not set"),
]


@pytest.fixture
def launch_files(tmp_path: Path) -> dict[str, str]:
    bad_xml = tmp_path / "bad.launch"
    bad_xml.write_text("<launch>\n  <node pkg='rospy_tutorials' name='t'/>\n</launch>\n")
    needs_arg = tmp_path / "needs_arg.launch"
    needs_arg.write_text("<launch>\n  <arg name='robot'/>\n"
                         "  <param name='r' value='$(arg robot)'/>\n</launch>\n")
    bad_find = tmp_path / "bad_find.launch"
    bad_find.write_text("<launch><param name='p' value='$(find no_such_pkg)/x'/></launch>\n")
    return {"bad_xml": str(bad_xml), "needs_arg": str(needs_arg), "bad_find": str(bad_find)}


@pytest.mark.parametrize("line, text", BAD_INPUTS)
def test_bad_input_one_line_error_in_the_console(console: Console, launch_files: dict[str, str],
                                                 line: str, text: str) -> None:
    line = line.format(**launch_files)
    result = console.execute(line)
    assert result.code != 0
    assert result.err.startswith("ERROR: ")
    assert text in result.err
    assert result.err.count("\n") == 1
    assert console.run("rosnode list") == "/rosout\n"  # and the console carries on


@pytest.mark.parametrize("line, text", BAD_INPUTS)
def test_bad_input_stops_a_script(tmp_path: Path, launch_files: dict[str, str],
                                  capsys: pytest.CaptureFixture[str], line: str, text: str) -> None:
    line = line.format(**launch_files)
    script = tmp_path / "s.txt"
    script.write_text(f"rosnode list\n{line}\nrosnode list\n")
    code = main(["console", "--script", str(script)])
    out = capsys.readouterr().out
    assert code != 0
    head, _, error = out.partition(f"$ {line}\n")
    assert head == "$ rosnode list\n/rosout\n"
    assert error.startswith("ERROR: ") and text in error and error.count("\n") == 1
    assert main(["console", "--script", str(script), "--keep-going"]) == 1
    assert capsys.readouterr().out.endswith("$ rosnode list\n/rosout\n")


def test_missing_script_file(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["console", "--script", "/no/such/script"]) == 1
    assert capsys.readouterr().err.startswith("ERROR: cannot read script /no/such/script")


def test_run_returns_text_and_raises_on_failure(console: Console) -> None:
    assert console.run("rosnode list") == "/rosout\n"
    with pytest.raises(ROSConsoleError, match="Unknown topic /x"):
        console.run("rostopic info /x")
    assert console.run("rostopic info /x", check=False) == "ERROR: Unknown topic /x\n"
    result = console.execute("rostopic type /nope")
    assert (result.code, result.out, result.err) == (1, "", "unknown topic type [/nope]\n")


def test_exit_ends_a_script() -> None:
    lines: list[str] = []
    code = run_script(Console(), ["rosnode list", "exit", "rosnode list"], lines.append)
    assert code == 0 and lines == ["$ rosnode list", "/rosout", "$ exit"]


def test_help(console: Console) -> None:
    text = console.run("help")
    assert text.startswith("ddes console: ROS 1 tools on one simulated world")
    for name in ("rosnode", "rosparam", "roslaunch", "rosrun", "rostopic", "sleep", "jobs"):
        assert name in text
    assert console.run("help rosnode").startswith("rosnode is a command-line tool")
    assert console.run("help exit") == "exit: a console command (see 'help')\n"


def test_failing_node_code_is_reported_and_the_console_goes_on(console: Console) -> None:
    node = console.world.create_node("fragile")
    string = __import__("ddes.msg", fromlist=["get_message_class"]).get_message_class(
        "std_msgs/String")

    def callback(msg: object) -> None:
        raise ValueError("bad data")

    node.subscribe("/in", string, callback)

    def main_loop():  # type: ignore[no-untyped-def]
        yield node.sleep(1.0)
        raise KeyError("lost")

    node.process(main_loop())
    result = console.execute("rostopic pub -1 /in std_msgs/String x")
    # rospy's rule: the bad callback is logged and the node goes on; the failing main
    # shuts its node down with a logged error; the command and the console go on.
    assert result.code == 0
    assert result.err.splitlines() == [
        "ERROR: bad callback in node /fragile: test_failing_node_code_is_reported_and_the_"
        "console_goes_on.<locals>.callback: ValueError: bad data"]
    assert "bad callback: test_failing_node_code" in result.out
    assert 'File "test_console.py"' in result.out and "ValueError: bad data" in result.out
    assert "process has died: the main of /fragile raised KeyError" in result.out
    assert "KeyError: 'lost'" in result.out
    assert console.run("time") == "simulated time: 3.000000000 s\n"
    assert "/fragile" not in console.run("rosnode list")


def test_completion(console: Console) -> None:
    console.run("rosrun --quiet rospy_tutorials talker &")
    assert console.complete("rost", "rost") == ["rostest", "rostopic"]
    assert "rosrun" in console.complete("", "")
    assert console.complete("roscd roscpp_t", "roscpp_t") == ["roscpp_tutorials"]
    assert console.complete("rospack find std_m", "std_m") == ["std_msgs"]
    assert console.complete("rostopic ", "") == ["bw", "delay", "echo", "find", "hz", "info",
                                                 "list", "pub", "type"]
    assert console.complete("rostopic echo /ch", "/ch") == ["/chatter"]
    assert console.complete("rostopic echo -n 3 /ro", "/ro") == ["/rosout", "/rosout_agg"]
    assert console.complete("rosnode info /t", "/t") == ["/talker_1"]
    assert console.complete("rosparam get /rosd", "/rosd") == ["/rosdistro"]
    assert console.complete("rosrun rospy_t", "rospy_t") == ["rospy_tutorials"]
    assert "talker" in console.complete("rosrun rospy_tutorials ta", "ta")
    assert console.complete("roslaunch rospy_tutorials tal", "tal") == ["talker_listener.launch"]
    assert console.complete("rostopic pub /x std_msgs/Str", "std_msgs/Str") == \
        ["std_msgs/String"]
    assert console.complete("rosmsg show geometry_msgs/Twi", "geometry_msgs/Twi") == \
        ["geometry_msgs/Twist", "geometry_msgs/TwistStamped",
         "geometry_msgs/TwistWithCovariance", "geometry_msgs/TwistWithCovarianceStamped"]
    assert console.complete("kill %", "%") == ["%1"]
    assert console.complete("rostopic echo 'unbal", "'unbal") == []


def test_world_can_be_passed_in_and_log_lines_go_to_out() -> None:
    from ddes.graph.world import World

    world = World(seed=4)
    lines: list[str] = []
    console = Console(world, core=False, out=lines.append)
    assert console.run("rosnode list") == "\n"
    console.run("rosrun rospy_tutorials talker &")
    world.run_for(0.15)  # the world run directly, outside any command
    assert lines == ["[INFO] [0.100000]: hello world 0.1"]


def test_open_quotes_continue_on_the_next_line() -> None:
    code, text = Console().transcript(['rostopic pub /p std_msgs/Header "seq: 7', 'frame_id: map" &',
                                       "rostopic echo -n 1 /p"])
    assert code == 0
    assert text == ('$ rostopic pub /p std_msgs/Header "seq: 7\n> frame_id: map" &\n'
                    "publishing and latching message. Press ctrl-C to terminate\n"
                    "[1] rostopic pub /p std_msgs/Header 'seq: 7\nframe_id: map'\n"
                    "$ rostopic echo -n 1 /p\n"
                    "seq: 7\nstamp: \n  secs: 0\n  nsecs:         0\nframe_id: \"map\"\n---\n")
    code, text = Console().transcript(["rosnode list", "rostopic echo 'open"])
    assert code == 1 and text.endswith("ERROR: cannot parse the command line: No closing "
                                       "quotation at the end of the script\n")
    result = Console().execute("rostopic echo 'open")  # one line, from Python: an error
    assert result.err == "ERROR: cannot parse the command line: No closing quotation\n"


def test_ampersand_glued_to_the_last_word(chat: Console) -> None:
    assert chat.run("rostopic echo /chatter&") == "[3] rostopic echo /chatter\n"
    chat.run("kill %3")
    chat.run("rostopic pub -1 /amp std_msgs/String 'a&' &")
    assert chat.run("rostopic echo -n 1 /amp") == 'data: "a&"\n---\n'
