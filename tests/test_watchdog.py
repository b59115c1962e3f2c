"""Code stuck in a loop is ended where it is stuck, the robot is stopped, and the student told."""

from __future__ import annotations

import itertools
import re
import sys
import threading
from pathlib import Path
from types import FrameType

import pytest
from helpers import run_cli

from roboscript.sim.simulation import make_simulation
from roboscript.transport.wirelog import read_wire_log
from roboscript.watchdog import RunawayCode, Watchdog


def _where(frame: FrameType | None) -> str:
    assert frame is not None
    return f"{frame.f_code.co_name}:{frame.f_lineno}"


def _spin_forever() -> None:
    for _ in itertools.count():
        pass


def test_code_that_never_returns_is_stopped_where_it_is() -> None:
    with pytest.raises(RunawayCode) as raised, Watchdog(0.2, _where):
        _spin_forever()
    assert raised.value.where.startswith("_spin_forever:")
    assert "did not return for 0.2 s and was stopped at _spin_forever:" in raised.value.reason


def test_one_catch_all_does_not_keep_it_in() -> None:
    caught = 0
    with pytest.raises(RunawayCode), Watchdog(0.2, _where):
        try:
            _spin_forever()
        except BaseException:  # noqa: BLE001 (a student's catch-all)
            caught += 1
        _spin_forever()  # the alarm comes again
    assert caught == 1


def test_petting_it_keeps_honest_code_running() -> None:
    ticks = 0
    with Watchdog(0.5, _where) as dog:
        for ticks in range(1, 40):  # noqa: B007 (ticks is read after the loop)
            threading.Event().wait(0.02)  # a tick's work, well under the limit
            dog.pet()
    assert ticks == 39  # 0.8 s in all, longer than the limit, yet never stopped


def test_after_the_block_nothing_fires() -> None:
    with Watchdog(0.05, _where):
        pass
    threading.Event().wait(0.15)  # an armed timer would raise in here


def test_a_limit_must_be_positive() -> None:
    with pytest.raises(ValueError, match="more than 0 s"):
        Watchdog(0, _where)


def test_off_the_main_thread_it_stands_aside() -> None:
    seen: list[bool] = []
    thread = threading.Thread(target=lambda: seen.append(Watchdog(1, _where).supported))
    thread.start()
    thread.join()
    assert seen == [False]


SPIN = '''\
"""Drive, checking a condition whose loop never ends."""

from roboscript import Drive, Mission, state


class Spin(Mission):
    """Drive two metres unless the condition fires."""

    go = state(
        Drive(distance_mm=2000, speed_mm_s=150),
        initial=True,
        on_done="done",
        on_failed="done",
        when=[("far", "done")],
    )
    done = state(final="success")

    def far(self) -> bool:
        """Count forever: a beginner's mistake."""
        n = 0
        while n >= 0:
            n += 1
        return True
'''


@pytest.mark.skipif(sys.platform == "win32", reason="the watchdog needs SIGALRM")
def test_run_ends_a_stuck_mission_with_its_line_and_the_motors_off(tmp_path: Path) -> None:
    mission = tmp_path / "spin.py"
    mission.write_text(SPIN, encoding="utf-8")
    log = tmp_path / "wire.log"
    result = run_cli("run", str(mission), "--wire-log", str(log), "--quiet")
    assert result.returncode == 1
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith("error: the mission's code did not return for 5 s and was stopped at ")
    assert re.search(r"spin\.py:2[12] in far:", last)  # a line of the endless loop
    assert "Traceback" not in result.stderr
    # replay what the host sent into a fresh simulated robot: the motors must be off
    sim = make_simulation("mirto")
    sim.connect()
    for t, direction, data in read_wire_log(log):
        if direction == ">":
            sim.tick(t, 0.0)
            sim.write(data)
    sim.tick(sim.time_s + 0.25, 0.0)
    assert sim.body.power == [0.0, 0.0]


LOOPING_BEHAVIOUR_FILE = '''\
"""Hangs when imported."""

while True:
    pass
'''


@pytest.mark.skipif(sys.platform == "win32", reason="the watchdog needs SIGALRM")
def test_check_ends_a_file_that_hangs_when_imported(tmp_path: Path) -> None:
    mission = tmp_path / "hang.py"
    mission.write_text(LOOPING_BEHAVIOUR_FILE, encoding="utf-8")
    result = run_cli("check", str(mission))
    assert result.returncode == 1
    assert "did not return for 5 s and was stopped at" in result.stderr
    assert re.search(r"hang\.py:[34] in <module>:", result.stderr)
