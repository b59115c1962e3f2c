"""The PLEN2 host driver (firmware 1.4.2): handshake, gait motions, joints and a safe stop.

Handshake (never a fixed sleep): ``<VI`` must name a PLEN2 running firmware 1.4 (1.4.2 is the
one roboscript is written against; another 1.4 release gets a notice, anything else is
refused). Then ``<MO`` reads each gait slot (80–83, see :mod:`~roboscript.drivers.plen.gaits`).
A slot whose dump differs from roboscript's gait, holds nothing, or answers with bytes that are
not a motion, is written with ``>MH`` + ``>MF`` and read back to check. Then the robot is ready.
Bytes that are not a motion mean an erased motion memory (a robot roboscript has not set up):
the firmware dumps an erased slot as 255 frames (``MotionController::dump`` prints the
header's ``frame_length``, 0xFF), about 260 KB and 5 s of output each, so the gait slots not
read yet are then written without being read first.

Replies have no terminator: the codec frames one when its brackets balance, and the driver
waits for it on the scheduler clock, giving up after 0.5 s without a byte (the wait restarts
whenever bytes arrive, so a long dump is never cut short). A getter unanswered three times
raises :class:`~roboscript.errors.LinkTimeoutError`. One getter is in flight at a time.

Pacing, as plen-ControlServer does it: an install goes out in 32-byte writes 50 ms apart (the
firmware writes each frame to EEPROM while its 128-byte ring buffer fills up); a control
command is followed by 10 ms of quiet. Every wait is on the scheduler clock.

Walking N steps sends ``#PU`` (slot, N) and ``#PO``: the firmware's interpreter plays the
gait's loop, one step per pass, exactly N times, with no EEPROM write and no host timing (more
than 255 steps go as several plays). Nothing reports when a motion ends, so :meth:`busy` is
predicted from the frames with :class:`~roboscript.drivers.plen.playback.Schedule`, stretched
by 3 % plus 0.1 s: the firmware's update comes every 32.768 ms (eight 4.096 ms Timer 1
overflows), 2.4 % more than the 32 ms its transition times are counted in, and a ``$PM`` or
``#PO`` sent while a motion still plays is ignored by the firmware.

Liveness: every command but the getters is silent, so once the robot is ready the driver asks
``<VI`` whenever the line has been quiet for ``HEARTBEAT_S`` and no getter is in flight (also
while a motion plays: the firmware answers getters between its 32 ms updates). A robot that
leaves it unanswered three times fails the run with the drivers' common "the robot stopped
responding" sentence (:mod:`roboscript.drivers.base`), instead of a walk predicted to succeed.

Stopping: ``$SM`` clears the motion's loop and jump flags, so the firmware finishes the step it
is in and stops in the home stance, both feet down; :meth:`~PlenDriver.stop_all` sends exactly
that. It sends neither ``#RI`` (which freezes every servo at once, possibly on one foot) nor
``$HP`` (which the still-playing frames would overwrite at the next 32 ms update, with a jerk).
"""

from __future__ import annotations

import difflib
import logging
import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

from roboscript import capabilities as cap
from roboscript.clock import Clock
from roboscript.drivers.base import Driver, PendingRequest
from roboscript.drivers.plen import messages as m
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.gaits import Gait, load_gaits
from roboscript.drivers.plen.playback import UPDATE_INTERVAL_MS, Schedule
from roboscript.errors import DeviceError, LinkError, LinkTimeoutError
from roboscript.robot_profile import RobotProfile
from roboscript.transport.link import Link

__all__ = ["PlenDriver"]

logger = logging.getLogger(__name__)

