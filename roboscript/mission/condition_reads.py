"""What a Python condition method reads that is not there, found before the robot moves.

A condition method runs many times a second once the mission has started; a name it reads
that does not exist (``self.bumpr``, ``bumper`` without ``self.``, ``self.drive(...)``) would
end the run with Python's ``AttributeError`` or ``NameError``. :func:`condition_slips` finds
them in the method's code, so ``roboscript check`` names the line and what to write. It also
finds calls that cannot work while a mission runs: ``input()`` (nobody types) and ``exit()``
(a mission ends in a final state, not by ending the program).

Only what is certain is reported: a class that makes attributes at run time (``setattr``,
``__getattr__``) is not checked for ``self.NAME``.
"""

from __future__ import annotations

import ast
import builtins
import inspect
import sys
import time
from collections.abc import Callable, Iterable, Iterator
from types import FunctionType

from roboscript.actions import ACTION_WORDS, ACTIONS
from roboscript.actions.base import RESULT_HINT, Action, Result
from roboscript.code_owner import is_student_file
from roboscript.errors import did_you_mean
from roboscript.mission.guards import TIME_WORDS
from roboscript.mission.python_source import PythonSource
from roboscript.watchdog import RETURN_AT_ONCE, TICK_BUDGET

__all__ = [
    "PY_WAIT",
    "YAML_WAIT",
    "Slip",
    "SourceOf",
    "action_sleeps",
    "condition_slips",
    "endless_waits",
    "helper_sleeps",
    "parsed_once",
    "sleep_warning",
    "sleeps_in",
    "update_returns",
]

Slip = tuple[ast.AST, str, str | None]
"""Where in the method, what is wrong, and what to write instead."""


PY_WAIT = 'pause = state(Wait(duration_s=2), on_done="next")'
"""A wait, as a Python mission writes it (in a sleep's fix)."""

YAML_WAIT = "pause: {do: {wait: {duration: 2 s}}, on: {done: next}}"
"""A wait, as a YAML mission writes it (in a sleep's fix)."""

_ENDS_PROGRAM = frozenset({"exit", "quit", "sys.exit", "os._exit"})
_STAYS_IN_LOOP = frozenset({*dir(builtins), "time.sleep"})
"""Calls that cannot leave a loop by themselves (Python's built-in functions, a sleep)."""
_NO_KEYBOARD = "input() waits for someone to type, and a running mission has no one at the keyboard"
_READ_AT_ONCE = "a condition reads the robot and returns at once, e.g. return self.bumper.any"
_NOT_THE_ROBOT = frozenset({"robot", "world", "name"})
"""Class attributes of a mission that are text, where a student may look for sensors."""


def _final_instead(method: str) -> str:
    return (
        "to end the mission, go to a final state when this condition holds:"
        f" when=[('{method}', 'end')], with end = state(final=\"success\")"
    )


def _walk_own(node: ast.FunctionDef | ast.AsyncFunctionDef) -> Iterator[ast.AST]:
    """Every node of a function's body, not entering nested functions, lambdas or classes
    (whose names are their own), nor annotations (which Python never runs in a body). The
    defaults and decorators are left out too: they run in the class, not in the method."""
    todo: list[ast.AST] = list(node.body)
    while todo:
        child = todo.pop()
        yield child
        if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda | ast.ClassDef):
            continue
        if isinstance(child, ast.AnnAssign):
            todo.extend(part for part in (child.target, child.value) if part is not None)
            continue
        todo.extend(ast.iter_child_nodes(child))


def _bound_otherwise(node: ast.FunctionDef | ast.AsyncFunctionDef, target: ast.Name) -> bool:
    """True if the method binds ``target``'s name other than by ``+=`` and its kind (an
    argument, an assignment, a loop, ``global``...)."""
    if target.id in {arg.arg for arg in ast.walk(node.args) if isinstance(arg, ast.arg)}:
        return True
    for child in _walk_own(node):
        if isinstance(child, ast.Global | ast.Nonlocal) and target.id in child.names:
            return True
        if (
            isinstance(child, ast.Name)
            and child.id == target.id
            and isinstance(child.ctx, ast.Store | ast.Del)
            and not _is_aug_target(node, child)
        ):
            return True
    return False


