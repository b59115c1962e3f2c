"""Run a mission: a ``transitions`` state machine ticked by the scheduler.

This module is the only user of ``transitions``. It hands the machine only callables it
built itself: ``transitions`` imports any dotted string it is given as a callback, so a
string from a mission file must never reach it. Timeouts are counted on the scheduler's clock
(not with ``transitions``' thread-based ``Timeout``), so simulated runs stay deterministic.

Each tick, in the current state:

1. the ``when`` conditions are tried in order; the first that holds moves on;
2. the action is updated; when it ends, its outcome (``done``, ``failed``, ``timeout``) is
   routed by ``on`` (conditional entries tried in order). A ``failed`` or ``timeout`` nobody
   routes ends the mission in failure, with the action's reason;
3. the state's ``timeout`` is checked.

Entering a final state runs its action (if any) to its end, then the mission ends with the
state's outcome. On the way out of every state the action's ``stop`` is called, and when the
mission ends the wheels are stopped.
"""

from __future__ import annotations

import logging
import math
from collections import Counter
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal, get_args

from transitions import Machine, State

from roboscript import capabilities as cap
from roboscript.actions.base import ActionContext, Outcome, Result
from roboscript.angles import turned_deg, wrap_deg
from roboscript.errors import CapabilityError
from roboscript.mission.cause import TransitionCause
from roboscript.mission.channels import Channels, logging_to
from roboscript.mission.checks import check_regions
from roboscript.mission.guards import GuardEnv
from roboscript.mission.sensor_readings import color_or_buttons
from roboscript.mission.spec import MissionSpec, TransitionSpec
from roboscript.mission.student_code import passes_through, student_fault

__all__ = [
    "MISSION_OUTCOMES",
    "STATES_KEPT_AT_EACH_END",
    "MissionOutcome",
    "MissionResult",
    "MissionRunner",
]

logger = logging.getLogger(__name__)


_RAISED_AGAIN = {"Interrupted", "KeyboardInterrupt", "RunawayCode"}
"""What transitions may drop that is raised again (the names it logs them by)."""


class _QuietTransitions(logging.Filter):
    """Drop transitions' notes that are not news to a student.

    Its note for every method it leaves off our bare model (on purpose), and its note that it
    dropped a Ctrl-C or a stop of stuck code (:func:`~roboscript.interrupts.kept` and the
    watchdog raise those again, and the run ends with its own sentence).
    """

    def filter(self, record: logging.LogRecord) -> bool:
        if "due to model override policy" in record.getMessage():
            return False
        # its arguments: the machine's name, the exception's type name, its text
        args = record.args if isinstance(record.args, tuple) else ()
        return not ("finalize callbacks" in str(record.msg) and _RAISED_AGAIN & set(args))


logging.getLogger("transitions.core").addFilter(_QuietTransitions())


MissionOutcome = Literal["success", "failure", "error"]
"""How a mission ended: ``success`` or ``failure`` (a final state of that kind, or a failure
nothing routed), ``error`` (the run itself broke: Ctrl-C, a lost link, a crash)."""

MISSION_OUTCOMES: tuple[MissionOutcome, ...] = get_args(MissionOutcome)

STATES_KEPT_AT_EACH_END = 4096
"""A mission's record keeps the first and the last this many states it entered. A mission
that loops between states for hours (stopped by ``--max-time``) would otherwise grow its
record, and ``run --json``, without bound; the states left out between are counted in
:attr:`MissionResult.states_dropped`, and visit counts (``visits.NAME``) stay exact."""


