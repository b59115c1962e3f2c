"""The recorded run: one mission run, tick by tick, in JSON Lines (``roboscript-run``, v1).

A recording is a text file of JSON objects, one per line (``docs/reference/recording.md``)::

    {"format": "roboscript-run", "version": 1, "mission": {...}, "robot": {...}, "world": ...}
    {"t": 0.0, "pose": [0.0, 0.0, 0.0], "state": "drive", "action": "drive", ...}
    {"t": 0.02, "pose": [0.0, 5.1, 0.0], "motors": {"left_mm_s": 200.0}}
    ...
    {"result": {"outcome": "success", "final_state": "done", "duration_s": 4.2, ...}}

* The **header** (first line) names the format and its version, the mission (name, states),
  the robot's geometry (body radius, track, sensor positions and rays), the world (walls, tape
  lines, regions; ``null`` on a real robot), the seed and where poses come from.
* Each **frame** (one per scheduler tick) carries ``t``, seconds on the mission clock, and only
  what changed since the frame before: a missing key keeps its last value, and ``sensors`` and
  ``motors`` list only the entries that changed. ``tone`` is an event: present only on the
  tick a tone started. Poses are ``[x mm east, y mm north, heading deg clockwise from north]``,
  headings from -180 to 180.
* The **result** (last line, ``{"result": {...}}``) says how the run ended.

Versioning: readers accept every version up to :data:`VERSION` and ignore keys they do not
know, so adding a key keeps the version; removing a key or changing a meaning or unit bumps it.

:class:`Recorder` builds a recording while the run goes (the header, then one frame per tick,
each handed to its listeners as it is made, e.g. a live view); :func:`load_recording` reads one
back with the frames filled in.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from roboscript.errors import InputError

__all__ = [
    "FORMAT",
    "MAX_FRAMES",
    "NESTED_KEYS",
    "VERSION",
    "Listener",
    "Recorder",
    "Recording",
    "RecordingError",
    "fill_frames",
    "load_recording",
    "parse_recording",
]

FORMAT = "roboscript-run"
"""The header's ``format`` value."""
VERSION = 1
"""The version this module writes (and the newest it reads)."""
MAX_FRAMES = 200_000
"""Most frames one recording keeps (66 minutes at 50 ticks a second); later ticks are counted
in the result's ``frames_not_recorded``, so a run of hours keeps a bounded size."""
NESTED_KEYS = ("sensors", "motors")
"""Frame keys whose value is an object recorded entry by entry (only changed entries)."""
EVENT_KEYS = ("tone",)
"""Frame keys that happen on one tick and do not carry over to the next."""

_NESTED = frozenset(NESTED_KEYS)
_EVENTS = frozenset(EVENT_KEYS)

Listener = Callable[[str, dict[str, Any]], None]
"""Called with ``("header" | "frame" | "end", dict)`` as a recording grows."""


class RecordingError(InputError):
    """A recording file cannot be read (not JSON Lines, not a roboscript run, newer version)."""


