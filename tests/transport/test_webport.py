"""The browser's ports and clock, in CPython: Pyodide's ``run_sync`` played by an asyncio loop,
and the page by the messages the port posts and the ones the test delivers.

The port lives in the page, the run in the page's worker: the worker's side of a port is
messages both ways (:mod:`roboscript.transport.webport`). tests/web/test_ports.py drives the
same code in a real Chromium through the page's Web Serial and Web Bluetooth layers; these pin
the rules the worker's side keeps, where a failure is quick to read.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Iterator
from typing import Any

import pytest
from serial import SerialException

from roboscript.errors import LinkError
from roboscript.interrupts import Interrupted
from roboscript.transport import open_port, webport
from roboscript.transport.webport import (
    LOST_USB,
    PageClock,
    WebBluetoothPort,
    WebSerialPort,
    chosen_robot,
    deliver,
    port_url,
)

pytestmark = pytest.mark.timeout(120)  # a wait that is never woken would hang; fail instead


class FakeFfi:
    """The part of ``pyodide.ffi`` the web ports use, with a private event loop as the
    worker's."""

    def __init__(self) -> None:
        self.loop = asyncio.new_event_loop()

    def run_sync(self, awaitable: Awaitable[Any]) -> Any:
        return self.loop.run_until_complete(awaitable)

    def to_js(self, value: Any, **_: Any) -> Any:
        return value


class FakeJs:
    """The worker's global scope: what the port posts to the page."""

    def __init__(self) -> None:
        self.posted: list[dict[str, Any]] = []

    class Object:
        @staticmethod
        def fromEntries(entries: Any) -> Any:  # noqa: N802 - the browser's name
            return dict(entries)

    def postMessage(self, message: dict[str, Any]) -> None:  # noqa: N802 - the browser's name
        self.posted.append(message)

    def kinds(self) -> list[str]:
        return [message["type"] for message in self.posted]


@pytest.fixture
def ffi() -> Iterator[FakeFfi]:
    fake = FakeFfi()
    yield fake
    fake.loop.close()


@pytest.fixture
def js(ffi: FakeFfi, monkeypatch: pytest.MonkeyPatch) -> FakeJs:
    fake = FakeJs()
    monkeypatch.setattr(webport, "_browser", lambda: (fake, ffi))
    return fake


def _page_answers(ffi: FakeFfi, *messages: tuple[str, Any]) -> None:
    """The page's messages, delivered while the worker waits."""
    for event, data in messages:
        ffi.loop.call_soon(deliver, event, data)


def _opened(js: FakeJs, ffi: FakeFfi, url: str = "webserial://1") -> Any:
    _page_answers(ffi, ("opened", None))
    port = open_port(url, baudrate=57600)
    js.posted.clear()
    return port


def test_a_stop_asked_by_the_page_lands_at_the_next_wait_with_its_reason(ffi: FakeFfi) -> None:
    clock = PageClock(ffi)
    clock.interrupt("stopped with the Stop button")
    clock.interrupt("the page was closed")  # the first reason given stays the reason
    with pytest.raises(Interrupted) as raised:
        clock.sleep_until(clock.now())
    assert raised.value.reason == "stopped with the Stop button"
    clock.sleep_until(clock.now())  # once: the run's own way out may wait again


def test_a_stop_asked_during_a_wait_ends_the_wait_at_once(ffi: FakeFfi) -> None:
    clock = PageClock(ffi)
    ffi.loop.call_soon(clock.interrupt, "stopped with the Stop button")
    with pytest.raises(Interrupted):
        clock.sleep_until(clock.now() + 3600.0)  # woken, not waited out


def test_a_port_is_opened_by_the_page_and_its_bytes_go_both_ways_in_order(
    js: FakeJs, ffi: FakeFfi
) -> None:
    _page_answers(ffi, ("opened", None))
    port = open_port("webserial://1", baudrate=57600)
    assert js.posted == [
        {"type": "port-open", "url": "webserial://1", "baudRate": 57600, "bluetooth": None}
    ]
    port.write(b"first")
    port.write(b"second")
    assert js.posted[1:] == [
        {"type": "port-write", "data": b"first"},
        {"type": "port-write", "data": b"second"},
    ]
    deliver("received", b"@I,a,")
    deliver("received", b"2\n")
    assert port.read(100) == b"@I,a,2\n"
    port.close()
    port.close()  # twice: said once
    assert js.kinds()[-1] == "port-close" and js.kinds().count("port-close") == 1


