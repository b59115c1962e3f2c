"""A mission as data: frozen dataclasses both the YAML and the Python loaders produce.

There is one set of rules for both syntaxes: the checks (:mod:`roboscript.mission.checks`) and
the runner work on a :class:`MissionSpec`, never on YAML.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from roboscript.inputs.source import Location

if TYPE_CHECKING:
    from roboscript.actions.base import Action

__all__ = [
    "OUTCOMES",
    "ActionSpec",
    "MissionSpec",
    "StateSpec",
    "TransitionSpec",
]

OUTCOMES = ("done", "failed", "timeout")
"""Outcomes a state's ``on`` can route."""


@dataclass(frozen=True)
class ActionSpec:
    """An action with its parameters converted to units.

    Attributes:
        name: The action word (``drive``).
        kwargs: Constructor keywords with units in their names (``distance_mm=500.0``).
        factory: Builds a fresh action object for each state entry.
        requires: Capability names the action needs.
        location: Where the action was written.
        bounded: False for an action that would run forever as written (``follow_wall``
            without ``until`` or ``duration``): its state then needs a timeout or a condition.
        inner: For nested states, the inner machine.
        children: For ``parallel`` and ``repeat``, the actions they run.
        param_locations: Where each parameter was written, by its mission name (a parameter
            not found here was not written, or not located: use ``location``).
        action_class: The :class:`~roboscript.actions.base.Action` class, whose facts (how
            it can fail, whether it can time out, which parameters are speeds and turn
            rates) the load-time checks read; ``None`` for ``parallel``, ``repeat`` and
            inner states, which are judged by what they hold.
    """

    name: str
    kwargs: Mapping[str, Any]
    factory: Callable[[], Any] = field(compare=False, repr=False)
    requires: frozenset[str] = frozenset()
    location: Location | None = None
    bounded: bool = True
    inner: MissionSpec | None = field(default=None, compare=False, repr=False)
    children: tuple[ActionSpec, ...] = field(default=(), compare=False, repr=False)
    param_locations: Mapping[str, Location] = field(default_factory=dict, compare=False, repr=False)
    action_class: type[Action] | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class TransitionSpec:
    """One way out of a state: go to ``target`` if ``guard`` holds (always, when ``None``).

    Attributes:
        target: The next state's name.
        guard: A compiled guard (:class:`~roboscript.mission.guards.Guard`) or a callable
            ``(env) -> bool`` from a Python mission; ``None`` means unconditional.
        guard_text: The guard as written, for diagrams and messages.
        location: Where the transition was written.
    """

    target: str
    guard: Callable[[Any], bool] | None = field(default=None, compare=False)
    guard_text: str | None = None
    location: Location | None = None


@dataclass(frozen=True)
class StateSpec:
    """One state of a mission.

    Attributes:
        name: State name.
        action: What the state does, or ``None`` for a state that only waits on guards.
        during: Actions run alongside ``action`` while in the state, stopped on leaving it.
        on: Outcome (``done``/``failed``/``timeout``) -> transitions tried in order.
        when: Guarded transitions checked every tick while in the state, in order.
        timeout_s: The state's time bound, seconds, or ``None``.
        final: ``"success"`` or ``"failure"`` for a final state, else ``None``.
        description: Free text.
        location: Where the state was written.
    """

    name: str
    action: ActionSpec | None = None
    during: tuple[ActionSpec, ...] = ()
    on: Mapping[str, tuple[TransitionSpec, ...]] = field(default_factory=dict)
    when: tuple[TransitionSpec, ...] = ()
    timeout_s: float | None = None
    final: str | None = None
    description: str = ""
    location: Location | None = None

    @property
    def action_name(self) -> str | None:
        """The name of the state's action (``drive``), or ``None`` for a state without one."""
        return self.action.name if self.action is not None else None

    def actions(self) -> list[ActionSpec]:
        """The state's action, then its ``during`` actions."""
        return ([] if self.action is None else [self.action]) + list(self.during)

    def targets(self) -> list[TransitionSpec]:
        """Every transition out of the state."""
        found = list(self.when)
        for transitions in self.on.values():
            found.extend(transitions)
        return found


@dataclass(frozen=True)
class MissionSpec:
    """A whole mission.

    Attributes:
        name: Mission name.
        description: Free text.
        initial: The first state.
        states: States by name, in the order written.
        path: The file the mission came from.
        location: Where the mission's top level starts.
        robot: The robot the mission is written for (``--robot`` overrides it), or ``None``.
        world: The simulator world it is written for (``--world`` overrides it), or ``None``.
        robot_location: Where ``robot`` was written, or ``None``.
        world_location: Where ``world`` was written, or ``None``.
        plots: Condition values recorded each tick as the student's own channels
            (``plot:``): ``(expression, compiled guard)``.
    """

    name: str
    initial: str
    states: Mapping[str, StateSpec]
    description: str = ""
    path: str = "<mission>"
    location: Location | None = None
    robot: str | None = None
    world: str | None = None
    robot_location: Location | None = field(default=None, compare=False, repr=False)
    world_location: Location | None = field(default=None, compare=False, repr=False)
    plots: tuple[tuple[str, Any], ...] = ()

    def requires(self) -> frozenset[str]:
        """Every capability the mission's actions and guards need."""
        needed: set[str] = {c for _, guard in self.plots for c in guard.capabilities}
        for state in self.states.values():
            for action in state.actions():
                needed |= action.requires
            for transition in state.targets():
                needed |= set(getattr(transition.guard, "capabilities", ()))
        return frozenset(needed)
