"""ASIP line framing: bytes into text lines, bounded, with every drop counted.

``LineFramer`` is tested with a decoder that records the lines it is given, so these tests see
the framing alone; the codec tests see it with the host's real decoder.
"""

from __future__ import annotations

import itertools

from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import CodecStats, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.framing import LineFramer, format_body, format_pairs
from roboscript.drivers.asip.value_ranges import OutOfRangeError
from roboscript.errors import RemoteProtocolError

EXAMPLES = 300
FAULT_KINDS = {"overlong", "garbage", "malformed", "out_of_range"}


class Recorder:
    """A line decoder that keeps each line as a DebugLine; ``!bad`` and ``!big`` it refuses."""

    def __call__(self, text: str) -> m.AsipMessage:
        if text == "!bad":
            raise ValueError("not a line")
        if text == "!big":
            raise OutOfRangeError("a value outside 0..1")
        return m.DebugLine(text)


def framer(max_line_bytes: int = 16) -> LineFramer:
    return LineFramer(CodecStats(), max_line_bytes, Recorder())


def run(framing: LineFramer, *chunks: bytes) -> list[object]:
    out: list[object] = []
    for chunk in chunks:
        framing.receive_data(chunk)
        out += [
            item.kind if isinstance(item, RemoteProtocolError) else item.text  # type: ignore[union-attr]
            for item in drain(framing)
        ]
    return out


def test_lines_end_at_newline_with_or_without_cr_and_blank_lines_are_skipped() -> None:
    framing = framer()
    assert run(framing, b"one\r\n\r\n  \ntw", b"o\n") == ["one", "two"]
    assert framing.stats.messages == 2
    assert not framing.stats.faults
    assert framing.pending_bytes() == 0


def test_a_line_waits_for_its_newline() -> None:
    framing = framer()
    assert run(framing, b"abc") == []
    assert framing.pending_bytes() == 3
    assert run(framing, b"\n") == ["abc"]


def test_a_line_at_the_limit_is_kept_and_one_byte_more_is_overlong() -> None:
    framing = framer(max_line_bytes=8)
    assert run(framing, b"12345678\n123456789\nok\n") == ["12345678", "overlong", "ok"]
    assert framing.stats.faults == {"overlong": 1}
    assert framing.stats.dropped_bytes == 10


def test_an_overlong_line_split_across_reads_is_one_fault_and_its_end_is_dropped() -> None:
    framing = framer(max_line_bytes=8)
    assert run(framing, b"123456789", b"abcdef") == ["overlong"]
    assert framing.pending_bytes() == 0  # dropped as it comes, never buffered
    assert run(framing, b"gh\nok\n") == ["ok"]
    assert framing.stats.faults == {"overlong": 1}
    assert framing.stats.dropped_bytes == len(b"123456789abcdefgh\n")
    assert framing.pending_bytes() == 0


def test_a_line_that_is_not_text_is_garbage_with_a_sample() -> None:
    framing = framer(max_line_bytes=200)
    framing.receive_data(b"@I,d,\x00" + b"x" * 100 + b"\nok\n")
    got = list(drain(framing))
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "garbage"
    assert len(got[0].data) == 64
    assert got[1] == m.DebugLine("ok")


def test_tab_and_del_are_text() -> None:
    assert run(framer(), b"a\tb\x7f\n") == ["a\tb\x7f"]


def test_an_error_line_may_echo_any_byte_as_its_service_or_tag() -> None:
    framing = framer()
    assert run(framing, b"~\x80,\x00,1{X}\n") == ["~\x80,\x00,1{X}"]
    assert run(framing, b"~\x80,\x00,1{\x80}\n", b"~\x80\x00,1{X}\n") == ["garbage", "garbage"]


def test_lines_the_decoder_refuses_are_counted_by_kind() -> None:
    framing = framer()
    assert run(framing, b"!bad\n!big\nok\n") == ["malformed", "out_of_range", "ok"]
    assert framing.stats.faults == {"malformed": 1, "out_of_range": 1}
    assert framing.stats.dropped_bytes == 10
    assert framing.stats.messages == 1


def test_body_formats() -> None:
    assert format_body(2, "1,0") == "2,{1,0}"
    assert format_pairs(((4, 255), (0, 0)), hex_second=True) == "4:FF,0:0"
    assert format_pairs(((-3, 10),)) == "-3:10"


# ------------------------------------------------------------------------------------------
# Fuzzing: random bytes, long lines, any chunking

line_bytes = st.binary(max_size=40) | st.sampled_from(
    [b"\n", b"\r\n", b"~", b"~\xff,?,1{X}", b"!bad", b"!big", b"x" * 30, b"\t"]
)


def split(data: bytes, cuts: list[int]) -> list[bytes]:
    points = sorted({min(cut, len(data)) for cut in cuts})
    return [data[a:b] for a, b in itertools.pairwise([0, *points, len(data)])]


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.lists(line_bytes, max_size=16), st.integers(4, 40), st.lists(st.integers(0, 300)))
def test_any_bytes_in_any_chunking_give_the_same_counted_result(
    parts: list[bytes], limit: int, cuts: list[int]
) -> None:
    stream = b"".join(parts)
    whole, chunked = framer(limit), framer(limit)
    expected = run(whole, stream)
    assert run(chunked, *split(stream, cuts)) == expected
    for framing in (whole, chunked):
        faults = [item for item in expected if item in FAULT_KINDS]
        assert sum(framing.stats.faults.values()) == len(faults)
        assert framing.stats.messages == len(expected) - len(faults)
        assert framing.stats.dropped_bytes <= len(stream)
        assert framing.pending_bytes() <= limit
    assert chunked.stats.faults == whole.stats.faults
    assert chunked.stats.dropped_bytes == whole.stats.dropped_bytes


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.integers(2, 64), st.integers(0, 3000), st.integers(1, 700))
def test_a_long_line_never_buffers_more_than_the_limit(limit: int, length: int, chunk: int) -> None:
    framing = framer(limit)
    stream = b"7" * length + b"\nok\n"
    for start in range(0, len(stream), chunk):
        framing.receive_data(stream[start : start + chunk])
        assert framing.pending_bytes() <= limit + chunk
        items = list(drain(framing))
        assert all(isinstance(item, RemoteProtocolError | m.DebugLine) for item in items)
        assert framing.pending_bytes() <= limit
    assert framing.stats.faults == ({"overlong": 1} if length > limit else {})


def test_an_error_whose_tag_is_a_newline_is_one_line_even_split_across_reads() -> None:
    # The board echoes the tag byte it read: "I," then a newline gives "~I,\n,2{...}".
    framing = framer(max_line_bytes=64)
    assert run(framing, b"~I,\n") == []  # its second half is still on its way
    assert run(framing, b",2{UNKNOWN_REQUEST}\nok\n") == ["~I,\n,2{UNKNOWN_REQUEST}", "ok"]
    assert framing.pending_bytes() == 0


def test_a_short_tilde_line_without_an_error_number_after_it_stays_its_own_line() -> None:
    framing = framer(max_line_bytes=64)
    assert run(framing, b"~I,\n@M,e\n") == ["~I,", "@M,e"]