def _set_name(statement: ast.AST) -> str:
    """The name ``count += 1`` or ``count = count + 1`` sets."""
    if isinstance(statement, ast.AugAssign) and isinstance(statement.target, ast.Name):
        return statement.target.id
    if isinstance(statement, ast.Assign) and isinstance(statement.targets[0], ast.Name):
        return statement.targets[0].id
    return ""


def _reads_before_set(node: ast.FunctionDef | ast.AsyncFunctionDef, statement: ast.AST) -> bool:
    """True for ``count = count + 1`` where the method gives ``count`` no value anywhere else,
    nor takes it as an argument, nor declares it ``global``: the method's own ``count``,
    read before it has one (Python's UnboundLocalError)."""
    if not (
        isinstance(statement, ast.Assign)
        and len(statement.targets) == 1
        and isinstance(statement.targets[0], ast.Name)
    ):
        return False
    name = statement.targets[0].id
    if not any(
        isinstance(read, ast.Name) and read.id == name and isinstance(read.ctx, ast.Load)
        for read in ast.walk(statement.value)
    ):
        return False
    if name in {arg.arg for arg in ast.walk(node.args) if isinstance(arg, ast.arg)}:
        return False
    target = statement.targets[0]
    for child in _walk_own(node):
        if isinstance(child, ast.Global | ast.Nonlocal) and name in child.names:
            return False
        if child is target:
            continue
        if isinstance(child, ast.Name) and child.id == name and isinstance(child.ctx, ast.Store):
            return False  # set elsewhere too (perhaps first, in a loop): not certain
        if isinstance(child, ast.alias) and (child.asname or child.name) == name:
            return False
        if isinstance(child, ast.FunctionDef | ast.ClassDef) and child.name == name:
            return False
    return True


def _is_aug_target(node: ast.FunctionDef | ast.AsyncFunctionDef, name: ast.Name) -> bool:
    return any(
        isinstance(child, ast.AugAssign) and child.target is name for child in _walk_own(node)
    )


def _own_names(node: ast.FunctionDef | ast.AsyncFunctionDef) -> set[str]:
    """Names the method binds itself: arguments, assignments, loop and ``with`` targets,
    ``except ... as``, imports, nested ``def`` and ``class``, ``global`` and ``nonlocal``."""
    names = {arg.arg for arg in ast.walk(node.args) if isinstance(arg, ast.arg)}
    for child in _walk_own(node):
        if isinstance(child, ast.Name) and isinstance(child.ctx, ast.Store | ast.Del):
            names.add(child.id)
        elif isinstance(child, ast.ExceptHandler) and child.name:
            names.add(child.name)
        elif isinstance(child, ast.Import | ast.ImportFrom):
            names.update((a.asname or a.name).split(".")[0] for a in child.names)
        elif isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(child.name)
        elif isinstance(child, ast.Global | ast.Nonlocal):
            names.update(child.names)
        elif isinstance(child, ast.MatchAs | ast.MatchStar) and child.name:
            names.add(child.name)
        elif isinstance(child, ast.MatchMapping) and child.rest:
            names.add(child.rest)
    return names


def _dynamic(cls: type, trees: Iterable[ast.AST | None]) -> bool:
    """True when the class may make attributes that its code does not write as ``self.X =``."""
    if any(
        "__getattr__" in vars(klass) or "__getattribute__" in vars(klass)
        for klass in cls.__mro__
        if klass is not object
    ):
        return True
    for tree in trees:
        for node in ast.walk(tree) if tree is not None else ():
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Name)
                and node.func.id in ("setattr", "vars")
            ):
                return True
            if isinstance(node, ast.Attribute) and node.attr == "__dict__":
                return True
    return False


