"""The roboscript exception tree.

Every branch is also a builtin exception, so code that knows nothing of roboscript can still
catch what it expects (a bad mission is a ``ValueError``, a lost link is an ``OSError``)::

    RoboscriptError(Exception)
    ├── InputError(RoboscriptError, ValueError)        a file a user wrote is wrong
    │   ├── MissionError                               mission YAML / Python
    │   ├── ProfileError                               robot profile
    │   ├── WorldError                                 simulator world
    │   └── SpecError                                  teacher test spec
    ├── CapabilityError(RoboscriptError, LookupError)  the robot lacks what is asked of it
    ├── ProtocolError(RoboscriptError, ValueError)
    │   ├── LocalProtocolError                         we tried to send something illegal
    │   └── RemoteProtocolError                        the peer sent bytes we cannot parse
    ├── DeviceError(RoboscriptError, RuntimeError)     the device reported an error itself
    └── LinkError(RoboscriptError, OSError)            the transport failed
        ├── LinkTimeoutError(LinkError, TimeoutError)  nothing answered in time
        └── LinkClosedError(LinkError, ConnectionError) the peer went away

Example scenarios:

* ``drvie:`` in a mission file -> :class:`MissionError` with ``path``, ``line``, ``col`` and a
  ``hint`` ("did you mean 'drive'?").
* ``follow_line`` on a robot without line sensors -> :class:`CapabilityError`.
* ``M,m,0,500`` (power out of range) built by a driver -> :class:`LocalProtocolError`.
* ``@M,e,2,{x:y}`` read from the wire -> :class:`RemoteProtocolError` (counted and skipped).
* ``~S,W,7{INVALID_DEVICE_NUMBER}`` from the board -> :class:`DeviceError`.
* The USB cable is pulled -> :class:`LinkClosedError`; no startup line within the handshake
  time -> :class:`LinkTimeoutError`.
"""

from __future__ import annotations

import difflib
import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path

__all__ = [
    "FAULT_SAMPLE_BYTES",
    "CapabilityError",
    "DeviceError",
    "InputError",
    "LinkClosedError",
    "LinkError",
    "LinkTimeoutError",
    "LocalProtocolError",
    "MissionError",
    "ProfileError",
    "ProtocolError",
    "RemoteProtocolError",
    "RoboscriptError",
    "SpecError",
    "WorldError",
    "did_you_mean",
    "grouped",
    "nearby_file",
    "pasted_with_it",
    "wrong_ending",
]

FAULT_SAMPLE_BYTES = 64
"""How many of a bad frame's bytes a :class:`RemoteProtocolError` keeps, for the log."""


_INVISIBLE = "\u200b\u200c\u200d\u2060\ufeff\u00a0\u00ad"
"""Characters that show as nothing (or as a plain space) where a web page or a document put
them: zero-width spaces and joiners, a byte-order mark, a non-breaking space, a soft hyphen."""
_INVISIBLE_RUN = re.compile(f"[{_INVISIBLE}]")


def did_you_mean(word: str, choices: Iterable[str], *, cutoff: float = 0.5) -> str | None:
    """The hint for a misspelt name: ``"did you mean 'x'?"``, or ``None`` if nothing is close.

    Args:
        word: What the user wrote.
        choices: The names that exist.
        cutoff: How alike (0-1, :func:`difflib.get_close_matches`) a choice must be.
    """
    options = sorted(set(choices))
    hidden = [char for char in word if char in _INVISIBLE]
    if hidden and _INVISIBLE_RUN.sub("", word) in options:  # drive\u200b: copied from a page
        visible = _INVISIBLE_RUN.sub("", word)
        return (
            f"'{visible}' holds an invisible character, U+{ord(hidden[0]):04X}, copied from a web"
            f" page or a document: type '{visible}' again"
        )
    # Another case ("MIRTO", "Done") is the choice itself, however short the word.
    same = [c for c in options if c.lower() == word.lower() and c != word]
    if same:
        return f"did you mean '{same[0]}'?"
    # A word cut short ("final_pose") means the choice it begins, before any look-alike.
    started = [c for c in options if len(word) >= 3 and c.startswith(word)]
    if started:
        return f"did you mean '{min(started, key=len)}'?"
    close = difflib.get_close_matches(word, options, n=1, cutoff=cutoff)
    return f"did you mean '{close[0]}'?" if close else None


