"""``socket://HOST:PORT`` without pyserial's per-call overhead: a TCP port that acts like a UART.

pyserial's ``socket://`` handler costs a ``select()`` and two ``Timeout`` objects on every
``read`` and another ``select()`` on every ``write`` (it waits for writability after the send
even when the send took everything). On a loopback round trip that overhead was about 10 µs
on top of an 8 µs kernel floor, most of roboscript's share of the trip (tests/bench/bench_rtt.py).
This port calls ``recv``/``send`` on a non-blocking socket directly and waits only when the
kernel's send buffer is full.

``TCP_NODELAY`` is set because a serial line sends each byte as soon as it is written; with
Nagle's algorithm a second small write would wait for the peer's ACK of the first.

URLs with pyserial options (``socket://host:port?logging=debug``) still go to pyserial.
"""

from __future__ import annotations

import select
import socket
import time
import urllib.parse

__all__ = ["SocketPort", "parse_socket_url"]

_CONNECT_TIMEOUT_S = 5.0


def parse_socket_url(url: str) -> tuple[str, int] | None:
    """``socket://HOST:PORT`` -> ``(host, port)``; ``None`` if the URL carries options.

    Raises:
        ValueError: Not a ``socket://`` URL with a host and a port.
    """
    parts = urllib.parse.urlsplit(url)
    if parts.scheme != "socket":
        raise ValueError(f"expected a socket:// URL, got {url!r}")
    if parts.query or parts.path or parts.fragment:
        return None
    if not parts.hostname or parts.port is None:
        raise ValueError(f"expected socket://HOST:PORT, got {url!r}")
    return parts.hostname, parts.port


class SocketPort:
    """A connected, non-blocking TCP socket with the part of pyserial's API a link uses.

    Args:
        host: Where to connect.
        port: The TCP port.
        write_timeout_s: How long :meth:`write` may wait for a full send buffer to drain.

    Raises:
        OSError: The connection failed (refused, unreachable, timed out).
    """

    def __init__(self, host: str, port: int, *, write_timeout_s: float = 2.0) -> None:
        self.port = f"socket://{host}:{port}"
        self.write_timeout_s = write_timeout_s
        self._socket = socket.create_connection((host, port), timeout=_CONNECT_TIMEOUT_S)
        self._socket.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._socket.setblocking(False)
        self.is_open = True

    def fileno(self) -> int:
        """The socket's descriptor, for ``select``."""
        return self._socket.fileno()

    def read(self, size: int = 1) -> bytes:
        """Return up to ``size`` bytes that have arrived, ``b""`` if none; never blocks.

        Raises:
            ConnectionResetError: The peer closed the connection.
            OSError: The socket failed.
        """
        try:
            data = self._socket.recv(size)
        except (BlockingIOError, InterruptedError):
            return b""
        if not data:
            raise ConnectionResetError(f"{self.port} was closed by the other end")
        return data

    def write(self, data: bytes, /) -> int:
        """Send all of ``data``, waiting at most ``write_timeout_s`` for buffer space.

        Raises:
            TimeoutError: The peer stopped reading and the send buffer stayed full.
            OSError: The socket failed.
        """
        try:
            sent = self._socket.send(data)
        except (BlockingIOError, InterruptedError):
            sent = 0
        if sent == len(data):  # the usual case: the kernel took it all at once
            return sent
        view = memoryview(data)[sent:]
        deadline: float | None = None
        while view:
            try:
                sent = self._socket.send(view)
            except (BlockingIOError, InterruptedError):
                sent = 0
            view = view[sent:]
            if not view:
                break
            # The kernel buffer is full: only now is waiting (and a clock read) worth it.
            now = time.monotonic()
            if deadline is None:
                deadline = now + self.write_timeout_s
            if now >= deadline or not select.select([], [self._socket], [], deadline - now)[1]:
                raise TimeoutError(f"{self.port} stopped reading for {self.write_timeout_s:g} s")
        return len(data)

    def close(self) -> None:
        """Close the connection (safe to call twice).

        There is no ``__del__``: the link closes its port on every way out, and a signal
        landing in a finalizer could only be dropped there.
        """
        self.is_open = False
        self._socket.close()
