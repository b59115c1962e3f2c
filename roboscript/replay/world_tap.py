"""Recording a graded run in the world's process, from the grader's own simulation.

In a graded run the student's mission runs in a sandbox and only sends bytes and reports; the
world process owns the simulation. :class:`WorldReplay` records there, so nothing the student
process writes becomes a frame except what the world has already checked: the states it
entered (with their actions and causes) and the lines it printed, each on the frame of the
tick it arrived in, and all named in the header's ``claimed`` as the mission's own. It reads
the body without disturbing it (the range sensors' last measurements, never a new one), keeps
at most ``rate_hz`` frames a second plus every state change, and its frames' ``motors`` are
the simulated wheels' speeds (``left_mm_s``/``right_mm_s``, mm/s, forward positive: the same
fields and units as ``run --record``'s, where they are the speeds the mission asked for): the
mission's own wheel commands never leave its sandbox.
"""

from __future__ import annotations

from typing import Any

from roboscript import capabilities as cap
from roboscript.mission.channels import MAX_PRINTED_LINES
from roboscript.profiles import RobotProfile
from roboscript.replay.header import PRINTED_BEFORE_START, run_header
from roboscript.replay.recording import TRANSITION_KEY, Recorder, encode_line
from roboscript.replay.session_tap import SHOWN, written_pose
from roboscript.sim.simulation import Simulation

__all__ = ["CLAIMED", "CLAIMED_CHARS", "DEFAULT_RATE_HZ", "PRINTED_CHARS", "WorldReplay"]

DEFAULT_RATE_HZ = 10.0
"""Frames a second a graded run keeps: enough to replay, small enough for a class report."""
CLAIMED_CHARS = 400_000
"""Most characters of the mission's claimed causes one recording keeps (about 2000 honest
transitions); later transitions show their state and action without a cause."""
PRINTED_CHARS = 100_000
"""Most characters of printed lines one recording keeps (and at most
:data:`~roboscript.mission.channels.MAX_PRINTED_LINES` lines); later lines are counted in the
result's ``prints_not_recorded``."""
CLAIMED = ("state", "action", "why", "print")
"""The frame keys whose values come from the mission's process: its own account, checked and
cut to size, never judged (the header's ``claimed``)."""


