"""Missions run from Python: ``roboscript.run(...)`` in a script, a REPL or a notebook.

Example::

    >>> import roboscript
    >>> result = roboscript.run("missions/square.yaml", seed=3)  # doctest: +SKIP
    >>> result.outcome, result.final_state  # doctest: +SKIP
    ('success', 'finished')

A run here is exactly a ``roboscript run``: the same loading and checks, the same session
(:func:`roboscript.session.run_session`), so the same mission, robot, world and seed give the
same result. The robot is stopped before :func:`run` returns or raises, whatever happens. In a
Jupyter notebook the result displays as the replay viewer (:mod:`roboscript.replay.viewer`).

``python my_mission.py`` runs the file's mission when the file ends with
``if __name__ == "__main__": MyMission.main()``
(:meth:`roboscript.mission.python_api.Mission.main`, which calls :func:`main` here).
"""

from __future__ import annotations

import contextlib
import html
import operator
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, NoReturn

from roboscript.errors import InputError, RoboscriptError
from roboscript.interrupts import handled
from roboscript.mission import fit_to_robot, mission_for_robot
from roboscript.mission.builder import MissionProblemsError
from roboscript.mission.checks import check_world_regions
from roboscript.mission.python_api import Mission, mission_file, note_mission_run
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.spec import MissionSpec
from roboscript.mission.student_code import is_student_file, stuck_at
from roboscript.replay.recording import Recorder, Recording
from roboscript.replay.session_tap import RunRecording
from roboscript.run_record import NOT_SERIALISED, Pose, RunRecord, Tone
from roboscript.session import Session, run_session, session_record
from roboscript.watchdog import DEFAULT_LIMIT_S, Watchdog

__all__ = ["RunResult", "main", "run"]

NOTEBOOK_FRAME_RATE_HZ = 25.0
"""Frames a second a notebook's viewer embeds (every state change is kept): a 60 s run stays
small enough for the notebook file."""
NOTEBOOK_VIEWER_HEIGHT_PX = 900
"""The viewer's height in a notebook cell."""


