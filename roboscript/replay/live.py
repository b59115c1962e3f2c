"""The live view: the replay viewer served on this computer while a mission runs (``--view``).

``roboscript run MISSION --view`` serves one page at ``http://127.0.0.1:PORT/`` (loopback
only: nobody else on the network can see it) and the run as Server-Sent Events at
``/events``: a ``header`` event, a ``frame`` event per tick (only what changed, as in a
recording) and an ``end`` event with the result (:mod:`roboscript.replay.recording`).

Who does what:

* The tick loop, the only code that touches the robot, hands every recording event to
  :meth:`LiveView.publish`. That appends it to a bounded history under a lock held for a few
  dictionary operations and returns: it never touches a socket and never waits for a browser.
* A standard-library HTTP server (:class:`http.server.ThreadingHTTPServer`, daemon threads)
  gives each browser a thread of its own, which collects what it has not sent yet
  :data:`BATCH_S` after the last time and sends it in one write.
* A browser that connects mid-run gets the header, then one full snapshot and the recent
  frames (:data:`HISTORY_FRAMES`), so it can scrub back. A browser that reads too slowly, or
  not at all, falls out of the history: when it reads again it gets a fresh snapshot and the
  recent frames, and the frames it missed are counted as dropped for it. Nobody else waits.

The server holds at most :data:`MAX_CONNECTIONS` connections, each with its own thread. A
connection that has not asked for anything yet (an idle socket, a browser's spare connection)
gives its place to a new one when all are taken, and is closed after :data:`READ_TIMEOUT_S`
anyway; streams keep theirs. A client that resets its connection or goes away is simply gone:
nothing is printed (the terminal shows the run).

Closing the page never stops the robot: the run does not know who is watching. After the run,
:meth:`LiveView.linger` keeps serving until every open page has the end of the run, or
:data:`LINGER_S` seconds if none is open (Ctrl-C ends the wait at once).
"""

from __future__ import annotations

import contextlib
import functools
import json
import logging
import socket
import sys
import threading
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

from roboscript.errors import RoboscriptError
from roboscript.replay.recording import EVENT_KEYS, NESTED_KEYS
from roboscript.replay.viewer import live_viewer, viewer_page

__all__ = [
    "BATCH_S",
    "HISTORY_FRAMES",
    "HOST",
    "LINGER_S",
    "LISTEN_BACKLOG",
    "MAX_CONNECTIONS",
    "READ_TIMEOUT_S",
    "ClientStats",
    "LiveView",
    "LiveViewError",
]

HOST = "127.0.0.1"
"""Where the live view listens: loopback only."""
HISTORY_FRAMES = 3000
"""Recent frames kept for a browser that connects late or falls behind (60 s at 50 Hz)."""
LINGER_S = 10.0
"""After the run, how long the page stays served when no open page has its end yet."""
BATCH_S = 0.05
"""How often a browser's sender collects the new frames: 20 times a second."""
PING_S = 15.0
"""A comment line this often keeps an idle stream (a paused run) from being cut by proxies."""
SEND_TIMEOUT_S = 30.0
"""A browser that accepts nothing this long is disconnected (its thread ends)."""
READ_TIMEOUT_S = 30.0
"""A connection that sends no complete request this long is closed (its thread ends)."""
MAX_CONNECTIONS = 32
"""Most connections served at once (each holds a thread); a browser opens about six."""
LISTEN_BACKLOG = 128
"""Connections the system queues before they are accepted (Python's default is 5)."""

logger = logging.getLogger(__name__)


class LiveViewError(RoboscriptError, OSError):
    """The live view cannot be served (its port is taken, say)."""


@dataclass
class ClientStats:
    """What one browser's stream has carried.

    Attributes:
        frames_sent: Frames written to it.
        frames_dropped: Frames it missed because it read too slowly.
        ended: The end of the run was written to it.
        connected: Its stream is still open.
    """

    frames_sent: int = 0
    frames_dropped: int = 0
    ended: bool = False
    connected: bool = True


def _merge(into: dict[str, Any], delta: Mapping[str, Any]) -> None:
    """Apply one frame's changes to a full snapshot (as the recording's reader does)."""
    for key, value in delta.items():
        if key in EVENT_KEYS:
            continue  # a tone happens on its tick only
        if key in NESTED_KEYS and isinstance(value, Mapping):
            into[key] = {**into.get(key, {}), **value}
        else:
            into[key] = value


