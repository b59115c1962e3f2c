"""The mission process of a graded run: the only place a student's mission is loaded and run.

The grader starts it sandboxed (:mod:`roboscript.grading.sandbox`) as::

    python -I -m roboscript.grading.mission_host FD MISSION ROBOT MAX_TIME_S HANG_AFTER_S [MAP]

(``MAP``: a file holding the world's regions and start pose as JSON,
:class:`roboscript.session.WorldMap`.)

It loads the mission, connects to the robot through ``lockstep://FD`` (the world lives in the
grader's process, :mod:`roboscript.grading.world_host`), runs the mission exactly as
``roboscript run`` would, and reports what only it can know: that the mission loaded, each
state it entered, and how it ended. The world timestamps every report itself and trusts none
of them with a name, a score or a verdict.

If the mission's own code stops returning, a watchdog thread writes where every thread was to
standard error (:mod:`faulthandler`) before the grader's hang limit ends the process, so the
teacher's report can say where it was stuck. The watchdog is re-armed as the mission makes
progress, so it fires only in a process that is stuck: reading another thread's frames while
that thread runs is not safe, and on a busy machine a timer that fired in healthy runs crashed
some of them.
"""

from __future__ import annotations

import faulthandler
import logging
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from roboscript.transport.lockstep import Kind, WorldChannel, WorldStoppedError

__all__ = ["main", "warm_up"]

_REASON_CHARS = 500


def main(argv: Sequence[str] | None = None) -> int:
    """Run one mission over the lockstep wire; the exit status means nothing to the grader."""
    args = list(sys.argv[1:] if argv is None else argv)
    fd, mission_path, robot, max_time_s, hang_after_s = (
        int(args[0]),
        args[1],
        args[2],
        float(args[3]),
        float(args[4]),
    )
    world_map = args[5] if len(args) > 5 else None
    logging.disable(logging.WARNING)
    channel = WorldChannel.for_fd(fd)
    watchdog = _StuckWatch(max(0.2, hang_after_s * 0.6))
    watchdog.arm()
    try:
        return _run(channel, mission_path, robot, max_time_s, world_map, watchdog)
    except WorldStoppedError:
        return 3
    finally:
        faulthandler.cancel_dump_traceback_later()


def warm_up(robot: str = "") -> None:
    """Import what a run needs, once, in a fork server whose runs are forked from it.

    Args:
        robot: The robot the runs connect to (its driver is imported too), or ``""``.
    """
    import roboscript.mission
    import roboscript.session  # noqa: F401 - imported to be inherited by every run

    if robot:
        from roboscript.drivers import driver_class
        from roboscript.profiles import get_profile

        driver_class(get_profile(robot).protocol)


class _StuckWatch:
    """Writes every thread's stack to stderr once the mission has made no progress for a while.

    Args:
        after_s: Wall seconds without :meth:`progress` before the stacks are written.
    """

    def __init__(self, after_s: float) -> None:
        self.after_s = after_s
        self._armed_at = 0.0

    def arm(self) -> None:
        """Start (or restart) the countdown."""
        faulthandler.dump_traceback_later(self.after_s, repeat=True, file=sys.stderr)
        self._armed_at = time.monotonic()

    def progress(self) -> None:
        """The mission moved on: restart the countdown (at most a few times per countdown,
        since each restart starts a new timer thread)."""
        if time.monotonic() - self._armed_at > self.after_s / 4:
            self.arm()


def _run(
    channel: WorldChannel,
    mission_path: str,
    robot: str,
    max_time_s: float,
    world_map: str | None = None,
    watchdog: _StuckWatch | None = None,
) -> int:
    from roboscript.errors import CapabilityError, InputError
    from roboscript.mission import mission_for_robot

    try:
        mission, profile, _warnings = mission_for_robot(mission_path, robot)
    except InputError as exc:
        problems = [p.format() for p in getattr(exc, "problems", None) or [exc]]
        channel.send_json(Kind.LOAD_ERROR, {"message": problems[0], "more": len(problems) - 1})
        return 2
    channel.send_json(Kind.LOADED, {"mission": mission.name})
    if watchdog is not None:
        watchdog.arm()

    from roboscript.session import WorldMap, run_session

    def on_state(_t_s: float, name: str, _cause: object) -> None:
        channel.send(Kind.STATE, name.encode("utf-8", "replace")[:256])

    try:
        session = run_session(
            mission,
            profile,
            port=f"lockstep://{channel_fd(channel)}",
            max_time_s=max_time_s,
            on_state=on_state,
            world_map=None
            if world_map is None
            else WorldMap.from_json(Path(world_map).read_text(encoding="utf-8")),
            on_connected=None if watchdog is None else (lambda _robot: watchdog.arm()),
            on_tick=None if watchdog is None else (lambda _runner, _robot: watchdog.progress()),
        )
    except CapabilityError as exc:
        channel.send_json(Kind.LOAD_ERROR, {"message": f"it does not fit the robot: {exc}"})
        return 2
    result = session.result
    channel.send_json(
        Kind.FINISH,
        {
            "outcome": result.outcome,
            "final_state": result.final_state,
            "reason": (result.reason or "")[:_REASON_CHARS] or None,
            "code_error": result.code_error,
        },
    )
    return 0


def channel_fd(channel: WorldChannel) -> int:
    """The descriptor a channel was opened on (the port URL names it)."""
    return channel.fileno()


if __name__ == "__main__":
    sys.exit(main())
