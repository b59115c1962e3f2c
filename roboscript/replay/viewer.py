"""The replay viewer: one self-contained HTML page (inline script and styles, nothing fetched).

The page's script and styles are package data beside this module (``viewer.js``,
``viewer.css``). A page holds one or more viewers (``<div class="rs-viewer">``) and the script
once; each viewer reads its run from an embedded ``<script type="application/json">`` or, live,
from a Server-Sent-Events URL (events ``header``, ``frame``, ``end``; see
:mod:`roboscript.replay.recording`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from functools import cache
from html import escape
from importlib import resources
from pathlib import Path
from typing import Any

from roboscript.replay.recording import (
    EVENT_KEYS,
    TRANSITION_KEY,
    Recorder,
    Recording,
    encode_line,
    load_recording,
    read_recording,
)

__all__ = [
    "decimate",
    "live_viewer",
    "view_recording",
    "viewer_assets",
    "viewer_block",
    "viewer_page",
    "viewer_script",
    "viewer_style",
    "write_viewer_page",
]


@cache
def viewer_assets() -> tuple[str, str]:
    """The viewer's ``(script, styles)`` text, from the package data."""
    folder = resources.files("roboscript.replay")
    script = (folder / "viewer.js").read_text(encoding="utf-8")
    style = (folder / "viewer.css").read_text(encoding="utf-8")
    return script, style


def viewer_script() -> str:
    """The ``<script>`` element that turns every viewer block of a page into a viewer."""
    # A literal "</" would end the element early; the script has none, this keeps it so.
    return "<script>\n" + viewer_assets()[0].replace("</", "<\\/") + "</script>\n"


def viewer_style() -> str:
    """The ``<style>`` element the viewer needs (its rules are scoped to ``.rs-viewer``)."""
    return "<style>\n" + viewer_assets()[1] + "</style>\n"


def decimate(frames: Sequence[Mapping[str, Any]], rate_hz: float) -> list[dict[str, Any]]:
    """At most ``rate_hz`` full frames a second, plus every frame of a transition (the state
    or why it was entered changes) and every frame the mission printed on.

    A tone that started on a dropped frame moves to the next frame kept, and the last frame is
    always kept, so the replay shows every state, every tone, every printed line at the tick
    it was printed in, and where the run ended.
    """
    if rate_hz <= 0:
        raise ValueError("the rate must be positive")
    period = 1.0 / rate_hz
    kept: list[dict[str, Any]] = []
    next_t = -float("inf")
    pending: dict[str, Any] = {}
    last_state: Any = object()
    last_why: Any = object()
    for index, frame in enumerate(frames):
        for key in EVENT_KEYS:
            if key in frame:
                pending[key] = frame[key]
        is_last = index == len(frames) - 1
        moved = frame.get("state") != last_state or frame.get(TRANSITION_KEY) is not last_why
        if frame["t"] >= next_t - 1e-9 or moved or is_last or "print" in frame:
            item = {k: v for k, v in frame.items() if k not in EVENT_KEYS}
            item.update(pending)
            pending = {}
            kept.append(item)
            next_t = frame["t"] + period
            last_state = frame.get("state")
            last_why = frame.get(TRANSITION_KEY)
    return kept


def _data(
    recording: Recording,
    *,
    open_at_s: float | None,
    marks: Iterable[Mapping[str, Any]],
    rate_hz: float | None,
) -> dict[str, Any]:
    frames = recording.frames if rate_hz is None else decimate(recording.frames, rate_hz)
    recorder = Recorder(recording.header, max_frames=len(frames) + 1)
    for frame in frames:
        recorder.add(frame)
    data: dict[str, Any] = {
        "header": recording.header,
        "frames": recorder.frames,
        "result": recording.result,
        "marks": list(marks),
    }
    if open_at_s is not None:
        data["open_at_s"] = open_at_s
    return data


def viewer_block(
    recording: Recording,
    *,
    open_at_s: float | None = None,
    marks: Iterable[Mapping[str, Any]] = (),
    rate_hz: float | None = None,
    label: str | None = None,
) -> str:
    """One viewer with its run embedded (needs :func:`viewer_script` once on the page).

    Args:
        recording: The run.
        open_at_s: Open at this time on the mission clock (else at the start).
        marks: Moments to mark on the plots: ``{"t": s, "label": text}``.
        rate_hz: Embed at most this many frames a second (see :func:`decimate`); ``None``
            embeds every frame.
        label: The viewer's accessible name.
    """
    data = _data(recording, open_at_s=open_at_s, marks=marks, rate_hz=rate_hz)
    opening, closing = _block_ends(label or _label(recording.header))
    return opening + _embedded(data) + closing


def _embedded(item: Mapping[str, Any]) -> str:
    """JSON for inside ``<script>``, where only ``"</"`` could end the element early:
    ``\\u003c`` is the same JSON string."""
    return encode_line(item).replace("<", "\\u003c")


def _label(header: Mapping[str, Any]) -> str:
    mission = header.get("mission")
    name = mission.get("name") if isinstance(mission, dict) else None
    return f"replay of {name if isinstance(name, str) else 'a run'}"


