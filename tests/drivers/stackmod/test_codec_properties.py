"""Property tests for the StackMod codec: chunking, arbitrary bytes, mutated packets."""

from __future__ import annotations

import itertools
from collections import Counter

from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import Codec, Role, drain
from roboscript.drivers.stackmod.codec import ChecksumRule, StackModCodec
from roboscript.drivers.stackmod.messages import (
    ADDRESS_MAX,
    ADDRESS_MIN,
    FORMATS,
    SOURCE_MAX,
    SOURCE_MIN,
    Command,
    DataFormat,
    Get,
    GetReply,
    Message,
    Set,
)
from roboscript.errors import RemoteProtocolError

EXAMPLES = 250
Outcome = list[Message | str]

rules: st.SearchStrategy[ChecksumRule] = st.sampled_from(("seed", "braces_excluded"))
roles = st.sampled_from(list(Role))
addresses = st.integers(ADDRESS_MIN, ADDRESS_MAX)
sources = st.none() | st.integers(SOURCE_MIN, SOURCE_MAX)
commands = st.sampled_from(list(Command))
settable = st.sampled_from([c for c in Command if FORMATS[c].settable])


def values(fmt: DataFormat) -> st.SearchStrategy[int]:
    legal = st.integers(fmt.value_min, fmt.value_max)
    if fmt.special_values:
        return legal | st.sampled_from(sorted(fmt.special_values))
    return legal


@st.composite
def gets(draw: st.DrawFn) -> Get:
    command = draw(commands)
    selector = draw(st.integers(0, FORMATS[command].selector_max))
    return Get(draw(addresses), command, selector, draw(sources))


@st.composite
def sets(draw: st.DrawFn) -> Set:
    command = draw(settable)
    fmt = FORMATS[command]
    selector = draw(st.integers(0, fmt.selector_max))
    return Set(draw(addresses), command, selector, draw(values(fmt)), draw(sources))


@st.composite
def replies(draw: st.DrawFn) -> GetReply:
    command = draw(commands)
    fmt = FORMATS[command]
    selector = draw(st.integers(0, fmt.selector_max))
    return GetReply(draw(addresses), command, selector, draw(values(fmt)))


requests: st.SearchStrategy[Get | Set] = gets() | sets()


def received_by(role: Role) -> st.SearchStrategy[Message]:
    """Messages that a codec of ``role`` accepts."""
    if role is Role.HOST:
        return replies()
    return requests


def sender(role: Role, rule: ChecksumRule) -> StackModCodec:
    """The codec that produces what ``role`` receives."""
    return StackModCodec(Role.DEVICE if role is Role.HOST else Role.HOST, checksum=rule)


def feed(codec: StackModCodec, chunks: list[bytes]) -> Outcome:
    """Feed every chunk, draining after each; check the buffer bound; return what came out."""
    out: Outcome = []
    for chunk in chunks:
        codec.receive_data(chunk)
        typed: Codec[Message] = codec
        for item in drain(typed):
            out.append(item.kind if isinstance(item, RemoteProtocolError) else item)
        assert codec.buffered < codec.max_packet_bytes
    return out


def split(data: bytes, cuts: list[int]) -> list[bytes]:
    points = sorted({min(c, len(data)) for c in cuts})
    bounds = [0, *points, len(data)]
    return [data[a:b] for a, b in itertools.pairwise(bounds)]


# Streams that mix valid packets with noise that is likely to confuse a parser.
noise = st.binary(max_size=12) | st.lists(
    st.sampled_from(list(b"{}?$@XpMTRSV0129+- \x00\xff")), max_size=12
).map(bytes)


@st.composite
def streams(draw: st.DrawFn, role: Role, rule: ChecksumRule) -> bytes:
    parts: list[bytes] = []
    encoder = sender(role, rule)
    for _ in range(draw(st.integers(0, 6))):
        if draw(st.booleans()):
            parts.append(encoder.send(draw(received_by(role))))
        else:
            parts.append(draw(noise))
    return b"".join(parts)