def _stored_on_self(trees: Iterable[ast.AST | None]) -> set[str]:
    """Every ``X`` the files set as ``self.X = ...`` (or ``+=``, ``for self.X in``...)."""
    return {
        node.attr
        for tree in trees
        if tree is not None
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute)
        and isinstance(node.ctx, ast.Store)
        and isinstance(node.value, ast.Name)
        and node.value.id == "self"
    }


def _called(node: ast.Call) -> str:
    """``exit``, ``sys.exit``: the dotted name a call calls, or ``""``."""
    func = node.func
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
        return f"{func.value.id}.{func.attr}"
    return ""


def condition_slips(
    cls: type,
    node: ast.FunctionDef | ast.AsyncFunctionDef,
    func: FunctionType,
    trees: Iterable[ast.AST | None],
    reading_names: Callable[[str], list[str]],
) -> list[Slip]:
    """What condition method ``node`` (the code of ``func``, a method of mission ``cls``)
    reads that is not there, and the calls in it that cannot work while a mission runs.

    Args:
        cls: The Mission subclass.
        node: The method's ``def``.
        func: The method itself (its globals and free names are the ones it sees).
        trees: The parsed files of ``cls`` and of the student's classes it extends.
        reading_names: What ``self.SENSOR`` has (``["distance_cm", "distance_mm"]``), or
            ``[]`` when ``SENSOR`` is no sensor.

    Returns:
        One ``(node, message, hint)`` per mistake, in the order written.
    """
    trees = list(trees)
    slips: list[Slip] = []
    own = _own_names(node)
    seen = set(func.__globals__) | set(dir(builtins)) | set(func.__code__.co_freevars)
    check_self = not _dynamic(cls, trees)
    stored = _stored_on_self(trees)
    public = sorted(
        {name for klass in cls.__mro__ for name in vars(klass) if not name.startswith("_")}
    )
    # self.visits(side), a state named without quotes, is told apart, with its own fix
    visited = {
        id(call.args[0])
        for call in _walk_own(node)
        if isinstance(call, ast.Call) and _called(call) == "self.visits" and call.args
    }
    for child in _walk_own(node):
        if not (
            isinstance(child, ast.AugAssign)
            and isinstance(child.target, ast.Name)
            and not _bound_otherwise(node, child.target)
        ) and not _reads_before_set(node, child):
            continue
        name = _set_name(child)
        # count += 1 on a name of the file: the method's own count, never given a value
        slips.append(
            (
                child,
                (
                    f"'{name}' is read here before this method gives it a value: a method"
                    f" that sets '{name}' has a '{name}' of its own, which starts with no"
                    " value each time the method runs"
                ),
                f"keep it on the mission: write self.{name} (with {name} = 0 in the class)",
            )
        )
    for child in _walk_own(node):
        if isinstance(child, ast.Call):
            called = _called(child)
            if called == "input":
                slips.append(
                    (
                        child,
                        _NO_KEYBOARD,
                        _READ_AT_ONCE,
                    )
                )
            elif called in _ENDS_PROGRAM:
                slips.append(
                    (
                        child,
                        f"{called}() would end the whole program, not the mission",
                        _final_instead(node.name),
                    )
                )
        elif (
            isinstance(child, ast.Attribute)
            and isinstance(child.value, ast.Name)
            and child.value.id not in own
            and child.value.id not in func.__globals__
            and child.value.id in dir(builtins)
            and reading_names(child.value.id)
        ):  # range.distance_cm: Python's own range, where the sensor self.range was meant
            sensor = child.value.id
            slips.append(
                (
                    child.value,
                    f"'{sensor}' here is Python's own {sensor}, not the robot's {sensor} sensor",
                    f"a sensor is read through self: self.{sensor}.{child.attr}",
                )
            )
        elif (
            isinstance(child, ast.Name)
            and isinstance(child.ctx, ast.Load)
            and child.id not in own
            and child.id not in seen
            and id(child) not in visited
        ):
            slips.append((child, f"name '{child.id}' is not defined", _name_hint(child.id, cls)))
        elif (
            isinstance(child, ast.Attribute)
            and isinstance(child.ctx, ast.Store)
            and isinstance(child.value, ast.Name)
            and child.value.id == "self"
            and isinstance(prop := inspect.getattr_static(cls, child.attr, None), property)
            and prop.fset is None
        ):
            slips.append(
                (
                    child,
                    f"self.{child.attr} is a value roboscript gives the mission, and cannot be set",
                    f"keep a value of your own under a name of its own: self.my_{child.attr} = ...",
                )
            )
        elif isinstance(child, ast.Attribute) and (text := _text_attribute(child, cls)):
            slips.append(
                (
                    child,
                    f"self.{text} is the name of the mission's {text}, as text",
                    f"the robot's sensors are read on self: self.{child.attr}"
                    if reading_names(child.attr)
                    else None,
                )
            )
        elif (
            check_self
            and isinstance(child, ast.Attribute)
            and isinstance(child.ctx, ast.Load)
            and isinstance(child.value, ast.Name)
            and child.value.id == "self"
            and child.attr not in stored
            and inspect.getattr_static(cls, child.attr, _MISSING) is _MISSING
        ):
            slips.append(
                (
                    child,
                    f"{cls.__name__} has no '{child.attr}'",
                    _self_hint(child.attr, cls, public, reading_names),
                )
            )
    return sorted(
        slips, key=lambda slip: (getattr(slip[0], "lineno", 0), getattr(slip[0], "col_offset", 0))
    )


