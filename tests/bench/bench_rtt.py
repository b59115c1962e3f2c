"""Benchmark 3: a driver round trip through roboscript's stack ÷ a raw socket round trip.

Two exchanges, each against one device process that serves every host stack on its own
loopback TCP connection, so the device's share of a trip is the same for all of them:

* **the G1b fixture** (performance.md B.1, where the 1.5× goal was set): the host sends the
  digital write ``I,d,13,1`` and the device echoes each request line as ``@`` + line, which
  roboscript decodes as a typed :class:`~roboscript.drivers.asip.messages.DigitalPortEvent`.
  This is the goal row.
* **the version query** ``#,?``, answered with the board's 29-byte ``@#,?,1,1,...`` line by a
  device that replies with canned bytes: the costliest reply to decode, against the leanest
  device. Reported for information.

The host stacks:

* **raw**: a blocking ``TCP_NODELAY`` socket: ``sendall`` the request bytes, ``recv`` until
  the reply's newline. This is the kernel's floor.
* **raw + codec**: the same socket with :class:`~roboscript.drivers.asip.codec.AsipCodec`
  encoding the request and decoding the reply: what the codec alone costs.
* **roboscript**: ``open_port("socket://...")`` and a :class:`~roboscript.transport.Link`:
  ``Link.send(request)``, then wait on the port's descriptor with ``poll`` and call
  ``Link.poll()`` until the typed reply comes back.

The stacks take turns in blocks, after a warm-up, so a slow moment of the machine hits all
of them. Run alone: ``python tests/bench/bench_rtt.py [--quick]``.
"""

from __future__ import annotations

import select
import socket
import time
import urllib.parse
from typing import NamedTuple

import devices
from benchlib import Row, at_most, info, percentile, pinned_to_one_core, run_alone, wire_time_s

from roboscript.clock import MonotonicClock
from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.transport import Link, open_port

__all__ = ["FIXTURE", "GOAL_RATIO", "VERSION", "Exchange", "measure", "round_trips"]

GOAL_RATIO = 1.5
"""performance.md G1b: driver RTT p50 ≤ 1.5 × a raw socket's RTT in the same run."""

_WAIT_MS = 2000  # a reply later than this means the device died: fail loudly, not hang


class Exchange(NamedTuple):
    """One request and the reply a host waits for."""

    label: str
    request: m.AsipMessage
    reply_type: type
    device_reply: bytes | None  # None: the device echoes "@" + the request line


FIXTURE = Exchange("ASIP I,d,13,1 echo", m.DigitalWrite(13, 1), m.DigitalPortEvent, None)
VERSION = Exchange(
    "ASIP #,? version query",
    m.VersionRequest(),
    m.VersionReply,
    AsipCodec(Role.DEVICE).send(m.VersionReply(1, 1, "ATmega328P", 20, "mirto")),
)


def _raw_round_trips(sock: socket.socket, request: bytes, count: int, samples: list[float]) -> None:
    clock = time.perf_counter
    for _ in range(count):
        start = clock()
        sock.sendall(request)
        data = sock.recv(4096)
        while not data.endswith(b"\n"):
            more = sock.recv(4096)
            if not more:
                raise ConnectionError("the device hung up")
            data += more
        samples.append(clock() - start)


def _raw_codec_round_trips(
    sock: socket.socket, exchange: Exchange, count: int, samples: list[float]
) -> None:
    """The raw socket plus the same codec work as the link: encode, then decode the reply."""
    clock = time.perf_counter
    codec = AsipCodec(Role.HOST)
    request, wanted = exchange.request, exchange.reply_type
    for _ in range(count):
        start = clock()
        sock.sendall(codec.send(request))
        answered = False
        while not answered:
            data = sock.recv(4096)
            if not data:
                raise ConnectionError("the device hung up")
            codec.receive_data(data)
            for message in drain(codec):
                if type(message) is wanted:
                    answered = True
        samples.append(clock() - start)