REPLY_SILENCE_S = 0.5
"""A getter's reply is given up after this long without a byte, seconds."""
REPLY_ATTEMPTS = 3
"""How many times a getter is sent before the robot counts as silent."""
CHUNK_BYTES = 32
"""Largest write of an install (plen-ControlServer's chunk)."""
CHUNK_GAP_S = 0.05
"""Quiet time after each install write, seconds."""
CONTROL_GAP_S = 0.01
"""Quiet time after a control command, seconds."""
PLAYBACK_STRETCH = 1.03
"""How much longer than 32 ms a real board's update takes, with room (32.768 ms; busy() errs
late)."""
PLAYBACK_MARGIN_S = 0.1
"""Extra time busy() stays true after the predicted end of a motion, seconds."""
MAX_PLAYS_PER_PUSH = 255
"""Most passes one ``#PU`` can ask for."""
JOINT_LIMIT_DEG = 90.0
"""Largest joint offset the joints capability sends, degrees."""
HEARTBEAT_S = 1.0
"""Once ready, ``<VI`` is asked after this long without a byte from the robot, seconds."""

_PERIOD_S = UPDATE_INTERVAL_MS / 1000.0 * PLAYBACK_STRETCH


# ------------------------------------------------------------------------------ operations


@dataclass
class _Send:
    """Write bytes, then keep the line quiet for ``gap_s``."""

    data: bytes
    gap_s: float
    motion: bool = False


@dataclass
class _Ask:
    """Send a getter and hand its reply on.

    ``on_garbled`` is called when bytes came back that are not the reply (an erased slot can
    dump anything); without it the getter is sent again.
    """

    request: m.GetJointSettings | m.GetMotion | m.GetVersion
    on_reply: Callable[[m.Reply], None]
    on_garbled: Callable[[], None] | None = None
    motion: bool = False
    checks: Gait | None = None
    """The gait whose slot this read checks during the handshake."""


@dataclass
class _Play:
    """Start a motion: ``$PM`` when ``play_count`` is None, else ``#PU`` + ``#PO``."""

    slot: int
    play_count: int | None
    schedule: Schedule
    motion: bool = True


@dataclass
class _WaitIdle:
    """Hold the queue until the motion playing now has ended."""

    motion: bool = False


@dataclass
class _Call:
    """Run a step of the driver's own (end of the handshake)."""

    action: Callable[[], None]
    motion: bool = False


_Op = _Send | _Ask | _Play | _WaitIdle | _Call
"""A queued step. ``motion`` marks the steps of a motion request: busy() counts them and a stop
drops them."""


@dataclass
class _Playing:
    """The motion the robot is playing, as far as the host can tell."""

    started_s: float
    schedule: Schedule
    end_s: float = field(default=math.inf)


def _answers(op: _Ask, reply: object) -> bool:
    return _reply_for(op.request, reply)


def _reply_for(request: object, reply: object) -> bool:
    if isinstance(request, m.GetVersion):
        return isinstance(reply, m.VersionReply)
    if isinstance(request, m.GetJointSettings):
        return isinstance(reply, m.JointSettingsReply)
    if isinstance(request, m.GetMotion):
        return isinstance(reply, m.MotionReply) and reply.slot == request.slot
    return False


# ---------------------------------------------------------------------------------- driver


