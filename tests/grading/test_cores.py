"""Each grading worker keeps its runs on one core: the world and the mission hand over there."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from roboscript.grading.batch import find_specs, find_submissions, grade_class
from roboscript.grading.cores import CoreShare, idle_ticks_by_core, keep_on_core, usable_cores

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


def test_workers_spread_over_the_cores_before_any_core_is_shared() -> None:
    share = CoreShare([0, 1, 2], read_stat=lambda: _stat(0, 0, 0))
    taken = [share.take() for _ in range(3)]
    assert sorted(taken) == [0, 1, 2]  # type: ignore[type-var]
    fourth = share.take()
    assert fourth is not None and share.workers_on(fourth) == 2
    share.give(taken[1])
    assert share.take() == taken[1], "a core given back is the least shared again"


def test_a_core_idle_since_the_last_choice_is_taken_before_a_busy_one() -> None:
    readings = iter([_stat(0, 0, 0), _stat(10, 500, 20), _stat(10, 500, 900)])
    share = CoreShare([0, 1, 2], read_stat=lambda: next(readings))
    assert share.take() == 1, "core 1 idled 500 ticks, the others 10 and 20"
    assert share.take() == 2, "then core 2 idled the most, and core 1 is taken"


def test_with_one_core_there_is_nothing_to_choose() -> None:
    share = CoreShare([3], read_stat=lambda: "")
    assert share.take() is None
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
