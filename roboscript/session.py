"""One mission run on one robot: connect, run the mission to its end, summarise what happened.

``roboscript run`` and the grader (:mod:`roboscript.grading.run`) both run missions through
:func:`run_session`, so a graded run is exactly the run a student gets at home with the same
robot, world and seed. :func:`session_record` tells what happened
(:class:`~roboscript.run_record.RunRecord`, whose JSON is the ``run --json`` object).
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from roboscript.errors import LinkError
from roboscript.interrupts import Interrupted, exit_status_for, reason_for
from roboscript.mission.cause import TransitionCause
from roboscript.mission.channels import stamped_prints
from roboscript.mission.runner import MissionResult, MissionRunner
from roboscript.mission.spec import MissionSpec
from roboscript.mission.student_code import is_student_file, stuck_at
from roboscript.profiles import RobotProfile
from roboscript.robot import Robot
from roboscript.run_record import Pose, RunRecord, SimulatedRun, Tone
from roboscript.sim.world import Region
from roboscript.watchdog import DEFAULT_LIMIT_S, TICK_BUDGET, RunawayCode, TooSlow, Watchdog

if TYPE_CHECKING:
    from roboscript.replay.session_tap import RunRecording

__all__ = ["Session", "WorldMap", "run_session", "session_record"]


@dataclass(frozen=True)
class WorldMap:
    """What a mission may know of its world: the named regions and where it starts.

    Attributes:
        regions: The world's regions by name (each has ``contains(x_mm, y_mm)``).
        start: The start pose ``(x_mm, y_mm, heading_deg)``, heading clockwise from north.
    """

    regions: Mapping[str, Region]
    start: tuple[float, float, float]

    @classmethod
    def of(cls, simulation: Any) -> WorldMap:
        """The map of an in-process simulation, read before the mission moves the robot."""
        body = simulation.body
        return cls(dict(simulation.world.regions), (body.x_mm, body.y_mm, body.heading_deg))

    def to_json(self) -> str:
        """The map as JSON (a graded run hands it to the mission's process)."""
        regions = {
            name: {"center": list(r.center), "radius_mm": r.radius_mm, "points": r.points}
            for name, r in self.regions.items()
        }
        return json.dumps({"regions": regions, "start": list(self.start)})

    @classmethod
    def from_json(cls, text: str) -> WorldMap:
        """Read :meth:`to_json`'s output."""
        data = json.loads(text)
        regions = {
            str(name): Region(
                str(name),
                (float(r["center"][0]), float(r["center"][1])),
                None if r["radius_mm"] is None else float(r["radius_mm"]),
                tuple((float(x), float(y)) for x, y in r["points"]),
            )
            for name, r in data["regions"].items()
        }
        x_mm, y_mm, heading_deg = (float(v) for v in data["start"])
        return cls(regions, (x_mm, y_mm, heading_deg))


@dataclass
class Session:
    """A finished mission run.

    Attributes:
        result: How the mission ended.
        robot: The robot it ran on (closed by now; its simulation, if any, keeps the log).
        profile: The robot's profile.
        start_time_s: Scheduler time at which the mission started; the mission clock's zero.
        code_stopped: ``"hung"`` when the mission's code did not return and was stopped,
            ``"too slow"`` when it took too long per tick too often (:mod:`roboscript.watchdog`),
            else ``""``.
        interrupted_by: The signal's exception (``KeyboardInterrupt``) that ended the run
            (its traceback says where it came from: a graded run has no Ctrl-C, so one raised
            there is the student's own code's), else ``None``; what :attr:`interrupted` and
            :attr:`interruption` are read from.
    """

    result: MissionResult
    robot: Robot
    profile: RobotProfile
    start_time_s: float
    code_stopped: Literal["", "hung", "too slow"] = ""
    interrupted_by: KeyboardInterrupt | None = field(default=None, repr=False, compare=False)

    @property
    def interrupted(self) -> int:
        """The exit status the signal that ended the run asks for (130 Ctrl-C, 143 SIGTERM,
        129 SIGHUP), else 0."""
        return 0 if self.interrupted_by is None else exit_status_for(self.interrupted_by)

    @property
    def interruption(self) -> Interrupted | None:
        """The signal that ended the run (its status is ``interrupted``), or ``None``."""
        return Interrupted(self.interrupted - 128) if self.interrupted else None

    @property
    def simulation(self) -> Any:
        """The in-process simulation, or ``None`` for a robot reached on a port."""
        return self.robot.simulation

    @property
    def wire_log_error(self) -> str | None:
        """Why the wire log (``wire_log=``) could not be written in full, or ``None``."""
        wire_log = self.robot.driver.link.wire_log
        return wire_log.error if wire_log is not None else None

    def mission_time_s(self, sim_time_s: float) -> float:
        """A simulator time on the mission clock (0 when the mission started), to the ms."""
        return round(sim_time_s - self.start_time_s, 3)

    def mission_path(self) -> list[tuple[float, float, float, float]]:
        """The simulator's path samples from the mission's start: ``(t s, x mm, y mm, deg)``.

        ``run --json`` and the grader both report these, so a graded run is the same run.
        """
        return list(self.simulation.path_since(self.start_time_s))

    def mission_tones(self) -> list[tuple[float, float, float]]:
        """The tones the simulator heard: ``(t s on the mission clock, Hz, duration s)``."""
        return list(self.simulation.tones_since(self.start_time_s))

    def final_pose(self) -> tuple[float, float, float]:
        """The simulated body's pose at the end: ``(x mm, y mm, heading deg)``, rounded."""
        return tuple(self.simulation.final_pose())


def run_session(
    spec: MissionSpec,
    profile: RobotProfile,
    *,
    port: str | None = None,
    world: str = "empty",
    seed: int = 1,
    start: tuple[float, float, float] | None = None,
    realtime: bool = False,
    wire_log: str | None = None,
    max_time_s: float = 300.0,
    on_state: Callable[[float, str, TransitionCause], None] | None = None,
    on_connected: Callable[[Robot], None] | None = None,
    on_tick: Callable[[MissionRunner, Robot], None] | None = None,
    runaway_after_s: float | None = DEFAULT_LIMIT_S,
    recording: RunRecording | None = None,
    world_map: WorldMap | None = None,
    on_slow_tick: Callable[[str], None] | None = None,
    on_print: Callable[[str], None] | None = None,
) -> Session:
    """Connect the robot, run ``spec`` on it until it ends or ``max_time_s`` passes, stop it.

    Args:
        spec: The mission.
        profile: The robot to run it on.
        port: A serial port or URL; ``None`` means the in-process simulator.
        world: Simulator world (name or path), for ``sim://``.
        seed: Simulator seed, for ``sim://``.
        start: Simulator start pose ``(x_mm, y_mm, heading_deg)``, or the world's.
        realtime: Pace a simulated robot to the wall clock.
        wire_log: Record every byte to this file.
        max_time_s: Mission time limit, seconds on the scheduler clock from the mission's
            first tick; past it the mission fails.
        on_state: Called with ``(mission time s, state, cause)`` whenever a state is entered.
        on_connected: Called with the robot once the handshake is done, before the mission.
        on_tick: Called after every scheduler tick with the runner and the robot (progress).
        runaway_after_s: Seconds of its own time (not the machine's load, not the wire) one
            tick's code (a behaviour, a condition) may run before the mission ends in error at
            the line where it is stuck (:mod:`roboscript.watchdog`); ``None`` turns the
            watchdog off, and with it the per-tick rule below.
        recording: Records the run tick by tick (``run --record``, the live view); it is
            closed with the result once the robot is stopped.
        world_map: The world's regions and the start pose, for ``in_region`` when the world
            is not in this process (a graded run's mission); by default the in-process
            simulator's.
        on_slow_tick: Called once, with a one-line warning naming the line and the time it
            took, the first time a tick's code takes longer than
            :attr:`~roboscript.watchdog.TickBudget.slow_tick_s`. On a simulated robot not paced
            to the wall clock (as every graded run), once
            slow ticks add up to :attr:`~roboscript.watchdog.TickBudget.too_slow_after_s`
            the mission ends in error as too slow, exactly as a graded run does.
        on_print: Called with each line the mission prints while it runs (without its
            newline), after the line is on the terminal and in ``recording``.

    Returns:
        The finished run. A lost link ends the mission with outcome ``error``; so do Ctrl-C,
        SIGTERM and SIGHUP (see :mod:`roboscript.interrupts`), which also set
        ``interrupted``, and code stuck in a loop; the robot is always told to stop first.

    Raises:
        LinkError: The robot could not be reached.
        ProfileError: Unknown robot.
    """
    robot = Robot.connect(
        profile, port, world=world, seed=seed, start=start, realtime=realtime, wire_log=wire_log
    )
    try:  # from here on, every way out (a signal while the run is set up too) stops the robot
        if world_map is None and robot.simulation is not None:
            world_map = WorldMap.of(robot.simulation)
        if on_connected is not None:
            on_connected(robot)
        sim = robot.simulation
        capabilities = robot.capabilities
        if recording is not None:  # the mission's commands are seen on their way to the driver
            capabilities = recording.attach(robot, spec, profile)
        runner = MissionRunner(
            spec,
            capabilities,
            robot_name=profile.name,
            gains=profile.gains,
            device_errors=robot.driver.take_device_error,
            on_state=on_state,
            # The path (for --json and grading) starts where the mission starts.
            on_start=(lambda now_s: sim.start_mission()) if sim is not None else None,
            # in_region places the robot's odometry at the start in the world's map: the same
            # answer in-process and in a graded run, whose world is in the grader's process
            regions=world_map.regions if world_map is not None else None,
            origin=world_map.start if world_map is not None else None,
        )
        watchdog = (
            Watchdog(
                runaway_after_s,
                stuck_at,
                budget=TICK_BUDGET,
                on_slow=(
                    None
                    if on_slow_tick is None
                    else (
                        lambda spent_s, where: on_slow_tick(
                            TICK_BUDGET.slow_message(spent_s, where)
                        )
                    )
                ),
                # A real robot's driver may wait on its port inside a tick, and a run paced to the
                # wall clock shares its process with the live view's threads (a wait for the
                # interpreter's lock is not told apart from the code's own time): warn only.
                end_when_too_slow=sim is not None and not realtime,
                watched=is_student_file,
            )
            if runaway_after_s is not None
            else None
        )
        robot.scheduler.add(runner if watchdog is None else watchdog.timed(runner.tick), "think")
        if on_tick is not None:

            def after_tick(now_s: float, dt_s: float) -> None:
                on_tick(runner, robot)

            robot.scheduler.add(after_tick, "after")
        if recording is not None:

            def record_tick(now_s: float, dt_s: float) -> None:
                recording.tick(runner)

            robot.scheduler.add(record_tick, "after")
    except BaseException:
        robot.close()
        raise
    interrupted_by: KeyboardInterrupt | None = None
    code_stopped: Literal["", "hung", "too slow"] = ""
    try:
        with robot:
            try:
                with (
                    watchdog or contextlib.nullcontext(),
                    stamped_prints(runner.elapsed, _print_hooks(recording, on_print)),
                ):
                    # The limit is on the mission's clock (from its first tick, as its
                    # duration is): a busy machine that starts the first tick late never
                    # ends the mission short of its limit.
                    robot.scheduler.run(
                        until=lambda: runner.finished or runner.elapsed() >= max_time_s - 1e-9
                    )
            except RunawayCode as exc:
                robot.stop()
                code_stopped = "too slow" if isinstance(exc, TooSlow) else "hung"
                runner.finish("error", exc.reason)
            except KeyboardInterrupt as exc:  # Ctrl-C, SIGTERM, SIGHUP (roboscript.interrupts)
                robot.stop()
                interrupted_by = exc
                runner.finish("error", reason_for(exc))
            except LinkError as exc:
                robot.stop()
                runner.finish("error", str(exc))
            if not runner.finished:
                runner.finish("failure", runner.out_of_time(max_time_s))
    except LinkError as exc:
        runner.finish("error", str(exc))
    except KeyboardInterrupt as exc:  # while the robot was told to stop and its port closed
        if interrupted_by is None:  # the first signal is the reason
            interrupted_by = exc
        runner.finish("error", reason_for(exc))  # a mission that had ended keeps its outcome
    session = Session(
        runner.result,
        robot,
        profile,
        runner.start_time_s,
        code_stopped,
        interrupted_by,
    )
    if recording is not None:
        recording.finish(session_record(session))
    return session


def _print_hooks(
    recording: RunRecording | None, on_print: Callable[[str], None] | None
) -> Callable[[str], None] | None:
    """Where each printed line goes besides the terminal: the recording, then ``on_print``."""
    record = recording.printed if recording is not None else None
    if record is None or on_print is None:
        return record or on_print
    told = on_print

    def both(line: str) -> None:
        record(line)
        told(line)

    return both


def session_record(session: Session) -> RunRecord:
    """The run's record (``run --json``); simulator times are on the mission clock."""
    result = session.result
    sim = session.simulation
    simulated = None
    if sim is not None:
        simulated = SimulatedRun(
            seed=sim.seed,
            world=sim.world.name,
            final_pose=Pose(*session.final_pose()),
            distance_travelled_mm=round(sim.log.distance_travelled_mm, 1),
            collisions=sim.log.contacts.total,
            tones=tuple(Tone(*tone) for tone in session.mission_tones()),
            path=tuple(session.mission_path()),
            # a run of hours: the first tones are listed, the rest counted
            tones_not_listed=sim.log.tones.more,
        )
    return RunRecord(
        mission=result.mission,
        robot=session.profile.name,
        outcome=result.outcome,
        final_state=result.final_state,
        reason=result.reason,
        duration_s=round(result.duration_s, 3),
        states=tuple((round(t, 3), name) for t, name in result.states),
        transitions=tuple(result.transitions()),
        # a long loop: only the first and last states are listed
        states_dropped=result.states_dropped,
        code_stopped=session.code_stopped,
        sim=simulated,
    )
