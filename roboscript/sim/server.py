"""Serve a simulated robot's protocol bytes in real time, as a serial line would carry them.

``roboscript sim --robot mirto --tcp 127.0.0.1:9999`` listens on a loopback TCP port (one
client at a time; a client that disconnects may reconnect); ``--pty`` opens a pseudo-terminal
and prints its path. Any tool that talks to the real robot can talk to the simulator:
``roboscript run --port socket://127.0.0.1:9999``, the python-asip client, a serial terminal.

One thread: a ``select`` loop waits for bytes or for the next physics step and ticks the
simulation on the wall clock. When a client connects, the device greets it as the real one
does after a reset; when it disconnects the motors are stopped, so a crashed client never
leaves the simulated robot driving.
"""

from __future__ import annotations

import errno
import logging
import os
import pty
import select
import socket
import time
import tty
from collections.abc import Callable

from roboscript.sim.simulation import Simulation

__all__ = ["SimServer", "parse_host_port"]

logger = logging.getLogger(__name__)

_READ_CHUNK = 65536


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
    """

    def __init__(
        self, simulation: Simulation, announce: Callable[[str], None] | None = None
    ) -> None:
        self.simulation = simulation
        self.announce = announce or logger.info
        self._origin = time.monotonic()
        self._stop = False

    def now(self) -> float:
        """Seconds since the server started (the simulation's clock)."""
        return time.monotonic() - self._origin

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
        client: socket.socket | None = None
        try:
            while not self._stop and not self._expired(max_runtime_s):
                wait = self._advance()
                if client is not None:
                    self._send_output(client)
                readable = [listener] if client is None else [client]
                ready, _, _ = select.select(readable, [], [], wait)
                if listener in ready:
                    client = self._accept(listener)
                elif client is not None and client in ready:
                    client = self._receive(client)
        finally:
            if client is not None:
                client.close()
            listener.close()
            self.simulation.stop_all()

    def _expired(self, max_runtime_s: float | None) -> bool:
        return max_runtime_s is not None and self.now() >= max_runtime_s

    def _accept(self, listener: socket.socket) -> socket.socket | None:
        try:
            client, address = listener.accept()
        except BlockingIOError:
            return None
        client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        client.setblocking(False)
        self.announce(f"client connected from {address[0]}:{address[1]}")
        self.simulation.read(self.simulation.in_waiting)  # nobody heard it: a serial line drops it
        self.simulation.connect()
        self._send_output(client)
        return client

    def _receive(self, client: socket.socket) -> socket.socket | None:
        try:
            data = client.recv(_READ_CHUNK)
        except (BlockingIOError, InterruptedError):
            return client
        except OSError:
            data = b""
        if not data:
            self.announce("client disconnected; motors stopped")
            self.simulation.stop_all()
            client.close()
            return None
        self.simulation.write(data)
        self._send_output(client)
        return client

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
        """Serve on a new pseudo-terminal until :meth:`stop`, Ctrl-C or ``max_runtime_s``."""
        master, slave = pty.openpty()
        tty.setraw(slave)  # no echo, no line editing: bytes pass through as on a serial line
        os.set_blocking(master, False)
        self.announce(os.ttyname(slave))
        self.simulation.connect()
        try:
            while not self._stop and not self._expired(max_runtime_s):
                wait = self._advance()
                self._pty_write(master)
                ready, _, _ = select.select([master], [], [], wait)
                if ready:
                    try:
                        data = os.read(master, _READ_CHUNK)
                    except BlockingIOError:
                        continue
                    except OSError as exc:
                        if exc.errno != errno.EIO:  # EIO: no process has the slave open
                            raise
                        continue
                    self.simulation.write(data)
                    self._pty_write(master)
        finally:
            self.simulation.stop_all()
            os.close(master)
            os.close(slave)

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
