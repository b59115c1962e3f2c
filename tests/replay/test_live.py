"""The live view (``run --view``): a browser watches the run while it goes, never holding it up."""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import struct
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from browser import open_browser
from helpers import HANG_BOUND_S, ROOT

import roboscript.replay.live as live_module
from roboscript.replay.live import HOST, LISTEN_BACKLOG, MAX_CONNECTIONS, LiveView, _Handler
from roboscript.transport.wirelog import read_wire_log

HEADER = {"format": "roboscript-run", "version": 1, "mission": {"name": "m", "states": []}}


def _start_run(*options: str) -> tuple[subprocess.Popen[str], str]:
    """``roboscript run MISSION --view OPTIONS`` in a child process, and its page's URL."""
    process = subprocess.Popen(
        [sys.executable, "-m", "roboscript", "run", *options, "--view"],
        cwd=ROOT,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert process.stderr is not None
    first = process.stderr.readline()
    found = re.fullmatch(
        r"live view: (http://127\.0\.0\.1:\d+/) \(open it in a web browser\)\n", first
    )
    if found is None:
        process.kill()
        pytest.fail(f"no live view URL, got {first!r}: {process.communicate()[1]}")
    return process, found.group(1)


@pytest.fixture
def live() -> Iterator[LiveView]:
    view = LiveView("m", history_frames=50)
    view.start()
    yield view
    view.close()


def _connect(view: LiveView, *, receive_buffer: int | None = None) -> socket.socket:
    """A browser asking for the stream; it reads nothing until the test says so."""
    client = socket.socket()
    if receive_buffer is not None:
        client.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, receive_buffer)
    client.connect((HOST, view.port))
    client.sendall(f"GET /events HTTP/1.1\r\nHost: {HOST}:{view.port}\r\n\r\n".encode())
    return client


def _read_events(client: socket.socket) -> list[tuple[str, Any]]:
    """Read the stream to its ``end`` event; every event as (name, data)."""
    client.settimeout(HANG_BOUND_S)
    data = b""
    while b"event: end\n" not in data or not data.endswith(b"\n\n"):
        chunk = client.recv(1 << 16)
        if not chunk:
            break
        data += chunk
    events = []
    for block in data.split(b"\r\n\r\n", 1)[1].decode().split("\n\n"):
        fields = dict(line.split(": ", 1) for line in block.splitlines() if ": " in line)
        if "event" in fields:
            events.append((fields["event"], json.loads(fields["data"])))
    return events


def _read_frames(stream: Any, count: int) -> None:
    """Read a live stream until ``count`` frames have come."""
    while count:
        line = stream.readline()
        assert line, "the stream ended"
        count -= line.startswith(b"event: frame")


def _wait_until(done: Callable[[], bool]) -> bool:
    """Wait for something another thread does; False only if it never happens (a bound for a
    hang, never a speed limit: a busy machine may take its time)."""
    deadline = time.monotonic() + HANG_BOUND_S
    while not done():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.01)
    return True


def _wait_for_clients(view: LiveView, count: int) -> None:
    # the server thread registers a browser as soon as it asks
    if not _wait_until(lambda: len(view.clients()) >= count):
        pytest.fail("the browser never reached the server")


# ---------------------------------------------------------------------- a real browser


LAPS = """\
mission: laps
initial: side
states:
  side:
    do: {drive: {distance: 20 cm, speed: 15 cm/s}}
    on: {done: corner, failed: stuck}
  corner:
    do: {rotate: {angle: 90 deg}}
    on: {done: side, failed: stuck}
  stuck:
    final: failure
"""
"""A mission that drives laps until it is stopped: it runs as long as the test needs."""


def test_a_browser_watches_the_state_change_while_the_mission_runs(tmp_path: Path) -> None:
    # The browser is started before the run, and the run goes on until the test has seen what
    # it looks for (then Ctrl-C ends it): however long a loaded machine takes to show the
    # page, the page sees the run while it goes. A page joining late is shown where the run
    # is now, so no state is waited for by name.
    laps = tmp_path / "laps.yaml"
    laps.write_text(LAPS, encoding="utf-8")
    with open_browser(tmp_path) as browser:
        process, url = _start_run(str(laps), "--max-time", str(HANG_BOUND_S))
        try:
            browser.open(url)
            state = "document.querySelector('[data-role=state]').textContent"
            now = f"['side', 'corner'].includes({state}) && {state}"
            first = browser.wait_for(now)
            assert process.poll() is None  # watched while the mission still runs
            browser.wait_for(f"{state} !== {first!r} && {now}")  # changed before our eyes
            assert process.poll() is None
            process.send_signal(signal.SIGINT)
            _, stderr = process.communicate(timeout=HANG_BOUND_S)
        finally:
            process.kill()
    assert process.returncode == 130, stderr
    assert stderr.splitlines()[-1] == "error: interrupted by Ctrl-C"


