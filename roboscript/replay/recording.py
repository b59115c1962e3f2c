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

One writer and one reader hold the framing: :func:`encode_line` writes a line no text can
break (every character a reader could take for a line end is escaped), and
:func:`read_recording` reads a file line by line, splitting at ``"\\n"`` only, bounding each
line and the number of frames, and checking each line has the shape a viewer draws, so a
hostile or huge file gets ``FILE:LINE: error: ...``, never a traceback. A :class:`Recorder`
given a :class:`RecordingFile` writes its lines as the run goes (flushed at least once a
second), so a run killed outright leaves a readable prefix.
"""

from __future__ import annotations

import json
import math
import re
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from roboscript.errors import InputError
from roboscript.transport.output_file import FLUSH_EVERY_S, OutputFile

__all__ = [
    "FORMAT",
    "MAX_FRAMES",
    "MAX_LINE_CHARS",
    "NESTED_KEYS",
    "TRANSITION_KEY",
    "VERSION",
    "Listener",
    "Recorder",
    "Recording",
    "RecordingError",
    "RecordingFile",
    "decode_line",
    "encode_line",
    "fill_frames",
    "load_recording",
    "parse_recording",
    "read_recording",
    "replay_misfit",
]

FORMAT = "roboscript-run"
"""The header's ``format`` value."""
VERSION = 1
"""The version this module writes (and the newest it reads)."""
MAX_FRAMES = 200_000
"""Most frames one recording keeps (66 minutes at 50 ticks a second); later ticks are counted
in the result's ``frames_not_recorded``, so a run of hours keeps a bounded size."""
MAX_LINE_CHARS = 4_000_000
"""Longest line a reader takes (a header with a world of 20,000 walls is about 1 MB)."""
NESTED_KEYS = ("sensors", "motors", "log")
"""Frame keys whose value is an object recorded entry by entry (only changed entries)."""
EVENT_KEYS = ("tone", "print")
"""Frame keys that happen on one tick and do not carry over to the next."""
TRANSITION_KEY = "why"
"""The frame key written on each transition's frame only (why the state was entered), which
readers carry on to later frames. A new one is a new transition even when it equals the one
before (a state entered again for the same cause), so it is told apart by identity: each
transition's frame holds its own object, and frames filled in from it share that object."""

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
        out: Where the lines go as the run goes: the header at once, the frames at least
            once a second, the result at :meth:`finish` (which closes it). A write error
            stops the writing (see :attr:`RecordingFile.error`), never the run.

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
        out: RecordingFile | None = None,
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
        self.out = out
        self._written = 0  # frames already handed to ``out``
        self._next_write_s = 0.0  # time.monotonic() at which the next frames are written
        if out is not None:
            out.write(self._header)
            out.flush()
            self._next_write_s = time.monotonic() + FLUSH_EVERY_S

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
        if self.out is not None and time.monotonic() >= self._next_write_s:
            self._write_out()
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
        if self.out is not None and time.monotonic() >= self._next_write_s:
            self._write_out()

    def _write_out(self) -> None:
        """Hand ``out`` the frames it has not had yet, and flush it."""
        out = self.out
        if out is None:
            return
        frames = self.frames
        for frame in frames[self._written :]:
            out.write(frame)
        self._written = len(frames)
        out.flush()
        self._next_write_s = time.monotonic() + FLUSH_EVERY_S

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
            elif (
                key == "t"
                or key not in last
                # a transition's cause by identity: entered again for the same cause is new
                or (last[key] is not value if key == TRANSITION_KEY else last[key] != value)
            ):
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
            if self.out is not None:
                self._write_out()
                self.out.write({"result": self.result})
                self.out.close()
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
        yield encode_line(self._header)
        for frame in self.frames:
            yield encode_line(frame)
        if self.result is not None:
            yield encode_line({"result": self.result})

    def write(self, path: str | Path) -> None:
        """Write the recording to ``path`` (JSON Lines, UTF-8).

        Raises:
            OSError: The file cannot be written.
        """
        with Path(path).open("w", encoding="utf-8", newline="\n") as out:
            for line in self.lines():
                out.write(line)
                out.write("\n")

    save = write

    def recording(self) -> Recording:
        """The recording so far, frames filled in, as :func:`load_recording` would read it."""
        return Recording(dict(self._header), fill_frames(self.frames), self.result)


