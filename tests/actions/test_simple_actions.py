"""wait, wait_until, play_tone, set_led, servo, walk / turn progress and the action context,
on small fakes: the bounds, defaults, messages and timings students and teachers see."""

from __future__ import annotations

from typing import Any

import pytest

from roboscript import capabilities as cap
from roboscript.actions import (
    REQUIRED,
    Action,
    ActionContext,
    Outcome,
    PlayTone,
    Result,
    Servo,
    SetLed,
    Turn,
    Wait,
    WaitUntil,
    Walk,
)
from roboscript.actions.output import parse_color
from roboscript.errors import CapabilityError

DT_S = 0.1


class Speaker:
    def __init__(self) -> None:
        self.beeps: list[tuple[float, float]] = []

    def beep(self, frequency_hz: float, duration_s: float) -> None:
        self.beeps.append((frequency_hz, duration_s))


class Servos:
    def __init__(self, count: int) -> None:
        self.count = count
        self.angles: dict[int, float] = {}

    def set_angle(self, index: int, angle_deg: float) -> None:
        self.angles[index] = angle_deg


class Leds:
    def __init__(self, count: int) -> None:
        self.count = count
        self.colors: dict[int, tuple[int, int, int]] = {}

    def set_color(self, index: int, rgb: tuple[int, int, int]) -> None:
        self.colors[index] = rgb


class Walker:
    stride_mm = 40.0
    turn_step_deg = 15.0

    def __init__(self) -> None:
        self.ticks_left = 0
        self.stopped = False

    def walk(self, steps: int) -> None:
        self.ticks_left = 3

    def turn(self, steps: int) -> None:
        self.ticks_left = 3

    def play_motion(self, slot: int) -> None:
        self.ticks_left = 3

    def busy(self) -> bool:
        return self.ticks_left > 0

    def stop(self) -> None:
        self.stopped = True


class Condition:
    """A compiled guard as the mission loader makes it: callable on the env, with a source."""

    def __init__(self, source: str) -> None:
        self.source = source

    def __call__(self, env: dict[str, bool]) -> bool:
        return env["holds"]


def ticks_until_done(
    action: Action, capabilities: dict[str, Any], *, start_s: float = 100.0, env: Any = None
) -> tuple[Result, int]:
    """Start at ``start_s`` (a state entered late in a mission) and tick at 10 Hz."""
    ctx = ActionContext(capabilities, env=env)
    ctx.now_s, ctx.dt_s = start_s, DT_S
    action.start(ctx)
    for ticks in range(1, 200):
        ctx.now_s = start_s + ticks * DT_S
        result = action.update(ctx)
        if result is not None:
            return result, ticks
    raise AssertionError("the action never ended")


# --- wait, play_tone, wait_until ---------------------------------------------------------


def test_wait_counts_from_when_its_state_was_entered() -> None:
    wait = Wait(duration_s=1.5)
    assert ticks_until_done(wait, {}) == (Result.done(), 15)
    assert wait.feedback == "waiting 1.5/1.5 s"


def test_a_zero_wait_ends_at_the_first_tick_and_a_negative_one_is_refused() -> None:
    assert ticks_until_done(Wait(duration_s=0), {}) == (Result.done(), 1)
    with pytest.raises(ValueError, match=r"^a wait cannot be negative$"):
        Wait(duration_s=-1)


def test_play_tone_beeps_once_and_ends_when_the_tone_has() -> None:
    speaker = Speaker()
    tone = PlayTone(frequency_hz=440)
    assert ticks_until_done(tone, {cap.SPEAKER: speaker}) == (Result.done(), 2)  # 0.2 s
    assert speaker.beeps == [(440, 0.2)]
    assert tone.feedback == "tone 440 Hz"


