"""rostopic echo/hz --filter runs in ddes.expr's safe subset, not with full builtins."""

from __future__ import annotations

import tracemalloc

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes.console.rostopic_live import _filter_fn
from ddes.console.shell import Console
from ddes.errors import DdesError, ResourceLimitError, ROSConsoleError, UnsafeExpressionError
from ddes.msg import get_message_class

String = get_message_class("std_msgs/String")
Header = get_message_class("std_msgs/Header")


@pytest.mark.parametrize("expr", [
    "__import__('os').system('true')", "open('/etc/passwd')", "getattr(m, 'data')",
    "(x for x in ()).gi_frame.f_back.f_globals", "m.__class__.__mro__",
    "'{0.__class__}'.format(m)", "exec('1')", "[c for c in m.data]"
])
def test_escapes_are_refused_before_any_message(expr: str) -> None:
    with pytest.raises(UnsafeExpressionError) as info:
        _filter_fn(expr, "/chatter")
    assert isinstance(info.value, ROSConsoleError)
    assert "--filter" in str(info.value)


def test_a_method_outside_the_list_is_refused_on_the_message() -> None:
    fn = _filter_fn("m.serialize(None)", "/chatter")
    assert fn is not None
    with pytest.raises(UnsafeExpressionError, match="serialize"):
        fn(String(data="x"))


def test_bombs_on_a_message_are_typed_and_refused_before_built() -> None:
    fn = _filter_fn("len(m.data * 10**10) > 0", "/chatter")
    assert fn is not None
    msg = String(data="x")
    # refused before the bomb is built: memory (tracemalloc), not CPU time, so it holds under load
    tracemalloc.start()
    try:
        with pytest.raises(ResourceLimitError) as info:
            fn(msg)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert isinstance(info.value, ROSConsoleError)
    assert "exceeds" in str(info.value)
    assert peak < 8 * 2**20, peak  # built, m.data * 10**10 would be 10 GB
    with pytest.raises(ResourceLimitError):
        _filter_fn("9**9**9", "/chatter")(String(data="x"))  # type: ignore[misc]


def test_filters_still_work() -> None:
    assert _filter_fn("m.data.endswith('0.3') and topic == '/c'", "/c")(String(data="a 0.3"))  # type: ignore[misc]
    fn = _filter_fn("m.stamp.to_sec() > 1.5 and math.floor(m.stamp.secs) == 2", "/h")
    assert fn is not None and fn(Header(stamp=__import__("ddes").Time(2)))
    with pytest.raises(ROSConsoleError, match="failed on a message of /c.*TypeError"):
        _filter_fn("m.data > 3", "/c")(String(data="x"))  # type: ignore[misc]


def test_echo_refuses_an_unsafe_filter(chat: Console) -> None:
    result = chat.execute("rostopic echo -n 1 --filter \"().__class__\" /chatter")
    assert result.code != 0
    assert "names starting with '_'" in result.err


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(["m", ".data", " + ", " * ", "10**9", "'a'", " == ", "(", ")",
                                 "topic", "[0]", "._x", "len(", " ** ", "9", ".upper()",
                                 " in ", "math.pi", "str("]), max_size=12).map("".join))
def test_fuzz_filter(expr: str) -> None:
    msg = String(data="hi")
    tracemalloc.start()  # a small memory bound, not a CPU-time one (holds under load)
    try:
        try:
            fn = _filter_fn(expr, "/c")
            if fn is not None:
                fn(msg)
        except DdesError:
            pass
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 16 * 2**20, (expr, peak)
