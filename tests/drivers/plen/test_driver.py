"""The PLEN2 host driver against the simulated PLEN2, byte for byte, on a simulated clock."""

from __future__ import annotations

import contextlib
import itertools
import select
import socket
import threading
from collections.abc import Callable
from typing import Any

import pytest
from helpers import run_cli

from roboscript import capabilities as cap
from roboscript.clock import SimClock
from roboscript.codec import Role
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.driver import CHUNK_BYTES, CHUNK_GAP_S, PlenDriver
from roboscript.drivers.plen.gaits import GAIT_KEYS, load_gait
from roboscript.drivers.plen.messages import VersionReply
from roboscript.errors import DeviceError, LinkTimeoutError
from roboscript.profiles import get_profile
from roboscript.scheduler import Scheduler
from roboscript.sim.simulation import make_simulation
from roboscript.transport import Link

PROFILE = get_profile("plen2")
STRIDE_MM = 40.5


class SimPort:
    """A port whose far end is a simulated PLEN2; every write is logged with its time.

    ``answer`` may rewrite what the robot says to a request (return ``None`` to keep it).
    """

    def __init__(self, clock: SimClock) -> None:
        self.clock = clock
        self.sim = make_simulation("plen2")
        self.sim.connect()
        self.writes: list[tuple[float, bytes]] = []
        self.answer: Callable[[bytes, bytes], bytes | None] = lambda request, reply: None
        self.pending = bytearray()
        """Bytes on their way to the host."""

    def write(self, data: bytes, /) -> int:
        self.writes.append((self.clock.now(), bytes(data)))
        self.pending += self.sim.read(self.sim.in_waiting)
        self.sim.write(bytes(data))
        reply = self.sim.read(self.sim.in_waiting)
        changed = self.answer(bytes(data), reply)
        self.pending += reply if changed is None else changed
        return len(data)

    def read(self, size: int = 1) -> bytes:
        self.pending += self.sim.read(self.sim.in_waiting)
        data = bytes(self.pending[:size])
        del self.pending[:size]
        return data

    def close(self) -> None:
        pass

    def sent(self) -> bytes:
        return b"".join(data for _, data in self.writes)


class Rig:
    """The driver, the simulated robot and a scheduler on a simulated clock."""

    def __init__(
        self, prepare: Callable[[SimPort], None] | None = None, port: type[SimPort] | None = None
    ) -> None:
        self.clock = SimClock()
        self.scheduler = Scheduler(self.clock, 0.02)
        self.port = (port or SimPort)(self.clock)
        if prepare is not None:
            prepare(self.port)
        self.link = Link(self.port, PlenDriver.make_codec(PROFILE), clock=self.clock)
        self.driver = PlenDriver(self.link, PROFILE, self.clock)
        self.board: Any = self.port.sim.device
        self.body = self.port.sim.body
        self.scheduler.add(self.port.sim, "sense")
        self.scheduler.add(self.driver.tick, "sense")
        self.scheduler.add(self.driver.flush, "act")

    def connect(self, limit_s: float = 20.0) -> None:
        self.driver.start()
        assert self.scheduler.run(until=lambda: self.driver.ready, max_duration_s=limit_s)

    def run(self, seconds: float) -> None:
        self.scheduler.run(until=lambda: False, max_duration_s=seconds)

    @property
    def walker(self) -> Any:
        return self.driver.capabilities()[cap.WALKER]

    def walk_until_idle(self, limit_s: float = 60.0) -> list[tuple[bool, bool]]:
        """Tick until the walker is idle; return (busy, robot playing) at every tick."""
        samples: list[tuple[bool, bool]] = []

        def sample(now_s: float, dt_s: float) -> None:
            samples.append((self.walker.busy(), self.board.playing))

        self.scheduler.add(sample, "after")
        self.scheduler.run(until=lambda: not self.walker.busy(), max_duration_s=limit_s)
        self.scheduler.remove(sample)
        return samples


def preinstalled(*keys: str) -> Callable[[SimPort], None]:
    def prepare(port: SimPort) -> None:
        for key in keys:
            gait = load_gait(key)
            port.sim.device.store(gait.header, list(gait.frames))  # type: ignore[attr-defined]

    return prepare


# ------------------------------------------------------------------------------ handshake


