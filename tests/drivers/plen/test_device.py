"""The simulated PLEN2 answers real bytes, plays motions and walks as firmware 1.4.2 does."""

from __future__ import annotations

import dataclasses
import itertools
import random
import socket

import pytest
from helpers import HANG_BOUND_S, served_simulator

from roboscript.codec import Role
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.device import UPDATE_INTERVAL_S, Plen2Board, simulated_device
from roboscript.drivers.plen.gaits import load_gait
from roboscript.drivers.plen.messages import (
    FACTORY_HOME_DDEG,
    JointSettingsReply,
    MotionFrame,
    MotionHeader,
    MotionReply,
    PopMotion,
    PushMotion,
    VersionReply,
    factory_joint_settings,
)
from roboscript.errors import ProfileError
from roboscript.profiles import get_profile
from roboscript.sim.body import Body, BodySpec
from roboscript.sim.world import Pose, load_world

VERSION_WIRE = (
    b'{\r\n\t"device": "PLEN2",\r\n\t"codename": "Cytisus",\r\n\t"version": "1.4.2"\r\n}\r\n'
)
KNEE = 6  # left_knee_pitch


class Rig:
    """A board on a body, with a clock the test moves by hand."""

    def __init__(self, world: str = "empty", start: Pose | None = None) -> None:
        self.body = Body(load_world(world), BodySpec(body_radius_mm=60.0), random.Random(1), start)
        self.board = Plen2Board(self.body)
        self.now_s = 0.0
        self.board.connect(0.0)

    def send(self, data: bytes) -> bytes:
        self.board.receive(data, self.now_s)
        return self.board.read_output()

    def run(self, seconds: float) -> None:
        """Advance time in 5 ms physics steps, as the simulation does."""
        end = self.now_s + seconds
        while self.now_s < end - 1e-9:
            self.now_s = round(self.now_s + 0.005, 6)
            self.board.step(self.now_s)

    def run_until_idle(self, limit_s: float = 30.0) -> float:
        """Advance until playback has ended; return how long it took."""
        start = self.now_s
        while self.board.playing:
            assert self.now_s - start < limit_s, "the motion never ended"
            self.run(0.005)
        return self.now_s - start

    def store(self, header: MotionHeader, frames: list[MotionFrame]) -> None:
        wire = PlenCodec(Role.HOST)
        assert self.send(b"".join(wire.send(c) for c in (header, *frames))) == b""

    def knee(self) -> int:
        return self.board.angles_ddeg[KNEE] - FACTORY_HOME_DDEG[KNEE]


def frame(slot: int, index: int, time_ms: int, knee_ddeg: int) -> MotionFrame:
    offsets = [0] * 24
    offsets[KNEE] = knee_ddeg
    return MotionFrame(slot, index, time_ms, tuple(offsets))


def knee_motion(slot: int = 5, *, loop: tuple[int, int, int] | None = None) -> MotionHeader:
    """Three frames moving the left knee: 100 over 64 ms, 250 over 96 ms, 0 over 64 ms."""
    return MotionHeader(
        slot=slot,
        name="Knee",
        frame_length=3,
        use_loop=loop is not None,
        loop_begin=loop[0] if loop else 0,
        loop_end=loop[1] if loop else 0,
        loop_count=loop[2] if loop else 0,
    )


KNEE_FRAMES = [frame(5, 0, 64, 100), frame(5, 1, 96, 250), frame(5, 2, 64, 0)]
KNEE_MOTION_S = (2 + 3 + 2) * UPDATE_INTERVAL_S


# ------------------------------------------------------------------------------- getters


def test_only_the_three_getters_answer() -> None:
    rig = Rig()
    assert rig.send(b"$hp$ad06064$an0a100$sm#ri#po>ho0a000>js$pm05") == b""
    assert rig.send(b"hello\r\n$zz<xx") == b""
    assert rig.send(b"<vi") == VERSION_WIRE
    assert rig.send(b"<VI") == VERSION_WIRE


