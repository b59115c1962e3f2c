"""drive, rotate, follow_wall and follow_line on an ideal drive base, tick by tick.

The simulator tests (test_motion.py, test_following.py) check accuracy end to end; these
check the rules students rely on exactly: where a move is measured from, which way the wheels
turn, the crawl before the stop, the stall watch's 2 mm in a second, heading hold with an IMU,
``until`` and the lost-wall / lost-line delays.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest

from roboscript import capabilities as cap
from roboscript.actions import Action, ActionContext, Drive, Result, Rotate
from roboscript.actions.following import FollowLine, FollowWall
from roboscript.actions.sensing import heading_deg
from roboscript.angles import turned_deg
from roboscript.control import wheel_speeds

TRACK_MM = 150.0
DT_S = 0.02


class IdealBase:
    """Wheels that go exactly as fast as told (or at most ``creep_mm_s``, a heavy load)."""

    track_mm = TRACK_MM
    max_speed_mm_s = 300.0

    def __init__(
        self,
        left_mm: float = 0.0,
        right_mm: float = 0.0,
        *,
        creep_mm_s: float | None = None,
        odometry_is_estimated: bool = False,
    ) -> None:
        self.distances = [left_mm, right_mm]
        self.creep_mm_s = creep_mm_s
        self.odometry_is_estimated = odometry_is_estimated
        self.speeds = (0.0, 0.0)
        self.commands: list[tuple[float, float]] = []
        self.stops = 0

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        self.speeds = (left_mm_s, right_mm_s)
        self.commands.append(self.speeds)

    def stop(self) -> None:
        self.speeds = (0.0, 0.0)
        self.stops += 1

    def wheel_distances_mm(self) -> tuple[float, float]:
        return self.distances[0], self.distances[1]

    def roll(self, dt_s: float) -> None:
        for wheel, speed in enumerate(self.speeds):
            if self.creep_mm_s is not None:
                speed = math.copysign(min(abs(speed), self.creep_mm_s), speed)
            self.distances[wheel] += speed * dt_s

    def set_turned(self, angle_deg: float) -> None:
        """Put the wheels where a turn in place of ``angle_deg`` leaves them."""
        arc = math.radians(angle_deg) * TRACK_MM / 2.0
        self.distances = [arc, -arc]


def rate_deg_s(command: tuple[float, float]) -> float:
    """The clockwise turn rate a (left, right) wheel speed command asks for."""
    return math.degrees((command[0] - command[1]) / TRACK_MM)


class Imu:
    """A heading sensor: a fixed reading, or following the wheels with some slip."""

    def __init__(
        self, reading: float | None = 0.0, base: IdealBase | None = None, scale: float = 1.0
    ) -> None:
        self.reading = reading
        self.base = base
        self.scale = scale

    def heading_deg(self) -> float | None:
        if self.base is None or self.reading is None:
            return self.reading
        left, right = self.base.wheel_distances_mm()
        return (self.reading + self.scale * turned_deg(left, right, TRACK_MM)) % 360.0


class SideRange:
    side = "right"
    max_range_mm = 1500.0

    def __init__(self, gap: Callable[[float], float | None]) -> None:
        self.gap = gap
        self.now_s = 0.0

    def distance_mm(self) -> float | None:
        return self.gap(self.now_s)


class LineSensors:
    names = ("left", "middle", "right")
    dark_threshold = 500.0

    def __init__(self, readings: Callable[[float], tuple[float, ...] | None]) -> None:
        self.readings = readings
        self.now_s = 0.0

    def values(self) -> tuple[float, ...] | None:
        return self.readings(self.now_s)


def run(
    action: Action,
    capabilities: dict[str, Any],
    *,
    start_s: float = 0.0,
    limit_s: float = 20.0,
    env: Any = None,
    gains: dict[str, tuple[float, float, float]] | None = None,
    each_tick: Callable[[float], None] | None = None,
) -> tuple[Result | None, float]:
    """Start the action at ``start_s``, tick it until it ends (then stop it, as leaving the
    state does); its result and how long it ran."""
    ctx = ActionContext(capabilities, env=env, gains=gains)
    ctx.now_s, ctx.dt_s = start_s, DT_S
    base: IdealBase = capabilities[cap.DRIVE_BASE]
    action.start(ctx)
    for tick in range(1, round(limit_s / DT_S) + 1):
        base.roll(DT_S)
        ctx.now_s = start_s + tick * DT_S
        for device in capabilities.values():
            if hasattr(device, "now_s"):
                device.now_s = ctx.now_s - start_s
        if each_tick is not None:
            each_tick(ctx.now_s - start_s)
        result = action.update(ctx)
        if result is not None:
            action.stop(ctx)
            return result, tick * DT_S
    return None, limit_s


def travelled(base: IdealBase, origin: tuple[float, float]) -> tuple[float, float]:
    return base.distances[0] - origin[0], base.distances[1] - origin[1]


# --- drive -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("distance", "origin"), [(300.0, (1000.0, 1200.0)), (-200.0, (500.0, -80.0))]
)
def test_drive_measures_from_where_the_wheels_are_when_it_starts(
    distance: float, origin: tuple[float, float]
) -> None:
    # the second drive of a mission starts with odometers far from zero
    base = IdealBase(*origin)
    result, _ = run(Drive(distance_mm=distance), {cap.DRIVE_BASE: base})
    assert result == Result.done()
    left, right = travelled(base, origin)
    assert left == pytest.approx(distance, abs=2.5)
    assert right == pytest.approx(distance, abs=2.5)
    assert base.speeds == (0.0, 0.0)


@pytest.mark.parametrize(
    ("drive", "first"),
    [
        (Drive(distance_mm=200), (150.0, 150.0)),
        (Drive(distance_mm=-200), (-150.0, -150.0)),
        (Drive(duration_s=1.0), (150.0, 150.0)),
        (Drive(distance_mm=200, speed_mm_s=1000), (300.0, 300.0)),
    ],
    ids=["forward", "backward", "for-a-time", "capped"],
)
def test_drive_sets_off_the_right_way_at_its_cruise_speed(
    drive: Drive, first: tuple[float, float]
) -> None:
    base = IdealBase()
    drive.start(ActionContext({cap.DRIVE_BASE: base}))
    assert base.commands == [first]


def test_drive_slows_to_a_crawl_for_the_last_stretch_and_stops() -> None:
    base = IdealBase()
    result, _ = run(Drive(distance_mm=300, speed_mm_s=150), {cap.DRIVE_BASE: base})
    assert result == Result.done()
    crawl = [c for c in base.commands if c == (40.0, 40.0)]
    # the slow zone is 12 % of the cruise speed's worth of mm (18 mm), at 0.8 mm a tick
    assert 15 <= len(crawl) <= 30
    assert base.commands[-1] == (40.0, 40.0)
    assert base.commands[-len(crawl) - 1] == (150.0, 150.0)


def test_drive_reports_its_progress() -> None:
    base = IdealBase()
    drive = Drive(distance_mm=500)
    run(drive, {cap.DRIVE_BASE: base}, limit_s=1.0)
    assert drive.feedback == "driving 150/500 mm"
    timed = Drive(duration_s=3.0)
    run(timed, {cap.DRIVE_BASE: IdealBase()}, start_s=10.0, limit_s=1.0)
    assert timed.feedback == "driving 1.0/3.0 s"


def test_drive_validates_its_parameters_with_plain_messages() -> None:
    with pytest.raises(ValueError) as missing:
        Drive()
    assert str(missing.value) == (  # as a traceback of `python mission.py` shows it
        "drive needs a distance or a duration (write Drive(distance_mm=500) or Drive(duration_s=2))"
    )
    with pytest.raises(ValueError, match=r"^drive speed must be positive \(use a negative"):
        Drive(distance_mm=100, speed_mm_s=0)
    assert Drive(distance_mm=100, speed_mm_s=0.5).speed_mm_s == 0.5  # slow is allowed
    assert Drive(distance_mm=100).speed_mm_s == 150.0


@pytest.mark.parametrize(
    "action",
    [
        lambda: Drive(duration_s=3.0),
        lambda: Rotate(angle_deg=3600.0),
        lambda: FollowWall(duration_s=3.0),
    ],
    ids=["drive", "rotate", "follow_wall"],
)
def test_wheels_creeping_1_mm_s_are_stalled_after_a_second(action: Callable[[], Action]) -> None:
    base = IdealBase(creep_mm_s=1.0)
    caps: dict[str, Any] = {cap.DRIVE_BASE: base, cap.SIDE_RANGE: SideRange(lambda t: 200.0)}
    result, ended_s = run(action(), caps, start_s=7.0, limit_s=3.0)
    assert result == Result.failed("stalled")
    assert ended_s == pytest.approx(1.0, abs=DT_S + 1e-9)
    assert base.speeds == (0.0, 0.0)


@pytest.mark.parametrize(
    "action",
    [
        lambda: Drive(duration_s=3.0),
        lambda: Rotate(angle_deg=3600.0),
        lambda: FollowWall(duration_s=3.0),
    ],
    ids=["drive", "rotate", "follow_wall"],
)
def test_wheels_creeping_2_5_mm_s_make_progress(action: Callable[[], Action]) -> None:
    # 2.5 mm in the first second is more than the 2 mm that counts as moving
    base = IdealBase(creep_mm_s=2.5)
    caps: dict[str, Any] = {cap.DRIVE_BASE: base, cap.SIDE_RANGE: SideRange(lambda t: 200.0)}
    result, _ = run(action(), caps, start_s=7.0, limit_s=2.9)
    assert result is None


def test_drive_with_an_imu_steers_back_to_its_starting_heading() -> None:
    base = IdealBase()
    imu = Imu(90.0)
    ctx = ActionContext({cap.DRIVE_BASE: base, cap.HEADING: imu})
    ctx.dt_s = DT_S
    drive = Drive(distance_mm=1000)
    drive.start(ctx)
    imu.reading = 100.0  # knocked 10 degrees to the right: turn left, kp 2 deg/s per degree
    drive.update(ctx)
    assert base.commands[-1] == pytest.approx(wheel_speeds(150.0, -20.0, TRACK_MM))
    imu.reading = 101.0  # still turning right: the damping adds 0.05 * 50 deg/s
    drive.update(ctx)
    assert base.commands[-1] == pytest.approx(wheel_speeds(150.0, -24.5, TRACK_MM))
    imu.reading = 150.0  # far off: the correction is limited to 30 deg/s
    drive.update(ctx)
    assert base.commands[-1] == pytest.approx(wheel_speeds(150.0, -30.0, TRACK_MM))


def test_drive_uses_the_profiles_heading_gains() -> None:
    base = IdealBase()
    imu = Imu(0.0)
    ctx = ActionContext({cap.DRIVE_BASE: base, cap.HEADING: imu}, gains={"heading": (1.0, 0, 0)})
    ctx.dt_s = DT_S
    drive = Drive(distance_mm=1000)
    drive.start(ctx)
    imu.reading = 350.0  # 10 degrees left, across north: turn right at 10 deg/s
    drive.update(ctx)
    assert base.commands[-1] == pytest.approx(wheel_speeds(150.0, 10.0, TRACK_MM))


def test_drive_goes_straight_while_the_imu_has_no_reading() -> None:
    base = IdealBase()
    imu = Imu(0.0)
    ctx = ActionContext({cap.DRIVE_BASE: base, cap.HEADING: imu})
    ctx.dt_s = DT_S
    drive = Drive(distance_mm=1000)
    drive.start(ctx)
    imu.reading = None
    drive.update(ctx)
    assert base.commands[-1] == (150.0, 150.0)
    no_imu = Drive(distance_mm=1000)
    still = Imu(None)
    ctx = ActionContext({cap.DRIVE_BASE: base, cap.HEADING: still})
    no_imu.start(ctx)
    still.reading = 30.0  # a first reading later does not start a hold from nowhere
    no_imu.update(ctx)
    assert base.commands[-1] == (150.0, 150.0)


# --- rotate ------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", [90.0, -90.0])
def test_rotate_measures_from_where_the_wheels_are_when_it_starts(angle: float) -> None:
    origin = (1000.0, 1200.0)
    base = IdealBase(*origin)
    result, _ = run(Rotate(angle_deg=angle), {cap.DRIVE_BASE: base})
    assert result == Result.done()
    assert turned_deg(*travelled(base, origin), TRACK_MM) == pytest.approx(angle, abs=1.0)
    assert base.speeds == (0.0, 0.0)


def test_rotate_with_an_imu_turns_by_the_imu_across_north_and_beyond_180() -> None:
    # the wheels slip: the robot turns only 0.9 of what the encoders say
    base = IdealBase()
    imu = Imu(350.0, base, scale=0.9)
    result, _ = run(Rotate(angle_deg=270.0), {cap.DRIVE_BASE: base, cap.HEADING: imu})
    assert result == Result.done()
    by_imu = 0.9 * turned_deg(*base.wheel_distances_mm(), TRACK_MM)
    assert 269.0 <= by_imu <= 270.5


def test_rotate_turns_at_its_rate_then_crawls_for_the_last_degrees() -> None:
    base = IdealBase()
    result, _ = run(Rotate(angle_deg=90.0), {cap.DRIVE_BASE: base})
    assert result == Result.done()
    rates = [round(rate_deg_s(c), 6) for c in base.commands]
    assert rates[0] == 90.0
    assert rates[-1] == 20.0
    # the slow zone is 12 % of the rate's worth of degrees (10.8), at 0.4 degrees a tick
    assert 20 <= rates.count(20.0) <= 30
    assert all(c[0] == -c[1] for c in base.commands)  # in place


@pytest.mark.parametrize(("turned", "rate"), [(83.5, 30.0), (84.5, 20.0)])
def test_a_slow_rotate_crawls_for_the_last_6_degrees(turned: float, rate: float) -> None:
    base = IdealBase()
    ctx = ActionContext({cap.DRIVE_BASE: base})
    ctx.dt_s = DT_S
    rotate = Rotate(angle_deg=90.0, turn_rate_deg_s=30.0)
    rotate.start(ctx)
    base.set_turned(turned)
    assert rotate.update(ctx) is None
    assert rate_deg_s(base.commands[-1]) == pytest.approx(rate)
    assert rotate.feedback == f"turning {turned:.0f}/90 deg"


def test_rotate_is_limited_by_the_wheels_top_speed() -> None:
    base = IdealBase()
    ctx = ActionContext({cap.DRIVE_BASE: base})
    rotate = Rotate(angle_deg=180.0, turn_rate_deg_s=1000.0)
    rotate.start(ctx)
    rotate.update(ctx)
    assert base.commands[-1] == pytest.approx((300.0, -300.0))


@pytest.mark.parametrize(
    ("angle", "turned", "rate"),
    [(90.0, 92.0, -8.0), (90.0, 91.2, -5.0), (-90.0, -92.0, 8.0), (-90.0, -91.2, 5.0)],
)
def test_rotate_turns_an_overshoot_back_slower_the_closer_it_is(
    angle: float, turned: float, rate: float
) -> None:
    base = IdealBase()
    ctx = ActionContext({cap.DRIVE_BASE: base})
    ctx.dt_s = DT_S
    rotate = Rotate(angle_deg=angle)
    rotate.start(ctx)
    base.set_turned(turned)  # coasted past (or short of) the target
    assert rotate.update(ctx) is None
    assert base.commands[-1] == pytest.approx(wheel_speeds(0.0, rate, TRACK_MM))


def test_rotate_validates_its_turn_rate_with_a_plain_message() -> None:
    with pytest.raises(ValueError, match=r"^turn rate must be positive \(use a negative angle"):
        Rotate(angle_deg=90, turn_rate_deg_s=0)
    assert Rotate(angle_deg=90, turn_rate_deg_s=0.5).turn_rate_deg_s == 0.5
    assert Rotate(angle_deg=90).turn_rate_deg_s == 90.0


# --- heading for actions -----------------------------------------------------------------


def test_heading_is_the_imus_when_there_is_one_else_odometrys() -> None:
    base = IdealBase()
    base.set_turned(30.0)
    assert heading_deg(ActionContext({cap.DRIVE_BASE: base})) == pytest.approx(30.0)
    with_imu = ActionContext({cap.DRIVE_BASE: base, cap.HEADING: Imu(90.0)})
    assert heading_deg(with_imu) == 90.0
    no_reading = ActionContext({cap.DRIVE_BASE: base, cap.HEADING: Imu(None)})
    assert heading_deg(no_reading) == pytest.approx(30.0)


# --- follow_wall and follow_line ---------------------------------------------------------


def _stop_flag() -> tuple[dict[str, bool], Callable[[dict[str, bool]], bool]]:
    env = {"stop": False}
    return env, lambda e: e["stop"]


@pytest.mark.parametrize("follow", ["wall", "line"])
def test_following_ends_done_when_its_until_condition_holds(follow: str) -> None:
    env, until = _stop_flag()
    base = IdealBase()
    caps: dict[str, Any] = {
        cap.DRIVE_BASE: base,
        cap.SIDE_RANGE: SideRange(lambda t: 200.0),
        cap.LINE: LineSensors(lambda t: (0.0, 900.0, 0.0)),
    }
    action = FollowWall(until=until) if follow == "wall" else FollowLine(until=until)

    def tick(t: float) -> None:
        env["stop"] = t >= 1.5

    result, ended_s = run(action, caps, env=env, limit_s=5.0, each_tick=tick)
    assert result == Result.done()
    assert ended_s == pytest.approx(1.5)
    assert base.speeds == (0.0, 0.0)


def test_follow_wall_fails_lost_wall_a_second_after_the_last_echo() -> None:
    base = IdealBase()
    sensor = SideRange(lambda t: 200.0 if t < 2.0 else None)
    result, ended_s = run(
        FollowWall(duration_s=10.0), {cap.DRIVE_BASE: base, cap.SIDE_RANGE: sensor}, start_s=30.0
    )
    assert result == Result.failed("lost wall")
    assert ended_s == pytest.approx(2.98, abs=DT_S + 1e-9)
    assert base.speeds == (0.0, 0.0)


def test_follow_wall_without_any_echo_fails_a_second_after_it_starts() -> None:
    base = IdealBase()
    sensor = SideRange(lambda t: None)
    result, ended_s = run(
        FollowWall(duration_s=10.0), {cap.DRIVE_BASE: base, cap.SIDE_RANGE: sensor}, start_s=30.0
    )
    assert result == Result.failed("lost wall")
    assert ended_s == pytest.approx(1.0, abs=DT_S + 1e-9)


def test_follow_wall_defaults_keep_20_cm_at_12_cm_s_on_the_right() -> None:
    action = FollowWall()
    assert (action.side, action.distance_mm, action.speed_mm_s) == ("right", 200.0, 120.0)
    base = IdealBase()
    run(action, {cap.DRIVE_BASE: base, cap.SIDE_RANGE: SideRange(lambda t: 200.0)}, limit_s=0.1)
    assert base.commands[-1] == (120.0, 120.0)
    assert action.feedback == "wall at 20 cm"


def test_follow_wall_steers_away_from_a_close_wall_with_the_profiles_gains() -> None:
    base = IdealBase()
    caps: dict[str, Any] = {cap.DRIVE_BASE: base, cap.SIDE_RANGE: SideRange(lambda t: 150.0)}
    run(FollowWall(duration_s=1.0), caps, limit_s=DT_S)
    left, right = base.commands[-1]
    assert left < right  # the wall is on the right: turn left
    base = IdealBase()
    caps[cap.DRIVE_BASE] = base
    run(FollowWall(duration_s=1.0), caps, limit_s=DT_S, gains={"wall": (0.0, 0.0, 0.0)})
    assert base.commands[-1] == (120.0, 120.0)  # a profile with no gain does not steer


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ({"side": "up"}, "side must be 'left' or 'right'"),
        (
            {"distance_mm": 0},
            "follow_wall needs a positive distance to keep (write FollowWall(distance_mm=200))",
        ),
        (
            {"speed_mm_s": 0},
            "follow_wall needs a positive speed (write FollowWall(speed_mm_s=120))",
        ),
    ],
)
def test_follow_wall_validates_its_parameters(value: dict[str, Any], message: str) -> None:
    with pytest.raises(ValueError) as refused:
        FollowWall(**value)
    assert str(refused.value) == message


def test_follow_wall_accepts_a_small_gap_and_a_slow_speed() -> None:
    action = FollowWall(distance_mm=0.5, speed_mm_s=0.5)
    assert (action.distance_mm, action.speed_mm_s) == (0.5, 0.5)


def test_follow_line_slows_in_bends() -> None:
    position = {"value": (0.0, 900.0, 0.0)}
    base = IdealBase()
    caps: dict[str, Any] = {
        cap.DRIVE_BASE: base,
        cap.LINE: LineSensors(lambda t: position["value"]),
    }
    ctx = ActionContext(caps)
    ctx.dt_s = DT_S
    action = FollowLine(duration_s=10.0)
    action.start(ctx)
    for readings, speed in [
        ((0.0, 900.0, 0.0), 100.0),  # on the line: full speed
        ((0.0, 900.0, 900.0), 70.0),  # half way out: 1 - 0.6 * 0.5
        ((0.0, 0.0, 900.0), 40.0),  # at the edge: 40 %
    ]:
        position["value"] = readings
        action.update(ctx)
        assert sum(base.commands[-1]) / 2.0 == pytest.approx(speed)
    assert action.feedback == "line at +1.00"


@pytest.mark.parametrize(
    ("last_seen", "turn"),
    [((0.0, 0.0, 900.0), 60.0), ((900.0, 0.0, 0.0), -60.0), ((0.0, 900.0, 0.0), 0.0)],
    ids=["right", "left", "ahead"],
)
def test_follow_line_searches_where_it_last_saw_the_line_then_fails(
    last_seen: tuple[float, ...], turn: float
) -> None:
    base = IdealBase()
    sensors = LineSensors(lambda t: last_seen if t < 1.0 else (0.0, 0.0, 0.0))
    ctx_caps: dict[str, Any] = {cap.DRIVE_BASE: base, cap.LINE: sensors}
    searching: list[tuple[float, float]] = []

    def tick(t: float) -> None:
        if base.commands and t > 1.0:
            searching.append(base.commands[-1])

    result, ended_s = run(FollowLine(duration_s=10.0), ctx_caps, start_s=40.0, each_tick=tick)
    assert result == Result.failed("lost line")
    assert ended_s == pytest.approx(1.48, abs=DT_S + 1e-9)
    # searching: 30 % of the speed, turning 60 deg/s towards the side it was last seen on
    assert searching[-1] == pytest.approx(wheel_speeds(30.0, turn, TRACK_MM))
    assert base.speeds == (0.0, 0.0)


def test_follow_line_with_no_readings_fails_half_a_second_after_it_starts() -> None:
    base = IdealBase()
    sensors = LineSensors(lambda t: None)
    result, ended_s = run(
        FollowLine(duration_s=10.0), {cap.DRIVE_BASE: base, cap.LINE: sensors}, start_s=40.0
    )
    assert result == Result.failed("lost line")
    assert ended_s == pytest.approx(0.5, abs=DT_S + 1e-9)


def test_follow_line_defaults_and_validation() -> None:
    action = FollowLine()
    assert (action.speed_mm_s, action.edge) == (100.0, "center")
    with pytest.raises(ValueError, match=r"^edge must be 'center', 'left' or 'right'$"):
        FollowLine(edge="middle")
    with pytest.raises(ValueError) as refused:
        FollowLine(speed_mm_s=0)
    assert str(refused.value) == (
        "follow_line needs a positive speed (write FollowLine(speed_mm_s=100))"
    )
    assert FollowLine(speed_mm_s=0.5).speed_mm_s == 0.5


def test_follow_line_steers_with_the_profiles_gains_up_to_150_deg_s() -> None:
    base = IdealBase()
    caps: dict[str, Any] = {
        cap.DRIVE_BASE: base,
        cap.LINE: LineSensors(lambda t: (0.0, 0.0, 900.0)),
    }
    run(FollowLine(duration_s=1.0), caps, limit_s=DT_S, gains={"line": (1000.0, 0.0, 0.0)})
    assert rate_deg_s(base.commands[-1]) == pytest.approx(150.0)
    base = IdealBase()
    caps[cap.DRIVE_BASE] = base
    run(FollowLine(duration_s=1.0), caps, limit_s=DT_S)
    assert rate_deg_s(base.commands[-1]) == pytest.approx(150.0)  # default kp 150 per unit
    base = IdealBase()
    caps[cap.DRIVE_BASE] = base
    run(FollowLine(duration_s=1.0), caps, limit_s=DT_S, gains={"line": (10.0, 0.0, 0.0)})
    assert rate_deg_s(base.commands[-1]) == pytest.approx(10.0)


def test_rotate_with_an_imu_silent_at_the_start_turns_by_the_wheels() -> None:
    base = IdealBase()
    imu = Imu(None)
    ctx = ActionContext({cap.DRIVE_BASE: base, cap.HEADING: imu})
    ctx.dt_s = DT_S
    rotate = Rotate(angle_deg=90.0)
    rotate.start(ctx)
    imu.reading = 300.0  # its first reading comes later: the turn stays on the encoders
    base.set_turned(45.0)
    assert rotate.update(ctx) is None
    assert rotate.feedback == "turning 45/90 deg"


def test_follow_wall_turns_towards_a_far_wall_at_most_60_deg_s() -> None:
    base = IdealBase()
    caps: dict[str, Any] = {cap.DRIVE_BASE: base, cap.SIDE_RANGE: SideRange(lambda t: 1400.0)}
    run(FollowWall(duration_s=1.0), caps, limit_s=DT_S)
    assert rate_deg_s(base.commands[-1]) == pytest.approx(60.0)


def test_follow_line_damping_uses_the_scheduler_dt() -> None:
    # kd 1: the line moving half a unit right in one 20 ms tick is a 25 deg/s turn right
    readings = {"value": (0.0, 900.0, 0.0)}
    base = IdealBase()
    caps: dict[str, Any] = {
        cap.DRIVE_BASE: base,
        cap.LINE: LineSensors(lambda t: readings["value"]),
    }
    ctx = ActionContext(caps, gains={"line": (0.0, 0.0, 1.0)})
    ctx.dt_s = DT_S
    action = FollowLine(duration_s=10.0)
    action.start(ctx)
    action.update(ctx)
    readings["value"] = (0.0, 900.0, 900.0)
    action.update(ctx)
    assert rate_deg_s(base.commands[-1]) == pytest.approx(25.0)
