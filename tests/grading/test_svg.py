"""The picture of a run: each expectation draws its own target on it."""

from __future__ import annotations

import re

from grading.expectations.runs import ROOM, _north, _record

from roboscript.grading.expectations import (
    Expectation,
    FinalPose,
    RunTargets,
    Tones,
)
from roboscript.grading.svg import trajectory_svg

TARGET = "<title>target: the robot must end inside this circle</title>"


def _circles(svg: str) -> list[tuple[float, float, float]]:
    found = re.findall(r'<circle cx="([\d.]+)" cy="([\d.]+)" r="([\d.]+)"[^>]*>' + TARGET, svg)
    return [(float(x), float(y), float(r)) for x, y, r in found]


def test_a_final_pose_target_is_drawn_where_the_run_had_to_end() -> None:
    record = _record(_north(5.0))  # from (0, 0) to (0, 50 cm)
    plain = trajectory_svg(ROOM, record)
    assert TARGET not in plain
    assert trajectory_svg(ROOM, record, expectations=[Expectation(Tones(count=1))]) == plain
    near = trajectory_svg(ROOM, record, expectations=[Expectation(FinalPose(0.0, 500.0, 80.0))])
    far = trajectory_svg(ROOM, record, expectations=[Expectation(FinalPose(0.0, 0.0, 160.0))])
    [(x_near, y_near, r_near)] = _circles(near)
    [(x_far, y_far, r_far)] = _circles(far)
    assert x_near == x_far and y_near < y_far  # north is up
    assert r_far == 2 * r_near


def test_a_run_with_a_target_of_its_own_is_drawn_with_it() -> None:
    record = _record(_north(5.0))
    key = (record.world_name, record.seed, record.start_pose)
    own = RunTargets(FinalPose(0.0, 500.0, 80.0), ((key, FinalPose(0.0, 500.0, 40.0)),))
    expectation = Expectation(FinalPose(0.0, 500.0, 80.0), targets=own)
    default = trajectory_svg(ROOM, record, expectations=[Expectation(FinalPose(0.0, 500.0, 80.0))])
    [(_, _, r_default)] = _circles(default)
    [(_, _, r_own)] = _circles(trajectory_svg(ROOM, record, expectations=[expectation]))
    assert r_own == r_default / 2
