"""Recording a mission run as it goes: taps on the robot's commands and one sample per tick.

:class:`RunRecording` is handed to :func:`roboscript.session.run_session`: once the robot is
connected it builds the header and wraps the capabilities the mission will use, so the wheel
speeds, tones and display text the mission asks for are seen on the way to the driver; after
every scheduler tick it samples the pose, the state, the action and every sensor the mission
can read. Sampling reads values the drivers already hold: it never talks to the robot, never
blocks, and a failure while sampling stops the recording, never the run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from contextlib import AbstractContextManager
from typing import Any

from roboscript import capabilities as cap
from roboscript.angles import wrap_deg
from roboscript.mission.channels import MAX_PRINTED_LINES, copied_prints, printed_line
from roboscript.mission.runner import MissionRunner
from roboscript.mission.spec import MissionSpec
from roboscript.profiles import RobotProfile
from roboscript.replay.header import (
    PRINTED_BEFORE_START,
    mission_header,
    port_header,
    run_header,
)
from roboscript.replay.recording import MAX_FRAMES, Listener, Recorder, RecordingFile
from roboscript.robot import Robot
from roboscript.run_record import RunRecord
from roboscript.sim.simulation import Simulation

__all__ = [
    "RESULT_FIELDS",
    "SHOWN",
    "CommandTap",
    "OdometryPose",
    "RunRecording",
    "result_line",
    "save_recording",
    "sensor_readers",
    "written_pose",
]


_UNSET: Any = object()
"""No value yet: differs from every value, ``None`` included."""


class CommandTap:
    """The last commands the mission gave: wheel speeds, a new tone, the display text."""

    def __init__(self) -> None:
        self.wheel_speeds_mm_s: tuple[float, float] | None = None
        self.tone: tuple[float, float] | None = None
        self.display: str | None = None

    def wrap(self, capabilities: Mapping[str, object]) -> dict[str, object]:
        """The capabilities with the drive base, speaker and display seen through this tap."""
        wrapped = dict(capabilities)
        if cap.DRIVE_BASE in wrapped:
            wrapped[cap.DRIVE_BASE] = _DriveBaseTap(wrapped[cap.DRIVE_BASE], self)
        if cap.SPEAKER in wrapped:
            wrapped[cap.SPEAKER] = _SpeakerTap(wrapped[cap.SPEAKER], self)
        if cap.DISPLAY in wrapped:
            wrapped[cap.DISPLAY] = _DisplayTap(wrapped[cap.DISPLAY], self)
        return wrapped


class _Tap:
    """Forwards everything to the wrapped capability; subclasses watch some methods."""

    def __init__(self, inner: object, tap: CommandTap) -> None:
        self._inner = inner
        self._tap = tap

    def __getattr__(self, name: str) -> Any:
        # Looked up once: a mission reads some every tick (a capability's methods and its
        # attributes, such as ``track_mm``, are fixed for the run), and a recorded run must
        # cost the tick loop next to nothing (tests/bench/bench_replay.py).
        value = getattr(self._inner, name)
        self.__dict__[name] = value
        return value


class _DriveBaseTap(_Tap):
    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        self._tap.wheel_speeds_mm_s = (left_mm_s, right_mm_s)
        self._inner.set_wheel_speeds(left_mm_s, right_mm_s)  # type: ignore[attr-defined]

    def stop(self) -> None:
        self._tap.wheel_speeds_mm_s = (0.0, 0.0)
        self._inner.stop()  # type: ignore[attr-defined]


class _SpeakerTap(_Tap):
    def beep(self, frequency_hz: float, duration_s: float) -> None:
        self._tap.tone = (frequency_hz, duration_s)
        self._inner.beep(frequency_hz, duration_s)  # type: ignore[attr-defined]


class _DisplayTap(_Tap):
    def show_text(self, text: str) -> None:
        self._tap.display = text
        self._inner.show_text(text)  # type: ignore[attr-defined]

    def clear(self) -> None:
        self._tap.display = ""
        self._inner.clear()  # type: ignore[attr-defined]


class OdometryPose:
    """A pose dead-reckoned from the wheel travel, for robots without a simulator.

    It starts at ``(0, 0)`` facing north and follows the same arc model as the simulator
    (clockwise positive), so a real run draws in the viewer like a simulated one.
    """

    def __init__(self, track_mm: float) -> None:
        self.track_mm = track_mm
        self.x_mm = 0.0
        self.y_mm = 0.0
        self.heading_deg = 0.0
        self._last: tuple[float, float] | None = None

    def update(self, left_mm: float, right_mm: float) -> tuple[float, float, float]:
        """Advance to the wheels' total travel; return ``(x mm, y mm, heading deg)``."""
        if self._last is None:
            self._last = (left_mm, right_mm)
        dl, dr = left_mm - self._last[0], right_mm - self._last[1]
        self._last = (left_mm, right_mm)
        distance = (dl + dr) / 2.0
        turn_rad = (dl - dr) / self.track_mm
        heading_rad = math.radians(self.heading_deg + math.degrees(turn_rad) / 2.0)
        self.x_mm += distance * math.sin(heading_rad)
        self.y_mm += distance * math.cos(heading_rad)
        self.heading_deg = (self.heading_deg + math.degrees(turn_rad)) % 360.0
        return self.x_mm, self.y_mm, self.heading_deg


