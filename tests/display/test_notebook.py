"""A real Jupyter kernel (nbclient + ipykernel) shows ddes objects with no magic.

One notebook, run as Jupyter runs it: a cell whose last value is a ddes
figure gets one ``image/png`` output (no ``%matplotlib inline``, no pyplot),
and a World, a trace selection and a Bag get ``text/html`` tables.
"""

from __future__ import annotations

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

import ddes

SETUP = '''\
import ddes
from ddes.actionlib import SimpleActionClient, SimpleActionServer, plot_goals
from ddes.msg import get_message_class
from ddes.rosbag import Bag

Fibonacci = get_message_class("actionlib_tutorials/FibonacciAction")
Goal = get_message_class("actionlib_tutorials/FibonacciGoal")
Feedback = get_message_class("actionlib_tutorials/FibonacciFeedback")
world = ddes.World(seed=0)
node = world.create_node("fibonacci")

def execute(goal):
    for i in range(goal.order):
        server.publish_feedback(Feedback(sequence=[i]))
        yield node.sleep(0.5)
    server.set_succeeded()

server = SimpleActionServer(node, "fibonacci", Fibonacci, execute)
client = SimpleActionClient(world.create_node("user"), "fibonacci", Fibonacci)
world.run(until=1.0)
client.send_goal(Goal(order=4))
world.run(until=5.0)
node.loginfo("<script>alert(1)</script>")
bag = Bag()
bag.write("/chatter", get_message_class("std_msgs/String")(data="hi"), ddes.Time(1))
'''


def test_a_notebook_shows_ddes_objects(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # the kernel imports the ddes under test, whatever the working directory
    monkeypatch.setenv("PYTHONPATH", str(Path(ddes.__file__).resolve().parents[1]))
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(src) for src in (
        SETUP,
        'plot_goals(world, ns="/fibonacci")',
        "world",
        'world.trace.select(kind="log")',
        "bag",
        "import sys; sorted(m for m in sys.modules if m.startswith('matplotlib.pyplot'))",
    )]
    NotebookClient(nb, timeout=120, kernel_name="python3",
                   resources={"metadata": {"path": str(tmp_path)}}).execute()
    setup, plot, world, selection, bag, pyplot = (cell.outputs for cell in nb.cells)
    assert [o.output_type for o in setup if o.output_type != "stream"] == []
    (out,) = plot  # one output: the picture, not also a second copy from a backend
    assert out.output_type == "execute_result"
    assert set(out.data) == {"image/png", "text/plain"}
    png = out.data["image/png"]
    assert png.startswith("iVBORw0KGgo")  # base64 of b"\x89PNG\r\n\x1a\n"
    assert out.metadata["image/png"]["width"] > 500
    (out,) = world
    assert "text/html" in out.data and ">seed</th>" in out.data["text/html"]
    assert "<code>/fibonacci/goal</code>" in out.data["text/html"]
    (out,) = selection
    html = out.data["text/html"]
    assert "<code>log</code>" in html and "&lt;script&gt;" in html and "<script>" not in html
    (out,) = bag
    assert "<code>/chatter</code>" in out.data["text/html"]
    (out,) = pyplot
    assert out.data["text/plain"] == "[]"  # nothing imported pyplot
