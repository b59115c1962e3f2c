"""Recorded runs and the replay viewer.

:mod:`~roboscript.replay.recording` holds the ``roboscript-run`` format (JSON Lines; see
``docs/reference/recording.md``), :mod:`~roboscript.replay.session_tap` records a mission run as
it goes, and :mod:`~roboscript.replay.viewer` writes the self-contained HTML page that replays
one.
"""

from roboscript.replay.recording import (
    FORMAT,
    VERSION,
    Recorder,
    Recording,
    RecordingError,
    load_recording,
)

__all__ = ["FORMAT", "VERSION", "Recorder", "Recording", "RecordingError", "load_recording"]
