"""Benchmarks 1 and 2: how fast roboscript takes in a device's messages, and at what CPU cost.

A device process writes N messages into a loopback TCP socket (and, for ASIP, a raw pty: the
kernel path of a real serial port) as fast as the host takes them. The host reads them the way
a robot's driver does, with :func:`~roboscript.transport.open_port` and
:meth:`Link.poll() <roboscript.transport.Link.poll>` (waiting on the port with ``select``
between polls), and counts the decoded messages.

1. **Ingest rate** ÷ the wire-limited rate of the same messages at 115200 baud, 8N1: how many
   saturated serial lines one host process could keep up with.
2. **Host CPU per message** (``time.process_time``) ÷ that message's wire time at 115200: the
   share of a core a saturated line costs.

The messages are encoded by roboscript's own device-role codecs, so they are exactly what the
simulated boards send. Codec-only rates (bytes already in memory) are reported too.
Run alone: ``python tests/bench/bench_ingest.py [--quick]``.
"""

from __future__ import annotations

import random
import select
import time
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager
from dataclasses import dataclass
from typing import Any

import devices
from benchlib import (
    WIRE_BAUD,
    Row,
    at_least,
    at_most,
    info,
    pinned_to_one_core,
    run_alone,
    wire_time_s,
)

from roboscript.clock import MonotonicClock
from roboscript.codec import Codec, Role, drain
from roboscript.drivers.asip import messages as asip
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.drivers.spike import messages as spike
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.transport import Link, open_port

__all__ = ["CPU_GOAL", "RATE_GOAL", "asip_stream", "measure", "spike_stream"]

RATE_GOAL = 100.0
"""performance.md G3: ingest ≥ 100 × the wire-limited message rate at 115200."""
CPU_GOAL = 0.05
"""performance.md G2: host CPU per message ≤ 0.05 × its wire time at 115200."""

_WAIT_S = 5.0  # no bytes for this long means the device died: fail, do not hang
_CHUNK = 65536


def asip_stream(count: int, seed: int = 8) -> list[bytes]:
    """``count`` ASIP lines: encoder, bump, IR, distance, analog, digital and error lines.

    The mix follows what a MIRTO board streams (mean about 18 bytes a line); values vary so
    line lengths do too.
    """
    rng = random.Random(seed)
    device = AsipCodec(Role.DEVICE)
    shapes: list[Callable[[], object]] = [
        lambda: asip.EncoderEvent(
            ((rng.randint(-9, 9), rng.randint(0, 2000)), (rng.randint(-9, 9), rng.randint(0, 2000)))
        ),
        lambda: asip.BumpEvent((rng.randint(0, 1), rng.randint(0, 1))),
        lambda: asip.IrEvent(tuple(rng.randint(0, 1023) for _ in range(3))),
        lambda: asip.DistanceEvent((rng.randint(2, 400),)),
        lambda: asip.AnalogEvent(tuple((pin, rng.randint(0, 1023)) for pin in range(3))),
        lambda: asip.DigitalPortEvent(rng.randint(0, 2), rng.randint(0, 255)),
        lambda: asip.ErrorReply("M", "R", 2, "UNKNOWN_REQUEST"),
        lambda: asip.EncoderEvent(((rng.randint(-3, 3), 0), (rng.randint(-3, 3), 0))),
    ]
    return [device.send(shapes[index % len(shapes)]()) for index in range(count)]


