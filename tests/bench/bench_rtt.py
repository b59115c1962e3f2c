"""Benchmark 3: a driver round trip through roboscript's stack ÷ a raw socket round trip.

The request is ASIP's version query ``#,?`` and the reply the board's ``@#,?,1,1,...`` line.
One device process answers every request line on two loopback TCP connections:

* **raw**: a blocking ``TCP_NODELAY`` socket: ``sendall`` the request bytes, ``recv`` until
  the reply's newline. This is the kernel's floor.
* **roboscript**: ``open_port("socket://...")`` and a :class:`~roboscript.transport.Link`
  with the host :class:`~roboscript.drivers.asip.codec.AsipCodec`: ``Link.send(VersionRequest())``,
  then wait on the port's file descriptor with ``select`` and ``Link.poll()`` until a
  decoded :class:`~roboscript.drivers.asip.messages.VersionReply` comes back.

The two stacks take turns in blocks, after a warm-up, so a slow moment of the machine hits
both. Run alone: ``python tests/bench/bench_rtt.py [--quick]``.
"""

from __future__ import annotations

import argparse
import select
import socket
import time
import urllib.parse

import devices
from benchlib import Row, at_most, info, percentile, pinned_to_one_core, wire_time_s

from roboscript.clock import MonotonicClock
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.drivers.codec import Role, drain
from roboscript.transport import Link, open_port

__all__ = ["GOAL_RATIO", "measure"]

GOAL_RATIO = 1.5
"""performance.md G1b: driver RTT ≤ 1.5 × a raw socket's RTT in the same run."""

_REQUEST = AsipCodec(Role.HOST).send(m.VersionRequest())
_REPLY = AsipCodec(Role.DEVICE).send(m.VersionReply(1, 1, "ATmega328P", 20, "mirto"))
_WAIT_S = 2.0  # a reply later than this means the device died: fail loudly, not hang


def _raw_round_trips(sock: socket.socket, count: int, samples: list[float]) -> None:
    clock = time.perf_counter
    for _ in range(count):
        start = clock()
        sock.sendall(_REQUEST)
        data = sock.recv(4096)
        while not data.endswith(b"\n"):
            more = sock.recv(4096)
            if not more:
                raise ConnectionError("the device hung up")
            data += more
        samples.append(clock() - start)


def _raw_codec_round_trips(
    sock: socket.socket, codec: AsipCodec, count: int, samples: list[float]
) -> None:
    """The raw socket plus the same codec work as the link: encode, then decode the reply."""
    clock = time.perf_counter
    request = m.VersionRequest()
    for _ in range(count):
        start = clock()
        sock.sendall(codec.send(request))
        answered = False
        while not answered:
            data = sock.recv(4096)
            if not data:
                raise ConnectionError("the device hung up")
            codec.receive_data(data)
            answered = any(type(message) is m.VersionReply for message in drain(codec))
        samples.append(clock() - start)


def _link_round_trips(link: Link, count: int, samples: list[float]) -> None:
    clock = time.perf_counter
    port = link.port
    request = m.VersionRequest()
    for _ in range(count):
        start = clock()
        link.send(request)
        answered = False
        while not answered:
            # Block on the descriptor instead of spinning on poll(): a spinning host would
            # starve the device process that shares its core.
            if not select.select([port], [], [], _WAIT_S)[0]:
                raise TimeoutError("no reply from the device")
            answered = any(type(message) is m.VersionReply for message in link.poll())
        samples.append(clock() - start)


def _raw_socket(url: str) -> socket.socket:
    address = urllib.parse.urlsplit(url)
    sock = socket.create_connection((address.hostname or "127.0.0.1", address.port or 0))
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def measure(quick: bool = False) -> list[Row]:
    """Run the round trips and return the p50 and p99 ratio rows."""
    blocks, per_block, warm_up = (4, 150, 100) if quick else (10, 250, 300)
    raw_samples: list[float] = []
    codec_samples: list[float] = []
    link_samples: list[float] = []
    with pinned_to_one_core(), devices.replying_socket(_REPLY, clients=3) as url:
        raw = _raw_socket(url)
        raw_codec = _raw_socket(url)
        codec = AsipCodec(Role.HOST)
        link = Link(open_port(url), AsipCodec(Role.HOST), clock=MonotonicClock(), name=url)
        try:
            _raw_round_trips(raw, warm_up, [])
            _raw_codec_round_trips(raw_codec, codec, warm_up, [])
            _link_round_trips(link, warm_up, [])
            for _ in range(blocks):  # take turns, so a slow moment of the machine hits all
                _raw_round_trips(raw, per_block, raw_samples)
                _raw_codec_round_trips(raw_codec, codec, per_block, codec_samples)
                _link_round_trips(link, per_block, link_samples)
        finally:
            raw.close()
            raw_codec.close()
            link.close()
    rows = []
    wire_us = wire_time_s(len(_REQUEST) + len(_REPLY)) * 1e6
    for label, fraction in (("p50", 0.50), ("p99", 0.99)):
        raw_us = percentile(raw_samples, fraction) * 1e6
        link_us = percentile(link_samples, fraction) * 1e6
        rows.append(
            at_most(
                "3",
                f"ASIP #,? round trip {label}: Link ÷ raw TCP socket",
                link_us / raw_us,
                GOAL_RATIO,
                f"Link {link_us:.1f} µs, raw {raw_us:.1f} µs, n={len(link_samples)} each",
            )
        )
    link_p50 = percentile(link_samples, 0.5) * 1e6
    codec_p50 = percentile(codec_samples, 0.5) * 1e6
    raw_p50 = percentile(raw_samples, 0.5) * 1e6
    rows.append(
        info(
            "3",
            "ASIP #,? round trip p50: Link ÷ raw socket + the same codec",
            link_p50 / codec_p50,
            f"raw socket + AsipCodec {codec_p50:.1f} µs: decoding costs "
            f"{codec_p50 - raw_p50:.1f} µs, port and link {link_p50 - codec_p50:.1f} µs",
        )
    )
    rows.append(
        info(
            "3",
            "ASIP #,? round trip p50 ÷ its wire time at 115200",
            link_p50 / wire_us,
            f"{link_p50:.1f} µs vs {wire_us:.0f} µs for {len(_REQUEST) + len(_REPLY)} B",
        )
    )
    return rows


def main() -> None:
    """Print this benchmark's rows."""
    from benchlib import format_table

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer round trips")
    args = parser.parse_args()
    print(format_table(measure(args.quick)))


if __name__ == "__main__":
    main()