@dataclass
class MissionResult:
    """How a mission ended (the core of ``run --json``).

    Attributes:
        mission: Mission name.
        outcome: ``success``, ``failure`` or ``error``.
        final_state: The state the mission ended in.
        reason: Why, when the outcome is not success.
        duration_s: Mission time on the scheduler clock, seconds.
        states: Every state entered, as ``[time_s, name]``; past
            ``2 * STATES_KEPT_AT_EACH_END`` entries only the first and the last
            :data:`STATES_KEPT_AT_EACH_END` of them.
        states_dropped: How many entered states were left out of ``states`` (0 when it
            holds them all); they were entered between its two halves.
        causes: Why each state in ``states`` was entered, one for one.
        code_error: True when an exception from the student's own code (a behaviour, a
            condition method) ended the mission: the grader scores such a run as crashed.
    """

    mission: str
    outcome: MissionOutcome | Literal["running"] = "running"
    final_state: str | None = None
    reason: str | None = None
    duration_s: float = 0.0
    states: list[tuple[float, str]] = field(default_factory=list)
    states_dropped: int = 0
    code_error: bool = False
    causes: list[TransitionCause] = field(default_factory=list)

    def record_state(self, time_s: float, name: str, cause: TransitionCause) -> None:
        """Add an entered state and why, keeping only the first and last ones past the cap."""
        self.states.append((time_s, name))
        self.causes.append(cause)
        if len(self.states) > 2 * STATES_KEPT_AT_EACH_END:
            del self.states[STATES_KEPT_AT_EACH_END]  # the oldest of the last ones
            del self.causes[STATES_KEPT_AT_EACH_END]
            self.states_dropped += 1

    def transitions(self) -> list[dict[str, Any]]:
        """Each entered state with its time and cause, as ``run --json`` writes them."""
        return [
            {"t_s": round(t, 3), "state": name, "cause": cause.to_json()}
            for (t, name), cause in zip(self.states, self.causes, strict=True)
        ]


class _Model:
    """The object ``transitions`` manages: it holds the state and nothing else."""

    state: str

    def trigger(self, name: str) -> bool:  # replaced by the machine (model_override)
        raise NotImplementedError


def _always(event: Any) -> bool:
    """A ``when`` option without a condition: it always holds."""
    return True


