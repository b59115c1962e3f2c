"""Code students wrote: importing their files, and telling them in their terms what went wrong.

Python missions and behaviour files are ordinary Python: importing one runs it with the
student's permissions, so roboscript never imports one unless a student asked for it (by
running or checking a mission). Teachers who grade untrusted submissions run each one in a
separate process.

Two kinds of trouble are reported here:

* at load time, a file that does not import (a syntax error, an exception, an unknown name):
  :func:`import_student_file` raises a :class:`~roboscript.errors.MissionError` located at the
  student's line, with a "did you mean" where one fits;
* at run time, an exception raised by a student's behaviour or condition method:
  :func:`student_fault` turns it into one sentence, ``your behaviour 'spin' raised
  ZeroDivisionError in state 'go': division by zero (spin.py:14)``, and the mission ends in
  failure instead of the program crashing (the traceback goes to the debug log).
"""

from __future__ import annotations

# ast and inspect at module level: roboscript.actions.base and roboscript.mission.guards,
# which this module imports below, import both anyway, so no path that loads this module
# spares their cost (python -X importtime -c "import roboscript.mission.student_code": with
# or without these lines, ast and inspect are each imported once, ~2 ms and ~5 ms).
import ast
import builtins
import functools
import hashlib
import importlib.machinery
import importlib.util
import inspect
import linecache
import logging
import re
import sys
import traceback
import warnings
from dataclasses import FrozenInstanceError, dataclass, fields
from pathlib import Path
from types import FrameType, ModuleType, TracebackType
from typing import Any

import roboscript
from roboscript.actions.base import (
    Action,
    ActionContext,
    UnderSpecifiedError,
    UpdateReturnError,
    params_of,
)
from roboscript.capabilities import CAPABILITY_NAMES
from roboscript.code_owner import is_student_class, is_student_file, raised_by_roboscript
from roboscript.errors import (
    LinkError,
    MissionError,
    RoboscriptError,
    did_you_mean,
    nearby_file,
    pasted_with_it,
)
from roboscript.inputs.quantities import (
    CLOCK,
    CURLY_QUOTES,
    DASHES,
    DIMENSIONS,
    clock_reading,
    without_leading_zeros,
)
from roboscript.mission.error_column import error_column
from roboscript.mission.guards import guard_names
from roboscript.mission.key_mistakes import meant_in_state_call
from roboscript.mission.python_api import LOADED_PREFIX, Mission, state
from roboscript.mission.roboscript_kept import Change, RoboscriptKept, changes_written
from roboscript.profiles import PROFILE_FILE_KEYS, BuiltinsKept
from roboscript.robot_profile import RobotProfile
from roboscript.watchdog import CodePlace, RunawayCode

__all__ = [
    "PASSES_THROUGH_STUDENT_CODE",
    "EndlessCalls",
    "StudentCodeError",
    "calls_without_end",
    "import_student_file",
    "is_student_class",
    "is_student_file",
    "loop_around",
    "message_of",
    "passes_through",
    "shown_path",
    "stuck_at",
    "student_fault",
]

PASSES_THROUGH_STUDENT_CODE: tuple[type[BaseException], ...] = (
    KeyboardInterrupt,
    GeneratorExit,
    RunawayCode,
)
"""What may come out of a student's code without being the student's error: a signal
(Ctrl-C, SIGTERM, SIGHUP), a generator being closed, and the watchdog stopping code that does
not return. Everything else a student's code raises, ``exit()`` and a class of their own
derived from ``BaseException`` included, is the student's mistake: it ends their mission (or
refuses their file) in their terms, never the program."""

logger = logging.getLogger(__name__)

# (resolved path, modification time, size) -> module; a file is imported once per version, so
# a behaviour class keeps its identity between `check` and `run` in one process.
_IMPORTED: dict[tuple[str, int, int], ModuleType] = {}


def shown_path(path: str | Path) -> str:
    """``path`` as a student would type it: relative to the working directory when inside it."""
    try:
        return str(Path(path).resolve().relative_to(Path.cwd().resolve()))
    except (ValueError, OSError):
        return str(path)


def _student_frame(tb: TracebackType | None) -> traceback.FrameSummary | None:
    """The innermost frame of the traceback that runs a student's file."""
    found = None
    for frame in traceback.extract_tb(tb):
        if is_student_file(frame.filename):
            found = frame
    return found


def stuck_at(frame: FrameType | None) -> CodePlace | None:
    """Where running code is, in the student's terms: ``spin.py:14 in update``.

    Args:
        frame: The innermost running frame (a signal handler's ``frame``).

    Returns:
        The innermost frame that runs a student's file, or None when none does.
    """
    while frame is not None:
        code = frame.f_code
        if is_student_file(code.co_filename):
            line = frame.f_lineno
            return CodePlace(
                shown_path(code.co_filename),
                line,
                _written_in(frame),
                loop_around(code.co_filename, line),
            )
        frame = frame.f_back
    return None


_LOOP_SOURCE_CHARS = 1_000_000
"""Longest file whose loops are looked for when its code is stopped (a bigger one is named
by the line it was stopped on)."""

_SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)


@functools.lru_cache(maxsize=8)
def _loops_and_scopes(source: str) -> tuple[ast.stmt | ast.expr, ...]:
    """Every loop and every function, lambda and class of ``source``: read once per file's
    text, as a stuck loop is located again each time its stop is raised again."""
    try:
        tree = ast.parse(source)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return ()
    kinds = (*_SCOPES, ast.While, ast.For, ast.AsyncFor)
    return tuple(node for node in ast.walk(tree) if isinstance(node, kinds))


def loop_around(filename: str, line: int) -> int | None:
    """The first line of the loop ``line`` runs in: the innermost ``while`` around it in the
    function (or class body, or module) it is written in, else the innermost ``for``.

    A loop that never ends is mostly written with ``while``; one inside a ``for`` that ends
    is the ``while``, and a ``while True:`` around a short ``for`` is the ``while``.

    Returns:
        The loop's first line, or None when ``line`` is in no loop or the file cannot be read.
    """
    lines = linecache.getlines(filename)
    if not lines or sum(map(len, lines)) > _LOOP_SOURCE_CHARS:
        return None
    around = [
        node
        for node in _loops_and_scopes("".join(lines))
        if node.lineno <= line <= (node.end_lineno or node.lineno)
    ]
    scope_line = max((n.lineno for n in around if isinstance(n, _SCOPES)), default=0)
    loops = [n for n in around if not isinstance(n, _SCOPES) and n.lineno >= scope_line]
    whiles = [n.lineno for n in loops if isinstance(n, ast.While)]
    fors = [n.lineno for n in loops if not isinstance(n, ast.While)]
    return max(whiles or fors, default=None)