@dataclass(frozen=True)
class RunResult(RunRecord):
    """One finished mission run, as :func:`run` returns it: its record and its replay.

    The record's fields (:class:`~roboscript.run_record.RunRecord`: ``mission``, ``robot``,
    ``outcome``, ``final_state``, ``reason``, ``duration_s``, ``states``, ``transitions``,
    ``sim``) are ``roboscript run --json``'s, and :attr:`summary` is that object.

    Attributes:
        warnings: The mission's warnings, each as ``file:line:col: warning: ...``, then the
            run's: a tick whose code took longer than a tick (``warning: the mission's code at
            FILE:LINE in NAME took 0.05 s in one tick ...``, printed on standard error when it
            happens, once a run, exactly as ``roboscript run`` prints it).
        recording: The run tick by tick (:class:`~roboscript.replay.recording.Recording`), or
            ``None`` when run with ``record=False``.
    """

    warnings: tuple[str, ...] = field(default=(), metadata=NOT_SERIALISED)
    recording: Recording | None = field(
        default=None, repr=False, compare=False, metadata=NOT_SERIALISED
    )

    @property
    def summary(self) -> dict[str, Any]:
        """The ``roboscript run --json`` object of this run."""
        return self.to_dict()

    @property
    def world(self) -> str | None:
        """The simulator world's name, or ``None`` on a real robot."""
        return self.sim.world if self.sim is not None else None

    @property
    def seed(self) -> int | None:
        """The simulator seed, or ``None`` on a real robot."""
        return self.sim.seed if self.sim is not None else None

    @property
    def tones(self) -> tuple[Tone, ...]:
        """Tones the simulator heard, as ``(t s, frequency Hz, duration s)``."""
        return self.sim.tones if self.sim is not None else ()

    @property
    def path(self) -> tuple[tuple[float, float, float, float], ...]:
        """The pose over time as ``(t s, x mm, y mm, heading deg)``: every 0.1 s from the
        simulator, or each recorded tick's estimate on a real robot (``()`` without one)."""
        if self.sim is not None:
            return self.sim.path
        frames = self.recording.frames if self.recording is not None else []
        return tuple(
            (float(f["t"]), float(f["pose"][0]), float(f["pose"][1]), float(f["pose"][2]))
            for f in frames
            if isinstance(f.get("pose"), list) and len(f["pose"]) == 3
        )

    @property
    def final_pose(self) -> Pose | None:
        """Where the robot ended: the simulator's true pose, or on a real robot the pose its
        wheels estimate (``None`` without wheels or without a recording)."""
        if self.sim is not None:
            return self.sim.final_pose
        path = self.path
        return Pose(*path[-1][1:]) if path else None

    def columns(self) -> dict[str, list[Any]]:
        """The run tick by tick as columns: ``t_s``, ``state``, ``why``, the pose, the
        sensors, the motors, the values the mission logged (``log.NAME``) and what it
        printed; ``pandas.DataFrame(result.columns())`` makes a table to plot.

        Raises:
            ValueError: The run was not recorded (``record=False``).
        """
        if self.recording is None:
            raise ValueError("this run was not recorded: run it with record=True")
        # the columns load only when a run is asked for them
        from roboscript.replay.columns import run_columns

        return run_columns(self.recording)

    @property
    def succeeded(self) -> bool:
        """Whether the mission ended in a success state."""
        return self.outcome == "success"

    @property
    def states_visited(self) -> list[str]:
        """Each state entered at least once, in the order first entered."""
        return list(dict.fromkeys(name for _, name in self.states))

    def __repr__(self) -> str:
        return f"<RunResult {self}>"

    def __str__(self) -> str:
        ended = f" in '{self.final_state}'" if self.final_state else ""
        text = (
            f"{self.mission} on {self.robot}: {self.outcome}{ended} after {self.duration_s:.2f} s"
        )
        if self.reason:
            text += f" ({self.reason})"
        return text

    def _repr_html_(self) -> str:
        """Jupyter's rich display: the replay viewer, in a frame of its own."""
        if self.recording is None:
            return f"<p>{html.escape(str(self))} (run with record=True to replay it)</p>"
        # only a notebook draws the replay page: its script and style load with it
        from roboscript.replay.viewer import recording_title, viewer_block, viewer_page

        page = viewer_page(
            viewer_block(self.recording, rate_hz=NOTEBOOK_FRAME_RATE_HZ),
            recording_title(self.recording),
        )
        # A frame keeps the page's script and styles away from the notebook's own; the
        # sandbox lets the script draw and nothing else.
        return (
            f'<iframe srcdoc="{html.escape(page, quote=True)}" sandbox="allow-scripts"'
            f' style="width: 100%; height: {NOTEBOOK_VIEWER_HEIGHT_PX}px; border: 0"'
            f' title="{html.escape(str(self), quote=True)}"></iframe>'
        )

    def save(self, path: str | Path) -> Path:
        """Write the recording as a ``roboscript-run`` file (``roboscript view`` opens it).

        Raises:
            ValueError: The run was not recorded (``record=False``).
            OSError: The file cannot be written.
        """
        if self.recording is None:
            raise ValueError("this run was not recorded: run it with record=True")

        recorder = Recorder(self.recording.header, max_frames=len(self.recording.frames) + 1)
        for frame in self.recording.frames:
            recorder.add(frame)
        # the header already names the format: keep the file's result exactly as recorded
        recorder.result = dict(self.recording.result or {})
        target = Path(path)
        recorder.write(target)
        return target


def _spec_and_robot(
    mission: str | Path | type[Mission] | MissionSpec, robot: str | None
) -> tuple[MissionSpec, Any, list[InputError]]:
    if isinstance(mission, MissionSpec):
        return fit_to_robot(mission, [], robot)
    if isinstance(mission, type) and issubclass(mission, Mission):
        spec, warnings = compile_mission(mission)
        return fit_to_robot(spec, warnings, robot)
    if isinstance(mission, str | Path):
        # a Python mission file runs when imported: a loop there must not hang the caller
        with Watchdog(DEFAULT_LIMIT_S, stuck_at, watched=is_student_file):
            return mission_for_robot(mission, robot)
    raise TypeError(
        "roboscript.run() takes a mission file's path, a Mission class or a MissionSpec"
        f" (got {type(mission).__name__})"
    )