class Recorder:
    """Builds a recording: a header, then frames fed once per tick, then the result.

    Frames go in as full snapshots (:meth:`add`); the recorder keeps (and hands its listeners)
    only what changed since the tick before, so a long run stays small.

    Args:
        header: The header's content (mission, robot, world, ...); ``format`` and ``version``
            are added.
        max_frames: Most frames kept; later ones are counted, not kept.
        format_changes: Turns a frame given to :meth:`add_changes` into its written form
            (rounded, JSON-ready); it runs when the frame is first needed (a listener, the
            :attr:`frames`, the file), not in the tick that recorded it.

    Attributes:
        result: The result once :meth:`finish` was called, else ``None``.
        error: Why recording stopped early (a sampling failure), or ``None``.
    """

    def __init__(
        self,
        header: Mapping[str, Any],
        *,
        max_frames: int = MAX_FRAMES,
        format_changes: Callable[[Any], dict[str, Any]] | None = None,
    ) -> None:
        self._header: dict[str, Any] = {"format": FORMAT, "version": VERSION, **header}
        self._frames: list[dict[str, Any]] = []
        self._pending: list[Any] = []
        self._room = max_frames  # frames still to take: len() would cost a tick too much
        self._format = format_changes
        self.result: dict[str, Any] | None = None
        self.error: str | None = None
        self.max_frames = max_frames
        self.not_recorded = 0
        self._last: dict[str, Any] = {}
        self._listeners: list[Listener] = []

    def header(self) -> dict[str, Any]:
        """The header line's object."""
        return self._header

    @property
    def frames(self) -> list[dict[str, Any]]:
        """The frames so far, each holding only what changed (the file's lines)."""
        if self._pending:
            self._flush()
        return self._frames

    def _flush(self) -> None:
        pending, self._pending = self._pending, []
        form = self._format
        self._frames.extend(pending if form is None else [form(frame) for frame in pending])

    def __len__(self) -> int:
        return len(self._frames) + len(self._pending)

    def subscribe(self, listener: Listener, *, with_header: bool = False) -> None:
        """Hand ``listener`` every event from now on: ``("frame", delta)``, ``("end", result)``.

        Args:
            listener: Called in the tick loop, so it must return quickly; one that raises is
                dropped (the run and the recording go on).
            with_header: Call it with ``("header", header)`` first.

        A listener joining late reads the frames so far from :attr:`frames`.
        """
        self._listeners.append(listener)
        if with_header:
            self._tell("header", self._header, [listener])

    def add(self, frame: Mapping[str, Any]) -> dict[str, Any] | None:
        """Record one tick's full snapshot; return the frame kept (only what changed).

        Args:
            frame: ``t`` (s, mission clock) and every value at this tick (see the module
                docstring); ``None`` values are kept as ``null`` (no reading).

        Returns:
            The frame as written (``t`` plus the changes), or ``None`` once the recording is
            full or finished.
        """
        if self.result is not None:
            return None
        if self._room <= 0:
            self.not_recorded += 1
            return None
        self._room -= 1
        delta = self._delta(frame)
        self.frames.append(delta)
        self._tell("frame", delta)
        return delta

    def add_changes(self, frame: Any) -> None:
        """Record one tick given as its changes already (``t`` plus what changed).

        For a feeder that tracks changes itself (:class:`~roboscript.replay.session_tap.
        RunRecording`); a recorder is fed through :meth:`add` or through this, not both.
        The frame is formatted (``format_changes``) when first needed: at once if someone
        listens, else when :attr:`frames` or the file is read, so the tick only stores it.
        """
        if self.result is not None:
            return
        if self._room <= 0:
            self.not_recorded += 1
            return
        self._room -= 1
        self._pending.append(frame)
        if self._listeners:
            self._flush()
            self._tell("frame", self._frames[-1])

    def _delta(self, frame: Mapping[str, Any]) -> dict[str, Any]:
        # Called once per tick: plain loops over a handful of keys, nothing clever.
        last = self._last
        delta: dict[str, Any] = {}
        for key, value in frame.items():
            if key in _EVENTS:
                if value is not None:
                    delta[key] = value
            elif key in _NESTED and value.__class__ is dict:
                before = last.get(key)
                if before is None:
                    before = last[key] = {}
                changed = {k: v for k, v in value.items() if k not in before or before[k] != v}
                if changed:
                    delta[key] = changed
                    before.update(changed)
            elif key == "t" or key not in last or last[key] != value:
                delta[key] = value
                last[key] = value
        return delta

    def finish(self, result: Mapping[str, Any]) -> dict[str, Any]:
        """Close the recording with how the run ended; later frames are refused.

        Returns:
            The result line's object (``frames`` and, if any, ``frames_not_recorded`` added).
        """
        if self.result is None:
            self.result = {**result, "frames": len(self)}
            if self.not_recorded:
                self.result["frames_not_recorded"] = self.not_recorded
            if self.error is not None:
                self.result["recording_error"] = self.error
            self._tell("end", self.result)
        return self.result

    def _tell(
        self, event: str, data: dict[str, Any], listeners: list[Listener] | None = None
    ) -> None:
        for listener in list(self._listeners if listeners is None else listeners):
            try:
                listener(event, data)
            except Exception:  # noqa: BLE001 - a broken viewer must not stop the run
                self._listeners.remove(listener)

    def lines(self) -> Iterable[str]:
        """The file's lines (without newlines): header, frames, result if finished."""
        yield _dumps(self._header)
        for frame in self.frames:
            yield _dumps(frame)
        if self.result is not None:
            yield _dumps({"result": self.result})

    def write(self, path: str | Path) -> None:
        """Write the recording to ``path`` (JSON Lines, UTF-8).

        Raises:
            OSError: The file cannot be written.
        """
        with Path(path).open("w", encoding="utf-8") as out:
            for line in self.lines():
                out.write(line)
                out.write("\n")

    save = write

    def recording(self) -> Recording:
        """The recording so far, frames filled in, as :func:`load_recording` would read it."""
        return Recording(dict(self._header), fill_frames(self.frames), self.result)


