"""The lockstep wire's framing: both roles read exactly what the other wrote, and nothing else."""

from __future__ import annotations

import itertools
import socket
import threading
import time
from collections.abc import Iterator

import pytest
from helpers import HANG_BOUND_S
from hypothesis import given
from hypothesis import strategies as st

from roboscript.transport.lockstep import (
    MAX_HELD_BYTES,
    MAX_PAYLOAD_BYTES,
    FrameDecoder,
    FrameError,
    Kind,
    WorldChannel,
    WorldStoppedError,
    decode_time,
    encode_frame,
    encode_time,
)
from roboscript.watchdog import CodeClock


def test_a_frame_is_kind_length_payload() -> None:
    assert encode_frame(Kind.WRITE, b"M,R,45") == b"W\x00\x00\x00\x06M,R,45"
    assert encode_frame(Kind.START) == b"S\x00\x00\x00\x00"


def test_frames_split_anywhere_are_read_whole_and_in_order() -> None:
    stream = encode_frame(Kind.TICK, encode_time(1.25)) + encode_frame(Kind.WRITE, b"\x00\xff")
    decoder = FrameDecoder(Kind.FROM_MISSION)
    frames = []
    for i in range(len(stream)):
        frames += decoder.feed(stream[i : i + 1])
    assert [k for k, _ in frames] == [Kind.TICK, Kind.WRITE]
    assert decode_time(frames[0][1]) == 1.25
    assert frames[1][1] == b"\x00\xff"
    assert decoder.pending_bytes == 0


def test_each_role_refuses_the_other_roles_frames() -> None:
    with pytest.raises(FrameError, match="unknown frame kind"):
        list(FrameDecoder(Kind.FROM_WORLD).feed(encode_frame(Kind.FINISH, b"{}")))
    with pytest.raises(FrameError, match="unknown frame kind"):
        list(FrameDecoder(Kind.FROM_MISSION).feed(encode_frame(Kind.OUTPUT, b"")))


def test_an_oversized_frame_is_refused_from_its_header() -> None:
    header = b"W" + (MAX_PAYLOAD_BYTES + 1).to_bytes(4, "big")
    with pytest.raises(FrameError, match="over the"):
        list(FrameDecoder(Kind.FROM_MISSION).feed(header))
    with pytest.raises(FrameError):
        encode_frame(Kind.WRITE, bytes(MAX_PAYLOAD_BYTES + 1))


def test_a_time_payload_must_be_eight_bytes() -> None:
    with pytest.raises(FrameError):
        decode_time(b"\x00" * 7)


@given(st.binary(max_size=2000))
def test_any_bytes_give_frames_or_a_frame_error(data: bytes) -> None:
    decoder = FrameDecoder(Kind.FROM_MISSION)
    try:
        for kind, payload in decoder.feed(data):
            assert kind[0] in Kind.FROM_MISSION
            assert len(payload) <= MAX_PAYLOAD_BYTES
    except FrameError:
        pass


@given(
    st.lists(st.tuples(st.sampled_from(sorted(Kind.FROM_MISSION)), st.binary(max_size=300))),
    st.lists(st.integers(min_value=0, max_value=4000)),
)
def test_what_is_encoded_is_decoded_however_the_reads_cut_it(
    frames: list[tuple[int, bytes]], cuts: list[int]
) -> None:
    stream = b"".join(encode_frame(bytes([k]), p) for k, p in frames)
    decoder = FrameDecoder(Kind.FROM_MISSION)
    decoded = []
    edges = [0, *sorted(c for c in cuts if c < len(stream)), len(stream)]
    for start, end in itertools.pairwise(edges):  # whole frames, a frame and a part, ...
        decoded += decoder.feed(memoryview(stream)[start:end])
    assert decoded == [(bytes([k]), p) for k, p in frames]
    assert decoder.pending_bytes == 0


def _world(sock: socket.socket, answers: list[bytes]) -> None:
    decoder = FrameDecoder(Kind.FROM_MISSION)
    for answer in answers:
        while not list(decoder.feed(sock.recv(100))):
            pass
        sock.sendall(answer)
    sock.close()


def test_a_request_returns_the_worlds_output_and_a_stop_ends_the_run() -> None:
    mission_end, world_end = socket.socketpair()
    answers = [encode_frame(Kind.OUTPUT, b"@I,v,1\n"), encode_frame(Kind.STOPPED)]
    thread = threading.Thread(target=_world, args=(world_end, answers))
    thread.start()
    channel = WorldChannel(mission_end)
    assert channel.request(Kind.TICK, encode_time(0.02)) == b"@I,v,1\n"
    with pytest.raises(WorldStoppedError, match="time is up"):
        channel.request(Kind.TICK, encode_time(0.04))
    with pytest.raises(WorldStoppedError):  # and stays stopped, without asking again
        channel.request(Kind.TICK, encode_time(0.06))
    thread.join()
    channel.close()


def _slow_world(sock: socket.socket, answer_after_s: float) -> None:
    FrameDecoder(Kind.FROM_MISSION).feed(sock.recv(100))
    time.sleep(answer_after_s)  # a busy world, stepping its physics
    sock.sendall(encode_frame(Kind.OUTPUT, b""))
    sock.close()


def test_time_waiting_for_the_worlds_answer_is_not_the_missions_own() -> None:
    mission_end, world_end = socket.socketpair()
    thread = threading.Thread(target=_slow_world, args=(world_end, 0.3))
    thread.start()
    channel = WorldChannel(mission_end)
    clock = CodeClock()
    before_s = clock.now()
    channel.request(Kind.TICK, encode_time(0.02))
    assert clock.now() - before_s < 0.2  # its own part is microseconds; the wait, 0.3 s
    thread.join()
    channel.close()