@pytest.mark.parametrize("frequency", [20, 20000])
def test_play_tone_accepts_the_whole_audible_range(frequency: float) -> None:
    assert PlayTone(frequency_hz=frequency).frequency_hz == frequency


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"frequency_hz": 19.9}, r"^a tone's frequency must be between 20 Hz and 20 kHz$"),
        ({"frequency_hz": 20000.1}, r"^a tone's frequency must be between 20 Hz and 20 kHz$"),
        ({"frequency_hz": 440, "duration_s": 0}, r"^a tone's duration must be positive$"),
    ],
)
def test_play_tone_refuses_what_cannot_be_heard(kwargs: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        PlayTone(**kwargs)


def test_wait_until_ends_done_on_the_tick_the_condition_holds() -> None:
    env = {"holds": False}
    ctx = ActionContext({}, env=env)
    ctx.now_s = 50.0
    wait = WaitUntil(Condition("range.distance_cm < 20"), timeout_s=5.0)
    wait.start(ctx)
    ctx.now_s = 51.0
    assert wait.update(ctx) is None
    assert wait.feedback == "waiting 1.0/5.0 s"
    env["holds"] = True
    assert wait.update(ctx) == Result.done()


def test_wait_until_times_out_after_its_bound_naming_the_condition() -> None:
    result, ticks = ticks_until_done(
        WaitUntil(Condition("range.distance_cm < 20"), timeout_s=2.5), {}, env={"holds": False}
    )
    assert ticks == 25
    assert result == Result(Outcome.TIMEOUT, "'range.distance_cm < 20' did not hold within 2.5 s")


def test_wait_until_a_condition_without_source_says_the_condition() -> None:
    result, _ = ticks_until_done(
        WaitUntil(lambda env: False, timeout_s=0.5), {}, env={"holds": False}
    )
    assert result.reason == "'the condition' did not hold within 0.5 s"


def test_wait_until_needs_a_positive_bound() -> None:
    with pytest.raises(ValueError) as refused:
        WaitUntil(Condition("x"), timeout_s=0)
    assert str(refused.value) == (
        "wait_until needs a positive timeout"
        ' (write WaitUntil(condition="range.distance_cm < 20", timeout_s=10))'
    )
    assert WaitUntil(Condition("x"), timeout_s=0.5).timeout_s == 0.5


def test_a_timeout_result_says_took_too_long_by_default() -> None:
    assert Result.timeout() == Result(Outcome.TIMEOUT, "took too long")


# --- set_led and servo -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "rgb"),
    [
        ("#0A80fF", (10, 128, 255)),
        (" Orange ", (255, 100, 0)),
        ([0, 128, 255], (0, 128, 255)),
        ((255, 0, 0), (255, 0, 0)),
    ],
)
def test_colours_read_names_hex_and_triples(value: object, rgb: tuple[int, int, int]) -> None:
    assert parse_color(value) == rgb


@pytest.mark.parametrize(
    "value",
    ["#12345", "1234567", "#1234567", "#gg0000", [0, 0, 256], [0, -1, 0], [0, 0], [1.5, 0, 0]],
)
def test_colours_out_of_range_or_malformed_are_refused_listing_the_forms(value: object) -> None:
    with pytest.raises(ValueError) as error:
        parse_color(value)
    assert str(error.value) == (
        "expected a colour (off, black, white, red, green, blue, yellow, orange, purple, cyan, "
        f"pink, '#RRGGBB' or [r, g, b]), got {value!r}"
    )


def test_set_led_defaults_to_the_first_led_and_refuses_a_negative_index() -> None:
    leds = Leds(2)
    assert ticks_until_done(SetLed(color="red"), {cap.LEDS: leds}) == (Result.done(), 1)
    assert leds.colors == {0: (255, 0, 0)}
    assert SetLed(color=(1, 2, 3)).color == (1, 2, 3)
    with pytest.raises(ValueError, match=r"^LED index must not be negative$"):
        SetLed(color="red", index=-1)


def test_set_led_past_the_last_led_fails_not_supported() -> None:
    leds = Leds(2)
    result, _ = ticks_until_done(SetLed(color="red", index=2), {cap.LEDS: leds})
    assert result == Result.failed("not supported: the robot has 2 LEDs")
    assert leds.colors == {}