def spike_stream(count: int, seed: int = 8) -> list[bytes]:
    """``count`` SPIKE frames: nine DeviceNotifications (~80 B) to one small response (4 B).

    Each notification carries what a driving robot reports: battery, IMU, the 5×5 display, two
    motors and a distance sensor.
    """
    rng = random.Random(seed)
    device = SpikeCodec(Role.DEVICE)
    port = spike.HubPort
    medium = spike.MotorDeviceType.MEDIUM_MOTOR

    def notification() -> spike.Message:
        position = rng.randint(-5000, 5000)
        return spike.DeviceNotification(
            (
                spike.DeviceBattery(rng.randint(60, 100)),
                spike.DeviceImu(
                    spike.HubFace.TOP,
                    spike.HubFace.FRONT,
                    *(rng.randint(-180, 179) for _ in range(3)),
                    *(rng.randint(-1000, 1000) for _ in range(6)),
                ),
                spike.DeviceMatrix5x5(tuple(rng.choice((0, 100)) for _ in range(25))),
                spike.DeviceMotor(port(0), medium, rng.randint(-180, 179), 4500, 45, position),
                spike.DeviceMotor(port(1), medium, rng.randint(-180, 179), -4400, -44, -position),
                spike.DeviceDistance(port(2), rng.randint(40, 2000)),
            )
        )

    ok = spike.ResponseStatus(0)
    small = (spike.DeviceNotificationResponse(ok), spike.ProgramFlowResponse(ok))
    frames = []
    for index in range(count):
        message = notification() if index % 10 else small[(index // 10) % 2]
        frames.append(device.send(message))
    return frames


@dataclass(frozen=True)
class Ingest:
    """One measured flood.

    Attributes:
        messages: Messages decoded.
        mean_bytes: Mean wire bytes per message.
        wall_s: From the host's "go" to the last message decoded, seconds.
        cpu_s: Host process CPU over the same interval, seconds.
    """

    messages: int
    mean_bytes: float
    wall_s: float
    cpu_s: float

    @property
    def rate_msgs_s(self) -> float:
        """Messages decoded per second."""
        return self.messages / self.wall_s

    @property
    def wire_rate_msgs_s(self) -> float:
        """The same messages' rate on a saturated 115200 8N1 line."""
        return 1.0 / wire_time_s(self.mean_bytes)

    @property
    def cpu_per_msg_s(self) -> float:
        """Host CPU seconds per message."""
        return self.cpu_s / self.messages


def _flood(
    device: Callable[[bytes], AbstractContextManager[str]],
    frames: list[bytes],
    codec: Codec[Any],
) -> Ingest:
    blob = b"".join(frames)
    count = len(frames)
    with pinned_to_one_core(), device(blob) as url:
        port = open_port(url, baudrate=WIRE_BAUD)
        link = Link(port, codec, clock=MonotonicClock(), name=url)
        received = 0
        try:
            wall = time.perf_counter()
            cpu = time.process_time()
            link.write(b"g")
            while received < count:
                # Wait on the descriptor, as an event loop would: never spin next to the device.
                if not select.select([port], [], [], _WAIT_S)[0]:
                    raise TimeoutError(f"{received} of {count} messages arrived")
                received += len(link.poll())
            cpu = time.process_time() - cpu
            wall = time.perf_counter() - wall
        finally:
            link.close()
    if sum(link.faults.values()):
        raise AssertionError(f"the codec rejected frames it should read: {link.faults}")
    return Ingest(received, len(blob) / count, wall, cpu)


def _codec_only(frames: list[bytes], make_codec: Callable[[], Codec[Any]]) -> Ingest:
    blob = b"".join(frames)
    chunks = [blob[start : start + _CHUNK] for start in range(0, len(blob), _CHUNK)]
    codec = make_codec()
    received = 0
    wall = time.perf_counter()
    cpu = time.process_time()
    for chunk in chunks:
        codec.receive_data(chunk)
        received += sum(1 for _ in drain(codec))
    cpu = time.process_time() - cpu
    wall = time.perf_counter() - wall
    return Ingest(received, len(blob) / len(frames), wall, cpu)


def _rows(label: str, via: str, result: Ingest, *, cpu_row: bool) -> Iterator[Row]:
    detail = (
        f"{result.rate_msgs_s:,.0f} msg/s vs {result.wire_rate_msgs_s:,.0f} msg/s on the wire "
        f"({result.mean_bytes:.1f} B/msg, n={result.messages:,})"
    )
    yield at_least(
        "1", f"{label} ingest via {via} ÷ 115200 wire rate", _ratio(result), RATE_GOAL, detail
    )
    if cpu_row:
        per_msg_us = result.cpu_per_msg_s * 1e6
        wire_us = wire_time_s(result.mean_bytes) * 1e6
        yield at_most(
            "2",
            f"{label} host CPU per message ÷ its wire time ({via})",
            result.cpu_per_msg_s / wire_time_s(result.mean_bytes),
            CPU_GOAL,
            f"{per_msg_us:.2f} µs CPU vs {wire_us:.0f} µs on the wire",
        )


def _ratio(result: Ingest) -> float:
    return result.rate_msgs_s / result.wire_rate_msgs_s


def measure(quick: bool = False) -> list[Row]:
    """Flood each codec through each transport; return rows 1 and 2."""
    asip_count, spike_count = (10_000, 4_000) if quick else (60_000, 20_000)
    asip_lines = asip_stream(asip_count)
    spike_frames = spike_stream(spike_count)

    def asip_host() -> Codec[Any]:
        return AsipCodec(Role.HOST)

    def spike_host() -> Codec[Any]:
        return SpikeCodec(Role.HOST)

    rows: list[Row] = []
    asip_tcp = _flood(devices.flood_socket, asip_lines, asip_host())
    rows += _rows("ASIP lines", "Link/TCP", asip_tcp, cpu_row=True)
    asip_pty = _flood(devices.flood_pty, asip_lines, asip_host())
    rows += _rows("ASIP lines", "Link/pty", asip_pty, cpu_row=True)
    spike_tcp = _flood(devices.flood_socket, spike_frames, spike_host())
    rows += _rows("SPIKE frames", "Link/TCP", spike_tcp, cpu_row=True)
    for label, frames, make in (
        ("ASIP lines", asip_lines, asip_host),
        ("SPIKE frames", spike_frames, spike_host),
    ):
        result = _codec_only(frames, make)
        rows.append(
            info(
                "1",
                f"{label} codec only (in memory) ÷ 115200 wire rate",
                _ratio(result),
                f"{result.rate_msgs_s:,.0f} msg/s, {result.cpu_per_msg_s * 1e6:.2f} µs/msg",
            )
        )
    return rows


if __name__ == "__main__":
    run_alone(__doc__, measure, "fewer messages")
