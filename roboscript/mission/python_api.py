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

import atexit
import inspect
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, NoReturn, TypeAlias

from roboscript.actions.base import Action
from roboscript.errors import RoboscriptError

if TYPE_CHECKING:
    from roboscript.mission.guards import GuardEnv

__all__ = [
    "BumperReading",
    "ButtonsReading",
    "Choice",
    "ColorReading",
    "Condition",
    "DrivenReading",
    "LineReading",
    "Mission",
    "PoseReading",
    "RangeReading",
    "Route",
    "StateDef",
    "mission_file",
    "note_mission_run",
    "run_command",
    "state",
]

LOADED_PREFIX = "_roboscript_"
"""How the names of the modules roboscript loads a student's file as begin."""

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


class DrivenReading:
    """How far the robot has driven, forwards or back, as its wheels measure it (needs
    ``drive_base``). Turning on the spot drives 0 mm."""

    def __init__(self, env: GuardEnv) -> None:
        self._env = env

    @property
    def total_mm(self) -> float:
        """Distance driven since the mission started, mm."""
        return float(self._env.sensor("driven", "total_mm"))

    @property
    def total_cm(self) -> float:
        """The same in cm."""
        return float(self._env.sensor("driven", "total_cm"))

    @property
    def state_mm(self) -> float:
        """Distance driven since the current state was entered, mm."""
        return float(self._env.sensor("driven", "state_mm"))

    @property
    def state_cm(self) -> float:
        """The same in cm."""
        return float(self._env.sensor("driven", "state_cm"))


class PoseReading:
    """Where the robot is, from its own odometry, measured from where the mission started
    (needs ``drive_base``): ``x_mm`` to the right of the start point, ``y_mm`` ahead of it."""

    def __init__(self, env: GuardEnv) -> None:
        self._env = env

    @property
    def x_mm(self) -> float:
        """mm to the right of the start point (left is negative)."""
        return float(self._env.sensor("pose", "x_mm"))

    @property
    def y_mm(self) -> float:
        """mm ahead of the start point (behind is negative)."""
        return float(self._env.sensor("pose", "y_mm"))

    @property
    def heading_deg(self) -> float:
        """Turn since the start, degrees clockwise, -180 to 180 (as ``heading_deg``)."""
        return float(self._env.sensor("pose", "heading_deg"))


class ColorReading:
    """The colour sensor, as a guard method reads it (needs ``color``)."""

    def __init__(self, env: GuardEnv) -> None:
        self._env = env

    @property
    def reflection(self) -> float:
        """Light reflected by the floor, 0 (black) to 100 (white) percent; not-a-number
        before the first reading (every comparison with it is False)."""
        return float(self._env.sensor("color", "reflection"))

    @property
    def name(self) -> str | None:
        """The colour seen (``"black"``, ``"white"``, ``"red"``, ...), or ``None``."""
        # Imported here: the guards module pulls in YAML, which `import roboscript` avoids.
        from roboscript.mission.guards import COLOR_NAMES

        return next((c for c in COLOR_NAMES if self._env.sensor("color", c)), None)

    @property
    def rgb(self) -> tuple[int, int, int]:
        """Raw red, green and blue, each 0-1023 (zeros before the first reading)."""
        # the guards module pulls in YAML, which `import roboscript` avoids
        from roboscript.mission.guards import RGB_NAMES

        red, green, blue = (int(self._env.sensor("color", channel)) for channel in RGB_NAMES)
        return (red, green, blue)


class ButtonsReading:
    """The robot's own buttons (a SPIKE hub's left and right), as a guard method reads them
    (needs ``buttons``)."""

    def __init__(self, env: GuardEnv) -> None:
        self._env = env

    @property
    def left(self) -> bool:
        """The left button is held down."""
        return bool(self._env.sensor("buttons", "left"))

    @property
    def right(self) -> bool:
        """The right button is held down."""
        return bool(self._env.sensor("buttons", "right"))

    @property
    def any(self) -> bool:
        """Either button is held down."""
        return bool(self._env.sensor("buttons", "any"))


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

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        _remind_to_run(cls)

    @classmethod
    def main(cls, argv: Sequence[str] | None = None) -> NoReturn:
        """Run this mission as ``roboscript run`` runs its file, then exit with its status.

        End a mission file with it, and ``python my_mission.py`` runs the mission::

            if __name__ == "__main__":
                Square.main()

        Args:
            argv: ``roboscript run``'s options (``--robot``, ``--world``, ``--seed``,
                ``--port``, ``--view``, ...); default: the command line's.
        """
        if cls.__module__.startswith(LOADED_PREFIX):
            # roboscript is loading the file (run, check, grade): it runs the mission itself
            raise RoboscriptError(
                f"{cls.__name__}.main() runs the mission when Python runs this file, not while"
                f' roboscript loads it (put it under if __name__ == "__main__":)'
            )
        note_mission_run()
        path = mission_file(cls)
        if path is None:
            sys.stderr.write(
                f"error: {cls.__name__}.main() runs a mission written in a .py file; here, use"
                f" roboscript.run({cls.__name__})\n"
            )
            raise SystemExit(2)
        run_command(["run", path, *(sys.argv[1:] if argv is None else argv)])

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
    def driven(self) -> DrivenReading:
        """Distance driven: ``self.driven.total_mm``, ``self.driven.state_mm`` (also ``_cm``)."""
        return DrivenReading(self._values())

    @property
    def pose(self) -> PoseReading:
        """Odometry from the start point: ``self.pose.x_mm``, ``.y_mm``, ``.heading_deg``."""
        return PoseReading(self._values())

    def in_region(self, name: str) -> bool:
        """True while the robot is inside the world's region ``name`` (simulator only).

        Raises:
            KeyError: The world has no region of that name.
            LookupError: The robot is not the simulator (a robot on a port cannot see the world).
        """
        return self._values().in_region(name)

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

    @property
    def color(self) -> ColorReading:
        """The colour sensor: ``self.color.reflection``, ``.name``, ``.rgb``."""
        return ColorReading(self._values())

    @property
    def buttons(self) -> ButtonsReading:
        """The robot's buttons: ``self.buttons.left``, ``.right``, ``.any``."""
        return ButtonsReading(self._values())


