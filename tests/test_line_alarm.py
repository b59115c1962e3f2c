"""The alarm that rings between two lines of watched code (the watchdog's timer without signals)."""

from __future__ import annotations

import sys
import time
from collections.abc import Iterator
from types import FrameType

import pytest

from roboscript.line_alarm import LineAlarm


class Rang(BaseException):
    """Raised by the test's ring, with where it rang."""


def _ring(frame: FrameType) -> None:
    raise Rang(f"{frame.f_code.co_name}:{frame.f_lineno}")


def _this_file(filename: str) -> bool:
    return filename == __file__


@pytest.fixture
def alarm() -> Iterator[LineAlarm]:
    line_alarm = LineAlarm(_ring, _this_file)
    assert line_alarm.start()
    try:
        yield line_alarm
    finally:
        line_alarm.stop()


def _loop_for(seconds: float) -> int:
    laps = 0
    until = time.perf_counter() + seconds
    while time.perf_counter() < until:
        laps += 1
    return laps


def test_it_rings_in_the_watched_loop_once_the_time_is_up(alarm: LineAlarm) -> None:
    alarm.set(0.05)
    with pytest.raises(Rang, match=r"^_loop_for:\d+$"):
        _loop_for(10.0)


def test_it_stays_quiet_before_the_time_and_once_disarmed(alarm: LineAlarm) -> None:
    alarm.set(10.0)
    assert _loop_for(0.05) > 0
    alarm.set(0.01)
    alarm.set(0)  # disarmed before it was due
    assert _loop_for(0.05) > 0


def test_unwatched_code_is_never_interrupted() -> None:
    line_alarm = LineAlarm(_ring, lambda filename: False)
    assert line_alarm.start()
    try:
        line_alarm.set(0.01)
        assert _loop_for(0.05) > 0  # this file is not watched here: the loop runs out
    finally:
        line_alarm.stop()


def test_after_stop_nothing_rings() -> None:
    line_alarm = LineAlarm(_ring, _this_file)
    assert line_alarm.start()
    line_alarm.set(0.01)
    line_alarm.stop()
    assert not line_alarm.started
    assert _loop_for(0.05) > 0


def test_setting_it_again_after_a_ring_watches_again(alarm: LineAlarm) -> None:
    for _ in range(2):
        alarm.set(0.02)
        with pytest.raises(Rang):
            _loop_for(10.0)


@pytest.mark.skipif(sys.version_info >= (3, 12), reason="Python 3.12 watches with sys.monitoring")
def test_a_debuggers_trace_function_is_never_taken() -> None:
    def debugger(frame: FrameType, event: str, arg: object) -> None:
        return None

    sys.settrace(debugger)
    try:
        assert not LineAlarm(_ring, _this_file).start()
        assert sys.gettrace() is debugger
    finally:
        sys.settrace(None)


@pytest.mark.skipif(sys.version_info < (3, 12), reason="sys.monitoring is Python 3.12's")
def test_a_monitoring_tool_already_there_is_never_taken() -> None:
    first = LineAlarm(_ring, _this_file)
    assert first.start()
    try:
        assert not LineAlarm(_ring, _this_file).start()
    finally:
        first.stop()
