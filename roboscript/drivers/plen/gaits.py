"""The gait motions roboscript installs on a PLEN2, read from the package's ``motions/`` folder.

Each file is a motion in plen-ControlServer's JSON format (see
:func:`~roboscript.drivers.plen.motionfile.motion_from_json`), designed for roboscript: one pass of
its loop is one step that starts and ends in the home stance, so walking N steps is the motion
played N times, and a stop after any pass leaves the robot on both feet. The loop code counts
255 ("until stopped"), so a PLEN app that plays the slot walks until it sends ``$SM``.
``@metadata`` says how far one pass walks (``stride_mm``) or turns (``turn_step_deg``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources

from roboscript.drivers.plen.commands import encode_command
from roboscript.drivers.plen.messages import MotionFrame, MotionHeader, MotionReply
from roboscript.drivers.plen.motionfile import motion_from_json
from roboscript.drivers.plen.playback import Schedule

__all__ = ["GAIT_KEYS", "Gait", "load_gait", "load_gaits"]

GAIT_KEYS = ("walk_forward", "walk_backward", "turn_right", "turn_left")
"""The gaits, by file name (``motions/<key>.json``)."""


@dataclass(frozen=True)
class Gait:
    """One gait motion as the driver installs and plays it.

    Attributes:
        key: File name without ``.json`` (``walk_forward``).
        header: The ``>MH`` command that stores it.
        frames: The ``>MF`` commands, in index order.
        stride_mm: Distance one pass walks (0 for a turn), mm; negative when walking backward.
        turn_step_deg: Rotation of one pass (0 for a walk), degrees, clockwise positive.
    """

    key: str
    header: MotionHeader
    frames: tuple[MotionFrame, ...]
    stride_mm: float = 0.0
    turn_step_deg: float = 0.0

    @property
    def slot(self) -> int:
        """The motion slot the gait lives in."""
        return self.header.slot

    @property
    def stored(self) -> MotionReply:
        """What ``<MO`` answers for the slot once the gait is installed."""
        return MotionReply.from_install(self.header, self.frames)

    def install_bytes(self) -> bytes:
        """The ``>MH`` and ``>MF`` commands that store the gait, back to back."""
        return b"".join(encode_command(command) for command in (self.header, *self.frames))

    def schedule(self, steps: int) -> Schedule:
        """The playback of ``steps`` passes (the interpreter's ``#PU slot steps``)."""
        return Schedule.of(
            [frame.transition_time_ms for frame in self.frames],
            (self.header.loop_begin, self.header.loop_end),
            steps,
        )


def load_gait(key: str) -> Gait:
    """Read one gait from the package data.

    Raises:
        KeyError: ``key`` is not one of :data:`GAIT_KEYS`.
    """
    if key not in GAIT_KEYS:
        raise KeyError(key)
    source = resources.files("roboscript.drivers.plen") / "motions" / f"{key}.json"
    data = json.loads(source.read_text(encoding="utf-8"))
    header, frames = motion_from_json(data)
    metadata = data.get("@metadata", {})
    backward = key == "walk_backward"
    counterclockwise = key == "turn_left"
    stride = float(metadata.get("stride_mm", 0.0))
    turn = float(metadata.get("turn_step_deg", 0.0))
    return Gait(
        key=key,
        header=header,
        frames=tuple(frames),
        stride_mm=-stride if backward else stride,
        turn_step_deg=-turn if counterclockwise else turn,
    )


def load_gaits() -> dict[str, Gait]:
    """Read every gait in :data:`GAIT_KEYS`, by key."""
    return {key: load_gait(key) for key in GAIT_KEYS}
