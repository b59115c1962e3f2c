'''Python missions: a class whose attributes are states, compiled to the same spec as YAML.

Example::

    from roboscript import Drive, Mission, PlayTone, Rotate, state

    class Square(Mission):
        """Drive a 50 cm square and beep at every corner."""

        side = state(Drive(distance_mm=500, speed_mm_s=150), initial=True, on_done="corner")
        corner = state(Rotate(angle_deg=90), on_done="beep")
        beep = state(
            PlayTone(frequency_hz=880, duration_s=0.2),
            on_done=[("four_sides_done", "finished"), "side"],
        )
        finished = state(final="success")

        def four_sides_done(self) -> bool:
            return self.visits("side") >= 4

Each ``state(...)`` is one state, named after its attribute. A transition names its target
state as text (or as the state object itself). A condition is the name of a method of the
class (a *guard method* returning True or False) or, when it is not a plain name, a
condition expression as in YAML (``"range.distance_cm < 20"``). Guard methods read the
mission's values through ``self`` (:meth:`Mission.visits`, :attr:`Mission.elapsed`,
:attr:`Mission.range`, ...); those are read-only.

The class is compiled by :func:`roboscript.mission.python_compiler.compile_mission` into a
:class:`~roboscript.mission.spec.MissionSpec` and checked by the same rules as YAML. A mission
file (``roboscript run square.py``) holds one such class.
'''

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, ClassVar, TypeAlias

from roboscript.actions.base import Action

if TYPE_CHECKING:
    from roboscript.mission.guards import GuardEnv

__all__ = [
    "BumperReading",
    "Choice",
    "Condition",
    "LineReading",
    "Mission",
    "RangeReading",
    "Route",
    "StateDef",
    "state",
]

Condition: TypeAlias = "str | Callable[[Any], object]"
"""A guard method's name, a condition expression, or a function taking the mission."""

Choice: TypeAlias = "str | StateDef | tuple[Condition, str | StateDef]"
"""A target state, or ``(condition, target state)`` taken only if the condition holds."""

Route: TypeAlias = "Choice | list[Choice] | None"
"""One choice, or a list of choices tried in order."""


class StateDef:
    """One state of a Python mission, as :func:`state` wrote it.

    The compiler reads these; missions only create them. ``where`` is the file and line of
    the ``state(...)`` call, used when the file's source cannot be read.
    """

    def __init__(
        self,
        action: Action | None,
        *,
        initial: bool,
        routes: dict[str, Route],
        when: Route,
        during: Sequence[Action],
        timeout_s: float | None,
        final: bool | str | None,
        description: str,
        where: tuple[str, int] | None,
    ) -> None:
        self.action = action
        self.initial = initial
        self.routes = routes
        self.when = when
        self.during = during
        self.timeout_s = timeout_s
        self.final = final
        self.description = description
        self.where = where
        self.names: list[str] = []

    def __set_name__(self, owner: type, name: str) -> None:
        self.names.append(name)

    def __repr__(self) -> str:
        name = self.names[0] if self.names else "?"
        return f"<state {name}>"


def state(
    action: Action | None = None,
    *,
    initial: bool = False,
    on_done: Route = None,
    on_failed: Route = None,
    on_timeout: Route = None,
    when: Route = None,
    during: Sequence[Action] = (),
    timeout_s: float | None = None,
    final: bool | str | None = None,
    description: str = "",
) -> StateDef:
    """Declare a state of a :class:`Mission` (assign it to a class attribute: its name).

    Args:
        action: What the state does, e.g. ``Drive(distance_mm=500)``; ``None`` for a state
            that only waits for a condition. The action is a template: every visit to the
            state runs a fresh copy of it.
        initial: True for the state the mission starts in (exactly one state).
        on_done: Where to go when the action ends ``done``: a state name, a
            ``(condition, state)`` choice, or a list of those tried in order.
        on_failed: The same, when the action ends ``failed`` (stalled, bumped, ...).
        on_timeout: The same, when ``timeout_s`` passes (or the action times out).
        when: ``(condition, state)`` choices checked every tick while in the state; the first
            that holds moves on, interrupting the action.
        during: Actions run alongside ``action`` while in the state (a tune while driving),
            stopped when the state is left.
        timeout_s: The state's time bound, seconds (> 0), or ``None``.
        final: ``"success"`` (or True) or ``"failure"``: the mission ends when this state's
            action, if any, has finished.
        description: Free text.

    Returns:
        The state, for the class body to assign.
    """
    where = None
    try:
        caller = sys._getframe(1)  # where the class body calls state(), for messages
        where = (caller.f_code.co_filename, caller.f_lineno)
    except ValueError:
        pass
    return StateDef(
        action,
        initial=initial,
        routes={"done": on_done, "failed": on_failed, "timeout": on_timeout},
        when=when,
        during=during,
        timeout_s=timeout_s,
        final=final,
        description=description,
        where=where,
    )


