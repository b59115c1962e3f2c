"""Framing of the LEGO SPIKE Prime hub protocol: a COBS variant, XOR 0x03 and delimiters.

The hub's framing has three steps (spike-docs ``encoding.rst``):

1. **COBS** that escapes the three values ``0x00``, ``0x01`` and ``0x02``, not only ``0x00``.
   Each block starts with a code word ``block_size + 2 + delimiter * 84``, where ``block_size``
   counts the code word itself (1..84) and ``delimiter`` (0, 1 or 2) is the escaped value that
   follows the block. Code words 3..86 stand for delimiter 0x00, 87..170 for 0x01 and
   171..254 for 0x02. The code word ``0xFF`` is a full block of 84 data bytes with no
   delimiter. The last block's code word is ``block_size + 2``; its implied ``0x00`` is dropped
   when decoding.
2. **XOR 0x03** on every encoded byte, so that ``0x03`` (Ctrl-C) never appears on the wire.
   After the XOR, the encoded bytes never contain ``0x01``, ``0x02`` or ``0x03``.
3. **Delimiters.** A frame always ends with ``0x02`` and may start with ``0x01``, which marks a
   high-priority message.

Example: the one-byte message ``00`` (InfoRequest) is COBS-encoded to ``03 03``, XORed to
``00 00`` and framed as ``00 00 02``.

This module is pure and stateless; the stream state machine (priorities, resynchronisation,
limits) lives in :class:`roboscript.drivers.spike.codec.SpikeCodec`.
"""

from __future__ import annotations

import re
from typing import Final

from roboscript.errors import RemoteProtocolError

__all__ = [
    "DELIMITER",
    "HIGH_PRIORITY",
    "MAX_BLOCK_SIZE",
    "NO_DELIMITER",
    "XOR_MASK",
    "decode",
    "encode",
    "escape",
    "pack",
    "unescape",
    "unpack",
]

DELIMITER: Final = 0x02
"""The byte that ends every frame (and starts or resumes a low-priority message)."""
HIGH_PRIORITY: Final = 0x01
"""The optional first byte of a frame that marks a high-priority message."""
NO_DELIMITER: Final = 0xFF
"""The code word of a full block: 84 data bytes and no escaped value after them."""
MAX_BLOCK_SIZE: Final = 84
"""The largest block, in bytes, counting the code word itself."""
XOR_MASK: Final = 0x03
"""Every encoded byte is XORed with this value."""

_CODE_OFFSET: Final = 2
_FIRST_CODE: Final = 3
_XOR_TABLE: Final = bytes(value ^ XOR_MASK for value in range(256))
_ESCAPED: Final = re.compile(rb"[\x00-\x02]")
# code word -> (data bytes in its block, delimiter after the block or -1 for none)
_BLOCKS: Final = tuple(
    (MAX_BLOCK_SIZE, -1)
    if code == NO_DELIMITER
    else divmod(code - _FIRST_CODE, MAX_BLOCK_SIZE)[::-1]
    if code >= _FIRST_CODE
    else (0, -1)  # never looked up: such bytes are rejected first
    for code in range(256)
)


def _bad(message: str, data: bytes) -> RemoteProtocolError:
    return RemoteProtocolError(message, kind="bad_cobs", data=data)


def encode(data: bytes) -> bytes:
    """COBS-encode ``data`` with the SPIKE variant (no XOR, no delimiters).

    Args:
        data: Any bytes (0 or more).

    Returns:
        The encoded bytes: at least one byte, none of them below ``0x03``. The overhead is one
        code word per escaped value or full block, plus one final code word.
    """
    out = bytearray([NO_DELIMITER])
    code_at = 0
    block = 1  # the block size so far, counting its code word
    for value in data:
        if value <= DELIMITER:
            out[code_at] = block + _CODE_OFFSET + value * MAX_BLOCK_SIZE
            code_at = len(out)
            out.append(NO_DELIMITER)
            block = 1
            continue
        out.append(value)
        block += 1
        if block > MAX_BLOCK_SIZE:
            # A full block keeps the NO_DELIMITER code word written when it began.
            code_at = len(out)
            out.append(NO_DELIMITER)
            block = 1
    out[code_at] = block + _CODE_OFFSET
    return bytes(out)


