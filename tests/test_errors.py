"""The error tree's shared pieces: fault samples and "did you mean" hints."""

from __future__ import annotations

from roboscript.errors import FAULT_SAMPLE_BYTES, RemoteProtocolError, did_you_mean


def test_a_fault_keeps_only_the_start_of_a_long_bad_frame() -> None:
    frame = bytearray(range(256)) * 40  # a 10 KiB frame of garbage
    fault = RemoteProtocolError("garbage", kind="garbage", data=frame)
    assert fault.data == bytes(frame[:FAULT_SAMPLE_BYTES])
    assert isinstance(fault.data, bytes)


def test_did_you_mean_names_the_closest_choice_or_nothing() -> None:
    assert did_you_mean("drvie", ["drive", "rotate"]) == "did you mean 'drive'?"
    assert did_you_mean("final_pose", ["final_pose_within", "final_state"]) == (
        "did you mean 'final_pose_within'?"
    )
    assert did_you_mean("xyzzy", ["drive", "rotate"]) is None