_COMPREHENSIONS = frozenset({"<listcomp>", "<setcomp>", "<dictcomp>", "<genexpr>"})
"""The names Python gives the code of a comprehension or a generator expression: no name a
student wrote, so a place inside one is named after the function it is written in."""


def _written_in(frame: FrameType) -> str:
    """The function ``frame``'s code is written in: its own name, or for a comprehension or
    a generator expression the name of the function around it (``<module>`` at the top)."""
    if frame.f_code.co_name not in _COMPREHENSIONS:
        return frame.f_code.co_name
    qualname = getattr(frame.f_code, "co_qualname", None)  # Python 3.11 and later
    if qualname is not None:
        names = [n for n in qualname.split(".") if n not in _COMPREHENSIONS and n != "<locals>"]
        return names[-1] if names else "<module>"
    outer = frame.f_back  # before 3.11: the frame that runs it, where it is written
    while outer is not None and outer.f_code.co_name in _COMPREHENSIONS:
        outer = outer.f_back
    return "<module>" if outer is None else outer.f_code.co_name


def _where(frame: traceback.FrameSummary | None) -> str | None:
    if frame is None:
        return None
    return f"{shown_path(frame.filename)}:{frame.lineno}"


# --------------------------------------------------------------------------------- run time


class StudentCodeError(RoboscriptError, RuntimeError):
    """Student code (a behaviour or a condition method) raised or misbehaved while running.

    Attributes:
        what: What the student wrote, for the sentence (``behaviour 'spin'``,
            ``condition 'four_sides_done'``).
        error: The exception it raised, or ``None``.
        problem: What it did instead of raising (``returned None``), or ``None``.
        fix: What to write instead, said after the state, or ``None``.
        where: ``file:line`` in the student's file, or ``None``.
    """

    def __init__(
        self,
        what: str,
        error: BaseException | None = None,
        *,
        problem: str | None = None,
        fix: str | None = None,
        where: str | None = None,
    ) -> None:
        self.what = what
        self.error = error
        self.problem = problem
        self.fix = fix
        self.where = where
        self.endless = calls_without_end(error) if problem is None else None
        """What a RecursionError was, in the student's terms, or ``None``."""
        if self.endless is not None and where is None:
            self.where = self.endless.where  # the call that repeats, not where the limit hit
        elif where is None and error is not None:
            self.where = _where(_student_frame(error.__traceback__))
        super().__init__(self.reason(None))

    def reason(self, state: str | None) -> str:
        """The one sentence a student reads, naming the state when it is known."""
        did = self.problem or f"raised {type(self.error).__name__}"
        detail = message_of(self.error) if self.error is not None and self.problem is None else ""
        meant = _attribute_meant(self.error) if self.problem is None else None
        if meant is not None:  # ctx.drive_base.set_speed: Python suggests only in a traceback
            detail += f" ({meant})"
        if isinstance(self.error, SystemExit) and self.problem is None:
            did = "called exit()"
            detail = "a mission ends by going to a final state, not by ending the program"
        fix = self.fix
        local = _LOCAL_UNSET.search(detail) if isinstance(self.error, UnboundLocalError) else None
        if local is not None and self.problem is None:  # count += 1 on a name of the file
            name = local.group(1)
            did = f"read '{name}' before giving it a value"
            detail = (
                f"a method that sets '{name}' has a '{name}' of its own, which starts with no"
                " value each time the method runs"
            )
            fix = f"keep it on the mission: write self.{name} (with {name} = 0 in the class)"
        if self.endless is not None:
            did, detail, fix = "never returned", self.endless.sentence, self.endless.fix
        text = f"your {self.what} {did}"
        if state is not None:
            text += f" in state '{state}'"
        if detail:
            text += f": {detail}"
        if fix:
            text += f"; {fix}"
        if self.where:
            text += f" ({self.where})"
        return text


def message_of(error: BaseException) -> str:
    """``str(error)``, or a sentence saying it could not be shown: a student's exception class
    may define a ``__str__`` that raises (even a ``BaseException`` of their own), and telling
    the student so must not fail."""
    try:
        return str(error)
    except PASSES_THROUGH_STUDENT_CODE:
        raise
    except BaseException as problem:  # noqa: BLE001 - whatever a student's __str__ raises
        return f"(its message cannot be shown: its __str__ raised {type(problem).__name__})"


_LOCAL_UNSET = re.compile(r"local variable '(\w+)'")


def _attribute_meant(error: BaseException | None) -> str | None:
    """``did you mean 'set_wheel_speeds'?`` for an ``AttributeError`` whose object has a
    look-alike of the missing name, else ``None``."""
    if not isinstance(error, AttributeError) or not isinstance(error.name, str):
        return None
    try:
        names = [name for name in dir(error.obj) if not name.startswith("_")]
    except Exception:  # noqa: BLE001 - a student's object may refuse dir()
        return None
    if isinstance(error.obj, ActionContext) and error.name in CAPABILITY_NAMES:
        # ctx.range.distance_cm, as a condition reads self.range: a behaviour asks ctx.get
        shown = _READ_IN_A_BEHAVIOUR.get(error.name, "")
        return (
            f'a behaviour reads the robot\'s {error.name} with ctx.get("{error.name}"):'
            f' write ctx.get("{error.name}"){shown}'
        )
    if isinstance(error.obj, Mission):
        # self.count += 1 with no count yet: a value, not a method, is what was meant
        kind = type(error.obj)
        values = [n for n in names if not inspect.isfunction(inspect.getattr_static(kind, n, None))]
        return did_you_mean(error.name, values) or (
            f"self.{error.name} is read before anything sets it: give it a first value in the"
            f" class, {error.name} = 0"
        )
    return did_you_mean(error.name, names)


_READ_IN_A_BEHAVIOUR = {
    "range": ".distance_mm() (mm, or None for no echo)",
    "side_range": ".distance_mm() (mm, or None for no echo)",
    "bumper": '.pressed() (the set of pressed switches, e.g. {"left"})',
    "line": ".values() (0 for white to 1023 for black)",
    "heading": ".heading_deg() (degrees clockwise)",
}
"""How a behaviour reads each sensor it most often reads, as write-your-own-behaviour.md
shows it."""


@dataclass(frozen=True)
class EndlessCalls:
    """Student code that called itself (or two functions each other) until Python's limit on
    calls in progress ran out: a ``RecursionError``, in the student's terms.

    Attributes:
        sentence: What happened (``'close' calls itself again and again, ...``).
        fix: What to do about it.
        where: ``file:line`` of the call that repeats, as the student names the file.
        line: That line, and ``filename`` its file as Python names it.
    """

    sentence: str
    fix: str
    where: str
    filename: str
    line: int


_ENDLESS_TAIL = 60
"""How many of the innermost frames of a RecursionError show which calls repeat."""