def _block_ends(label: str) -> tuple[str, str]:
    """The viewer block's text before and after its embedded JSON."""
    opening = (
        f'<div class="rs-viewer" tabindex="0" role="region" aria-label="{escape(label)}">'
        '<script type="application/json" class="rs-data">'
    )
    return opening, "</script></div>\n"


def live_viewer(url: str, *, label: str = "live view") -> str:
    """One viewer fed live from the Server-Sent-Events stream at ``url``."""
    return (
        f'<div class="rs-viewer" tabindex="0" role="region" aria-label="{escape(label)}"'
        f' data-live="{escape(url)}"></div>\n'
    )


def viewer_page(body: str, title: str) -> str:
    """A whole page around viewer blocks: styles, the blocks, the script once."""
    head, tail = _page_ends(title)
    return head + body + tail


def _page_ends(title: str) -> tuple[str, str]:
    """The page's text before and after its viewer blocks."""
    head = (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{escape(title)}</title>\n{viewer_style()}"
        "<style>body { margin: 1rem auto; max-width: 900px; padding: 0 1rem;"
        " font-family: system-ui, sans-serif; } h1 { font-size: 1.3rem; }</style>\n"
        f"</head>\n<body>\n<h1>{escape(title)}</h1>\n"
    )
    return head, f"{viewer_script()}</body>\n</html>\n"


def recording_title(recording: Recording) -> str:
    """The page title for a run: mission, robot, world."""
    return _title(recording.header)


def _title(header: Mapping[str, Any]) -> str:
    def name(part: Any, default: str) -> str:
        found = part.get("name") if isinstance(part, dict) else None
        return found if isinstance(found, str) and found else default

    mission = name(header.get("mission"), "a run")
    robot = name(header.get("robot"), "a robot")
    world = name(header.get("world"), "")
    return f"{mission} on {robot}{f' in {world}' if world else ''}"


def write_viewer_page(recording_path: str | Path, out_path: str | Path) -> Path:
    """Write the replay page of the recording at ``recording_path`` to ``out_path``.

    The recording is read and the page written line by line, so memory stays bounded
    whatever the file's size; the page appears whole or not at all (it is written beside
    ``out_path`` and renamed when done). A device or a pipe named as ``out_path``
    (``/dev/stdout``) is written into, never replaced by a file.

    Raises:
        RecordingError: The recording cannot be read (nothing is written).
        OSError: The page cannot be written.
    """
    out = Path(out_path)
    if out.exists() and not out.is_file():  # renamed over, a device would be lost
        with out.open("w", encoding="utf-8") as page:
            _stream_page(read_recording(recording_path), page.write)
        return out
    part = out.with_name(out.name + ".part")
    try:
        with part.open("w", encoding="utf-8") as page:
            _stream_page(read_recording(recording_path), page.write)
        os.replace(part, out)
    finally:
        part.unlink(missing_ok=True)
    return out


def _stream_page(
    items: Iterable[tuple[str, int, dict[str, Any]]], write: Callable[[str], object]
) -> None:
    """Write a page from a recording's lines (:func:`read_recording`) as they are read."""
    result: dict[str, Any] | None = None
    opened = False
    closing = tail = ""
    for kind, _, item in items:
        if kind == "header":
            head, tail = _page_ends(_title(item))
            opening, closing = _block_ends(_label(item))
            write(head + opening + '{"header":' + _embedded(item) + ',"frames":[')
        elif kind == "frame":
            write(("," if opened else "") + _embedded(item))
            opened = True
        else:
            result = item
    write('],"result":' + _embedded_value(result) + ',"marks":[]}' + closing + tail)


def _embedded_value(value: dict[str, Any] | None) -> str:
    return "null" if value is None else _embedded(value)


def view_recording(
    recording_path: str,
    out_path: str | None = None,
    *,
    open_page: bool = False,
    csv_path: str | None = None,
) -> tuple[Path, str | None]:
    """``roboscript view``: write the page (default: the recording's name with ``.html``),
    and with ``csv_path`` the run as columns (:func:`~roboscript.replay.columns.write_csv`).

    Returns:
        The page's path, and the one-line problem if it could not be written or opened.

    Raises:
        RecordingError: The recording cannot be read.
    """
    out = Path(out_path) if out_path else Path(recording_path).with_suffix(".html")
    try:
        write_viewer_page(recording_path, out)
    except OSError as exc:
        return out, f"error: cannot write the page {out}: {exc.strerror or exc}"
    if csv_path is not None:
        # the CSV writer loads only when one is asked for
        from roboscript.replay.columns import write_csv

        try:  # the page streamed the file; the columns need it whole (bounded by the reader)
            write_csv(load_recording(recording_path), csv_path)
        except OSError as exc:
            return out, f"error: cannot write {csv_path}: {exc.strerror or exc}"
    if open_page:
        import webbrowser

        if not webbrowser.open(out.resolve().as_uri()):
            return out, f"error: no web browser to open {out}; open it by hand"
    return out, None
