"""Tests of the SPIKE Prime framing (COBS variant, XOR 0x03, delimiters) and its CRC32."""

from __future__ import annotations

import zlib

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.drivers.spike import cobs
from roboscript.drivers.spike.crc import crc32
from roboscript.errors import RemoteProtocolError

# (message bytes, frame bytes): the golden frames of the protocol facts.
GOLDEN_FRAMES = [
    pytest.param(b"\x00", b"\x00\x00\x02", id="InfoRequest"),
    pytest.param(b"\x18", b"\x07\x1b\x02", id="GetHubNameRequest"),
    pytest.param(b"\x28\x64\x00", b"\x06\x2b\x67\x00\x02", id="DeviceNotificationRequest(100)"),
    pytest.param(b"\x1e\x00\x00", b"\x07\x1d\x00\x00\x02", id="ProgramFlowRequest(start,0)"),
]

A84 = b"A" * 84

# (data, COBS encoding before the XOR), worked out by hand from the code word rule
# code = block_size + 2 + delimiter * 84 (block_size counts the code word), 0xFF = full block.
ENCODINGS = [
    pytest.param(b"", b"\x03", id="empty"),
    pytest.param(b"\x00", b"\x03\x03", id="nul"),
    pytest.param(b"\x01", bytes([87, 3]), id="one"),
    pytest.param(b"\x02", bytes([171, 3]), id="two"),
    pytest.param(b"\x03", b"\x04\x03", id="three-is-data"),
    pytest.param(b"\x05\x00", b"\x04\x05\x03", id="data-then-nul"),
    pytest.param(b"\x05\x01\x06", bytes([88, 5, 4, 6]), id="data-one-data"),
    pytest.param(b"\x00\x01\x02", bytes([3, 87, 171, 3]), id="three-delimiters"),
    pytest.param(A84, b"\xff" + A84 + b"\x03", id="full-block"),
    pytest.param(A84[:83] + b"\x02", bytes([254]) + A84[:83] + b"\x03", id="longest-escaped"),
    pytest.param(A84 + b"A", b"\xff" + A84 + b"\x04A", id="full-block-plus-one"),
    pytest.param(A84 + b"\x00", b"\xff" + A84 + b"\x03\x03", id="full-block-then-nul"),
    pytest.param(A84 * 2, b"\xff" + A84 + b"\xff" + A84 + b"\x03", id="two-full-blocks"),
]

# Biased towards the escaped values and the values next to them.
ANY_BYTES = st.one_of(
    st.integers(0, 600).flatmap(lambda n: st.binary(min_size=n, max_size=n)),
    st.lists(
        st.one_of(st.sampled_from([0, 1, 2, 3, 0xFE, 0xFF]), st.integers(0, 255)), max_size=600
    ).map(bytes),
)


@pytest.mark.parametrize(("data", "frame"), GOLDEN_FRAMES)
def test_golden_frames_pack(data: bytes, frame: bytes) -> None:
    assert cobs.pack(data) == frame


@pytest.mark.parametrize(("data", "frame"), GOLDEN_FRAMES)
def test_golden_frames_unpack(data: bytes, frame: bytes) -> None:
    assert cobs.unpack(frame) == data
    assert cobs.unpack(b"\x01" + frame) == data


def test_high_priority_prefix() -> None:
    assert cobs.pack(b"\x00", high_priority=True) == b"\x01\x00\x00\x02"
    assert cobs.pack(b"\x18", high_priority=True) == b"\x01\x07\x1b\x02"


@pytest.mark.parametrize(("data", "encoded"), ENCODINGS)
def test_encode_vectors(data: bytes, encoded: bytes) -> None:
    assert cobs.encode(data) == encoded
    assert cobs.decode(encoded) == data


@pytest.mark.parametrize(("data", "encoded"), ENCODINGS)
def test_escape_is_xor_3(data: bytes, encoded: bytes) -> None:
    assert cobs.escape(data) == bytes(b ^ 3 for b in encoded)
    assert cobs.pack(data) == bytes(b ^ 3 for b in encoded) + b"\x02"