class MissionRunner(GuardEnv):
    """Runs one mission on a robot's capabilities.

    Args:
        spec: The mission.
        capabilities: The robot's capability objects by name.
        robot_name: For messages.
        on_state: Called with ``(time_s, state, cause)`` whenever a state is entered.
        on_start: Called with the scheduler time when the mission starts.
        gains: Host PID gains from the robot profile, for the actions' control loops.
        device_errors: Returns the next error the robot reported, or ``None``; such an error
            fails the running action with the robot's reason.
        regions: The world's regions by name, each with ``contains(x_mm, y_mm)``: what
            ``in_region.NAME`` reads. ``None`` when no world is known (a robot on a port).
        origin: Where the mission starts in that world, ``(x_mm, y_mm, heading_deg)``. The
            robot's own odometry (``pose``) is placed there to tell which region it is in, so
            a mission reads the same regions in-process, in a graded run (whose world lives in
            another process) and anywhere else its start is known.
        outer: For an inner state machine, the mission it runs in: ``pose``,
            ``driven.total_*`` and ``in_region`` are the whole mission's.

    Raises:
        CapabilityError: A condition reads ``in_region`` and ``regions`` is ``None``, or it
            names a region the world does not have.
    """

    def __init__(
        self,
        spec: MissionSpec,
        capabilities: Mapping[str, object],
        *,
        robot_name: str = "the robot",
        on_state: Callable[[float, str, TransitionCause], None] | None = None,
        on_start: Callable[[float], None] | None = None,
        gains: Mapping[str, tuple[float, float, float]] | None = None,
        device_errors: Callable[[], str | None] | None = None,
        regions: Mapping[str, Any] | None = None,
        origin: tuple[float, float, float] | None = None,
        outer: MissionRunner | None = None,
    ) -> None:
        self.spec = spec
        self.capabilities = capabilities
        self.ctx = ActionContext(capabilities, robot_name, gains=gains, env=self)
        self.result = MissionResult(spec.name)
        self.finished = False
        self._stopping = False  # finish() has begun stopping (it may have been cut short)
        self.action: Any = None
        self.during: list[Any] = []
        self.action_result: Result | None = None
        self._cause: str | None = None  # the last failure routed by 'on', for the final reason
        # Why the next state is entered: set before a transition fires, taken by _enter.
        self._pending: TransitionCause | None = None
        # What a condition being evaluated has read so far (None: no condition running).
        self._reads: dict[str, float | bool] | None = None
        self.last_cause: TransitionCause | None = None
        """Why the current state was entered (``None`` before the mission starts)."""
        self.channels: Channels = outer.channels if outer is not None else {}
        """The student's own values (``log()`` and ``plot:``), the last of each by name."""
        self._visits: Counter[str] = Counter()
        self._start_s: float | None = None
        self._state_start_s = 0.0
        self._on_state = on_state
        self._on_start = on_start
        self._device_errors = device_errors
        self._odometry_origin: tuple[float, float] | None = None
        self._wheels_last_mm: tuple[float, float] | None = None
        self._driven_mm = 0.0  # path length of the robot's centre, forwards or back
        self._driven_at_state_mm = 0.0
        self._pose = [0.0, 0.0, 0.0]  # x right, y ahead of the start point (mm), heading
        self._outer = outer
        self._regions: Mapping[str, Any] | None = regions if outer is None else outer._regions
        self._origin: tuple[float, float, float] | None = origin if outer is None else outer._origin
        problems = check_regions(spec, None if self._regions is None else set(self._regions))
        if problems:
            raise CapabilityError(problems[0].message)
        self._model = _Model()
        # Each state's conditions, in order: checked here every tick, so the machine is asked
        # to move only on the tick one holds (see _check).
        self._conditions: dict[str, list[Callable[[Any], bool]]] = {
            name: [] for name in spec.states
        }
        self._decided: dict[Callable[[Any], bool], bool] | None = None
        self._machine = self._build_machine()

    # ------------------------------------------------------------------------ the machine

    def _build_machine(self) -> Machine:
        states = [
            State(
                name,
                on_enter=[self._make_enter(name)],
                on_exit=[self._make_exit(name)],
            )
            for name in self.spec.states
        ]
        machine = Machine(
            model=self._model,
            states=states,
            initial=self.spec.initial,
            auto_transitions=False,
            ignore_invalid_triggers=True,
            send_event=True,
            queued=False,
            model_override=True,
        )
        for name, state in self.spec.states.items():
            for outcome, options in state.on.items():
                for option in options:
                    self._add(machine, outcome, name, option)
            for option in state.when:
                self._add(machine, "check", name, option)
        return machine

    def _add(self, machine: Machine, trigger: str, source: str, option: TransitionSpec) -> None:
        conditions: list[str | Callable[..., bool | None]] = []
        guard = option.guard
        if guard is None and trigger == "check":
            self._conditions[source].append(_always)
        if guard is not None:
            text = option.guard_text or "condition"

            def condition(event: Any, guard: Callable[[Any], bool] = guard) -> bool:
                decided = self._decided
                if decided is not None and condition in decided:
                    return decided[condition]  # evaluated once this tick, by _check
                outer_reads, self._reads = self._reads, {}
                try:
                    held = bool(guard(self))
                finally:
                    reads, self._reads = self._reads, outer_reads
                if held:
                    values = TransitionCause.kept_values(reads)
                    if trigger == "check":
                        self._pending = TransitionCause(
                            "when", source, condition=text, values=values
                        )
                        self._cause = self._pending.in_state()
                    elif self._pending is not None:
                        self._pending = replace(self._pending, condition=text, values=values)
                return held

            condition.__name__ = option.guard_text or "condition"
            conditions.append(condition)
            if trigger == "check":
                self._conditions[source].append(condition)
        machine.add_transition(trigger, source, option.target, conditions=conditions)

    def _make_enter(self, name: str) -> Callable[[Any], None]:
        def enter(event: Any) -> None:
            self._enter(name)

        return enter

    def _make_exit(self, name: str) -> Callable[[Any], None]:
        def exit_(event: Any) -> None:
            self._exit()

        return exit_

    # ------------------------------------------------------------------------------ states

    @property
    def state(self) -> str:
        """The current state's name."""
        return self._model.state

    def _now(self) -> float:
        return self.ctx.now_s

    def _enter(self, name: str) -> None:
        now = self._now()
        start = self._start_s if self._start_s is not None else now
        self._visits[name] += 1
        self._state_start_s = now
        self._driven_at_state_mm = self._driven_mm
        cause = self._pending or TransitionCause("start")
        self._pending = None
        self.last_cause = cause
        self.result.record_state(round(now - start, 3), name, cause)
        if self._on_state is not None:
            self._on_state(now - start, name, cause)
        spec = self.spec.states[name]
        self.action_result = None
        self.action = spec.action.factory() if spec.action is not None else None
        if self.action is not None:
            self.action.start(self.ctx)
        self.during = [extra.factory() for extra in spec.during]
        for extra in self.during:
            extra.start(self.ctx)

    def _exit(self) -> None:
        for extra in self.during:
            extra.stop(self.ctx)
        self.during = []
        if self.action is not None:
            self.action.stop(self.ctx)
            self.action = None

    def record_inner_state(self, name: str, cause: TransitionCause) -> None:
        """Add a nested machine's state, and why it was entered, to this mission's timeline."""
        start = self._start_s if self._start_s is not None else self.ctx.now_s
        self.last_cause = cause
        self.result.record_state(round(self.ctx.now_s - start, 3), name, cause)
        if self._on_state is not None:
            self._on_state(self.ctx.now_s - start, name, cause)

    def _tick_during(self) -> None:
        still = []
        for extra in self.during:
            if extra.update(self.ctx) is None:
                still.append(extra)
            else:
                extra.stop(self.ctx)
        self.during = still

    def _check(self) -> bool:
        """Move on the current state's first condition that holds; True if it moved.

        Each condition is evaluated once, in order, up to the first that holds (a student's
        guard may count its calls); the machine then takes that one's transition, reading
        the values found here. On the many ticks where none holds, the machine is not asked
        at all: asking it cost more than the conditions themselves.
        """
        decided: dict[Callable[[Any], bool], bool] = {}
        for condition in self._conditions[self.state]:
            held = decided[condition] = condition(None)
            if held:
                break
        else:
            return False
        self._decided = decided
        try:
            return self._fire("check")
        finally:
            self._decided = None

    def _fire(self, trigger: str) -> bool:
        try:
            # transitions drops a Ctrl-C that lands in its finalise step: the scheduler's
            # tick raises it again (roboscript.interrupts.kept)
            moved = bool(self._model.trigger(trigger))
        finally:
            self._pending = None  # taken by the state entered, or no transition fired
        if moved:
            self._end_if_final()
        return moved

    def _end_if_final(self) -> None:
        """A final state without an action ends the mission as soon as it is entered."""
        state = self.spec.states[self.state]
        if state.final and self.action is None:
            outcome: MissionOutcome = "success" if state.final == "success" else "failure"
            self.finish(outcome, self._final_reason(outcome, state.name))

    # -------------------------------------------------------------------------------- tick

    def tick(self, now_s: float, dt_s: float) -> None:
        """Advance the mission by one scheduler tick.

        An exception from a student's code (a behaviour's start/update/stop, a guard method)
        ends the mission in failure with one sentence naming it, the state and the exception;
        the traceback goes to the debug log. Any other exception propagates.
        """
        try:
            with logging_to(self.channels):
                self._tick(now_s, dt_s)
                self._plot()
        except BaseException as exc:  # a student's exit() ends the run, not the program
            if passes_through(exc):
                raise
            reason = student_fault(exc, self.state)
            if reason is None:
                raise
            self.action = None  # it may be the code that raised: do not call its stop()
            self.during = []
            self.result.code_error = True
            self.finish("failure", reason)

    def _tick(self, now_s: float, dt_s: float) -> None:
        if self.finished:
            return
        self.ctx.now_s = now_s
        self.ctx.dt_s = dt_s
        if self._start_s is None:
            self._start_s = now_s
            if self._on_start is not None:
                self._on_start(now_s)
            if cap.DRIVE_BASE in self.capabilities:
                base = self.capabilities[cap.DRIVE_BASE]
                self._odometry_origin = base.wheel_distances_mm()  # type: ignore[attr-defined]
                self._wheels_last_mm = self._odometry_origin
                self._pose[2] = self._heading_deg()
            self._enter(self.state)
            self._end_if_final()
            if self.finished:
                return
        if self._wheels_last_mm is not None:
            self._track_odometry()
        name = self.state
        state = self.spec.states[name]
        if state.when and not state.final and self._check():
            return
        if self.during:
            self._tick_during()
        if self.action is not None and self.action_result is None:
            refused = self._device_errors() if self._device_errors is not None else None
            result = Result.failed(refused) if refused else self.action.update(self.ctx)
            if result is not None:
                self.action_result = result
                if self._route(name, result):
                    return
        if state.final and self.action_result is not None:
            outcome: MissionOutcome = "success" if state.final == "success" else "failure"
            self.finish(outcome, self._final_reason(outcome, name))
            return
        if state.timeout_s is not None and self.ctx.has_passed(
            self._state_start_s, state.timeout_s
        ):
            timed_out = TransitionCause("timeout", name, timeout_s=state.timeout_s)
            self._cause = timed_out.in_state()
            self._pending = timed_out
            if not self._fire("timeout"):
                self.finish("failure", self._cause)

    def _plot(self) -> None:
        """Record the ``plot:`` values of this tick (after it decided, as the sensors are)."""
        for text, guard in self.spec.plots:
            number = guard.value(self)
            self.channels[text] = number if math.isfinite(number) else None

    def _route(self, name: str, result: Result) -> bool:
        """Route an action's outcome; True if the mission moved on or ended."""
        state = self.spec.states[name]
        if state.final:
            return False
        routed = TransitionCause(
            result.outcome.value,
            name,
            action=state.action.name if state.action else None,
            reason=result.reason,
        )
        cause = routed.in_state()
        if result.outcome is not Outcome.DONE:
            self._cause = cause
        self._pending = routed
        if self._fire(result.outcome.value):
            return True
        if result.outcome is Outcome.DONE:
            return False  # the state waits for a condition or its timeout
        self.finish("failure", cause)
        return True

    def _final_reason(self, outcome: MissionOutcome, state: str) -> str | None:
        if outcome == "success":
            return None
        text = f"ended in the failure state '{state}'"
        return f"{text} after {self._cause}" if self._cause else text

    def finish(self, outcome: MissionOutcome, reason: str | None = None) -> None:
        """End the mission now with ``outcome`` (``success``, ``failure`` or ``error``).

        The action and the wheels are stopped first; only then is the mission marked
        finished. If stopping raises (a lost link, a signal), the mission is left unfinished
        and the exception propagates, so the caller's own ``finish("error", why)`` records
        why; that second call tries the stops again but lets a failing one pass.
        """
        if self.finished:
            return
        again = self._stopping
        self._stopping = True
        try:
            outcome, reason = self._stop_all(outcome, reason)
        except Exception:
            if not again:
                raise
            logger.debug("stopping again while finishing failed", exc_info=True)
        self.finished = True
        self.result.outcome = outcome
        self.result.final_state = self.state
        self.result.reason = reason
        self.result.duration_s = self.elapsed()

    def _stop_all(
        self, outcome: MissionOutcome, reason: str | None
    ) -> tuple[MissionOutcome, str | None]:
        """Stop the action, the ``during`` actions and the wheels; the outcome to record."""
        try:
            self._exit()
        except Exception as exc:
            fault = student_fault(exc, self.state)  # a student's behaviour raised in stop()
            if fault is None:
                raise
            self.action, self.during = None, []
            self.result.code_error = True
            if outcome == "success":
                outcome, reason = "failure", fault
        base = self.capabilities.get(cap.DRIVE_BASE)
        if base is not None:
            base.stop()  # type: ignore[attr-defined]
        return outcome, reason

    @property
    def start_time_s(self) -> float:
        """Scheduler time at which the mission started (0 before it has)."""
        return self._start_s or 0.0

    def elapsed(self) -> float:
        """Seconds since the mission started."""
        return 0.0 if self._start_s is None else round(self.ctx.now_s - self._start_s, 6)

    # ----------------------------------------------------------------------------- guards

    def out_of_time(self, max_time_s: float) -> str:
        """Why a run ended at its time limit, for its reason: ``the mission did not finish
        within 30 s``, and, when it went round a loop, which states it kept entering (a loop
        with no way out is the usual cause)."""
        reason = f"the mission did not finish within {max_time_s:g} s"
        looped = [(name, count) for name, count in self._visits.most_common(2) if count >= 3]
        if not looped:
            return reason
        entered = " and ".join(f"'{name}' entered {count} times" for name, count in looped)
        return (
            f"{reason}: it kept going round, {entered} (a loop needs a way out to a final"
            f" state, e.g. a when condition on visits.{looped[0][0]})"
        )

    def visits(self, state: str) -> int:
        """How many times ``state`` has been entered."""
        count = self._visits[state]
        if self._reads is not None:
            self._reads[f"visits.{state}"] = count
        return count

    def in_region(self, name: str) -> bool:
        """True while the robot, by its own odometry, is inside the world's region ``name``."""
        # A YAML condition's regions were checked when the runner was made; a Python
        # mission's self.in_region("name") is checked here, when it asks.
        if self._regions is None or self._origin is None:
            raise LookupError(
                f"in_region('{name}') needs a world map, which a robot on a port does not have"
            )
        if name not in self._regions:
            listed = ", ".join(sorted(self._regions)) or "none"
            raise KeyError(f"the world has no region '{name}' (its regions: {listed})")
        x_mm, y_mm = self._world_position(self._origin)
        inside = bool(self._regions[name].contains(x_mm, y_mm))
        if self._reads is not None:
            self._reads[f"in_region.{name}"] = inside
        return inside

    def _world_position(self, origin: tuple[float, float, float]) -> tuple[float, float]:
        """Where odometry puts the robot in the world: ``pose`` turned and moved to ``origin``."""
        if self._outer is not None:
            return self._outer._world_position(origin)
        x0_mm, y0_mm, heading_deg = origin
        # pose is x to the right, y ahead of the start; the world's heading is clockwise
        # from north (+y), so "ahead" is (sin h, cos h) and "right" is (cos h, -sin h)
        h = math.radians(heading_deg)
        right_mm, ahead_mm = self._pose[0], self._pose[1]
        return (
            x0_mm + right_mm * math.cos(h) + ahead_mm * math.sin(h),
            y0_mm - right_mm * math.sin(h) + ahead_mm * math.cos(h),
        )

    def _track_odometry(self) -> None:
        """Integrate the wheels' travel since the last tick into the pose and the distance."""
        left, right = self.ctx.drive_base.wheel_distances_mm()
        last = self._wheels_last_mm or (left, right)
        self._wheels_last_mm = (left, right)
        forward_mm = ((left - last[0]) + (right - last[1])) / 2.0
        heading = self._heading_deg()
        previous = self._pose[2]
        # along the mean of the two headings: the chord of the arc driven this tick
        middle = math.radians(previous + wrap_deg(heading - previous) / 2.0)
        self._pose[0] += forward_mm * math.sin(middle)
        self._pose[1] += forward_mm * math.cos(middle)
        self._pose[2] = heading
        self._driven_mm += abs(forward_mm)

    def sensor(self, root: str, attr: str | None) -> float | bool:
        """The value a guard name reads (see :mod:`roboscript.mission.guards`)."""
        value = self._sensor(root, attr)
        if self._reads is not None:  # a condition is deciding: remember what it saw
            self._reads[root if attr is None else f"{root}.{attr}"] = value
        return value

    def _sensor(self, root: str, attr: str | None) -> float | bool:
        whole_mission = root == "pose" or (root == "driven" and attr in ("total_mm", "total_cm"))
        if whole_mission and self._outer is not None:
            return self._outer.sensor(root, attr)
        if root == "driven":
            driven = self._driven_mm
            if attr in ("state_mm", "state_cm"):
                driven -= self._driven_at_state_mm
            return driven / 10.0 if attr is not None and attr.endswith("_cm") else driven
        if root == "pose":
            if attr == "heading_deg":
                return self._heading_deg()
            return self._pose[0] if attr == "x_mm" else self._pose[1]
        if root == "elapsed":
            return self.elapsed()
        if root == "state_time":
            return self.ctx.now_s - self._state_start_s
        if root == "heading_deg":
            return self._heading_deg()
        if root in ("range", "side_range"):
            reading = self.ctx.get(cap.RANGE if root == "range" else cap.SIDE_RANGE).distance_mm()
            value = math.inf if reading is None else float(reading)
            return value / 10.0 if attr == "distance_cm" else value
        if root == "bumper":
            pressed = self.ctx.get(cap.BUMPER).pressed()
            return bool(pressed) if attr == "any" else attr in pressed
        if root == "line":
            sensors = self.ctx.get(cap.LINE)
            values = sensors.values() or tuple(0.0 for _ in sensors.names)
            if attr == "any":
                return any(value > sensors.dark_threshold for value in values)
            if attr not in sensors.names:  # one sensor (a SPIKE colour sensor): reads white
                return 0.0
            return float(values[sensors.names.index(attr)])
        if root in ("color", "buttons"):
            return color_or_buttons(self.ctx, root, attr)
        raise KeyError(root)

    def _heading_deg(self) -> float:
        """Turn since the start, degrees clockwise, in [-180, 180) (the one convention)."""
        if cap.HEADING in self.capabilities:
            heading = self.ctx.get(cap.HEADING).heading_deg()
            return 0.0 if heading is None else wrap_deg(heading)
        base = self.ctx.drive_base
        left, right = base.wheel_distances_mm()
        origin = self._odometry_origin or (0.0, 0.0)
        return wrap_deg(turned_deg(left - origin[0], right - origin[1], base.track_mm))
