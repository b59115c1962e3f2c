"""The column of a student's line that an exception was raised at, on every Python roboscript
runs on.

Python 3.11 and later keep it in each traceback entry (``FrameSummary.colno``); Python 3.10
keeps only the line. There the column is found in the line's syntax tree: the part of the
statement that the exception names (the unknown name, the missing attribute, the keyword no
parameter has, the division by zero), or the call that ran the function that raised, or the
one call the line holds. A line where none of those picks one part is told without a column,
never at a guessed one.
"""

from __future__ import annotations

import ast
import linecache
import re
import traceback
from types import FrameType

__all__ = ["error_column", "python_column"]

_NAMED = re.compile(r"(?:name|local variable) '(\w+)'")
_ATTRIBUTE = re.compile(r"(?:attribute|field) '(\w+)'")
_KEYWORD = re.compile(r"got an unexpected keyword argument '(\w+)'")
_CALLED = re.compile(
    r"^(?:(\w+)\.)?(\w+)\(\) (?:missing|takes|got)|^Can't instantiate abstract class (\w+)"
)
"""Python's words for a call it refused before running the function: the name it was called by
(a class's for its ``__init__``)."""
_METHODS_OF_A_CLASS = frozenset({"__init__", "__new__", "__post_init__", "__init_subclass__"})
"""Functions a call of a class runs: the call is written with the class's name."""


def python_column(frame: traceback.FrameSummary) -> int | None:
    """The 0-based column Python itself kept for ``frame`` (3.11 and later), or ``None``."""
    colno: int | None = getattr(frame, "colno", None)
    return colno


def error_column(exc: BaseException, frame: traceback.FrameSummary) -> int | None:
    """The 0-based column of ``frame``'s line at which ``exc`` was raised, or ``None``.

    Args:
        exc: The exception, with its traceback.
        frame: The traceback entry of the student's line (``exc``'s own traceback holds it).

    Returns:
        Python's own column where it keeps one, else the column of the part of the line's
        statement the exception points at, or ``None`` when no one part is certain.
    """
    kept = python_column(frame)
    if kept is not None:
        return kept
    try:
        return _column_from_source(exc, frame)
    except (SyntaxError, ValueError, RecursionError, MemoryError):  # a file changed since
        return None


def _column_from_source(exc: BaseException, frame: traceback.FrameSummary) -> int | None:
    line = frame.lineno
    if line is None:
        return None
    tree = ast.parse("".join(linecache.getlines(frame.filename)))
    statement = _innermost_statement(tree, line)
    if statement is None:
        return None
    if isinstance(statement, ast.Import | ast.ImportFrom) and isinstance(exc, ImportError):
        return statement.col_offset
    parts = [
        node
        for node in ast.walk(statement)
        if isinstance(node, ast.expr) and node.lineno <= line <= (node.end_lineno or node.lineno)
    ]
    found = _named_part(exc, parts) or _call_of(_callees(exc, frame), parts)
    itself = isinstance(statement, ast.Raise | ast.Assert | ast.ClassDef)
    if found is None and itself and _raised_on_the_line(exc, frame):  # the statement raised
        return statement.col_offset if statement.lineno == line else None
    if found is None:
        calls = [node for node in parts if isinstance(node, ast.Call) and node.lineno == line]
        found = calls[0] if len(calls) == 1 else None
    return found.col_offset if found is not None and found.lineno == line else None


def _innermost_statement(tree: ast.Module, line: int) -> ast.stmt | None:
    """The smallest statement that spans ``line``."""
    spanning = [
        node
        for node in ast.walk(tree)
        if isinstance(node, ast.stmt) and node.lineno <= line <= (node.end_lineno or node.lineno)
    ]
    return min(
        spanning, key=lambda node: (node.end_lineno or node.lineno) - node.lineno, default=None
    )


def _named_part(exc: BaseException, parts: list[ast.expr]) -> ast.expr | None:
    """The part of the line the exception names: an unknown name, a missing attribute, a
    keyword no parameter has, a division."""
    found: list[ast.expr] = []
    if isinstance(exc, NameError):
        named = getattr(exc, "name", None) or _first(_NAMED, str(exc))
        found = [node for node in parts if isinstance(node, ast.Name) and node.id == named]
    elif isinstance(exc, AttributeError):  # a frozen field too: "cannot assign to field 'x'"
        named = getattr(exc, "name", None) or _first(_ATTRIBUTE, str(exc))
        found = [node for node in parts if isinstance(node, ast.Attribute) and node.attr == named]
    elif isinstance(exc, ZeroDivisionError):
        found = [
            node
            for node in parts
            if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div | ast.FloorDiv | ast.Mod)
        ]
    elif isinstance(exc, TypeError) and (keyword := _first(_KEYWORD, str(exc))) is not None:
        found = [
            node
            for node in parts
            if isinstance(node, ast.Call) and any(k.arg == keyword for k in node.keywords)
        ]
    elif isinstance(exc, TypeError) and (called := _CALLED.search(str(exc))) is not None:
        owner, function, abstract = called.groups()
        named = abstract or (owner if owner and function in _METHODS_OF_A_CLASS else function)
        return _call_of({named}, parts)
    elif isinstance(exc, EOFError | OSError):  # input() with no one at the keyboard
        return _call_of({"input"}, parts)
    return found[0] if len(found) == 1 else None


def _first(pattern: re.Pattern[str], text: str) -> str | None:
    match = pattern.search(text)
    return match.group(1) if match else None


def _entries(exc: BaseException) -> list[tuple[FrameType, int]]:
    return list(traceback.walk_tb(exc.__traceback__))


def _student_entry(exc: BaseException, frame: traceback.FrameSummary) -> int | None:
    """The index, in ``exc``'s traceback, of the last entry that is ``frame``."""
    found = None
    for index, (running, line) in enumerate(_entries(exc)):
        if running.f_code.co_filename == frame.filename and line == frame.lineno:
            found = index
    return found


def _raised_on_the_line(exc: BaseException, frame: traceback.FrameSummary) -> bool:
    """Whether ``frame``'s line raised ``exc`` itself (no function it called did)."""
    index = _student_entry(exc, frame)
    return index is not None and index == len(_entries(exc)) - 1


def _callees(exc: BaseException, frame: traceback.FrameSummary) -> set[str]:
    """The names the student's line may have called the raising function by: its own, and its
    object's class's (a class's ``__init__``, however it is wrapped); none when the line raised
    itself or the callee is built in."""
    index = _student_entry(exc, frame)
    entries = _entries(exc)
    if index is None or index + 1 >= len(entries):
        return set()
    called: FrameType = entries[index + 1][0]
    names = {called.f_code.co_name}
    made = called.f_locals.get("self", called.f_locals.get("cls"))
    if made is not None:
        names.add(made.__name__ if isinstance(made, type) else type(made).__name__)
    return names


def _call_of(callees: set[str], parts: list[ast.expr]) -> ast.Call | None:
    """The one call on the line written with one of the ``callees``' names (``Drive(...)``,
    ``self.far(...)``), or ``None``."""
    calls = [
        node
        for node in parts
        if isinstance(node, ast.Call)
        and (
            (isinstance(node.func, ast.Name) and node.func.id in callees)
            or (isinstance(node.func, ast.Attribute) and node.func.attr in callees)
        )
    ]
    return calls[0] if len(calls) == 1 else None
