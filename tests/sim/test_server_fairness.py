"""``roboscript sim --tcp`` is fair to a classroom: idle, second and flooding clients.

The server runs in a thread on loopback TCP with real sockets; its clock is the test's, so
"five seconds of silence" is a step of that clock, not a wait. Socket timeouts below only keep
a broken server from hanging the test run; no assertion depends on them.
"""

from __future__ import annotations

import queue
import socket
import subprocess
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, serving_simulator

from roboscript.codec import Role, drain
from roboscript.drivers.stackmod.codec import StackModCodec
from roboscript.drivers.stackmod.messages import Command, Get, GetReply
from roboscript.sim.server import BUSY_LINE, DEFAULT_HANDSHAKE_WAIT_S, SimServer
from roboscript.sim.simulation import make_simulation

_SAFETY_S = HANG_BOUND_S
"""How long a test waits for the server before calling it hung (never reached when it works)."""


class TestClock:
    """Wall time that moves only when the test says so."""

    __test__ = False

    def __init__(self) -> None:
        self.now_s = 1000.0

    def __call__(self) -> float:
        return self.now_s


@dataclass
class Served:
    server: SimServer
    clock: TestClock
    port: int
    lines: queue.Queue[str]

    def said(self, start: str) -> str:
        """The next line the server says that starts with ``start`` (earlier ones skipped)."""
        while True:
            line = self.lines.get(timeout=_SAFETY_S)
            if line.startswith(start):
                return line

    def connect(self) -> socket.socket:
        sock = socket.create_connection(("127.0.0.1", self.port), timeout=_SAFETY_S)
        return sock

    def step_clock(self, seconds: float) -> None:
        """Move the clock on, and return once the server has gone round its loop after that."""
        self.clock.now_s += seconds
        for _ in range(2):  # the turn that saw the new time, then one that began after it
            target_s = self.server.now() - self.server.simulation.physics_dt_s
            deadline = time.monotonic() + _SAFETY_S  # a bound for a hang, not a speed limit
            while self.server.simulation.time_s < target_s:
                assert time.monotonic() < deadline, "the server's loop stopped turning"
                time.sleep(0.01)
            self.clock.now_s += self.server.simulation.physics_dt_s


@pytest.fixture
def served() -> Iterator[Served]:
    lines: queue.Queue[str] = queue.Queue()
    clock = TestClock()
    server = SimServer(make_simulation("stackmod-rover"), lines.put, clock=clock)
    thread = threading.Thread(target=server.serve_tcp, args=("127.0.0.1", 0), daemon=True)
    thread.start()
    first = lines.get(timeout=_SAFETY_S)
    port = int(first.split("socket://127.0.0.1:")[1].rstrip(")"))
    try:
        yield Served(server, clock, port, lines)
    finally:
        server.stop()
        thread.join(timeout=_SAFETY_S)


def _ask_arm(sock: socket.socket) -> GetReply:
    """Ask the motor module whether it is armed; return its answer (a working robot)."""
    host = StackModCodec(Role.HOST)
    sock.sendall(host.send(Get(ord("M"), Command.ARM, 0)))
    while True:
        data = sock.recv(4096)
        assert data, "the simulator closed the connection"
        host.receive_data(data)
        for message in drain(host):
            if isinstance(message, GetReply):
                return message


def _read_to_end(sock: socket.socket) -> bytes:
    received = bytearray()
    while data := sock.recv(4096):
        received += data
    return bytes(received)


def test_a_client_that_says_nothing_keeps_the_robot_while_nobody_else_wants_it(
    served: Served,
) -> None:
    with served.connect() as quiet:  # a program still importing on a busy machine
        served.said("client connected from ")
        served.step_clock(10 * DEFAULT_HANDSHAKE_WAIT_S)
        assert served.server.idle_drops == 0
        assert _ask_arm(quiet).address == ord("M")  # its first words, long after connecting
    assert served.said("client ") == "client disconnected; motors stopped"