def test_a_chosen_port_that_will_not_open_is_named_as_the_student_chose_it(
    js: FakeJs, ffi: FakeFfi
) -> None:
    _page_answers(ffi, ("failed", "NetworkError: Failed to open serial port."))
    with pytest.raises(LinkError) as raised:
        open_port("webserial://1")
    assert str(raised.value) == (
        "cannot reach the robot on the serial port you chose: "
        "NetworkError: Failed to open serial port."
    )


def test_the_pages_stop_while_the_port_opens_ends_the_run_there(js: FakeJs, ffi: FakeFfi) -> None:
    _page_answers(ffi, ("interrupt", "stopped with the Stop button"))
    with pytest.raises(Interrupted) as raised:
        open_port("webserial://1")
    assert raised.value.reason == "stopped with the Stop button"
    assert not webport.interrupt_open_ports("again")  # the port is not left among the open


def test_a_lost_link_ends_the_run_with_its_sentence_and_refuses_later_writes(
    js: FakeJs, ffi: FakeFfi
) -> None:
    port = _opened(js, ffi)
    deliver("lost", "NetworkError: The device has been lost.")
    with pytest.raises(Interrupted) as raised:
        port.clock.sleep_until(port.clock.now())
    assert raised.value.reason == LOST_USB
    with pytest.raises(SerialException, match="USB connection was lost"):
        port.write(b"more")
    port.close()


def test_the_robots_stop_is_handed_to_the_page_in_the_hubs_packets(
    js: FakeJs, ffi: FakeFfi
) -> None:
    port = _opened(js, ffi, "webbluetooth://2")
    assert isinstance(port, WebBluetoothPort)
    port.set_max_packet_size(4)  # as the driver does with the hub's InfoResponse
    port.write(b"0123456789")
    port.ready(b"STOP-IT")
    assert js.posted == [
        {"type": "port-write", "data": b"0123"},
        {"type": "port-write", "data": b"4567"},
        {"type": "port-write", "data": b"89"},
        {"type": "robot-ready", "stop": [b"STOP", b"-IT"]},
    ]
    port.close()


def test_a_bluetooth_port_asks_the_page_for_the_hubs_service(js: FakeJs, ffi: FakeFfi) -> None:
    _page_answers(ffi, ("opened", None))
    open_port("webbluetooth://1").close()
    assert js.posted[0]["bluetooth"] == {
        "service": webport.SERVICE_UUID,
        "rx": webport.RX_CHARACTERISTIC,
        "tx": webport.TX_CHARACTERISTIC,
    }


def test_what_the_page_still_had_for_a_closed_port_goes_nowhere(js: FakeJs, ffi: FakeFfi) -> None:
    port = _opened(js, ffi)
    assert isinstance(port, WebSerialPort)
    port.close()
    deliver("received", b"late")  # no error, and nobody reads it
    assert port.in_waiting == 0


def test_a_page_port_outside_a_browser_is_refused_in_one_sentence() -> None:
    with pytest.raises(LinkError, match="exist only in roboscript's browser app"):
        open_port("webserial://1")


def test_a_chosen_port_is_named_by_its_scheme_and_number() -> None:
    assert port_url("webserial", 3) == "webserial://3"
    with pytest.raises(ValueError, match="webserial or webbluetooth"):
        port_url("socket", 1)


@pytest.mark.parametrize(
    ("url", "named"),
    [
        ("webserial://3", "the robot on the serial port you chose"),
        ("webbluetooth://1", "the Bluetooth robot you chose"),
        ("socket://127.0.0.1:9999", None),  # a URL the user gave is named by itself
    ],
)
def test_a_chosen_robot_is_named_by_how_it_was_chosen(url: str, named: str | None) -> None:
    assert chosen_robot(url) == named