def test_servo_moves_and_gives_it_half_a_second_by_default() -> None:
    servos = Servos(2)
    assert ticks_until_done(Servo(angle_deg=0), {cap.SERVOS: servos}) == (Result.done(), 5)
    assert servos.angles == {0: 0}
    servo = Servo(angle_deg=180, index=1, duration_s=0)
    assert ticks_until_done(servo, {cap.SERVOS: servos}) == (Result.done(), 1)
    assert servos.angles == {0: 0, 1: 180}


def test_a_servo_the_robot_lacks_is_not_moved_and_fails_not_supported() -> None:
    servos = Servos(2)
    result, _ = ticks_until_done(Servo(angle_deg=90, index=2), {cap.SERVOS: servos})
    assert result == Result.failed("not supported: the robot has 2 servos")
    assert servos.angles == {}


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"angle_deg": -0.5}, r"^a servo angle is between 0 and 180 degrees$"),
        ({"angle_deg": 180.5}, r"^a servo angle is between 0 and 180 degrees$"),
        ({"angle_deg": 90, "index": -1}, r"^servo index and duration must not be negative$"),
        ({"angle_deg": 90, "duration_s": -1}, r"^servo index and duration must not be negative$"),
    ],
)
def test_servo_refuses_impossible_moves(kwargs: dict[str, Any], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        Servo(**kwargs)


# --- walk and turn -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("action", "feedback"),
    [
        (Walk(steps=3), "walking 3 steps forward"),
        (Walk(steps=1), "walking 1 steps forward"),
        (Walk(steps=-2), "walking 2 steps backward"),
        (Turn(steps=1), "turning 1 steps right"),
        (Turn(steps=-4), "turning 4 steps left"),
    ],
)
def test_gait_progress_says_which_way(action: Action, feedback: str) -> None:
    walker = Walker()
    ctx = ActionContext({cap.WALKER: walker})
    action.start(ctx)
    assert action.update(ctx) is None
    assert action.feedback == feedback
    walker.ticks_left = 0
    assert action.update(ctx) == Result.done()


def test_gait_actions_refuse_fractions_and_zero_naming_the_action() -> None:
    with pytest.raises(ValueError, match=r"^walk takes whole steps, not 1.5$"):
        Walk(steps=1.5)
    with pytest.raises(ValueError) as refused:
        Turn(steps=0)
    assert str(refused.value) == (
        "turn needs at least one step (0 does nothing) (write Turn(steps=4))"
    )


# --- the context -------------------------------------------------------------------------


def test_a_missing_capability_names_the_robot_and_what_it_lacks() -> None:
    with pytest.raises(CapabilityError) as error:
        ActionContext({}).get(cap.HEADING)
    assert str(error.value) == "the robot has no heading (an IMU or compass heading)"
    assert error.value.missing == (cap.HEADING,)
    with pytest.raises(CapabilityError, match=r"^mirto has no nonsense \(nonsense\)$"):
        ActionContext({}, "mirto").get("nonsense")


def test_conditions_are_evaluated_on_the_mission_env_and_false_outside_a_mission() -> None:
    assert ActionContext({}, env={"holds": True}).holds(Condition("x"))
    assert not ActionContext({}, env={"holds": False}).holds(Condition("x"))
    assert not ActionContext({}).holds(Condition("x"))
    assert not ActionContext({}, env={"holds": True}).holds(None)


def test_the_context_uses_the_profiles_gains_for_a_loop_else_the_default() -> None:
    ctx = ActionContext({}, gains={"wall": (1.0, 2.0, 3.0)})
    assert ctx.gain("wall", (0.0, 0.0, 0.0)) == (1.0, 2.0, 3.0)
    assert ctx.gain("line", (4.0, 5.0, 6.0)) == (4.0, 5.0, 6.0)
    assert (ctx.now_s, ctx.dt_s, ctx.env) == (0.0, 0.0, None)


def test_required_parameters_read_required_in_the_reference() -> None:
    assert repr(REQUIRED) == "REQUIRED"