class RunRecording:
    """Records one :func:`~roboscript.session.run_session` run.

    Args:
        max_frames: Most frames kept (see :data:`~roboscript.replay.recording.MAX_FRAMES`).
        listeners: Handed every event as it is made: ``("header", header)`` once connected,
            ``("frame", frame)`` each tick, ``("end", result)`` (a live view streams these).
        path: Write the recording to this file as the run goes (``run --record``): a run
            killed outright leaves every line up to its last second; see
            :func:`save_recording` for how it ends.

    Attributes:
        recorder: The recording, from the moment the robot is connected (else ``None``).
    """

    def __init__(
        self,
        *,
        max_frames: int = MAX_FRAMES,
        listeners: tuple[Listener, ...] = (),
        path: str | None = None,
    ) -> None:
        self.max_frames = max_frames
        self.path = path
        self.listeners = list(listeners)
        self.recorder: Recorder | None = None
        self.commands = CommandTap()
        self._readers: list[tuple[str, Callable[[], Any]]] = []
        self._keys: list[str] = []
        self._reads: list[Callable[[], Any]] = []
        self._raw: list[Any] = []
        # The last value written of each frame key (_UNSET: none yet, so the first frame
        # writes everything).
        self._last_pose: Any = _UNSET
        self._last_state: Any = _UNSET
        self._last_action: Any = _UNSET
        self._last_result: Any = _UNSET
        self._last_outcome: Any = _UNSET
        self._last_cause: Any = _UNSET
        self._last_log: dict[str, Any] = {}
        self._printed: list[str] = []  # printed since the last tick was recorded
        self._printed_before_start: list[str] = []  # printed while the mission loaded
        self._printed_total = 0
        self._last_wheels: Any = _UNSET
        self._last_motors: dict[str, float] = {}
        self._last_written_pose: Any = _UNSET
        self._last_display: Any = _UNSET
        self._last_contact: Any = _UNSET
        self._actions: dict[str, str | None] = {}
        self._sample_pose: Callable[[], tuple[float, float, float] | None] = lambda: None
        self._body: Any = None  # the simulated body, read directly (the fastest way)
        self._start_s: float | None = None

    def attach(self, robot: Robot, spec: MissionSpec, profile: RobotProfile) -> dict[str, object]:
        """Start recording ``robot``; return the capabilities the mission should be given."""
        # A graded mission's robot has a stand-in for the world (the lockstep wire), no body.
        sim = robot.simulation if isinstance(robot.simulation, Simulation) else None
        caps = robot.capabilities
        self.add_sensors(sensor_readers(caps))
        self._actions = {name: state.action_name for name, state in spec.states.items()}
        if sim is not None:
            body = sim.body
            pose_source = "simulator"
            self._body = body
        elif cap.DRIVE_BASE in caps:
            base: Any = caps[cap.DRIVE_BASE]
            odometry = OdometryPose(base.track_mm)
            pose_source = "odometry"

            def odometry_pose() -> tuple[float, float, float]:
                return odometry.update(*base.wheel_distances_mm())

            self._sample_pose = odometry_pose
        else:
            pose_source = "none"
        header = run_header(
            mission_header(spec),
            profile,
            world=sim.world if sim is not None else None,
            seed=sim.seed if sim is not None else None,
            pose_source=pose_source,
            tick_s=robot.scheduler.period_s,
            body=sim.body.spec if sim is not None else None,
        )
        header["port"] = port_header(robot.url)
        if self._printed_before_start:
            header[PRINTED_BEFORE_START] = list(self._printed_before_start)
        self.recorder = Recorder(
            header,
            max_frames=self.max_frames,
            format_changes=self.format_row,
            out=RecordingFile(self.path) if self.path is not None else None,
        )
        for listener in self.listeners:
            self.recorder.subscribe(listener, with_header=True)
        return self.commands.wrap(caps)

    def add_sensors(self, readers: list[tuple[str, Callable[[], Any]]]) -> None:
        """Record these sensors too: ``(name, reader)``, read once per tick."""
        self._readers += readers
        self._keys = [key for key, _ in self._readers]
        self._reads = [read for _, read in self._readers]
        self._raw = [*self._raw, *([_UNSET] * len(readers))]

    def printed(self, line: str) -> None:
        """Record a line the mission printed (written with the next tick, as ``print``)."""
        self._printed_total += 1
        if self._printed_total <= MAX_PRINTED_LINES:
            self._printed.append(printed_line(line))

    def loading(self) -> AbstractContextManager[None]:
        """Record what is printed while the block loads the mission, before the robot is
        connected: a Python mission's ``print`` at the top of its file or in its class body.
        The lines go on to the terminal, and into the header as ``printed_before_start``."""
        return copied_prints(self._printed_while_loading)

    def _printed_while_loading(self, line: str) -> None:
        self._printed_total += 1
        if self._printed_total <= MAX_PRINTED_LINES:
            self._printed_before_start.append(printed_line(line))

    def tick(self, runner: MissionRunner) -> None:
        """Record this tick (called after the mission's think phase).

        This runs on every tick of the robot's loop, so it only reads: the tick is kept as
        one row of values as the robot gives them (a tuple, a set, an unrounded float), and
        :meth:`format_row` turns rows into frames (what changed, rounded) later, outside the
        tick loop, or at once for a listener.
        """
        recorder = self.recorder
        if recorder is None or recorder.error is not None:
            return
        try:
            if self._start_s is None:
                self._start_s = runner.start_time_s
            body = self._body
            pose = (
                (body.x_mm, body.y_mm, body.heading_deg)
                if body is not None
                else self._sample_pose()
            )
            printed = self._printed
            if printed:
                self._printed = []
            commands = self.commands
            tone = commands.tone
            if tone is not None:
                commands.tone = None
            recorder.add_changes(
                (
                    runner.ctx.now_s,
                    pose,
                    runner.state,
                    runner.action_result,
                    [read() for read in self._reads],
                    commands.wheel_speeds_mm_s,
                    tone,
                    commands.display,
                    (body.contact_side if body.in_contact else None)
                    if body is not None
                    else _UNSET,
                    runner.last_cause,
                    dict(runner.channels) if runner.channels else None,
                    printed or None,
                )
            )
        except Exception as exc:  # noqa: BLE001 - a failed sample ends the recording only
            recorder.error = f"recording stopped at {runner.elapsed():.2f} s: {exc}"

    def format_row(self, row: Any) -> dict[str, Any]:
        """The frame of one kept row: ``t`` and what changed since the row before, written.

        Rows must be formatted once each, in order (the recorder does so).
        """
        (
            now_s,
            pose,
            state,
            result,
            values,
            wheels,
            tone,
            display,
            contact,
            cause,
            logged,
            printed,
        ) = row
        frame: dict[str, Any] = {"t": round(now_s - (self._start_s or 0.0), 3) + 0.0}
        if pose != self._last_pose:
            self._last_pose = pose
            written = None if pose is None else written_pose(*pose)
            if written != self._last_written_pose:
                frame["pose"] = self._last_written_pose = written
        if state != self._last_state:
            frame["state"] = self._last_state = state
            action = self._actions.get(state)
            if action != self._last_action:
                frame["action"] = self._last_action = action
        if cause is not self._last_cause:  # a new transition, even back into the same state
            self._last_cause = cause
            if cause is not None:
                frame["why"] = cause.to_json()
        if result is not self._last_result:
            self._last_result = result
            outcome = None if result is None else result.outcome.value
            if outcome != self._last_outcome:
                frame["outcome"] = self._last_outcome = outcome
        if values != self._raw:
            frame["sensors"] = {
                key: SHOWN[key](value)
                for key, value, before in zip(self._keys, values, self._raw, strict=True)
                if value != before or before is _UNSET
            }
            self._raw = values
        if wheels is not None and wheels != self._last_wheels:
            self._last_wheels = wheels
            motors = {"left_mm_s": round(wheels[0], 1), "right_mm_s": round(wheels[1], 1)}
            changed = {k: v for k, v in motors.items() if self._last_motors.get(k) != v}
            if changed:
                frame["motors"] = changed
                self._last_motors = motors
        if logged is not None and logged != self._last_log:
            frame["log"] = {
                name: _logged(value)
                for name, value in logged.items()
                if self._last_log.get(name, _UNSET) != value
            }
            self._last_log = logged
        if tone is not None:
            frame["tone"] = [tone[0], tone[1]]
        if printed is not None:
            frame["print"] = printed
        if display is not None and display != self._last_display:
            frame["display"] = self._last_display = display
        if contact is not _UNSET and contact != self._last_contact:
            frame["contact"] = self._last_contact = contact
        return frame

    def finish(self, record: RunRecord, **extra: Any) -> dict[str, Any] | None:
        """Close the recording with the run's record (and ``extra`` keys)."""
        if self.recorder is None:
            return None
        if self._printed_total > MAX_PRINTED_LINES:
            extra["prints_not_recorded"] = self._printed_total - MAX_PRINTED_LINES
        return self.recorder.finish({**result_line(record), **extra})


