"""The link: bytes in, messages out; garbage counted and skipped; a lost peer is one error."""

from __future__ import annotations

import logging
import socket

import pytest

from roboscript.clock import SimClock
from roboscript.codec import Role
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.errors import LinkClosedError
from roboscript.transport import Link, open_port
from roboscript.transport.wirelog import WireLog, read_wire_log


@pytest.fixture
def pair() -> tuple[socket.socket, Link]:
    server = socket.create_server(("127.0.0.1", 0))
    port = open_port(f"socket://127.0.0.1:{server.getsockname()[1]}")
    peer, _ = server.accept()
    server.close()
    link = Link(port, AsipCodec(Role.HOST), clock=SimClock(), name="test robot")
    return peer, link


def _poll_until(link: Link, count: int) -> list[object]:
    found: list[object] = []
    for _ in range(200):
        found.extend(link.poll())
        if len(found) >= count:
            break
        socket.socket().close()  # yield to the kernel briefly without sleeping in the test
    return found


def test_messages_arrive_in_order_split_anywhere(pair: tuple[socket.socket, Link]) -> None:
    peer, link = pair
    peer.sendall(b"@M,e,2,{1:1,2:2}\n@B,e,")
    peer.sendall(b"2,{1,0}\n@D,e,1,{42}\n")
    found = _poll_until(link, 3)
    assert found == [
        m.EncoderEvent(((1, 1), (2, 2))),
        m.BumpEvent((1, 0)),
        m.DistanceEvent((42,)),
    ]
    peer.close()


def test_garbage_is_counted_skipped_and_logged_once_per_kind(
    pair: tuple[socket.socket, Link], caplog: pytest.LogCaptureFixture
) -> None:
    peer, link = pair
    caplog.set_level(logging.WARNING)
    noise = b"\xff\xfe\x00garbage\n" * 5 + b"@D,e,1,{x}\n" * 3 + b"@D,e,1,{17}\n"
    peer.sendall(noise)
    found = _poll_until(link, 1)
    assert found == [m.DistanceEvent((17,))]
    assert link.faults == {"garbage": 5, "malformed": 3}
    warnings = [r for r in caplog.records if "cannot read" in r.getMessage()]
    assert len(warnings) == 2
    peer.close()


def test_peer_disconnect_raises_one_link_closed_error(pair: tuple[socket.socket, Link]) -> None:
    peer, link = pair
    peer.close()
    with pytest.raises(LinkClosedError, match="the connection to test robot was lost"):
        for _ in range(200):
            link.poll()
    with pytest.raises(LinkClosedError):
        link.send(m.StopMotors())


def test_wire_log_records_both_directions_exactly(
    pair: tuple[socket.socket, Link], tmp_path: object
) -> None:
    peer, link = pair
    path = f"{tmp_path}/w.log"
    link.wire_log = WireLog(path)
    link.send(m.SetMotorsPower(10, -10))
    peer.sendall(b"@B,e,2,{1,1}\n\xff\n")
    _poll_until(link, 1)
    link.close()
    records = read_wire_log(path)
    assert (records[0][1], records[0][2]) == (">", b"M,M,10,-10\n")
    assert b"".join(data for _, d, data in records if d == "<") == b"@B,e,2,{1,1}\n\xff\n"
    peer.close()


def test_opening_a_missing_port_names_it() -> None:
    from roboscript.errors import LinkError

    with pytest.raises(LinkError, match="cannot open /dev/nope-1"):
        open_port("/dev/nope-1")


def test_a_lost_link_still_closes_its_port(pair: tuple[socket.socket, Link]) -> None:
    peer, link = pair
    peer.close()
    with pytest.raises(LinkClosedError):
        for _ in range(200):
            link.poll()
    link.close()
    assert not link.port.is_open  # type: ignore[attr-defined]


def test_a_signal_while_the_port_closes_still_closes_the_wire_log(
    pair: tuple[socket.socket, Link], tmp_path: object, monkeypatch: pytest.MonkeyPatch
) -> None:
    peer, link = pair
    path = f"{tmp_path}/w.log"
    link.wire_log = WireLog(path)
    link.send(m.StopMotors())

    closed: list[str] = []
    close_log = link.wire_log.close

    def interrupted() -> None:
        closed.append("port")
        raise KeyboardInterrupt

    def logged_close() -> None:
        closed.append("log")
        close_log()

    monkeypatch.setattr(link.port, "close", interrupted)
    monkeypatch.setattr(link.wire_log, "close", logged_close)
    with pytest.raises(KeyboardInterrupt):
        link.close()
    # the port first (the log records its last bytes), the log even though that was stopped
    assert closed == ["port", "log"]
    assert [data for _, _, data in read_wire_log(path)] == [b"M,S,0\n"]  # flushed: closed
    peer.close()