def calls_without_end(error: BaseException | None) -> EndlessCalls | None:
    """What a ``RecursionError`` out of a student's code was, in the student's terms, or
    ``None`` for any other exception (or one whose repeating calls are not a student's).

    The innermost frames of such a traceback are the same few functions over and over: the
    student's among them name the function (or functions) that never stop calling.
    """
    if not isinstance(error, RecursionError):
        return None
    frames = [f for f in traceback.extract_tb(error.__traceback__) if is_student_file(f.filename)]
    tail = frames[-_ENDLESS_TAIL:]
    counts: dict[tuple[str, str], int] = {}
    for frame in tail:
        counts[frame.filename, frame.name] = counts.get((frame.filename, frame.name), 0) + 1
    first_seen: dict[tuple[str, str], int] = {}
    for index, frame in enumerate(frames):
        first_seen.setdefault((frame.filename, frame.name), index)
    # the outermost first: the function the student's code called to begin with
    repeating = sorted((k for k, n in counts.items() if n >= 3), key=first_seen.__getitem__)
    if not repeating:
        return None
    first = repeating[0]
    lines = [f.lineno for f in tail if (f.filename, f.name) == first and f.lineno is not None]
    line = max(set(lines), key=lines.count)  # the call that repeats, not where the limit hit
    names = [f"'{name}'" for _, name in repeating]
    who = (
        f"{names[0]} calls itself"
        if len(names) == 1
        else f"{', '.join(names[:-1])} and {names[-1]} call each other"
    )
    return EndlessCalls(
        f"{who} again and again, more deeply than Python allows",
        "give it a way to return a value without calling itself"
        if len(names) == 1
        else "give one of them a way to return a value without calling the other",
        f"{shown_path(first[0])}:{line}",
        first[0],
        line,
    )


def _student_action(tb: TracebackType | None) -> Any:
    """The outermost student-written action running in the traceback, or ``None``.

    Outermost, so that a behaviour calling its own helpers is named, and a built-in
    composite action running a student's behaviour blames the behaviour, not itself.
    """
    for frame, _ in traceback.walk_tb(tb):
        owner = frame.f_locals.get("self")
        if isinstance(owner, Action) and is_student_class(type(owner)):
            return owner
    return None


def student_fault(exc: BaseException, state: str) -> str | None:
    """Describe ``exc`` as a student's mistake, or return ``None`` if it is not one.

    Args:
        exc: An exception raised while a mission ran.
        state: The state the mission was in.

    Returns:
        One sentence naming the behaviour or condition, the state and the exception, when
        ``exc`` came out of code a student wrote; ``None`` for anything else (a roboscript
        bug, or a lost link, which is the robot's fault, not the student's).
    """
    if isinstance(exc, LinkError):
        return None
    if isinstance(exc, StudentCodeError):
        fault = exc
    elif isinstance(exc, UpdateReturnError):
        action = _student_action(exc.__traceback__)
        name = getattr(type(action), "name", type(action).__name__)
        where = f"{shown_path(exc.filename)}:{exc.line}"
        fault = StudentCodeError(
            f"behaviour '{name}'", problem=exc.problem, fix=exc.fix, where=where
        )
    else:
        action = _student_action(exc.__traceback__)
        if action is None:
            return None
        name = getattr(type(action), "name", type(action).__name__)
        fault = StudentCodeError(f"behaviour '{name}'", exc)
    reason = fault.reason(state)
    logger.debug("%s", reason, exc_info=fault.error or fault)
    return reason


# -------------------------------------------------------------------------------- load time


def import_student_file(path: str | Path, *, kind: str = "mission") -> ModuleType:
    """Import a student's Python file as a module of its own.

    The file's folder is put first on ``sys.path`` while it is imported, as ``python FILE``
    would, so it can import files beside it. A file is imported once per version of its
    contents (modification time and size).

    Args:
        path: The ``.py`` file, as the student named it (used in messages).
        kind: ``mission`` or ``behaviour``, for messages.

    Returns:
        The module.

    Raises:
        MissionError: The file cannot be read, has a syntax error, or raised while it was
            imported; located at the student's line, with a hint where one fits.
    """
    file = Path(path)
    try:
        stat = file.resolve().stat()
    except OSError as exc:
        raise MissionError(
            f"cannot read the file: {exc.strerror}", path=str(path), hint=nearby_file(path)
        ) from None
    key = (str(file.resolve()), stat.st_mtime_ns, stat.st_size)
    if key in _IMPORTED:
        return _IMPORTED[key]
    digest = hashlib.sha1(key[0].encode("utf-8")).hexdigest()[:10]  # a module name, not security
    stem = re.sub(r"\W", "_", file.stem)
    name = f"{LOADED_PREFIX}{kind}_{stem}_{digest}"
    # read as Python source whatever the case of its ending (nap.PY, saved so on Windows)
    loader = (
        importlib.machinery.SourceFileLoader(name, str(file.resolve()))
        if file.suffix.lower() == ".py"
        else None
    )
    spec = importlib.util.spec_from_file_location(name, file.resolve(), loader=loader)
    if spec is None or spec.loader is None:
        raise MissionError(f"a {kind} file is a Python file ending in .py", path=str(path))
    module = importlib.util.module_from_spec(spec)
    folder = str(file.resolve().parent)
    sys.modules[name] = module  # classes look their module up here (inspect, dataclasses)
    sys.path.insert(0, folder)
    kept = BuiltinsKept()
    own = RoboscriptKept()
    try:
        with warnings.catch_warnings():
            # told below as this file's own mistake, at its line, rather than as Python's
            warnings.filterwarnings("ignore", '"is( not)?" with', SyntaxWarning)
            spec.loader.exec_module(module)
        changed = kept.changed()
        changes = own.changed()
        tree = _tree(module)  # once for each rule read from the file's text
        if changed:
            raise _builtin_changed(changed, path, tree)
        _refuse_changes(changes, path, module, tree)
        _refuse_is_with_a_value(path, tree)
    except SyntaxError as exc:
        del sys.modules[name]
        raise _syntax_problem(exc, path) from None
    except MissionError:
        del sys.modules[name]
        raise
    except BaseException as exc:  # reported in the student's terms, or passed through
        del sys.modules[name]
        kept.changed()  # a change made before the exception is undone too
        own.changed()
        if passes_through(exc):  # stopped while it ran (a loop at its top, Ctrl-C)
            raise
        raise _import_problem(exc, path, module, kind) from None
    finally:
        if folder in sys.path:
            sys.path.remove(folder)
    _IMPORTED[key] = module
    return module


def passes_through(exc: BaseException) -> bool:
    """Whether ``exc``, come out of a student's code, is not the student's mistake (one of
    :data:`PASSES_THROUGH_STUDENT_CODE`). A ``GeneratorExit`` the student's own line raised
    (its innermost frame is the student's) is theirs; one thrown in where the code waited (a
    generator being closed) comes out of roboscript's or Python's code, and passes."""
    if not isinstance(exc, PASSES_THROUGH_STUDENT_CODE):
        return False
    frames = traceback.extract_tb(exc.__traceback__)
    raised_by_student = bool(frames) and is_student_file(frames[-1].filename)
    return not (isinstance(exc, GeneratorExit) and raised_by_student)


