"""A scriptable fake ASIP board on a loopback TCP port, for fault tests.

It greets like the firmware, answers the handshake, streams encoder events every 33 ms once
asked, and can be told to misbehave: close the connection, fall silent, mix garbage into its
output, or refuse tones.
"""

from __future__ import annotations

import contextlib
import random
import socket
import threading
import time


class FakeAsipBoard:
    """A fake board serving one client on ``127.0.0.1:port``.

    Args:
        close_after_s: Close the connection this long after the client connects.
        silent_after_s: Stop sending anything this long after the client connects.
        garbage: Mix random bytes, non-ASCII and over-long lines into the output.
        refuse_tones: Answer ``T,P`` with ``~T,P,2{UNKNOWN_REQUEST}``.
    """

    def __init__(
        self,
        *,
        close_after_s: float | None = None,
        silent_after_s: float | None = None,
        garbage: bool = False,
        refuse_tones: bool = False,
    ) -> None:
        self.close_after_s = close_after_s
        self.silent_after_s = silent_after_s
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
        handled = 0
        with conn:
            self._send(conn, b"!fake running on ATmega328P with Services: I M B R D T L \n")
            while not self._stop.is_set():
                now = time.monotonic() - start
                if self.close_after_s is not None and now >= self.close_after_s:
                    return
                try:
                    data = conn.recv(4096)
                    if not data:
                        return
                    self.received += data
                except TimeoutError:
                    pass
                except OSError:
                    return
                if self.silent_after_s is not None and now >= self.silent_after_s:
                    continue
                text = self.received.decode("latin-1")
                for request in text[handled:].split("\n")[:-1]:
                    handled += len(request) + 1
                    if request.startswith("#,?"):
                        self._send(conn, b"@#,?,1,1,ATmega328P,20,fake\n")
                    elif request.startswith("#,N"):
                        self._send(
                            conn,
                            b"@#,N,7,{I:ASIP core IO,M:Motors,B:Bump Sensors,R:IR Sensors,"
                            b"D:Distance,T:Tone,L:LCD}\n",
                        )
                    elif request.startswith("M,A,1"):
                        encoders = True
                    elif request.startswith("T,P") and self.refuse_tones:
                        self._send(conn, b"~T,P,2{UNKNOWN_REQUEST}\n")
                if encoders and time.monotonic() >= next_event:
                    next_event += 0.033
                    self._send(conn, b"@M,e,2,{0:0,0:0}\n")
                    if self.garbage:
                        noise = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 40)))
                        self._send(conn, noise + b"\n\xff\xfe\xfd\n" + b"x" * 700 + b"\n")
