"""socket://HOST:PORT opens roboscript's lean TCP port; it behaves as the link needs."""

from __future__ import annotations

import socket
from collections.abc import Iterator

import pytest

from roboscript.errors import LinkError
from roboscript.transport import open_port
from roboscript.transport.socketport import SocketPort, parse_socket_url


@pytest.fixture
def pair() -> Iterator[tuple[socket.socket, SocketPort]]:
    server = socket.create_server(("127.0.0.1", 0))
    port = open_port(f"socket://127.0.0.1:{server.getsockname()[1]}")
    assert isinstance(port, SocketPort)
    peer, _ = server.accept()
    server.close()
    yield peer, port
    port.close()
    peer.close()


def _read_some(port: SocketPort) -> bytes:
    for _ in range(1000):
        data = port.read(4096)
        if data:
            return data
        socket.socket().close()  # give the kernel a moment without sleeping
    return b""


def test_read_returns_nothing_then_what_arrived(pair: tuple[socket.socket, SocketPort]) -> None:
    peer, port = pair
    assert port.read(4096) == b""
    peer.sendall(b"@B,e,2,{1,0}\n")
    assert _read_some(port) == b"@B,e,2,{1,0}\n"


def test_write_sends_everything_at_once_without_nagle(
    pair: tuple[socket.socket, SocketPort],
) -> None:
    peer, port = pair
    assert port._socket.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY)
    assert port.write(b"M,M,10,-10\n") == 11
    assert peer.recv(100) == b"M,M,10,-10\n"


def test_a_peer_that_hangs_up_is_an_error_not_silence(
    pair: tuple[socket.socket, SocketPort],
) -> None:
    peer, port = pair
    peer.close()
    with pytest.raises(ConnectionResetError, match="closed by the other end"):
        for _ in range(1000):
            port.read(4096)


def test_a_peer_that_stops_reading_times_the_write_out(
    pair: tuple[socket.socket, SocketPort],
) -> None:
    _, port = pair
    port.write_timeout_s = 0.1
    with pytest.raises(TimeoutError, match="stopped reading"):
        for _ in range(1000):  # fills both kernel buffers, then waits 0.1 s
            port.write(b"x" * 65536)


def test_urls_with_options_still_go_to_pyserial() -> None:
    server = socket.create_server(("127.0.0.1", 0))
    port = open_port(f"socket://127.0.0.1:{server.getsockname()[1]}?logging=warning")
    try:
        assert not isinstance(port, SocketPort)
    finally:
        port.close()
        server.close()


def test_nothing_listening_is_explained() -> None:
    server = socket.create_server(("127.0.0.1", 0))
    free_port = server.getsockname()[1]
    server.close()
    with pytest.raises(LinkError, match="nothing is listening there"):
        open_port(f"socket://127.0.0.1:{free_port}")


@pytest.mark.parametrize(
    ("url", "expected"),
    [
        ("socket://127.0.0.1:9999", ("127.0.0.1", 9999)),
        ("SOCKET://localhost:1", ("localhost", 1)),
        ("socket://[::1]:80", ("::1", 80)),
        ("socket://host:1?logging=debug", None),
    ],
)
def test_socket_urls_parse(url: str, expected: tuple[str, int] | None) -> None:
    assert parse_socket_url(url) == expected


@pytest.mark.parametrize("url", ["socket://nohost", "socket://:80", "socket://h:99999"])
def test_bad_socket_urls_name_the_url(url: str) -> None:
    with pytest.raises(LinkError, match="cannot open"):
        open_port(url)