class PlenDriver(Driver):
    """Host side of the PLEN2 protocol (see the module docstring).

    Attributes:
        version: The ``<VI`` reply, after the handshake.
        gaits: The gait motions, by key.
        installed: Keys of the gaits written to the robot during this handshake.
    """

    protocol = "plen"

    def __init__(self, link: Link, profile: RobotProfile, clock: Clock) -> None:
        super().__init__(link, profile, clock)
        self.version: m.VersionReply | None = None
        self.gaits: dict[str, Gait] = load_gaits()
        self.installed: list[str] = []
        self._ops: deque[_Op] = deque()
        self._hold_until_s = -math.inf
        # The wait for a reply restarts whenever bytes arrive: a long dump is never cut short.
        self._asking: PendingRequest[_Ask] = PendingRequest(
            timeout_s=REPLY_SILENCE_S,
            retries=REPLY_ATTEMPTS - 1,
            matches=_answers,
            give_up=self._silent,
        )
        self._ask_received = 0
        self._playing: _Playing | None = None
        self._motion_generation = 0
        self._now_s = clock.now()
        self._offsets_deg: dict[str, float] = {}
        # The motion being written, and the unreadable bytes counted when its writing began.
        self._upload: tuple[Gait, int] | None = None

    # ---------------------------------------------------------------------------- handshake

    def start(self) -> None:
        """Ask for the version (the first step of the handshake)."""
        self._ops.append(_Ask(m.GetVersion(), self._on_version))
        self._advance(self.clock.now())

    def _on_version(self, reply: m.Reply) -> None:
        assert isinstance(reply, m.VersionReply)
        self.version = reply
        if reply.device != m.DEVICE_NAME or reply.version.split(".")[:2] != ["1", "4"]:
            raise DeviceError(
                f"this robot says it is a {reply.device} with firmware {reply.version}; the "
                f"plen2 driver needs a PLEN2 with firmware {m.FIRMWARE_VERSION} "
                "(see drivers/plen2/README.md to flash it)"
            )
        if reply.version != m.FIRMWARE_VERSION:
            self.notice(
                f"this PLEN2 runs firmware {reply.version}; roboscript was written against "
                f"{m.FIRMWARE_VERSION}"
            )
        checks: list[_Op] = [
            _Ask(
                m.GetMotion(gait.slot),
                self._checker(gait),
                on_garbled=self._installer(gait),
                checks=gait,
            )
            for gait in self.gaits.values()
        ]
        self._ops.extendleft(reversed([*checks, _Call(self._become_ready)]))

    def _checker(self, gait: Gait) -> Callable[[m.Reply], None]:
        def check(reply: m.Reply) -> None:
            if reply != gait.stored:
                self._install(gait)

        return check

    def _installer(self, gait: Gait) -> Callable[[], None]:
        def install_the_rest() -> None:
            # A slot that holds no motion at all is an erased (or failing) motion memory, and
            # reading an erased slot dumps 255 frames (seconds of output each): the gait slots
            # not read yet are written unread, after this one.
            unread = [op for op in self._ops if isinstance(op, _Ask) and op.checks is not None]
            for op in unread:
                self._ops.remove(op)
            for op in reversed(unread):
                assert op.checks is not None
                self._install(op.checks)
            self._install(gait)

        return install_the_rest

    def _install(self, gait: Gait) -> None:
        """Queue the paced writes of ``gait`` and a read-back, before anything else."""
        data = gait.install_bytes()
        writes: list[_Op] = [
            _Call(lambda: self._begin_upload(gait)),
            *(
                _Send(data[start : start + CHUNK_BYTES], CHUNK_GAP_S)
                for start in range(0, len(data), CHUNK_BYTES)
            ),
        ]

        def verify(reply: m.Reply) -> None:
            self._upload = None
            if reply != gait.stored:
                raise DeviceError(
                    f"the PLEN2 did not keep the {gait.key} motion written to slot "
                    f"{gait.slot}: its motion memory may be failing"
                )
            self.installed.append(gait.key)

        def unreadable() -> None:
            raise DeviceError(
                f"the PLEN2 answered garbage when asked for slot {gait.slot} after writing "
                f"the {gait.key} motion there"
            )

        writes.append(_Ask(m.GetMotion(gait.slot), verify, on_garbled=unreadable))
        self._ops.extendleft(reversed(writes))

    def _begin_upload(self, gait: Gait) -> None:
        self._upload = (gait, self._unreadable_bytes())

    def _unreadable_bytes(self) -> int:
        codec = self.link.codec
        return codec.unreadable_bytes if isinstance(codec, PlenCodec) else 0

    def _check_upload(self) -> None:
        """Fail at once if the robot sends garbage while a motion is written to it.

        The firmware says nothing while it stores a motion, so any byte then is noise on the
        line (a wrong baud rate, a failing board), and the motion being written cannot be
        trusted; a stream of it would also keep the read-back waiting (bytes restart the
        reply wait) until the handshake's time ran out.
        """
        upload = self._upload
        if upload is None or self._unreadable_bytes() <= upload[1]:
            return
        gait, _ = upload
        self._upload = None
        raise DeviceError(
            f"the PLEN2 sent unreadable bytes while the {gait.key} motion was being written"
            f" to slot {gait.slot}, so it may be stored wrong: check that the port is the"
            f" robot's USB serial at {self.profile.baudrate} baud, then connect again"
        )

    def _become_ready(self) -> None:
        self.offer({cap.WALKER: _Walker(self), cap.JOINTS: _Joints(self)})

    def describe(self) -> str:
        """Device, code name and firmware version, as the robot reported them."""
        if self.version is None:
            return self.profile.name
        v = self.version
        return f"{v.device} (firmware {v.version} {v.codename})"

    # -------------------------------------------------------------------------- sense / act

    def tick(self, now_s: float, dt_s: float) -> None:
        """Read replies and hand them on; give up on a late one."""
        self._now_s = now_s
        for message in self.link.poll():
            asked = self._asking.answered(message)
            if asked is not None:
                asked.on_reply(message)
            else:
                logger.debug("PLEN2 reply nobody asked for: %r", message)
        self._check_upload()
        self._check_reply_timeout(now_s)

    def flush(self, now_s: float, dt_s: float) -> None:
        """Send the queued commands whose time has come."""
        self._now_s = now_s
        self._advance(now_s)

    def _advance(self, now_s: float) -> None:
        while self._ops and self._asking.in_flight is None and now_s >= self._hold_until_s:
            op = self._ops[0]
            if isinstance(op, _WaitIdle):
                if now_s < self._play_end_s():
                    break
                self._ops.popleft()
                continue
            self._ops.popleft()
            if isinstance(op, _Send):
                self.link.write(op.data)
                self._hold_until_s = now_s + op.gap_s
            elif isinstance(op, _Ask):
                self._send_ask(op, now_s)
            elif isinstance(op, _Play):
                self._start_play(op, now_s)
            else:
                op.action()
        self._heartbeat(now_s)

    def _heartbeat(self, now_s: float) -> None:
        """Ask ``<VI`` if the ready robot has been quiet for ``HEARTBEAT_S`` (liveness)."""
        if not self.ready or self._asking.in_flight is not None or now_s < self._hold_until_s:
            return
        if self._ops and not isinstance(self._ops[0], _WaitIdle):
            return  # the queue is moving: its own getters and quiet times come first
        if self.silent_for_s(now_s) < HEARTBEAT_S - 1e-9:
            return
        self._send_ask(_Ask(m.GetVersion(), self._on_heartbeat), now_s)

    def _on_heartbeat(self, reply: m.Reply) -> None:
        del reply  # any version reply proves the robot is alive

    def _send_ask(self, op: _Ask, now_s: float) -> None:
        self._asking.sent(op, now_s)  # the op that just timed out, sent again, is a retry
        self._ask_received = self.link.bytes_received
        self.link.send(op.request)

    def _check_reply_timeout(self, now_s: float) -> None:
        op = self._asking.expired(now_s, heard_s=self.link.last_receive_s)
        if op is None:
            return
        codec = self.link.codec
        if isinstance(codec, PlenCodec) and (codec.in_progress or codec.pending_bytes()):
            codec.reset()
        garbled = self.link.bytes_received > self._ask_received
        if garbled and op.on_garbled is not None:
            self._asking.cancel()
            op.on_garbled()
        elif self._asking.may_retry:
            self._ops.appendleft(op)  # sent again in its turn, after any quiet time
        else:
            raise self._asking.give_up_error()

    def _silent(self, op: _Ask, tries: int) -> LinkTimeoutError:
        if self.ready:
            return LinkTimeoutError(
                f"the PLEN2 did not answer {self.link.codec.send(op.request).decode()} "
                f"({tries} tries)"
            )
        return LinkTimeoutError(
            f"the PLEN2 did not answer {self.link.codec.send(op.request).decode()} "
            f"({tries} tries): is it switched on, and is the port the robot's "
            f"USB serial at {self.profile.baudrate} baud?"
        )

    # ---------------------------------------------------------------------------- playback

    def _play_end_s(self) -> float:
        return -math.inf if self._playing is None else self._playing.end_s

    def _start_play(self, op: _Play, now_s: float) -> None:
        if op.play_count is None:
            data = self.link.codec.send(m.PlayMotion(op.slot))
        else:
            data = self.link.codec.send(m.PushMotion(op.slot, op.play_count))
            data += self.link.codec.send(m.PopMotion())
        self.link.write(data)
        self._hold_until_s = now_s + CONTROL_GAP_S
        duration = op.schedule.duration_s(_PERIOD_S)
        end = math.inf if duration is None else now_s + duration + PLAYBACK_MARGIN_S
        self._playing = _Playing(now_s, op.schedule, end)

    def motion_busy(self) -> bool:
        """True while a motion plays or is waiting to be started."""
        in_flight = self._asking.in_flight
        asking = in_flight is not None and in_flight.motion
        return asking or self._now_s < self._play_end_s() or any(op.motion for op in self._ops)

    def queue_gait(self, key: str, steps: int) -> None:
        """Queue ``steps`` passes of gait ``key`` after whatever plays now."""
        gait = self.gaits[key]
        while steps > 0:
            plays = min(steps, MAX_PLAYS_PER_PUSH)
            self._ops.append(_WaitIdle(motion=True))
            self._ops.append(_Play(gait.slot, plays, gait.schedule(plays)))
            steps -= plays

    def queue_motion(self, slot: int) -> None:
        """Queue ``$PM`` of a stored motion, read first to learn how long it plays."""
        generation = self._motion_generation

        def play(reply: m.Reply) -> None:
            assert isinstance(reply, m.MotionReply)
            if generation != self._motion_generation:
                return  # stopped while the dump was on its way
            if not reply.frames:
                self.notice(f"motion slot {slot} of the PLEN2 is empty: nothing was played")
                return
            loop = reply.loop
            passes: int | None = 1
            if loop is not None:
                passes = None if loop.count in (0, m.LOOP_FOREVER) else loop.count + 1
            last = len(reply.frames) - 1
            schedule = Schedule.of(
                [frame.transition_time_ms for frame in reply.frames],
                (min(loop.begin, last), min(loop.end, last)) if loop is not None else None,
                passes,
            )
            self._ops.appendleft(_Play(slot, None, schedule))

        def unreadable() -> None:
            self.notice(f"motion slot {slot} of the PLEN2 holds no readable motion")

        self._ops.append(_WaitIdle(motion=True))
        self._ops.append(_Ask(m.GetMotion(slot), play, on_garbled=unreadable, motion=True))

    def stop_motion(self) -> None:
        """Drop queued motions and let the playing one finish its step (``$SM``)."""
        self._motion_generation += 1
        self._ops = deque(op for op in self._ops if not op.motion)
        playing = self._playing
        if playing is None or self._now_s >= playing.end_s:
            return
        try:
            self.link.send(m.StopMotion())
        except LinkError as exc:  # a stop on the way out of a lost link must not hide it
            logger.debug("$SM not sent: %s", exc)
        self._shorten_playback()

    # ------------------------------------------------------------------------------ joints

    def queue_joint(self, name: str, angle_deg: float) -> None:
        """Queue ``$AD`` for joint ``name`` (after any motion), ``angle_deg`` from home."""
        offset = max(-JOINT_LIMIT_DEG, min(JOINT_LIMIT_DEG, angle_deg))
        command = m.SetAngleDiff(m.JOINT_IDS[name], round(offset * 10))
        self._ops.append(_WaitIdle())
        self._ops.append(_Send(self.link.codec.send(command), CONTROL_GAP_S))
        self._offsets_deg[name] = offset

    def queue_home(self) -> None:
        """Queue ``$HP`` (after any motion)."""
        self._ops.append(_WaitIdle())
        self._ops.append(_Send(self.link.codec.send(m.HomePosition()), CONTROL_GAP_S))
        self._offsets_deg = dict.fromkeys(self._offsets_deg, 0.0)

    def joint_offset_deg(self, name: str) -> float | None:
        """The offset last commanded for ``name``, degrees."""
        return self._offsets_deg.get(name)

    # ------------------------------------------------------------------------------ safety

    def send_stop(self) -> None:
        """Drop queued motions and send ``$SM`` (see the module docstring)."""
        self._motion_generation += 1
        self._ops = deque(op for op in self._ops if not op.motion)
        self.link.send(m.StopMotion())

    def after_stop(self) -> None:
        """Predict the end of the playing motion again, whether ``$SM`` went out or not."""
        self._shorten_playback()

    def _shorten_playback(self) -> None:
        """Predict the end of the playing motion again, now that ``$SM`` has been sent."""
        playing = self._playing
        if playing is None or self._now_s >= playing.end_s:
            return
        # The robot may be a little further on than the host thinks: take the later end.
        elapsed = self._now_s - playing.started_s
        ends = (
            playing.schedule.stopped_at_s(elapsed, _PERIOD_S),
            playing.schedule.stopped_at_s(elapsed * PLAYBACK_STRETCH + 0.1, _PERIOD_S),
        )
        playing.end_s = min(playing.end_s, playing.started_s + max(ends) + PLAYBACK_MARGIN_S)


