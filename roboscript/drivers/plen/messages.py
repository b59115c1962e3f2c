"""Messages of the PLEN2 serial protocol, firmware 1.4.2 ("Cytisus").

Every command the firmware parses has a frozen dataclass here, and so does each of the three
JSON replies of the getters ``<JS``, ``<MO`` and ``<VI``. The bytes live in
:mod:`roboscript.drivers.plen.codec`; this module only holds values and checks them.

Units and conventions:

* Angles are in **tenths of a degree** (``_ddeg``): ``900`` is 90.0°. PLEN2's joint range is
  ±900 (``ANGLE_MIN``/``ANGLE_MAX`` in the firmware).
* Joints are addressed by **id** 0–23; only 18 ids carry a servo (:data:`JOINT_NAMES`).
* Motion slots are 0–89; a motion has 1–20 frames, indexed from 0; a frame's transition time
  is 32–65535 ms, interpolated by the firmware in 32 ms steps.
* Motion frame values are **offsets from each joint's home angle**, like ``$AD``.

Range checks (``__post_init__`` raises :class:`~roboscript.errors.LocalProtocolError`) are the
host's policy, a little stricter than the firmware, which clamps or silently ignores bad
values:

* ``$AN``, ``>HO``, ``>MA``, ``>MI`` take an absolute angle within ±900. The firmware clamps
  ``$AN`` to the joint's [min, max] and *ignores* ``>HO``/``>MA``/``>MI`` outside ±900, so a
  larger value is always a mistake.
* ``$AD`` takes an offset within ±1800, the widest distance between two angles in range; the
  firmware clamps home + offset to [min, max].
* Motion frame offsets may use the whole int16 range: the firmware stores them verbatim and
  echoes them in ``<MO``.

Replies are checked only for shape and representable ranges, because they report whatever the
robot's EEPROM holds.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TypeAlias

from roboscript.errors import LocalProtocolError

__all__ = [
    "ANGLE_MAX_DDEG",
    "ANGLE_MIN_DDEG",
    "CODENAME",
    "DEVICE_NAME",
    "DIFF_LIMIT_DDEG",
    "FACTORY_HOME_DDEG",
    "FIRMWARE_VERSION",
    "FRAME_LENGTH_MAX",
    "FRAME_LENGTH_MIN",
    "JOINT_COUNT",
    "JOINT_IDS",
    "JOINT_NAMES",
    "LOOP_FOREVER",
    "NAME_LENGTH",
    "PLAY_FOREVER",
    "SLOT_COUNT",
    "TRANSITION_MAX_MS",
    "TRANSITION_MIN_MS",
    "Command",
    "GetJointSettings",
    "GetMotion",
    "GetVersion",
    "HomePosition",
    "JointSetting",
    "JointSettingsReply",
    "JumpCode",
    "LoopCode",
    "MotionFrame",
    "MotionHeader",
    "MotionReply",
    "MotionReplyFrame",
    "PlayMotion",
    "PlenMessage",
    "PopMotion",
    "PushMotion",
    "Reply",
    "ResetInterpreter",
    "ResetJointSettings",
    "SetAngle",
    "SetAngleDiff",
    "SetHome",
    "SetMax",
    "SetMin",
    "StopMotion",
    "VersionReply",
    "factory_joint_settings",
    "joint_id",
]

# --------------------------------------------------------------------------------------------
# Constants of firmware 1.4.2
# --------------------------------------------------------------------------------------------

FIRMWARE_VERSION = "1.4.2"
"""The firmware version these messages describe (``<VI`` ``version``)."""
CODENAME = "Cytisus"
"""The firmware's code name (``<VI`` ``codename``)."""
DEVICE_NAME = "PLEN2"
"""The device name (``<VI`` ``device``)."""