class RecordingFile:
    """A recording's file, written line by line as the run goes.

    Every line goes through :func:`encode_line`. A write that fails (a full disk, a file-size
    limit, a line that cannot be JSON) closes the file, keeps what reached it, and is said in
    :attr:`error`; later lines are dropped, so the run itself never sees the error
    (:class:`~roboscript.transport.output_file.OutputFile`).

    Args:
        path: The file (replaced if it exists).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._out = OutputFile(path, "the recording")

    @property
    def error(self) -> str | None:
        """``"cannot write the recording PATH: why"``, or ``None`` while all is well."""
        return self._out.error

    def write(self, item: Mapping[str, Any]) -> None:
        """Write one line (a header, a frame or the result); buffered until :meth:`flush`."""
        try:
            line = encode_line(item)
        except (ValueError, TypeError) as exc:
            self._out.fail(exc)
            return
        self._out.write(line + "\n")

    def flush(self) -> None:
        """Push the lines written so far to the file."""
        self._out.flush()

    def close(self) -> None:
        """Flush and close; later lines are dropped."""
        self._out.close()


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
    """Read a recording file, its frames filled in.

    Raises:
        RecordingError: Unreadable file, not a roboscript recording, a newer version, or a
            line that is not what a recording holds (with ``file:line``).
    """
    return _recording_of(read_recording(path))


def parse_recording(text: str, name: str = "<recording>") -> Recording:
    """Read a recording from its text; ``name`` is used in error messages.

    Raises:
        RecordingError: See :func:`load_recording`.
    """
    return _recording_of(_items(_split(text), name))


def _recording_of(items: Iterable[tuple[str, int, dict[str, Any]]]) -> Recording:
    header: dict[str, Any] = {}
    deltas: list[dict[str, Any]] = []
    result: dict[str, Any] | None = None
    for kind, _, item in items:
        if kind == "header":
            header = item
        elif kind == "frame":
            deltas.append(item)
        else:
            result = item
    return Recording(header, fill_frames(deltas), result)


def read_recording(path: str | Path) -> Iterator[tuple[str, int, dict[str, Any]]]:
    """The lines of a recording file as they are read: ``(kind, line number, object)``.

    ``kind`` is ``"header"`` (first), ``"frame"`` (the frame's changes, as written) or
    ``"result"`` (the result line's object, last if present). Memory stays bounded by one
    line (at most :data:`MAX_LINE_CHARS`) whatever the file's size; a file may hold at most
    :data:`MAX_FRAMES` frames, as no recorder writes more.

    Raises:
        RecordingError: See :func:`load_recording`; raised when the bad line is reached.
    """
    name = str(path)
    try:
        with Path(path).open(encoding="utf-8", newline="\n") as stream:
            yield from _items(_read_lines(stream, name), name)
    except OSError as exc:  # opening it: reading it raises RecordingError already
        raise RecordingError(
            f"cannot read the recording: {exc.strerror or exc}", path=name
        ) from None


def _read_lines(stream: IO[str], name: str) -> Iterator[tuple[int, str, bool]]:
    """``(line number, text, ended)`` for each line; ``ended`` is False for a last line
    with no newline (a run killed while writing it)."""
    number = 0
    while True:
        number += 1
        try:
            line = stream.readline(MAX_LINE_CHARS + 1)
        except UnicodeDecodeError:
            raise RecordingError("this line is not UTF-8 text", path=name, line=number) from None
        except OSError as exc:
            raise RecordingError(
                f"cannot read the recording: {exc.strerror or exc}", path=name, line=number
            ) from None
        if not line:
            return
        if line.endswith("\n"):
            yield number, line[:-1], True
        elif len(line) > MAX_LINE_CHARS:
            raise RecordingError(
                f"this line is longer than {MAX_LINE_CHARS:,} characters",
                path=name,
                line=number,
            )
        else:
            yield number, line, False


def _split(text: str) -> Iterator[tuple[int, str, bool]]:
    lines = text.split("\n")
    last = len(lines) - 1
    for index, line in enumerate(lines):
        if index < last or line:
            yield index + 1, line, index < last


def _items(
    lines: Iterable[tuple[int, str, bool]], name: str
) -> Iterator[tuple[str, int, dict[str, Any]]]:
    seen_header = seen_result = False
    frames = 0
    for number, line, ended in lines:
        if not line.strip():
            continue
        if not ended and seen_header and _cut_short(line):
            return  # the last line, cut short when the run was killed: the rest is good
        item = decode_line(line, name, number)
        if not seen_header:
            _check_header(item, name, number)
            seen_header = True
            yield "header", number, item
        elif seen_result:
            raise RecordingError("nothing may follow the result line", path=name, line=number)
        elif "result" in item:
            _check_shape(item["result"], _RESULT, "result", name, number)
            seen_result = True
            yield "result", number, item["result"]
        else:
            frames += 1
            if frames > MAX_FRAMES:
                raise RecordingError(
                    f"more than {MAX_FRAMES:,} frames: no recording holds so many",
                    path=name,
                    line=number,
                )
            problem = _frame_misfit(item, "")
            if problem is not None:
                raise RecordingError(problem, path=name, line=number)
            yield "frame", number, item
    if not seen_header:
        raise RecordingError("the recording is empty", path=name)


def _cut_short(line: str) -> bool:
    """True if ``line`` is the start of a JSON text that was never finished."""
    try:
        json.loads(line, parse_constant=_no_constant)
    except json.JSONDecodeError:
        return True
    except (ValueError, RecursionError):
        return False
    return False


# Characters a reader may take for the end of a line (Python's str.splitlines() does, and
# JavaScript's line terminators include U+2028/U+2029) that json.dumps leaves raw, and lone
# surrogates, which UTF-8 cannot hold: each is written as its \uXXXX escape, which any JSON
# reader turns back into the same character.
_UNSAFE = re.compile("[\x85\u2028\u2029\ud800-\udfff]")


def _escape(match: re.Match[str]) -> str:
    return f"\\u{ord(match.group()):04x}"


def encode_line(item: Mapping[str, Any]) -> str:
    """One line of a recording (no newline): compact JSON, UTF-8-safe, unbreakable.

    Raises:
        ValueError: A number is NaN or infinite (JSON has none).
        TypeError: A value is not JSON (an object of some class).
    """
    # Compact separators: a 60 s run is 3000 lines, and the viewer embeds them as they are.
    text = json.dumps(item, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    return _UNSAFE.sub(_escape, text)


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a number JSON allows")


def decode_line(line: str, name: str = "<recording>", number: int = 0) -> dict[str, Any]:
    """Read one line written by :func:`encode_line`.

    Raises:
        RecordingError: Not a JSON object (NaN, Infinity, nesting too deep: named so).
    """
    try:
        item = json.loads(line, parse_constant=_no_constant)
    except RecursionError:
        raise RecordingError("this line is nested too deeply", path=name, line=number) from None
    except ValueError as exc:
        reason = str(exc.args[0] if exc.args else exc).split(":")[0]
        raise RecordingError(
            f"this line is not JSON ({reason})", path=name, line=number or None
        ) from None
    if not isinstance(item, dict):
        raise RecordingError("each line must be a JSON object", path=name, line=number or None)
    return item


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
    _check_shape(item, _HEADER, "", name, number)


# ---- shapes: what the viewer and the state diagram read, checked before they read it ----
#
# A shape is NUMBER, TEXT or ANY; Maybe(shape) (also null); [shape] (a list of); a tuple of
# shapes (a list of exactly these); {key: shape} (an object whose listed keys, when present,
# have these shapes; other keys are free); Each(shape) (an object, every value of this shape).

NUMBER = "a number"
TEXT = "text"
ANY = "anything"


@dataclass(frozen=True)
class Maybe:
    """A shape that may also be ``null``."""

    shape: Any


@dataclass(frozen=True)
class Each:
    """An object whose every value has ``shape``."""

    shape: Any


_XY = (NUMBER, NUMBER)
_SEGMENT = (NUMBER, NUMBER, NUMBER, NUMBER)
_HEADER = {
    "mission": {"name": Maybe(TEXT), "initial": Maybe(TEXT), "states": [{"name": TEXT}]},
    "robot": {
        "name": Maybe(TEXT),
        "body_radius_mm": NUMBER,
        "sensors": [
            {
                "name": TEXT,
                "kind": TEXT,
                "forward_mm": NUMBER,
                "right_mm": NUMBER,
                "bearing_deg": NUMBER,
                "cone_deg": NUMBER,
                "max_range_mm": NUMBER,
                "spots_mm": [_XY],
                "spot_diameter_mm": NUMBER,
            }
        ],
    },
    "world": Maybe(
        {
            "name": Maybe(TEXT),
            "walls": [_SEGMENT],
            "lines": [{"segments": [_SEGMENT], "width_mm": NUMBER}],
            "regions": [{"name": TEXT, "center": _XY, "radius_mm": Maybe(NUMBER), "points": [_XY]}],
            "start": (NUMBER, NUMBER, NUMBER),
        }
    ),
    "tick_s": Maybe(NUMBER),
    "port": Maybe(TEXT),
    "printed_before_start": [TEXT],
}
_SENSOR_VALUE = Maybe(ANY)
_FRAME = {
    "pose": Maybe((NUMBER, NUMBER, NUMBER)),
    "state": Maybe(TEXT),
    "action": Maybe(TEXT),
    "outcome": Maybe(TEXT),
    "display": Maybe(TEXT),
    "contact": Maybe(TEXT),
    "sensors": Each(_SENSOR_VALUE),
    "motors": Each(Maybe(NUMBER)),
    "tone": (NUMBER, NUMBER),
    "why": {"kind": TEXT, "text": TEXT, "values": Each(_SENSOR_VALUE)},
    "log": Each(_SENSOR_VALUE),
    "print": [TEXT],
}
_RESULT = {
    "outcome": Maybe(TEXT),
    "final_state": Maybe(TEXT),
    "reason": Maybe(TEXT),
    "duration_s": Maybe(NUMBER),
    "states": [(NUMBER, TEXT)],
}


def _frame_misfit(item: Any, where: str, limit_s: float = math.inf) -> str | None:
    """What is wrong with a frame's changes (one sentence), or ``None``."""
    if not isinstance(item, dict):
        return f"'{where}' must be an object"
    t = item.get("t")
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t):
        return "a frame needs 't', its time in seconds"
    if not -limit_s <= t <= limit_s:
        return f"a frame's time {t!r} s is outside the run"
    return _misfit(item, _FRAME, where)


def replay_misfit(replay: Any, limit_s: float = math.inf) -> str | None:
    """What is wrong with a run's replay as the grader keeps it (``{"header", "frames",
    "result"}``: a recording's lines, the frames as written), one sentence naming where; or
    ``None`` when the viewer can show it. ``limit_s``: the most any of its times may be, s.

    A results file can be damaged or forged: its replay gets the checks a recording file's
    lines get (:func:`read_recording`) before a report embeds it.
    """
    if not isinstance(replay, dict) or not isinstance(replay.get("frames"), list):
        return "'replay' must be an object with a list of frames"
    header = replay.get("header")
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        return f'\'replay.header\' must be a recording\'s header ("format": "{FORMAT}")'
    frames: list[Any] = replay["frames"]
    if len(frames) > MAX_FRAMES:
        return f"'replay.frames' holds more than {MAX_FRAMES:,} frames: no recording holds so many"
    problem = _misfit(header, _HEADER, "replay.header")
    for index, frame in enumerate(frames):
        if problem is not None:
            break
        problem = _frame_misfit(frame, f"replay.frames[{index}]", limit_s)
    result = replay.get("result")
    if problem is None and result is not None:
        problem = _misfit(result, _RESULT, "replay.result")
    return problem


def _check_shape(value: Any, shape: Any, where: str, name: str, number: int) -> None:
    problem = _misfit(value, shape, where)
    if problem is not None:
        raise RecordingError(problem, path=name, line=number)


def _misfit(value: Any, shape: Any, where: str) -> str | None:
    """What is wrong with ``value`` for ``shape`` (one sentence), or ``None``."""
    if isinstance(shape, Maybe):
        return None if value is None else _misfit(value, shape.shape, where)
    if shape is ANY:
        return None
    if shape is NUMBER:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return f"'{where}' must be a number"
        return None if math.isfinite(value) else f"'{where}' must be a finite number"
    if shape is TEXT:
        return None if isinstance(value, str) else f"'{where}' must be text"
    if isinstance(shape, tuple):
        if not isinstance(value, list) or len(value) != len(shape):
            return f"'{where}' must be a list of {len(shape)} values"
        for index, (item, part) in enumerate(zip(value, shape, strict=True)):
            problem = _misfit(item, part, f"{where}[{index}]")
            if problem:
                return problem
        return None
    if isinstance(shape, list):
        if not isinstance(value, list):
            return f"'{where}' must be a list"
        for index, item in enumerate(value):
            problem = _misfit(item, shape[0], f"{where}[{index}]")
            if problem:
                return problem
        return None
    if not isinstance(value, dict):
        return f"'{where}' must be an object"
    if isinstance(shape, Each):
        for key, item in value.items():
            problem = _misfit(item, shape.shape, f"{where}.{key}")
            if problem:
                return problem
        return None
    for key, part in shape.items():
        if key in value:
            problem = _misfit(value[key], part, f"{where}.{key}" if where else key)
            if problem:
                return problem
    return None
