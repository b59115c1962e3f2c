"""The words reports show: capped, safe in any file, and the student-facing view of a run.

Much of what a report shows comes from a student's code: the message of an exception it
raised, a traceback, the reason a mission gave, its state and mission names. A student can make
any of them as long as they like (a 20 MB exception message once made a 614 MB grader and
60 MB HTML pages), and put in them characters that break an XML file, a UTF-8 file or a
terminal. Every report therefore takes that text through :func:`cap` (by way of
:func:`cap_result`, which caps every field of a run that a report shows): it is cut to a limit,
visibly (``… (cut: 1234 characters)``), and cleaned.

:func:`public_reason` is what a student may read about a run whose variant the teacher keeps
hidden: pass or fail and why, never its seed, start, world or the spec's path, and nothing the
mission printed or raised.

:func:`clean_name` is the one place a student's name is made safe, once, when the grader
finds the submission (:class:`~roboscript.grading.submissions.Submission`): every report then
shows the same name. :func:`student_text` takes the teacher's folders out of a sentence a
student reads.
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import replace
from pathlib import Path

from roboscript.grading.record import RunRecord, RunResult, Verdict

__all__ = [
    "DEBUG_CHARS",
    "MARKS_PER_CHARACTER",
    "MESSAGE_CHARS",
    "NAME_CHARS",
    "advice",
    "cap",
    "cap_result",
    "clean_name",
    "display_width",
    "format_points",
    "padded",
    "public_reason",
    "student_text",
    "xml_safe",
]

MESSAGE_CHARS = 2_000
"""Longest message, reason or verdict detail a report shows."""
DEBUG_CHARS = 20_000
"""Longest debug block (a traceback) a report shows."""
NAME_CHARS = 200
"""Longest name (a state, a mission, a final state, a margin) a report shows."""

_MARKER_ROOM = 40  # room for the marker, so a capped text is never longer than its limit
# Characters that are not allowed in XML 1.0, break UTF-8 output (lone surrogates), or move a
# terminal's cursor: C0 controls but tab and newline, DEL, C1 controls, U+FFFE and U+FFFF.
_XML_UNSAFE = "\x00-\x08\x0b-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff"
_UNSAFE = re.compile(f"[{_XML_UNSAFE}]")
# The bidirectional controls that reorder what a terminal or a page shows after them (a
# student's "deliaf" read backwards as "failed"): embeddings, overrides, isolates, marks.
_BIDI = "\u202a-\u202e\u2066-\u2069\u200e\u200f\u061c"
_SHOWN_UNSAFE = re.compile(f"[{_XML_UNSAFE}{_BIDI}]")


def cap(text: str, limit: int = MESSAGE_CHARS) -> str:
    """``text`` cleaned, and cut to at most ``limit`` characters with a visible marker.

    Characters that would break a report (control characters, lone surrogates) or reorder
    what follows them (bidirectional controls) become ``�``. A cut text ends ``… (cut: N
    characters)``, N being how many were left out; the result, marker included, is never
    longer than ``limit``, so capping twice changes nothing.
    """
    if len(text) > limit:
        keep = max(0, limit - _MARKER_ROOM)
        text = f"{text[:keep]}… (cut: {len(text) - keep} characters)"
    return _SHOWN_UNSAFE.sub("\ufffd", text)


# What may not be in a name: any control character (tab and newline too: a name is one line),
# line and paragraph separators, and the bidirectional controls.
_NAME_UNSAFE = re.compile(f"[\x00-\x1f\x7f-\x9f\u2028\u2029{_BIDI}\ud800-\udfff\ufffe\uffff]")


# Characters that show as nothing: a name holding one would read, in a table, like a
# classmate's (``bob`` beside ``bob`` + U+3164). They are Unicode's default-ignorable code
# points (fillers, variation selectors, tags, Khmer's and Mongolian's silent marks) and the
# blank Braille cell, which shows as a space no ``strip()`` removes. Every format character
# (Unicode's "Cf": zero-width spaces and joiners, the soft hyphen, the byte-order mark...) is
# invisible too.
_BLANKS = re.compile(
    "[\u034f\u115f\u1160\u17b4\u17b5\u180b-\u180f\u2060-\u206f\u2800\u3164\ufe00-\ufe0f"
    "\uffa0\ufff0-\ufff8\U000e0000-\U000e0fff]"
)
MARKS_PER_CHARACTER = 4
"""Most combining marks (accents) a name shows on one character: enough for any script's
names (a Hebrew letter with its points), while a pile of them, drawn on top of each other,
reaches over the lines above and below it in a terminal or a page."""
_MARK_CATEGORIES = frozenset({"Mn", "Me"})


def _visible(text: str) -> str:
    """``text`` with each character that shows as nothing, and the marks piled on one
    character past :data:`MARKS_PER_CHARACTER`, shown as ``�`` (once for a pile)."""
    shown: list[str] = []
    marks = 0
    for char in text:
        category = unicodedata.category(char)
        if category == "Cf" or _BLANKS.match(char):
            char, marks = "\ufffd", 0
        elif category not in _MARK_CATEGORIES:
            marks = 0
        else:
            marks += 1
            if marks > MARKS_PER_CHARACTER:
                if marks == MARKS_PER_CHARACTER + 1:
                    shown.append("\ufffd")
                continue
        shown.append(char)
    return "".join(shown)


def clean_name(raw: str) -> str:
    """A student's name made safe for every report: one line, nothing a terminal obeys.

    Control characters (newlines, tabs and escape sequences included), separators,
    bidirectional controls and characters that show as nothing (zero-width spaces, soft
    hyphens, joiners, variation selectors, fillers) each become ``�``, and so does a pile of
    more than :data:`MARKS_PER_CHARACTER` accents on one character (once), so no two names
    that differ look alike and none reaches over the lines around it; the name is
    stripped of spaces at either end, put in Unicode's composed form (NFC), and cut to
    :data:`NAME_CHARS`. An empty name becomes ``student``. Cleaning a clean name changes
    nothing.
    """
    return cap(one_line(raw).strip(), NAME_CHARS) or "student"


def display_width(text: str) -> int:
    """How many columns of a terminal ``text`` takes: a wide character (Chinese, Japanese,
    Korean, full-width letters) two, an accent drawn on the character before it none."""
    return sum(
        0
        if unicodedata.category(char) in _MARK_CATEGORIES
        else 2
        if unicodedata.east_asian_width(char) in ("W", "F")
        else 1
        for char in text
    )


def padded(text: str, columns: int, *, right: bool = False) -> str:
    """``text`` padded with spaces to take ``columns`` columns of a terminal
    (:func:`display_width`), on its right, or on its left when ``right`` (numbers)."""
    room = " " * max(0, columns - display_width(text))
    return room + text if right else text + room


def one_line(raw: str) -> str:
    """``raw`` as one line of visible text (a file's name in a sentence): what
    :func:`clean_name` does to a name, without stripping or cutting it."""
    return _visible(_NAME_UNSAFE.sub("\ufffd", unicodedata.normalize("NFC", raw)))


# An absolute path's folders (POSIX or Windows): what is left of it is the file's name.
_FOLDERS = re.compile(
    r"(?<![^\s'\"(\[<=,;:])(?:[A-Za-z]:)?(?:[/\\][^\s/\\:'\"()\[\],;]+)+[/\\](?=[^\s/\\])"
)


def student_text(text: str, root: str | Path | None = None) -> str:
    """``text`` with no folder of the teacher's computer in it, for a student to read.

    Paths inside ``root`` (the student's folder, or the class folder of a student who is a
    file) become relative to it (``helpers/turns.py:3``); any other absolute path keeps only
    its file name.
    """
    if root is not None:
        for folder in dict.fromkeys((str(root), str(Path(root).resolve()))):
            text = text.replace(folder.rstrip("/\\") + "/", "")
    return _FOLDERS.sub("", text)


def xml_safe(text: str) -> str:
    """``text`` with every character XML 1.0 does not allow (``\\x01``, lone surrogates...)
    shown as ``�``; tab, newline and carriage return stay."""
    return _UNSAFE.sub("\ufffd", text.replace("\r", "\n"))


def _cap_verdict(verdict: Verdict) -> Verdict:
    return replace(
        verdict,
        name=cap(verdict.name, NAME_CHARS),
        margin=cap(verdict.margin, NAME_CHARS),
        detail=cap(verdict.detail, MESSAGE_CHARS),
        margin_unit=cap(verdict.margin_unit, NAME_CHARS),
    )


def _cap_record(record: RunRecord) -> RunRecord:
    return replace(
        record,
        mission=cap(record.mission, NAME_CHARS),
        sim=None
        if record.sim is None
        else replace(record.sim, world=cap(record.sim.world, NAME_CHARS)),
        final_state=cap(record.final_state, NAME_CHARS) if record.final_state else None,
        reason=cap(record.reason, MESSAGE_CHARS) if record.reason else record.reason,
        states=tuple((t, cap(name, NAME_CHARS)) for t, name in record.states),
    )


def cap_result(result: RunResult) -> RunResult:
    """``result`` with every text a report shows capped by :func:`cap`.

    The message, verdict details and the mission's reason get :data:`MESSAGE_CHARS`, the
    debug block :data:`DEBUG_CHARS`, names :data:`NAME_CHARS`. The student's name is left
    as it is: it was cleaned once, when the submission was found (:func:`clean_name`).
    """
    return replace(
        result,
        label=cap(result.label, NAME_CHARS),
        message=cap(result.message, MESSAGE_CHARS),
        debug=cap(result.debug, DEBUG_CHARS),
        verdicts=tuple(_cap_verdict(v) for v in result.verdicts),
        record=_cap_record(result.record) if result.record is not None else None,
    )


def public_reason(result: RunResult, hidden: bool) -> str:
    """Why the run did not pass, in words a student may read (empty when it passed).

    A visible run gives its message. A hidden run that failed an expectation gives the
    expectation and its margin only (``final_pose_within failed by 41.5 cm``): the details
    name positions, and a target relative to the start would give the start away. A hidden run
    that did not finish gives one fixed sentence for its status: its message may quote what
    the mission printed or raised, and a mission can read its start.
    """
    if result.passed:
        return ""
    if not hidden or result.status == "missing":  # nothing ran: the grader's own words
        return result.message
    if result.status != "failed":
        return _HIDDEN_ENDINGS.get(result.status, "the run did not finish")
    failed = [v for v in result.verdicts if not v.passed]
    if not failed:
        return "an expectation did not hold"
    first = failed[0]
    text = f"{first.name} {first.margin}" if first.margin else f"{first.name} failed"
    if len(failed) > 1:
        text += f" (and {len(failed) - 1} more check{'s' if len(failed) > 2 else ''} failed)"
    return text


_HIDDEN_ENDINGS = {
    "crashed": "the run crashed (a hidden run does not show why)",
    "hung": "the mission stopped responding (a hidden run does not show where)",
    "too slow": "the mission was too slow (a hidden run does not show where)",
    "timeout": "the run did not finish in time (a hidden run does not show where)",
    "invalid": "the mission does not load (a visible run shows why)",
}


def format_points(points: float) -> str:
    """Points as people write them: ``3``, ``2.5``, ``6.67`` (at most two decimals)."""
    text = f"{points:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def advice(status: str) -> str:
    """What a student can do about a run that did not finish, in one sentence."""
    if status in ("too slow", "timeout", "hung"):
        return (
            "Try the mission with 'roboscript run' at home: it stops code that never returns"
            " and warns about code that takes too long per tick, at its line, as the grader does."
        )
    if status == "invalid":
        return "Run 'roboscript check' on the mission to see every problem with its line."
    if status == "missing":
        return "Name your mission after the test, or hand in one mission only."
    return "Run the mission with 'roboscript run --debug' to see where it stops."