# ------------------------------------------------------------ python my_mission.py


def mission_file(cls: type[Mission]) -> str | None:
    """The ``.py`` file that defines ``cls``, or ``None`` (a class typed into a notebook)."""
    holder: object = sys.modules.get(cls.__module__)
    for name in cls.__qualname__.split("."):
        holder = getattr(holder, name, None)
    if holder is not cls:  # made in a namespace of its own (a notebook cell), not its module
        return None
    try:
        source = inspect.getsourcefile(cls)
    except (TypeError, OSError):  # a class typed into a REPL or a notebook has no file
        return None
    return source if source is not None and Path(source).is_file() else None


def run_command(args: Sequence[str]) -> NoReturn:
    """Hand this process over to ``roboscript ARGS``, and exit with its status.

    The command line sits above missions, so a mission file that runs itself
    (:meth:`Mission.main`) runs the command as its user would: the same process on POSIX
    (its exit status, its Ctrl-C), a child process it waits for elsewhere.
    """
    command = [sys.executable, "-m", "roboscript", *args]
    env = dict(os.environ)
    # wherever this roboscript was imported from, the command imports the same one
    home = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (home, env.get("PYTHONPATH")) if p)
    sys.stdout.flush()
    sys.stderr.flush()
    if os.name == "posix":
        os.execve(sys.executable, command, env)
    import subprocess  # only where exec is not how a process hands over (Windows)

    with subprocess.Popen(command, env=env) as child:
        while True:
            try:
                raise SystemExit(child.wait())
            except KeyboardInterrupt:
                continue  # the command stops the robot on Ctrl-C, then exits: wait for it


class _Script:
    """The mission classes the script being run (``python my_mission.py``) defines, and
    whether the program ran a mission."""

    missions: ClassVar[list[type[Mission]]] = []
    ran: ClassVar[bool] = False


def note_mission_run() -> None:
    """Say that this program runs a mission, so the script's own is not run again at exit."""
    _Script.ran = True


def _remind_to_run(cls: type[Mission]) -> None:
    """Remember a mission the script itself defines, to run it when the script ends.

    ``python my_mission.py`` on a file without ``Mission.main()`` would otherwise end
    silently, as if the mission had done nothing.
    """
    script = getattr(sys.modules.get("__main__"), "__file__", None)
    if cls.__module__ != "__main__" or script is None:  # imported, a notebook, the REPL
        return
    if not _Script.missions:
        atexit.register(_run_at_exit, script)
    _Script.missions.append(cls)


def _run_at_exit(script: str) -> None:
    """``python my_mission.py`` runs the mission the file defines, as
    ``roboscript run my_mission.py`` does, with the script's own options (``--robot``,
    ``--world``, ...), when the script ran no mission itself and did not end on an error."""
    if _Script.ran or not _Script.missions or _ended_on_an_error():
        return
    nested = {
        id(definition.action)
        for cls in _Script.missions
        for definition in vars(cls).values()
        if isinstance(definition, StateDef)
    }
    leaves = [cls for cls in _Script.missions if id(cls) not in nested]
    chosen = (leaves or _Script.missions)[-1]
    if not _held_by_its_module(chosen):  # made by code the script ran (exec), not written in it
        return
    name, file = chosen.__name__, Path(script).name
    sys.stderr.write(f"{file} defines the mission {name}: running it (roboscript run {file})\n")
    _Script.ran = True
    run_command(["run", script, *sys.argv[1:]])


def _held_by_its_module(cls: type[Mission]) -> bool:
    """Whether ``cls`` is a class its module holds by its name (what ``roboscript run`` finds
    in the script), not one code the script ran made in a namespace of its own."""
    return getattr(sys.modules.get(cls.__module__), cls.__qualname__, None) is cls


def _ended_on_an_error() -> bool:
    """Whether the script stopped on an exception no one caught (Python printed it, Ctrl-C
    included): its mission is then not run."""
    return getattr(sys, "last_value", None) is not None