JOINT_COUNT = 24
"""Joint slots in the firmware, ids 0–23 (only 18 are wired to servos)."""
ANGLE_MIN_DDEG = -900
"""Lowest PLEN2 joint angle, tenths of a degree."""
ANGLE_MAX_DDEG = 900
"""Highest PLEN2 joint angle, tenths of a degree."""
DIFF_LIMIT_DDEG = ANGLE_MAX_DDEG - ANGLE_MIN_DDEG
"""Largest ``$AD`` offset we send (±1800 tenths of a degree): any wider is always clamped."""
SLOT_COUNT = 90
"""Motion slots 0–89."""
FRAME_LENGTH_MIN = 1
"""Fewest frames in a motion."""
FRAME_LENGTH_MAX = 20
"""Most frames in a motion (frame indices 0–19)."""
TRANSITION_MIN_MS = 32
"""Shortest frame transition, milliseconds (one interpolation step)."""
TRANSITION_MAX_MS = 65535
"""Longest frame transition, milliseconds (4 hex digits)."""
NAME_LENGTH = 20
"""Characters of a motion name (space-padded on the wire)."""
LOOP_FOREVER = 255
"""``MotionHeader.loop_count`` value meaning "loop until stopped"."""
PLAY_FOREVER = 0
"""``PushMotion.play_count`` value the firmware turns into its loop-forever count (0 − 1 = 255)."""

JOINT_NAMES: dict[int, str] = {
    0: "left_shoulder_pitch",
    1: "left_thigh_yaw",
    2: "left_shoulder_roll",
    3: "left_elbow_roll",
    4: "left_thigh_roll",
    5: "left_thigh_pitch",
    6: "left_knee_pitch",
    7: "left_foot_pitch",
    8: "left_foot_roll",
    12: "right_shoulder_pitch",
    13: "right_thigh_yaw",
    14: "right_shoulder_roll",
    15: "right_elbow_roll",
    16: "right_thigh_roll",
    17: "right_thigh_pitch",
    18: "right_knee_pitch",
    19: "right_foot_pitch",
    20: "right_foot_roll",
}
"""Joint id -> joint name (plen-ControlServer ``device_map.json``); ids 9–11, 21–23 are unused."""

JOINT_IDS: dict[str, int] = {name: joint for joint, name in JOINT_NAMES.items()}
"""Joint name -> joint id, the inverse of :data:`JOINT_NAMES`."""

_LEFT_HOME_DDEG = (-200, 50, 375, 250, -470, -220, 500, 200, 220)

FACTORY_HOME_DDEG: tuple[int, ...] = (
    *_LEFT_HOME_DDEG,
    0,
    0,
    0,
    *(-value for value in _LEFT_HOME_DDEG),
    0,
    0,
    0,
)
"""Factory home angle of every joint id 0–23, tenths of a degree.

Joints 0–8 are the left side; 12–20 mirror them with the sign flipped. The unused ids hold 0
(an assumption: nothing drives them).
"""

_INT16_MIN = -32768
_INT16_MAX = 32767


def joint_id(name: str) -> int:
    """Return the joint id (0–23) of a joint name such as ``"left_knee_pitch"``.

    Raises:
        LocalProtocolError: ``name`` is not one of the 18 PLEN2 joints.
    """
    try:
        return JOINT_IDS[name]
    except KeyError:
        raise LocalProtocolError(f"unknown PLEN2 joint name {name!r}") from None


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------


def _check_int(field: str, value: object, low: int, high: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int):
        raise LocalProtocolError(f"{field} must be an int, not {value!r}")
    if not low <= value <= high:
        raise LocalProtocolError(f"{field}={value} is outside {low}..{high}")


def _check_bool(field: str, value: object) -> None:
    if not isinstance(value, bool):
        raise LocalProtocolError(f"{field} must be a bool, not {value!r}")


def _check_joint(value: object) -> None:
    _check_int("joint", value, 0, JOINT_COUNT - 1)


def _check_slot(field: str, value: object) -> None:
    _check_int(field, value, 0, SLOT_COUNT - 1)


def _check_angle(field: str, value: object) -> None:
    _check_int(field, value, ANGLE_MIN_DDEG, ANGLE_MAX_DDEG)