def nearby_file(path: str | Path) -> str | None:
    """For a file that is not there: ``did you mean 'good.yaml'?`` when its folder holds a
    file of a like name (another case, ``.yml`` for ``.yaml``, no ending); else ``None``."""
    wanted = Path(path)
    try:
        if wanted.exists():
            return None
        if os.sep == "/" and "\\" in str(path):  # `missions\square.yaml` typed as on Windows
            return _windows_path_hint(str(path))
        if not wanted.parent.exists() or wanted.name == EXAMPLES_FOLDER:
            return _missing_folder(wanted)
        names = [entry.name for entry in os.scandir(wanted.parent or ".") if entry.is_file()]
    except OSError:
        return None
    same = [n for n in names if n.lower() == wanted.name.lower()]
    if same:
        return f"capitals count: did you mean '{same[0]}'?"
    stem = wanted.name.rsplit(".", 1)[0].lower()
    endings = [n for n in names if n.rsplit(".", 1)[0].lower() == stem]
    if endings:
        return f"did you mean '{min(endings)}'?"
    return did_you_mean(wanted.name, names[:1000], cutoff=0.8)


def _windows_path_hint(path: str) -> str:
    """For a path written as on Windows, on a computer whose folders are separated by ``/``."""
    slashed = path.replace("\\", "/")
    if re.match(r"[A-Za-z]:/", slashed):
        return "this is a Windows path: here a path has no drive letter and '/' separates folders"
    return f"folders are separated by '/' here: did you mean '{slashed}'?"


EXAMPLES_FOLDER = "missions"
"""The folder of example missions the guides name (``missions/square.yaml``): it is in the
roboscript folder, beside ``README.md``, and ``roboscript examples`` writes it anywhere else."""


def _missing_folder(wanted: Path) -> str:
    """For a path under a folder that is not there, or the examples' folder itself: which
    folder, looked for where.

    The guides' examples (``missions/square.yaml``) run from the roboscript folder; run from
    anywhere else, the hint says where they are rather than only that they are not here.
    """
    missing = wanted if wanted.name == EXAMPLES_FOLDER else wanted.parent
    while missing.parent != missing and not missing.parent.exists():
        missing = missing.parent
    where = missing.parent.resolve()
    hint = f"there is no folder '{missing.name}' in {where}"
    if missing.name == EXAMPLES_FOLDER and not (where / "README.md").exists():
        hint += ": `roboscript examples` writes the example missions here"
    return hint


class RoboscriptError(Exception):
    """Base of every error roboscript raises on purpose."""


class InputError(RoboscriptError, ValueError):
    """A file written by a user (mission, profile, world, test spec) is invalid.

    Attributes:
        message: What is wrong, in the writer's terms.
        path: The file, or ``None`` when the input did not come from a file.
        line: 1-based line number, or ``None``.
        col: 1-based column number, or ``None``.
        hint: A suggestion such as ``"did you mean 'drive'?"``, or ``None``.
        severity: ``"error"`` or ``"warning"``.
    """

    def __init__(
        self,
        message: str,
        *,
        path: str | None = None,
        line: int | None = None,
        col: int | None = None,
        hint: str | None = None,
        severity: str = "error",
    ) -> None:
        self.message = message
        self.path = path
        self.line = line
        self.col = col
        self.hint = hint
        self.severity = severity
        super().__init__(self.format())

    def format(self) -> str:
        """Return the ``file:line:col: error: message (hint)`` form users see."""
        if self.path is None:  # not from a file (a built-in profile's options, say)
            text = f"{self.severity}: {self.message}"
        else:
            where = self.path
            if self.line is not None:
                where += f":{self.line}"
                if self.col is not None:
                    where += f":{self.col}"
            text = f"{where}: {self.severity}: {self.message}"
        if self.hint:
            text += f" ({self.hint})"
        return text