@pytest.mark.parametrize(
    "frame",
    [
        pytest.param(b"", id="nothing"),
        pytest.param(b"\x02", id="empty-body"),
        pytest.param(b"\x01\x02", id="empty-high-priority-body"),
        pytest.param(b"\x00\x00", id="no-end-delimiter"),
        pytest.param(b"\x03\x02", id="code-word-zero"),
        pytest.param(b"\x00\x03\x02", id="xor-3-byte-inside"),
        pytest.param(b"\x00\x02\x00\x02", id="delimiter-inside"),
        pytest.param(bytes([5 ^ 3, 9 ^ 3]) + b"\x02", id="block-cut-short"),
        pytest.param(bytes([87 ^ 3]) + b"\x02", id="ends-with-delimiter-one"),
        pytest.param(bytes([171 ^ 3]) + b"\x02", id="ends-with-delimiter-two"),
        pytest.param(bytes(b ^ 3 for b in b"\xff" + A84) + b"\x02", id="ends-with-full-block"),
    ],
)
def test_bad_frames(frame: bytes) -> None:
    with pytest.raises(RemoteProtocolError) as info:
        cobs.unpack(frame)
    assert info.value.kind == "bad_cobs"


@settings(max_examples=300, deadline=None)
@given(ANY_BYTES, st.booleans())
def test_pack_unpack_round_trip(data: bytes, high_priority: bool) -> None:
    frame = cobs.pack(data, high_priority=high_priority)
    assert cobs.unpack(frame) == data
    body = frame[1:-1] if high_priority else frame[:-1]
    assert frame.endswith(b"\x02")
    assert frame.startswith(b"\x01") == high_priority
    # The body never holds a delimiter or Ctrl-C.
    assert not set(body) & {0x01, 0x02, 0x03}
    # One code word per escaped value (replacing it), per full block, plus the final one.
    assert len(body) <= len(data) + 1 + len(data) // 84


@settings(max_examples=300, deadline=None)
@given(ANY_BYTES)
def test_decode_accepts_only_canonical_bodies(body: bytes) -> None:
    try:
        data = cobs.unescape(body)
    except RemoteProtocolError as exc:
        assert exc.kind == "bad_cobs"
    else:
        assert cobs.escape(data) == body


# ---------------------------------------------------------------------------- CRC32


def test_crc32_examples() -> None:
    assert crc32(b"") == 0
    assert crc32(b"1234") == 0x9BE3E0A3 == zlib.crc32(b"1234")
    assert crc32(b"abc") == 0xA75D6850 == zlib.crc32(b"abc\x00")
    assert crc32(b"123456789") == 0x77D55834 == zlib.crc32(b"123456789\x00\x00\x00")
    assert crc32(b"12345") == zlib.crc32(b"12345\x00\x00\x00")


def test_crc32_running_seed() -> None:
    assert crc32(b"5678", crc32(b"1234")) == crc32(b"12345678")
    assert crc32(b"xyz", crc32(b"abcd")) == zlib.crc32(b"abcdxyz\x00")
    # Only the data of one call is padded.
    assert crc32(b"d", crc32(b"abc")) == zlib.crc32(b"abc\x00d\x00\x00\x00")


def test_crc32_align() -> None:
    assert crc32(b"abc", align=1) == zlib.crc32(b"abc")
    assert crc32(b"abc", align=8) == zlib.crc32(b"abc" + bytes(5))


@pytest.mark.parametrize(("seed", "align"), [(-1, 4), (1 << 32, 4), (0, 0)])
def test_crc32_rejects_bad_arguments(seed: int, align: int) -> None:
    with pytest.raises(ValueError):
        crc32(b"abc", seed, align=align)


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=300), st.integers(1, 40))
def test_crc32_chunked_matches_whole(data: bytes, words_per_chunk: int) -> None:
    chunk = 4 * words_per_chunk
    running = 0
    for start in range(0, len(data), chunk):
        running = crc32(data[start : start + chunk], running)
    assert running == crc32(data) == zlib.crc32(data + bytes(-len(data) % 4))