def run(
    mission: str | Path | type[Mission] | MissionSpec,
    robot: str | None = None,
    world: str | None = None,
    seed: int = 1,
    *,
    port: str | None = None,
    max_time_s: float = 300.0,
    realtime: bool = False,
    record: bool = True,
) -> RunResult:
    """Run a mission to its end, as ``roboscript run`` does, and return what happened.

    Args:
        mission: A mission file (``.yaml`` or ``.py``), a :class:`~roboscript.Mission`
            subclass, or a :class:`~roboscript.mission.spec.MissionSpec`.
        robot: A built-in robot profile or a profile file (default: the mission's robot,
            else ``mirto``).
        world: The simulator world, a name or a file (default: the mission's, else
            ``empty``).
        seed: The simulator seed; the same seed gives the same run.
        port: A serial port or URL of a real robot (``/dev/ttyUSB0``,
            ``socket://host:port``); ``None`` runs the built-in simulator.
        max_time_s: Mission time limit, seconds (> 0); past it the mission fails.
        realtime: Pace the simulator to the wall clock (a real robot always is).
        record: Keep the run tick by tick in :attr:`RunResult.recording` (the replay).

    Returns:
        The finished run; the robot has been told to stop.

    Raises:
        InputError: The mission, robot profile or world is invalid (its message is
            ``file:line:col: error: ...``; ``problems`` lists every problem).
        LinkError: The robot could not be reached.
        KeyboardInterrupt: Ctrl-C (or SIGTERM, SIGHUP) stopped the run; the robot was told
            to stop first. It is a :class:`~roboscript.interrupts.Interrupted` whose text is
            the sentence ``roboscript run`` ends with (``interrupted by Ctrl-C``) and whose
            ``exit_status`` is the command's (130, 143, 129). Signals are handled this way
            only while :func:`run` runs, in the main thread; the program's own handlers are
            back when it returns or raises.
        ValueError: ``max_time_s`` is not more than 0.
        TypeError: ``seed`` is not a whole number.
    """
    if not max_time_s > 0:
        raise ValueError(f"max_time_s must be more than 0 (got {max_time_s})")
    try:  # any whole number a notebook holds (numpy's too), never 3.5, "3" or True
        if isinstance(seed, bool):
            raise TypeError
        seed = operator.index(seed)
    except TypeError:
        # a seed of 3.5 or "3" would reach the simulator's URL and be read there, or not
        raise TypeError(f"seed must be a whole number, like seed=3 (got {seed!r})") from None
    note_mission_run()
    # Ctrl-C, SIGTERM and SIGHUP stop the robot on the way out here as on the command line;
    # the caller's program gets its own handlers back when the run ends.
    with handled():
        return _run(mission, robot, world, seed, port, max_time_s, realtime, record)


def _run(
    mission: str | Path | type[Mission] | MissionSpec,
    robot: str | None,
    world: str | None,
    seed: int,
    port: str | None,
    max_time_s: float,
    realtime: bool,
    record: bool,
) -> RunResult:
    recording = RunRecording() if record else None
    # what a Python mission prints while it loads is recorded too, as before the start
    with recording.loading() if recording is not None else contextlib.nullcontext():
        spec, profile, warnings = _spec_and_robot(mission, robot)
    world_name = world or spec.world or "empty"
    _check_world_regions(spec, world_name if port is None or port.startswith("sim:") else None)
    slow: list[str] = []

    def warn_slow(text: str) -> None:  # said when it happens, as ``roboscript run`` says it
        slow.append(text)
        sys.stderr.write(text + "\n")
        sys.stderr.flush()

    session = run_session(
        spec,
        profile,
        port=port,
        world=world_name,
        seed=seed,
        realtime=realtime,
        max_time_s=max_time_s,
        recording=recording,
        on_slow_tick=warn_slow,
    )
    if session.interruption is not None:
        raise session.interruption  # the robot is stopped by now
    return _result(session, recording, [*(w.format() for w in warnings), *slow])


def _check_world_regions(spec: MissionSpec, world: str | None) -> None:
    problems = check_world_regions(spec, world)
    if problems:
        raise MissionProblemsError(problems)


def _result(session: Session, recording: RunRecording | None, warnings: Sequence[str]) -> RunResult:
    recorded = None
    if recording is not None and recording.recorder is not None:
        recorded = recording.recorder.recording()
    record = session_record(session)
    return RunResult(
        **{item.name: getattr(record, item.name) for item in fields(record)},
        warnings=tuple(warnings),
        recording=recorded,
    )


def _mission_file(mission: type[Mission] | str | Path) -> str:
    if isinstance(mission, str | Path):
        return str(mission)
    source = mission_file(mission)
    if source is None:
        raise RoboscriptError(
            f"{mission.__name__}.main() runs a mission written in a .py file; here, use"
            f" roboscript.run({mission.__name__})"
        )
    return source


def main(mission: type[Mission] | str | Path, argv: Sequence[str] | None = None) -> NoReturn:
    """``roboscript run FILE [OPTIONS]`` for the file that holds ``mission``; exits.

    The options are those of ``roboscript run`` (``--robot``, ``--world``, ``--seed``,
    ``--port``, ``--max-time``, ``--realtime``, ``--json``, ``--record``, ``--view``, ...);
    the exit status too (0 success, 1 failure, 2 invalid input, 130 Ctrl-C).

    Args:
        mission: A :class:`~roboscript.Mission` subclass (its file is run) or a file.
        argv: The options; default: the command line's (``sys.argv[1:]``).
    """
    note_mission_run()
    try:
        path = _mission_file(mission)
    except RoboscriptError as exc:
        sys.stderr.write(f"error: {exc}\n")
        raise SystemExit(2) from None
    # the command line's parsers load only for a program run as a command
    from roboscript.cli import main as cli_main

    options = list(sys.argv[1:] if argv is None else argv)
    cli_main(["run", path, *options])