_QUOTED = re.compile(r"'[^']*'")

REPEATS_SHOWN = 3
"""How many problems that read alike (one typo copied down a file) are printed each in full,
before the rest are counted on one line with their line numbers."""

LINES_LISTED = 10
"""How many line numbers that one line lists before it skips to the last."""


def grouped(problems: Sequence[InputError]) -> list[str]:
    """The lines that print ``problems`` (in file order) for a user: each in full, except that
    of problems with the same file, severity, message and hint (only the place differs) the
    first :data:`REPEATS_SHOWN` are printed and the rest told on one line after them,
    ``m.yaml:13:10: error: and 297 more like it at lines 13, 16, ... 901``, at the first
    one left out."""

    def key(problem: InputError) -> tuple[object, ...]:
        # A name in quotes may differ ("in state 's1'", "in state 's2'"): the same mistake
        # made in another state; the hint (the fix) must be the same.
        return (problem.path, problem.severity, _QUOTED.sub("'...'", problem.message), problem.hint)

    alike: dict[tuple[object, ...], list[InputError]] = {}
    for problem in problems:
        alike.setdefault(key(problem), []).append(problem)
    lines = []
    for problem in problems:
        same = alike[key(problem)]
        place = next(i for i, p in enumerate(same) if p is problem)
        if place < REPEATS_SHOWN:
            lines.append(problem.format())
        if place == REPEATS_SHOWN - 1 and len(same) > REPEATS_SHOWN:
            rest = same[REPEATS_SHOWN:]
            numbers = [str(p.line) for p in rest if p.line is not None]
            if len(numbers) > LINES_LISTED:
                numbers = [*numbers[: LINES_LISTED - 1], "...", numbers[-1]]
            at = f" at lines {', '.join(numbers)}" if numbers else ""
            first = rest[0]
            told = InputError(
                f"and {len(rest)} more like it{at}",
                path=first.path,
                line=first.line,
                col=first.col,
                severity=first.severity,
            )
            lines.append(told.format())
    return lines


class MissionError(InputError):
    """A mission file is invalid (unknown action, bad unit, unreachable state, ...)."""


class ProfileError(InputError):
    """A robot profile is invalid or names no known robot."""


class WorldError(InputError):
    """A simulator world file is invalid."""


class SpecError(InputError):
    """A teacher test spec is invalid."""


class CapabilityError(RoboscriptError, LookupError):
    """The robot lacks a capability a mission or action needs.

    Attributes:
        missing: The capability names that are missing.
    """

    def __init__(self, message: str, *, missing: tuple[str, ...] = ()) -> None:
        self.missing = missing
        super().__init__(message)


class ProtocolError(RoboscriptError, ValueError):
    """Bytes that do not follow a robot protocol."""


class LocalProtocolError(ProtocolError):
    """We tried to encode a message that is illegal for the protocol or our role."""


class RemoteProtocolError(ProtocolError):
    """The peer sent bytes that cannot be parsed.

    The codec has already consumed the offending bytes, so decoding may continue.

    Attributes:
        kind: A short, stable name for the fault (``"bad_checksum"``, ``"overlong"``, ...),
            used to count faults and log each kind once.
        data: The offending bytes, at most the first :data:`FAULT_SAMPLE_BYTES` of them.
    """

    def __init__(
        self, message: str, *, kind: str = "malformed", data: bytes | bytearray | memoryview = b""
    ) -> None:
        self.kind = kind
        self.data = bytes(data[:FAULT_SAMPLE_BYTES])
        super().__init__(message)


class DeviceError(RoboscriptError, RuntimeError):
    """The device itself reported an error.

    Attributes:
        code: The device's error number or status, when it gives one.
    """

    def __init__(self, message: str, *, code: int | None = None) -> None:
        self.code = code
        super().__init__(message)