def test_joint_settings_dump_follows_the_setters() -> None:
    rig = Rig()
    assert rig.send(b"<js") == PlenCodec(Role.DEVICE).send(factory_joint_settings())
    rig.send(b">ho0a064>ma0a1f4>mi0afce>mi0b384")  # the last: min above max, ignored
    (reply,) = feed_host(rig.send(b"<js"))
    assert isinstance(reply, JointSettingsReply)
    assert (reply.joints[10].home_ddeg, reply.joints[10].max_ddeg) == (100, 500)
    assert reply.joints[10].min_ddeg == -50
    assert reply.joints[11].min_ddeg == -900
    rig.send(b">js")
    assert feed_host(rig.send(b"<js")) == [factory_joint_settings()]


def test_an_empty_slot_dumps_no_frames_and_a_stored_one_dumps_itself() -> None:
    rig = Rig()
    assert feed_host(rig.send(b"<mo05")) == [MotionReply(5, "", ())]
    header = knee_motion(loop=(0, 2, 255))
    rig.store(header, KNEE_FRAMES)
    expected = MotionReply.from_install(header, KNEE_FRAMES)
    assert rig.send(b"<mo05") == PlenCodec(Role.DEVICE).send(expected)


def test_a_frame_never_written_reads_as_erased_memory() -> None:
    rig = Rig()
    rig.store(knee_motion(), KNEE_FRAMES[:2])
    (reply,) = feed_host(rig.send(b"<mo05"))
    assert isinstance(reply, MotionReply)
    assert reply.frames[2].transition_time_ms == 65535
    assert set(reply.frames[2].offsets_ddeg) == {-1}


def test_a_frame_of_no_updates_divides_by_zero_as_the_avr_does() -> None:
    # an erased slot's header is slot 255, whose frames Frame::get refuses: the buffer keeps
    # its frame of 0 ms, the count is 0, and `diff /= 0` gives -1 (avr-gcc's __divmodsi4):
    # at the first update every joint goes one tenth of a degree below its home, and stays
    rig = Rig()
    rig.send(b"$pm0a")
    assert rig.board.playing and rig.board.angles_ddeg == list(FACTORY_HOME_DDEG)
    rig.run(0.6)
    assert rig.board.angles_ddeg == [home - 1 for home in FACTORY_HOME_DDEG]


def test_a_frame_of_no_updates_is_passed_over_without_moving() -> None:
    # a frame of 8192 ms is 256 updates, 0 in the firmware's uint8_t: played when no update
    # is due, it is finished at once, the next frame is set up from it, and the joints
    # move from there
    rig = Rig()
    header = knee_motion()
    frames = [
        dataclasses.replace(KNEE_FRAMES[0], transition_time_ms=8192),
        *KNEE_FRAMES[1:],
    ]
    rig.store(header, frames)
    rig.send(b"$pm05")
    rig.run(UPDATE_INTERVAL_S)
    assert rig.board.update_count == 1
    # from frame 0's 100 toward frame 1's 250 in three updates: 150 after the first
    assert rig.board.angles_ddeg[KNEE] == FACTORY_HOME_DDEG[KNEE] + 150


def feed_host(data: bytes) -> list[object]:
    codec = PlenCodec(Role.HOST)
    codec.receive_data(data)
    out = []
    while (message := codec.next_message()) is not None:
        out.append(message)
    return out


# -------------------------------------------------------------------------------- joints


def test_angles_are_clamped_and_home_restores() -> None:
    rig = Rig()
    rig.send(b">ma06258")  # max 600
    rig.send(b"$an06384")  # 900 -> 600
    assert rig.board.angles_ddeg[KNEE] == 600
    rig.send(b"$ad06f9c")  # home 500 - 100
    assert rig.board.angles_ddeg[KNEE] == 400
    rig.send(b"$hp")
    assert rig.board.angles_ddeg == list(FACTORY_HOME_DDEG)


# ------------------------------------------------------------------------------ playback


