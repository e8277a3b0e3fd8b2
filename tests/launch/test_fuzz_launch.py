"""Fuzz roslaunch XML: random and mutated launch files give a LaunchPlan or a DdesError, fast."""

from __future__ import annotations

import tracemalloc

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes.errors import DdesError
from ddes.launch import load_launch
from ddes.launch.plan import LaunchPlan

_VALID = """<launch>
  <arg name="robot" default="r1"/>
  <param name="rate" value="10"/>
  <param name="cfg" type="yaml" value="{a: 1, b: [1, 2]}"/>
  <rosparam ns="gains">{P: 1.0, angle: !degrees 90, r: rad(pi/2)}</rosparam>
  <group ns="$(arg robot)" if="true">
    <param name="~x" value="1.5"/>
    <remap from="a" to="b"/>
  </group>
</launch>
"""

_PIECES = ["<launch>", "</launch>", "<group>", "</group>", '<group ns="g">', "<arg ", "/>", ">",
           'name="a"', 'value="1"', 'default="$(arg a)"', '<param name="p" value="1"/>',
           '<param name="y" type="yaml" value="&amp;a [*a]"/>', "<rosparam>", "</rosparam>",
           "a: &amp;x [1, *x]", "x: !radians 9**9**9", "$(eval 1)", "$(find nope)", "&amp;",
           "&lt;", '<!DOCTYPE l [<!ENTITY e "ee">]>', "&e;", "<![CDATA[", "]]>", "<!-- -->",
           '<include file="/dev/zero"/>', '<param name="b" binfile="/dev/zero"/>', "\x00", "é",
           '<node pkg="p" type="t" name="n"/>', 'if="$(arg a)"', "<env name='E' value='1'/>"]


def _check(text: str) -> None:
    source = text if text.lstrip().startswith("<") else "<" + text
    tracemalloc.start()  # a memory bound, not a CPU-time one: it holds on a loaded machine
    try:
        try:
            plan = load_launch(source)
            assert isinstance(plan, LaunchPlan)
        except DdesError:
            pass
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 16 * 2**20, (text, peak)  # /dev/zero, alias and angle bombs never expand


@st.composite
def _mutated(draw: st.DrawFn) -> str:
    text = _VALID
    for _ in range(draw(st.integers(1, 6))):
        i = draw(st.integers(0, len(text)))
        op = draw(st.sampled_from(["insert", "delete", "piece", "repeat"]))
        if op == "insert":
            text = text[:i] + draw(st.text(max_size=8)) + text[i:]
        elif op == "delete":
            text = text[:i] + text[i + draw(st.integers(1, 20)):]
        elif op == "piece":
            text = text[:i] + draw(st.sampled_from(_PIECES)) + text[i:]
        else:
            j = min(len(text), i + draw(st.integers(1, 40)))
            text = text[:i] + text[i:j] * draw(st.integers(2, 300)) + text[j:]
    return text


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_mutated())
def test_fuzz_mutated_launch_xml_gives_a_plan_or_a_ddes_error(text: str) -> None:
    _check(text)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(_PIECES), max_size=60).map("".join))
def test_fuzz_launch_xml_from_pieces_gives_a_plan_or_a_ddes_error(text: str) -> None:
    _check("<launch>" + text + "</launch>")


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=300))
def test_fuzz_random_text_gives_a_plan_or_a_ddes_error(text: str) -> None:
    _check(text)


def test_the_unmutated_seed_file_loads() -> None:
    plan = load_launch(_VALID)
    assert plan.params["/rate"] == 10
