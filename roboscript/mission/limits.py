"""Range checks on the numbers a mission gives its actions, before the robot moves.

Two kinds of check:

* :func:`param_problems`, on their own: every quantity is a finite number, times are positive,
  and each built-in action's values are within what any robot could do (a ``drive`` of at most
  100 m, a ``walk`` of at most 1000 steps, a tone a buzzer can play). These are errors,
  located at the parameter; parameters that cannot be given together are the action's own
  rule (:meth:`Action.conflicts <roboscript.actions.base.Action.conflicts>`).
* :func:`profile_problems`, against the robot a mission runs on: speeds and turn rates above
  what the robot can do are held at its top speed, and those too slow to overcome the wheels'
  static friction may not move it at all; a tone longer than an ASIP board's ``int`` holds
  (32.767 s on an ATmega328P) is cut short or not played. These are warnings that say what
  will happen.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from typing import Any

from roboscript import capabilities as cap
from roboscript.actions.base import PARAM_EXAMPLES, Param
from roboscript.drivers.asip.options import AsipOptions
from roboscript.errors import InputError, MissionError
from roboscript.inputs.quantities import DIMENSIONS
from roboscript.inputs.source import Location
from roboscript.mission.spec import ActionSpec, MissionSpec

__all__ = [
    "GUARD_NUMBER_LIMIT",
    "MAX_DISTANCE_MM",
    "MAX_STEPS",
    "MAX_TIME_S",
    "MIN_SPEED_MM_S",
    "param_problems",
    "profile_problems",
    "time_problem",
]

MIN_SPEED_MM_S = 10.0
"""Slowest wheel speed that reliably moves a robot: below it the motors' power is inside their
dead band (about 4 % of full power on the robots roboscript drives), so the wheels may not
overcome static friction, and the stall check (2 mm in a second) may end the move first."""

MAX_DISTANCE_MM = 100_000.0
"""Longest ``drive``: 100 m, more than any classroom, and 10 minutes at a top speed."""

MAX_TIME_S = 3600.0
"""Longest duration or timeout: an hour, longer than any run is allowed."""

MAX_ANGLE_DEG = 3600.0
"""Largest ``rotate``: ten whole turns."""

MAX_STEPS = 1000
"""Most gait steps in one ``walk`` or ``turn`` (a PLEN2 step takes about a second)."""

MAX_INDEX = 63
"""Highest servo or LED index any supported board has."""

TONE_HZ = (20.0, 20_000.0)
"""Pitches a buzzer can play (and a person hear), hertz."""

SERVO_DEG = (0.0, 180.0)
"""A hobby servo's travel, degrees."""

GUARD_NUMBER_LIMIT = 1e9
"""Largest number a condition may compare with: no sensor, time or count comes near it."""

_Problem = tuple[str, str, str | None]  # (param name, message, hint)