def test_handshake_reads_the_version_then_each_gait_slot() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    assert rig.port.sent() == b"<VI<MO50<MO51<MO52<MO53"
    assert rig.driver.installed == []
    assert set(rig.driver.capabilities()) == {cap.WALKER, cap.JOINTS}
    assert rig.driver.describe() == "PLEN2 (firmware 1.4.2 Cytisus)"


def test_missing_gaits_are_installed_in_paced_chunks_and_read_back() -> None:
    rig = Rig()
    rig.connect()
    assert rig.driver.installed == list(GAIT_KEYS)
    installs = [(t, data) for t, data in rig.port.writes if not data.startswith((b"<", b"$"))]
    assert all(len(data) <= CHUNK_BYTES for _, data in installs)
    gaps = [later[0] - earlier[0] for earlier, later in itertools.pairwise(installs)]
    assert min(gaps) >= CHUNK_GAP_S - 1e-9
    gait = load_gait("walk_forward")
    assert gait.install_bytes() in rig.port.sent()
    assert rig.port.sent().count(b"<MO50") == 2  # the check, and the read-back
    assert rig.board.dump(gait.slot) == gait.stored


def test_only_the_missing_or_different_gait_is_installed() -> None:
    def prepare(port: SimPort) -> None:
        preinstalled("walk_forward", "walk_backward", "turn_right")(port)
        other = load_gait("turn_left")
        frames = list(other.frames)
        frames[0] = type(frames[0])(other.slot, 0, 160, frames[0].offsets_ddeg)
        port.sim.device.store(other.header, frames)  # type: ignore[attr-defined]

    rig = Rig(prepare)
    rig.connect()
    assert rig.driver.installed == ["turn_left"]
    assert rig.port.sent().count(b">MH") == 1
    assert b">MH53RS Turn Left" in rig.port.sent()


def test_a_garbled_slot_is_written_and_the_gait_slots_after_it_are_written_unread() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))

    def erased(request: bytes, reply: bytes) -> bytes | None:
        # An erased EEPROM dumps bytes that are not a motion (its "slot" is 255), once.
        if request != b"<MO51" or b">MH51" in rig.port.sent():
            return None
        return b'{\r\n\t"slot": 255,\r\n\t"name": "\xff\xff",\r\n'

    rig.port.answer = erased
    rig.connect()
    # An erased slot dumps 255 frames on the real firmware: the slots after it are not read.
    assert rig.driver.installed == ["walk_backward", "turn_right", "turn_left"]
    assert b"<MO52" not in rig.port.sent().split(b">MH51")[0]
    assert rig.port.sent().startswith(b"<VI<MO50<MO51>MH51")


def test_a_reply_arriving_in_pieces_is_read_until_complete() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    held = bytearray()

    def trickle(request: bytes, reply: bytes) -> bytes | None:
        held.extend(reply)
        return b""

    def release(now_s: float, dt_s: float) -> None:
        # Two bytes a tick until the version is in (0.7 s: longer than the 0.5 s silence
        # limit, which restarts with every byte), then faster.
        size = 2 if rig.driver.version is None else 500
        rig.port.pending += held[:size]
        del held[:size]

    rig.port.answer = trickle
    rig.scheduler.add(release, "sense")
    rig.connect()
    assert rig.driver.version == VersionReply()
    assert rig.driver.installed == []


def test_a_silent_robot_times_out_after_three_tries() -> None:
    rig = Rig()
    rig.port.answer = lambda request, reply: b""
    rig.driver.start()
    with pytest.raises(LinkTimeoutError, match=r"did not answer <VI \(3 tries\)"):
        rig.scheduler.run(until=lambda: rig.driver.ready, max_duration_s=20.0)
    assert rig.port.sent() == b"<VI<VI<VI"


class NoisyPort(SimPort):
    """A PLEN2 whose line turns to noise once a motion starts being written: from then on
    every read brings garbage, and never a reply."""

    NOISE = b"\xde\xad~noise~"

    def read(self, size: int = 1) -> bytes:
        data = super().read(size)
        writing = any(not sent.startswith((b"<", b"$")) for _, sent in self.writes)
        return self.NOISE if writing else data


def test_garbage_while_a_motion_is_written_fails_the_handshake_at_once() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS[1:]), port=NoisyPort)  # walk_forward to be written
    rig.driver.start()
    with pytest.raises(DeviceError, match="sent unreadable bytes while the walk_forward motion"):
        rig.scheduler.run(
            until=lambda: rig.driver.ready, max_duration_s=PROFILE.handshake_timeout_s
        )
    first_write_s = next(t for t, data in rig.port.writes if not data.startswith((b"<", b"$")))
    # on the tick the noise is read, not when the handshake's time runs out
    assert rig.clock.now() - first_write_s <= 2 * rig.scheduler.period_s + 1e-9