def _link_round_trips(link: Link, exchange: Exchange, count: int, samples: list[float]) -> None:
    clock = time.perf_counter
    # Block on the descriptor instead of spinning on poll(): a spinning host would starve the
    # device process that shares its core. One poll object, registered once, as a driver
    # waiting on its port would keep it.
    waiter = select.poll()
    waiter.register(link.port.fileno(), select.POLLIN)  # type: ignore[attr-defined]
    request, wanted = exchange.request, exchange.reply_type
    for _ in range(count):
        start = clock()
        link.send(request)
        answered = False
        while not answered:
            if not waiter.poll(_WAIT_MS):
                raise TimeoutError("no reply from the device")
            for message in link.poll():  # as a driver's tick dispatches what arrived
                if type(message) is wanted:
                    answered = True
        samples.append(clock() - start)


def _raw_socket(url: str) -> socket.socket:
    address = urllib.parse.urlsplit(url)
    sock = socket.create_connection((address.hostname or "127.0.0.1", address.port or 0))
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


class Samples(NamedTuple):
    """Round-trip times in seconds, per host stack."""

    raw: list[float]
    codec: list[float]
    link: list[float]


def round_trips(exchange: Exchange, quick: bool = False) -> Samples:
    """Measure one exchange with the three host stacks, taking turns in blocks."""
    blocks, per_block, warm_up = (4, 150, 100) if quick else (10, 250, 300)
    samples = Samples([], [], [])
    raw_request = AsipCodec(Role.HOST).send(exchange.request)
    with pinned_to_one_core(), devices.replying_socket(exchange.device_reply, clients=3) as url:
        raw = _raw_socket(url)
        raw_codec = _raw_socket(url)
        link = Link(open_port(url), AsipCodec(Role.HOST), clock=MonotonicClock(), name=url)
        try:
            for target in (None, samples):  # a warm-up pass, then the measured blocks
                for _ in range(1 if target is None else blocks):
                    count = warm_up if target is None else per_block
                    _raw_round_trips(raw, raw_request, count, [] if target is None else target.raw)
                    _raw_codec_round_trips(
                        raw_codec, exchange, count, [] if target is None else target.codec
                    )
                    _link_round_trips(link, exchange, count, [] if target is None else target.link)
        finally:
            raw.close()
            raw_codec.close()
            link.close()
    return samples


def measure(quick: bool = False) -> list[Row]:
    """The goal row for the G1b fixture, and the information rows."""
    rows = []
    for exchange in (FIXTURE, VERSION):
        samples = round_trips(exchange, quick)
        raw_p50 = percentile(samples.raw, 0.5) * 1e6
        codec_p50 = percentile(samples.codec, 0.5) * 1e6
        link_p50 = percentile(samples.link, 0.5) * 1e6
        raw_p99 = percentile(samples.raw, 0.99) * 1e6
        link_p99 = percentile(samples.link, 0.99) * 1e6
        name = f"{exchange.label} round trip p50: Link ÷ raw TCP socket"
        detail = (
            f"Link {link_p50:.1f} µs, raw {raw_p50:.1f} µs, n={len(samples.link)} each; "
            f"codec {codec_p50 - raw_p50:.1f} µs, port and link {link_p50 - codec_p50:.1f} µs"
        )
        if exchange is FIXTURE:
            rows.append(at_most("3", name, link_p50 / raw_p50, GOAL_RATIO, detail))
        else:
            rows.append(info("3", name, link_p50 / raw_p50, detail))
        rows.append(
            info(
                "3",
                f"{exchange.label} round trip p99: Link ÷ raw TCP socket",
                link_p99 / raw_p99,
                f"Link {link_p99:.1f} µs, raw {raw_p99:.1f} µs",
            )
        )
        if exchange is FIXTURE:
            request_bytes = len(AsipCodec(Role.HOST).send(exchange.request))
            wire_us = wire_time_s(2 * request_bytes + 1) * 1e6  # the reply is "@" + request
            rows.append(
                info(
                    "3",
                    f"{exchange.label} round trip p50 ÷ its wire time at 115200",
                    link_p50 / wire_us,
                    f"{link_p50:.1f} µs vs {wire_us:.0f} µs for {2 * request_bytes + 1} B",
                )
            )
    return rows


if __name__ == "__main__":
    run_alone(__doc__, measure, "fewer round trips")