# ---------------------------------------------------------------------------- the readings


class RangeReading:
    """A distance sensor, as a guard method reads it (needs ``range`` or ``side_range``)."""

    def __init__(self, env: GuardEnv, root: str = "range") -> None:
        self._env = env
        self._root = root

    @property
    def distance_mm(self) -> float:
        """Distance to what is in front of the sensor, mm; no echo reads as infinity."""
        return float(self._env.sensor(self._root, "distance_mm"))

    @property
    def distance_cm(self) -> float:
        """The same in cm."""
        return float(self._env.sensor(self._root, "distance_cm"))


class BumperReading:
    """The bump switches, as a guard method reads them (needs ``bumper``)."""

    def __init__(self, env: GuardEnv) -> None:
        self._env = env

    @property
    def left(self) -> bool:
        """The left switch is pressed."""
        return bool(self._env.sensor("bumper", "left"))

    @property
    def right(self) -> bool:
        """The right switch is pressed."""
        return bool(self._env.sensor("bumper", "right"))

    @property
    def any(self) -> bool:
        """Any switch is pressed."""
        return bool(self._env.sensor("bumper", "any"))


class LineReading:
    """The downward line sensors, as a guard method reads them (needs ``line``)."""

    def __init__(self, env: GuardEnv) -> None:
        self._env = env

    @property
    def left(self) -> float:
        """Left sensor, 0 (white) to 1023 (black)."""
        return float(self._env.sensor("line", "left"))

    @property
    def center(self) -> float:
        """Centre sensor, 0 (white) to 1023 (black)."""
        return float(self._env.sensor("line", "center"))

    @property
    def right(self) -> float:
        """Right sensor, 0 (white) to 1023 (black)."""
        return float(self._env.sensor("line", "right"))

    @property
    def any(self) -> bool:
        """Any sensor is over a dark line."""
        return bool(self._env.sensor("line", "any"))


# ----------------------------------------------------------------------------- the mission


class Mission:
    """Base class of a Python mission: subclass it, and give it states and guard methods.

    Class attributes a mission may set (all optional):

    * ``name``: the mission's name (default: the class name in kebab case, ``bump-and-turn``
      for ``BumpAndTurn``);
    * ``robot``: the robot it is written for (``--robot`` overrides it), e.g. ``"mirto"``;
    * ``world``: the simulator world it is written for (``--world`` overrides it);
    * ``requires``: capabilities the guard methods read that roboscript cannot see in their
      code (for example through a helper function outside the class), e.g. ``("range",)``.

    The class docstring is the mission's description.

    While the mission runs, guard methods read these values through ``self``. They are
    read-only; they are not available outside a run.
    """

    name: ClassVar[str | None] = None
    robot: ClassVar[str | None] = None
    world: ClassVar[str | None] = None
    requires: ClassVar[tuple[str, ...]] = ()

    def __init__(self) -> None:
        self._env: GuardEnv | None = None
        self._state_names: frozenset[str] | None = None

    def _bind(self, env: GuardEnv, state_names: frozenset[str]) -> None:
        """Give this object the values of one run (the compiler does this)."""
        self._env = env
        self._state_names = state_names

    def _values(self) -> GuardEnv:
        env: GuardEnv | None = getattr(self, "_env", None)
        if env is None:
            raise RuntimeError("a mission's values can only be read while the mission runs")
        return env

    def visits(self, state: str) -> int:
        """How many times ``state`` has been entered so far (the current visit included).

        Raises:
            KeyError: There is no state of that name.
        """
        env = self._values()
        names = getattr(self, "_state_names", None)
        if names is not None and state not in names:
            raise KeyError(f"there is no state '{state}'")
        return env.visits(state)

    @property
    def elapsed(self) -> float:
        """Seconds since the mission started."""
        return float(self._values().sensor("elapsed", None))

    @property
    def state_time(self) -> float:
        """Seconds since the current state was entered."""
        return float(self._values().sensor("state_time", None))

    @property
    def heading_deg(self) -> float:
        """How far the robot has turned since the start, -180 to 180, clockwise positive."""
        return float(self._values().sensor("heading_deg", None))

    @property
    def range(self) -> RangeReading:
        """The distance sensor: ``self.range.distance_cm``, ``self.range.distance_mm``."""
        return RangeReading(self._values())

    @property
    def side_range(self) -> RangeReading:
        """The sideways distance sensor (wall following): ``self.side_range.distance_cm``."""
        return RangeReading(self._values(), "side_range")

    @property
    def bumper(self) -> BumperReading:
        """The bump switches: ``self.bumper.left``, ``.right``, ``.any``."""
        return BumperReading(self._values())

    @property
    def line(self) -> LineReading:
        """The line sensors: ``self.line.left``, ``.center``, ``.right``, ``.any``."""
        return LineReading(self._values())