def _int_tuple(field: str, values: Iterable[int], low: int, high: int) -> tuple[int, ...]:
    if isinstance(values, (str, bytes)):
        raise LocalProtocolError(f"{field} must be a sequence of ints, not {values!r}")
    try:
        result = tuple(values)
    except TypeError:
        raise LocalProtocolError(f"{field} must be a sequence of ints, not {values!r}") from None
    if len(result) != JOINT_COUNT:
        raise LocalProtocolError(f"{field} needs {JOINT_COUNT} values, got {len(result)}")
    for index, value in enumerate(result):
        _check_int(f"{field}[{index}]", value, low, high)
    return result


# --------------------------------------------------------------------------------------------
# Controller commands ($)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class SetAngle:
    """``$AN``: move one joint to an absolute angle. Wire: ``$ANjjvvv`` (id 2, value 3 hex).

    The firmware clamps the angle to the joint's [min, max].

    Attributes:
        joint: Joint id, 0–23.
        angle_ddeg: Absolute angle in tenths of a degree, −900..900.
    """

    joint: int
    angle_ddeg: int

    def __post_init__(self) -> None:
        _check_joint(self.joint)
        _check_angle("angle_ddeg", self.angle_ddeg)


@dataclass(frozen=True, slots=True)
class SetAngleDiff:
    """``$AD``: move one joint to home + an offset. Wire: ``$ADjjvvv`` (id 2, value 3 hex).

    The firmware clamps home + offset to the joint's [min, max].

    Attributes:
        joint: Joint id, 0–23.
        diff_ddeg: Offset from the joint's home angle, tenths of a degree, −1800..1800.
    """

    joint: int
    diff_ddeg: int

    def __post_init__(self) -> None:
        _check_joint(self.joint)
        _check_int("diff_ddeg", self.diff_ddeg, -DIFF_LIMIT_DDEG, DIFF_LIMIT_DDEG)


@dataclass(frozen=True, slots=True)
class PlayMotion:
    """``$PM`` (alias ``$MP``, accepted when decoding): play a stored motion. Wire: ``$PMss``.

    The firmware ignores it while another motion is playing.

    Attributes:
        slot: Motion slot, 0–89.
    """

    slot: int

    def __post_init__(self) -> None:
        _check_slot("slot", self.slot)


@dataclass(frozen=True, slots=True)
class StopMotion:
    """``$SM`` (alias ``$MS``, accepted when decoding): stop the playing motion.

    The firmware clears the motion's loop and jump flags, so the motion stops after its
    remaining frames, not at once.
    """


@dataclass(frozen=True, slots=True)
class HomePosition:
    """``$HP``: reload the joint settings and move every joint to its home angle."""


# --------------------------------------------------------------------------------------------
# Interpreter commands (#)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class PushMotion:
    """``#PU``: queue a motion for the interpreter. Wire: ``#PUsscc`` (slot 2, count 2 hex).

    About the count: the firmware stores ``count − 1`` as the motion's loop counter (extra
    plays after the first), because the official apps, and plen-ControlServer's ``push()``,
    send "repeats + 1". So the wire count is the **number of times the motion plays**, and that
    is what :attr:`play_count` holds: it is sent unchanged. ``#PU0a03`` plays slot 10 three
    times. ``play_count=0`` (:data:`PLAY_FOREVER`) makes the firmware's 8-bit counter wrap to
    255, its "loop forever" value. The queue holds 32 entries.

    Attributes:
        slot: Motion slot, 0–89.
        play_count: How many times the motion plays, 1–255, or 0 for "until stopped".
    """

    slot: int
    play_count: int = 1

    def __post_init__(self) -> None:
        _check_slot("slot", self.slot)
        _check_int("play_count", self.play_count, 0, 255)


@dataclass(frozen=True, slots=True)
class PopMotion:
    """``#PO``: pop the next queued motion and play it."""