class LinkError(RoboscriptError, OSError):
    """The transport to the robot failed."""


class LinkTimeoutError(LinkError, TimeoutError):
    """The robot did not answer within the time allowed."""


class LinkClosedError(LinkError, ConnectionError):
    """The link to the robot was closed or lost."""


_SHELL = "take away '>>> ' and '... ' at the start of each line, keeping the indentation after them"
_IPYTHON = (
    "take away 'In [1]: ' and '...: ' at the start of each line, keeping the indentation after them"
)
_PROMPTS = (
    (re.compile(r">>>(?: |$)"), "'>>> ', the prompt of Python's interactive shell", _SHELL),
    (
        re.compile(r"\.\.\. +\S"),
        "'... ', the prompt Python's interactive shell shows inside a block",
        _SHELL,
    ),
    (re.compile(r"In \[\d*\]: "), "'In [1]: ', the prompt of IPython or a notebook", _IPYTHON),
    (re.compile(r"\.\.\.: "), "'...: ', the prompt IPython shows inside a block", _IPYTHON),
)
_COMMAND = re.compile(
    r"(?:\$|%|PS [^>]*>|[A-Za-z]:\\[^>]*>)\s*(?:\.venv/bin/)?(?:roboscript|python)"
)
"""A terminal's prompt and a command (``$ roboscript run m.yaml``), copied into a file."""


def pasted_with_it(text: str, python: bool) -> tuple[int, int, str, str] | None:
    """The first line of a file that was copied with what surrounded it on the page it was
    copied from: a Markdown fence (```), a terminal's command, or (in Python) a prompt of
    Python's interactive shell (``>>> ``). Asked only of a file that does not parse, so an
    honest file is never told.

    Returns:
        ``(line, column, message, hint)``, 1-based, or ``None``.
    """
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.lstrip().lstrip("\ufeff")
        col = len(line) - len(stripped) + 1
        if stripped.startswith("```"):
            return (
                number,
                col,
                "this line is a Markdown code fence (```), copied with the mission",
                "take away each ``` line: the file holds the mission alone",
            )
        if _COMMAND.match(stripped):
            return (
                number,
                col,
                "this line is a command typed in a terminal, copied with the mission",
                "take it away: type commands in the terminal, and keep the file for the mission",
            )
        if not python:
            continue
        for prompt, what, hint in _PROMPTS:
            if prompt.match(stripped):
                return number, col, f"this line starts with {what}, copied with the code", hint
    return None


_DOCUMENTS = {
    ".docx": "a Word document",
    ".doc": "a Word document",
    ".odt": "a LibreOffice document",
    ".rtf": "a rich-text document",
    ".pages": "a Pages document",
    ".pdf": "a PDF",
    ".gdoc": "a Google Docs link",
}


def wrong_ending(path: str | Path) -> str | None:
    """How to save a mission kept in a file whose name ends otherwise than a mission's
    (``m.yaml.txt``, ``m.docx``), or ``None`` when nothing more fitting than a file of a like
    name beside it can be said."""
    name = Path(path).name
    suffix = Path(path).suffix.lower()
    inner = Path(Path(path).stem).suffix.lower()
    if suffix == ".txt" and inner in (".yaml", ".yml", ".py"):
        return (
            f"rename it to {Path(path).stem}: the editor added '.txt', which Windows hides"
            " from the file's name"
        )
    document = _DOCUMENTS.get(suffix)
    if document is not None:
        return (
            f"{name} is {document}, not plain text: copy the mission into a plain-text editor"
            f" (the one you write code in) and save it as {Path(path).stem}.yaml, or .py for a"
            " Python mission"
        )
    if suffix == ".txt":
        return (
            f"save it as {Path(path).stem}.yaml, or {Path(path).stem}.py for a Python"
            " mission: the ending tells roboscript how to read it"
        )
    return None