def _event(name: str, data: Mapping[str, Any]) -> bytes:
    text = json.dumps(data, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    return f"event: {name}\ndata: {text}\n\n".encode()


class LiveView:
    """Serves the viewer page and one run's events to browsers on this computer.

    Args:
        title: The page's title (the mission's name, say).
        port: The TCP port; 0 picks a free one.
        history_frames: Recent frames kept for browsers that connect late or fall behind.

    Attributes:
        url: The page's address, once :meth:`start` has run.
        frames_published: Frames handed over by the tick loop so far.
    """

    def __init__(self, title: str, *, port: int = 0, history_frames: int = HISTORY_FRAMES) -> None:
        if history_frames < 1:
            raise ValueError("history_frames must be 1 or more")
        self.title = title
        self.port = port
        self.url = ""
        self.frames_published = 0
        self._history: deque[tuple[int, dict[str, Any]]] = deque(maxlen=history_frames)
        self._before_history: dict[str, Any] = {}  # every frame that left the history, merged
        self._header: dict[str, Any] | None = None
        self._end: dict[str, Any] | None = None
        self._closed = False
        self._changed = threading.Condition()
        self._clients: list[ClientStats] = []
        self._server: _Server | None = None
        self._thread: threading.Thread | None = None
        self._page = viewer_page(live_viewer("/events", label=f"live view of {title}"), title)

    # ---------------------------------------------------------------- the tick loop's side

    def publish(self, event: str, data: dict[str, Any]) -> None:
        """Take one recording event (a :data:`~roboscript.replay.recording.Listener`).

        Called in the tick loop: it only stores the event. Frames are picked up by the
        senders every :data:`BATCH_S` (waking a sender on every tick would make it compete
        with the tick loop for the interpreter 50 times a second); the header and the end
        wake them at once.
        """
        with self._changed:
            if event == "frame":
                if len(self._history) == self._history.maxlen:
                    _merge(self._before_history, self._history[0][1])
                self.frames_published += 1
                self._history.append((self.frames_published, data))
                return
            if event == "header":
                self._header = data
            elif event == "end":
                self._end = data
            self._changed.notify_all()

    # ---------------------------------------------------------------------- the server

    def start(self) -> str:
        """Listen on :data:`HOST` and serve in a background thread; return the page's URL.

        Raises:
            LiveViewError: The port cannot be used (taken by another program, say).
        """
        view = self

        class Handler(_Handler):
            live = view

        try:
            server = _Server((HOST, self.port), Handler)
        except OSError as exc:
            raise LiveViewError(
                f"cannot serve the live view on {HOST}:{self.port}: {exc.strerror or exc}"
                " (choose another port with --view-port)"
            ) from None
        self._server = server
        self.port = int(server.server_address[1])
        self.url = f"http://{HOST}:{self.port}/"
        self._thread = threading.Thread(
            target=server.serve_forever, kwargs={"poll_interval": 0.2}, daemon=True
        )
        self._thread.name = "roboscript live view"
        self._thread.start()
        return self.url

    def close(self) -> None:
        """Stop serving: end every stream and close the listening socket."""
        with self._changed:
            self._closed = True
            self._changed.notify_all()
        if self._server is not None:
            self._server.shutdown()
            self._server.server_close()
            self._server = None

    def clients(self) -> list[ClientStats]:
        """A copy of each browser's figures, in the order they connected."""
        with self._changed:
            return [ClientStats(**vars(c)) for c in self._clients]

    def serve_the_end(self, say: Callable[[str], None], *, interrupted: bool = False) -> None:
        """After the run, let the pages show its end, then stop serving.

        Unless the run was interrupted, waits as :meth:`linger` does; Ctrl-C ends the wait.
        When no page is open (nor had the end), it first says where the page stays and for
        how long. An open page is waited for without a word, however long a busy machine takes
        to send it the end. The robot is already stopped.
        """
        try:
            if not interrupted:
                if not self._watched():
                    say(f"the live view stays at {self.url} for {LINGER_S:g} s (Ctrl-C to quit)")
                self.linger(LINGER_S)
        except KeyboardInterrupt:  # the run is over: Ctrl-C only ends the wait
            pass
        finally:
            self.close()

    def _watched(self) -> bool:
        """Whether some page is open now, or had the end of the run."""
        with self._changed:
            return any(c.connected or c.ended for c in self._clients)

    def linger(self, timeout_s: float = LINGER_S) -> bool:
        """After the run: wait until every open page has the run's end, or ``timeout_s``.

        Returns:
            True if some page had the whole end of the run when the wait ended.
        """

        def pages_have_end() -> bool:
            waiting = [c for c in self._clients if c.connected and not c.ended]
            return any(c.ended for c in self._clients) and not waiting

        with self._changed:
            self._changed.wait_for(pages_have_end, timeout=timeout_s)
            return any(c.ended for c in self._clients)

    # --------------------------------------------------------------- one browser's stream

    def _catch_up(
        self, stats: ClientStats, cursor: int, first: bool, joined_late: bool = False
    ) -> tuple[list[dict[str, Any]], int]:
        """The frames after ``cursor`` (call with the lock held).

        A stream that lacks what came before the oldest frame kept (it joined late, or read
        too slowly and fell out of the history) gets that frame as a full snapshot; frames
        it was due but that are no longer kept are counted as dropped. A browser that joined
        mid-run was never due the frames that fell out before its first read (the run went on
        while its thread started): its snapshot covers them, and they are not counted.
        """
        if not self._history or self._history[-1][0] <= cursor:
            return [], cursor
        last = self._history[-1][0]
        oldest = self._history[0][0]
        if cursor >= oldest or (cursor == oldest - 1 and not (first and oldest > 1)):
            return [frame for seq, frame in self._history if seq > cursor], last
        if not (first and joined_late):
            stats.frames_dropped += oldest - 1 - cursor
        snapshot = {k: dict(v) if isinstance(v, dict) else v
                    for k, v in self._before_history.items()}  # fmt: skip
        _merge(snapshot, self._history[0][1])
        snapshot["t"] = self._history[0][1]["t"]
        return [snapshot, *(frame for seq, frame in self._history if seq > oldest)], last

    def _news(self, cursor: int, have_header: bool) -> bool:
        """Whether a stream that has sent up to ``cursor`` has something to do."""
        return (
            self._closed
            or self._end is not None
            or (self._header is not None and not have_header)
            or (bool(self._history) and self._history[-1][0] > cursor)
        )

    def _stream(self, send: Callable[[bytes], object]) -> None:
        """Send this run to one browser until its end, the browser leaves or we close."""
        stats = ClientStats()
        with self._changed:
            self._clients.append(stats)
            # due: the frames still kept, and every frame from now on
            cursor = self._history[0][0] - 1 if self._history else self.frames_published
            joined_late = bool(self._history)
        header: dict[str, Any] | None = None
        first = True
        quiet_s = 0.0
        try:
            send(b"retry: 2000\n\n")
            while True:
                with self._changed:
                    news = functools.partial(self._news, cursor, header is not None)
                    self._changed.wait_for(news, timeout=BATCH_S)
                    if self._closed:
                        return
                    new_header = self._header if header is None else None
                    frames, cursor = self._catch_up(stats, cursor, first, joined_late)
                    first = first and not frames
                    end = self._end
                out = []
                if new_header is not None:
                    header = new_header
                    out.append(_event("header", header))
                encoded = []
                for frame in frames:
                    try:
                        encoded.append(_event("frame", frame))
                    except ValueError:  # not JSON (a NaN slipped through): skip that frame
                        stats.frames_dropped += 1
                out += encoded
                finished = end is not None and not frames
                if finished and end is not None:
                    out.append(_event("end", end))
                quiet_s = 0.0 if out else quiet_s + BATCH_S
                if quiet_s >= PING_S:  # nothing new for a while: keep the stream open
                    out.append(b": ping\n\n")
                    quiet_s = 0.0
                if out:
                    send(b"".join(out))  # one write per batch
                stats.frames_sent += len(encoded)
                if finished:
                    stats.ended = True
                    return
        except OSError:  # the browser left
            return
        finally:
            with self._changed:
                stats.connected = False
                self._changed.notify_all()  # linger() may be waiting for this stream


class _Server(ThreadingHTTPServer):
    """The standard threading server, bounded: at most :data:`MAX_CONNECTIONS` connections,
    a listen backlog of :data:`LISTEN_BACKLOG`, and silence for clients that go away.

    Each connection is *idle* until its request line arrives and again between requests;
    when every place is taken, a new connection takes the place of the longest idle one (so
    sockets that connect and say nothing can never lock a browser out), and if none is idle
    the new one is closed at once.
    """

    daemon_threads = True  # a browser's thread never keeps the program alive
    request_queue_size = LISTEN_BACKLOG

    def __init__(self, address: tuple[str, int], handler: type[_Handler]) -> None:
        super().__init__(address, handler)
        self._lock = threading.Lock()
        self._idle: dict[socket.socket, None] = {}  # insertion order: the oldest first
        self._busy: set[socket.socket] = set()
        self.refused = 0
        self.evicted = 0

    def connections(self) -> int:
        """Connections being served now."""
        with self._lock:
            return len(self._idle) + len(self._busy)

    def process_request(self, request: Any, client_address: Any) -> None:
        """Take the connection if there is a place (freeing an idle one if need be)."""
        with self._lock:
            if len(self._idle) + len(self._busy) >= MAX_CONNECTIONS:
                if not self._idle:
                    self.refused += 1
                    self.shutdown_request(request)
                    return
                oldest = next(iter(self._idle))
                del self._idle[oldest]
                self.evicted += 1
                _hang_up(oldest)  # its thread reads the end of the stream and finishes
            self._idle[request] = None
        super().process_request(request, client_address)

    def process_request_thread(self, request: Any, client_address: Any) -> None:
        try:
            super().process_request_thread(request, client_address)
        finally:
            with self._lock:
                self._idle.pop(request, None)
                self._busy.discard(request)

    def mark(self, request: socket.socket, *, busy: bool) -> bool:
        """Say whether a connection is answering a request; False if it was closed meanwhile."""
        with self._lock:
            if busy:
                if request not in self._idle:
                    return False  # it gave its place to a newer connection
                del self._idle[request]
                self._busy.add(request)
            elif request in self._busy:
                self._busy.discard(request)
                self._idle[request] = None
            return True

    def handle_error(self, request: Any, client_address: Any) -> None:
        """Say nothing: a browser that resets, times out or sends garbage is its own business."""
        logger.debug("live view client %s left: %s", client_address, sys.exc_info()[1])


def _hang_up(connection: socket.socket) -> None:
    with contextlib.suppress(OSError):  # already gone
        connection.shutdown(socket.SHUT_RDWR)


class _Handler(BaseHTTPRequestHandler):
    """``/`` is the page, ``/events`` the stream; nothing else, and only for this computer."""

    live: LiveView
    server: _Server
    protocol_version = "HTTP/1.1"
    timeout = READ_TIMEOUT_S  # for every read, the request line first

    def parse_request(self) -> bool:
        """Read the request's head; from its first line on, the connection is busy."""
        if not self.server.mark(self.request, busy=True):
            self.close_connection = True  # it gave its place to a newer connection
            return False
        return super().parse_request()

    def handle_one_request(self) -> None:
        """Answer one request, then wait idle for the next (a browser keeps connections)."""
        try:
            super().handle_one_request()
        finally:
            self.server.mark(self.request, busy=False)

    def log_message(self, format: str, *args: Any) -> None:
        """Say nothing: the terminal shows the run, not each request."""

    def _allowed(self) -> bool:
        # A page on another site could make the browser ask 127.0.0.1 by a name it controls
        # (DNS rebinding); the Host header shows which name was used.
        port = self.live.port
        return self.headers.get("Host", "") in (f"{HOST}:{port}", f"localhost:{port}")

    def do_GET(self) -> None:
        """Serve the page or the stream."""
        if not self._allowed():
            self._plain(HTTPStatus.FORBIDDEN, "the live view answers only to 127.0.0.1\n")
            return
        path = self.path.split("?", 1)[0]
        if path == "/":
            body = self.live._page.encode()
            self.send_response(HTTPStatus.OK)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)
        elif path == "/events":
            self.close_connection = True
            self.send_response(HTTPStatus.OK)
            self.send_header("Content-Type", "text/event-stream; charset=utf-8")
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.connection.settimeout(SEND_TIMEOUT_S)
            self.live._stream(self.wfile.write)
        else:
            self._plain(HTTPStatus.NOT_FOUND, "not found: the live view is at /\n")

    def _plain(self, status: HTTPStatus, text: str) -> None:
        body = text.encode()
        self.send_response(status)
        self.send_header("Content-Type", "text/plain; charset=utf-8")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)
