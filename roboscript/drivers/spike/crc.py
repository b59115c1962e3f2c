"""The CRC32 the SPIKE Prime hub uses for file uploads.

It is the ordinary zlib CRC-32, computed over the data zero-padded to a multiple of 4 bytes
(spike-docs ``glossary.rst``). ``TransferChunkRequest`` carries the *running* CRC: the CRC of
each chunk seeded with the CRC of the chunks before it.
"""

from __future__ import annotations

import zlib

__all__ = ["crc32"]


def crc32(data: bytes, seed: int = 0, *, align: int = 4) -> int:
    """Return the hub's CRC32 of ``data``.

    Chaining, ``crc32(b, crc32(a))``, equals ``crc32(a + b)`` when ``len(a)`` is a multiple of
    ``align``, because only the data passed in one call is padded. Send chunks whose sizes are
    multiples of 4 bytes (except the last) to keep the running CRC equal to the file's CRC.

    Args:
        data: The bytes to check.
        seed: The running CRC so far (0 to start), an unsigned 32-bit value.
        align: Pad ``data`` with ``0x00`` to a multiple of this many bytes (at least 1).

    Returns:
        The CRC, an unsigned 32-bit value.

    Raises:
        ValueError: If ``align`` is below 1 or ``seed`` is not an unsigned 32-bit value.
    """
    if align < 1:
        raise ValueError(f"align must be at least 1, not {align}")
    if not 0 <= seed <= 0xFFFFFFFF:
        raise ValueError(f"seed must be an unsigned 32-bit value, not {seed}")
    padding = -len(data) % align
    if padding:
        data = bytes(data) + bytes(padding)
    return zlib.crc32(data, seed) & 0xFFFFFFFF