def _refuse_is_with_a_value(path: str | Path, tree: ast.Module | None) -> None:
    """Refuse ``x is 20`` (or ``is "go"``) in the file's ``tree``: ``is`` asks whether two
    things are one object, which a number read from a sensor never is, so the comparison is
    always false."""
    for node in ast.walk(tree or ast.Module(body=[], type_ignores=[])):
        if not isinstance(node, ast.Compare):
            continue
        sides = [node.left, *node.comparators]
        for op, left, right in zip(node.ops, sides[:-1], sides[1:], strict=True):
            value = next(
                (
                    side.value
                    for side in (left, right)
                    if isinstance(side, ast.Constant)
                    and isinstance(side.value, int | float | str | bytes)
                    and not isinstance(side.value, bool)
                ),
                _NOTHING,
            )
            if isinstance(op, ast.Is | ast.IsNot) and value is not _NOTHING:
                compare = "==" if isinstance(op, ast.Is) else "!="
                word = "is" if isinstance(op, ast.Is) else "is not"
                raise MissionError(
                    f"'{word} {value!r}' asks whether two things are one and the same object,"
                    f" which a value read from the robot never is, so it is always"
                    f" {'false' if compare == '==' else 'true'}",
                    path=str(path),
                    line=node.lineno,
                    col=node.col_offset + 1,
                    hint=f"compare values with {compare}: {ast.unparse(left)} {compare}"
                    f" {ast.unparse(right)}",
                )


_NOTHING = object()


def _refuse_changes(
    made: list[Change], path: str | Path, module: ModuleType, tree: ast.Module | None
) -> None:
    """Refuse a file that changes roboscript's classes or names (``made`` while it loaded,
    already put back), or has a line of its ``tree`` that would as it runs: at the first
    such line."""
    written = changes_written(module, tree)
    if written:
        node, change = written[0]
        line, col = getattr(node, "lineno", None), getattr(node, "col_offset", None)
    elif made:
        change, col = made[0], None
        line = _line_naming(tree, {made[0].name})
    else:
        return
    message, hint = change.sentence()
    raise MissionError(
        message, path=str(path), line=line, col=None if col is None else col + 1, hint=hint
    )


def _builtin_changed(
    changed: list[tuple[str, str]], path: str | Path, tree: ast.Module | None
) -> MissionError:
    """The error for a file that changed a built-in robot profile while it was loaded, at
    the first line that names the changed field."""
    robot, field = changed[0]
    line = _line_naming(tree, {f for _, f in changed})
    named = ", ".join(f for r, f in changed if r == robot)
    return MissionError(
        f"this file changes the built-in robot '{robot}' ({named}), and a built-in robot"
        " stays as it is built: the simulated robot would not have the change",
        path=str(path),
        line=line,
        hint=_robot_of_your_own(robot, field),
    )


def _profile_in(module: ModuleType) -> str:
    """The name of the robot profile the student's file holds, for the hint (``mirto`` when
    it holds none by a name of its own)."""
    found = [value.name for value in vars(module).values() if isinstance(value, RobotProfile)]
    return found[0] if found else "mirto"


def _robot_of_your_own(robot: str, field: str) -> str:
    """How to describe a robot that differs from the built-in ``robot`` in ``field``."""
    if field not in PROFILE_FILE_KEYS:
        return (
            f"'{field}' is the board's own, which no profile file changes: keep '{robot}' as it is"
        )
    return (
        f"a robot of your own is a profile file beside the mission, e.g. my_{robot}.yaml"
        f" holding 'extends: {robot}' and '{field}: ...'; then write robot = \"my_{robot}.yaml\""
    )


def _line_naming(tree: ast.Module | None, names: set[str]) -> int | None:
    """The first line of the student's file (its ``tree``) that names one of ``names`` as an
    attribute (``mirto.gains[...] = ...``) or as text (``setattr(mirto, "gains", ...)``)."""
    lines = [
        node.lineno
        for node in (ast.walk(tree) if tree is not None else ())
        if (isinstance(node, ast.Attribute) and node.attr in names)
        or (isinstance(node, ast.Constant) and node.value in names)
    ]
    return min(lines) if lines else None


def _syntax_problem(exc: SyntaxError, path: str | Path) -> MissionError:
    where = str(path)
    if exc.filename and Path(exc.filename).resolve() != Path(path).resolve():
        where = shown_path(exc.filename)
    pasted = pasted_with_it("".join(linecache.getlines(exc.filename or str(path))), python=True)
    if pasted is not None:  # >>> or ``` copied with the code: Python's own words would puzzle
        return MissionError(pasted[2], path=where, line=pasted[0], col=pasted[1], hint=pasted[3])
    message = exc.msg or "invalid syntax"
    if not message.startswith(("invalid syntax", "expected", "unexpected")):
        message = f"syntax error: {message}"
    hint = None
    if any(f"'{quote}'" in message for quote in CURLY_QUOTES):  # invalid character '“'
        hint = "a curly quote, as a word processor writes it: type straight quotes, \" or '"
    elif any(f"'{dash}'" in message for dash in DASHES):
        hint = "a dash, as a word processor writes a minus: type the minus key, -"
    elif (typed := _typed_number_hint(exc.msg or "", exc.text or "")) is not None:
        hint = typed  # 010, 5O0, 90°, 1:30
    elif isinstance(exc, TabError):
        hint = "indent with spaces only: a tab looks like spaces but Python counts it apart"
    elif _YAML_MISSION.match(exc.text or "") and exc.lineno is not None and exc.lineno <= 3:
        hint = "this is a YAML mission: a YAML mission's file name ends in .yaml"
    elif (unit := _NUMBER_WITH_UNIT.search(exc.text or "")) is not None:
        hint = _without_unit(exc.text or "", unit)
    elif (other := _other_language(exc.text or "")) is not None:
        hint = other
    elif _def_inside_brackets(exc):
        hint = (
            "a def is a line of its own in the class, not a value inside state(...): write the"
            ' method below the states, and name it in quotes there, e.g. when=[("near", "end")]'
        )
    else:
        hint = next((h for start, h in _SYNTAX_HINTS if (exc.msg or "").startswith(start)), None)
    col = exc.offset
    if type(exc) is IndentationError and exc.text and exc.text.strip():  # a TabError: at the tab
        col = len(exc.text) - len(exc.text.lstrip()) + 1  # where the line's text starts
    return MissionError(message, path=where, line=exc.lineno, col=col, hint=hint)


