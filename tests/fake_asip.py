"""A scriptable fake ASIP board on a loopback TCP port, for fault tests.

It greets like the firmware, reads requests the way the firmware does (the device-role codec:
no newline needed, ``parseInt`` waits ended after a second, unknown services answered
``~X,?,1{INVALID_SERVICE}`` at once), answers the handshake, streams encoder events every
33 ms once asked, and can be told to misbehave: close the connection, fall silent, mix garbage
into its output, or refuse tones.
"""

from __future__ import annotations

import contextlib
import math
import random
import socket
import threading
import time

from roboscript.codec import Role, readable
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec

_SERVICES = "IMBRDTL"


class FakeAsipBoard:
    """A fake board serving one client on ``127.0.0.1:port``.

    Args:
        close_after_s: Close the connection this long after the handshake (when the host
            asks for encoder events, as it does once it has what it asked for).
        silent_after_s: Stop sending anything this long after the handshake.

    Both count from the handshake, not from the connection: a host that a busy machine slows
    down gets through its handshake before the fault, whatever the load.
        answer_after_s: Answer no request until this long after the client connects (a
            board slow to start).
        garbage: Mix random bytes, non-ASCII and over-long lines into the output.
        refuse_tones: Answer ``T,P`` with ``~T,P,2{UNKNOWN_REQUEST}``.
    """

    def __init__(
        self,
        *,
        close_after_s: float | None = None,
        silent_after_s: float | None = None,
        answer_after_s: float = 0.0,
        garbage: bool = False,
        refuse_tones: bool = False,
    ) -> None:
        self.close_after_s = close_after_s
        self.silent_after_s = silent_after_s
        self.answer_after_s = answer_after_s
        self.garbage = garbage
        self.refuse_tones = refuse_tones
        self.received = bytearray()
        self.sent = bytearray()
        self._server = socket.create_server(("127.0.0.1", 0))
        self.port = self._server.getsockname()[1]
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        """The ``socket://`` URL to give ``--port``."""
        return f"socket://127.0.0.1:{self.port}"

    def close(self) -> None:
        """Stop serving."""
        self._stop.set()
        self._server.close()
        self._thread.join(timeout=5)

    def _send(self, conn: socket.socket, data: bytes) -> None:
        conn.sendall(data)  # an OSError (the client hung up) ends _serve quietly
        self.sent += data

    def _serve(self) -> None:
        # The client going away mid-send is what some tests are about.
        with contextlib.suppress(OSError):
            self._serve_one()

    def _serve_one(self) -> None:
        try:
            conn, _ = self._server.accept()
        except OSError:
            return
        rng = random.Random(7)
        start = time.monotonic()
        conn.settimeout(0.01)
        encoders = False
        next_event = start
        requests = AsipCodec(Role.DEVICE, services=_SERVICES)
        last_byte = start
        shaken: float | None = None
        with conn:
            self._send(conn, b"!fake running on ATmega328P with Services: I M B R D T L \n")
            while not self._stop.is_set():
                now = time.monotonic() - shaken if shaken is not None else -math.inf
                if self.close_after_s is not None and now >= self.close_after_s:
                    return
                try:
                    data = conn.recv(4096)
                    if not data:
                        return
                    self.received += data
                    requests.receive_data(data)
                    last_byte = time.monotonic()
                except TimeoutError:
                    pass
                except OSError:
                    return
                if self.silent_after_s is not None and now >= self.silent_after_s:
                    continue
                if time.monotonic() - start < self.answer_after_s:
                    continue
                if requests.waiting and time.monotonic() - last_byte >= 1.0:
                    requests.parse_timeout()  # the firmware's parseInt gives up
                    last_byte = time.monotonic()
                for request in readable(requests):
                    if isinstance(request, m.VersionRequest):
                        self._send(conn, b"@#,?,1,1,ATmega328P,20,fake\n")
                    elif isinstance(request, m.ServiceNamesRequest):
                        self._send(
                            conn,
                            b"@#,N,7,{I:ASIP core IO,M:Motors,B:Bump Sensors,R:IR Sensors,"
                            b"D:Distance,T:Tone,L:LCD}\n",
                        )
                    elif isinstance(request, m.EnableEncoderEvents):
                        encoders = request.enabled
                        if shaken is None:  # the host is through its handshake
                            shaken = time.monotonic()
                    elif isinstance(request, m.PlayTone) and self.refuse_tones:
                        self._send(conn, b"~T,P,2{UNKNOWN_REQUEST}\n")
                    elif isinstance(request, m.InvalidServiceRequest):
                        error = f"~{request.service},?,1{{INVALID_SERVICE}}\n"
                        self._send(conn, error.encode("latin-1"))
                if encoders and time.monotonic() >= next_event:
                    next_event += 0.033
                    self._send(conn, b"@M,e,2,{0:0,0:0}\n")
                    if self.garbage:
                        noise = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 40)))
                        self._send(conn, noise + b"\n\xff\xfe\xfd\n" + b"x" * 700 + b"\n")
