"""``regions_in_order`` and ``never_enter``: where the robot went among the world's regions."""

from __future__ import annotations

from dataclasses import replace

import pytest
from grading.expectations.runs import (
    YARD,
    _judge,
    _north,
    _record,
    _same,
    _sim_changed,
    _verdict,
)

from roboscript.grading.expectations import (
    NeverEnter,
    RegionsInOrder,
)
from roboscript.grading.record import RunRecord, Verdict


def test_regions_in_order_lists_when_each_was_reached() -> None:
    verdict = _judge(RegionsInOrder(("a", "b")), _record(_north(12.0)))
    assert verdict.passed
    assert verdict.detail == "reached 'a' at 4.0 s, 'b' at 9.0 s"


def test_regions_out_of_order_fail_by_the_closest_miss() -> None:
    # Drives north past a and b, so b-then-a never happens after b.
    verdict = _judge(RegionsInOrder(("b", "a")), _record(_north(12.0)))
    assert not verdict.passed
    assert verdict.detail.startswith("never reached 'a' after 'b' at 9.0 s")
    assert verdict.margin == "failed by 31.0 cm"  # just after b (y = 910 mm) to a's edge (600)
    assert verdict.first_violation_s is None  # never reaching has no moment


def test_a_fast_robot_cannot_slip_through_a_region_between_samples() -> None:
    # 1 m/s: samples 100 mm apart straddle the 10 mm wide region "dot" at y = 2000 +- 5.
    path = [(round(t * 0.1, 3), 0.0, 1950.0 + t * 100.0, 0.0) for t in range(3)]
    assert _judge(RegionsInOrder(("dot",)), _record(path)).passed


def test_never_enter_gives_the_first_entry_time_and_depth() -> None:
    # East at 100 mm/s along y = 500 from x = 0: on the pit's edge (x = 500) at 5.0 s, inside
    # from the next sample on.
    path = [(round(i * 0.1, 3), i * 10.0, 500.0, 90.0) for i in range(71)]
    verdict = _judge(NeverEnter(("pit",)), _record(path))
    assert not verdict.passed
    assert verdict.first_violation_s == 5.1
    assert verdict.margin == "failed by 10.0 cm"  # deepest: x = 600, the pit's middle
    assert "entered 'pit' at 5.1 s" in verdict.detail


def test_never_enter_passes_by_the_closest_approach() -> None:
    verdict = _judge(NeverEnter(("pit",)), _record(_north(10.0)))
    assert verdict.passed
    assert verdict.margin == "passed by 50.0 cm"  # x = 0 to the pit's west edge at 500


def test_never_enter_names_the_first_region_entered_and_the_deepest_point() -> None:
    # east along y = 500 from x = 0 at 100 mm/s: into the pit (x > 500) after 5 s
    path = [(round(i * 0.1, 3), i * 10.0, 500.0, 90.0) for i in range(61)]
    verdict = _judge(NeverEnter(("pond", "pit")), _record(path, world=YARD))
    assert verdict == Verdict(
        "never_enter",
        False,
        "failed by 10.0 cm",
        5.1,
        "entered 'pit' at 5.1 s; the deepest was 10.0 cm inside 'pit'",
        -100.0,
        "mm",
    )


def test_never_enter_passes_by_the_closest_approach_to_any_of_its_regions() -> None:
    verdict = _judge(NeverEnter(("pit", "pond")), _record(_north(3.0), world=YARD))
    # x = 0 passes 30 cm from the pond's rim (centre 40 cm west, radius 10 cm)
    assert verdict == Verdict(
        "never_enter",
        True,
        "passed by 30.0 cm",
        None,
        "closest approach: 30.0 cm from 'pond'",
        300.0,
        "mm",
    )


def test_a_record_without_a_path_never_moved_and_so_never_entered() -> None:
    record = _sim_changed(_record(_north(1.0), world=YARD), path=())
    assert _judge(NeverEnter(("pit",)), record) == Verdict(
        "never_enter", True, "", None, "the robot never moved"
    )


@pytest.mark.parametrize(
    ("names", "record", "wanted"),
    [
        pytest.param(
            ("a", "b"),
            _record(_north(12.0)),
            _verdict("regions_in_order", True, detail="reached 'a' at 4.0 s, 'b' at 9.0 s"),
            id="both, in order",
        ),
        pytest.param(
            ("b", "a"),
            _record(_north(12.0)),
            _verdict(
                "regions_in_order",
                False,
                "failed by 31.0 cm",
                None,
                "never reached 'a' after 'b' at 9.0 s; the closest it came was 31.0 cm from its"
                " edge",
                -310.0,
                "mm",
            ),
            id="out of order: measured after the last one reached",
        ),
        pytest.param(
            ("a", "b"),
            _record(_north(8.0)),
            _verdict(
                "regions_in_order",
                False,
                "failed by 10.0 cm",
                None,
                "never reached 'b' after 'a' at 4.0 s; the closest it came was 10.0 cm from its"
                " edge",
                -100.0,
                "mm",
            ),
            id="stopped short",
        ),
        pytest.param(
            ("a", "b"),
            _record(_north(4.0)),
            _verdict("regions_in_order", False, detail="never reached 'b' after 'a' at 4.0 s"),
            id="the run ended as it reached the first: nothing to measure",
        ),
        pytest.param(
            ("a", "b"),
            _sim_changed(_record(_north(1.0)), path=()),
            _verdict("regions_in_order", False, detail="never reached 'a'"),
            id="no path",
        ),
    ],
)
def test_regions_in_order_verdicts(
    names: tuple[str, ...], record: RunRecord, wanted: Verdict
) -> None:
    _same(_judge(RegionsInOrder(names), record), wanted)


def test_regions_need_a_world() -> None:
    record = replace(_record(_north(1.0)), world=None)
    with pytest.raises(ValueError, match=r"^this record has no world to find its regions in$"):
        _judge(RegionsInOrder(("a",)), record)
