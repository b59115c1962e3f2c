"""Load-time checks on a mission, shared by the YAML and Python loaders.

Errors: unreachable states, states with no way out, a mission that can reach no final state,
actions or sensors the chosen robot lacks (naming the robot, the capability and what to use
instead). Warnings: states from which no final state can be reached, states that wait on a
condition with no timeout, and outcomes that would end the mission without a route (a
``failed`` or a ``timeout`` nobody handles).
"""

from __future__ import annotations

import ast
import contextlib
import difflib
from collections.abc import Collection
from dataclasses import dataclass

from roboscript import capabilities as cap
from roboscript.errors import InputError, MissionError
from roboscript.inputs.source import Location
from roboscript.mission.guards import Guard
from roboscript.mission.spec import ActionSpec, MissionSpec, StateSpec, TransitionSpec

__all__ = [
    "FIXED_NODES",
    "check_capabilities",
    "check_mission",
    "check_regions",
    "check_world_regions",
    "regions_read",
]

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


@dataclass(frozen=True)
class _Write:
    """What to write, in each language a state can be written in: the hint given is the one
    of the file the problem is in (a Python mission may hold YAML missions as states)."""

    yaml: str
    python: str

    def at(self, where: Location | None) -> str:
        is_python = where is not None and str(where.path).lower().endswith(".py")
        return self.python if is_python else self.yaml