def sensor_readers(capabilities: Mapping[str, object]) -> list[tuple[str, Callable[[], Any]]]:
    """Each sensor the mission can read: the header's name and its reader.

    :data:`SHOWN` says how each is written: ranges in mm (``None``: no echo), ``line`` as the
    readings 0-1023 left to right (``None`` before the first), ``bumper`` as the pressed
    switches, ``heading_deg`` in degrees clockwise.
    """
    readers: list[tuple[str, Callable[[], Any]]] = []
    sensor: Any
    for name, key in ((cap.RANGE, "range_mm"), (cap.SIDE_RANGE, "side_range_mm")):
        sensor = capabilities.get(name)
        if sensor is not None:
            readers.append((key, sensor.distance_mm))
    for name, key, method in (
        (cap.LINE, "line", "values"),
        (cap.BUMPER, "bumper", "pressed"),
        (cap.HEADING, "heading_deg", "heading_deg"),
    ):
        sensor = capabilities.get(name)
        if sensor is not None:
            readers.append((key, getattr(sensor, method)))
    return readers


def _rounded(value: float | None) -> float | None:
    if value is None or not math.isfinite(value):
        return None
    return round(float(value), 1)


def _heading(value: float | None) -> float | None:
    rounded = _rounded(value)
    return None if rounded is None else round(wrap_deg(rounded), 1) + 0.0