def test_frames_are_interpolated_in_32_ms_steps() -> None:
    rig = Rig()
    rig.store(knee_motion(), KNEE_FRAMES)
    rig.run(0.010)
    rig.send(b"$pm05")
    seen = []
    for _ in range(7):
        rig.run(UPDATE_INTERVAL_S)
        seen.append(rig.knee())
    assert seen == [50, 100, 150, 200, 250, 125, 0]
    assert not rig.board.playing


def test_updates_fall_due_every_32_768_ms_and_a_motion_after_a_pause_starts_at_once() -> None:
    # Timer 1 overflows every 4.096 ms and the update is due once per 8 (JointController.cpp);
    # the due flag stays set while nothing plays, so the first update comes straight away.
    assert pytest.approx(0.032768) == UPDATE_INTERVAL_S
    rig = Rig()
    rig.store(knee_motion(), KNEE_FRAMES)
    rig.run(1.0)
    rig.send(b"$pm05")
    rig.run(0.005)
    assert rig.knee() == 50
    update_s = []
    while rig.board.playing:
        before = rig.board.update_count
        rig.run(0.001)
        if rig.board.update_count != before:
            update_s.append(rig.now_s)
    assert len(update_s) == 6
    gaps = [later - earlier for earlier, later in itertools.pairwise(update_s)]
    assert gaps == pytest.approx([UPDATE_INTERVAL_S] * 5, abs=0.0051)


def test_a_play_while_playing_is_ignored() -> None:
    rig = Rig()
    rig.store(knee_motion(), KNEE_FRAMES)
    rig.store(MotionHeader(6, "Other", 1), [frame(6, 0, 320, -300)])
    rig.send(b"$pm05")
    rig.run(0.1)
    rig.send(b"$pm06")
    assert rig.run_until_idle() == pytest.approx(KNEE_MOTION_S - 0.1, abs=UPDATE_INTERVAL_S)
    assert rig.knee() == 0


def test_stop_finishes_the_frames_left_in_the_motion() -> None:
    rig = Rig()
    rig.store(knee_motion(loop=(0, 2, 255)), KNEE_FRAMES)
    rig.send(b"$pm05")
    rig.run(3 * KNEE_MOTION_S)
    assert rig.board.playing  # looping until stopped
    rig.run(0.08)  # into frame 1 of the fourth pass
    rig.send(b"$sm")
    assert rig.run_until_idle() == pytest.approx(KNEE_MOTION_S - 0.08, abs=UPDATE_INTERVAL_S + 1e-6)
    assert rig.knee() == 0


@pytest.mark.parametrize(("count", "passes"), [(1, 2), (2, 3)])
def test_a_loop_count_repeats_the_section_that_many_more_times(count: int, passes: int) -> None:
    rig = Rig()
    rig.store(knee_motion(loop=(0, 2, count)), KNEE_FRAMES)
    rig.send(b"$pm05")
    assert rig.run_until_idle() == pytest.approx(passes * KNEE_MOTION_S, abs=UPDATE_INTERVAL_S)


def test_the_interpreter_plays_a_motion_the_pushed_number_of_times() -> None:
    rig = Rig()
    rig.store(knee_motion(loop=(0, 2, 255)), KNEE_FRAMES)
    rig.send(b"#pu0503#po")
    assert rig.run_until_idle() == pytest.approx(3 * KNEE_MOTION_S, abs=UPDATE_INTERVAL_S)
    rig.send(b"#pu0501#po")
    assert rig.run_until_idle() == pytest.approx(KNEE_MOTION_S, abs=UPDATE_INTERVAL_S)


def test_a_queued_motion_starts_when_the_playing_one_ends() -> None:
    rig = Rig()
    rig.store(knee_motion(), KNEE_FRAMES)
    rig.send(b"$pm05")
    rig.run(0.05)
    rig.send(b"#pu0502")
    assert rig.run_until_idle() == pytest.approx(3 * KNEE_MOTION_S - 0.05, abs=0.07)


