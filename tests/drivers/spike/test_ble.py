"""The BLE port to the SPIKE hub, with a fake bleak client in place of the radio.

The port runs its real background thread and event loop; only the client (``connect``,
``start_notify``, ``write_gatt_char``, ``disconnect``) and the scan are fakes.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from helpers import HANG_BOUND_S
from serial import SerialException

from roboscript.clock import SimClock
from roboscript.codec import Role, drain
from roboscript.drivers.spike import messages as m
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.errors import LinkClosedError, LinkError
from roboscript.transport import Link, open_port
from roboscript.transport.ble import (
    RX_CHARACTERISTIC,
    TX_CHARACTERISTIC,
    BlePort,
    split_packets,
)
from roboscript.transport.urlhandler.protocol_ble import parse_ble_url

ROOT = Path(__file__).parents[3]


class FakeClient:
    """bleak's client, as far as the port uses it; a hub that answers when ``answer`` is set."""

    def __init__(self, device: Any, on_disconnect: Callable[[Any], None]) -> None:
        self.device = device
        self.on_disconnect = on_disconnect
        self.writes: list[tuple[str, bytes, bool]] = []
        self.notify: Callable[[Any, bytearray], None] | None = None
        self.notify_uuid = ""
        self.disconnected = False
        self.answer: Callable[[bytes], list[bytes]] | None = None

    async def connect(self) -> None:
        pass

    async def start_notify(self, uuid: str, callback: Callable[[Any, bytearray], None]) -> None:
        self.notify_uuid = uuid
        self.notify = callback

    async def write_gatt_char(self, uuid: str, data: bytes, response: bool = True) -> None:
        self.writes.append((uuid, bytes(data), response))
        if self.answer is not None and self.notify is not None:
            for packet in self.answer(bytes(data)):
                self.notify(None, bytearray(packet))

    async def disconnect(self) -> None:
        self.disconnected = True


class FakeRadio:
    """Builds fake clients and finds one hub, ``SPIKE-7``."""

    def __init__(self) -> None:
        self.clients: list[FakeClient] = []

    def client(self, device: Any, on_disconnect: Callable[[Any], None]) -> FakeClient:
        client = FakeClient(device, on_disconnect)
        self.clients.append(client)
        return client

    async def find(self, target: str, timeout_s: float) -> Any:
        return {"name": target} if target == "SPIKE-7" else None


@pytest.fixture
def radio() -> FakeRadio:
    return FakeRadio()


@pytest.fixture
def port(radio: FakeRadio) -> Iterator[BlePort]:
    ble = BlePort("SPIKE-7", client_factory=radio.client, find_device=radio.find)
    ble.open()
    yield ble
    ble.close()


def in_loop(port: BlePort, action: Callable[[], None]) -> None:
    """Run ``action`` on the port's BLE thread (where bleak calls back), then wait for it."""
    assert port._loop is not None
    port._loop.call_soon_threadsafe(action)
    port.flush()


def test_split_packets_keeps_every_byte_in_order() -> None:
    assert split_packets(bytes(range(45)), 20) == [
        bytes(range(20)),
        bytes(range(20, 40)),
        bytes(range(40, 45)),
    ]
    assert split_packets(b"", 20) == []
    with pytest.raises(ValueError):
        split_packets(b"x", 0)


def test_opening_finds_the_hub_and_turns_on_notifications(port: BlePort, radio: FakeRadio) -> None:
    (client,) = radio.clients
    assert client.device == {"name": "SPIKE-7"}
    assert client.notify_uuid == TX_CHARACTERISTIC


def test_writes_go_out_in_20_byte_packets_until_the_hub_says_its_size(
    port: BlePort, radio: FakeRadio
) -> None:
    frame = SpikeCodec(Role.HOST).send(m.TunnelMessage(bytes(range(3, 50))))
    assert len(frame) > 40 and len(frame) % 20  # two full packets and a short one
    port.write(frame)
    port.flush()
    (client,) = radio.clients
    assert [len(data) for _, data, _ in client.writes] == [len(p) for p in split_packets(frame, 20)]
    assert all(uuid == RX_CHARACTERISTIC and not response for uuid, _, response in client.writes)
    assert b"".join(data for _, data, _ in client.writes) == frame
    port.set_max_packet_size(64)
    client.writes.clear()
    port.write(frame)
    port.flush()
    assert [len(data) for _, data, _ in client.writes] == [len(frame)]