@settings(max_examples=EXAMPLES)
@given(st.data(), roles, rules, st.lists(st.integers(0, 200), max_size=20))
def test_any_chunking_gives_the_same_result(
    data: st.DataObject, role: Role, rule: ChecksumRule, cuts: list[int]
) -> None:
    stream = data.draw(streams(role, rule))
    whole = StackModCodec(role, checksum=rule)
    chunked = StackModCodec(role, checksum=rule)
    assert feed(chunked, split(stream, cuts)) == feed(whole, [stream])
    assert chunked.stats.faults == whole.stats.faults
    assert chunked.stats.dropped_bytes == whole.stats.dropped_bytes
    assert chunked.stats.messages == whole.stats.messages
    assert chunked.buffered == whole.buffered


@settings(max_examples=EXAMPLES)
@given(st.data(), roles, rules, st.lists(st.integers(0, 200), max_size=20))
def test_valid_packets_with_clean_gaps_all_decode(
    data: st.DataObject, role: Role, rule: ChecksumRule, cuts: list[int]
) -> None:
    messages = data.draw(st.lists(received_by(role), max_size=8))
    gaps = data.draw(
        st.lists(st.binary(max_size=5).filter(lambda b: b"{" not in b), min_size=len(messages))
    )
    encoder = sender(role, rule)
    stream = b"".join(gap + encoder.send(m) for gap, m in zip(gaps, messages, strict=False))
    codec = StackModCodec(role, checksum=rule)
    got = feed(codec, split(stream, cuts))
    assert [m for m in got if not isinstance(m, str)] == messages
    assert set(Counter(m for m in got if isinstance(m, str))) <= {"garbage"}
    assert codec.stats.messages == len(messages)
    assert codec.stats.dropped_bytes == sum(len(g) for g in gaps[: len(messages)])
    assert codec.buffered == 0


@settings(max_examples=EXAMPLES)
@given(
    roles,
    rules,
    st.integers(14, 40),
    st.lists(st.binary(max_size=64) | noise, max_size=10),
)
def test_arbitrary_bytes_only_raise_remote_protocol_error(
    role: Role, rule: ChecksumRule, limit: int, chunks: list[bytes]
) -> None:
    codec = StackModCodec(role, checksum=rule, max_packet_bytes=limit)
    got = feed(codec, chunks)  # drain() lets anything but RemoteProtocolError escape
    total = sum(len(c) for c in chunks)
    assert codec.stats.dropped_bytes + codec.buffered <= total
    assert codec.stats.messages == sum(1 for m in got if not isinstance(m, str))
    assert sum(codec.stats.faults.values()) == sum(1 for m in got if isinstance(m, str))


@settings(max_examples=EXAMPLES)
@given(st.data(), roles, rules)
def test_round_trip_any_message(data: st.DataObject, role: Role, rule: ChecksumRule) -> None:
    message = data.draw(received_by(role))
    codec = StackModCodec(role, checksum=rule)
    assert feed(codec, [sender(role, rule).send(message)]) == [message]


@settings(max_examples=EXAMPLES)
@given(st.data(), roles, rules, st.integers(0, 255))
def test_mutated_packet_is_refused_and_counted(
    data: st.DataObject, role: Role, rule: ChecksumRule, replacement: int
) -> None:
    encoder = sender(role, rule)
    original = encoder.send(data.draw(received_by(role)))
    index = data.draw(st.integers(0, len(original) - 1))
    if replacement == original[index]:
        replacement ^= 0x01
    mutated = original[:index] + bytes([replacement]) + original[index + 1 :]
    sentinel = data.draw(received_by(role))
    codec = StackModCodec(role, checksum=rule)
    got = feed(codec, [mutated + encoder.send(sentinel)])
    assert [m for m in got if not isinstance(m, str)] == [sentinel]
    assert got[-1] == sentinel
    assert sum(codec.stats.faults.values()) >= 1
    assert codec.stats.messages == 1
