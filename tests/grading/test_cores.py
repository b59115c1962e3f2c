"""Each grading worker keeps its runs on one core: the world and the mission hand over there."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from roboscript.grading.batch import find_specs, find_submissions, grade_class
from roboscript.grading.cores import (
    SAMPLE_S,
    CoreShare,
    idle_ticks_by_core,
    keep_on_core,
    usable_cores,
)

STAT = """\
cpu  {total}
cpu0 100 0 50 {idle0} 5 0 0 0 0 0
cpu1 100 0 50 {idle1} 5 0 0 0 0 0
cpu2 100 0 50 {idle2} 5 0 0 0 0 0
intr 12345
"""


def _stat(idle0: int, idle1: int, idle2: int) -> str:
    return STAT.format(total="1 2 3 4", idle0=idle0, idle1=idle1, idle2=idle2)


def test_idle_time_is_read_per_core_from_proc_stat_with_io_wait() -> None:
    assert idle_ticks_by_core(_stat(1000, 2000, 3000)) == {0: 1005, 1: 2005, 2: 3005}
    assert idle_ticks_by_core("cpu 1 2\ncpuX 1\ncpu3 1 2\n") == {}, "malformed lines are skipped"


class _Clock:
    """A clock that moves only when slept on, or by hand."""

    def __init__(self) -> None:
        self.now_s = 0.0
        self.slept_s: list[float] = []

    def __call__(self) -> float:
        return self.now_s

    def sleep(self, seconds: float) -> None:
        self.slept_s.append(seconds)
        self.now_s += seconds


def _share(cores: list[int], read_stat: object, clock: _Clock | None = None) -> CoreShare:
    clock = clock or _Clock()
    return CoreShare(cores, read_stat=read_stat, clock=clock, sleep=clock.sleep)  # type: ignore[arg-type]


def test_workers_spread_over_the_cores_before_any_core_is_shared() -> None:
    share = _share([0, 1, 2], lambda: _stat(0, 0, 0))
    taken = [share.take() for _ in range(3)]
    assert sorted(taken) == [0, 1, 2]  # type: ignore[type-var]
    fourth = share.take()
    assert fourth is not None and share.workers_on(fourth) == 2
    share.give(taken[1])
    assert share.take() == taken[1], "a core given back is the least shared again"


def test_the_first_choice_looks_at_the_cores_for_a_moment_and_takes_the_idle_one() -> None:
    clock = _Clock()
    readings = iter([_stat(0, 0, 0), _stat(0, 3, 1)])
    share = _share([0, 1, 2], lambda: next(readings), clock)
    assert share.take() == 1, "core 1 idled 3 ticks, core 0 none (another program's), core 2 one"
    assert clock.slept_s == [SAMPLE_S], "the first choice waited to compare the cores"


def test_choices_made_at_once_keep_the_last_comparison_and_avoid_busy_cores() -> None:
    clock = _Clock()
    readings = iter([_stat(0, 0, 0), _stat(0, 3, 2), _stat(0, 6, 4)])
    share = _share([0, 1, 2], lambda: next(readings), clock)
    assert [share.take(), share.take()] == [1, 2], "core 0 is busy with another program"
    assert clock.slept_s == [SAMPLE_S], "only the first choice waits"
    clock.now_s += 10.0
    share.give(1)
    assert share.take() == 1, "a core given back is the least shared again"


def test_with_one_core_there_is_nothing_to_choose() -> None:
    clock = _Clock()
    share = _share([3], lambda: "", clock)
    assert share.take() is None
    assert clock.slept_s == [], "nor anything to wait for"
    share.give(None)  # nothing to give back either


def test_keeping_a_process_on_a_core_outside_its_set_is_refused_quietly() -> None:
    assert keep_on_core(None) is False
    if not usable_cores():
        pytest.skip("this platform does not tell which cores a process may use")
    assert keep_on_core(max(usable_cores()) + 4096) is False


PRINTS_ITS_CORES = """\
import os
from roboscript import Mission, Wait, state

print("cores", sorted(os.sched_getaffinity(0)))


class Idle(Mission):
    go = state(Wait(duration_s=0.2), initial=True, on_done="end")
    end = state(final="success")
"""


def test_two_students_graded_at_once_run_each_on_a_core_of_its_own(tmp_path: Path) -> None:
    cores = usable_cores()
    if len(cores) < 2 or not hasattr(os, "sched_getaffinity"):
        pytest.skip("needs a platform that tells cores apart, with two cores to use")
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: idle\nexpect:\n  - outcome: success\n", encoding="utf-8")
    folder = tmp_path / "class"
    folder.mkdir()
    for name in ("ann", "bob"):
        (folder / f"{name}.py").write_text(PRINTS_ITS_CORES, encoding="utf-8")
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(folder)]).submissions, jobs=2
    )
    assert report.passed
    seen = [re.findall(r"cores \[([\d, ]+)\]", result.debug) for result in report.results]
    assert all(len(found) == 1 for found in seen), seen
    kept = [[int(core) for core in found[0].split(",")] for found in seen]
    assert all(len(one) == 1 and one[0] in cores for one in kept), kept
    assert kept[0] != kept[1], "the two workers, graded at once, are on different cores"