def test_a_client_that_says_nothing_gives_the_robot_to_the_next_one_after_the_wait(
    served: Served,
) -> None:
    idle = served.connect()
    first = served.said("client connected from ").split()[-1]
    served.clock.now_s += DEFAULT_HANDSHAKE_WAIT_S - 0.5
    other = served.connect()  # while the idle client is still within the wait: refused
    assert served.said("client ").endswith(f"refused: busy with {first}")
    assert _read_to_end(other).startswith(b"roboscript sim: busy:")
    served.clock.now_s += 0.5
    with served.connect() as nxt:
        dropped = served.said("client ")
        newcomer = served.said("client connected from ").split()[-1]
        assert dropped == (
            f"client {first} dropped: it sent nothing for 5 s after connecting"
            f" and {newcomer} wants the robot; motors stopped"
        )
        assert _read_to_end(idle) == b""
        assert served.server.idle_drops == 1
        assert _ask_arm(nxt).address == ord("M")


def test_a_client_that_talks_keeps_the_robot_past_the_handshake_wait(served: Served) -> None:
    with served.connect() as talker:
        served.said("client connected from ")
        _ask_arm(talker)  # its last message was whole: it may stay quiet as long as it likes
        served.clock.now_s += 10 * DEFAULT_HANDSHAKE_WAIT_S
        with served.connect() as other:  # the quiet client still has the robot
            assert _read_to_end(other).startswith(b"roboscript sim: busy:")
        assert _ask_arm(talker).address == ord("M")
    assert served.server.idle_drops == 0


def test_a_second_client_is_told_plainly_that_the_robot_is_busy(served: Served) -> None:
    with served.connect() as owner:
        connected = served.said("client connected from ").split()[-1]
        _ask_arm(owner)
        with served.connect() as second:
            told = _read_to_end(second)
        assert told == BUSY_LINE.format(other=connected).encode("ascii")
        refused = served.said("client ")
        assert refused.startswith("client 127.0.0.1:")
        assert refused.endswith(f" refused: busy with {connected}")
        assert _ask_arm(owner).address == ord("M")  # the owner never noticed
    assert served.server.refused == 1


def test_a_flooding_client_cannot_keep_the_robot_busy(served: Served) -> None:
    flood = 10 * 1024 * 1024
    with served.connect() as flooder:
        served.said("client connected from ")
        sender = threading.Thread(target=flooder.sendall, args=(b"{" * flood,), daemon=True)
        sender.start()
        warned = served.said("client ")
        assert "sends faster than the robot's line (65536 bytes/s)" in warned
        sender.join(timeout=_SAFETY_S)
    gone = served.said("client disconnected")
    # The clock stood still: the line carried one burst and not a byte more.
    burst = int(served.server.burst_bytes)
    assert served.server.dropped_bytes == flood - burst
    assert gone.endswith(f"({flood - burst} bytes sent faster than the line were dropped)")
    with served.connect() as nxt:
        served.said("client connected from ")
        assert _ask_arm(nxt).address == ord("M")


def test_the_line_refills_at_the_baudrate(served: Served) -> None:
    ask = StackModCodec(Role.HOST).send(Get(ord("M"), Command.ARM, 0))
    with served.connect() as client:
        served.said("client connected from ")
        burst = int(served.server.burst_bytes)
        client.sendall(b"\n" * (burst - len(ask)))  # with the question: one full burst
        assert _ask_arm(client).address == ord("M")
        served.clock.now_s += 0.1  # a tenth of a second of line time
        client.sendall(b"\n" * (int(served.server.line_bytes_s * 0.1) - len(ask)))
        assert _ask_arm(client).address == ord("M")
    served.said("client disconnected")
    assert served.server.dropped_bytes == 0


def test_a_client_connecting_right_after_a_flood_ends_gets_the_robot(served: Served) -> None:
    with served.connect() as flooder:
        served.said("client connected from ")
        flooder.sendall(b"{" * (4 * 1024 * 1024))
    # At once: the server may still hold the flood's bytes when this client knocks.
    with served.connect() as nxt:
        assert _ask_arm(nxt).address == ord("M")
    assert served.server.refused == 0