def test_reset_interpreter_stops_at_once() -> None:
    rig = Rig()
    rig.store(knee_motion(), KNEE_FRAMES)
    rig.send(b"$pm05")
    rig.run(2 * UPDATE_INTERVAL_S + 0.01)
    rig.send(b"#ri")
    assert not rig.board.playing
    rig.run(1.0)
    assert rig.knee() == 100


def test_a_jump_continues_with_another_slot() -> None:
    rig = Rig()
    rig.store(MotionHeader(7, "A", 1, use_jump=True, jump_slot=8), [frame(7, 0, 64, 300)])
    rig.store(MotionHeader(8, "B", 1), [frame(8, 0, 64, -100)])
    rig.send(b"$pm07")
    assert rig.run_until_idle() == pytest.approx(4 * UPDATE_INTERVAL_S, abs=UPDATE_INTERVAL_S)
    assert rig.knee() == -100


# ------------------------------------------------------------------------------- walking


def play_gait(rig: Rig, key: str, steps: int) -> None:
    gait = load_gait(key)
    rig.store(gait.header, list(gait.frames))
    codec = PlenCodec(Role.HOST)
    rig.send(codec.send(PushMotion(gait.slot, steps)) + codec.send(PopMotion()))
    rig.run_until_idle(limit_s=60.0)


def test_walking_forward_moves_the_body_along_its_heading() -> None:
    rig = Rig(start=Pose(0.0, 0.0, 90.0))
    play_gait(rig, "walk_forward", 3)
    assert rig.body.x_mm == pytest.approx(3 * 40.5, abs=3.0)
    assert rig.body.y_mm == pytest.approx(0.0, abs=1e-6)
    assert rig.body.heading_deg == pytest.approx(90.0)


def test_walking_backward_and_turning_both_ways() -> None:
    rig = Rig()
    play_gait(rig, "walk_backward", 2)
    assert rig.body.y_mm == pytest.approx(-2 * 40.5, abs=3.0)
    play_gait(rig, "turn_right", 2)
    assert rig.body.heading_deg == pytest.approx(30.0, abs=0.5)
    play_gait(rig, "turn_left", 3)
    assert rig.body.heading_deg == pytest.approx(345.0, abs=0.5)
    assert rig.body.y_mm == pytest.approx(-2 * 40.5, abs=3.0)


def test_posing_a_leg_in_the_air_does_not_move_the_body() -> None:
    rig = Rig()
    rig.send(b"$ad0407f")  # lean right onto the right foot (left thigh roll +127)
    rig.send(b"$ad0612c$ad0507f")  # bend the left knee, swing the left thigh
    assert (rig.body.x_mm, rig.body.y_mm) == (0.0, 0.0)


def test_a_wall_stops_a_walking_robot() -> None:
    rig = Rig(world="square-room")  # the north wall is 1 m ahead
    play_gait(rig, "walk_forward", 30)
    assert rig.body.log.collisions
    assert 1000.0 - 60.0 - 41.0 < rig.body.y_mm < 1000.0 - 60.0


# ------------------------------------------------------------------------ roboscript sim


def test_roboscript_sim_serves_the_simulated_plen2() -> None:
    with served_simulator("plen2") as port:
        codec = PlenCodec(Role.HOST)
        with socket.create_connection(("127.0.0.1", port), timeout=HANG_BOUND_S) as sock:
            sock.sendall(b"<VI")
            reply = None
            while reply is None:
                data = sock.recv(4096)
                assert data, "the simulator closed the connection"
                codec.receive_data(data)
                reply = codec.next_message()
        assert reply == VersionReply()


# ---------------------------------------------------------------------------- UART line


class UartRig(Rig):
    """A board reached over its 2 Mbaud UART, with the clock moved in 0.1 ms steps."""

    def __init__(self) -> None:
        super().__init__()
        self.board = Plen2Board(self.body, transport="uart")
        self.board.connect(0.0)

    def send(self, data: bytes) -> bytes:
        self.board.receive(data, self.now_s)
        for _ in range(2000):  # 0.2 s
            self.now_s = round(self.now_s + 0.0001, 6)
            self.board.step(self.now_s)
        return self.board.read_output()


