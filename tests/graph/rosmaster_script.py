"""Script parts for interop tests that need a live ROS master (real rosmaster, system Python).

``MASTER`` starts ``rosmaster --core`` on a free loopback port, points this
process at it (``ROS_MASTER_URI``, ``ROS_HOSTNAME``, a private ``ROS_HOME``)
and stops it when the script exits.  A script is ``MASTER + body``; run it
with the ``ros_python`` fixture (which skips when ROS is not installed).
The body finds ``MASTER_URI``, ``PORT`` and ``start_process(args)`` (a
subprocess on the same master, stdout and stderr captured).
"""

from __future__ import annotations

MASTER = r'''
import atexit, os, socket, subprocess, sys, tempfile, time, xmlrpc.client

def _free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port

PORT = _free_port()
MASTER_URI = "http://127.0.0.1:%d" % PORT
_HOME = tempfile.mkdtemp(prefix="ddes-ros-home-")
os.environ.update(ROS_MASTER_URI=MASTER_URI, ROS_HOSTNAME="127.0.0.1", ROS_HOME=_HOME,
                  ROS_LOG_DIR=os.path.join(_HOME, "log"))
os.environ.pop("ROS_NAMESPACE", None)
os.environ.pop("ROS_IP", None)
_master = subprocess.Popen(["rosmaster", "--core", "-p", str(PORT)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
_children = []

def _stop():
    for p in _children + [_master]:
        if p.poll() is None:
            p.terminate()
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()
atexit.register(_stop)

_deadline = time.time() + 30
while True:
    try:
        xmlrpc.client.ServerProxy(MASTER_URI).getSystemState("/probe")
        break
    except Exception:
        if time.time() > _deadline or _master.poll() is not None:
            raise SystemExit("rosmaster did not start")
        time.sleep(0.05)

def start_process(args, **kwargs):
    p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ), **kwargs)
    _children.append(p)
    return p
'''