def test_a_client_that_stops_mid_message_gives_the_robot_up_after_the_same_wait(
    served: Served,
) -> None:
    stalled = served.connect()
    first = served.said("client connected from ").split()[-1]
    stalled.sendall(StackModCodec(Role.HOST).send(Get(ord("M"), Command.ARM, 0))[:1])
    deadline = time.monotonic() + HANG_BOUND_S  # a bound for a hang, not a speed limit
    while not served.server.simulation.input_pending:  # until the byte has reached the device
        assert time.monotonic() < deadline, "the byte never reached the device"
        time.sleep(0.01)
    served.clock.now_s += DEFAULT_HANDSHAKE_WAIT_S - 0.5
    other = served.connect()  # not yet: still within the wait, so the robot is busy
    assert _read_to_end(other).startswith(b"roboscript sim: busy:")
    served.step_clock(0.5)  # alone, a stalled client is not dropped: someone must want the robot
    assert served.server.idle_drops == 0
    with served.connect() as nxt:
        dropped = served.said(f"client {first} ")
        newcomer = served.said("client connected from ").split()[-1]
        assert dropped == (
            f"client {first} dropped: it stopped in the middle of a message and sent"
            f" nothing for 5 s and {newcomer} wants the robot; motors stopped"
        )
        assert _read_to_end(stalled) == b""
        assert _ask_arm(nxt).address == ord("M")


def _ask_arm_unless_busy(port: int) -> GetReply | None:
    """Connect and ask the motor module; ``None`` if told the robot is busy."""
    with socket.create_connection(("127.0.0.1", port), timeout=_SAFETY_S) as sock:
        host = StackModCodec(Role.HOST)
        sock.sendall(host.send(Get(ord("M"), Command.ARM, 0)))
        received = b""
        while data := sock.recv(4096):
            received += data
            if received.startswith(BUSY_LINE[:20].encode("ascii")):
                return None
            host.receive_data(data)
            for message in drain(host):
                if isinstance(message, GetReply):
                    return message
        return None


def _voluntary_switches(pid: int) -> int:
    """How many times process ``pid`` has gone to sleep (Linux: each wait in its loop)."""
    status = Path(f"/proc/{pid}/status").read_text(encoding="ascii")
    return int(status.split("voluntary_ctxt_switches:")[1].split()[0])


def _let_it_turn_twice(proc: subprocess.Popen[str]) -> None:
    """Return once the server has slept and woken in its loop twice from now on: a whole turn
    of its loop began after this call, whatever the machine's load."""
    start = _voluntary_switches(proc.pid)
    deadline = time.monotonic() + _SAFETY_S  # a bound for a hang, not a speed limit
    while _voluntary_switches(proc.pid) < start + 2:
        assert time.monotonic() < deadline, "the server's loop stopped turning"
        time.sleep(0.01)


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads Linux's /proc")
def test_roboscript_sim_keeps_a_client_that_is_slow_to_speak_while_nobody_else_wants_it() -> None:
    wait_s = 0.2
    with serving_simulator("stackmod-rover", "--handshake-wait", str(wait_s)) as (port, proc):
        assert proc.stdout is not None
        with socket.create_connection(("127.0.0.1", port), timeout=_SAFETY_S) as slow:
            assert proc.stdout.readline().startswith("client connected from ")
            time.sleep(wait_s)  # at least the wait since the server took it, on any machine
            _let_it_turn_twice(proc)  # the server has looked at it since
            host = StackModCodec(Role.HOST)
            slow.sendall(host.send(Get(ord("M"), Command.ARM, 0)))
            data = slow.recv(4096)
            assert data, "the simulator dropped a client that was only slow to speak"
            host.receive_data(data)
    printed = proc.stdout.read()
    assert "dropped" not in printed


def test_roboscript_sim_gives_the_robot_to_a_newcomer_after_one_byte_and_silence() -> None:
    with (
        serving_simulator("stackmod-rover", "--handshake-wait", "0.5") as (port, proc),
        socket.create_connection(("127.0.0.1", port), timeout=_SAFETY_S) as stalled,
    ):
        frame = StackModCodec(Role.HOST).send(Get(ord("M"), Command.ARM, 0))
        stalled.sendall(frame[:1])  # the first byte of a frame, and nothing more
        deadline = time.monotonic() + _SAFETY_S  # a bound for a hang, not a speed limit
        while (reply := _ask_arm_unless_busy(port)) is None:  # busy within the wait
            assert time.monotonic() < deadline, "the quiet client kept the robot"
            time.sleep(0.05)
        assert reply.address == ord("M")  # the robot went to the one that asked
        assert _read_to_end(stalled) == b""  # the server hung up on the quiet one
    assert proc.stdout is not None
    assert "sent nothing for 0.5 s and 127.0.0.1:" in proc.stdout.read()