class WorldReplay:
    """Records one graded run from the world's simulation.

    Args:
        sim: The world's simulation.
        profile: The robot simulated.
        tick_s: The mission's scheduler period, seconds.
        rate_hz: Most frames a second (state changes are always kept).
    """

    def __init__(
        self,
        sim: Simulation,
        profile: RobotProfile,
        *,
        tick_s: float = 0.02,
        rate_hz: float = DEFAULT_RATE_HZ,
    ) -> None:
        self.sim = sim
        self.profile = profile
        self.period_s = 1.0 / rate_hz
        header = run_header(
            {"name": "", "states": []},
            profile,
            world=sim.world,
            seed=sim.seed,
            pose_source="simulator",
            tick_s=tick_s,
            body=sim.body.spec,
        )
        header["port"] = "grader"
        header["frame_rate_hz"] = rate_hz
        header["claimed"] = list(CLAIMED)
        self.recorder = Recorder(header)
        self._start_s: float | None = None
        self._next_s = 0.0
        self._last_t: float | None = None  # the last kept frame's t, s
        self._state: str | None = None
        self._tones = 0
        self._states: list[str] = []
        self._actions: dict[str, str | None] = {}
        self._action: str | None = None
        self._why: dict[str, Any] | None = None  # the last claimed cause, not yet in a frame
        self._claimed_chars = 0
        self._printed_lines = 0
        self._printed_chars = 0
        self._prints_not_recorded = 0
        self._printed_before_start: list[str] = []

    def enter(
        self, now_s: float, state: str, action: str | None, why: dict[str, Any] | None
    ) -> None:
        """The mission says it entered ``state`` at ``now_s``, running ``action``, because of
        ``why``: a frame is kept for it at once (even for a state entered again).

        ``action`` and ``why`` are the mission's own account (checked and cut to size by the
        caller; ``why`` in :meth:`~roboscript.mission.cause.TransitionCause.to_json`'s shape):
        they are recorded for the page to show, ``why`` marked ``"claimed": true``, and judge
        nothing.
        """
        self._action = action
        self._why = None
        if why is not None and self._claimed_chars < CLAIMED_CHARS:
            self._claimed_chars += len(encode_line(why))
            self._why = {**why, "claimed": True}
        self._next_s = 0.0
        self.tick(now_s, state)

    def printed(self, now_s: float, line: str) -> None:
        """The mission printed ``line`` at ``now_s`` (in the tick of that time): it is written
        on that tick's frame, which is kept for it.

        ``line`` is the mission's own words, made printable and cut to size by the caller. A
        line printed before the mission started (while it loaded) goes in the header's
        ``printed_before_start``, as ``run --record`` keeps it. A line past
        :data:`PRINTED_CHARS` or :data:`~roboscript.mission.channels.MAX_PRINTED_LINES`, or
        printed after the start before the mission's first state, is only counted.
        """
        self._printed_lines += 1
        self._printed_chars += len(line)
        if self._printed_lines > MAX_PRINTED_LINES or self._printed_chars > PRINTED_CHARS:
            self._prints_not_recorded += 1
            return
        if self._start_s is None:
            self._printed_before_start.append(line)
            return
        if self._state is None:
            self._prints_not_recorded += 1
            return
        t = round(now_s - self._start_s, 3)
        if t != self._last_t:
            self._next_s = 0.0  # a frame for the tick it was printed in
            self.tick(now_s, self._state)
        frames = self.recorder.frames
        if not frames or frames[-1]["t"] != t:  # the recording is full
            self._prints_not_recorded += 1
            return
        frames[-1].setdefault("print", []).append(line)

    def start(self, now_s: float) -> None:
        """The mission started at simulated time ``now_s`` (its clock's zero)."""
        self._start_s = now_s
        self._tones = len(self.sim.log.tones)

    def tick(self, now_s: float, state: str | None) -> None:
        """The simulation reached ``now_s``; ``state`` is the state the mission last reported."""
        if self._start_s is None or state is None:
            return
        t = round(now_s - self._start_s, 3)
        if (
            state == self._state
            and self._why is None
            and (t < self._next_s - 1e-9 or t == self._last_t)
        ):
            return  # nearly every tick: nothing new to keep
        if state not in self._actions:  # a dict: a mission may enter thousands of states
            self._states.append(state)
            self._actions[state] = self._action
        if state == self._state and t == self._last_t and self._why is not None:
            last = self.recorder.frames[-1]
            if TRANSITION_KEY not in last:
                # Entered again on a tick already kept (the mission reports after the world
                # ticked): that tick's frame is the transition's, as in run --record.
                last[TRANSITION_KEY] = self._why
                self._why = None
                return
        if state == self._state and t < self._next_s - 1e-9:
            return  # a cause this tick's frame already holds waits for the next frame kept
        self._state = state
        self._next_s = t + self.period_s
        self._last_t = t
        frame = self.recorder.add(self._sample(t, state))
        if frame is not None and self._why is not None:
            # written on its transition's frame only, as run --record does (the reader
            # carries it on): equal causes one after another are still two transitions
            frame[TRANSITION_KEY] = self._why
            self._why = None

    def _sample(self, t: float, state: str) -> dict[str, Any]:
        body = self.sim.body
        log = self.sim.log
        frame: dict[str, Any] = {
            "t": t,
            "pose": written_pose(body.x_mm, body.y_mm, body.heading_deg),
            "state": state,
            "action": self._action,
            "sensors": self._sensors(),
            "motors": {
                "left_mm_s": round(body.wheel_speed_mm_s[0], 1) + 0.0,
                "right_mm_s": round(body.wheel_speed_mm_s[1], 1) + 0.0,
            },
            "contact": body.contact_side if body.in_contact else None,
        }
        if len(log.tones) > self._tones:  # the last tone heard since the frame before
            _, frequency, duration = log.tones[-1]
            frame["tone"] = [float(frequency), round(duration, 3)]
            self._tones = len(log.tones)
        if log.display:
            frame["display"] = log.display
        return frame

    def _sensors(self) -> dict[str, Any]:
        body = self.sim.body
        has = self.profile.capabilities
        front, side = body.last_ranges_mm()
        values: dict[str, Any] = {}
        if cap.RANGE in has:
            values["range_mm"] = None if front is None else round(front, 1)
        if cap.SIDE_RANGE in has:
            values["side_range_mm"] = None if side is None else round(side, 1)
        if cap.LINE in has:
            values["line"] = list(body.line_levels())
        if cap.BUMPER in has:
            names = body.spec.bumper_names
            values["bumper"] = [
                n for n, down in zip(names, body.bumpers_pressed(), strict=True) if down
            ]
        if cap.HEADING in has:
            values["heading_deg"] = SHOWN["heading_deg"](body.imu_heading_deg())
        return values

    def finish(
        self,
        *,
        mission: str,
        outcome: str,
        final_state: str | None,
        reason: str | None,
        duration_s: float,
        states: tuple[tuple[float, str], ...],
        now_s: float,
    ) -> dict[str, Any]:
        """Close the recording; return it as ``{"header", "frames", "result"}``."""
        if self._start_s is not None and final_state is not None:
            self._next_s = 0.0  # the last moment is always kept
            self.tick(now_s, final_state)
        header = self.recorder.header()
        if self._printed_before_start:
            header[PRINTED_BEFORE_START] = list(self._printed_before_start)
        header["mission"] = {
            "name": mission,
            "initial": states[0][1] if states else None,
            "states": [
                {"name": name, "action": self._actions.get(name), "final": None}
                for name in self._states
            ],
        }
        ended: dict[str, Any] = {
            "outcome": outcome,
            "final_state": final_state,
            "reason": reason,
            "duration_s": round(duration_s, 3),
            "states": [[t, name] for t, name in states],
        }
        if self._prints_not_recorded:
            ended["prints_not_recorded"] = self._prints_not_recorded
        result = self.recorder.finish(ended)
        return {"header": header, "frames": self.recorder.frames, "result": result}
