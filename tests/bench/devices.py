"""Device processes for the benchmarks: the robot's end of a loopback socket or a pty.

Each device runs in a child process (forked, so it inherits the CPU pinning) and uses only
raw sockets and file descriptors, so its cost is the same whichever host stack is measured.
The host side starts a device with :func:`start`, which returns once the device listens.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import pty
import select
import socket
import tty
from collections.abc import Callable, Iterator
from multiprocessing.process import BaseProcess
from typing import Any

__all__ = [
    "flood_pty",
    "flood_socket",
    "replying_socket",
    "silent_socket",
]

_CHUNK = 65536


def _context() -> Any:
    # fork keeps the parent's CPU affinity and needs no pickling of the device functions.
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if "fork" in methods else "spawn")


@contextlib.contextmanager
def _run(target: Callable[..., None], *args: Any) -> Iterator[BaseProcess]:
    process = _context().Process(target=target, args=args, daemon=True)
    process.start()
    try:
        yield process
    finally:
        process.join(timeout=5)
        if process.is_alive():
            process.terminate()
            process.join(timeout=5)


def _listener() -> socket.socket:
    listener = socket.create_server(("127.0.0.1", 0))
    listener.listen(4)
    return listener


def _accept(listener: socket.socket) -> socket.socket:
    peer, _ = listener.accept()
    peer.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return peer


# ------------------------------------------------------------------------------ flooding


def _flood_socket_device(listener: socket.socket, blob: bytes) -> None:
    peer = _accept(listener)
    listener.close()
    if peer.recv(1):  # the host's "go"
        peer.sendall(blob)
    while peer.recv(_CHUNK):  # hold the line open until the host has read it all
        pass
    peer.close()


@contextlib.contextmanager
def flood_socket(blob: bytes) -> Iterator[str]:
    """A device that writes ``blob`` into a loopback socket, as fast as it is taken, on "go".

    Yields:
        The URL to open (``socket://127.0.0.1:PORT``); write one byte to start the flood.
    """
    listener = _listener()
    port = listener.getsockname()[1]
    with _run(_flood_socket_device, listener, blob):
        listener.close()  # the child holds its own copy
        yield f"socket://127.0.0.1:{port}"


def _flood_pty_device(master: int, blob: bytes) -> None:
    os.set_blocking(master, True)
    if os.read(master, 1):  # the host's "go"
        view = memoryview(blob)
        while view:
            written = os.write(master, view[:_CHUNK])
            view = view[written:]
    # Keep the master open until the host closes the slave (EIO), so no byte is lost.
    with contextlib.suppress(OSError):
        while os.read(master, _CHUNK):
            pass


@contextlib.contextmanager
def flood_pty(blob: bytes) -> Iterator[str]:
    """Like :func:`flood_socket`, through a raw pseudo-terminal (a serial line's kernel path).

    Yields:
        The path of the pty's slave end, to open as a serial port.
    """
    master, slave = pty.openpty()
    tty.setraw(slave)
    path = os.ttyname(slave)
    with _run(_flood_pty_device, master, blob):
        os.close(master)
        try:
            yield path
        finally:
            os.close(slave)


# ------------------------------------------------------------------------------ replying


def _replying_device(listener: socket.socket, reply: bytes | None, clients: int) -> None:
    peers = [_accept(listener) for _ in range(clients)]
    listener.close()
    pending = dict.fromkeys(peers, b"")
    while pending:
        ready, _, _ = select.select(list(pending), [], [])
        for peer in ready:
            data = peer.recv(_CHUNK)
            if not data:
                del pending[peer]
                peer.close()
                continue
            *lines, pending[peer] = (pending[peer] + data).split(b"\n")
            if not lines:
                continue
            if reply is None:  # echo: "@" + the request line
                peer.sendall(b"".join(b"@" + line + b"\n" for line in lines))
            else:
                peer.sendall(reply * len(lines))


@contextlib.contextmanager
def replying_socket(reply: bytes | None, clients: int = 2) -> Iterator[str]:
    """A device that answers every newline-terminated request with ``reply``.

    With ``reply=None`` it echoes each request line back as ``"@" + line``: the fixture of
    performance.md B.1, where ``I,d,13,1`` is answered with ``@I,d,13,1``.

    It serves ``clients`` connections at once (made in any order), so two host stacks can
    take turns against the same device in one run.

    Yields:
        The URL to open (``socket://127.0.0.1:PORT``).
    """
    listener = _listener()
    port = listener.getsockname()[1]
    with _run(_replying_device, listener, reply, clients):
        listener.close()
        yield f"socket://127.0.0.1:{port}"


# -------------------------------------------------------------------------------- silent


def _silent_device(listener: socket.socket) -> None:
    peer = _accept(listener)
    listener.close()
    while peer.recv(_CHUNK):  # a connected board with nothing to say
        pass
    peer.close()


@contextlib.contextmanager
def silent_socket() -> Iterator[str]:
    """A device that accepts the connection and never sends a byte.

    Yields:
        The URL to open (``socket://127.0.0.1:PORT``).
    """
    listener = _listener()
    port = listener.getsockname()[1]
    with _run(_silent_device, listener):
        listener.close()
        yield f"socket://127.0.0.1:{port}"
