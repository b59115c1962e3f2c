"""ASIP line framing: the board's byte stream into text lines, with garbage counted.

The board ends every line with ``\\n`` (sketch ``println`` output with ``\\r\\n``). A line is
ASCII text, printable characters and tab, with one exception: an error line
``~S,T,N{TEXT}`` echoes the service and tag bytes the board received, whatever they were,
a newline among them (``I,`` then a newline is answered ``~I,\\n,2{UNKNOWN_REQUEST}``, which
arrives as ``~I,`` and ``,2{UNKNOWN_REQUEST}``: the framer joins the two).
:class:`LineFramer` cuts reads into lines with ``bytes.split`` (in C), keeps at most
``max_line_bytes`` of an unfinished line, drops an overlong line whole (its end included when
it arrives) and refuses lines that are not text; each drop is counted in the codec's stats and
raised in its place among the lines. It hands each good line to a line decoder and counts the
lines the decoder refuses.

Both directions share the body syntax ``n,{a,b,...}``: :func:`format_body` writes it.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable

from roboscript.codec import CodecStats
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.value_ranges import OutOfRangeError
from roboscript.errors import FAULT_SAMPLE_BYTES, RemoteProtocolError

__all__ = ["LineDecoder", "LineFramer", "format_body", "format_pairs", "line_fault"]

LineDecoder = Callable[[str], m.AsipMessage]
"""Decodes one line of text; raises ``ValueError`` (or ``IndexError``) for a line that does
not parse, :class:`~roboscript.drivers.asip.value_ranges.OutOfRangeError` for a number beyond
its range."""

_TEXT_BYTES = b"\t" + bytes(range(0x20, 0x80))  # printable ASCII and tab: what a line may hold
_COMMA = 0x2C
_TILDE = 0x7E


def line_fault(stats: CodecStats, line: bytes, why: str, kind: str) -> RemoteProtocolError:
    """Count ``line`` (and its newline) as a fault of ``kind``; return the error to raise."""
    stats.fault(kind, len(line) + 1)
    return RemoteProtocolError(f"{why}: {line[:FAULT_SAMPLE_BYTES]!r}", kind=kind, data=line)


def format_body(count: int, items: str) -> str:
    """The body ``count,{items}`` of a request or event."""
    return f"{count},{{{items}}}"


def format_pairs(pairs: Iterable[tuple[int, int]], *, hex_second: bool = False) -> str:
    """``a:b,c:d``, the second numbers in upper-case hex if asked (port masks)."""
    if hex_second:
        return ",".join(f"{a}:{b:X}" for a, b in pairs)
    return ",".join(f"{a}:{b}" for a, b in pairs)


def _is_text(line: bytes) -> bool:
    return line.isascii() and (
        line.decode("ascii").isprintable() or not line.translate(None, _TEXT_BYTES)
    )


def _error_line_with_raw_ids(stats: CodecStats, line: bytes) -> str:
    """``~S,T,...`` whose service or tag byte is not text (the board echoes what it got).

    Raises:
        RemoteProtocolError: Any other line that is not text, counted as ``"garbage"``.
    """
    if line[:1] == b"~" and len(line) > 4 and line[2] == line[4] == _COMMA and _is_text(line[5:]):
        return line.decode("latin-1")
    raise line_fault(stats, line, "not ASCII text", "garbage")


class LineFramer:
    """Cuts the board's byte stream into text lines, bounded by ``max_line_bytes``, and hands
    each to a line decoder.

    Args:
        stats: Where messages and drops are counted.
        max_line_bytes: Longest line kept, line ending excluded; longer ones are dropped as
            ``"overlong"``.
        decode: Turns one line (text, no line ending, not blank) into a message; what it
            refuses is counted as ``"malformed"`` or ``"out_of_range"``.
    """

    def __init__(self, stats: CodecStats, max_line_bytes: int, decode: LineDecoder) -> None:
        self.stats = stats
        self._decode = decode
        self._max_line = max_line_bytes
        # Complete lines, and faults found while framing in their place among them.
        self._lines: deque[bytes | RemoteProtocolError] = deque()
        self._tail = b""  # the start of the line still arriving
        self._skipping_overlong = False

    def receive_data(self, data: bytes) -> None:
        """Add bytes read from the wire."""
        if self._tail:
            data = self._tail + data
        lines = data.split(b"\n")
        tail = lines.pop()
        if lines:
            if self._skipping_overlong:  # the end of a line already dropped as overlong
                self._skipping_overlong = False
                self.stats.dropped_bytes += len(lines[0]) + 1
                del lines[0]
            self._lines.extend(lines)
        if self._skipping_overlong or len(tail) > self._max_line:
            # Never buffer more than a line's worth: drop it, and the rest of it as it comes
            # (still skipping here means no newline came in this read).
            if self._skipping_overlong:
                self.stats.dropped_bytes += len(tail)
            else:
                self._skipping_overlong = True
                self.stats.fault("overlong", len(tail))
                self._lines.append(
                    RemoteProtocolError(f"line longer than {self._max_line} bytes", kind="overlong")
                )
            tail = b""
        self._tail = tail

    def next_message(self) -> m.AsipMessage | None:
        """Decode the next non-blank line; ``None`` if no line is complete.

        Raises:
            RemoteProtocolError: An overlong line or one that is not text (``"overlong"``,
                ``"garbage"``), or one the decoder refuses (``"malformed"``,
                ``"out_of_range"``); already dropped and counted.
        """
        lines = self._lines
        stats = self.stats
        while lines:
            line = lines.popleft()
            if not isinstance(line, bytes):
                raise line  # a fault found while framing, in its place among the lines
            if len(line) > self._max_line:  # a whole line that came in one read
                why = f"line longer than {self._max_line} bytes"
                raise line_fault(stats, line, why, "overlong")
            if len(line) == 3 and line[0] == _TILDE and line[2] == _COMMA:
                # "~S," and ",N{TEXT}": an error whose tag byte was a newline.
                if not lines:
                    lines.appendleft(line)  # its second half is still on its way
                    return None
                rest = lines[0]
                if isinstance(rest, bytes) and rest[:1] == b"," and rest[1:2].isdigit():
                    lines.popleft()
                    line = line + b"\n" + rest
            if line.endswith(b"\r"):
                line = line.rstrip(b"\r")
            if not line or line.isspace():
                continue
            # All in C: isascii() and isprintable() pass a normal line without copying it;
            # only a line with a tab or a control byte pays for translate().
            text = line.decode("latin-1")
            if not line.isascii() or (not text.isprintable() and line.translate(None, _TEXT_BYTES)):
                text = _error_line_with_raw_ids(stats, line)
            try:
                message = self._decode(text)
            except OutOfRangeError as exc:
                raise line_fault(
                    stats, line, f"value out of range ({exc})", "out_of_range"
                ) from None
            except (ValueError, IndexError) as exc:
                raise line_fault(stats, line, f"unreadable line ({exc})", "malformed") from None
            stats.messages += 1
            return message
        return None

    def pending_bytes(self) -> int:
        """Bytes received and not yet returned as lines or dropped."""
        queued = sum(len(line) + 1 for line in self._lines if isinstance(line, bytes))
        return queued + len(self._tail)