def test_an_answer_stays_whole_when_the_next_read_reuses_the_buffer() -> None:
    mission_end, world_end = socket.socketpair()
    long, short = b"@E,2,{0:1,1:2}\n" * 40, b"@I,v,1\n"
    answers = [encode_frame(Kind.OUTPUT, long), encode_frame(Kind.OUTPUT, short)]
    thread = threading.Thread(target=_world, args=(world_end, answers))
    thread.start()
    channel = WorldChannel(mission_end)
    first = channel.request(Kind.TICK, encode_time(0.02))
    second = channel.request(Kind.TICK, encode_time(0.04))
    assert (first, second) == (long, short)  # the first is the device's, not the buffer's
    thread.join()
    channel.close()


def test_a_world_that_hangs_up_is_a_world_stopped() -> None:
    mission_end, world_end = socket.socketpair()
    world_end.close()
    channel = WorldChannel(mission_end)
    with pytest.raises(WorldStoppedError, match="hung up"):
        channel.request(Kind.OPEN)


def _echo_world(sock: socket.socket, seen: list[bytes]) -> None:
    """A world whose device echoes every write; it answers Y and T with what is waiting."""
    decoder = FrameDecoder(Kind.FROM_MISSION)
    waiting = b""
    while data := sock.recv(4096):
        for kind, payload in decoder.feed(data):
            seen.append(kind)
            if kind == Kind.WRITE:
                waiting += payload
            elif kind in (Kind.SYNC, Kind.TICK, Kind.OPEN):
                sock.sendall(encode_frame(Kind.OUTPUT, waiting))
                waiting = b""
    sock.close()


def test_a_read_right_after_a_write_sees_the_answer_as_in_process() -> None:
    from roboscript.transport.urlhandler.protocol_lockstep import RemoteWorld

    mission_end, world_end = socket.socketpair()
    seen: list[bytes] = []
    thread = threading.Thread(target=_echo_world, args=(world_end, seen))
    thread.start()
    world = RemoteWorld(WorldChannel(mission_end))
    world.connect()
    world.write(b"I,v\n")
    assert world.in_waiting == 4  # asks once (Y), as the device answered at once in-process
    assert world.read(100) == b"I,v\n"
    assert world.read(100) == b""  # nothing unanswered: no second question
    world.write(b"A")
    world.tick(0.02, 0.02)  # the tick's answer carries it: no Y needed
    assert world.read(10) == b"A"
    mission_end.close()
    thread.join()
    assert seen == [Kind.OPEN, Kind.WRITE, Kind.SYNC, Kind.WRITE, Kind.TICK]


def _one_write(world_end: socket.socket) -> list[tuple[bytes, bytes]]:
    """The frames that arrive together, in one read."""
    world_end.settimeout(HANG_BOUND_S)
    return list(FrameDecoder(Kind.FROM_MISSION).feed(world_end.recv(1 << 20)))


@pytest.fixture
def wire() -> Iterator[tuple[WorldChannel, socket.socket]]:
    """The mission's channel and the world's end of the socket, closed after the test."""
    mission_end, world_end = socket.socketpair()
    world_end.setblocking(False)
    channel = WorldChannel(mission_end)
    yield channel, world_end
    channel.close()
    world_end.close()


def test_frames_that_need_no_answer_leave_with_the_next_question_in_one_write(
    wire: tuple[WorldChannel, socket.socket],
) -> None:
    channel, world_end = wire
    channel.send(Kind.START)
    channel.send(Kind.WRITE, b"M,0,100\n")
    channel.send(Kind.STATE, b"forward")
    channel.send(Kind.PRINT, b"turning now")
    with pytest.raises(BlockingIOError):  # held: nothing to wake the world for yet
        world_end.recv(4096)
    world_end.sendall(encode_frame(Kind.OUTPUT, b"@E,2\n"))  # the answer, ready in advance
    assert channel.request(Kind.TICK, encode_time(0.02)) == b"@E,2\n"
    sent = _one_write(world_end)  # everything, in the order it was sent
    kinds = [kind for kind, _ in sent]
    assert kinds == [Kind.START, Kind.WRITE, Kind.STATE, Kind.PRINT, Kind.TICK]


def test_a_report_leaves_at_once_with_what_was_held(
    wire: tuple[WorldChannel, socket.socket],
) -> None:
    channel, world_end = wire
    channel.send(Kind.STATE, b"done")
    channel.send_json(Kind.FINISH, {"outcome": "success"})
    assert [kind for kind, _ in _one_write(world_end)] == [Kind.STATE, Kind.FINISH]


def test_a_flood_of_writes_is_sent_once_it_passes_the_held_limit(
    wire: tuple[WorldChannel, socket.socket],
) -> None:
    channel, world_end = wire
    frame_bytes = len(encode_frame(Kind.WRITE, b"x" * 1000))
    for _ in range(MAX_HELD_BYTES // frame_bytes):
        channel.send(Kind.WRITE, b"x" * 1000)
    with pytest.raises(BlockingIOError):  # all held, up to the limit
        world_end.recv(1)
    channel.send(Kind.WRITE, b"x" * 1000)  # past it: out it goes, without a question
    assert len(_one_write(world_end)) > MAX_HELD_BYTES // frame_bytes


def test_closing_the_channel_sends_what_was_held(wire: tuple[WorldChannel, socket.socket]) -> None:
    channel, world_end = wire
    channel.send(Kind.WRITE, b"stop\n")
    channel.close()
    assert _one_write(world_end) == [(Kind.WRITE, b"stop\n")]