def test_over_the_uart_a_burst_past_the_receive_ring_loses_bytes() -> None:
    rig = UartRig()
    assert rig.send(b"x" * 60 + b"<VI") == VERSION_WIRE  # read as it arrives
    assert rig.send(b"x" * 300 + b"<VI") == b""  # 5 us a byte in, 29 us a byte read
    assert rig.board.lost_bytes > 0
    assert Rig().send(b"x" * 300 + b"<VI") == VERSION_WIRE  # USB waits instead


def test_over_the_uart_a_getter_behind_a_long_reply_is_lost_past_63_bytes() -> None:
    rig = UartRig()
    settings = PlenCodec(Role.DEVICE).send(factory_joint_settings())
    assert rig.send(b"<JS" + b"x" * 40 + b"<VI") == settings + VERSION_WIRE
    assert rig.send(b"<JS" + b"x" * 100 + b"<VI") == settings


def test_over_the_uart_the_drivers_paced_writes_lose_nothing() -> None:
    rig = UartRig()
    wire = PlenCodec(Role.HOST)
    data = b"".join(wire.send(c) for c in (knee_motion(), *KNEE_FRAMES))
    for start in range(0, len(data), 32):
        rig.send(data[start : start + 32])
    assert rig.board.lost_bytes == 0
    assert rig.board.dump(5).frames[1].offsets_ddeg[KNEE] == 250


def test_a_plen2_profile_takes_only_the_transport_option() -> None:
    profile = get_profile("plen2")
    with pytest.raises(ProfileError, match="transport"):
        simulated_device(dataclasses.replace(profile, options={"transport": "serial"}))
    with pytest.raises(ProfileError, match="transport"):
        simulated_device(dataclasses.replace(profile, options={"baud": 9600}))
    board = simulated_device(dataclasses.replace(profile, options={"transport": "uart"}))(
        Rig().body
    )
    assert board.transport == "uart"


def test_over_the_uart_a_reply_takes_the_firmwares_time_to_write() -> None:
    rig = UartRig()
    rig.board.receive(b"<VI", rig.now_s)
    rig.board.step(rig.now_s + 0.0005)  # <VI: 73 bytes, 11.6 us each, from about 125 us
    early = rig.board.read_output()
    assert 0 < len(early) < len(VERSION_WIRE)
    rig.board.step(rig.now_s + 0.002)
    assert early + rig.board.read_output() == VERSION_WIRE


# -------------------------------------------------------------------------------- resets


def test_a_reset_keeps_what_the_firmware_keeps_in_eeprom_and_nothing_else() -> None:
    rig = Rig()
    rig.store(knee_motion(loop=(0, 2, 255)), KNEE_FRAMES)  # loops for ever
    rig.send(b">HO06064")  # the knee's home, in the chip's EEPROM: 100
    rig.send(b"$AN00100")  # an angle: not kept
    rig.send(b"$PM05")
    rig.run(0.2)
    assert rig.board.playing
    rig.board.reset(rig.now_s)
    assert not rig.board.playing and not rig.board.queue
    assert rig.board.angles_ddeg[KNEE] == 100  # its home, as loadSettings sets it
    assert rig.board.angles_ddeg[0] == FACTORY_HOME_DDEG[0]
    rig.run(0.01)  # setup() has opened its UART again
    assert b'"home": 100' in rig.send(b"<JS")
    assert rig.board.headers[5].name.startswith("Knee")  # the motion EEPROM keeps it


def test_a_reset_board_hears_nothing_until_its_uart_is_open() -> None:
    rig = Rig()
    rig.board.reset(rig.now_s)
    assert rig.send(b"<VI") == b""  # 3.39 ms of setup(): lost
    rig.now_s += 0.004
    assert rig.send(b"<VI") == VERSION_WIRE
