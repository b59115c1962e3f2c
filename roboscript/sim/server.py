"""Serve a simulated robot's protocol bytes in real time, as a serial line would carry them.

``roboscript sim --robot mirto --tcp 127.0.0.1:9999`` listens on a loopback TCP port (one
client at a time; a client that disconnects may reconnect); ``--pty`` opens a pseudo-terminal
and prints its path. Any tool that talks to the real robot can talk to the simulator:
``roboscript run --port socket://127.0.0.1:9999``, the python-asip client, a serial terminal.

One thread: a ``select`` loop waits for bytes or for the next physics step and ticks the
simulation on the wall clock. When a client connects, the device greets it as the real one
does after a reset; when it disconnects the motors are stopped, so a crashed client never
leaves the simulated robot driving.

Fair to every client of a classroom (TCP):

* **One client at a time.** A client that connects while another has the robot is told so in
  one line of text (:data:`BUSY_LINE`), then closed; the server prints
  ``client X refused: busy with Y``.
* **A quiet client keeps the robot until another wants it.** Nothing is dropped for silence
  alone: on a busy machine an honest program may take seconds to say its first byte, so how
  busy the machine is never takes the robot from a client nobody else is waiting for. When
  another client connects, the one that has the robot gives it up if it has sent nothing
  since connecting, or stopped in the middle of a message (the device holds part of a
  frame), for at least ``handshake_wait_s`` (:data:`DEFAULT_HANDSHAKE_WAIT_S`): it is
  closed, the motors stopped, and the newcomer gets the robot, so a stray connection cannot
  keep the robot from the next client. A client that finished its last message keeps the
  robot however long it stays quiet (a host waiting for sensor events).
* **No client can flood the robot.** The device takes bytes no faster than the robot's line
  carries them (``baudrate / 10`` bytes a second, at least :data:`MIN_LINE_BYTES_S`, with
  :data:`LINE_BURST_S` of burst); what a client sends beyond that is dropped and counted, as
  a real receive buffer that is full drops it, and the server says so once per client.
"""

from __future__ import annotations

import ctypes
import errno
import logging
import os
import pty
import select
import socket
import struct
import time
import tty
from collections.abc import Callable
from dataclasses import dataclass

from roboscript.sim.simulation import Simulation

__all__ = [
    "BUSY_LINE",
    "DEFAULT_HANDSHAKE_WAIT_S",
    "LINE_BURST_S",
    "MIN_LINE_BYTES_S",
    "SimServer",
    "parse_host_port",
]

logger = logging.getLogger(__name__)

_READ_CHUNK = 65536
_CATCH_UP_READS = 256
"""Most reads of the current client before deciding a newcomer must be refused."""

DEFAULT_HANDSHAKE_WAIT_S = 5.0
"""A TCP client quiet this long after connecting (or mid-message) yields to a newcomer, seconds."""
LINE_BURST_S = 0.25
"""Line time a client may send at once before bytes are dropped, seconds (at the baudrate)."""
MIN_LINE_BYTES_S = 65536
"""The slowest line a client is held to, bytes a second. Robots on USB (a SPIKE hub, a PLEN2)
take bytes faster than their nominal baud rate, and an agent upload must never lose a byte;
a flood is still bounded to what the simulated device handles in a small part of its time."""
BUSY_LINE = (
    "roboscript sim: busy: another client ({other}) has the simulated robot;"
    " try again when it disconnects\r\n"
)
"""What a client that connects while another has the robot reads before it is closed."""


@dataclass
class _Client:
    """The client that has the robot, and what the server knows of it."""

    sock: socket.socket
    name: str
    connected_s: float
    budget_bytes: float
    budget_at_s: float
    heard: bool = False
    dropped_bytes: int = 0
    last_byte_s: float = 0.0
    mid_frame: bool = False

    def quiet_since_s(self) -> float | None:
        """Since when its silence counts against it; ``None`` while it may stay quiet."""
        if not self.heard:
            return self.connected_s
        return self.last_byte_s if self.mid_frame else None


def parse_host_port(text: str) -> tuple[str, int]:
    """Split ``HOST:PORT`` (port 0 picks a free one).

    Raises:
        ValueError: Not of that form, or the port is out of range.
    """
    host, sep, port_text = text.rpartition(":")
    if not sep or not host:
        raise ValueError(f"expected HOST:PORT, got {text!r}")
    port = int(port_text)
    if not 0 <= port <= 65535:
        raise ValueError(f"port {port} is out of range")
    return host.strip("[]"), port


