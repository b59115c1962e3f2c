"""Load-time checks on a mission, shared by the YAML and Python loaders.

Errors: unreachable states, states with no way out, actions or sensors the chosen robot lacks
(naming the robot, the capability and what to use instead). Warnings: outcomes that would end
the mission without a route (a ``failed`` or a ``timeout`` nobody handles).
"""

from __future__ import annotations

from roboscript import capabilities as cap
from roboscript.errors import InputError, MissionError
from roboscript.inputs.source import Location
from roboscript.mission.spec import MissionSpec, StateSpec

__all__ = ["check_capabilities", "check_mission"]

_CAN_FAIL = {"drive": "stalled", "rotate": "stalled"}

_INSTEAD = {
    cap.DRIVE_BASE: "use walk/turn on a walking robot",
    cap.LINE: "use follow_wall or drive with a range condition",
    cap.RANGE: "use bumper conditions instead",
    cap.DISPLAY: "use play_tone to signal instead",
    cap.SPEAKER: "use display to signal instead",
    cap.WALKER: "use drive/rotate on a wheeled robot",
}

_INSTEAD_NEEDS = {
    cap.DRIVE_BASE: cap.WALKER,
    cap.RANGE: cap.BUMPER,
    cap.DISPLAY: cap.SPEAKER,
    cap.SPEAKER: cap.DISPLAY,
}
"""What the suggestion in ``_INSTEAD`` needs: a robot without it gets no suggestion."""


def _instead(missing: str, have: frozenset[str]) -> str | None:
    """What to use instead of ``missing``, if the robot has what that needs."""
    needs = _INSTEAD_NEEDS.get(missing)
    return _INSTEAD.get(missing) if needs is None or needs in have else None


def _problem(
    message: str, where: Location | None, hint: str | None = None, severity: str = "error"
) -> InputError:
    return MissionError(
        message,
        path=where.path if where else None,
        line=where.line if where else None,
        col=where.col if where else None,
        hint=hint,
        severity=severity,
    )


def _reachable(spec: MissionSpec) -> set[str]:
    seen = {spec.initial}
    todo = [spec.initial]
    while todo:
        state = spec.states.get(todo.pop())
        if state is None:
            continue
        for transition in state.targets():
            if transition.target not in seen:
                seen.add(transition.target)
                todo.append(transition.target)
    return seen


def _has_way_out(state: StateSpec) -> bool:
    return bool(state.final or state.when or any(state.on.values()))


def check_mission(spec: MissionSpec, profile: object | None = None) -> list[InputError]:
    """Check a mission's structure (and its fit to a robot, when ``profile`` is given).

    Args:
        spec: The mission.
        profile: A :class:`~roboscript.profiles.RobotProfile`, or ``None``.

    Returns:
        Problems found, errors and warnings (``severity``).
    """
    problems: list[InputError] = []
    reachable = _reachable(spec)
    for name, state in spec.states.items():
        if name not in reachable:
            problems.append(
                _problem(
                    f"state '{name}' can never be reached from '{spec.initial}'",
                    state.location,
                    "add a transition to it, or remove it",
                )
            )
        if not _has_way_out(state):
            problems.append(
                _problem(
                    f"state '{name}' has no way out",
                    state.location,
                    "add 'on: {done: NEXT}', a 'when' condition, or 'final: success'",
                )
            )
        if state.final and (state.when or any(state.on.values())):
            problems.append(
                _problem(
                    f"final state '{name}' cannot also have transitions",
                    state.location,
                    "remove 'final', or remove its 'on'/'when'",
                )
            )
        if state.final:
            continue
        action = state.action
        if action is not None and not action.bounded and state.timeout_s is None and not state.when:
            problems.append(
                _problem(
                    f"'{action.name}' in state '{name}' never ends as written",
                    action.location,
                    "give it 'until' or 'duration', or give the state a 'timeout' or a 'when'",
                )
            )
        if state.timeout_s is not None and not state.on.get("timeout"):
            problems.append(
                _problem(
                    f"if state '{name}' times out the mission ends in failure",
                    state.location,
                    "add 'on: {timeout: STATE}' to handle it",
                    "warning",
                )
            )
        if action is not None and action.name in _CAN_FAIL and not state.on.get("failed"):
            problems.append(
                _problem(
                    f"if '{action.name}' fails ({_CAN_FAIL[action.name]}) in state '{name}', "
                    "the mission ends in failure",
                    action.location,
                    "add 'on: {failed: STATE}' to handle it",
                    "warning",
                )
            )
    if profile is not None:
        problems.extend(check_capabilities(spec, profile))
    return problems


def check_capabilities(spec: MissionSpec, profile: object) -> list[InputError]:
    """Errors for every action or condition the robot of ``profile`` cannot serve."""
    have: frozenset[str] = getattr(profile, "capabilities", frozenset())
    robot = getattr(profile, "name", "the robot")
    problems: list[InputError] = []
    for state in spec.states.values():
        for action in state.actions():
            for missing in sorted(action.requires - have):
                problems.append(
                    _problem(
                        f"'{action.name}' needs {missing} "
                        f"({cap.CAPABILITY_NAMES.get(missing, missing)}),"
                        f" which {robot} does not have",
                        action.location,
                        _instead(missing, have),
                    )
                )
        for transition in state.targets():
            needs = frozenset(getattr(transition.guard, "capabilities", ()))
            for missing in sorted(needs - have):
                problems.append(
                    _problem(
                        f"the condition '{transition.guard_text}' reads {missing}, "
                        f"which {robot} does not have",
                        transition.location,
                        _instead(missing, have),
                    )
                )
    return problems