def decode(encoded: bytes) -> bytes:
    """Decode SPIKE-variant COBS (after the XOR has been undone).

    Only the canonical form that :func:`encode` produces is accepted, so
    ``encode(decode(x)) == x`` whenever ``decode(x)`` succeeds.

    Args:
        encoded: The COBS bytes, without delimiters.

    Returns:
        The decoded data.

    Raises:
        RemoteProtocolError: ``kind="bad_cobs"`` if ``encoded`` is empty, contains a byte below
            ``0x03``, ends inside a block, or ends with a block that is full or implies a
            ``0x01``/``0x02`` delimiter.
    """
    if not encoded:
        raise _bad("empty COBS data", encoded)
    bad = _ESCAPED.search(encoded)
    if bad is not None:
        raise _bad(f"byte 0x{encoded[bad.start()]:02x} inside COBS data", encoded)
    # Each code word after the first takes the place of the previous block's delimiter;
    # after a full block (no delimiter) the next code word is removed instead.
    out = bytearray(encoded)
    size = len(out)
    blocks = _BLOCKS
    count, delimiter = blocks[out[0]]
    index = 1 + count
    removed: list[int] = []
    while index < size:
        code = out[index]
        if delimiter < 0:
            removed.append(index)
        else:
            out[index] = delimiter
        count, delimiter = blocks[code]
        index += 1 + count
    if index > size:
        raise _bad(f"COBS block of {count} bytes cut short", encoded)
    if delimiter != 0:
        raise _bad(f"COBS data ends with code word 0x{encoded[index - 1 - count]:02x}", encoded)
    for position in reversed(removed):
        del out[position]
    del out[0]
    return bytes(out)


def escape(data: bytes) -> bytes:
    """COBS-encode ``data`` and XOR every byte with ``0x03``: a frame body without delimiters.

    Args:
        data: The message bytes (message id first).

    Returns:
        The frame body; it never contains ``0x01``, ``0x02`` or ``0x03``.
    """
    return encode(data).translate(_XOR_TABLE)


def unescape(body: bytes) -> bytes:
    """Undo :func:`escape`: XOR every byte with ``0x03``, then COBS-decode.

    Args:
        body: A frame body, without the ``0x01`` prefix and the ``0x02`` end.

    Returns:
        The message bytes.

    Raises:
        RemoteProtocolError: ``kind="bad_cobs"`` if the body is not valid escaped COBS.
    """
    try:
        return decode(bytes(body).translate(_XOR_TABLE))
    except RemoteProtocolError as exc:
        raise _bad(str(exc), body) from None


def pack(data: bytes, *, high_priority: bool = False) -> bytes:
    """Encode, escape and frame one message.

    Args:
        data: The message bytes (message id first).
        high_priority: Prefix the frame with ``0x01``, marking a high-priority message.

    Returns:
        The complete frame, ending with ``0x02``.
    """
    body = escape(data)
    if high_priority:
        return bytes([HIGH_PRIORITY]) + body + bytes([DELIMITER])
    return body + bytes([DELIMITER])


def unpack(frame: bytes) -> bytes:
    """Deframe, unescape and decode one complete frame.

    Args:
        frame: One frame: an optional ``0x01``, the body, and the final ``0x02``.

    Returns:
        The message bytes.

    Raises:
        RemoteProtocolError: ``kind="bad_cobs"`` if the frame does not end with ``0x02``,
            holds another delimiter, or its body is not valid escaped COBS.
    """
    if not frame or frame[-1] != DELIMITER:
        raise _bad("frame does not end with 0x02", frame)
    start = 1 if frame[0] == HIGH_PRIORITY else 0
    return unescape(frame[start:-1])
