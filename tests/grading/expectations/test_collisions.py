"""``no_collisions``: the body never touches a wall."""

from __future__ import annotations

from dataclasses import replace

from grading.expectations.runs import YARD, _judge, _north, _record

from roboscript.grading.expectations import NoCollisions
from roboscript.grading.record import Collision, Verdict


def test_no_collisions_fails_at_the_first_collision() -> None:
    hits = (Collision(2.5, 200.0, 250.0, "right"), Collision(4.0, 200.0, 400.0, "right"))
    verdict = _judge(NoCollisions(), _record(_north(5.0), collisions=hits))
    assert not verdict.passed
    assert verdict.first_violation_s == 2.5
    assert verdict.margin == "failed by 2 collisions"
    assert "the first at 2.5 s on the right bumper" in verdict.detail


def test_no_collisions_passes_by_the_clearance_to_the_nearest_wall() -> None:
    # Centre at x = 0, walls at +-300, body radius 100: 20 cm to spare.
    verdict = _judge(NoCollisions(), _record(_north(5.0)))
    assert verdict.passed
    assert verdict.margin == "passed by 20.0 cm"


def test_no_collisions_names_the_first_hit_and_counts_them_all() -> None:
    hits = (Collision(2.5, 200.0, 250.0, "left"), Collision(4.0, 210.0, 400.0, "right"))
    record = replace(_record(_north(5.0)), collisions=hits)
    assert _judge(NoCollisions(), record) == Verdict(
        "no_collisions",
        False,
        "failed by 2 collisions",
        2.5,
        "2 collisions; the first at 2.5 s on the left bumper, at (200, 250) mm",
        -2.0,
        "collisions",
    )


def test_no_collisions_passes_by_the_closest_the_body_came_to_a_wall() -> None:
    # the body (radius 100 mm) drifting east from x = 0 to x = 150, the wall at x = 300
    path = [(round(i * 0.1, 3), i * 5.0, i * 10.0, 0.0) for i in range(31)]
    assert _judge(NoCollisions(), _record(path, world=YARD)) == Verdict(
        "no_collisions",
        True,
        "passed by 5.0 cm",
        None,
        "no collisions; the closest the body came to a wall was 5.0 cm",
        50.0,
        "mm",
    )


def test_no_collisions_without_walls_passes_with_nothing_to_measure() -> None:
    record = replace(_record(_north(3.0)), world=None)
    assert _judge(NoCollisions(), record) == Verdict(
        "no_collisions", True, "", None, "no collisions"
    )