_MISSING = object()


def _text_attribute(node: ast.Attribute, cls: type) -> str:
    """``robot`` for ``self.robot.range``: a mission's text attribute read as if it were the
    robot; else ``""``."""
    inner = node.value
    if (
        isinstance(inner, ast.Attribute)
        and isinstance(inner.value, ast.Name)
        and inner.value.id == "self"
        and inner.attr in _NOT_THE_ROBOT
    ):
        value = inspect.getattr_static(cls, inner.attr, None)
        if value is None or isinstance(value, str):
            return inner.attr
    return ""


def _name_hint(name: str, cls: type) -> str | None:
    if inspect.getattr_static(cls, name, _MISSING) is not _MISSING:
        return f"inside a method, the mission's own values are read through self: self.{name}"
    if name in sys.stdlib_module_names:
        return f"add 'import {name}' at the top of the file"
    capital = {"true": "True", "false": "False", "none": "None", "null": "None"}.get(name.lower())
    if capital is not None:  # true, FALSE, null: another language's spelling
        return f"Python writes it {capital}, with a capital letter"
    return did_you_mean(name, [n for n in dir(builtins) if not n.startswith("_")], cutoff=0.8)


def _self_hint(
    attr: str, cls: type, public: list[str], reading_names: Callable[[str], list[str]]
) -> str | None:
    if attr.lower() in ACTIONS or attr.lower() in ACTION_WORDS:  # believed to make it act
        return (
            "a condition cannot make the robot act: run the action in a state of its own,"
            " e.g. turn = state(Rotate(angle_deg=90), ...), and go there when the condition"
            " holds"
        )
    if attr.lower() in TIME_WORDS and "elapsed" in public:  # self.time > 5
        return (
            "a mission has two clocks: self.elapsed, the seconds since the mission started, and"
            " self.state_time, the seconds since this state began"
        )
    sensors = [name for name in public if attr in reading_names(name)]
    if sensors:
        return f"did you mean self.{sensors[0]}.{attr}?"
    meant = did_you_mean(attr, public, cutoff=0.7)  # "camera" is not a misspelt "name"
    if meant is not None:
        return meant
    readable = [name for name in public if reading_names(name)]
    own = f"a value of your own needs a first value in the class, {attr} = 0"
    return f"{own}; the robot's sensors are {', '.join(f'self.{n}' for n in readable)}"


