"""Code stuck in a loop is ended where it is stuck, the robot is stopped, and the student told."""

from __future__ import annotations

import contextlib
import dataclasses
import gc
import itertools
import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from types import FrameType

import pytest
from helpers import HANG_BOUND_S, ROOT, every_core_busy, run_cli

from roboscript import watchdog as watchdog_module
from roboscript.sim.simulation import make_simulation
from roboscript.transport.wirelog import read_wire_log
from roboscript.watchdog import (
    REPEAT_S,
    CodeClock,
    CodePlace,
    RunawayCode,
    TickBudget,
    TooSlow,
    Watchdog,
    wire_wait,
)


def _where(frame: FrameType | None) -> CodePlace:
    assert frame is not None
    return CodePlace(frame.f_code.co_filename, frame.f_lineno, frame.f_code.co_name)


@contextlib.contextmanager
def no_timer_signal() -> Iterator[None]:
    """Python without ``signal.setitimer`` inside the block, as on Windows or in a browser tab.

    Not ``monkeypatch.delattr``: pytest-timeout cancels its timer with ``setitimer`` as soon as
    a test fails, before fixtures are undone, so a failure would become an internal error that
    ends the session and hides what failed. The block gives it back before any report.
    """
    setitimer = signal.setitimer
    del signal.setitimer
    try:
        yield
    finally:
        signal.setitimer = setitimer


def _spin_forever() -> None:
    for _ in itertools.count():
        pass


def _in_loop_of(where: CodePlace | None, function: Callable[..., object]) -> bool:
    """``where`` is a line of ``function``'s body, in this file."""
    first = function.__code__.co_firstlineno
    return (
        where is not None
        and where.file == __file__
        and where.function == function.__name__
        and first < where.line <= first + 3
    )


def _students_loop() -> None:
    for _ in itertools.count():
        pass


def _in_students_code(frame: FrameType | None) -> CodePlace | None:
    """Where ``_students_loop`` runs, the one function here that stands for a student's."""
    while frame is not None:
        if frame.f_code is _students_loop.__code__:
            return CodePlace(__file__, frame.f_lineno, frame.f_code.co_name)
        frame = frame.f_back
    return None


def test_a_stop_raised_again_outside_the_students_code_still_names_their_loop() -> None:
    # Their loop is stopped; on its way out, code of no file of theirs runs on (freeing the
    # list a comprehension built can take seconds): the stop, raised again there, still
    # says where their loop was.
    with pytest.raises(RunawayCode) as raised, Watchdog(0.2, _in_students_code):
        try:
            _students_loop()
        finally:
            time.sleep(5 * REPEAT_S)  # the stop is raised again in here
    assert raised.value.where is not None
    assert raised.value.where.function == "_students_loop"


def _where_in_its_loop(frame: FrameType | None) -> CodePlace:
    """Where the code is, its loop being ``_spin_forever``'s ``for`` (as a student's file's
    place is found by :func:`roboscript.mission.student_code.loop_around`)."""
    place = _where(frame)
    return dataclasses.replace(place, loop_line=_spin_forever.__code__.co_firstlineno + 1)


def test_a_stop_names_the_loop_it_caught_and_a_slow_tick_its_line() -> None:
    # A loop is caught on any of its lines: the stop names its first line, the same each time.
    with pytest.raises(RunawayCode) as raised, Watchdog(0.2, _where_in_its_loop):
        _spin_forever()
    assert raised.value.line == _spin_forever.__code__.co_firstlineno + 1
    place = CodePlace("m.py", 12, "near", loop_line=10)
    assert place.in_loop() == CodePlace("m.py", 10, "near")
    assert str(place) == "m.py:12 in near"  # a slow tick's place: the line it was slow on
    assert CodePlace("m.py", 12, "near").in_loop() == CodePlace("m.py", 12, "near")


def test_code_that_stops_time_for_itself_is_still_stopped(monkeypatch: pytest.MonkeyPatch) -> None:
    # A mission that replaces time.perf_counter cannot stop its own watchdog's clock.
    monkeypatch.setattr(time, "perf_counter", lambda: 0.0)
    with pytest.raises(RunawayCode) as raised, Watchdog(0.2, _where):
        _spin_forever()
    assert _in_loop_of(raised.value.where, _spin_forever)