@dataclass(frozen=True, slots=True)
class ResetInterpreter:
    """``#RI``: clear the interpreter's queue."""


# --------------------------------------------------------------------------------------------
# Setter commands (>)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class SetHome:
    """``>HO``: set a joint's home angle (kept in EEPROM). Wire: ``>HOjjvvv``.

    The firmware ignores a home outside the joint's [min, max].

    Attributes:
        joint: Joint id, 0–23.
        angle_ddeg: Home angle, tenths of a degree, −900..900.
    """

    joint: int
    angle_ddeg: int

    def __post_init__(self) -> None:
        _check_joint(self.joint)
        _check_angle("angle_ddeg", self.angle_ddeg)


@dataclass(frozen=True, slots=True)
class SetMax:
    """``>MA``: set a joint's maximum angle (kept in EEPROM). Wire: ``>MAjjvvv``.

    The firmware ignores a maximum that is not above the joint's minimum.

    Attributes:
        joint: Joint id, 0–23.
        angle_ddeg: Maximum angle, tenths of a degree, −900..900.
    """

    joint: int
    angle_ddeg: int

    def __post_init__(self) -> None:
        _check_joint(self.joint)
        _check_angle("angle_ddeg", self.angle_ddeg)


@dataclass(frozen=True, slots=True)
class SetMin:
    """``>MI``: set a joint's minimum angle (kept in EEPROM). Wire: ``>MIjjvvv``.

    The firmware ignores a minimum that is not below the joint's maximum.

    Attributes:
        joint: Joint id, 0–23.
        angle_ddeg: Minimum angle, tenths of a degree, −900..900.
    """

    joint: int
    angle_ddeg: int

    def __post_init__(self) -> None:
        _check_joint(self.joint)
        _check_angle("angle_ddeg", self.angle_ddeg)


@dataclass(frozen=True, slots=True)
class ResetJointSettings:
    """``>JS``: reset every joint's min, max and home to the factory values."""


@dataclass(frozen=True, slots=True)
class MotionHeader:
    """``>MH``: write a motion's header. Wire: ``>MH`` + 35 characters::

        slot(2) name(20, space-padded) use_loop(1) loop_begin(2) loop_end(2) loop_count(2)
        use_jump(1) jump_slot(2) use_extra(1) frame_length(2)

    Numbers are hex; the flags are ``0``/``1`` (the firmware reads any other character as 1).

    Attributes:
        slot: Motion slot, 0–89.
        name: Motion name, at most 20 printable ASCII characters, without ``"`` or ``\\`` (the
            firmware echoes it unescaped inside the ``<MO`` JSON) and without trailing spaces
            (they are the padding and are stripped when decoding).
        frame_length: Number of frames, 1–20.
        use_loop: Whether frames ``loop_begin``..``loop_end`` repeat.
        loop_begin: First frame index of the loop, 0–19.
        loop_end: Last frame index of the loop, 0–19.
        loop_count: Loop repetitions, 0–255; 255 (:data:`LOOP_FOREVER`) loops until stopped.
        use_jump: Whether to continue with another motion at the end.
        jump_slot: The motion slot to jump to, 0–89.
        use_extra: The extra-code flag (reserved by the firmware).
    """

    slot: int
    name: str
    frame_length: int
    use_loop: bool = False
    loop_begin: int = 0
    loop_end: int = 0
    loop_count: int = 0
    use_jump: bool = False
    jump_slot: int = 0
    use_extra: bool = False

    def __post_init__(self) -> None:
        _check_slot("slot", self.slot)
        if not isinstance(self.name, str):
            raise LocalProtocolError(f"name must be a str, not {self.name!r}")
        if len(self.name) > NAME_LENGTH:
            raise LocalProtocolError(f"name {self.name!r} is longer than {NAME_LENGTH}")
        for char in self.name:
            if not " " <= char <= "~" or char in '"\\':
                raise LocalProtocolError(
                    f"name {self.name!r} may hold only printable ASCII without '\"' or '\\'"
                )
        if self.name != self.name.rstrip(" "):
            raise LocalProtocolError(f"name {self.name!r} ends with spaces (they are padding)")
        _check_int("frame_length", self.frame_length, FRAME_LENGTH_MIN, FRAME_LENGTH_MAX)
        _check_bool("use_loop", self.use_loop)
        _check_int("loop_begin", self.loop_begin, 0, FRAME_LENGTH_MAX - 1)
        _check_int("loop_end", self.loop_end, 0, FRAME_LENGTH_MAX - 1)
        _check_int("loop_count", self.loop_count, 0, 255)
        _check_bool("use_jump", self.use_jump)
        _check_slot("jump_slot", self.jump_slot)
        _check_bool("use_extra", self.use_extra)