def sleeps_in(
    node: ast.FunctionDef | ast.AsyncFunctionDef, namespace: dict[str, object]
) -> list[ast.Call]:
    """The calls of ``time.sleep`` in a function's own body (``time.sleep(2)``,
    ``sleep(2)`` after ``from time import sleep``, ``t.sleep(2)`` after ``import time as
    t``), as its module's ``namespace`` names them; ``time.sleep(0)`` waits for nothing."""
    own = _own_names(node)
    found = []
    for child in _walk_own(node):
        if not isinstance(child, ast.Call):
            continue
        func = child.func
        if isinstance(func, ast.Name):
            sleeps = func.id not in own and namespace.get(func.id) is time.sleep
        elif isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
            sleeps = (
                func.attr == "sleep"
                and func.value.id not in own
                and namespace.get(func.value.id) is time
            )
        else:
            sleeps = False
        first = child.args[0] if child.args else None
        if sleeps and not (isinstance(first, ast.Constant) and first.value == 0):
            found.append(child)
    return sorted(found, key=lambda call: (call.lineno, call.col_offset))


SourceOf = Callable[[str], PythonSource]
"""The parsed file of a name as Python knows it (a code object's ``co_filename``)."""


def helper_sleeps(
    node: ast.FunctionDef | ast.AsyncFunctionDef,
    namespace: dict[str, object],
    source_of: SourceOf | None = None,
) -> list[tuple[FunctionType, ast.Call]]:
    """Each ``time.sleep`` in the student's own functions that ``node`` calls by their name
    (``pause()``, defined in its module or imported from a file of theirs), and in those they
    call, with the function it is in: a sleep there holds up the tick as one in ``node``
    does. ``source_of`` as in :func:`action_sleeps`."""
    source_of = source_of or parsed_once()
    found: list[tuple[FunctionType, ast.Call]] = []
    seen: set[FunctionType] = set()
    todo: list[tuple[ast.FunctionDef | ast.AsyncFunctionDef, dict[str, object]]] = [
        (node, namespace)
    ]
    while todo:
        caller, names = todo.pop(0)
        own = _own_names(caller)
        for child in _walk_own(caller):
            if not (isinstance(child, ast.Call) and isinstance(child.func, ast.Name)):
                continue
            helper = names.get(child.func.id) if child.func.id not in own else None
            if (
                not isinstance(helper, FunctionType)
                or helper in seen
                or not is_student_file(helper.__code__.co_filename)
            ):
                continue
            seen.add(helper)
            helper_def = _def_of(helper, source_of)
            if helper_def is not None:
                found.extend((helper, call) for call in sleeps_in(helper_def, helper.__globals__))
                todo.append((helper_def, helper.__globals__))
    return found


def action_sleeps(
    cls: type, source_of: SourceOf | None = None
) -> list[tuple[FunctionType, ast.Call, FunctionType | None]]:
    """Each ``time.sleep`` in the ``start``, ``update`` and ``stop`` of a student's action
    class, in the methods of the class they call on ``self`` and in the functions of the
    student's own they call (:func:`helper_sleeps`), with the method it is in or reached from
    and the helper function it is in, if any (whose code names its file and line).
    ``source_of`` gives each file parsed once (default: parsed once for this call)."""
    source_of = source_of or parsed_once()
    found: list[tuple[FunctionType, ast.Call, FunctionType | None]] = []
    todo = ["start", "update", "stop"]
    seen: set[str] = set()
    while todo:
        name = todo.pop(0)
        if name in seen:
            continue
        seen.add(name)
        function = inspect.getattr_static(cls, name, None)
        function = getattr(function, "__wrapped__", function)
        if not isinstance(function, FunctionType) or not is_student_file(
            function.__code__.co_filename
        ):
            continue
        node = _def_of(function, source_of)
        if node is None:
            continue
        found.extend((function, call, None) for call in sleeps_in(node, function.__globals__))
        found.extend(
            (function, call, helper)
            for helper, call in helper_sleeps(node, function.__globals__, source_of)
        )
        todo.extend(
            child.func.attr
            for child in _walk_own(node)
            if isinstance(child, ast.Call)
            and isinstance(child.func, ast.Attribute)
            and isinstance(child.func.value, ast.Name)
            and child.func.value.id == "self"
        )
    return found