def test_code_that_never_returns_is_stopped_where_it_is() -> None:
    with pytest.raises(RunawayCode) as raised, Watchdog(0.2, _where):
        _spin_forever()
    stopped = raised.value
    assert _in_loop_of(stopped.where, _spin_forever)
    assert stopped.where is not None
    assert (stopped.file, stopped.line) == (__file__, stopped.where.line)
    assert (
        f"did not return for 0.2 s and was stopped at {__file__}:{stopped.line} in _spin_forever:"
        in stopped.reason
    )


@pytest.mark.skipif(sys.platform == "win32", reason="the watchdog needs SIGALRM")
def test_quick_ticks_set_no_timer_and_a_later_stuck_tick_is_still_stopped(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Setting the timer twice a tick was two system calls in every tick of every run.
    set_timer = signal.setitimer
    settings: list[float] = []

    def counted(which: int, seconds: float, interval: float = 0.0) -> tuple[float, float]:
        settings.append(seconds)
        return set_timer(which, seconds, interval)

    monkeypatch.setattr(watchdog_module.signal, "setitimer", counted)
    dog = Watchdog(1.0, _where, budget=BUDGET)
    with pytest.raises(RunawayCode) as raised, dog:
        for _ in range(500):
            dog.timed(_quick_tick)(0.0, 0.02)
        quick_settings = len(settings)
        dog.timed(lambda now_s, dt_s: _spin_forever())(0.0, 0.02)
    assert quick_settings <= 3, settings  # set on the way in, and by alarms, never per tick
    assert _in_loop_of(raised.value.where, _spin_forever)


@pytest.mark.parametrize("timer", ["SIGALRM", "between lines"])
def test_one_catch_all_does_not_keep_it_in(timer: str) -> None:
    if timer == "between lines" and sys.version_info < (3, 12):
        pytest.skip("before Python 3.12 a catch-all keeps it in (line_alarm)")
    caught = 0
    with (
        no_timer_signal() if timer == "between lines" else contextlib.nullcontext(),
        pytest.raises(RunawayCode),
        Watchdog(0.2, _where),
    ):
        try:
            _spin_forever()
        except BaseException:  # noqa: BLE001 (a student's catch-all)
            caught += 1
        _spin_forever()  # the alarm comes again
    assert caught == 1


def _stopped_then_dropped() -> str:
    """Stuck, then the stop is dropped and the code returns: as a student's catch-all does,
    or a library that logs and drops what its callbacks raise, or a finaliser."""
    try:
        _spin_forever()
    except BaseException as exc:  # noqa: BLE001 (the mistake under test)
        return f"dropped {type(exc).__name__}"
    return "never stopped"


@pytest.mark.parametrize("timer", ["SIGALRM", "between lines"])
def test_a_stop_dropped_by_the_ticks_code_is_raised_again_when_the_tick_returns(
    timer: str,
) -> None:
    def tick(now_s: float, dt_s: float) -> None:
        _stopped_then_dropped()

    with no_timer_signal() if timer == "between lines" else contextlib.nullcontext():
        dog = Watchdog(0.2, _where, budget=BUDGET)
        with pytest.raises(RunawayCode) as raised, dog:
            dog.timed(tick)(0.0, 0.02)
    assert not isinstance(raised.value, TooSlow)  # stuck, as it was: not merely slow
    assert _in_loop_of(raised.value.where, _spin_forever)


def test_a_stop_dropped_in_a_watched_block_is_raised_again_as_the_block_ends() -> None:
    with pytest.raises(RunawayCode) as raised, Watchdog(0.2, _where):
        _stopped_then_dropped()  # a file that hangs when imported, its loop in a catch-all
    assert _in_loop_of(raised.value.where, _spin_forever)


def test_a_stop_the_loop_dealt_with_is_not_raised_again() -> None:
    with Watchdog(0.2, _where) as dog:
        try:
            _spin_forever()
        except RunawayCode:
            dog.pet()  # the loop caught it, and goes on: its own decision


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


def test_off_the_main_thread_a_loop_is_stopped_between_two_of_its_lines() -> None:
    raised: list[RunawayCode] = []

    def watched_loop() -> None:
        try:
            with Watchdog(0.2, _where):
                _spin_forever()
        except RunawayCode as exc:
            raised.append(exc)

    thread = threading.Thread(target=watched_loop)
    thread.start()
    thread.join()
    assert len(raised) == 1
    assert _in_loop_of(raised[0].where, _spin_forever)


def test_without_sigalrm_a_loop_is_stopped_at_its_line() -> None:
    with no_timer_signal():
        dog = Watchdog(0.2, _where, watched=lambda filename: filename == __file__)
        assert dog.supported
        with pytest.raises(RunawayCode) as raised, dog:
            _spin_forever()
    assert _in_loop_of(raised.value.where, _spin_forever)


def test_without_sigalrm_a_loop_is_stopped_again_in_a_later_tick() -> None:
    stops = 0
    with no_timer_signal(), Watchdog(0.2, _where) as dog:
        for _tick in range(2):
            try:
                _spin_forever()
            except RunawayCode:
                stops += 1
            dog.pet()
    assert stops == 2


def test_without_sigalrm_nothing_is_watched_after_the_block() -> None:
    with no_timer_signal():
        with Watchdog(0.05, _where):
            pass
        assert sys.gettrace() is None
        deadline = time.perf_counter() + 0.15
        while time.perf_counter() < deadline:  # a watched loop would be stopped in here
            pass


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


def _run_without_sigalrm(*args: str) -> subprocess.CompletedProcess[str]:
    """``roboscript ARGS`` in a child process whose Python has no timer signal (as on
    Windows, or in a browser tab)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    program = (
        "import runpy, signal, sys\n"
        "del signal.setitimer\n"
        "sys.argv = ['roboscript', *sys.argv[1:]]\n"
        "runpy.run_module('roboscript', run_name='__main__')\n"
    )
    return subprocess.run(
        [sys.executable, "-c", program, *args],
        capture_output=True,
        text=True,
        timeout=HANG_BOUND_S,
        cwd=ROOT,
        env=env,
        check=False,
    )


@pytest.mark.parametrize("timer", ["SIGALRM", "between lines"])
def test_run_ends_a_stuck_mission_with_its_line_and_the_motors_off(
    tmp_path: Path, timer: str
) -> None:
    if timer == "SIGALRM" and sys.platform == "win32":
        pytest.skip("Windows has no SIGALRM")
    mission = tmp_path / "spin.py"
    mission.write_text(SPIN, encoding="utf-8")
    log = tmp_path / "wire.log"
    run = run_cli if timer == "SIGALRM" else _run_without_sigalrm
    result = run("run", str(mission), "--wire-log", str(log), "--quiet")
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


def test_run_ends_a_condition_that_drops_its_stop_as_stuck_at_its_line(tmp_path: Path) -> None:
    mission = tmp_path / "spin.py"
    mission.write_text(
        SPIN.replace(
            "        n = 0\n        while n >= 0:\n            n += 1\n        return True\n",
            "        n = 0\n        try:\n            while n >= 0:\n                n += 1\n"
            "        except BaseException:\n            return False\n        return True\n",
        ),
        encoding="utf-8",
    )
    result = run_cli("run", str(mission), "--quiet")
    assert result.returncode == 1
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith("error: the mission's code did not return for 5 s and was stopped at ")
    assert re.search(r"spin\.py:2[23] in far:", last)  # a line of the endless loop


LOOPING_BEHAVIOUR_FILE = '''\
"""Hangs when imported."""

while True:
    pass
'''


@pytest.mark.parametrize("timer", ["SIGALRM", "between lines"])
def test_check_ends_a_file_that_hangs_when_imported(tmp_path: Path, timer: str) -> None:
    if timer == "SIGALRM" and sys.platform == "win32":
        pytest.skip("Windows has no SIGALRM")
    mission = tmp_path / "hang.py"
    mission.write_text(LOOPING_BEHAVIOUR_FILE, encoding="utf-8")
    run = run_cli if timer == "SIGALRM" else _run_without_sigalrm
    square = ROOT / "missions" / "square.yaml"
    result = run("check", str(mission), str(square))
    assert result.returncode == 2
    # that file's own mistake, at its line, and the next file is still checked
    assert re.search(
        r"hang\.py:[34]: error: the file did not finish loading in 5 s: a loop at its top"
        r" level \(outside any def\) never ends",
        result.stderr,
    )
    assert result.stderr.splitlines()[-1] == "checked 2 files: 1 with errors"


# ------------------------------------------------------------------ the per-tick rule

BUDGET = TickBudget(slow_tick_s=0.02, too_slow_after_s=0.3)


def _napping_tick(now_s: float, dt_s: float) -> None:
    time.sleep(0.05)


def _quick_tick(now_s: float, dt_s: float) -> None:
    sum(range(1000))


@pytest.mark.skipif(sys.platform == "win32", reason="the watchdog needs SIGALRM")
def test_ticks_that_sleep_are_reported_once_at_their_line_then_ended_as_too_slow() -> None:
    seen: list[tuple[float, CodePlace | None]] = []
    dog = Watchdog(5.0, _where, budget=BUDGET, on_slow=lambda s, w: seen.append((s, w)))
    tick = dog.timed(_napping_tick)
    ticks = 0
    with pytest.raises(TooSlow) as raised, dog:
        for ticks in range(1, 100):  # noqa: B007 (ticks is read after the loop)
            tick(0.0, 0.02)
    # 0.3 s of slow ticks at 0.05 s each (the one interrupted to say where may count less)
    assert 6 <= ticks < 20
    assert len(seen) == 1
    spent_s, where = seen[0]
    # the warning names the slowest of the ticks so far (the first, never interrupted, slept
    # its 0.05 s; a busy machine's wait for a CPU around a sleep is left out of the code's own
    # time, so it may measure a little less): if this fails, whether every tick
    # measured short tells the clock from the rule
    assert spent_s > 0.02, f"{dog.slow_ticks} slow ticks, slowest {dog.slowest_s:.4f} s"
    assert _in_loop_of(where, _napping_tick)
    assert raised.value.where == where
    assert raised.value.reason.startswith(f"the mission was too slow: its code at {where}")
    assert "never time.sleep" in raised.value.reason


def test_one_slow_tick_alone_is_forgiven_and_warned_about_without_a_line() -> None:
    seen: list[tuple[float, CodePlace | None]] = []
    dog = Watchdog(5.0, _where, budget=BUDGET, on_slow=lambda s, w: seen.append((s, w)))
    with dog:
        dog.timed(_napping_tick)(0.0, 0.02)
        for _ in range(20):
            dog.timed(_quick_tick)(0.0, 0.02)
    assert dog.slow_ticks == 1
    assert len(seen) == 1 and seen[0][0] > 0.02  # its 0.05 s, less any wait for a CPU
    assert seen[0][1] is None  # the tick was not interrupted to see where: it was the first


def test_a_warning_only_watchdog_never_ends_the_run() -> None:
    dog = Watchdog(5.0, _where, budget=BUDGET, end_when_too_slow=False)
    with dog:
        for _ in range(10):
            dog.timed(_napping_tick)(0.0, 0.02)
    assert dog.slow_ticks == 10


@pytest.mark.skipif(not CodeClock().load_independent, reason="needs Linux's scheduler statistics")
def test_honest_ticks_are_never_slow_on_a_saturated_machine() -> None:
    def honest(now_s: float, dt_s: float) -> None:
        sum(range(20_000))  # about a millisecond of work

    dog = Watchdog(0.5, _where, budget=BUDGET)
    with every_core_busy(extra=1), dog:
        for _ in range(300):
            dog.timed(honest)(0.0, 0.02)
    assert dog.slow_ticks == 0


def _a_heap_whose_full_collection_takes(at_least_s: float) -> list[list[object]]:
    """Objects enough (a notebook's or a test suite's) that one full collection takes
    ``at_least_s`` of this thread's CPU time; bounded, whatever the machine."""
    heap: list[list[object]] = []
    for _ in range(40):
        heap.extend([[None] for _ in range(100_000)])
        began_s = time.thread_time()
        gc.collect()
        if time.thread_time() - began_s >= at_least_s:
            return heap
    pytest.skip("a full collection of 4 million objects stays quick on this machine")


def test_a_full_garbage_collection_in_a_tick_costs_only_the_runs_own_objects() -> None:
    # A full collection starts in whichever tick allocates past Python's threshold. Before,
    # in a test suite's large process, it visited every object the process held, and the
    # collections that fell in honest missions' ticks ended them as too slow.
    heap = _a_heap_whose_full_collection_takes(2 * BUDGET.slow_tick_s)

    def collecting(now_s: float, dt_s: float) -> None:
        gc.collect()  # as Python starts one in whichever tick allocates past its threshold

    dog = Watchdog(5.0, _where, budget=BUDGET)
    with dog:
        for _ in range(12):  # 0.48 s of full collections or more, over the budget's 0.3 s
            dog.timed(collecting)(0.0, 0.02)
    assert dog.slow_ticks == 0, f"slowest {dog.slowest_s:.3f} s"
    del heap


def test_objects_older_than_the_run_are_collected_again_once_the_last_watchdog_ends() -> None:
    outer = Watchdog(5.0, _where)
    with outer:
        with Watchdog(5.0, _where):
            assert gc.get_freeze_count() > 0
        assert gc.get_freeze_count() > 0  # the outer run is still under way
    assert gc.get_freeze_count() == 0


@pytest.mark.skipif(not CodeClock().load_independent, reason="needs Linux's scheduler statistics")
def test_a_quick_tick_reads_the_kernels_cpu_wait_once(monkeypatch: pytest.MonkeyPatch) -> None:
    # Each reading is a system call, in every tick of every run: a tick whose wall time is
    # under the budget's is not slow whatever it waited for a CPU, so only its start is read.
    dog = Watchdog(5.0, _where, budget=BUDGET)
    real_read = dog._clock._queued
    assert real_read is not None
    reads = itertools.count()

    def counted() -> float:
        next(reads)
        return real_read()

    monkeypatch.setattr(dog._clock, "_queued", counted)
    with dog:
        for _ in range(200):
            dog.timed(_quick_tick)(0.0, 0.02)
        dog.timed(_napping_tick)(0.0, 0.02)  # a slow one is read at its end too, and caught
    # once a tick, and again only when the thread lost the CPU while reading
    assert next(reads) < 2 * 201
    assert dog.slow_ticks == 1


def test_time_waiting_on_the_wire_is_not_the_codes_own() -> None:
    clock = CodeClock()
    before = clock.now()
    with wire_wait():
        time.sleep(0.2)
        during = clock.now() - before  # a wait under way is left out too
    assert during < 0.1
    assert clock.now() - before < 0.1


@pytest.mark.parametrize("sampled", [True, False], ids=["after-the-sample", "before-it"])
@pytest.mark.parametrize("preempted_read", range(4))
def test_losing_the_cpu_while_the_clock_is_read_never_changes_the_codes_time(
    monkeypatch: pytest.MonkeyPatch, preempted_read: int, sampled: bool
) -> None:
    # The kernel's CPU wait is read once or more per reading of the clock: whichever read
    # loses the CPU (as a tick begins or as it ends), and whether the kernel's sample of the
    # wait came before or after, the tick's own time is what it did, never 30 ms off.
    wall_s = [100.0]
    queued_s = [0.0]
    reads = itertools.count()

    def read_queued() -> float:
        preempted = next(reads) == preempted_read
        if preempted and not sampled:  # the wait is over before the kernel samples it
            wall_s[0] += 0.03
            queued_s[0] += 0.03
        value = queued_s[0]
        if preempted and sampled:  # the CPU is lost just after the kernel's sample
            wall_s[0] += 0.03
            queued_s[0] += 0.03
        return value

    monkeypatch.setattr(watchdog_module, "_perf_counter", lambda: wall_s[0])
    clock = CodeClock()
    clock._queued = read_queued
    before = clock.now()
    wall_s[0] += 0.001  # the code's own millisecond
    assert clock.now() - before == pytest.approx(0.001)