@dataclass(frozen=True, slots=True)
class MotionFrame:
    """``>MF``: write one frame of a motion. Wire: ``>MF`` + 104 characters::

        slot(2) index(2) transition_time_ms(4) then 24 × value(4, int16 two's complement)

    Attributes:
        slot: Motion slot, 0–89.
        index: Frame index within the motion, 0–19.
        transition_time_ms: Time to reach this frame from the previous one, 32–65535 ms.
        offsets_ddeg: 24 offsets from each joint's home angle, tenths of a degree, indexed by
            joint id (int16; a list is accepted and stored as a tuple).
    """

    slot: int
    index: int
    transition_time_ms: int
    offsets_ddeg: tuple[int, ...]

    def __post_init__(self) -> None:
        _check_slot("slot", self.slot)
        _check_int("index", self.index, 0, FRAME_LENGTH_MAX - 1)
        _check_int(
            "transition_time_ms", self.transition_time_ms, TRANSITION_MIN_MS, TRANSITION_MAX_MS
        )
        values = _int_tuple("offsets_ddeg", self.offsets_ddeg, _INT16_MIN, _INT16_MAX)
        object.__setattr__(self, "offsets_ddeg", values)


# --------------------------------------------------------------------------------------------
# Getter commands (<)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class GetJointSettings:
    """``<JS``: ask for every joint's settings; answered by :class:`JointSettingsReply`."""


@dataclass(frozen=True, slots=True)
class GetMotion:
    """``<MO``: ask for a stored motion; answered by :class:`MotionReply`. Wire: ``<MOss``.

    Attributes:
        slot: Motion slot, 0–89.
    """

    slot: int

    def __post_init__(self) -> None:
        _check_slot("slot", self.slot)


@dataclass(frozen=True, slots=True)
class GetVersion:
    """``<VI``: ask for the version; answered by :class:`VersionReply`."""


# --------------------------------------------------------------------------------------------
# Replies (JSON, device -> host)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class JointSetting:
    """One joint's entry of the ``<JS`` reply (``{"@device", "max", "min", "home"}``).

    Attributes:
        joint: Joint id, 0–23.
        min_ddeg: Minimum angle, tenths of a degree.
        max_ddeg: Maximum angle, tenths of a degree.
        home_ddeg: Home angle, tenths of a degree.
    """

    joint: int
    min_ddeg: int
    max_ddeg: int
    home_ddeg: int

    def __post_init__(self) -> None:
        _check_joint(self.joint)
        _check_int("min_ddeg", self.min_ddeg, _INT16_MIN, _INT16_MAX)
        _check_int("max_ddeg", self.max_ddeg, _INT16_MIN, _INT16_MAX)
        _check_int("home_ddeg", self.home_ddeg, _INT16_MIN, _INT16_MAX)


@dataclass(frozen=True, slots=True)
class JointSettingsReply:
    """The ``<JS`` reply: the settings of all 24 joint slots.

    Attributes:
        joints: 24 :class:`JointSetting`, ``joints[i].joint == i`` (a list is accepted and
            stored as a tuple).
    """

    joints: tuple[JointSetting, ...]

    def __post_init__(self) -> None:
        joints = tuple(self.joints)
        if len(joints) != JOINT_COUNT:
            raise LocalProtocolError(f"joints needs {JOINT_COUNT} entries, got {len(joints)}")
        for index, entry in enumerate(joints):
            if not isinstance(entry, JointSetting) or entry.joint != index:
                raise LocalProtocolError(
                    f"joints[{index}] must be the JointSetting of joint {index}"
                )
        object.__setattr__(self, "joints", joints)