def test_other_firmware_is_refused_or_noticed() -> None:
    device = PlenCodec(Role.DEVICE)

    def version(text: str) -> Callable[[bytes, bytes], bytes | None]:
        reply = device.send(VersionReply(version=text))
        return lambda request, _reply: reply if request == b"<VI" else None

    old = Rig()
    old.port.answer = version("1.3.1")
    with pytest.raises(DeviceError, match=r"firmware 1\.3\.1"):
        old.connect()
    close = Rig(preinstalled(*GAIT_KEYS))
    close.port.answer = version("1.4.1")
    close.connect()
    assert close.driver.notices == [
        "this PLEN2 runs firmware 1.4.1; roboscript was written against 1.4.2"
    ]


# -------------------------------------------------------------------------------- walking


def test_walk_pushes_the_gait_with_its_step_count() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    mark = len(rig.port.sent())
    rig.walker.walk(4)
    rig.run(0.02)
    assert rig.port.sent()[mark:] == b"#PU5004#PO"
    rig.walk_until_idle()
    rig.walker.turn(-2)
    rig.run(0.02)
    assert rig.port.sent().endswith(b"#PU5302#PO")


def test_busy_lasts_until_the_robot_has_really_finished() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.walk(3)
    samples = rig.walk_until_idle()
    assert all(busy for busy, playing in samples if playing)
    assert not rig.board.playing
    assert rig.body.y_mm == pytest.approx(3 * STRIDE_MM, abs=3.0)


def test_a_walk_asked_for_while_walking_follows_it() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.walk(2)
    rig.run(0.5)
    rig.walker.turn(1)
    rig.walker.walk(-1)
    rig.walk_until_idle()
    assert rig.port.sent().count(b"#PO") == 3
    assert rig.body.heading_deg == pytest.approx(15.0, abs=0.5)


def test_stop_lets_the_step_in_progress_finish() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.walk(8)
    rig.run(1.5)  # in the middle of the second step
    rig.walker.stop()
    rig.run(0.02)
    assert rig.port.sent().endswith(b"$SM")
    assert rig.walker.busy() and rig.board.playing
    samples = rig.walk_until_idle()
    assert all(busy for busy, playing in samples if playing)
    assert rig.body.y_mm == pytest.approx(2 * STRIDE_MM, abs=3.0)
    assert rig.port.sent().count(b"$SM") == 1


def test_stop_drops_walks_not_yet_started() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.walk(1)
    rig.walker.walk(5)
    rig.run(0.5)
    rig.walker.stop()
    rig.walk_until_idle()
    rig.run(2.0)
    assert rig.port.sent().count(b"#PO") == 1
    assert rig.body.y_mm == pytest.approx(STRIDE_MM, abs=3.0)


def test_a_long_walk_goes_as_several_pushes() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.walk(300)
    rig.run(0.02)
    assert rig.port.sent().endswith(b"#PU50ff#PO")
    rig.walker.stop()
    rig.walk_until_idle()
    assert b"#PU502d" not in rig.port.sent()


def test_play_motion_reads_the_slot_first_then_plays_it() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    mark = len(rig.port.sent())
    rig.walker.play_motion(0x50)
    assert rig.walker.busy()
    rig.run(0.2)
    assert rig.port.sent()[mark:] == b"<MO50$PM50"
    rig.run(3.0)
    assert rig.walker.busy() and rig.board.playing  # that gait loops until stopped
    rig.walker.stop()
    rig.walk_until_idle()
    assert not rig.board.playing


def test_playing_an_empty_slot_is_a_notice() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.play_motion(12)
    rig.walk_until_idle()
    assert rig.driver.notices == ["motion slot 12 of the PLEN2 is empty: nothing was played"]
    assert b"$PM" not in rig.port.sent()


# ------------------------------------------------------------------------- joints, safety


