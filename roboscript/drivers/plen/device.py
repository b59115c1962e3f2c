"""A simulated PLEN2: firmware 1.4.2's device side, on a simulated body.

This is a second, independent implementation of the protocol (it never imports the host
driver), written from the firmware's behaviour:

* Every command is silent except the getters ``<JS``, ``<MO`` and ``<VI``, answered in the
  firmware's tab-indented, CRLF JSON. Bad bytes are dropped without a word. Nothing is sent
  when a host connects.
* Joints: 24 slots holding absolute angles in tenths of a degree, each with min, max and home
  (``>HO``, ``>MA``, ``>MI``, ``>JS``); ``$AN`` and ``$AD`` are clamped to [min, max]; ``$HP``
  and ``>JS`` (which restores the factory settings first) move every joint home.
* Motion memory: 90 slots of a header and up to 20 frames, written by ``>MH`` and ``>MF``.
* Playback with the motion controller's timing: each joint moves one equal fixed-point step
  (16 fractional bits, C integer division) towards the next frame per update,
  ``transition_time_ms // 32`` updates per frame, modulo 256 (the firmware's ``uint8_t``).
  An update falls due every 32.768 ms (``UPDATE_INTERVAL_S``, counted from power-on: Timer 1's
  4.096 ms overflow, once per eight multiplexed servos, ``JointController.cpp``) and runs at
  once if a motion plays, else waits for one, so the first update of a motion started after a
  pause comes straight away (``m_1cycle_finished`` stays set while nothing plays). Interpolation
  starts from the last frame the controller played, not from where ``$AD`` left a joint.
  ``$PM`` is ignored while a motion plays. A loop code ``[begin, end, count]`` jumps back after
  ``end`` ``count`` times (0 and 255: until stopped), then plays on; a jump code continues with
  another slot. ``$SM`` clears both flags, so the frame in progress and the rest of the motion
  still play.
* Interpreter: ``#PU`` queues (slot, count − 1) (31 entries), ``#PO`` plays the next entry with
  that loop count over the motion's loop section (or the whole motion), ``#RI`` empties the
  queue and stops at once; an entry is also played when a motion ends.

The link (``transport``): over USB, the PLEN2's own port, the host waits while the firmware is
busy and a command acts the moment it is written. Over the 2 Mbaud UART (``transport: uart``,
the line the firmware tier's emulated board is reached by) the board keeps the firmware's
clock: bytes arrive 5 us apart, ``loop()`` reads one a turn (:data:`READ_BYTE_S`) and none
while a command runs (a reply, :data:`TEXT_BYTE_S` a byte of text; an EEPROM write or read), and a
byte that arrives while the 64-byte receive ring is full is lost: a burst of more than about
75 bytes loses some, which is why the driver writes 32 bytes every 50 ms.

Walking: the body moves by the legs' own geometry (a planar two-segment leg per side, thigh
and shank ``LEG_SEGMENT_MM`` long, straight at the factory home angles, hips
``HIP_WIDTH_MM`` apart). Leaning (the thigh rolls) lowers one hip and raises the other. A foot
is planted over a joint change when it reaches lowest both before and after it; the body then
moves by the opposite of that foot's travel, forward along the heading and round by its
thigh-yaw twist (both feet down: their mean). The sign conventions, an assumption about the
servo mounting: a positive left thigh or knee pitch offset swings the thigh forward or bends
the knee, a positive left thigh roll leans the robot right; the right side is mirrored
(negative offsets), as its home angles are; a positive thigh-yaw offset turns that foot's toes
outward. Ankles and arms do not move the body. Walls stop the body as they stop a wheeled one.

Slots never written are erased (0xFF) as the EEPROM is delivered. An erased header reads
as slot 255 with every flag set, so ``$PM`` of an erased slot plays as the firmware plays
it: ``Frame::get`` refuses slot 255 and leaves the frame buffer as the last motion left it,
and the motion goes on between the two buffers, looping for ever, until ``$SM`` (a jump to
a slot past the last one plays its own motion again; one to an erased slot plays that).
An ``>MF`` that was never written reads as an erased frame (65535 ms, every value −1).

Simplification: an erased slot dumps as a motion of no frames. The firmware prints the
erased header as it reads it (slot 255, a name of 0xFF bytes, a loop and a jump code) and
then 255 frames (``MotionController::dump`` loops to the header's ``frame_length``;
``Frame::get`` refuses an index of 20 or more and leaves the previous frame in place), about
260 KB that no host reads as a motion.
"""

