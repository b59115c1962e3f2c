"""``roboscript sim --robot spike-prime --tcp``: a raw client speaking LEGO's framing gets answers.

The client here is not roboscript's driver: it builds each frame with the codec's messages,
sends it on a plain socket and checks the reply, as any tool written against LEGO's protocol
documentation would.
"""

from __future__ import annotations

import json
import socket
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, run_cli, served_simulator

from roboscript.codec import Role, drain
from roboscript.drivers.spike import messages as m
from roboscript.drivers.spike import tunnel as t
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.drivers.spike.crc import crc32

ACK = m.ResponseStatus.ACKNOWLEDGED
NACK = m.ResponseStatus.NOT_ACKNOWLEDGED
PROGRAM = b'AGENT_VERSION = "tcp-test 1"\n' + b"pass\n" * 150  # two chunks


@pytest.fixture
def server_port() -> Iterator[int]:
    with served_simulator("spike-prime") as port:
        yield port


class Client:
    """A plain socket plus a host-role codec."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port))
        self.sock.settimeout(0.2)
        self.codec = SpikeCodec(Role.HOST)
        self.inbox: list[m.Message] = []

    def ask(self, request: m.Message, *want: type[m.Message]) -> list[m.Message]:
        """Send ``request``; return the first message of each wanted type, in order."""
        self.sock.sendall(self.codec.send(request))
        return [self.expect(kind) for kind in want]

    def expect(self, kind: type[m.Message], limit_s: float = HANG_BOUND_S) -> m.Message:
        deadline = time.monotonic() + limit_s  # a bound on a hung server, not a timing check
        while time.monotonic() < deadline:
            for index, message in enumerate(self.inbox):
                if isinstance(message, kind):
                    del self.inbox[: index + 1]
                    return message
            try:
                data = self.sock.recv(4096)
            except TimeoutError:
                continue
            assert data, "the simulator closed the connection"
            self.codec.receive_data(data)
            for item in drain(self.codec):
                assert isinstance(item, m.Message), item
                self.inbox.append(item)
        raise AssertionError(f"no {kind.__name__} within {limit_s} s")


def test_a_raw_client_gets_correct_answers_to_every_request_type(server_port: int) -> None:
    hub = Client(server_port)
    (info,) = hub.ask(m.InfoRequest(), m.InfoResponse)
    assert isinstance(info, m.InfoResponse)
    assert (info.max_packet_size, info.max_chunk_size) == (20, 512)
    assert info.product_group_device is m.ProductGroupDevice.SPIKE_PRIME

    assert hub.ask(m.GetHubNameRequest(), m.GetHubNameResponse) == [
        m.GetHubNameResponse("Simulated SPIKE")
    ]
    assert hub.ask(m.SetHubNameRequest("Lab 3"), m.SetHubNameResponse) == [
        m.SetHubNameResponse(ACK)
    ]
    assert hub.ask(m.GetHubNameRequest(), m.GetHubNameResponse) == [m.GetHubNameResponse("Lab 3")]
    (uuid,) = hub.ask(m.DeviceUuidRequest(), m.DeviceUuidResponse)
    assert isinstance(uuid, m.DeviceUuidResponse) and len(uuid.device_uuid) == 16

    # Upload into slot 2 with a running CRC; a chunk with a wrong one is refused.
    assert hub.ask(m.StartFileUploadRequest("p.py", 2, crc32(PROGRAM)), m.StartFileUploadResponse)[
        0
    ] == m.StartFileUploadResponse(ACK)
    first, rest = PROGRAM[:512], PROGRAM[512:]
    assert hub.ask(m.TransferChunkRequest(12345, first), m.TransferChunkResponse) == [
        m.TransferChunkResponse(NACK)
    ]
    running = crc32(first)
    assert hub.ask(m.TransferChunkRequest(running, first), m.TransferChunkResponse) == [
        m.TransferChunkResponse(ACK)
    ]
    assert hub.ask(m.TransferChunkRequest(crc32(rest, running), rest), m.TransferChunkResponse) == [
        m.TransferChunkResponse(ACK)
    ]

    # Program flow, the agent's console line and a tunnel round trip.
    started = hub.ask(
        m.ProgramFlowRequest(m.ProgramAction.START, 2),
        m.ProgramFlowResponse,
        m.ProgramFlowNotification,
        m.ConsoleNotification,
    )
    assert started == [
        m.ProgramFlowResponse(ACK),
        m.ProgramFlowNotification(m.ProgramAction.START),
        m.ConsoleNotification("tcp-test 1 ready, tunnel from hub.config['module_tunnel']"),
    ]
    (reply,) = hub.ask(m.TunnelMessage(t.VersionQuery().encode()), m.TunnelMessage)
    assert isinstance(reply, m.TunnelMessage)
    assert list(t.decode_records(reply.data, Role.HOST)) == [t.Version("tcp-test 1")]
    assert hub.ask(
        m.ProgramFlowRequest(m.ProgramAction.STOP, 2),
        m.ProgramFlowResponse,
        m.ProgramFlowNotification,
    ) == [m.ProgramFlowResponse(ACK), m.ProgramFlowNotification(m.ProgramAction.STOP)]

    assert hub.ask(m.ClearSlotRequest(2), m.ClearSlotResponse) == [m.ClearSlotResponse(ACK)]
    assert hub.ask(m.ClearSlotRequest(2), m.ClearSlotResponse) == [m.ClearSlotResponse(NACK)]
    assert hub.ask(m.ProgramFlowRequest(m.ProgramAction.START, 2), m.ProgramFlowResponse) == [
        m.ProgramFlowResponse(NACK)
    ]

    # Telemetry.
    response, notification = hub.ask(
        m.DeviceNotificationRequest(100), m.DeviceNotificationResponse, m.DeviceNotification
    )
    assert response == m.DeviceNotificationResponse(ACK)
    assert isinstance(notification, m.DeviceNotification)
    motors = [d.port for d in notification.devices if isinstance(d, m.DeviceMotor)]
    assert motors == [m.HubPort.A, m.HubPort.B, m.HubPort.F]  # drive A, B; the arm motor F

    # Firmware updates are refused by the simulator.
    assert hub.ask(m.StartFirmwareUploadRequest(bytes(20), 0), m.StartFirmwareUploadResponse) == [
        m.StartFirmwareUploadResponse(NACK, 0)
    ]
    assert hub.ask(m.BeginFirmwareUpdateRequest(bytes(20), 0), m.BeginFirmwareUpdateResponse) == [
        m.BeginFirmwareUpdateResponse(NACK)
    ]
    hub.sock.close()


def test_roboscript_drives_the_simulated_hub_over_tcp(server_port: int, tmp_path: Path) -> None:
    mission = tmp_path / "nudge.yaml"
    mission.write_text(
        "mission: nudge\n"
        "initial: go\n"
        "states:\n"
        "  go:\n"
        "    do: {drive: {distance: 5 cm, speed: 10 cm/s}}\n"
        "    on: {done: beep, failed: stuck}\n"
        "  beep:\n"
        "    do: {play_tone: {frequency: 880 Hz, duration: 100 ms}}\n"
        "    on: {done: finished}\n"
        "  stuck: {final: failure}\n"
        "  finished: {final: success}\n",
        encoding="utf-8",
    )
    port = f"socket://127.0.0.1:{server_port}"
    result = run_cli("run", str(mission), "--robot", "spike-prime", "--port", port, "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert (summary["outcome"], summary["final_state"]) == ("success", "finished")