class SimServer:
    """Runs a simulation in real time and moves its bytes to one client.

    Args:
        simulation: The simulated robot to serve.
        announce: Called with each line the server has to say (where it listens, who
            connected); defaults to logging.
        handshake_wait_s: A TCP client that sends nothing this long after connecting, or
            stops this long in the middle of a message, gives the robot up to the next client
            that connects, seconds (never dropped while nobody else wants the robot).
        clock: Wall-clock seconds (``time.monotonic``; tests inject their own).

    Attributes:
        dropped_bytes: Bytes clients sent faster than the robot's line carries, dropped.
        refused: Clients refused because another had the robot.
        idle_drops: Quiet clients dropped because another client wanted the robot.

    Raises:
        ValueError: A wait that is not positive.
    """

    def __init__(
        self,
        simulation: Simulation,
        announce: Callable[[str], None] | None = None,
        *,
        handshake_wait_s: float = DEFAULT_HANDSHAKE_WAIT_S,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        if handshake_wait_s <= 0:
            raise ValueError("the handshake wait must be positive")
        self.simulation = simulation
        self.announce = announce or logger.info
        self.handshake_wait_s = handshake_wait_s
        self._clock = clock
        self._origin = clock()
        self._stop = False
        # The device's serial line: baudrate / 10 bytes a second (8N1).
        self.line_bytes_s = max(MIN_LINE_BYTES_S, simulation.profile.baudrate / 10.0)
        self.burst_bytes = self.line_bytes_s * LINE_BURST_S
        self.dropped_bytes = 0
        self.refused = 0
        self.idle_drops = 0

    def now(self) -> float:
        """Seconds since the server started (the simulation's clock)."""
        return self._clock() - self._origin

    def stop(self) -> None:
        """Ask the loop to end at its next wake-up."""
        self._stop = True

    def _advance(self) -> float:
        """Tick the simulation to now; return seconds until the next physics step."""
        now = self.now()
        self.simulation.tick(now, self.simulation.physics_dt_s)
        next_step = (int(now / self.simulation.physics_dt_s) + 1) * self.simulation.physics_dt_s
        return max(0.0, next_step - self.now())

    # ---------------------------------------------------------------------------------- TCP

    def serve_tcp(self, host: str, port: int, *, max_runtime_s: float | None = None) -> None:
        """Serve on ``host:port`` until :meth:`stop`, Ctrl-C or ``max_runtime_s``."""
        listener = socket.create_server((host, port), reuse_port=False)
        listener.setblocking(False)
        bound_host, bound_port = listener.getsockname()[:2]
        self.announce(
            f"listening on tcp://{bound_host}:{bound_port}"
            f" (use --port socket://{bound_host}:{bound_port})"
        )
        client: _Client | None = None
        try:
            while not self._stop and not self._expired(max_runtime_s):
                wait = self._advance()
                if client is not None:
                    self._send_output(client.sock)
                readable = [listener] if client is None else [client.sock, listener]
                ready, _, _ = select.select(readable, [], [], wait)
                # The client first: one that has just hung up frees the robot for the next.
                if client is not None and client.sock in ready:
                    client = self._receive(client)
                if listener in ready:
                    if client is not None:
                        client = self._catch_up(client)
                    client = self._knock(listener, client)
        finally:
            if client is not None:
                client.sock.close()
            listener.close()
            self.simulation.stop_all()

    def _expired(self, max_runtime_s: float | None) -> bool:
        return max_runtime_s is not None and self.now() >= max_runtime_s

    def _knock(self, listener: socket.socket, client: _Client | None) -> _Client | None:
        """A newcomer connects: it gets the robot if it is free or its holder has been quiet
        for the handshake wait; otherwise it is told the robot is busy. Returns the holder."""
        try:
            sock, address = listener.accept()
        except BlockingIOError:
            return client
        name = f"{address[0]}:{address[1]}"
        if client is not None and not self._yields(client, name):
            self._refuse(sock, name, client)
            return client
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sock.setblocking(False)
        self.announce(f"client connected from {name}")
        self.simulation.read(self.simulation.in_waiting)  # nobody heard it: a serial line drops it
        self.simulation.connect()
        now = self.now()
        newcomer = _Client(sock, name, now, self.burst_bytes, now)
        self._send_output(sock)
        return newcomer

    def _catch_up(self, client: _Client) -> _Client | None:
        """Read all ``client`` has sent so far, to learn whether it has hung up already.

        A client that closed right after sending (or flooding) may still have bytes waiting
        here; the one that connects after it must not be refused for them. Bounded: the
        kernel's receive buffer holds a few megabytes at most.
        """
        current: _Client | None = client
        for _ in range(_CATCH_UP_READS):  # a client still flooding does not hold the loop
            if current is None:
                break
            ready, _, _ = select.select([current.sock], [], [], 0)
            if not ready:
                break
            current = self._receive(current)
        return current

    def _refuse(self, sock: socket.socket, name: str, client: _Client) -> None:
        """Tell ``sock``, which came while ``client`` has the robot, that it is busy; close it."""
        try:
            sock.setblocking(False)
            sock.send(BUSY_LINE.format(other=client.name).encode("ascii"))
        except OSError as exc:
            logger.debug("could not tell %s it is refused: %s", name, exc)
        finally:
            sock.close()
        self.refused += 1
        self.announce(f"client {name} refused: busy with {client.name}")

    def _yields(self, client: _Client, newcomer: str) -> bool:
        """Drop ``client`` for ``newcomer`` if it has said nothing, or stopped mid-message,
        for the handshake wait; True if dropped."""
        quiet_since_s = client.quiet_since_s()
        if quiet_since_s is None or self.now() - quiet_since_s < self.handshake_wait_s:
            return False
        self.idle_drops += 1
        wait = f"{self.handshake_wait_s:g} s"
        why = (
            f"it stopped in the middle of a message and sent nothing for {wait}"
            if client.heard
            else f"it sent nothing for {wait} after connecting"
        )
        self._hang_up(
            client,
            f"client {client.name} dropped: {why} and {newcomer} wants the robot; motors stopped",
        )
        return True

    def _hang_up(self, client: _Client, line: str) -> None:
        self.simulation.stop_all()
        client.sock.close()
        if client.dropped_bytes:
            line += f" ({client.dropped_bytes} bytes sent faster than the line were dropped)"
        self.announce(line)

    def _receive(self, client: _Client) -> _Client | None:
        try:
            data = client.sock.recv(_READ_CHUNK)
        except (BlockingIOError, InterruptedError):
            return client
        except OSError:
            data = b""
        if not data:
            self._hang_up(client, "client disconnected; motors stopped")
            return None
        client.heard = True
        self.simulation.write(self._within_line_rate(client, data))
        client.last_byte_s = self.now()
        client.mid_frame = self.simulation.input_pending > 0
        self._send_output(client.sock)
        return client

    def _within_line_rate(self, client: _Client, data: bytes) -> bytes:
        """The part of ``data`` the robot's serial line carries now; the rest is counted."""
        now = self.now()
        refill = (now - client.budget_at_s) * self.line_bytes_s
        client.budget_bytes = min(self.burst_bytes, client.budget_bytes + refill)
        client.budget_at_s = now
        taken = min(len(data), int(client.budget_bytes))
        client.budget_bytes -= taken
        excess = len(data) - taken
        if excess:
            if not client.dropped_bytes:
                self.announce(
                    f"client {client.name} sends faster than the robot's line "
                    f"({self.line_bytes_s:.0f} bytes/s): dropping what does not fit"
                )
            client.dropped_bytes += excess
            self.dropped_bytes += excess
        return data[:taken]

    def _send_output(self, client: socket.socket) -> None:
        data = self.simulation.read(self.simulation.in_waiting)
        if not data:
            return
        try:
            client.sendall(data)
        except BlockingIOError:
            logger.debug("client is not reading; dropped %d bytes", len(data))
        except OSError as exc:
            logger.debug("send failed: %s", exc)

    # ---------------------------------------------------------------------------------- pty

    def serve_pty(self, *, max_runtime_s: float | None = None) -> None:
        """Serve on a new pseudo-terminal until :meth:`stop`, Ctrl-C or ``max_runtime_s``.

        A program opening the pty is a host opening the robot's port: the device greets it
        (a board that resets on connect starts again first); when the last one closes it,
        the motors are stopped. What the device sends while nobody has it open is lost, as
        on a serial line nobody listens to.
        """
        master, slave = pty.openpty()
        tty.setraw(slave)  # no echo, no line editing: bytes pass through as on a serial line
        os.set_blocking(master, False)
        # Not kept open here, so that the master reads EIO exactly while no program has it;
        # watched before its path is said, so that no program can open it unseen.
        path = os.ttyname(slave)
        os.close(slave)
        watch = _PtyOpenings(path)
        self.announce(path)
        opened = False
        try:
            while not self._stop and not self._expired(max_runtime_s):
                wait = self._advance()
                if opened:
                    self._pty_write(master)
                else:
                    self.simulation.read(self.simulation.in_waiting)  # nobody hears it
                # Without a program on the other side the master is always "ready" (EIO):
                # it is then looked at once a physics step.
                select.select([master, *watch.files()] if opened else watch.files(), [], [], wait)
                data = _pty_read(master)
                for now_open in watch.changes(has_reader=data is not None):
                    if now_open:
                        self.simulation.connect()  # the port opened (a board's DTR line)
                    else:
                        self.simulation.stop_all()
                opened = data is not None
                if data:
                    self.simulation.write(data)
                    self._pty_write(master)
        finally:
            self.simulation.stop_all()
            watch.close()
            os.close(master)

    def _pty_write(self, master: int) -> None:
        data = self.simulation.read(self.simulation.in_waiting)
        if not data:
            return
        try:
            os.write(master, data)
        except BlockingIOError:
            # Nobody is reading and the pty buffer is full: drop, as a serial line would.
            logger.debug("pty full; dropped %d bytes", len(data))
        except OSError as exc:
            if exc.errno != errno.EIO:
                raise


def _pty_read(master: int) -> bytes | None:
    """What the program on the pty wrote (``b""``: nothing yet), or None when no program
    has the pty open."""
    try:
        return os.read(master, _READ_CHUNK)
    except BlockingIOError:
        return b""
    except OSError as exc:
        if exc.errno != errno.EIO:  # EIO: no process has the slave open
            raise
        return None


_IN_OPEN, _IN_CLOSE = 0x20, 0x08 | 0x10  # inotify: opened; closed (written to or not)


class _PtyOpenings:
    """When programs open and close a pty: each time the first opens it (a port opening,
    which resets a board whose DTR line drives its reset) and the last closes it.

    On Linux, from inotify's open and close events on the pty, so that a program closing
    the pty and another opening it at once is seen however busy the machine is; elsewhere,
    from whether the master has a reader each time it is looked at.
    """

    def __init__(self, path: str) -> None:
        self._fd: int | None = None
        self._holders = 0
        self._had_reader = False
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            fd = libc.inotify_init1(os.O_NONBLOCK | os.O_CLOEXEC)
        except (OSError, AttributeError):  # not Linux
            return
        if fd < 0:
            return
        if libc.inotify_add_watch(fd, os.fsencode(path), _IN_OPEN | _IN_CLOSE) < 0:
            os.close(fd)
            return
        self._fd = fd

    def files(self) -> list[int]:
        """What to wait on besides the pty (the inotify descriptor, if any)."""
        return [] if self._fd is None else [self._fd]

    def changes(self, *, has_reader: bool) -> list[bool]:
        """Since the last call, in order: True where the pty was opened by a first program,
        False where the last closed it. ``has_reader``: whether the master has one now."""
        if self._fd is None:
            changed = [has_reader] if has_reader != self._had_reader else []
            self._had_reader = has_reader
            return changed
        changes: list[bool] = []
        for mask in self._masks():
            if mask & _IN_OPEN:
                self._holders += 1
                if self._holders == 1:
                    changes.append(True)
            elif mask & _IN_CLOSE and self._holders:
                self._holders -= 1
                if not self._holders:
                    changes.append(False)
        return changes

    def _masks(self) -> list[int]:
        assert self._fd is not None
        masks: list[int] = []
        while True:
            try:
                data = os.read(self._fd, 4096)
            except BlockingIOError:
                return masks
            offset = 0
            while offset + 16 <= len(data):
                _, mask, _, name_bytes = struct.unpack_from("iIII", data, offset)
                masks.append(mask)
                offset += 16 + name_bytes

    def close(self) -> None:
        """Stop watching."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None