def test_closing_the_page_does_not_stop_the_run() -> None:
    process, url = _start_run("missions/square.yaml", "--max-time", "2", "--json")
    try:
        with urllib.request.urlopen(url + "events", timeout=HANG_BOUND_S) as stream:
            assert stream.readline() == b"retry: 2000\n"
            _read_frames(stream, 1)
        # the page is gone a moment after the start; the mission runs on to its limit
        stdout, stderr = process.communicate(timeout=HANG_BOUND_S)
    finally:
        process.kill()
    summary = json.loads(stdout)
    assert summary["duration_s"] >= 2.0  # its whole limit, from its first tick however late
    assert summary["reason"] == "the mission did not finish within 2 s"
    assert process.returncode == 1, stderr


def test_ctrl_c_stops_the_robot_first(tmp_path: Path) -> None:
    log = tmp_path / "wire.log"
    process, url = _start_run("missions/square.yaml", "--wire-log", str(log))
    try:
        with urllib.request.urlopen(url + "events", timeout=HANG_BOUND_S) as stream:
            _read_frames(stream, 50)  # a second of driving
            process.send_signal(signal.SIGINT)
            _, stderr = process.communicate(timeout=HANG_BOUND_S)
    finally:
        process.kill()
    assert process.returncode == 130, stderr
    assert stderr.splitlines()[-1] == "error: interrupted by Ctrl-C"
    sent = [data for _, direction, data in read_wire_log(log) if direction == ">"]
    assert sent[-2:] == [b"M,S,0\n", b"M,M,0,0\n"]  # mirto's stop, the last bytes sent
    with pytest.raises(OSError):  # and the page is no longer served
        urllib.request.urlopen(url, timeout=5)


# -------------------------------------------------------------------------- the server


def test_the_server_answers_only_on_loopback(live: LiveView) -> None:
    assert live.url == f"http://127.0.0.1:{live.port}/"
    with urllib.request.urlopen(live.url, timeout=HANG_BOUND_S) as page:
        assert b'data-live="/events"' in page.read()
    # bound to 127.0.0.1 itself, not to every address: another loopback address is refused
    with pytest.raises(ConnectionRefusedError):
        socket.create_connection(("127.0.0.2", live.port), timeout=5)
    # a page elsewhere reaching it through a name it controls (DNS rebinding) is refused
    request = urllib.request.Request(live.url, headers={"Host": f"evil.example:{live.port}"})
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(request, timeout=HANG_BOUND_S)
    assert refused.value.code == 403


def test_a_stalled_browser_drops_frames_and_never_holds_up_the_ticks(live: LiveView) -> None:
    stalled = _connect(live, receive_buffer=4096)
    _wait_for_clients(live, 1)
    live.publish("header", HEADER)
    ticks = 5000
    padding = "x" * 2000  # 10 MB in all: far more than the sockets can hold
    for tick in range(ticks):
        frame: dict[str, Any] = {"t": tick / 50, "pad": padding}
        if tick == 0:
            frame["state"] = "side"
        if tick == 3000:
            frame["state"] = "corner"
        live.publish("frame", frame)
    live.publish("end", {"outcome": "success"})
    assert live.frames_published == ticks  # every tick went on, the browser reading nothing
    events = _read_events(stalled)  # the browser reads again
    frames = [data for name, data in events if name == "frame"]
    [stats] = live.clients()
    assert stats.frames_dropped > 0
    assert stats.frames_sent == len(frames)
    assert stats.frames_sent + stats.frames_dropped == ticks
    times = [f["t"] for f in frames]
    assert times == sorted(times) and times[-1] == (ticks - 1) / 50
    # After each run of frames it missed (how many, and where, is up to how the threads
    # were scheduled) it gets a full snapshot: the state set long before is there. Frames
    # it got in turn carry only what changed.
    previous = [-1 / 50, *times[:-1]]  # missing the first frames is a gap too
    gaps = [
        i for i, (t, before) in enumerate(zip(times, previous, strict=True)) if t - before > 0.03
    ]
    assert gaps, "it missed no frame: the test proves nothing"
    for index, frame in enumerate(frames):
        if index in gaps:
            assert frame["state"] == ("corner" if frame["t"] >= 3000 / 50 else "side"), index
        elif frame["t"] not in (0.0, 3000 / 50):
            assert "state" not in frame, index
    assert events[-1] == ("end", {"outcome": "success"})


def test_a_browser_joining_late_gets_the_header_a_snapshot_and_recent_frames(
    live: LiveView,
) -> None:
    live.publish("header", HEADER)
    for tick in range(120):
        live.publish("frame", {"t": tick / 50, **({"state": "side"} if tick == 0 else {})})
    late = _connect(live)
    _wait_for_clients(live, 1)
    live.publish("frame", {"t": 120 / 50, "state": "corner"})
    live.publish("end", {"outcome": "failure"})
    events = _read_events(late)
    assert events[0] == ("header", HEADER)
    frames = [data for name, data in events if name == "frame"]
    # the 50 kept when it joined (ticks 70-119), or those kept when its thread first ran
    first = 70 if len(frames) == 51 else 71
    assert [f["t"] for f in frames] == [tick / 50 for tick in range(first, 121)]
    assert frames[0]["state"] == "side"  # the snapshot carries what changed long before
    assert frames[-1]["state"] == "corner"
    assert live.clients()[0].frames_dropped == 0  # it missed nothing it was ever due


