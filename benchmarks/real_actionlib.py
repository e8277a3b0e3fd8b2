"""Real actionlib's goal throughput: run under the system Python with ROS Noetic (not the venv).

    /usr/bin/python3 benchmarks/real_actionlib.py 300

Starts ``rosmaster --core`` on a free loopback port (a private ROS_HOME), one
process with an ``actionlib.ActionServer`` (accept, one feedback, succeed: the
same five messages per goal as ``bench_actions.py``) and an
``actionlib.ActionClient`` sending N goals one at a time, each waiting for
DONE.  The action is ``actionlib/Test`` (int32 goal, result and feedback:
actionlib_tutorials is not installed with ROS; the Fibonacci messages of
``bench_actions.py`` are about as small).  Prints one JSON line: ``{"goals": N, "goals_per_s": ...}``
(wall clock: the work is spread over rospy's threads and the master).
"""

import json
import os
import socket
import subprocess
import sys
import tempfile
import threading
import time


def _free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def main(n):
    port = _free_port()
    home = tempfile.mkdtemp(prefix="ddes-bench-ros-")
    os.environ.update(ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_HOSTNAME="127.0.0.1",
                      ROS_HOME=home, ROS_LOG_DIR=os.path.join(home, "log"))
    os.environ.pop("ROS_NAMESPACE", None)
    os.environ.pop("ROS_IP", None)
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        import actionlib
        import rospy
        from actionlib.msg import TestAction, TestFeedback, TestGoal, TestResult

        deadline = time.time() + 30
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), 0.5).close()
                break
            except OSError:
                if time.time() > deadline:
                    raise
                time.sleep(0.05)
        rospy.init_node("bench_actionlib", disable_signals=True, disable_rosout=True)
        feedback, result = TestFeedback(feedback=1), TestResult(result=2)

        def goal_cb(gh):
            gh.set_accepted()
            gh.publish_feedback(feedback)
            gh.set_succeeded(result)

        server = actionlib.ActionServer("fibonacci", TestAction, goal_cb, auto_start=False)
        server.start()
        client = actionlib.ActionClient("fibonacci", TestAction)
        if not client.wait_for_server(rospy.Duration(30)):
            raise RuntimeError("the action server never appeared")
        time.sleep(1.0)  # let every status/feedback/result connection form
        done = threading.Event()

        def transition(gh):
            if gh.get_comm_state() == actionlib.CommState.DONE:
                done.set()

        handles = []
        t0 = time.perf_counter()
        for _ in range(n):
            done.clear()
            handles.append(client.send_goal(TestGoal(goal=3), transition))
            if not done.wait(30):
                raise RuntimeError("a goal never finished")
        dt = time.perf_counter() - t0
        print(json.dumps({"goals": n, "goals_per_s": n / dt}))
        rospy.signal_shutdown("done")
    finally:
        master.terminate()
        master.wait(10)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 300)
