"""``check: file.py:function``: a teacher's own Python function judges the run."""

from __future__ import annotations

import ast
import importlib.util
import sys
import traceback
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING

from roboscript.errors import did_you_mean
from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark
from roboscript.watchdog import CodePlace, RunawayCode, Watchdog

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["CHECK_LIMIT_S", "CheckFunction"]

CHECK_LIMIT_S = 10.0
"""Seconds of its own time (never the busy machine's) a teacher's check may take on one run
before it is stopped: a loop that never ends must not stall the class's grading."""


@dataclass(frozen=True)
class CheckFunction(Rule):
    """``check``: a teacher's Python function, by file (``path``) and name (``function``),
    as ``written`` in the spec. It is read (not run) when the spec is, and imported and
    called in the grading worker, never in the process that reads the spec."""

    kind = "check"

    path: str
    function: str
    written: str

    def describe(self) -> str:
        return f"check: {self.function}"

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        if not isinstance(value, str) or ":" not in value:
            raise reader.fail(
                "check is written 'file.py:function' (a Python file beside the spec)", mark
            )
        file_part, _, function = value.rpartition(":")
        if not function.isidentifier():
            raise reader.fail(f"'{function}' is not a Python function name", mark)
        path = (ctx.folder / file_part).resolve()
        if path.suffix != ".py" or not path.is_file():
            raise reader.fail(f"no Python file '{file_part}' next to the spec", mark)
        try:
            tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        except (SyntaxError, UnicodeDecodeError) as exc:
            raise reader.fail(f"cannot read {file_part}: {exc}", mark) from None
        defined = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
        if function not in defined:
            raise reader.fail(
                f"{file_part} has no function '{function}'", mark, did_you_mean(function, defined)
            )
        for problem in (_missing_import(tree, path), _not_one_argument(defined[function])):
            if problem:
                raise reader.fail(
                    f"{file_part}:{problem}: the check would fail every run, whatever the"
                    " robot did",
                    mark,
                )
        return cls(str(path), function, value)

    def judge(self, record: RunRecord) -> Verdict:
        name = self.describe()
        try:
            with Watchdog(CHECK_LIMIT_S, self._locate_frame):
                function = _load_check(self)
                answer = function(record)
        except RunawayCode as stuck:
            at = f" (stopped at {stuck.where.file}:{stuck.where.line})" if stuck.where else ""
            return Verdict(
                name,
                False,
                "",
                None,
                f"the teacher's check did not return within {CHECK_LIMIT_S:g} s{at}: is there"
                " a loop in it that never ends?",
                teachers_fault=True,
            )
        except Exception as exc:  # noqa: BLE001 - a fault of the teacher's code fails this check
            where = traceback.extract_tb(exc.__traceback__)[-1]
            return Verdict(
                name,
                False,
                "",
                None,
                f"the teacher's check raised {type(exc).__name__}: {exc}"
                f" ({Path(where.filename).name}:{where.lineno})",
                teachers_fault=True,
            )
        if isinstance(answer, Verdict):
            return answer
        if isinstance(answer, bool):
            return Verdict(name, answer)
        if (
            isinstance(answer, tuple)
            and len(answer) == 2
            and isinstance(answer[0], bool)
            and isinstance(answer[1], str)
        ):
            return Verdict(name, answer[0], "", None, answer[1])
        return Verdict(
            name,
            False,
            "",
            None,
            f"the teacher's check returned {type(answer).__name__}; it must return True/False,"
            " (True/False, message) or a Verdict",
            teachers_fault=True,
        )

    def _locate_frame(self, frame: FrameType | None) -> CodePlace | None:
        """Where in the check's file a stopped check was (its innermost line there)."""
        while frame is not None:
            if frame.f_code.co_filename == self.path:
                return CodePlace(Path(self.path).name, frame.f_lineno, frame.f_code.co_name)
            frame = frame.f_back
        return None


def _missing_import(tree: ast.Module, path: Path) -> str | None:
    """``LINE: it imports 'name', which is not installed`` for the first module the check's
    file imports at its top that cannot be found (looked up, not imported), or ``None``."""
    for node in tree.body:
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        else:
            continue
        for name in names:
            top = name.partition(".")[0]
            if (path.parent / f"{top}.py").is_file() or (path.parent / top).is_dir():
                continue  # a helper beside the check, found there when the worker imports it
            try:
                found = importlib.util.find_spec(top) is not None
            except (ImportError, ValueError):
                found = False
            if not found:
                return f"{node.lineno}: it imports '{top}', which is not installed"
    return None


def _not_one_argument(function: ast.FunctionDef) -> str | None:
    """``LINE: ...`` when ``function`` cannot be called with the run's record alone."""
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    needed = len(positional) - len(args.defaults)
    needed_keywords = [
        a.arg for a, d in zip(args.kwonlyargs, args.kw_defaults, strict=True) if d is None
    ]
    if (positional or args.vararg) and needed <= 1 and not needed_keywords:
        return None
    return (
        f"{function.lineno}: {function.name}() must take one argument, the run's record"
        f" (def {function.name}(run): ...)"
    )


def _load_check(ref: CheckFunction) -> Callable[[RunRecord], object]:
    module_name = f"roboscript_teacher_check_{zlib.crc32(ref.path.encode()):08x}"
    module = sys.modules.get(module_name)
    if module is None:
        spec = importlib.util.spec_from_file_location(module_name, ref.path)
        if spec is None or spec.loader is None:
            raise ImportError(f"cannot import {ref.path}")
        module = importlib.util.module_from_spec(spec)
        sys.modules[module_name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[module_name]
            raise
    function = getattr(module, ref.function)
    if not callable(function):
        raise TypeError(f"{ref.function} is not a function")
    return function  # type: ignore[no-any-return]
