"""The date of default recording names: set_record_date, DDES_BAG_DATE, and its forms."""

from __future__ import annotations

import datetime
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ddes.errors import DdesTypeError, DdesValueError
from ddes.graph.world import World
from ddes.rosbag import Recorder
from ddes.rosbag.recorder import (
    bag_filename,
    default_record_date,
    parse_record_date,
    record_date,
    set_record_date,
)

DATES = st.datetimes(min_value=datetime.datetime(1970, 1, 1),
                     max_value=datetime.datetime(2200, 12, 31, 23, 59, 59))


@given(DATES)
def test_a_date_in_rosbags_form_names_that_file(when: datetime.datetime) -> None:
    text = when.strftime("%Y-%m-%d-%H-%M-%S")
    ns = parse_record_date(text)
    assert bag_filename(stamp_ns=ns) == text + ".bag"
    assert ns == parse_record_date(when.replace(microsecond=0).isoformat())
    assert ns == parse_record_date(when.replace(microsecond=0))


def test_zones_and_iso_forms() -> None:
    utc_noon = parse_record_date("2024-03-01-12-00-00")
    assert parse_record_date("2024-03-01T12:00:00Z") == utc_noon
    assert parse_record_date("2024-03-01 13:00:00+01:00") == utc_noon
    assert parse_record_date("2024-03-01") == utc_noon - 12 * 3600 * 10**9
    plus_two = datetime.timezone(datetime.timedelta(hours=2))
    assert parse_record_date("2024-03-01-14-00-00", tz=plus_two) == utc_noon


@pytest.mark.parametrize(("value", "error", "text"), [
    ("March", DdesValueError, "recording date 'March' is not a date"),
    ("2024-02-30-00-00-00", DdesValueError, "day is out of range for month"),
    ("1969-12-31", DdesValueError, "before 1970-01-01"),
    (17, DdesTypeError, "must be text or a datetime"),
])
def test_bad_dates_say_what_to_write(value: object, error: type[Exception], text: str) -> None:
    with pytest.raises(error, match=text) as info:
        parse_record_date(value)  # type: ignore[arg-type]
    assert "YYYY-MM-DD-HH-MM-SS" in str(info.value) or "1970" in str(info.value)


def test_the_world_date_advances_with_kernel_time_and_wins_over_the_environment(
        tmp_path: Path) -> None:
    world = World()
    assert record_date(world) is None
    assert default_record_date(world, {"DDES_BAG_DATE": "2000-01-01"}) == "2000-01-01"
    assert default_record_date(world, {"DDES_BAG_DATE": ""}) is None
    set_record_date(world, "2024-03-01-12-00-00")
    assert default_record_date(world, {"DDES_BAG_DATE": "2000-01-01"}) is None
    world.run(until=3599.9)
    rec = Recorder(world, ["/x"], output_prefix="p", cwd=str(tmp_path))
    assert rec.path == "p_2024-03-01-12-59-59.bag"  # as rosbag prints it; written in cwd
    rec.stop()
    assert (tmp_path / "p_2024-03-01-12-59-59.bag").exists()
    explicit = Recorder(world, ["/x"], date="2030-01-01", cwd=str(tmp_path))  # date= wins
    assert explicit.path == "2030-01-01-00-59-59.bag"
    explicit.stop()
    set_record_date(world, None)
    assert record_date(world) is None