def factory_joint_settings() -> JointSettingsReply:
    """Return the factory joint settings (what ``>JS`` restores): ±900 limits and the homes of
    :data:`FACTORY_HOME_DDEG`."""
    return JointSettingsReply(
        tuple(
            JointSetting(joint, ANGLE_MIN_DDEG, ANGLE_MAX_DDEG, home)
            for joint, home in enumerate(FACTORY_HOME_DDEG)
        )
    )


@dataclass(frozen=True, slots=True)
class LoopCode:
    """The ``loop`` code of a motion (``{"method": "loop", "arguments": [begin, end, count]}``).

    Attributes:
        begin: First frame index of the loop.
        end: Last frame index of the loop.
        count: Repetitions; 255 (:data:`LOOP_FOREVER`) loops until stopped.
    """

    begin: int
    end: int
    count: int

    def __post_init__(self) -> None:
        _check_int("begin", self.begin, 0, 255)
        _check_int("end", self.end, 0, 255)
        _check_int("count", self.count, 0, 255)


@dataclass(frozen=True, slots=True)
class JumpCode:
    """The ``jump`` code of a motion (``{"method": "jump", "arguments": [slot]}``).

    Attributes:
        slot: The motion slot played after this one.
    """

    slot: int

    def __post_init__(self) -> None:
        _check_int("slot", self.slot, 0, 255)


@dataclass(frozen=True, slots=True)
class MotionReplyFrame:
    """One frame of the ``<MO`` reply.

    Attributes:
        index: Frame index (``@index``).
        transition_time_ms: Transition time, milliseconds.
        offsets_ddeg: 24 offsets from home, tenths of a degree, indexed by joint id.
    """

    index: int
    transition_time_ms: int
    offsets_ddeg: tuple[int, ...]

    def __post_init__(self) -> None:
        _check_int("index", self.index, 0, 255)
        _check_int("transition_time_ms", self.transition_time_ms, 0, TRANSITION_MAX_MS)
        values = _int_tuple("offsets_ddeg", self.offsets_ddeg, _INT16_MIN, _INT16_MAX)
        object.__setattr__(self, "offsets_ddeg", values)