def _problem(
    message: str,
    where: Location | None,
    hint: str | _Write | None = None,
    severity: str = "error",
) -> InputError:
    return MissionError(
        message,
        path=where.path if where else None,
        line=where.line if where else None,
        col=where.col if where else None,
        hint=hint.at(where) if isinstance(hint, _Write) else hint,
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


def _can_finish(spec: MissionSpec) -> set[str]:
    """States from which some final state can be reached (the final states included)."""
    leads_to: dict[str, set[str]] = {name: set() for name in spec.states}
    for name, state in spec.states.items():
        for transition in state.targets():
            leads_to.setdefault(transition.target, set()).add(name)
    found = {name for name, state in spec.states.items() if state.final}
    todo = list(found)
    while todo:
        for source in leads_to.get(todo.pop(), ()):
            if source not in found:
                found.add(source)
                todo.append(source)
    return found


def _failure(action: ActionSpec) -> str | None:
    """Why ``action`` may end ``failed`` whatever the robot, or ``None`` if it cannot (as its
    class says: :attr:`Action.failure <roboscript.actions.base.Action.failure>`)."""
    if action.action_class is not None and not action.children and action.inner is None:
        return action.action_class.failure
    if action.inner is not None:
        inner = action.inner
        reachable = _reachable(inner)
        if any(inner.states[n].final == "failure" for n in reachable if n in inner.states):
            return "its inner states reach a failure"
        return None
    reasons = [r for r in (_failure(child) for child in action.children) if r]
    return reasons[0] if reasons else None


def _how_to_end(action: ActionSpec) -> _Write:
    """How to give an endless action an end: one of the parameters that end it (its class's
    ``bounded_by``, with an example of each), or a time bound on its state."""
    state = _Write("`timeout: 10 s` or a `when`", "timeout_s=10 or a when=")
    endless = action
    while endless.children:  # a parallel or a repeat of an endless action: that action
        endless = next((c for c in endless.children if not c.bounded), endless.children[0])
    cls = endless.action_class
    if cls is None or not cls.bounded_by:
        return _Write(f"give the state {state.yaml}", f"give the state {state.python}")
    examples = [cls.example(name) for name in cls.bounded_by]
    inside = "" if endless is action else f" in '{endless.name}'"
    return _Write(
        f"write {' or '.join(y for y, _ in examples)}{inside}, or give the state {state.yaml}",
        f"write {' or '.join(p for _, p in examples)}, or give the state {state.python}",
    )


def _times_out(action: ActionSpec) -> bool:
    can = action.action_class is not None and action.action_class.can_time_out
    return can or any(_times_out(c) for c in action.children)


def _waits_on(state: StateSpec) -> bool:
    """True if the state can only be left by a ``when`` condition (or its timeout)."""
    action = state.action
    if not state.when or state.timeout_s is not None:
        return False
    return action is None or not action.bounded or not state.on.get("done")


_ACTION_OUTCOMES = {"done": "is done", "failed": "fails"}


def _routes_without_action(name: str, state: StateSpec) -> list[InputError]:
    """Routes for an action's outcome in a state that runs no action: nothing can take them
    (students meet this after deleting a state's ``do:``), so the state would wait for ever."""
    return [
        _problem(
            f"state '{name}' moves on when its action {ends}, but it has no "
            + _Write("'do:' action", "action").at(state.location)
            + ", so it would wait for ever",
            state.location,
            _Write(
                "give it an action, e.g. do: {drive: {distance: 50 cm}}, or leave it with "
                "'when:' or 'timeout:'",
                "give it an action, e.g. state(Drive(distance_mm=500), ...), or leave it with "
                "when= or timeout_s=",
            ),
        )
        for outcome, ends in _ACTION_OUTCOMES.items()
        if state.on.get(outcome)
    ]


FIXED_NODES = (
    ast.Constant,
    ast.BoolOp,
    ast.Compare,
    ast.UnaryOp,
    ast.BinOp,
    ast.Expression,
    ast.operator,
    ast.boolop,
    ast.cmpop,
    ast.unaryop,
)
"""What a condition made only of fixed values is built of: values and operators."""


def fixed_condition(text: str) -> bool:
    """True if the condition ``text`` (as YAML or Python writes it) reads nothing: only fixed
    values (``True``, ``1 < 2``, ``not false``), so it never changes."""
    written = " ".join(text.split())
    for word, value in (("true", "True"), ("false", "False")):
        written = " ".join(value if part == word else part for part in written.split(" "))
    try:
        tree = ast.parse(written, mode="eval")
    except SyntaxError:
        return False
    return all(isinstance(node, FIXED_NODES) for node in ast.walk(tree))


def fixed_condition_problem(
    text: str, holds: bool | None, state: str, target: str, where: Location | None
) -> InputError:
    """The warning for a condition of ``state`` made only of fixed values (``holds``: what it
    always gives, when known), which goes to ``target``."""
    if holds is None:
        then = ""
    elif holds:
        then = f": it always holds, so state '{state}' goes to '{target}' at its first tick"
    else:
        then = f": it never holds, so state '{state}' never goes to '{target}' this way"
    return _problem(
        f"the condition '{text}' is made only of fixed values, so it never changes{then}",
        where,
        "compare a sensor's value, e.g. range.distance_cm < 20",
        "warning",
    )


def _fixed_conditions(name: str, state: StateSpec) -> list[InputError]:
    """A warning for each of the state's YAML conditions that reads nothing (but a last
    ``true`` after other choices: an otherwise, written on purpose)."""
    found = []
    for number, choice in enumerate(state.when):
        guard = choice.guard
        if not isinstance(guard, Guard) or not fixed_condition(guard.source):
            continue
        holds: bool | None = None
        with contextlib.suppress(Exception):  # a fixed value reads no sensor: no env needed
            holds = bool(guard(None))  # type: ignore[arg-type]
        if holds and number > 0 and number == len(state.when) - 1:
            continue
        found.append(
            fixed_condition_problem(
                guard.source.strip(), holds, name, choice.target, choice.location or state.location
            )
        )
    return found


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
    can_finish = _can_finish(spec)
    stuck = any(not _has_way_out(spec.states[n]) for n in reachable if n in spec.states)
    if spec.initial not in can_finish and not stuck:  # a dead end says why already
        first = spec.states.get(spec.initial)
        problems.append(
            _problem(
                f"mission '{spec.name}' can never finish: no final state can be reached "
                f"from '{spec.initial}'",
                first.location if first is not None else spec.location,
                _Write(
                    "add a state with 'final: success' and a transition to it, "
                    "e.g. on: {done: finished}",
                    'add a state with final="success" and a transition to it, '
                    'e.g. finished = state(final="success") and on_done="finished"',
                ),
            )
        )
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
                    _Write(
                        "add 'on: {done: NEXT}', a 'when' condition, or 'final: success'",
                        'add on_done="NEXT", a when= condition, or final="success"',
                    ),
                )
            )
        if state.action is None and not state.final:
            problems.extend(_routes_without_action(name, state))
        if state.final and (state.when or any(state.on.values())):
            problems.append(
                _problem(
                    f"final state '{name}' cannot also have transitions",
                    state.location,
                    _Write(
                        "remove 'final', or remove its 'on'/'when'",
                        "remove final=, or remove its on_done=/on_failed=/on_timeout=/when=",
                    ),
                )
            )
        if state.final:
            continue
        problems.extend(_fixed_conditions(name, state))
        for choice in state.when:
            if choice.target == name:  # re-entered on every tick the condition holds
                condition = choice.guard_text or "its condition"
                problems.append(
                    _problem(
                        f"state '{name}' goes to itself when '{condition}' holds: it starts"
                        " again at once, and again on every tick while that holds",
                        choice.location or state.location,
                        "go to another state, one that turns away, say; or leave the condition out",
                        "warning",
                    )
                )
                break
        if (
            name in reachable
            and name not in can_finish
            and spec.initial in can_finish
            and _has_way_out(state)
        ):
            problems.append(
                _problem(
                    f"once in state '{name}' the mission can never finish: no final state "
                    "can be reached from it",
                    state.location,
                    _Write(
                        "add a transition from it to a final state, e.g. 'timeout: 30 s' and "
                        "'on: {timeout: FINAL_STATE}'",
                        "add a transition from it to a final state, e.g. timeout_s=30 and "
                        'on_timeout="FINAL_STATE"',
                    ),
                    "warning",
                )
            )
        if _waits_on(state):
            waited = "' or '".join(t.guard_text or "?" for t in state.when)
            problems.append(
                _problem(
                    f"state '{name}' waits for '{waited}' with no timeout: if that never "
                    "holds, the mission runs until its time limit",
                    state.location,
                    _Write(
                        "add 'timeout: 10 s' and 'on: {timeout: STATE}' to the state",
                        'add timeout_s=10 and on_timeout="STATE" to the state',
                    ),
                    "warning",
                )
            )
        action = state.action
        if action is not None and not action.bounded and state.timeout_s is None and not state.when:
            problems.append(
                _problem(
                    f"'{action.name}' in state '{name}' never ends as written",
                    action.location,
                    _how_to_end(action),
                )
            )
        if state.timeout_s is not None and not state.on.get("timeout"):
            problems.append(
                _problem(
                    f"if state '{name}' times out the mission ends in failure",
                    state.location,
                    _Write(
                        "add 'on: {timeout: STATE}' to handle it",
                        'add on_timeout="STATE" to handle it',
                    ),
                    "warning",
                )
            )
        timed_out = {t.target for t in state.on.get("timeout", ())}
        elsewhere = {t.target for o, ts in state.on.items() if o != "timeout" for t in ts}
        if (
            timed_out - elsewhere  # a way of its own, not every outcome sent to one state
            and state.timeout_s is None
            and not (action is not None and (_times_out(action) or action.inner is not None))
        ):
            way_out = state.on["timeout"][0]
            problems.append(
                _problem(
                    f"state '{name}' goes to '{way_out.target}' when it times out, but it has"
                    " no timeout, so it never times out",
                    way_out.location or state.location,
                    _Write("add 'timeout: 10 s' to the state", "add timeout_s=10 to the state"),
                    "warning",
                )
            )
        why = _failure(action) if action is not None else None
        if action is not None and why is not None and not state.on.get("failed"):
            what = (
                f"the inner states of '{name}' end in failure"
                if action.inner is not None
                else f"'{action.name}' fails ({why}) in state '{name}'"
            )
            problems.append(
                _problem(
                    f"if {what}, the mission ends in failure",
                    action.location,
                    _Write(
                        "add 'on: {failed: STATE}' to handle it",
                        'add on_failed="STATE" to handle it',
                    ),
                    "warning",
                )
            )
        if (
            action is not None
            and _times_out(action)
            and state.timeout_s is None
            and not state.on.get("timeout")
        ):
            problems.append(
                _problem(
                    f"if '{action.name}' times out in state '{name}', the mission ends in failure",
                    action.location,
                    _Write(
                        "add 'on: {timeout: STATE}' to handle it",
                        'add on_timeout="STATE" to handle it',
                    ),
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


def regions_read(spec: MissionSpec) -> list[tuple[str, TransitionSpec]]:
    """Every ``in_region.NAME`` a condition of the mission reads (inner states too)."""
    found: list[tuple[str, TransitionSpec]] = []
    for state in spec.states.values():
        for transition in state.targets():
            for region in sorted(getattr(transition.guard, "regions", ())):
                found.append((region, transition))
        for action in state.actions():
            found.extend(_inner_regions(action))
    return found


def _inner_regions(action: ActionSpec) -> list[tuple[str, TransitionSpec]]:
    found = regions_read(action.inner) if action.inner is not None else []
    for child in action.children:
        found.extend(_inner_regions(child))
    return found


def check_regions(
    spec: MissionSpec, regions: Collection[str] | None, world: str = "the world"
) -> list[InputError]:
    """Errors for every ``in_region.NAME`` the world cannot answer.

    Args:
        spec: The mission.
        regions: The region names of the mission's world, or ``None`` when the mission runs
            on a robot reached on a port (which has no world map to place itself in).
        world: The world's name, for messages.
    """
    problems: list[InputError] = []
    for region, transition in regions_read(spec):
        where = transition.location
        if regions is None:
            problems.append(
                _problem(
                    f"the condition '{transition.guard_text}' reads in_region.{region}, but a "
                    "robot on a port has no world map to place itself in",
                    where,
                    "run it on the simulator, or use pose.x_mm and pose.y_mm, which odometry gives",
                )
            )
        elif region not in regions:
            close = difflib.get_close_matches(region, sorted(regions), n=1)
            listed = ", ".join(sorted(regions)) or "none"
            problems.append(
                _problem(
                    f"the world '{world}' has no region '{region}' (its regions: {listed})",
                    where,
                    f"did you mean 'in_region.{close[0]}'?" if close else None,
                )
            )
    return problems


def check_world_regions(spec: MissionSpec, world: str | None) -> list[InputError]:
    """:func:`check_regions` against a simulator world by name or file (``None``: on a port).

    The world is read only if a condition reads ``in_region``.

    Raises:
        InputError: The world file itself is not valid.
    """
    if not regions_read(spec):
        return []
    if world is None:
        return check_regions(spec, None)
    # the simulator's worlds load only for a mission whose conditions read in_region
    from roboscript.sim.world import load_world

    loaded = load_world(world)
    return check_regions(spec, set(loaded.regions), loaded.name)