from __future__ import annotations

import math
import re
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, cast

from roboscript.codec import Role, readable
from roboscript.drivers.plen import messages as m
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.errors import ProfileError

if TYPE_CHECKING:
    from roboscript.robot_profile import RobotProfile
    from roboscript.sim.body import Body

__all__ = [
    "HIP_WIDTH_MM",
    "LEG_SEGMENT_MM",
    "TRANSPORTS",
    "UPDATE_INTERVAL_S",
    "Plen2Board",
    "simulated_device",
]

RESET_UART_ON_S = 3.39e-3
"""After a reset, when the firmware's ``setup()`` opens its UART (``System::begin``), seconds:
a byte that arrives before is lost. Measured on the emulated ATmega32u4 build (UCSR1B's
RXEN1 set 3.39 ms after the reset)."""
UPDATE_INTERVAL_S = 8 * 1024 * 64 / 16_000_000
"""The motion controller's update period, seconds: 32.768 ms, eight Timer 1 overflows (10-bit
fast PWM, prescaler 64, 16 MHz), one per multiplexed servo line; ``UPDATE_INTERVAL_MS`` (32)
is the nominal value the firmware divides transition times by."""
LEG_SEGMENT_MM = 45.0
"""Length of the simulated thigh and of the shank, mm."""
HIP_WIDTH_MM = 50.0
"""Distance between the simulated hip joints, mm."""

TRANSPORTS = ("usb", "uart")
"""How a host reaches the board: its USB serial port or its 2 Mbaud UART."""
LINE_BYTE_S = 10 / 2_000_000
"""One byte on the serial line, seconds: 10 bits (8N1) at ``System.h``'s
``BLESERIAL_BAUDRATE`` of 2,000,000."""
RECEIVE_RING_BYTES = 63
"""Bytes the ATmega32u4 core's 64-byte receive ring holds: a byte that arrives while it is
full is lost."""
READ_BYTE_S = 29e-6
"""The firmware's time per byte it reads, seconds: ``loop()`` reads one byte a turn (also
polling the USB port), about 460 cycles at 16 MHz; measured on the emulated firmware (a run
of stray bytes ahead of ``<VI`` delays its reply 29 us a byte). The line brings a byte every
5 us, so a burst of more than about 75 bytes overflows the ring."""
TEXT_BYTE_S = 7.6e-6
"""The firmware's time per byte of a dump's text (``<JS``, ``<MO``: its keys, braces, tabs and
line ends), seconds: measured on the emulated firmware, where ``<JS`` (1742 bytes, 1469 of
them text) takes 23.0 ms from its first byte to its last."""
NUMBER_S = 12e-6
DIGIT_S = 44e-6
SIGN_S = 5e-6
"""A number in a dump takes the firmware ``NUMBER_S`` and ``DIGIT_S`` a digit (``Print``'s
division by 10 on an 8-bit core), and ``SIGN_S`` more when negative, seconds: 56, 100 and
144 us for 1 to 3 digits, measured on the emulated firmware; its digits are written once
all are worked out."""
_NUMBER_OR_TEXT = re.compile(rb"-?[0-9]+|[^-0-9]+|-")
VERSION_BYTE_S = 11.6e-6
"""The same for ``<VI``, printed from flash strings only (73 bytes in 0.84 ms)."""
REPLY_START_S = 33e-6
"""From reading a getter's last byte to its reply's first byte leaving the line, seconds."""
EEPROM_SLOT_WRITE_S = 6.4e-3
"""One 30-byte slot written to the motion EEPROM: the I2C write at 400 kHz, then
``ExternalEEPROM::writeSlot``'s ``delay(5)`` (``>MH`` writes one, ``>MF`` two)."""
MOTION_READ_S = 4.3e-3
"""Reading a motion's header and first frame from the motion EEPROM (``$PM``, ``#PO``)."""
RX_ISR_S = 5e-6
"""The core's receive interrupt (``HardwareSerial::_rx_complete_irq`` with its register saves,
about 80 cycles), seconds: a byte that arrives while the firmware works takes this from it,
so a burst at 2 Mbaud (a byte every 5 us) slows its reading and fills the ring sooner.
Fitted to the emulated firmware: bursts of 5 to 8 ``$AN`` commands and 8 ``<VI`` lose the
getters the firmware loses (it answers 8, 5, 2, 0 of them; 5 or 6 us fit, 4 us does not)."""
SET_ANGLE_S = 80e-6
"""``$AN``: ``JointController::setAngle``'s clamp and its ``map()`` of the angle to the
servo's PWM count (32-bit arithmetic on an 8-bit core), seconds; measured on the emulated
firmware (each ``$AN`` ahead of ``<VI`` delays its reply 80 us more than 8 stray bytes do)."""
SET_ANGLE_DIFF_S = 86e-6
"""``$AD``: the same after adding the joint's home, seconds (measured alike: 86 us)."""
SETTINGS_S = 1.9e-3
"""``$HP`` and ``>JS``: 144 bytes of joint settings read or written, 24 servo outputs mapped."""