@dataclass(frozen=True, slots=True)
class MotionReply:
    """The ``<MO`` reply: one stored motion, as the firmware dumps it.

    The checks are loose (any 8-bit frame index, transition 0–65535) because the reply shows
    whatever the EEPROM holds; :meth:`to_install` applies the strict command checks.

    Attributes:
        slot: Motion slot, 0–89.
        name: Motion name with its padding stripped.
        frames: The frames, ``frames[i].index == i``.
        loop: The loop code, or ``None`` when the motion does not loop.
        jump: The jump code, or ``None`` when the motion does not jump.
    """

    slot: int
    name: str
    frames: tuple[MotionReplyFrame, ...]
    loop: LoopCode | None = None
    jump: JumpCode | None = None

    def __post_init__(self) -> None:
        _check_slot("slot", self.slot)
        if not isinstance(self.name, str) or len(self.name) > NAME_LENGTH:
            raise LocalProtocolError(f"name must be a str of at most {NAME_LENGTH} characters")
        frames = tuple(self.frames)
        if len(frames) > 255:
            raise LocalProtocolError(f"a motion has at most 255 frames, got {len(frames)}")
        for index, frame in enumerate(frames):
            if not isinstance(frame, MotionReplyFrame) or frame.index != index:
                raise LocalProtocolError(
                    f"frames[{index}] must be a MotionReplyFrame of index {index}"
                )
        if self.loop is not None and not isinstance(self.loop, LoopCode):
            raise LocalProtocolError(f"loop must be a LoopCode or None, not {self.loop!r}")
        if self.jump is not None and not isinstance(self.jump, JumpCode):
            raise LocalProtocolError(f"jump must be a JumpCode or None, not {self.jump!r}")
        object.__setattr__(self, "frames", frames)

    @property
    def frame_length(self) -> int:
        """Number of frames (the reply's ``@frame_length``)."""
        return len(self.frames)

    def to_install(self) -> tuple[MotionHeader, list[MotionFrame]]:
        """Return the ``>MH`` and ``>MF`` commands that store this motion again.

        Raises:
            LocalProtocolError: The dumped motion breaks a command's range checks.
        """
        loop = self.loop
        jump = self.jump
        header = MotionHeader(
            slot=self.slot,
            name=self.name,
            frame_length=self.frame_length,
            use_loop=loop is not None,
            loop_begin=loop.begin if loop else 0,
            loop_end=loop.end if loop else 0,
            loop_count=loop.count if loop else 0,
            use_jump=jump is not None,
            jump_slot=jump.slot if jump else 0,
        )
        frames = [
            MotionFrame(self.slot, frame.index, frame.transition_time_ms, frame.offsets_ddeg)
            for frame in self.frames
        ]
        return header, frames

    @classmethod
    def from_install(cls, header: MotionHeader, frames: Iterable[MotionFrame]) -> MotionReply:
        """Build the reply a device holding ``header`` and ``frames`` sends to ``<MO``.

        Args:
            header: The stored header.
            frames: The stored frames, in index order, ``header.frame_length`` of them.

        Raises:
            LocalProtocolError: The frames do not match the header.
        """
        frame_list = list(frames)
        if len(frame_list) != header.frame_length:
            raise LocalProtocolError(
                f"header says {header.frame_length} frames, got {len(frame_list)}"
            )
        reply_frames: list[MotionReplyFrame] = []
        for index, frame in enumerate(frame_list):
            if frame.slot != header.slot or frame.index != index:
                raise LocalProtocolError(
                    f"frame {index} must have slot {header.slot} and index {index}"
                )
            reply_frames.append(
                MotionReplyFrame(index, frame.transition_time_ms, frame.offsets_ddeg)
            )
        return cls(
            slot=header.slot,
            name=header.name,
            frames=tuple(reply_frames),
            loop=(
                LoopCode(header.loop_begin, header.loop_end, header.loop_count)
                if header.use_loop
                else None
            ),
            jump=JumpCode(header.jump_slot) if header.use_jump else None,
        )


@dataclass(frozen=True, slots=True)
class VersionReply:
    """The ``<VI`` reply.

    Attributes:
        device: Device name, ``"PLEN2"``.
        codename: Firmware code name, ``"Cytisus"`` for 1.4.2.
        version: Firmware version, ``"1.4.2"``.
    """

    device: str = DEVICE_NAME
    codename: str = CODENAME
    version: str = FIRMWARE_VERSION

    def __post_init__(self) -> None:
        for field, value in (
            ("device", self.device),
            ("codename", self.codename),
            ("version", self.version),
        ):
            if not isinstance(value, str):
                raise LocalProtocolError(f"{field} must be a str, not {value!r}")


Command: TypeAlias = (
    SetAngle
    | SetAngleDiff
    | PlayMotion
    | StopMotion
    | HomePosition
    | PushMotion
    | PopMotion
    | ResetInterpreter
    | SetHome
    | SetMax
    | SetMin
    | ResetJointSettings
    | MotionHeader
    | MotionFrame
    | GetJointSettings
    | GetMotion
    | GetVersion
)
"""Every command the host sends (and the device decodes)."""

Reply: TypeAlias = JointSettingsReply | MotionReply | VersionReply
"""Every reply the device sends (and the host decodes)."""

PlenMessage: TypeAlias = Command | Reply
"""Anything :class:`~roboscript.drivers.plen.codec.PlenCodec` decodes."""