def _logged(value: float | bool | None) -> float | bool | None:
    """A ``log()`` value as a frame writes it: numbers to 0.001, true/false as they are."""
    return value if value is None or isinstance(value, bool) else round(value, 3) + 0.0


def _line(values: tuple[float, ...] | None) -> list[int] | None:
    return None if values is None else [round(v) for v in values]


SHOWN: dict[str, Callable[[Any], Any]] = {
    "range_mm": _rounded,
    "side_range_mm": _rounded,
    "heading_deg": _heading,
    "line": _line,
    "bumper": sorted,
}
"""How each sensor's reading is written, by its name (see :func:`sensor_readers`)."""


def written_pose(x_mm: float, y_mm: float, heading_deg: float) -> list[float]:
    """A pose as a frame writes it: ``[x mm, y mm, heading deg]`` to 0.1, heading wrapped."""
    # Headings in [-180, 180), the project's one convention (roboscript.angles): wrapped
    # again after rounding, as 179.96 rounds to 180.0; "+ 0.0" turns -0.0 into 0.0.
    heading = wrap_deg(round(wrap_deg(heading_deg), 1))
    return [round(x_mm, 1) + 0.0, round(y_mm, 1) + 0.0, round(heading, 1) + 0.0]


RESULT_FIELDS = ("outcome", "final_state", "reason", "duration_s", "states")
"""The run record's fields a recording's result line holds, as the record writes them
(docs/reference/recording.md: the rest of the line is the recording's own)."""


def result_line(record: RunRecord) -> dict[str, Any]:
    """The result line's object for a run's record."""
    data = record.to_dict()
    return {name: data[name] for name in RESULT_FIELDS}


def save_recording(recording: RunRecording, path: str) -> str | None:
    """Finish writing a finished run's recording to ``path``; the one-line problem, or ``None``.

    A recording made with ``path`` was written as the run went (and closed when it finished);
    one made without is written now. Called after the robot is stopped, so a slow or failing
    disk never delays the stop.
    """
    recorder = recording.recorder
    if recorder is None:
        return f"error: nothing recorded to {path}: the robot was never connected"
    if recorder.out is not None:
        if recorder.out.error is not None:
            return f"error: {recorder.out.error}"
    else:
        try:
            recorder.write(path)
        except (OSError, ValueError, TypeError) as exc:
            reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
            return f"error: cannot write the recording {path}: {reason}"
    if recorder.error is not None:
        return f"warning: {path}: {recorder.error}"
    return None