_SYNTAX_HINTS = (
    (
        "unexpected indent",
        "this line is indented further than the line above it: line it up with its block",
    ),
    (
        "expected an indented block",
        "indent the lines that belong to it 4 spaces further than the line ending in ':'",
    ),
    (
        "unindent does not match",
        "line it up, with spaces, with the lines of the block it belongs to",
    ),
    (
        "expected ':'",
        "a line starting with class, def, if, elif, else, for or while ends with ':'",
    ),
)
"""Python's words for a beginner's syntax slip, and what to do about it."""

_ELIF = "Python writes 'else if' as elif: elif CONDITION:"
_AND_OR_NOT = "Python writes && as and, || as or, and ! as not"
_OTHER_LANGUAGE = tuple(
    (re.compile(pattern), hint)
    for pattern, hint in (
        (r"^\s*(?:else\s*:?\s*if|elseif|elsif)\b", _ELIF),
        (
            r"^\s*\}",
            "Python has no braces: a block is the lines indented under a line ending in ':'",
        ),
        (
            r"^\s*(?:if|elif|else|while|for|def|class)\b.*\{\s*$",
            "Python has no braces: end the line with ':' and indent the lines of its block",
        ),
        (r"^\s*function\b", "Python defines a function with def: def name(self):"),
        (
            r"^\s*(?:void|int|float|bool|char)\s+\w+\s*\(",
            "this line is C or Arduino code: a roboscript mission is written in Python or YAML",
        ),
        (r"<>", "Python writes 'is not equal to' as !="),
        (r"\b\d+[lL]\b", "a number in Python has no L at its end: write 500, not 500L"),
        (r"^\s*(?:var|let|const)\s+\w+\s*=", "Python needs no var or let: write name = value"),
        (r"&&|\|\||!\s*(?=self\b|\()", _AND_OR_NOT),
        (r"\b(?:AND|OR|NOT|And|Or|Not)\b", "Python writes and, or and not in lower case"),
        (
            r"\b(?:and|or)\s*(?:<|>|==|!=)",
            (
                "each side of and/or is a whole comparison: name the value again, e.g."
                " self.range.distance_cm < 20 and self.range.distance_cm > 5"
            ),
        ),
    )
)
"""A line of a program in another language (JavaScript, C, Java) where Python's slipped, and
how Python writes it."""

_NUMBER_WITH_UNIT = re.compile(r"\b(\d+(?:\.\d+)?)\s*(mm|cm|m|s|ms|sec|min|deg|Hz|hz)\b(?!\s*[=(])")
"""A number written with its unit in Python code (``< 20 cm``), which Python cannot read."""

_NAME_WITH_UNIT = re.compile(r"\b([a-z]\w*?)_(mm|cm|m|s|ms|deg|hz)\b")


def _def_inside_brackets(exc: SyntaxError) -> bool:
    """Whether the line Python could not read is a ``def`` written inside brackets, as a
    value of ``state(...)`` or a list (the line before it leaves a bracket open)."""
    if not (exc.text or "").lstrip().startswith("def ") or exc.lineno is None or not exc.filename:
        return False
    before = linecache.getline(exc.filename, exc.lineno - 1).split("#")[0].rstrip()
    return before.endswith(("(", "[", ",", "="))


def _other_language(line: str) -> str | None:
    """How Python writes what ``line`` wrote in another language, or ``None``."""
    return next((hint for pattern, hint in _OTHER_LANGUAGE if pattern.search(line)), None)


def _without_unit(line: str, found: re.Match[str]) -> str:
    """The hint for a number written with its unit in Python (``distance_mm=50 cm``): the
    number in the unit of the name before it (``500``), as far as the line shows one."""
    named = list(_NAME_WITH_UNIT.finditer(line[: found.start()]))
    number, unit = float(found.group(1)), found.group(2).lower()
    if named:
        name, name_unit = named[-1].group(0), named[-1].group(2)
        for dimension in DIMENSIONS.values():
            units = {u.lower(): f for u, f in dimension.units.items()}
            if unit in units and name_unit in units:
                value = number * units[unit] / units[name_unit]
                return (
                    f"a number in Python has no unit: for {found.group(0).strip()} write"
                    f" {value:g}, as {name} is in {name_unit}"
                )
    return "a number in Python has no unit: write it in the unit its name ends in (_cm, _mm, _s)"


_LEADING_ZEROS = re.compile(r"(?<![\w.])0[\d_]*\d")  # the digits Python points at
_LETTER_O = re.compile(r"(?<![\w.])\d*[Oo]+\d[\dOo]*|(?<![\w.])\d+[Oo]+(?![A-Za-z_])")
_CLOCK_IN_CODE = re.compile(rf"(\w+)\s*=\s*({CLOCK.pattern})")


def _typed_number_hint(message: str, line: str) -> str | None:
    """The fix for a number Python refuses as typed on line ``line`` (``010``, ``5O0``,
    ``90°``, ``1:30``), from Python's ``message`` about it; ``None`` for any other mistake.
    A clock's time and leading zeros are read by the rules YAML values are read by."""
    if message.startswith("leading zeros") and (found := _LEADING_ZEROS.search(line)):
        return f"write {without_leading_zeros(found.group())}, without the leading 0"
    if "invalid decimal literal" in message and (found := _LETTER_O.search(line)):
        written = found.group()
        return (
            f"'{written}' has the letter O where a zero was meant: write"
            f" {written.replace('O', '0').replace('o', '0')}"
        )
    if "'°' (U+00B0)" in message:
        return "a number in code has no unit sign: its keyword says the unit, e.g. angle_deg=90"
    if message == "invalid syntax" and (found := _CLOCK_IN_CODE.search(line)):
        seconds, read = clock_reading(found.group(2)) or (0.0, None)
        return (
            f"a time is one number in its keyword's unit: {f'for {read}, ' if read else ''}"
            f"write {found.group(1)}={seconds:g}"
        )
    return None


_YAML_MISSION = re.compile(r"\s*(?:mission|states|initial|robot|world)\s*:")
"""The first lines of a YAML mission (saved by mistake with a .py ending)."""


_UNEXPECTED_KEYWORD = re.compile(
    r"^(?:(\w+)\.)?(\w+)\(\) got an unexpected keyword argument '(\w+)'"
)
_MISSING_ARGUMENT = re.compile(
    r"^(?:(\w+)\.)?(\w+)\(\) missing \d+ required (?:positional |keyword-only )?argument"
)
_MORE_THAN_ONE_ACTION = re.compile(r"^state\(\) takes from 0 to 1 positional arguments? but")
_TOO_MANY_VALUES = re.compile(
    r"^(?:(\w+)\.)?(\w+)\(\) takes (?:from \d+ to )?\d+ positional arguments? but (\d+) were"
)
_MODULE_AS_BASE = re.compile(r"^module\(\) takes at most 2 arguments")
"""What Python says of ``class M(mission):`` when ``mission`` is a module."""
_MODULE_BASE = re.compile(r"^\s*class\s+(\w+)\s*\(\s*([\w.]+)")
_OTHER_WORDS = {
    "Behaviour": ("Action", "a behaviour of your own is a class that extends Action"),
    "Behavior": ("Action", "a behaviour of your own is a class that extends Action"),
    "State": ("state", "a state is made with state(...), in lower case"),
}
"""Names from the tutorials' words that roboscript spells otherwise: (its name, why)."""
_ABSTRACT = re.compile(r"^Can't instantiate abstract class (\w+) with abstract methods? (\w+)")
_FROZEN_FIELD = re.compile(r"^cannot assign to field '(\w+)'")
_CANNOT_IMPORT = re.compile(r"^cannot import name '(\w+)' from '([\w.]+)'")