def test_joints_move_by_name_once_the_robot_stands_still() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    joints = rig.driver.capabilities()[cap.JOINTS]
    rig.walker.walk(1)
    joints.set_angle("left_shoulder_pitch", 45.0)
    rig.run(0.5)
    assert b"$AD" not in rig.port.sent()
    rig.walk_until_idle()
    rig.run(0.1)
    assert rig.port.sent().endswith(b"$AD001c2")
    assert rig.board.angles_ddeg[0] == -200 + 450
    assert joints.angle_deg("left_shoulder_pitch") == 45.0
    joints.set_angle("right_knee_pitch", -200.0)  # clamped to 90 degrees
    joints.home()
    rig.run(0.1)
    assert rig.port.sent().endswith(b"$AD12c7c$HP")
    assert joints.angle_deg("right_knee_pitch") == 0.0
    with pytest.raises(ValueError, match="did you mean 'left_knee_pitch'"):
        joints.set_angle("left_knee", 10.0)


def test_stop_all_sends_stop_motion_and_never_raises() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.walk(3)
    rig.run(0.3)
    rig.driver.stop_all()
    assert rig.port.sent().endswith(b"$SM")
    rig.link.close()
    rig.driver.stop_all()


# ------------------------------------------------------------------------------- liveness


def test_a_quiet_line_is_checked_with_a_version_request_every_second() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    mark = len(rig.port.writes)
    rig.run(3.05)
    beats = [t for t, data in rig.port.writes[mark:] if data == b"<VI"]
    assert len(beats) == 3
    # A second after the last reply, which is read one 20 ms tick after its request.
    assert [round(b - a, 2) for a, b in itertools.pairwise(beats)] == [1.02, 1.02]


def test_the_version_request_also_goes_out_while_a_walk_plays() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    rig.walker.walk(6)
    rig.walker.walk(2)  # queued behind the first walk: the queue waits, the check does not
    mark = len(rig.port.writes)
    rig.run(2.5)
    assert rig.board.playing
    assert [data for _, data in rig.port.writes[mark:] if data == b"<VI"]


def test_a_robot_silent_after_the_handshake_fails_the_walk() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    ready_s = rig.clock.now()
    rig.port.answer = lambda request, reply: b""
    rig.walker.walk(20)
    with pytest.raises(LinkTimeoutError) as caught:
        rig.run(10.0)
    message = str(caught.value)
    assert message.startswith("the robot stopped responding ")
    assert message.endswith(": the PLEN2 did not answer <VI (3 tries)")
    assert rig.clock.now() - ready_s == pytest.approx(1.0 + 3 * 0.5, abs=0.05)


def test_a_reply_with_impossible_values_is_counted_skipped_and_asked_again() -> None:
    rig = Rig(preinstalled(*GAIT_KEYS))
    rig.connect()
    impossible = b'{"slot": 999, "name": "x", "codes": [], "frames": []}'
    spoiled: list[bytes] = []

    def once(request: bytes, reply: bytes) -> bytes | None:
        if request == b"<VI" and not spoiled:
            spoiled.append(reply)
            return impossible
        return None

    rig.port.answer = once
    mark = len(rig.port.writes)
    rig.run(2.0)
    assert rig.link.faults == {"bad_reply": 1}
    beats = [data for _, data in rig.port.writes[mark:] if data == b"<VI"]
    assert len(beats) >= 2  # asked again after the garbage, and answered


def test_roboscript_run_says_in_one_line_that_the_upload_met_garbage() -> None:
    """A PLEN2 behind a socket whose line turns to noise once a motion is being written."""
    sim = make_simulation("plen2")
    listener = socket.create_server(("127.0.0.1", 0))
    port = listener.getsockname()[1]

    def serve() -> None:
        connection, _ = listener.accept()
        sim.connect()
        writing = False
        with connection:
            while True:
                if select.select([connection], [], [], 0.01)[0]:
                    try:
                        data = connection.recv(4096)
                    except OSError:  # roboscript hung up with bytes unread: a reset
                        return
                    if not data:
                        return
                    writing = writing or b">MH" in data
                    sim.write(data)
                out = sim.read(sim.in_waiting)
                with contextlib.suppress(OSError):
                    connection.sendall(NoisyPort.NOISE if writing else out)

    server = threading.Thread(target=serve, daemon=True)
    server.start()
    try:
        done = run_cli("run", "missions/plen_walk.yaml", "--port", f"socket://127.0.0.1:{port}")
    finally:
        listener.close()
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stderr
    assert done.stderr.strip().splitlines()[-1] == (
        "error: the PLEN2 sent unreadable bytes while the walk_forward motion was being written"
        " to slot 80, so it may be stored wrong: check that the port is the robot's USB serial"
        " at 2000000 baud, then connect again"
    )