# ----------------------------------------------------------------------------- capabilities


def _count(steps: float) -> int:
    """The number of whole steps in ``steps``, without its sign."""
    if steps != int(steps):
        raise ValueError(f"a PLEN2 takes whole steps, not {steps:g}")
    return abs(int(steps))


class _Walker:
    def __init__(self, driver: PlenDriver) -> None:
        self._driver = driver
        self.stride_mm = driver.gaits["walk_forward"].stride_mm
        self.turn_step_deg = driver.gaits["turn_right"].turn_step_deg

    def walk(self, steps: int) -> None:
        self._driver.queue_gait("walk_forward" if steps > 0 else "walk_backward", _count(steps))

    def turn(self, steps: int) -> None:
        self._driver.queue_gait("turn_right" if steps > 0 else "turn_left", _count(steps))

    def play_motion(self, slot: int) -> None:
        if not 0 <= slot < m.SLOT_COUNT:
            raise ValueError(f"PLEN2 motion slots are 0 to {m.SLOT_COUNT - 1}, not {slot}")
        self._driver.queue_motion(slot)

    def busy(self) -> bool:
        return self._driver.motion_busy()

    def stop(self) -> None:
        self._driver.stop_motion()


class _Joints:
    names = tuple(m.JOINT_NAMES.values())

    def __init__(self, driver: PlenDriver) -> None:
        self._driver = driver

    def _check(self, name: str) -> None:
        if name not in m.JOINT_IDS:
            close = difflib.get_close_matches(name, self.names, n=1)
            hint = f": did you mean '{close[0]}'?" if close else ""
            raise ValueError(f"the PLEN2 has no joint '{name}'{hint}")

    def set_angle(self, name: str, angle_deg: float) -> None:
        self._check(name)
        self._driver.queue_joint(name, angle_deg)

    def angle_deg(self, name: str) -> float | None:
        self._check(name)
        return self._driver.joint_offset_deg(name)

    def home(self) -> None:
        self._driver.queue_home()