def _import_problem(
    exc: BaseException, path: str | Path, module: ModuleType, kind: str
) -> MissionError:
    frame = _student_frame(exc.__traceback__)
    where, line, col = str(path), None, None
    if frame is not None:
        if Path(frame.filename).resolve() != Path(path).resolve():
            where = shown_path(frame.filename)
        line = frame.lineno
        colno = error_column(exc, frame)
        col = colno + 1 if colno is not None else None
    message, hint = _explain(exc, module, raised_by_roboscript(exc), kind, frame)
    return MissionError(message, path=where, line=line, col=col, hint=hint)


_OLD_UNBOUND = re.compile(r"^local variable '(\w+)' referenced before assignment$")
_UNBOUND = r"cannot access local variable '\1' where it is not associated with a value"
"""Python 3.10's words for an UnboundLocalError, and 3.11's, which say it as every Python
after: a student reads the same sentence whichever Python runs the mission."""


def _explain(
    exc: BaseException,
    module: ModuleType,
    raised_by_roboscript: bool,
    kind: str,
    frame: traceback.FrameSummary | None = None,
) -> tuple[str, str | None]:
    """A message and a hint for an exception raised while a student's file was imported
    (``frame``: the student's line it was raised at)."""
    text = _OLD_UNBOUND.sub(_UNBOUND, message_of(exc))
    colno = error_column(exc, frame) if frame is not None else None
    call = _call_at(module, frame, colno)
    if isinstance(exc, SystemExit):
        return f"the {kind} file called exit() while it was loaded", None
    line = linecache.getline(frame.filename, frame.lineno or 0) if frame is not None else ""
    if isinstance(exc, EOFError | OSError) and re.search(r"\binput\s*\(", line):
        return (
            (
                f"the {kind} file asks for input() while it is loaded, and a mission runs with no"
                " one at the keyboard"
            ),
            "write the value in the file instead, e.g. distance_mm = 300",
        )
    endless = calls_without_end(exc)
    if endless is not None:
        return endless.sentence, endless.fix
    frozen = _FROZEN_FIELD.match(text) if isinstance(exc, FrozenInstanceError) else None
    if frozen is not None and frozen.group(1) in {f.name for f in fields(RobotProfile)}:
        field = frozen.group(1)
        return (
            (
                f"a built-in robot profile cannot be changed ({field}): the simulated robot is"
                " made from the built-in robot as it is"
            ),
            _robot_of_your_own(_profile_in(module), field),
        )
    if isinstance(exc, UnderSpecifiedError) and raised_by_roboscript:
        return exc.python_message, f"write {exc.python}"
    if isinstance(exc, RoboscriptError | ValueError) and raised_by_roboscript:
        return text, None  # roboscript's own sentence, e.g. "drive speed must be positive"
    if isinstance(exc, TypeError):
        said = _explain_type_error(exc, text, module, call, frame)
        if said is not None:
            return said
    if isinstance(exc, NameError) and not isinstance(exc, UnboundLocalError):
        return _explain_name_error(exc, text, module, frame, colno)
    mission = _mission_class(getattr(exc, "obj", None))
    if isinstance(exc, AttributeError) and mission is not None:
        return f"a mission has no {exc.name}(): take this line away", (
            "roboscript run and python both run the mission a file defines; to say so in the"
            f' file, write {mission.__name__}.main() under if __name__ == "__main__":'
        )
    if isinstance(exc, ImportError):
        said = _explain_import_error(exc, text, module, kind)
        if said is not None:
            return said
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__, None


def _explain_type_error(
    exc: TypeError,
    text: str,
    module: ModuleType,
    call: ast.Call | None,
    frame: traceback.FrameSummary | None,
) -> tuple[str, str | None] | None:
    """A message and a hint for a ``TypeError`` of a call in the student's file (an action
    given a parameter it has not, too many values, ``state()`` given two actions, a module
    extended as a class), or ``None`` to say Python's own words."""
    abstract = _ABSTRACT.match(text)
    if abstract is not None:  # an Action without update(): Python will not make one
        return (
            (
                f"{abstract.group(1)} has no {abstract.group(2)}(self, ctx), the method roboscript"
                " calls on an action each tick"
            ),
            (
                f"write def {abstract.group(2)}(self, ctx): in the class, returning None while it"
                " runs and Result.done() when it has finished"
            ),
        )
    match = _UNEXPECTED_KEYWORD.match(text)
    if match:
        owner, func, keyword = match.groups()
        callee = _called_name(call) or (owner if func == "__init__" and owner else func)
        meant = meant_in_state_call(keyword) if callee == "state" else None
        return f"{callee}() has no parameter '{keyword}'", meant or _meant_parameter(
            callee, keyword, module, call
        )
    if _MORE_THAN_ONE_ACTION.match(text) and getattr(module, "state", None) is roboscript.state:
        fixed = _state_call_fixed(call)
        if fixed is not None:
            return fixed
        return "a state runs one action, and this state(...) was given more", (
            "to do one thing after another, give each its own state and go on with"
            ' on_done="NEXT"; to do them at the same time, write state(Parallel([...]), ...)'
        )
    match = _TOO_MANY_VALUES.match(text)
    if match:
        too_many = _values_without_names(match.group(1), int(match.group(3)) - 1, module)
        if too_many is not None:
            return too_many
    match = _MISSING_ARGUMENT.match(text)
    if match:
        owner, func = match.groups()
        callee = owner if func == "__init__" and owner else func
        return text.replace(f"{owner}.{func}()" if owner else f"{func}()", f"{callee}()"), None
    if _MODULE_AS_BASE.match(text) and frame is not None:
        base = _MODULE_BASE.search(linecache.getline(frame.filename, frame.lineno or 0))
        if base is not None and base.group(2).lower() in ("mission", "action"):
            cls, meant = base.group(1), base.group(2).capitalize()
            return f"'{base.group(2)}' is a module of roboscript, not a class to extend", (
                f"extend {meant}, with a capital {meant[0]}: from roboscript import {meant},"
                f" then class {cls}({meant}):"
            )
        if base is not None:
            return f"'{base.group(2)}' is a module, not a class to extend", None
    return None