_ACTION_RETURNED = (
    f"run it in a state of its own, and go there when this one is done; {RESULT_HINT}"
)


def update_returns(
    cls: type, source_of: SourceOf | None = None
) -> list[tuple[FunctionType, ast.Return, str, str]]:
    """Each ``return`` in the ``update`` of a student's action class that gives what is no
    :class:`~roboscript.actions.base.Result` (``return True``, ``return Drive(...)``,
    ``return Result.done`` without its call), with the function, what it returns and the
    fix; run, it would end the mission in failure. ``source_of`` as in
    :func:`action_sleeps`."""
    function = inspect.getattr_static(cls, "update", None)
    function = getattr(function, "__wrapped__", function)
    if not isinstance(function, FunctionType) or not is_student_file(function.__code__.co_filename):
        return []
    node = _def_of(function, source_of or parsed_once())
    if node is None:
        return []
    found = []
    for child in _walk_own(node):
        if not isinstance(child, ast.Return) or child.value is None:
            continue
        value = child.value
        called = value.func if isinstance(value, ast.Call) else None
        made = function.__globals__.get(called.id) if isinstance(called, ast.Name) else None
        if isinstance(value, ast.Constant) and value.value is not None:
            found.append((function, child, repr(value.value), RESULT_HINT))
        elif isinstance(made, type) and issubclass(made, Action):
            found.append(
                (
                    function,
                    child,
                    f"{called.id}(...), an action, which update() cannot run"
                    if isinstance(called, ast.Name)
                    else "an action",
                    _ACTION_RETURNED,
                )
            )
        elif (
            isinstance(value, ast.Attribute)
            and isinstance(value.value, ast.Name)
            and function.__globals__.get(value.value.id) is Result
        ):
            meant = value.attr if hasattr(Result, value.attr) else value.attr.lower()
            if not hasattr(Result, meant):  # Result.DONE, Result.SUCCESS: said when it runs
                continue
            found.append(
                (
                    function,
                    child,
                    f"Result.{value.attr} without calling it"
                    if meant == value.attr
                    else f"Result.{value.attr}, which Result does not have (its outcomes are"
                    " written in small letters)",
                    f"write return Result.{meant}({'' if meant == 'done' else '...'})",
                )
            )
    return sorted(found, key=lambda item: item[1].lineno)


def parsed_once(shown: Callable[[str], str] = str) -> SourceOf:
    """A :data:`SourceOf` that parses each file the first time it is asked for and keeps it,
    named in messages as ``shown`` names it."""
    sources: dict[str, PythonSource] = {}

    def source_of(filename: str) -> PythonSource:
        if filename not in sources:
            sources[filename] = PythonSource(filename, shown(filename))
        return sources[filename]

    return source_of


def _def_of(
    function: FunctionType, source_of: SourceOf
) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
    """The ``def`` of ``function`` in its file's syntax tree, or ``None``."""
    code = function.__code__
    return source_of(code.co_filename).function_def(code.co_name, code.co_firstlineno)