def shown(value: Any, unit: str = "") -> str:
    """A number as a message shows it: ``1e+400`` is ``infinity``, a huge int is its length."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 64:
        digits = int(value.bit_length() * math.log10(2)) + 1
        return f"a number with about {digits} digits"
    if isinstance(value, float) and math.isnan(value):
        return "not a number"
    if isinstance(value, float) and math.isinf(value):
        return "infinity" if value > 0 else "minus infinity"
    text = f"{value:g}" if isinstance(value, float) else str(value)
    return f"{text} {unit}".strip()


def a_noun(noun: str) -> str:
    """``noun`` with its article: ``a distance``, ``an angle``."""
    return f"an {noun}" if noun[:1] in "aeiou" else f"a {noun}"


def example(kind: str) -> str:
    """A value of a quantity ``kind`` as a student writes it, for hints (``'50 cm'``)."""
    return f"'{PARAM_EXAMPLES[kind]}'" if kind in DIMENSIONS and kind != "count" else "a number"


def time_problem(label: str, value: float) -> tuple[str, str] | None:
    """``(message, hint)`` if ``value`` seconds cannot be a duration or a timeout."""
    if not math.isfinite(value):
        return (
            f"{label}: {shown(value)} is not a time the robot can wait",
            f"write a time such as '2 s', at most {MAX_TIME_S:g} s",
        )
    if value <= 0:
        return (
            f"{label}: {shown(value, 's')} is not a positive time, so it would end at once",
            "write a positive time such as '2 s'",
        )
    if value > MAX_TIME_S:
        return (
            f"{label}: {shown(value, 's')} is longer than any run (at most 1 hour)",
            f"write a time of at most {MAX_TIME_S:g} s",
        )
    return None


_STILL = {
    ("drive", "distance"): ("move", "a distance such as '50 cm'", "drives backward"),
    ("rotate", "angle"): ("turn", "an angle such as '90 deg'", "turns left"),
}
"""A ``drive`` or ``rotate`` of zero: what it would not do, an example and what a negative
value does instead."""


def param_problems(
    action: str, params: Sequence[Param], kwargs: Mapping[str, Any], *, built_in: bool
) -> list[_Problem]:
    """Values out of range for an action, whatever the robot.

    Args:
        action: The action's name, for messages.
        params: The action's parameters.
        kwargs: Its converted keyword arguments (quantities in base units).
        built_in: True for roboscript's own actions, whose values are also bounded; a
            student's behaviour gets only the checks every quantity needs (finite; times
            positive).

    Returns:
        ``(param name, message, hint)`` for each problem, in parameter order.
    """
    problems: list[_Problem] = []
    for param in params:
        value = kwargs.get(param.kwarg)
        if value is None or isinstance(value, bool) or not isinstance(value, int | float):
            continue
        found = _one(action, param, value, built_in)
        if found is not None:
            problems.append((param.name, *found))
    return problems


def _one(action: str, param: Param, value: float, built_in: bool) -> tuple[str, str | None] | None:
    label = f"{action} {param.name}"
    kind = param.kind
    if kind == "count":
        if built_in and param.name == "steps" and abs(value) > MAX_STEPS:
            return (
                (
                    f"{label}: {shown(value)} is more steps than a robot can take in one go "
                    f"(at most {MAX_STEPS} each way)"
                ),
                f"write steps from -{MAX_STEPS} to {MAX_STEPS}, or repeat a shorter {action}",
            )
        if built_in and param.name == "index" and not 0 <= value <= MAX_INDEX:
            return (
                f"{label}: {shown(value)} is not an index a board has (0 to {MAX_INDEX})",
                "count from 0: the first one is index 0",
            )
        return None
    if kind not in DIMENSIONS:
        return None
    unit = DIMENSIONS[kind].base_unit
    if kind == "time":
        return time_problem(label, value)
    if not math.isfinite(value):
        return (
            f"{label}: {shown(value)} is not a number the robot can use",
            f"write {a_noun(DIMENSIONS[kind].name)} such as {example(kind)}",
        )
    if not built_in:
        return None
    if (action, param.name) in _STILL and value == 0:
        does, example_value, other_way = _STILL[action, param.name]
        return (
            f"{label}: {shown(value, unit)} does not {does} the robot, so '{action}' ends at once",
            f"write {example_value}; a negative one {other_way}; to stay still, use wait",
        )
    if kind == "distance" and abs(value) > MAX_DISTANCE_MM:
        return (
            f"{label}: {shown(value, unit)} is farther than any room (at most 100 m)",
            "write a distance such as '50 cm'",
        )
    if kind == "angle" and action == "servo" and not SERVO_DEG[0] <= value <= SERVO_DEG[1]:
        return (
            f"{label}: {shown(value, unit)} is beyond a servo's travel (0 to 180 deg)",
            "write an angle from 0 deg to 180 deg",
        )
    if kind == "angle" and abs(value) > MAX_ANGLE_DEG:
        return (
            f"{label}: {shown(value, unit)} is more than ten whole turns",
            "write an angle such as '90 deg'; a negative angle turns left",
        )
    if kind == "frequency" and not TONE_HZ[0] <= value <= TONE_HZ[1]:
        return (
            f"{label}: {shown(value, unit)} is beyond what a buzzer can play (20 Hz to 20 kHz)",
            "write a pitch such as '880 Hz'",
        )
    if kind in ("speed", "turn_rate") and value <= 0:
        other_way = "distance drives backward" if kind == "speed" else "angle turns left"
        return (
            f"{label}: {shown(value, unit)} is not a positive {DIMENSIONS[kind].name}",
            (
                f"write {a_noun(DIMENSIONS[kind].name)} such as {example(kind)}; "
                f"a negative {other_way}"
            ),
        )
    return None


# ------------------------------------------------------------------------ against a robot


def _actions(spec: MissionSpec) -> Iterator[ActionSpec]:
    """Every action of a mission, inner machines, ``parallel`` and ``repeat`` included."""
    todo = [a for state in spec.states.values() for a in state.actions()]
    while todo:
        action = todo.pop(0)
        yield action
        todo.extend(action.children)
        if action.inner is not None:
            todo.extend(a for state in action.inner.states.values() for a in state.actions())


def _warning(message: str, where: Location | None, hint: str) -> InputError:
    where = where or Location("<mission>")
    return MissionError(
        message, path=where.path, line=where.line, col=where.col, hint=hint, severity="warning"
    )


def _speeds(spec: MissionSpec) -> Iterator[tuple[ActionSpec, str, Any, bool]]:
    """``(action, parameter, value, True for a speed / False for a turn rate)`` for each
    speed and turn rate of the mission's actions, as their classes name them
    (:attr:`Action.drive_speeds <roboscript.actions.base.Action.drive_speeds>`,
    :attr:`~roboscript.actions.base.Action.turn_rates`)."""
    for action in _actions(spec):
        cls = action.action_class
        if cls is None:
            continue
        kwargs = {p.name: p.kwarg for p in cls.params}
        for name in cls.drive_speeds:
            yield action, name, action.kwargs.get(kwargs[name]), True
        for name in cls.turn_rates:
            yield action, name, action.kwargs.get(kwargs[name]), False


def profile_problems(spec: MissionSpec, profile: Any) -> list[InputError]:
    """Warnings for speeds and turn rates the robot of ``profile`` cannot hold.

    Args:
        spec: The mission.
        profile: Its :class:`~roboscript.profiles.RobotProfile`.

    Returns:
        A warning for each speed above the robot's top speed (it will be held at the top
        speed) or below :data:`MIN_SPEED_MM_S` (the wheels may not turn), and the same for
        ``rotate`` turn rates, located at the parameter.
    """
    problems = _tone_problems(spec, profile)
    if cap.DRIVE_BASE not in getattr(profile, "capabilities", frozenset()):
        return problems
    robot = profile.name
    top_mm_s = float(profile.max_speed_mm_s)
    track_mm = float(profile.track_mm)
    # Turning in place, each wheel runs at rate * track / 2.
    top_deg_s = math.degrees(2.0 * top_mm_s / track_mm)
    low_deg_s = math.degrees(2.0 * MIN_SPEED_MM_S / track_mm)
    for action, param, value, speed in _speeds(spec):
        if speed:
            unit, top, low, verb = "mm/s", top_mm_s, MIN_SPEED_MM_S, "drive"
        else:
            unit, top, low, verb = "deg/s", top_deg_s, low_deg_s, "turn"
        if not isinstance(value, int | float) or not math.isfinite(value) or value <= 0:
            continue  # the parameter checks reported it
        where = action.param_locations.get(param, action.location)
        label = f"{action.name} {param}"
        if value > top + 1e-9:
            problems.append(
                _warning(
                    f"{label}: {shown(float(value), unit)} is faster than {robot} can {verb}, "
                    f"so it will {verb} at its top {param.replace('_', ' ')} "
                    f"of {top:.0f} {unit}",
                    where,
                    f"write {param}: {math.floor(top):.0f} {unit} or less",
                )
            )
        elif value < low - 1e-9:
            problems.append(
                _warning(
                    f"{label}: {shown(float(value), unit)} is too slow to overcome the wheels' "
                    f"friction, so {robot} may not move and '{action.name}' may fail "
                    "(stalled)",
                    where,
                    f"write {param}: {math.ceil(low):.0f} {unit} or more",
                )
            )
    return problems


def _tone_problems(spec: MissionSpec, profile: Any) -> list[InputError]:
    """A warning for each ``play_tone`` longer than the robot's board plays: an ASIP board
    on an ATmega328P keeps a tone's length in a 16-bit ``int`` (32.767 s)."""
    if getattr(profile, "protocol", None) != "asip":
        return []
    options = AsipOptions.from_mapping(profile.options, profile=profile.name)
    longest_s = options.longest_tone_ms / 1000.0
    problems: list[InputError] = []
    for action in _actions(spec):
        duration = action.kwargs.get("duration_s") if action.name == "play_tone" else None
        if not isinstance(duration, int | float) or not longest_s < duration < math.inf:
            continue
        problems.append(
            _warning(
                f"{action.name} duration: {shown(float(duration), 's')} is longer than "
                f"{profile.name}'s board can play a tone ({longest_s:g} s): it keeps a tone's "
                "length in a small number that runs over, so the tone is cut short or not "
                "played at all",
                action.param_locations.get("duration", action.location),
                f"write duration: {math.floor(longest_s):.0f} s or less; for a longer sound, "
                "repeat a shorter play_tone",
            )
        )
    return problems