_UPDATE_INTERVAL_MS = 32
_FIXED_BITS = 16
_MOST_PASSED_FRAMES = 256
"""A bound on frames of no updates passed in one turn of the loop (a looping motion of such
frames spins in the firmware until its next update)."""
_QUEUE_SIZE = 32
_ERASED_TIME_MS = 0xFFFF
_ERASED_VALUE = -1
_TOUCH_MM = 0.01
"""A foot this close to the lowest one is on the floor too, mm."""

_LEFT_THIGH_YAW, _LEFT_THIGH_ROLL, _LEFT_THIGH_PITCH, _LEFT_KNEE = 1, 4, 5, 6
_RIGHT_THIGH_YAW, _RIGHT_THIGH_ROLL, _RIGHT_THIGH_PITCH, _RIGHT_KNEE = 13, 16, 17, 18


def _cdiv(a: int, b: int) -> int:
    """C integer division (truncates toward zero)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b >= 0) else -q


@dataclass(frozen=True)
class _Foot:
    """Where a foot is relative to the pelvis: ahead, below, and turned (clockwise)."""

    forward_mm: float
    down_mm: float
    yaw_cw_deg: float


@dataclass
class _Frame:
    index: int
    transition_time_ms: int
    values: list[int]


@dataclass(frozen=True)
class _Header:
    """The header of the motion playing, as ``MotionController`` holds it (the firmware edits
    its loop and jump fields as it plays)."""

    slot: int
    frame_length: int
    use_loop: bool
    loop_begin: int
    loop_end: int
    loop_count: int
    use_jump: bool
    jump_slot: int

    @classmethod
    def of(cls, header: m.MotionHeader) -> _Header:
        return cls(
            header.slot,
            header.frame_length,
            header.use_loop,
            header.loop_begin,
            header.loop_end,
            header.loop_count,
            header.use_jump,
            header.jump_slot,
        )


_ERASED_HEADER = _Header(0xFF, 0xFF, True, 0xFF, 0xFF, 0xFF, True, 0xFF)
"""``Header::get`` of a slot never written: every byte 0xFF, every flag bit set."""


class Plen2Board:
    """The simulated PLEN2 control board on a body (see the module docstring).

    Args:
        body: The simulated body the board moves.
        transport: ``"usb"`` (the PLEN2's own link: the host waits while the firmware is
            busy, nothing is lost, and a command acts the moment it is written) or ``"uart"``
            (its 2 Mbaud serial line: bytes arrive 5 us apart and are read as the firmware
            reads them, a byte a turn of its loop and none while a command runs, and a byte
            that arrives while the 64-byte receive ring is full is lost).
    """

    def __init__(self, body: Body, transport: str = "usb") -> None:
        if transport not in TRANSPORTS:
            raise ValueError(f"transport must be one of {TRANSPORTS}, not {transport!r}")
        self.body = body
        self.transport = transport
        self.codec = PlenCodec(Role.DEVICE)
        self._out = bytearray()
        self._arrivals: deque[tuple[float, int]] = deque()
        """Over the UART, the host's bytes on the line: (when each arrives s, the byte)."""
        self._line_free_s = 0.0
        self._ring: deque[int] = deque()
        self._read_s = 0.0
        """When the firmware reads its next byte (it is busy until then), seconds."""
        self._now_s = 0.0
        self._replies: deque[tuple[float, float, bytes]] = deque()
        """Over the UART, replies still being written: (first byte's time s, s a byte, bytes)."""
        self.lost_bytes = 0
        """Bytes that arrived while the receive ring was full."""
        factory = m.factory_joint_settings().joints
        self.min_ddeg = [joint.min_ddeg for joint in factory]
        self.max_ddeg = [joint.max_ddeg for joint in factory]
        self.home_ddeg = [joint.home_ddeg for joint in factory]
        self.angles_ddeg = list(self.home_ddeg)
        """Absolute angle of every joint now, tenths of a degree."""
        self.headers: dict[int, m.MotionHeader] = {}
        self.frames: dict[tuple[int, int], m.MotionFrame] = {}
        self.queue: deque[tuple[int, int]] = deque()
        """The interpreter's queue: (slot, loop count)."""
        self.playing = False
        self.header: _Header | None = None
        """The header of the motion playing (its loop and jump flags change as it plays)."""
        self._current = _Frame(0, 0, [0] * m.JOINT_COUNT)
        self._next = _Frame(0, 0, [0] * m.JOINT_COUNT)
        self._count = 0
        self._fixed = [0] * m.JOINT_COUNT
        self._step = [0] * m.JOINT_COUNT
        self._next_update_s = UPDATE_INTERVAL_S
        self._update_due = False
        self.update_count = 0
        """Motion-controller updates run since power-on (one each period while playing)."""
        self._deaf_until_s = -math.inf  # after a reset: until its UART is open again
        self._feet = self._foot_positions()

    # ------------------------------------------------------------------------- SimDevice API

    def connect(self, now_s: float) -> None:
        """A host opened the port: the firmware says nothing and forgets a half command."""
        self.codec = PlenCodec(Role.DEVICE)
        self._arrivals.clear()
        self._ring.clear()

    def receive(self, data: bytes, now_s: float) -> None:
        """The host writes command bytes: over USB they are acted on at once; over the UART
        they arrive one byte time apart and are read as the firmware reads them."""
        if now_s < self._deaf_until_s - 1e-9 and self.transport == "usb":
            return  # still starting after a reset: lost
        if self.transport == "usb":
            self.codec.receive_data(data)
            for message in readable(self.codec):  # the firmware resets its parser silently
                # mypy widens PlenMessage's long union to object through the generic.
                self._handle(cast(m.PlenMessage, message))
            return
        self._now_s = now_s
        start_s = max(now_s, self._line_free_s)  # a write follows what is still on the line
        deaf_until_s = self._deaf_until_s - 1e-9  # a byte that comes before is lost
        self._arrivals.extend(
            (arrival_s, byte)
            for index, byte in enumerate(data)
            if (arrival_s := start_s + (index + 1) * LINE_BYTE_S) >= deaf_until_s
        )
        self._line_free_s = start_s + len(data) * LINE_BYTE_S
        self._read_bytes(now_s)

    def _read_bytes(self, now_s: float) -> None:
        """Read what has arrived by ``now_s``, a byte per :data:`READ_BYTE_S` of the
        firmware's time and none while a command keeps it busy; a byte that arrives while the
        receive ring is full is lost."""
        ring, arrivals = self._ring, self._arrivals
        while True:
            read_s = self._read_s
            # between two reads the ring only fills: a byte is kept if it has room on arrival
            arrived_by_s = min(read_s, now_s) + 1e-9  # a byte due exactly then is there
            while arrivals and arrivals[0][0] <= arrived_by_s:
                arrival_s, byte = arrivals.popleft()
                if arrival_s < read_s - 1e-9:
                    # its receive interrupt takes the time from the firmware's work
                    read_s = self._read_s = read_s + RX_ISR_S
                    arrived_by_s = min(read_s, now_s) + 1e-9
                if len(ring) < RECEIVE_RING_BYTES:
                    ring.append(byte)
                else:
                    self.lost_bytes += 1
            if read_s > now_s:
                return
            if not ring:
                arrival_s = arrivals[0][0] if arrivals else math.inf
                if arrival_s > now_s:
                    self._read_s = now_s
                    return
                self._read_s = max(read_s, arrival_s)
                continue
            self.codec.receive_data(bytes((ring.popleft(),)))
            busy_s = READ_BYTE_S
            for message in readable(self.codec):  # the firmware resets its parser silently
                # mypy widens PlenMessage's long union to object through the generic.
                busy_s += self._handle(cast(m.PlenMessage, message))
            self._read_s = read_s + busy_s

    def step(self, now_s: float) -> None:
        """Read the bytes that have arrived, then run the updates due by ``now_s`` (one for
        each period passed while a motion plays, and the one left due when a motion has just
        started)."""
        self._now_s = now_s
        self._read_bytes(now_s)
        while True:
            if self.playing and self._update_due:
                self._update_due = False
                self._update()
            if now_s < self._next_update_s - 1e-9:
                return
            self._next_update_s += UPDATE_INTERVAL_S
            self._update_due = True

    def pending_input_bytes(self) -> int:
        """Request bytes received and not yet a whole message (a frame the host has not
        finished)."""
        return len(self._arrivals) + len(self._ring) + self.codec.pending_bytes()

    def read_output(self) -> bytes:
        """Take the bytes written since the last call (over the UART, those on the line by
        the time the board was last stepped)."""
        replies = self._replies
        while replies:
            first_s, byte_s, data = replies[0]
            count = min(len(data), math.floor((self._now_s - first_s) / byte_s + 1e-6) + 1)
            if count <= 0:
                break
            self._out += data[:count]
            if count < len(data):
                replies[0] = (first_s + count * byte_s, byte_s, data[count:])
                break
            replies.popleft()
        data = bytes(self._out)
        self._out.clear()
        return data

    def reset(self, now_s: float) -> None:
        """The board resets at ``now_s`` (its reset line, or its supply dipping under the
        servos' load): ``setup()`` runs again. What the firmware keeps in EEPROM stays (the
        joint settings in the chip's own, the motions in the external one); everything else
        starts afresh: no motion plays, the queue is empty, a half-read command and the bytes
        waiting are gone, a reply not yet written is cut, every joint goes to its home
        (``JointController::loadSettings``) and the 32 ms update timer starts again."""
        self._now_s = max(self._now_s, now_s)
        self._out += self.read_output()  # what is on the line by now was sent
        self.codec = PlenCodec(Role.DEVICE)
        self._arrivals.clear()
        self._ring.clear()
        self._replies.clear()  # the rest of a reply is cut
        self._line_free_s = self._read_s = self._now_s = now_s
        self._deaf_until_s = now_s + RESET_UART_ON_S
        self.queue.clear()
        self.playing = False
        self.header = None
        self._update_due = False
        self._next_update_s = now_s + UPDATE_INTERVAL_S
        self.angles_ddeg = list(self.home_ddeg)
        self._move_body()

    def stop_all(self) -> None:
        """Power loss: playback and the interpreter's queue end, the servos stop where they are."""
        self.queue.clear()
        self.playing = False

    # --------------------------------------------------------------------- motion memory

    def store(self, header: m.MotionHeader, frames: list[m.MotionFrame]) -> None:
        """Write a motion into the motion memory, as ``>MH`` and ``>MF`` would."""
        self.headers[header.slot] = header
        for frame in frames:
            self.frames[(frame.slot, frame.index)] = frame

    def _read_header(self, slot: int) -> _Header | None:
        """``Header::get``: the slot's header, erased if never written; None past the last
        slot (refused: the header held stays)."""
        if not 0 <= slot < m.SLOT_COUNT:
            return None
        stored = self.headers.get(slot)
        return _ERASED_HEADER if stored is None else _Header.of(stored)

    def _read_frame(self, slot: int, index: int) -> _Frame | None:
        """``Frame::get``: None for a slot or an index past the last (refused: the buffer
        keeps what it held)."""
        if not (0 <= slot < m.SLOT_COUNT and 0 <= index < m.FRAME_LENGTH_MAX):
            return None
        return self._frame(slot, index)

    def _frame(self, slot: int, index: int) -> _Frame:
        stored = self.frames.get((slot, index))
        if stored is None:
            return _Frame(index, _ERASED_TIME_MS, [_ERASED_VALUE] * m.JOINT_COUNT)
        return _Frame(index, stored.transition_time_ms, list(stored.offsets_ddeg))

    def dump(self, slot: int) -> m.MotionReply:
        """What ``<MO`` answers for ``slot``."""
        header = self.headers.get(slot)
        if header is None:
            return m.MotionReply(slot, "", ())
        frames = []
        for index in range(header.frame_length):
            frame = self._frame(slot, index)
            frames.append(m.MotionReplyFrame(index, frame.transition_time_ms, tuple(frame.values)))
        loop = (
            m.LoopCode(header.loop_begin, header.loop_end, header.loop_count)
            if header.use_loop
            else None
        )
        jump = m.JumpCode(header.jump_slot) if header.use_jump else None
        return m.MotionReply(slot, header.name, tuple(frames), loop, jump)

    # -------------------------------------------------------------------------- commands

    def _send(self, reply: m.Reply) -> float:
        data = self.codec.send(reply)
        if self.transport == "usb":
            self._out += data
            return 0.0
        start_s = self._read_s + READ_BYTE_S + REPLY_START_S
        if isinstance(reply, m.VersionReply):
            self._replies.append((start_s, VERSION_BYTE_S, data))
            return REPLY_START_S + len(data) * VERSION_BYTE_S
        # a dump: its text at TEXT_BYTE_S a byte, each number once printed (its digits
        # worked out first, then written)
        clock_s = start_s - TEXT_BYTE_S  # when the byte before the first was written
        for match in _NUMBER_OR_TEXT.finditer(data):
            part = match.group()
            if part[0] in b"-0123456789" and part != b"-":
                digits = len(part) - (part[0] == 0x2D)
                took_s = NUMBER_S + digits * DIGIT_S + (part[0] == 0x2D) * SIGN_S
                first_s = clock_s + took_s - (len(part) - 1) * TEXT_BYTE_S
            else:
                took_s = len(part) * TEXT_BYTE_S
                first_s = clock_s + TEXT_BYTE_S
            self._replies.append((first_s, TEXT_BYTE_S, part))
            clock_s += took_s
        return clock_s + TEXT_BYTE_S - self._read_s - READ_BYTE_S

    def _handle(self, msg: m.PlenMessage) -> float:
        """Act on a command; returns the firmware's time doing it, seconds (besides reading
        it), during which it reads nothing."""
        if isinstance(msg, (m.PlayMotion, m.PopMotion)):
            busy_s = MOTION_READ_S
        elif isinstance(msg, (m.HomePosition, m.ResetJointSettings)):
            busy_s = SETTINGS_S
        elif isinstance(msg, m.MotionHeader):
            busy_s = EEPROM_SLOT_WRITE_S
        elif isinstance(msg, m.MotionFrame):
            busy_s = 2 * EEPROM_SLOT_WRITE_S
        elif isinstance(msg, m.SetAngle):
            busy_s = SET_ANGLE_S
        elif isinstance(msg, m.SetAngleDiff):
            busy_s = SET_ANGLE_DIFF_S
        else:
            busy_s = 0.0
        return busy_s + self._act(msg)

    def _act(self, msg: m.PlenMessage) -> float:
        if isinstance(msg, m.SetAngle):
            self._set_angle(msg.joint, msg.angle_ddeg)
            self._move_body()
        elif isinstance(msg, m.SetAngleDiff):
            self._set_angle(msg.joint, self.home_ddeg[msg.joint] + msg.diff_ddeg)
            self._move_body()
        elif isinstance(msg, m.HomePosition):
            self.angles_ddeg = list(self.home_ddeg)
            self._move_body()
        elif isinstance(msg, m.PlayMotion):
            self._play(msg.slot)
        elif isinstance(msg, m.StopMotion):
            if self.header is not None:
                self.header = replace(self.header, use_loop=False, use_jump=False)
        elif isinstance(msg, m.PushMotion):
            if len(self.queue) < _QUEUE_SIZE - 1:
                self.queue.append((msg.slot, (msg.play_count - 1) & 0xFF))
        elif isinstance(msg, m.PopMotion):
            self._pop()
        elif isinstance(msg, m.ResetInterpreter):
            self.queue.clear()
            self._stop()
        else:
            return self._handle_setting(msg)
        return 0.0

    def _handle_setting(self, msg: m.PlenMessage) -> float:
        """Act on a setter or getter; returns the time the reply takes to write, seconds."""
        if isinstance(msg, m.SetHome):
            self.home_ddeg[msg.joint] = msg.angle_ddeg
        elif isinstance(msg, m.SetMax):
            if msg.angle_ddeg > self.min_ddeg[msg.joint]:
                self.max_ddeg[msg.joint] = msg.angle_ddeg
        elif isinstance(msg, m.SetMin):
            if msg.angle_ddeg < self.max_ddeg[msg.joint]:
                self.min_ddeg[msg.joint] = msg.angle_ddeg
        elif isinstance(msg, m.ResetJointSettings):
            factory = m.factory_joint_settings().joints
            self.min_ddeg = [joint.min_ddeg for joint in factory]
            self.max_ddeg = [joint.max_ddeg for joint in factory]
            self.home_ddeg = [joint.home_ddeg for joint in factory]
            # JointController::resetSettings also moves every joint to its factory home
            for joint, home in enumerate(self.home_ddeg):
                self._set_angle(joint, home)
            self._move_body()
        elif isinstance(msg, m.MotionHeader):
            self.headers[msg.slot] = msg
        elif isinstance(msg, m.MotionFrame):
            self.frames[(msg.slot, msg.index)] = msg
        elif isinstance(msg, m.GetJointSettings):
            return self._send(
                m.JointSettingsReply(
                    tuple(
                        m.JointSetting(joint, low, high, home)
                        for joint, (low, high, home) in enumerate(
                            zip(self.min_ddeg, self.max_ddeg, self.home_ddeg, strict=True)
                        )
                    )
                )
            )
        elif isinstance(msg, m.GetMotion):
            return self._send(self.dump(msg.slot))
        elif isinstance(msg, m.GetVersion):
            return self._send(m.VersionReply())
        return 0.0

    def _set_angle(self, joint: int, angle_ddeg: int) -> None:
        self.angles_ddeg[joint] = max(self.min_ddeg[joint], min(self.max_ddeg[joint], angle_ddeg))

    # -------------------------------------------------------------------------- playback

    def _play(self, slot: int) -> None:
        header = self._read_header(slot)
        if self.playing or header is None:
            return
        self.header = header
        self._setup(0)
        self.playing = True
        self._pass_finished_frames()

    def _pop(self) -> None:
        if not self.queue:
            return
        slot, loop_count = self.queue.popleft()
        self._play(slot)
        header = self.header
        if header is None:
            return
        # As the firmware does, this edits the playing header even when the play was ignored.
        if loop_count != 0:
            if not header.use_loop:
                header = replace(
                    header, use_loop=True, loop_begin=0, loop_end=header.frame_length - 1
                )
        else:
            header = replace(header, use_loop=False)
        self.header = replace(header, use_jump=False, loop_count=loop_count)

    def _stop(self) -> None:
        self.playing = False
        self._current, self._next = self._next, self._current  # m_bufferingFrame

    def _setup(self, index: int) -> None:
        assert self.header is not None
        frame = self._read_frame(self.header.slot, index)
        if frame is not None:  # a refused read leaves the buffer as it was
            self._next = frame
        # MotionController.h keeps the count in a uint8_t: from 8192 ms on it wraps (10240 ms
        # is 64 updates). A count of 0 (under 32 ms, or a multiple of 8192 ms) divides by
        # zero: avr-gcc's __divmodsi4 then gives -1 (+1 for a negative difference).
        self._count = (self._next.transition_time_ms // _UPDATE_INTERVAL_MS) & 0xFF
        for joint in range(m.JOINT_COUNT):
            self._fixed[joint] = self._current.values[joint] << _FIXED_BITS
            diff = (self._next.values[joint] << _FIXED_BITS) - self._fixed[joint]
            if self._count:
                self._step[joint] = _cdiv(diff, self._count)
            else:
                self._step[joint] = 1 if diff < 0 else -1

    def _pass_finished_frames(self) -> None:
        """The firmware's loop after a frame is set up: an update falls due first when one is
        (``frameUpdatable``), and a count of 0 then wraps to 255 (the frame takes 256
        updates); otherwise a frame of no updates is finished at once, so the next one is
        loaded (or the motion stops) without the angles moving. Frames of no updates that
        loop for ever spin until the next update falls due."""
        for _ in range(_MOST_PASSED_FRAMES):
            if not self.playing or self._count or self._update_due:
                return
            if self._next_loadable():
                self._load_next()
            else:
                self._stop()
                if self.queue:
                    self._pop()

    def _update(self) -> None:
        self.update_count += 1
        self._count = (self._count - 1) & 0xFF  # a uint8_t: 0 wraps to 255
        for joint in range(m.JOINT_COUNT):
            self._fixed[joint] += self._step[joint]
            self._set_angle(joint, self.home_ddeg[joint] + (self._fixed[joint] >> _FIXED_BITS))
        self._move_body()
        if self._count > 0:
            return
        if self._next_loadable():
            self._load_next()
            self._pass_finished_frames()
            if not self.playing and self.queue:
                self._pop()
        else:
            self._stop()
            if self.queue:
                self._pop()

    def _next_loadable(self) -> bool:
        header = self.header
        assert header is not None
        if header.use_loop or header.use_jump:
            return True
        return self._next.index + 1 < header.frame_length

    def _load_next(self) -> None:
        header = self.header
        assert header is not None
        self._current, self._next = self._next, self._current  # m_bufferingFrame
        index = self._current.index
        if header.use_loop and index >= header.loop_end:
            count = header.loop_count
            if count != m.LOOP_FOREVER:
                count = (count - 1) & 0xFF
            self.header = replace(header, loop_count=count, use_loop=count != 0)
            self._setup(header.loop_begin)
            return
        if not header.use_loop and header.use_jump and index >= header.frame_length - 1:
            jumped = self._read_header(header.jump_slot)
            if jumped is not None:
                self.header = jumped
            self._setup(0)
            return
        self._setup(index + 1)

    # ---------------------------------------------------------------------------- walking

    def _offset_rad(self, joint: int, sign: int = 1) -> float:
        """A joint's angle from its factory home, radians, with the side's sign applied."""
        return math.radians(sign * (self.angles_ddeg[joint] - m.FACTORY_HOME_DDEG[joint]) / 10.0)

    def _foot_positions(self) -> tuple[_Foot, _Foot]:
        """Left and right foot relative to the pelvis, from the joint angles now."""
        # Leaning right lowers the right hip and raises the left one.
        lean = (self._offset_rad(_LEFT_THIGH_ROLL) + self._offset_rad(_RIGHT_THIGH_ROLL, -1)) / 2
        hip_drop_mm = HIP_WIDTH_MM / 2.0 * math.sin(lean)

        def leg(pitch: int, knee: int, yaw: int, sign: int, drop_mm: float) -> _Foot:
            thigh = self._offset_rad(pitch, sign)
            shank = thigh - self._offset_rad(knee, sign)
            return _Foot(
                forward_mm=LEG_SEGMENT_MM * (math.sin(thigh) + math.sin(shank)),
                down_mm=LEG_SEGMENT_MM * (math.cos(thigh) + math.cos(shank)) + drop_mm,
                yaw_cw_deg=-math.degrees(self._offset_rad(yaw)),
            )

        return (
            leg(_LEFT_THIGH_PITCH, _LEFT_KNEE, _LEFT_THIGH_YAW, 1, -hip_drop_mm),
            leg(_RIGHT_THIGH_PITCH, _RIGHT_KNEE, _RIGHT_THIGH_YAW, -1, hip_drop_mm),
        )

    def _move_body(self) -> None:
        """Move the body by the travel of the planted foot since the last joint change.

        A foot is planted over a change when it is the lowest (within 0.01 mm) both before and
        after it; a foot coming down or lifting off in between is in the air. When neither
        foot is planted throughout (the weight changed feet), the lower one on average is.
        """
        before = self._feet
        after = self._foot_positions()
        self._feet = after

        def on_floor(feet: tuple[_Foot, _Foot]) -> set[int]:
            lowest = max(foot.down_mm for foot in feet)
            return {side for side, foot in enumerate(feet) if foot.down_mm > lowest - _TOUCH_MM}

        planted = sorted(on_floor(before) & on_floor(after))
        if not planted:
            reach = [old.down_mm + new.down_mm for old, new in zip(before, after, strict=True)]
            planted = [0 if reach[0] >= reach[1] else 1]
        forward_mm = -sum(after[i].forward_mm - before[i].forward_mm for i in planted)
        turn_deg = -sum(after[i].yaw_cw_deg - before[i].yaw_cw_deg for i in planted)
        if forward_mm or turn_deg:
            self.body.displace(forward_mm / len(planted), turn_deg / len(planted))


def simulated_device(profile: RobotProfile) -> Callable[[Body], Plen2Board]:
    """The PLEN2 unit's simulated device factory: a PLEN2 control board. Its one option,
    ``transport``, is ``usb`` (the default) or ``uart`` (see :class:`Plen2Board`).

    Raises:
        ProfileError: An option other than ``transport``, or a transport it does not know.
    """
    options = dict(profile.options)
    transport = options.pop("transport", "usb")
    if options or transport not in TRANSPORTS:
        raise ProfileError(
            f"{profile.name}: a PLEN2 profile's one option is 'transport' "
            f"({' or '.join(TRANSPORTS)}), not {profile.options!r}"
        )
    return lambda body: Plen2Board(body, str(transport))