def _explain_name_error(
    exc: NameError,
    text: str,
    module: ModuleType,
    frame: traceback.FrameSummary | None,
    colno: int | None,
) -> tuple[str, str | None]:
    """A message and a hint for a name the student's file uses and nothing defines: a
    roboscript name not imported, ``self`` in a class body, a state named without quotes, a
    name set further down, a module not imported, a unit written as a name."""
    line = linecache.getline(frame.filename, frame.lineno or 0) if frame is not None else ""
    name = getattr(exc, "name", None) or ""
    if name in _roboscript_names():
        return f"NameError: {text}", f"add 'from roboscript import {name}'"
    if name == "self" and frame is not None:
        meant = _self_in_class_body(line[colno or 0 :], module)
        if meant is not None:
            return f"NameError: {text}", meant
    what = _class_members(module).get(name)
    if what in ("action", "value"):  # turn = Rotate(...), size = 500: set below its use
        return f"NameError: {text}", (
            f"'{name}' is set further down in the class, but Python runs a class from the"
            " top: set it above the line that uses it"
        )
    if what is not None:
        return f"NameError: {text}", f"a {what} is named in quotes: write '{name}'"
    below = _defined_at(module).get(name)
    if below is not None:
        return f"NameError: {text}", (
            f"'{name}' is defined further down, on line {below}, but Python runs a file"
            " from the top: define it above, or make it a method and name it in quotes:"
            f" '{name}'"
        )
    if name in sys.stdlib_module_names:
        return f"NameError: {text}", f"add 'import {name}' at the top of the file"
    times = re.search(rf"\b(\d+(?:\.\d+)?)\s*\*\s*{re.escape(name)}\b", line)
    if times is not None:  # distance_mm=50 * cm: a unit as a name, as some libraries have
        written = f"{line[: times.start()]}{times.group(1)} {name}"
        unit = _NUMBER_WITH_UNIT.search(written, times.start())
        if unit is not None:
            return f"NameError: {text}", _without_unit(written, unit)
    known = [*vars(module), *dir(builtins)]
    # only a close look-alike: "near" is not a misspelt "setattr"
    return f"NameError: {text}", did_you_mean(name, [*known, *_roboscript_names()], cutoff=0.7)


def _explain_import_error(
    exc: ImportError, text: str, module: ModuleType, kind: str
) -> tuple[str, str | None] | None:
    """A message and a hint for a module or name the student's file imports and cannot (another
    robot's library, roboscript misspelt, a file of theirs not beside it, a name roboscript
    has not), or ``None`` to say Python's own words."""
    top = (getattr(exc, "name", None) or "").split(".")[0]
    if isinstance(exc, ModuleNotFoundError) and top in _OTHER_ROBOTS_LIBRARIES:
        return _other_robots_library(top)
    if isinstance(exc, ModuleNotFoundError) and top.lower().replace("_", "") == "roboscript":
        return f"ModuleNotFoundError: {text}", "write it in lower case, in one word: roboscript"
    if isinstance(exc, ModuleNotFoundError) and exc.name and "." not in exc.name:
        file = Path(getattr(module, "__file__", None) or f"{kind}.py")
        return f"ModuleNotFoundError: {text}", (
            f"if '{exc.name}' is a file of yours, it must sit in the same folder as "
            f"{file.name}: {exc.name}.py, or a folder {exc.name}/ holding __init__.py"
        )
    match = _CANNOT_IMPORT.match(text)
    if match and match.group(2).startswith("roboscript.") and match.group(1) in _roboscript_names():
        return f"{match.group(2)} has no '{match.group(1)}' to import", (
            f"a mission imports from roboscript itself: write from roboscript import"
            f" {match.group(1)}"
        )
    if match and match.group(2) == "roboscript":
        name = match.group(1)
        other = _OTHER_WORDS.get(name)
        return f"roboscript has no '{name}' to import", (
            f"{other[1]}: write from roboscript import {other[0]}"
            if other is not None
            else did_you_mean(name, _roboscript_names())
        )
    return None


_OTHER_ROBOTS_LIBRARIES = {
    "pybricks": "Pybricks",
    "spike": "the LEGO SPIKE app",
    "mindstorms": "the LEGO MINDSTORMS app",
    "hub": "the LEGO SPIKE app",
    "motor": "the LEGO SPIKE app",
    "motor_pair": "the LEGO SPIKE app",
    "runloop": "the LEGO SPIKE app",
    "color_sensor": "the LEGO SPIKE app",
    "distance_sensor": "the LEGO SPIKE app",
    "force_sensor": "the LEGO SPIKE app",
    "ev3dev": "ev3dev (LEGO EV3)",
    "ev3dev2": "ev3dev (LEGO EV3)",
    "vex": "VEXcode",
    "vexiq": "VEXcode",
    "vexcode": "VEXcode",
    "vexcode_vr": "VEXcode VR",
    "microbit": "the micro:bit",
    "cyberpi": "mBlock (CyberPi)",
    "mbot": "mBlock (mBot)",
    "buildhat": "the Raspberry Pi Build HAT",
}
"""Libraries of code written for another robot's own software, which a student copies from
its examples: the modules a file imports first, and whose they are."""


def _other_robots_library(top: str) -> tuple[str, str]:
    """The sentence for a file importing ``top``, another robot's library, and the hint."""
    spike = (
        'write robot = "spike-prime" in the mission class; '
        if "SPIKE" in (_OTHER_ROBOTS_LIBRARIES[top]) or top == "pybricks"
        else ""
    )
    return (
        (
            f"'{top}' is a library of {_OTHER_ROBOTS_LIBRARIES[top]}, for code that runs on"
            " that robot's own software: a roboscript mission does not use it"
        ),
        (
            f"{spike}a mission is a class of states, e.g. from roboscript import Drive, Mission,"
            ' state, then go = state(Drive(distance_mm=500), initial=True, on_done="end")'
        ),
    )


def _mission_class(value: object) -> type[Mission] | None:
    """The Mission subclass ``value`` is, or is an object of (``Square().run()``), or None."""
    cls = value if isinstance(value, type) else type(value)
    return cls if issubclass(cls, Mission) else None


def _call_at(
    module: ModuleType, frame: traceback.FrameSummary | None, colno: int | None
) -> ast.Call | None:
    """The call in the student's file that failed (``frame``'s line, at 0-based ``colno``), or
    ``None``."""
    tree = _tree(module) if frame is not None and colno is not None else None
    if tree is None or frame is None:
        return None
    calls = [
        node
        for node in ast.walk(tree)
        if isinstance(node, ast.Call) and (node.lineno, node.col_offset) == (frame.lineno, colno)
    ]
    return calls[0] if len(calls) == 1 else None