def test_a_frame_split_across_notifications_is_whole_again(port: BlePort, radio: FakeRadio) -> None:
    device = SpikeCodec(Role.DEVICE)
    frames = device.send(m.ConsoleNotification("hello from the hub, a long line")) + device.send(
        m.ProgramFlowNotification(m.ProgramAction.START)
    )
    (client,) = radio.clients
    assert client.notify is not None
    notify = client.notify
    for packet in split_packets(frames, 7):
        in_loop(port, lambda packet=packet: notify(None, bytearray(packet)))  # type: ignore[misc]
    assert port.in_waiting == len(frames)
    host = SpikeCodec(Role.HOST)
    host.receive_data(port.read(4096))
    assert list(drain(host)) == [
        m.ConsoleNotification("hello from the hub, a long line"),
        m.ProgramFlowNotification(m.ProgramAction.START),
    ]


def test_reads_never_block(port: BlePort) -> None:
    assert port.read(100) == b""


def test_a_link_over_the_port_talks_to_a_hub_answering_in_small_packets(
    port: BlePort, radio: FakeRadio
) -> None:
    (client,) = radio.clients
    hub = SpikeCodec(Role.DEVICE)

    def answer(packet: bytes) -> list[bytes]:
        hub.receive_data(packet)
        out = b"".join(
            hub.send(m.InfoResponse(1, 0, 0, 1, 0, 0, 20, 1024, 512, 0))
            for message in drain(hub)
            if isinstance(message, m.InfoRequest)
        )
        return split_packets(out, 20)

    client.answer = answer
    link = Link(port, SpikeCodec(Role.HOST), clock=SimClock(), name="ble://SPIKE-7")
    link.send(m.InfoRequest())
    port.flush()
    (info,) = link.poll()
    assert isinstance(info, m.InfoResponse) and info.max_chunk_size == 512


def test_a_disconnect_fails_the_next_read_after_the_bytes_already_received(
    port: BlePort, radio: FakeRadio
) -> None:
    (client,) = radio.clients
    assert client.notify is not None
    notify = client.notify

    def drop() -> None:
        notify(None, bytearray(b"\x00\x00\x02"))
        client.on_disconnect(client)

    assert port._loop is not None
    port._loop.call_soon_threadsafe(drop)
    assert port._thread is not None
    port._thread.join(timeout=HANG_BOUND_S)
    link = Link(port, SpikeCodec(Role.DEVICE), clock=SimClock(), name="ble://SPIKE-7")
    assert link.poll() == [m.InfoRequest()]
    with pytest.raises(LinkClosedError):
        link.poll()
    assert client.disconnected
    with pytest.raises(SerialException, match="disconnected"):
        port.write(b"x")


def test_closing_disconnects_and_ends_the_thread(radio: FakeRadio) -> None:
    ble = BlePort("SPIKE-7", client_factory=radio.client, find_device=radio.find)
    ble.open()
    ble.close()
    assert radio.clients[0].disconnected
    assert ble._thread is not None and not ble._thread.is_alive()
    with pytest.raises(SerialException):
        ble.read(1)


def test_a_hub_that_is_not_found_is_named_in_the_error(radio: FakeRadio) -> None:
    ble = BlePort(
        "SPIKE-9", scan_timeout_s=2.0, client_factory=radio.client, find_device=radio.find
    )
    with pytest.raises(SerialException, match="no SPIKE Prime hub called 'SPIKE-9' found"):
        ble.open()
    assert radio.clients == []


def test_without_bleak_opening_says_how_to_install_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "bleak", None)  # makes "import bleak" fail
    with pytest.raises(LinkError) as caught:
        open_port("ble://SPIKE-7")
    assert str(caught.value) == (
        "cannot open ble://SPIKE-7: BLE needs the bleak library: pip install 'roboscript[ble]'"
    )


def test_roboscript_loads_without_bleak() -> None:
    code = (
        "import sys\n"
        "sys.modules['bleak'] = None\n"
        "import roboscript.transport.ble, roboscript.drivers.spike.driver\n"
        "from roboscript.robot import Robot\n"
        "with Robot.connect('spike-prime') as robot:\n"
        "    assert robot.has('drive_base')\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT, timeout=HANG_BOUND_S)


@pytest.mark.parametrize(
    ("url", "expected"),
    [
        ("ble://SPIKE-7", ("SPIKE-7", 10.0)),
        ("ble://My%20Hub?timeout=20", ("My Hub", 20.0)),
        ("ble://A0:E6:F8:1E:58:9C", ("A0:E6:F8:1E:58:9C", 10.0)),
    ],
)
def test_ble_urls_name_the_hub_and_the_scan_time(url: str, expected: tuple[str, float]) -> None:
    assert parse_ble_url(url) == expected


@pytest.mark.parametrize("url", ["ble://", "socket://x:1", "ble://hub?timeout=soon"])
def test_bad_ble_urls_are_refused(url: str) -> None:
    with pytest.raises(ValueError):
        parse_ble_url(url)
