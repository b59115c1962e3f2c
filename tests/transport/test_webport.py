"""The browser's ports and clock, in CPython: Pyodide's ``run_sync`` played by an asyncio loop.

tests/web/test_ports.py drives the same code in a real Chromium through its Web Serial layer;
these pin the rules that code keeps, where a failure is quick to read.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable, Iterator
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
    WebPort,
    chosen_robot,
    remember_chosen,
)

pytestmark = pytest.mark.timeout(120)  # a wait that is never woken would hang; fail instead


class FakeFfi:
    """The part of ``pyodide.ffi`` the web ports use, with a private event loop as the page's."""

    def __init__(self) -> None:
        self.loop = asyncio.new_event_loop()

    def run_sync(self, awaitable: Awaitable[Any]) -> Any:
        return self.loop.run_until_complete(awaitable)

    def can_run_sync(self) -> bool:
        return True

    def create_proxy(self, function: Callable[..., Any]) -> Any:
        return _Proxy(function)

    def to_js(self, value: Any, **_: Any) -> Any:
        return value


class _Proxy:
    def __init__(self, function: Callable[..., Any]) -> None:
        self.function = function
        self.destroyed = False

    def __call__(self, *args: Any) -> Any:
        return self.function(*args)

    def destroy(self) -> None:
        self.destroyed = True


class Promise:
    """A browser promise the test settles by hand."""

    def __init__(self) -> None:
        self.on_ok: Any = None
        self.on_fail: Any = None

    def then(self, on_ok: Any, on_fail: Any) -> None:
        self.on_ok, self.on_fail = on_ok, on_fail


class BrowserPort(WebPort):
    """A web port whose browser side is a list of started writes."""

    def __init__(self, ffi: FakeFfi) -> None:
        super().__init__(None, ffi, LOST_USB)
        self.started: list[tuple[bytes, Promise]] = []
        self.shut = False
        self.is_open = True

    def _start_write(self, packet: bytes) -> Any:
        promise = Promise()
        self.started.append((packet, promise))
        return promise

    async def _shut(self) -> None:
        self.shut = True


@pytest.fixture
def ffi() -> Iterator[FakeFfi]:
    fake = FakeFfi()
    yield fake
    fake.loop.close()


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


def test_writes_go_to_the_browser_one_at_a_time_in_order(ffi: FakeFfi) -> None:
    port = BrowserPort(ffi)
    port.write(b"first")
    port.write(b"second")
    assert [packet for packet, _ in port.started] == [b"first"]
    port.started[0][1].on_ok(None)
    assert [packet for packet, _ in port.started] == [b"first", b"second"]


def test_a_failed_write_ends_the_run_with_the_lost_link_sentence(ffi: FakeFfi) -> None:
    port = BrowserPort(ffi)
    port.write(b"$SM")
    port.started[0][1].on_fail("NetworkError: The device has been lost.")
    with pytest.raises(Interrupted) as raised:
        port.clock.sleep_until(port.clock.now())
    assert raised.value.reason == LOST_USB
    with pytest.raises(SerialException, match="USB connection was lost"):
        port.write(b"more")


def test_closing_waits_for_the_writes_under_way_then_releases_the_port(ffi: FakeFfi) -> None:
    port = BrowserPort(ffi)
    port.write(b"$SM")
    ffi.loop.call_later(0.01, port.started[0][1].on_ok, None)  # the browser takes the stop
    port.close()
    assert port.shut and [packet for packet, _ in port.started] == [b"$SM"]
    assert all(proxy.destroyed for proxy in (port._sent_proxy, port._send_failed_proxy))


def test_a_page_port_outside_a_browser_is_refused_in_one_sentence() -> None:
    with pytest.raises(LinkError, match="exist only in roboscript's browser app"):
        open_port("webserial://1")


class Characteristic:
    """The hub's RX characteristic: the writes the browser was asked to make."""

    def __init__(self) -> None:
        self.writes: list[tuple[bytes, Promise]] = []

    def writeValueWithoutResponse(self, data: bytes) -> Promise:  # noqa: N802 - the browser's name
        promise = Promise()
        self.writes.append((data, promise))
        return promise


def test_a_bluetooth_write_goes_out_in_the_hubs_packets_one_at_a_time(ffi: FakeFfi) -> None:
    port = WebBluetoothPort(None, ffi, device=None)
    rx = Characteristic()
    port._rx = rx
    port.is_open = True
    port.set_max_packet_size(4)  # as the driver does with the hub's InfoResponse
    port.write(b"0123456789")
    while len(rx.writes) < 3:
        rx.writes[-1][1].on_ok(None)
    assert [data for data, _ in rx.writes] == [b"0123", b"4567", b"89"]


def test_a_device_that_takes_nothing_more_does_not_keep_the_port_from_closing(
    ffi: FakeFfi,
) -> None:
    port = BrowserPort(ffi)
    port.write(b"$SM")  # never taken: the promise is never settled
    port.close()
    assert port.shut


class _RefusingSerialPort:
    """A ``SerialPort`` the browser will not open (another program holds it)."""

    async def open(self, options: Any) -> None:
        raise RuntimeError("NetworkError: Failed to open serial port.")


class _Js:
    class Object:
        @staticmethod
        def fromEntries(entries: Any) -> Any:  # noqa: N802 - the browser's name
            return dict(entries)


def test_a_chosen_port_that_will_not_open_is_named_as_the_student_chose_it(
    ffi: FakeFfi, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(webport, "_browser", lambda: (_Js, ffi))
    url = remember_chosen("webserial", _RefusingSerialPort())
    with pytest.raises(LinkError) as raised:
        open_port(url)
    assert str(raised.value) == (
        "cannot reach the robot on the serial port you chose: "
        "NetworkError: Failed to open serial port."
    )


def test_a_page_port_never_chosen_asks_for_connect_without_a_url(
    ffi: FakeFfi, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(webport, "_browser", lambda: (_Js, ffi))
    with pytest.raises(LinkError) as raised:
        open_port("webbluetooth://99")
    assert str(raised.value) == "no robot is connected in this page: press Connect, then run again"


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
