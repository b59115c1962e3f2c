"""``wall_ahead_at_end``: the gap to the wall straight ahead at the end."""

from __future__ import annotations

from dataclasses import replace

import pytest
from grading.expectations.runs import WANTED, _judge, _same, _stopped, _verdict

from roboscript.grading.expectations import WallAhead
from roboscript.grading.record import RunRecord, Verdict


def test_wall_ahead_is_measured_from_the_front_of_the_body() -> None:
    # Facing east at x = 0, the wall at x = 300: the centre is 30 cm away, the body's front
    # (radius 10 cm) 20 cm.
    record = _stopped(0.0, 500.0, 90.0)
    verdict = _judge(WallAhead(200.0, 30.0), record)
    assert verdict.passed
    assert verdict.margin == "passed by 3.0 cm"
    assert verdict.detail.startswith("stopped 20.0 cm from the wall ahead")
    centre = _judge(WallAhead(300.0, 30.0), record)
    assert not centre.passed
    assert centre.margin == "failed by 7.0 cm"
    assert "(too close)" in centre.detail
    assert centre.first_violation_s == 5.0


def test_wall_ahead_follows_the_heading() -> None:
    # At x = 100: east, the wall is 20 cm from the centre (10 cm from the front); west, 40 cm
    # (30 cm); at 45° the ray meets x = 300 after 200 / sin 45° = 282.8 mm.
    assert _judge(WallAhead(100.0, 5.0), _stopped(100.0, 500.0, 90.0)).passed
    assert _judge(WallAhead(300.0, 5.0), _stopped(100.0, 500.0, 270.0)).passed
    slanted = _judge(WallAhead(182.8, 1.0), _stopped(100.0, 500.0, 45.0))
    assert slanted.margin_value == pytest.approx(1.0, abs=0.05)
    north = _judge(WallAhead(100.0, 5.0), _stopped(100.0, 500.0, 0.0))
    assert not north.passed
    assert north.detail.startswith("no wall straight ahead when the robot stopped (facing 0°)")


@pytest.mark.parametrize(
    ("rule", "record", "wanted"),
    [
        pytest.param(
            WallAhead(200.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                True,
                "passed by 3.0 cm",
                None,
                f"stopped 20.0 cm from the wall ahead, {WANTED} 20.0 cm ± 3.0 cm",
                30.0,
                "mm",
                1.0,
            ),
            id="right on the distance",
        ),
        pytest.param(
            WallAhead(300.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "failed by 7.0 cm",
                5.0,
                f"stopped 20.0 cm from the wall ahead (too close), {WANTED} 30.0 cm ± 3.0 cm",
                -70.0,
                "mm",
                -70.0 / 30.0,
            ),
            id="too close",
        ),
        pytest.param(
            WallAhead(100.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "failed by 7.0 cm",
                5.0,
                f"stopped 20.0 cm from the wall ahead (too far), {WANTED} 10.0 cm ± 3.0 cm",
                -70.0,
                "mm",
                -70.0 / 30.0,
            ),
            id="too far",
        ),
        pytest.param(
            WallAhead(170.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                True,
                "passed by 0.0 cm",
                None,
                f"stopped 20.0 cm from the wall ahead, {WANTED} 17.0 cm ± 3.0 cm",
                0.0,
                "mm",
                0.0,
            ),
            id="the edge of the tolerance passes",
        ),
        pytest.param(
            WallAhead(199.5, 0.2),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "failed by 0.0 cm",
                5.0,
                f"stopped 20.0 cm from the wall ahead (too far), {WANTED} 19.9 cm ± 0.0 cm",
                pytest.approx(-0.3),  # type: ignore[arg-type]
                "mm",
                -1.5,
            ),
            id="half a millimetre too far is too far",
        ),
        pytest.param(
            WallAhead(200.0, 30.0),
            replace(_stopped(0.0, 500.0, 90.0), world=None),
            _verdict(
                "wall_ahead_at_end",
                False,
                "",
                5.0,
                "no wall straight ahead when the robot stopped (facing 90°);"
                " wanted 20.0 cm ± 3.0 cm",
            ),
            id="a record without a world has no wall",
        ),
        pytest.param(
            WallAhead(200.0, 30.0),
            _stopped(0.0, 500.0, 0.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "",
                5.0,
                "no wall straight ahead when the robot stopped (facing 0°);"
                " wanted 20.0 cm ± 3.0 cm",
            ),
            id="facing down the corridor",
        ),
    ],
)
def test_wall_ahead_verdicts(rule: WallAhead, record: RunRecord, wanted: Verdict) -> None:
    _same(_judge(rule, record), wanted)