def test_after_the_run_the_server_waits_for_open_pages_then_closes(live: LiveView) -> None:
    page = _connect(live)
    _wait_for_clients(live, 1)
    live.publish("header", HEADER)
    live.publish("frame", {"t": 0.0, "state": "side"})
    live.publish("end", {"outcome": "success"})
    said: list[str] = []
    live.serve_the_end(said.append)  # returns once the page has the end, however late
    assert said == []  # a page is open: it is sent the end, nobody need be told to open one
    assert live.clients()[0].ended
    assert _read_events(page)[-1] == ("end", {"outcome": "success"})
    with pytest.raises(OSError):
        socket.create_connection((HOST, live.port), timeout=5)


def test_after_the_run_with_no_page_open_it_says_where_the_page_stays(
    live: LiveView, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(live_module, "LINGER_S", 0.1)
    live.publish("header", HEADER)
    live.publish("end", {"outcome": "success"})
    said: list[str] = []
    live.serve_the_end(said.append)
    assert said == [f"the live view stays at {live.url} for 0.1 s (Ctrl-C to quit)"]
    with pytest.raises(OSError):
        socket.create_connection((HOST, live.port), timeout=5)


# ---------------------------------------------------------- hostile and careless clients


def _reset(port: int, says: bytes = b"") -> None:
    """A client that connects, maybe starts a request, and resets the connection."""
    client = socket.create_connection((HOST, port), timeout=HANG_BOUND_S)
    if says:
        client.sendall(says)
    client.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    client.close()  # with a zero linger: RST, not FIN


def _settle(view: LiveView, connections: int) -> None:
    """Wait until the server holds at most ``connections`` connections."""
    server = view._server
    assert server is not None
    if not _wait_until(lambda: server.connections() <= connections):
        pytest.fail(f"the server still holds {server.connections()} connections")


def test_clients_that_reset_their_connection_print_nothing(
    live: LiveView, capfd: pytest.CaptureFixture[str]
) -> None:
    for index in range(300):
        _reset(live.port, [b"", b"GET / HT", f"GET / HTTP/1.1\r\nHost: {HOST}".encode()][index % 3])
    _settle(live, 0)
    with urllib.request.urlopen(live.url, timeout=HANG_BOUND_S) as page:  # still answering
        assert page.status == 200
    captured = capfd.readouterr()
    assert captured.err == "" and captured.out == ""


def test_idle_connections_hold_a_bounded_number_of_places_and_never_lock_a_browser_out(
    live: LiveView,
) -> None:
    server = live._server
    assert server is not None
    threads_before = threading.active_count()
    idle = [socket.create_connection((HOST, live.port), timeout=HANG_BOUND_S) for _ in range(300)]
    try:
        with urllib.request.urlopen(live.url, timeout=HANG_BOUND_S) as page:
            assert b'data-live="/events"' in page.read()
        assert server.connections() <= MAX_CONNECTIONS
        assert server.evicted >= 300 - MAX_CONNECTIONS
        # every connection given up ends its thread: the threads come back to the bound
        assert _wait_until(lambda: threading.active_count() <= threads_before + MAX_CONNECTIONS)
        # the oldest idle sockets were hung up on: they read the end of the stream
        assert idle[0].recv(1) == b""
    finally:
        for client in idle:
            client.close()


def test_an_idle_connection_is_closed_after_the_read_timeout(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(_Handler, "timeout", 0.2)
    view = LiveView("m")
    view.start()
    try:
        client = socket.create_connection((HOST, view.port), timeout=HANG_BOUND_S)
        client.sendall(b"GET / HT")  # and nothing more
        assert client.recv(1) == b""  # the server gave up on it and closed
        _settle(view, 0)
    finally:
        view.close()


def test_the_listen_backlog_queues_a_burst_of_connections(live: LiveView) -> None:
    server = live._server
    assert server is not None
    assert server.socket.getsockopt(socket.SOL_SOCKET, socket.SO_ACCEPTCONN) == 1
    assert server.request_queue_size == LISTEN_BACKLOG >= 128


def test_a_run_with_a_live_view_prints_nothing_for_clients_that_reset() -> None:
    process, url = _start_run("missions/square.yaml")
    port = int(url.rsplit(":", 1)[1].strip("/"))
    try:
        for index in range(300):
            _reset(port, b"GET /events HTTP/1.1\r\n" if index % 2 else b"")
        with urllib.request.urlopen(url, timeout=HANG_BOUND_S) as page:
            assert page.status == 200
        process.send_signal(signal.SIGINT)
        _, stderr = process.communicate(timeout=HANG_BOUND_S)
    finally:
        process.kill()
    assert "Traceback" not in stderr and "Exception" not in stderr, stderr
    assert stderr.splitlines()[-1] == "error: interrupted by Ctrl-C"