def sleep_warning(
    call: ast.Call, runs: str, example: str, function: FunctionType | None = None
) -> tuple[str, str]:
    """The warning for ``time.sleep`` in code that runs every tick (``runs``: ``update()``,
    ``near()``): ``(message, fix)``, the fix showing ``example``, a wait as the mission's
    syntax writes it; ``function``: the helper of the student's own the sleep is in, when
    it is not in ``runs`` itself."""
    written = ast.unparse(call)
    if len(written) > 40:
        written = "time.sleep(...)"
    first = call.args[0] if call.args else None
    seconds = (
        f" for {first.value:g} s"
        if isinstance(first, ast.Constant)
        and isinstance(first.value, int | float)
        and not isinstance(first.value, bool)
        else ""
    )
    inside = runs if function is None else f"{function.__name__}(), called by {runs},"
    message = (
        f"{written} in {inside} holds up the whole robot{seconds}: {runs} is run once every"
        f" tick ({TICK_BUDGET.slow_tick_s:g} s), and while it sleeps no condition is checked,"
        " no timeout counted and no other action run"
    )
    return message, f"{RETURN_AT_ONCE}: e.g. a state of its own, {example}"


_CLOCKS = frozenset({"elapsed", "state_time", "heading_deg"})
"""Values of a mission's own that, like its sensors' readings, stay as they are while a
condition runs."""
_OPPOSITE: dict[type[ast.cmpop], ast.cmpop] = {
    ast.Lt: ast.GtE(),
    ast.LtE: ast.Gt(),
    ast.Gt: ast.LtE(),
    ast.GtE: ast.Lt(),
    ast.Eq: ast.NotEq(),
    ast.NotEq: ast.Eq(),
}


def _fixed_reads(test: ast.expr, reading_names: Callable[[str], list[str]]) -> list[str] | None:
    """The readings ``test`` reads (``self.bumper.any``), when it reads nothing else but
    constants; else ``None``."""
    reads: list[str] = []
    for child in ast.walk(test):
        if isinstance(child, ast.Attribute):
            inner = child.value
            if (
                isinstance(inner, ast.Attribute)
                and isinstance(inner.value, ast.Name)
                and inner.value.id == "self"
                and child.attr in reading_names(inner.attr)
            ):
                reads.append(ast.unparse(child))
            elif not (
                isinstance(inner, ast.Name)
                and inner.id == "self"
                and (child.attr in _CLOCKS or reading_names(child.attr))
            ):
                return None
            elif child.attr in _CLOCKS:
                reads.append(ast.unparse(child))
        elif (isinstance(child, ast.Name) and child.id != "self") or isinstance(
            child, ast.Call | ast.Subscript | ast.NamedExpr | ast.Lambda
        ):  # a value of the method's own, or what a call gives: it may change
            return None
    return reads or None


def _ends(body: list[ast.stmt]) -> bool:
    """True if ``body`` may leave its loop (a break, return, raise or yield) or call what
    could (anything but a built-in function, such as print, or time.sleep)."""
    for statement in body:
        for child in ast.walk(statement):
            if isinstance(child, ast.Break | ast.Return | ast.Raise | ast.Yield | ast.YieldFrom):
                return True
            if isinstance(child, ast.Call):
                called = _called(child)
                if called in _ENDS_PROGRAM or called not in _STAYS_IN_LOOP:
                    return True
    return False


def endless_waits(
    node: ast.FunctionDef | ast.AsyncFunctionDef, reading_names: Callable[[str], list[str]]
) -> list[tuple[ast.While, str, str]]:
    """Each ``while`` loop in a condition method that waits for a reading to change (``while
    not self.bumper.any: pass``): what a condition reads stays as it is while it runs, so the
    loop never ends. With what it waits for and what to return instead."""
    found = []
    for child in _walk_own(node):
        if not isinstance(child, ast.While) or _ends(child.body):
            continue
        reads = _fixed_reads(child.test, reading_names)
        if reads is None:
            continue
        test = child.test
        if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
            meant = ast.unparse(test.operand)
        elif (
            isinstance(test, ast.Compare) and len(test.ops) == 1 and type(test.ops[0]) in _OPPOSITE
        ):
            meant = ast.unparse(
                ast.Compare(test.left, [_OPPOSITE[type(test.ops[0])]], test.comparators)
            )
        else:
            meant = f"not ({ast.unparse(test)})"
        found.append((child, reads[0], meant))
    return found
