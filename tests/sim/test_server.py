"""``roboscript sim``: the simulated robot served like hardware, on TCP and on a pty."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import serial
from helpers import HANG_BOUND_S, ROOT, served_on_pty, served_simulator

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec


@pytest.fixture
def tcp_sim() -> Iterator[int]:
    with served_simulator("mirto") as port:
        yield port


def _read_until(
    sock: socket.socket, codec: AsipCodec, want: type, limit_s: float = HANG_BOUND_S
) -> object:
    deadline = time.monotonic() + limit_s  # a bound for a hang: a busy machine takes its time
    sock.settimeout(0.2)
    while time.monotonic() < deadline:
        try:
            data = sock.recv(4096)
        except TimeoutError:
            continue
        assert data, "the simulator closed the connection"
        codec.receive_data(data)
        for message in drain(codec):
            if isinstance(message, want):
                return message
    raise AssertionError(f"no {want.__name__} within {limit_s} s")


def test_tcp_client_is_greeted_and_answered(tcp_sim: int) -> None:
    codec = AsipCodec(Role.HOST)
    with socket.create_connection(("127.0.0.1", tcp_sim)) as sock:
        startup = _read_until(sock, codec, m.StartupLine)
        assert isinstance(startup, m.StartupLine) and "M" in startup.services
        sock.sendall(codec.send(m.VersionRequest()))
        version = _read_until(sock, codec, m.VersionReply)
        assert isinstance(version, m.VersionReply) and (version.major, version.minor) == (1, 1)


def test_motors_move_encoders_over_tcp_and_stop_on_disconnect(tcp_sim: int) -> None:
    codec = AsipCodec(Role.HOST)
    with socket.create_connection(("127.0.0.1", tcp_sim)) as sock:
        _read_until(sock, codec, m.StartupLine)
        sock.sendall(codec.send(m.EnableEncoderEvents(True)) + codec.send(m.SetMotorsPower(50, 50)))
        deadline = time.monotonic() + HANG_BOUND_S  # a bound: the loop ends once it is seen
        total = 0
        while time.monotonic() < deadline and total < 500:
            event = _read_until(sock, codec, m.EncoderEvent)
            assert isinstance(event, m.EncoderEvent)
            total = event.totals[0]
        assert total >= 500
    # Reconnect: a new client is greeted again and the wheels were stopped for it.
    codec = AsipCodec(Role.HOST)
    with socket.create_connection(("127.0.0.1", tcp_sim)) as sock:
        _read_until(sock, codec, m.StartupLine)
        sock.sendall(codec.send(m.EnableEncoderEvents(True)))
        first = _read_until(sock, codec, m.EncoderEvent)
        time.sleep(0.3)
        codec = AsipCodec(Role.HOST)
        later = _read_until(sock, codec, m.EncoderEvent)
        assert isinstance(first, m.EncoderEvent) and isinstance(later, m.EncoderEvent)
        assert abs(later.totals[0] - first.totals[0]) < 60  # coasting only, not driving


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a POSIX pty")
def test_pty_path_is_the_first_line_and_speaks_asip() -> None:
    with served_on_pty("mirto") as first:
        assert Path(first).exists(), first
        with serial.Serial(first, 57600, timeout=0.2) as port:
            codec = AsipCodec(Role.HOST)
            port.write(codec.send(m.VersionRequest()))
            deadline = time.monotonic() + HANG_BOUND_S  # a bound: the loop ends once it is seen
            found = None
            while time.monotonic() < deadline and found is None:
                codec.receive_data(port.read(4096))
                found = next((msg for msg in drain(codec) if isinstance(msg, m.VersionReply)), None)
            assert found is not None


def test_bad_tcp_address_is_invalid_input() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "roboscript", "sim", "--tcp", "nowhere"],
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
        cwd=ROOT,
        timeout=HANG_BOUND_S,
        check=False,
    )
    assert result.returncode == 2
    assert "expected HOST:PORT" in result.stderr


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a POSIX pty")
def test_a_pty_board_that_resets_on_connect_is_deaf_until_its_sketch_greets_each_opening() -> None:
    with served_on_pty("mirto", "--reset-on-connect") as path:
        for _ in range(2):  # every opening resets it again
            with serial.Serial(path, 57600, timeout=0.05) as port:
                opened_s = time.monotonic()
                port.write(b"#,?\n")  # lost: the board is still starting
                deadline = opened_s + HANG_BOUND_S  # a bound: the loop ends once it is seen
                heard = b""
                while time.monotonic() < deadline and b"is service P" not in heard:
                    heard += port.read(4096)
                greeted_s = time.monotonic()
                # a lower bound on the wall clock: a busy machine only makes it later
                assert greeted_s - opened_s >= 3.0
                assert heard.startswith(b"!Mirtle2017 running on")
                port.write(b"#,?\n")
                while time.monotonic() < deadline and b"@#,?" not in heard:
                    heard += port.read(4096)
                assert heard.count(b"@#,?") == 1  # the first request was lost, not queued