@dataclass
class Recording:
    """A recorded run read back.

    Attributes:
        header: The header line's object.
        frames: One full snapshot per tick: every key carries its last value (``sensors`` and
            ``motors`` complete), ``tone`` only on the tick it started.
        result: The result line's object, or ``None`` if the run was cut short.
    """

    header: dict[str, Any]
    frames: list[dict[str, Any]] = field(default_factory=list)
    result: dict[str, Any] | None = None

    def frame_at(self, t_s: float) -> dict[str, Any] | None:
        """The last frame at or before ``t_s`` seconds, or ``None`` before the first."""
        found = None
        for frame in self.frames:
            if frame["t"] > t_s + 1e-9:
                break
            found = frame
        return found


def fill_frames(deltas: Iterable[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Full snapshots from frames that hold only changes (the file's frame lines)."""
    frames: list[dict[str, Any]] = []
    current: dict[str, Any] = {}
    for delta in deltas:
        for key, value in delta.items():
            if key in NESTED_KEYS and isinstance(value, Mapping):
                current[key] = {**current.get(key, {}), **value}
            elif key not in EVENT_KEYS:
                current[key] = value
        frame = dict(current)
        for key in NESTED_KEYS:
            if key in frame:
                frame[key] = dict(frame[key])
        for key in EVENT_KEYS:
            if key in delta:
                frame[key] = delta[key]
        frames.append(frame)
    return frames


def load_recording(path: str | Path) -> Recording:
    """Read a recording file.

    Raises:
        RecordingError: Unreadable file, not a roboscript recording, a newer version, or a
            line that is not a JSON object (with ``file:line``).
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise RecordingError(f"cannot read the recording: {reason}", path=str(path)) from None
    return parse_recording(text, str(path))


def parse_recording(text: str, name: str = "<recording>") -> Recording:
    """Read a recording from its text; ``name`` is used in error messages.

    Raises:
        RecordingError: See :func:`load_recording`.
    """
    header: dict[str, Any] | None = None
    deltas: list[dict[str, Any]] = []
    result: dict[str, Any] | None = None
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        try:
            item = json.loads(line)
        except ValueError as exc:
            raise RecordingError(
                f"this line is not JSON ({exc.args[0].split(':')[0]})", path=name, line=number
            ) from None
        if not isinstance(item, dict):
            raise RecordingError("each line must be a JSON object", path=name, line=number)
        if header is None:
            _check_header(item, name, number)
            header = item
        elif result is not None:
            raise RecordingError("nothing may follow the result line", path=name, line=number)
        elif "result" in item:
            if not isinstance(item["result"], dict):
                raise RecordingError("'result' must be an object", path=name, line=number)
            result = item["result"]
        else:
            t = item.get("t")
            if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t):
                raise RecordingError(
                    "a frame needs 't', its time in seconds", path=name, line=number
                )
            deltas.append(item)
    if header is None:
        raise RecordingError("the recording is empty", path=name)
    return Recording(header, fill_frames(deltas), result)


def _check_header(item: dict[str, Any], name: str, number: int) -> None:
    if item.get("format") != FORMAT:
        raise RecordingError(
            f'not a roboscript recording (the first line needs "format": "{FORMAT}")',
            path=name,
            line=number,
        )
    version = item.get("version")
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise RecordingError("the header's 'version' must be a whole number", path=name, line=1)
    if version > VERSION:
        raise RecordingError(
            f"this recording is version {version}; this roboscript reads up to version"
            f" {VERSION} (upgrade roboscript)",
            path=name,
            line=number,
        )


def _dumps(item: Mapping[str, Any]) -> str:
    # Compact separators: a 60 s run is 3000 lines, and the viewer embeds them as they are.
    return json.dumps(item, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
