"""Where things were written in a Python file: positions read from its syntax tree.

Python missions and behaviours are reported like YAML ones, ``file:line:col``. The objects a
class body creates do not know where they were written, so the compiler asks this module:
the ``state(...)`` assigned to ``side`` in class ``Square``, its ``on_done=`` keyword, the
third item of that list, the ``def`` of a guard method, and so on. Columns are 1-based
characters (the syntax tree counts UTF-8 bytes from 0).
"""

from __future__ import annotations

import ast
import linecache
from pathlib import Path

from roboscript.inputs.source import Location

__all__ = ["PythonSource", "item", "keyword"]


class PythonSource:
    """The syntax tree of one Python file, for finding positions.

    Args:
        filename: The file as Python knows it (a code object's ``co_filename``).
        shown: The file as messages should name it.
    """

    def __init__(self, filename: str, shown: str) -> None:
        self.filename = filename
        self.shown = shown
        self.lines = linecache.getlines(filename)
        if not self.lines and Path(filename).is_file():
            self.lines = Path(filename).read_text(encoding="utf-8").splitlines(keepends=True)
        self.tree: ast.Module | None
        try:
            self.tree = ast.parse("".join(self.lines)) if self.lines else None
        except SyntaxError:
            self.tree = None
        self._defs: dict[tuple[str, int], ast.FunctionDef | ast.AsyncFunctionDef] | None = None
        """Each ``def`` by its name and first line, indexed at the first look-up: a check asks
        for many methods of one file, and each look-up must not walk the whole file again."""
        self._assigned: dict[ast.ClassDef, dict[str, tuple[ast.expr, ast.expr]]] = {}
        """Each class's assignments by name, indexed at its first look-up."""

    def loc(self, node: ast.AST | None, line: int | None = None) -> Location:
        """Where ``node`` starts (or just ``line``, when there is no node)."""
        if node is None or not hasattr(node, "lineno"):
            return Location(self.shown, line)
        lineno: int = node.lineno
        offset: int = getattr(node, "col_offset", 0)
        text = self.lines[lineno - 1] if 0 < lineno <= len(self.lines) else ""
        col = len(text.encode("utf-8")[:offset].decode("utf-8", errors="ignore"))
        return Location(self.shown, lineno, col + 1)

    def class_def(self, name: str, near_line: int | None = None) -> ast.ClassDef | None:
        """The ``class NAME`` statement; the one spanning ``near_line`` if there are several."""
        if self.tree is None:
            return None
        found = [n for n in ast.walk(self.tree) if isinstance(n, ast.ClassDef) and n.name == name]
        if near_line is not None:
            for node in found:
                if node.lineno <= near_line <= (node.end_lineno or node.lineno):
                    return node
        return found[0] if found else None

    def assignment(
        self, cls_node: ast.ClassDef | None, name: str
    ) -> tuple[ast.expr, ast.expr] | None:
        """``(target, value)`` of the last ``NAME = ...`` directly in a class body."""
        if cls_node is None:
            return None
        if cls_node not in self._assigned:  # a class of many states: one pass, not one a name
            self._assigned[cls_node] = _assignments(cls_node)
        return self._assigned[cls_node].get(name)

    def function_def(
        self, name: str, first_line: int
    ) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """The ``def NAME`` whose first line (decorators included) is ``first_line``."""
        if self._defs is None:
            self._defs = {}
            for node in ast.walk(self.tree) if self.tree is not None else ():
                if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                    start = min([node.lineno, *(d.lineno for d in node.decorator_list)])
                    self._defs.setdefault((node.name, start), node)
        return self._defs.get((name, first_line))


def _assignments(cls_node: ast.ClassDef) -> dict[str, tuple[ast.expr, ast.expr]]:
    """``(target, value)`` of each ``NAME = ...`` directly in a class body, by name: the last
    one where a name is assigned more than once."""
    found: dict[str, tuple[ast.expr, ast.expr]] = {}
    for stmt in cls_node.body:
        if isinstance(stmt, ast.Assign) and stmt.value is not None:
            for target in stmt.targets:
                if isinstance(target, ast.Name):
                    found[target.id] = (target, stmt.value)
        elif (
            isinstance(stmt, ast.AnnAssign)
            and stmt.value is not None
            and isinstance(stmt.target, ast.Name)
        ):
            found[stmt.target.id] = (stmt.target, stmt.value)
    return found


def keyword(call: ast.expr | None, name: str) -> ast.expr | None:
    """The value of keyword ``name`` in a call, or ``None``."""
    if not isinstance(call, ast.Call):
        return None
    for item in call.keywords:
        if item.arg == name:
            return item.value
    return None


def item(node: ast.expr | None, index: int, length: int) -> ast.expr | None:
    """Item ``index`` of a list or tuple literal of ``length`` items, else ``node`` itself."""
    if isinstance(node, ast.List | ast.Tuple) and len(node.elts) == length:
        return node.elts[index]
    return node