def _called_name(call: ast.Call | None) -> str | None:
    """The name the student called, as written (``Turn`` for ``Turn(angle_deg=90)``, whose
    ``__init__`` Python names by the class that defines it, ``_GaitAction``), or ``None``."""
    if call is None:
        return None
    func = call.func
    return (
        func.id
        if isinstance(func, ast.Name)
        else func.attr
        if isinstance(func, ast.Attribute)
        else None
    )


def _state_call_fixed(call: ast.Call | None) -> tuple[str, str] | None:
    """``state(Drive(...), "end")`` or ``state(Drive(...), True, "end")``: values after the
    action without their names, said with the call written with them
    (``state(Drive(...), initial=True, on_done="end")``), or ``None`` for another mistake."""
    if call is None or len(call.args) < 2:
        return None
    routes = iter(("on_done", "on_failed", "on_timeout"))
    named = []
    for value in call.args[1:]:
        given = value.value if isinstance(value, ast.Constant) else None
        if isinstance(given, bool):
            named.append(f"initial={given}")
        elif isinstance(given, str) and (route := next(routes, None)) is not None:
            named.append(f'{route}="{given}"')
        else:
            return None  # another action, most likely: the general answer fits
    written = [ast.unparse(call.args[0]), *named, *(ast.unparse(k) for k in call.keywords)]
    return (
        "state() takes one action, and everything after it with its name",
        f"write state({', '.join(written)})",
    )


_SELF_ATTRIBUTE = re.compile(r"\bself\.(\w+(?:\.\w+)*)")


def _self_in_class_body(line: str, module: ModuleType) -> str | None:
    """``when=[(self.bumper_hit, "stuck")]`` in the class body, where there is no ``self``:
    a condition method is named in quotes, a sensor's reading written as text."""
    found = _SELF_ATTRIBUTE.search(line)
    if found is None:
        return None
    written = found.group(1)
    what = _class_members(module).get(written)
    if what in ("condition", "state"):
        return f"a {what} is named in quotes, without 'self.': write '{written}'"
    if written.split(".")[0] in {name.split(".")[0] for name in guard_names()}:
        return f"a condition written as text names the sensors without 'self.': write '{written}'"
    return None


def _meant_parameter(
    callee: str, keyword: str, module: ModuleType, call: ast.Call | None
) -> str | None:
    """What ``callee(keyword=...)`` meant: the parameter in its own unit, with the value
    converted (``distance_cm=50``: write ``distance_mm=500``), a look-alike, or the
    parameters there are."""
    cls = _action_class(callee, module)
    if cls is not None and keyword.lower() in cls.guessed_params:
        return cls.guessed_params[keyword.lower()]
    if cls is not None:
        given = [k.value for k in call.keywords if k.arg == keyword] if call is not None else []
        value = given[0].value if given and isinstance(given[0], ast.Constant) else None
        for param in params_of(cls):
            written = param.in_its_unit(keyword, value)
            if written is not None:
                return f"write {written}"
    names = _parameters(callee, module)
    return did_you_mean(keyword, names) or (
        f"its parameters: {', '.join(names)}" if names else None
    )


def _values_without_names(
    owner: str | None, given: int, module: ModuleType
) -> tuple[str, str] | None:
    """``Drive(500, 150, 2, 9)``: an action given more values without their names than it
    takes, said with the names that take them, or ``None`` for another callee (a student's
    own function keeps Python's message, at its line). ``given`` excludes ``self``."""
    cls = _action_class(owner or "", module)
    if cls is None:
        return None
    try:
        parameters = inspect.signature(cls).parameters.values()
    except (TypeError, ValueError):
        return None
    kinds = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    takes = [p.name for p in parameters if p.kind in kinds]
    values = "value" if len(takes) == 1 else "values"
    message = (
        f"{cls.__name__}() takes at most {len(takes)} {values} without their names, and was"
        f" given {given}"
    )
    return message, f"name each value: write {cls.__name__}({', '.join(f'{n}=...' for n in takes)})"


def _action_class(name: str, module: ModuleType) -> type[Action] | None:
    """The action class ``name`` stands for in the student's file: one of the student's own
    (``class Spin(Action)`` above, or imported from a file beside it) first, then
    roboscript's; ``None`` when ``name`` is no action class."""
    cls = getattr(module, name, None) or getattr(roboscript, name, None)
    return cls if isinstance(cls, type) and issubclass(cls, Action) else None


def _class_members(module: ModuleType) -> dict[str, str]:
    """What the student's file defines in a class body, by name: ``state`` for an assignment
    (the states of a mission), ``condition`` for a method, ``action`` for an action kept for
    states to run (``turn = Rotate(angle_deg=90)``, or ``turn = Spin()`` of the student's own
    action class), ``value`` for a number or text kept
    (``side_mm = 500``).

    Read from the source, since the class that defines them is still being built when a
    state refers to a later one without quotes."""
    tree = _tree(module)
    if tree is None:
        return {}
    members: dict[str, str] = {}
    for node in ast.walk(tree):
        if not isinstance(node, ast.ClassDef):
            continue
        for statement in node.body:
            if isinstance(statement, ast.FunctionDef):
                members.setdefault(statement.name, "condition")
            targets = (
                statement.targets
                if isinstance(statement, ast.Assign)
                else [statement.target]
                if isinstance(statement, ast.AnnAssign)
                else []
            )
            value = getattr(statement, "value", None)
            called = value.func if isinstance(value, ast.Call) else None
            kept = isinstance(called, ast.Name) and _action_class(called.id, module) is not None
            plain = isinstance(value, ast.Constant)
            for target in targets:
                if isinstance(target, ast.Name):
                    members[target.id] = "action" if kept else "value" if plain else "state"
    return members


def _tree(module: ModuleType) -> ast.Module | None:
    """The student's file parsed, or ``None`` if it cannot be read."""
    try:
        return ast.parse(Path(module.__file__ or "").read_bytes())
    except (OSError, SyntaxError, ValueError, RecursionError, MemoryError):
        return None


def _defined_at(module: ModuleType) -> dict[str, int]:
    """The line of each function, class or variable the file defines at its top level."""
    tree = _tree(module)
    lines: dict[str, int] = {}
    for statement in tree.body if tree is not None else []:
        if isinstance(statement, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            lines.setdefault(statement.name, statement.lineno)
        elif isinstance(statement, ast.Assign):
            for target in statement.targets:
                if isinstance(target, ast.Name):
                    lines.setdefault(target.id, statement.lineno)
    return lines


def _roboscript_names() -> list[str]:
    return list(getattr(roboscript, "__all__", []))


def _parameters(callee: str, module: ModuleType) -> list[str]:
    target = getattr(module, callee, None)
    if target is None:
        target = getattr(roboscript, callee, None) if callee[:1].isupper() else None
        if callee == "state":
            target = state
    try:
        return list(inspect.signature(target).parameters) if callable(target) else []
    except (TypeError, ValueError):
        return []
