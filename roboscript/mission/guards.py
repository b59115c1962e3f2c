"""Guard expressions: ``range.distance_cm < 20 and not bumper.any``, compiled without ``eval``.

The text is parsed with :func:`ast.parse` and only an allow-list of node types is accepted:
``and``/``or``/``not``, comparisons (chains too), ``+ - * /``, numbers, ``true``/``false`` and
names rooted at the sensors and mission values below. There are no calls, no subscripts, no
strings and no attribute chains beyond one dot, so a guard cannot reach anything but these
values. The result is a tree of closures evaluated against a :class:`GuardEnv`.

Names:

=====================  ==================================================  ===============
name                   value                                               needs
=====================  ==================================================  ===============
``range.distance_mm``  distance ahead in mm (no echo reads as infinity)    ``range``
``range.distance_cm``  the same in cm                                      ``range``
``side_range.distance_cm`` gap to a wall beside the robot (also ``_mm``)  ``side_range``
``bumper.left``        left bump switch pressed (also ``right``, ``any``)  ``bumper``
``line.left``          line sensor reading 0-1023 (``center``, ``right``)  ``line``
``line.any``           any line sensor over a dark line                    ``line``
``color.reflection``   light the colour sensor gets back, 0-100 % (none:   ``color``
                       compares false)
``color.black``        the colour sensor sees black (also ``white``,       ``color``
                       ``red``, ``green``, ``blue``, ``yellow``, ...)
``color.rgb_red``      raw red 0-1023 (also ``rgb_green``, ``rgb_blue``)   ``color``
``buttons.left``       the hub's left button is held (``right``, ``any``)  ``buttons``
``heading_deg``        turn since the start, degrees clockwise, -180-180  ``drive_base``
``driven.total_mm``    distance driven since the start (also ``_cm``)      ``drive_base``
``driven.state_mm``    distance driven in this state (also ``_cm``)        ``drive_base``
``pose.x_mm``          odometry: mm to the right of the start point        ``drive_base``
``pose.y_mm``          odometry: mm ahead of the start point               ``drive_base``
``pose.heading_deg``   odometry heading, the same as ``heading_deg``       ``drive_base``
``in_region.NAME``     the robot is inside the world's region NAME         ``drive_base``
``visits.STATE``       how many times STATE has been entered               --
``elapsed``            seconds since the mission started                   --
``state_time``         seconds since the current state was entered         --
=====================  ==================================================  ===============

A number may carry a unit (``20 cm``, ``1.5 s``, ``-90 deg``): it is converted to the unit of
the name it is compared with (``range.distance_cm < 200 mm`` compares in cm). Arithmetic never
raises: dividing by zero gives infinity (or not-a-number for 0/0, which compares false).
"""

from __future__ import annotations

import ast
import difflib
import math
import operator
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from roboscript import capabilities as cap
from roboscript.inputs.quantities import (
    CURLY_QUOTES,
    DASHES,
    DIMENSIONS,
    QuantityError,
    parse_quantity,
)
from roboscript.mission.limits import GUARD_NUMBER_LIMIT, shown
from roboscript.mission.never_true import bounds_of, never_true

__all__ = [
    "COLOR_NAMES",
    "RGB_NAMES",
    "TIME_WORDS",
    "Guard",
    "GuardEnv",
    "GuardError",
    "compile_guard",
]

COLOR_NAMES = (
    "black",
    "magenta",
    "purple",
    "blue",
    "azure",
    "turquoise",
    "green",
    "yellow",
    "orange",
    "red",
    "white",
)
"""The colours a colour sensor names (LEGO's set), each a yes/no guard name: ``color.red``."""
RGB_NAMES = ("rgb_red", "rgb_green", "rgb_blue")
"""The colour sensor's raw channels as guard names (``color.rgb_red``), 0-1023."""

_UNREADABLE = {
    "buttons.center": "the hub's centre button stops the program, so a mission never sees"
    " it pressed; use buttons.left or buttons.right",
}


class GuardError(ValueError):
    """A guard expression is not valid.

    Attributes:
        offset: 0-based character offset of the problem in the expression.
        hint: A suggestion, or ``None``.
    """

    def __init__(self, message: str, offset: int = 0, hint: str | None = None) -> None:
        super().__init__(message)
        self.offset = offset
        self.hint = hint


class GuardEnv:
    """The values a guard can read at one moment. Subclassed by the mission runner."""

    def sensor(self, root: str, attr: str | None) -> float | bool:
        """Value of ``root`` or ``root.attr`` (``range.distance_mm``, ``heading_deg``)."""
        raise NotImplementedError

    def visits(self, state: str) -> int:
        """How many times ``state`` has been entered."""
        raise NotImplementedError

    def in_region(self, name: str) -> bool:
        """True while the robot is inside the world's region ``name`` (simulator only)."""
        raise NotImplementedError


_ATTRS: dict[str, dict[str, tuple[str, str]]] = {
    "range": {
        "distance_mm": ("mm", cap.RANGE),
        "distance_cm": ("cm", cap.RANGE),
    },
    "side_range": {
        "distance_mm": ("mm", cap.SIDE_RANGE),
        "distance_cm": ("cm", cap.SIDE_RANGE),
    },
    "bumper": dict.fromkeys(("left", "right", "any"), ("", cap.BUMPER)),
    "line": dict.fromkeys(("left", "center", "right", "any"), ("", cap.LINE)),
    # A condition has no strings: a colour is a yes/no name (color.black), not color == 'black'.
    "color": dict.fromkeys(("reflection", *COLOR_NAMES, *RGB_NAMES), ("", cap.COLOR)),
    "buttons": dict.fromkeys(("left", "right", "any"), ("", cap.BUTTONS)),
    "driven": {
        "total_mm": ("mm", cap.DRIVE_BASE),
        "total_cm": ("cm", cap.DRIVE_BASE),
        "state_mm": ("mm", cap.DRIVE_BASE),
        "state_cm": ("cm", cap.DRIVE_BASE),
    },
    "pose": {
        "x_mm": ("mm", cap.DRIVE_BASE),
        "y_mm": ("mm", cap.DRIVE_BASE),
        "heading_deg": ("deg", cap.DRIVE_BASE),
    },
}
"""Each sensor's values a condition reads as ``root.attr``: the unit its number is in (``mm``,
``cm``, ``deg``; ``""`` for a yes/no value or a reading without one) and the capability it
needs."""
_DOTTED_EXAMPLES = {
    "range": "range.distance_cm < 20",
    "side_range": "side_range.distance_cm < 20",
    "bumper": "bumper.left, bumper.right or bumper.any",
    "line": "line.left, line.center, line.right or line.any",
    "color": "color.black, color.red or color.reflection < 30",
    "buttons": "buttons.left, buttons.right or buttons.any",
    "driven": "driven.state_cm > 50 or driven.total_cm > 200",
    "pose": "pose.x_mm > 500, pose.y_mm > 500 or pose.heading_deg > 90",
}
"""A condition for each sensor written without its value (each is compiled by a test)."""


def _dotted_example(root: str) -> str:
    """What a bare ``bumper`` (or ``visits``, ``in_region``) could have meant, written out."""
    if root == "visits":
        return "e.g. visits.STATE >= 2, with the name of one of your states"
    if root == "in_region":
        return "e.g. in_region.REGION, with the name of one of the world's regions"
    return f"write {_DOTTED_EXAMPLES[root]}"


_PLAIN: dict[str, tuple[str, str | None]] = {
    "heading_deg": ("deg", cap.DRIVE_BASE),
    "elapsed": ("s", None),
    "state_time": ("s", None),
}
"""The values a condition reads by a name alone: the unit each is in, and the capability it
needs (``None``: the mission's own clock)."""
_UNIT_DIMENSION = {"mm": "distance", "cm": "distance", "deg": "angle", "s": "time"}
_UNIT_FACTOR = {"mm": 1.0, "cm": 10.0, "deg": 1.0, "s": 1.0}

_NUMBER_WITH_UNIT = re.compile(
    r"(?<![\w.])(\d+(?:\.\d*)?|\.\d+)\s*(mm|cm|m|ms|s|sec|min|deg|rad|°)(?![\w/])"
)

_REGION = re.compile(r"(?<![\w.])in_region\.([A-Za-z_]\w*(?:-\w+)+)")

GUARD_MAX_CHARS = 1000
"""Longest condition, characters (the longest in ``missions/`` is under 60)."""
GUARD_MAX_DEPTH = 32
"""Deepest nesting of a condition's expression (brackets, ``not``, operators): deeper ones
would exhaust Python's recursion limit when compiled or evaluated."""


def _depth(node: ast.AST) -> int:
    """How deep ``node``'s tree goes, counted without recursion."""
    deepest = 0
    todo = [(node, 1)]
    while todo:
        current, depth = todo.pop()
        deepest = max(deepest, depth)
        todo.extend((child, depth + 1) for child in ast.iter_child_nodes(current))
    return deepest


_LONG_NUMBER = re.compile(rf"(?<![\w.])\d{{{len(str(int(GUARD_NUMBER_LIMIT))) + 1},}}")

_COMPARE: dict[type[ast.cmpop], Callable[[Any, Any], bool]] = {
    ast.Lt: operator.lt,
    ast.LtE: operator.le,
    ast.Gt: operator.gt,
    ast.GtE: operator.ge,
    ast.Eq: operator.eq,
    ast.NotEq: operator.ne,
}


def _divide(left: float, right: float) -> float:
    """Division that never raises: x/0 is +-infinity (nan for 0/0, and nan compares false)."""
    if right == 0:
        return math.nan if left == 0 else math.copysign(math.inf, left) * math.copysign(1, right)
    return float(left) / float(right)


_ARITH: dict[type[ast.operator], Callable[[Any, Any], Any]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: _divide,
}

_Eval = Callable[[GuardEnv], Any]


@dataclass(frozen=True)
class Guard:
    """A compiled guard.

    Attributes:
        source: The expression as written.
        capabilities: Capability names the guard reads.
        states: State names it reads through ``visits.STATE``.
        regions: World region names it reads through ``in_region.NAME``.
    """

    source: str
    _evaluate: _Eval = field(repr=False, compare=False)
    capabilities: frozenset[str] = frozenset()
    states: frozenset[str] = frozenset()
    regions: frozenset[str] = frozenset()

    def __call__(self, env: GuardEnv) -> bool:
        """Evaluate the guard now."""
        return bool(self._evaluate(env))

    def value(self, env: GuardEnv) -> float | bool:
        """The expression's value now, not made true/false (what ``plot:`` records)."""
        found = self._evaluate(env)
        return found if isinstance(found, bool) else float(found)


@dataclass
class _Quantity:
    value: float
    unit: str
    offset: int


class _Compiler:
    def __init__(
        self, source: str, state_names: frozenset[str] | None, *, truth: bool = False
    ) -> None:
        self.source = source
        self.truth = truth
        self.state_names = state_names
        self.capabilities: set[str] = set()
        self.states: set[str] = set()
        self.regions: set[str] = set()
        self.region_names: dict[str, str] = {}  # identifier -> region name with its dashes
        self.quantities: dict[str, _Quantity] = {}

    def fail(
        self, message: str, node: ast.AST | None = None, hint: str | None = None
    ) -> GuardError:
        offset = getattr(node, "col_offset", 0) if node is not None else 0
        if isinstance(node, ast.Attribute) and node.end_col_offset is not None:
            offset = node.end_col_offset - len(node.attr)  # point at the misspelt part
        return GuardError(message, self._source_offset(offset), hint)

    def _is_meant(self, node: ast.Compare) -> str:
        """What ``bumper.any is True`` (or ``is not``, ``is False``) means, as a condition."""
        left = self.source[node.col_offset : node.left.end_col_offset or node.col_offset]
        right = node.comparators[0]
        if len(node.ops) == 1 and isinstance(right, ast.Constant) and isinstance(right.value, bool):
            holds = right.value != isinstance(node.ops[0], ast.IsNot)
            return f"a switch is true or false by itself: write {'' if holds else 'not '}{left}"
        return "compare numbers with == or !="

    def _source_offset(self, offset: int) -> int:
        return max(0, offset)

    def rewrite(self) -> str:
        # Each "20 cm" becomes an identifier of the same length, so offsets still match.
        def replace(match: re.Match[str]) -> str:
            index = len(self.quantities)
            name = f"_{index}".ljust(len(match.group(0)), "_")
            self.quantities[name] = _Quantity(float(match.group(1)), match.group(2), match.start())
            return name

        def region(match: re.Match[str]) -> str:
            # a world's region may be named 'north-wall': a '-' would read as a minus
            name = match.group(1)
            self.region_names[name.replace("-", "_")] = name
            return f"in_region.{name.replace('-', '_')}"

        return _NUMBER_WITH_UNIT.sub(replace, _REGION.sub(region, self.source))

    def compile(self) -> Guard:
        long = _LONG_NUMBER.search(self.source)
        if long is not None:  # Python would refuse a 5000-digit literal with a SyntaxError
            raise GuardError(
                f"a number of {len(long.group(0))} digits is too large for a condition "
                f"(at most {GUARD_NUMBER_LIMIT:g})",
                long.start(),
                "compare with a number a sensor can read, e.g. range.distance_cm < 20",
            )
        self._refuse_unreadable()
        text = self.rewrite()
        text = re.sub(r"\btrue\b", "True", re.sub(r"\bfalse\b", "False", text))
        try:
            tree = ast.parse(text.strip(), mode="eval")
        except SyntaxError as exc:
            offset = (exc.offset or 1) - 1
            raise (
                _syntax_mistake(self.source)
                or _unclosed(self.source)
                or GuardError(
                    f"cannot read the condition '{self.source}'", self._source_offset(offset)
                )
            ) from None
        except (RecursionError, MemoryError):  # the parser's own depth limit
            raise self._too_deep() from None
        if _depth(tree.body) > GUARD_MAX_DEPTH:
            raise self._too_deep()
        whole = tree.body
        if self.truth:
            self._refuse_bare_numbers(whole)
        if (
            self.truth
            and isinstance(whole, ast.Constant)
            and isinstance(whole.value, int | float)
            and not isinstance(whole.value, bool)
        ):  # if: 20, a limit without what it limits
            raise self.fail(
                f"the condition '{self.source}' is only a number, which never changes, so it"
                " would always count as true",
                whole,
                f"compare a value with it, e.g. range.distance_cm < {self.source.strip()}",
            )
        evaluate = self.node(tree.body)
        if self.truth:
            self._refuse_never_true(tree.body)
        return Guard(
            self.source,
            evaluate,
            frozenset(self.capabilities),
            frozenset(self.states),
            frozenset(self.regions),
        )

    def _refuse_never_true(self, whole: ast.expr) -> None:
        """Refuse a condition no reading can make true: a distance below zero, or a value
        both below one number and above a larger one (``range.distance_cm < 20 and
        range.distance_cm > 30``, where 'or' was meant)."""
        parts = (
            whole.values
            if isinstance(whole, ast.BoolOp) and isinstance(whole.op, ast.And)
            else [whole]
        )
        found = never_true(bounds_of(parts, self._reading, self._in_its_unit))
        if found is None:
            return
        raise self.fail(
            f"the condition '{self.source.strip()}' can never be true: {found.why}",
            found.node,
            found.hint(self.source, len(parts)),
        )

    def _reading(self, node: ast.expr) -> str | None:
        """The reading ``node`` names (``range.distance_cm``; ``range.distance`` beside a number
        with its unit reads ``range.distance_mm``, as :meth:`compare` does), or ``None``."""
        read = _with_unit_suffix(node)
        if not isinstance(read, ast.Name | ast.Attribute) or self.is_quantity(read):
            return None
        return ast.unparse(read)

    def _in_its_unit(self, number: ast.expr, read: ast.expr) -> float | None:
        """The number with its unit ``number`` (``20 cm``, ``-10 cm``) in the unit of the
        reading ``read`` compares it with (``range.distance_mm``: 200), or ``None`` when
        ``number`` is none."""
        unsigned = _unsigned(number)
        read = _with_unit_suffix(read)
        if not (isinstance(unsigned, ast.Name) and self.is_quantity(unsigned)):
            return None
        if not isinstance(read, ast.Name | ast.Attribute) or self.is_quantity(read):
            return None
        value = self._in_unit(unsigned, self.unit_of(read))
        return -value if unsigned is not number else value

    def _in_unit(self, node: ast.Name, unit: str | None) -> float:
        """The number with its unit at ``node`` (``20 cm``) in ``unit`` (``mm``: 200), or in
        its dimension's own unit when ``unit`` is ``None``."""
        quantity = self.quantities[node.id]
        target = unit or _default_unit(quantity.unit)
        dimension = _UNIT_DIMENSION.get(target or "")
        if dimension is None:
            raise self.fail(
                f"'{quantity.value:g} {quantity.unit}' is compared with a value that has no unit",
                node,
            )
        try:
            base = parse_quantity(f"{quantity.value} {quantity.unit}", dimension)
        except QuantityError as exc:
            raise self.fail(str(exc), node) from None
        return base / _UNIT_FACTOR[target or "mm"]

    def _refuse_unreadable(self) -> None:
        """Refuse conditions no one writes by hand before Python's parser sees them."""
        if len(self.source) > GUARD_MAX_CHARS:
            raise GuardError(
                f"a condition of {len(self.source)} characters is too long"
                f" (at most {GUARD_MAX_CHARS})",
                GUARD_MAX_CHARS,
                "split it: a Python mission's condition method can hold longer logic",
            )
        for offset, char in enumerate(self.source):
            if "\ud800" <= char <= "\udfff":  # a lone surrogate: not text, Python cannot parse it
                raise GuardError(
                    f"the condition holds U+{ord(char):04X}, which is not a character", offset
                )

    def _too_deep(self) -> GuardError:
        return GuardError(
            f"the condition is nested more than {GUARD_MAX_DEPTH} deep",
            0,
            "write it flatter: 'a and b and c' rather than brackets inside brackets",
        )

    # ------------------------------------------------------------------------------ nodes

    def node(self, node: ast.expr) -> _Eval:
        if isinstance(node, ast.BoolOp):
            parts = [self.node(value) for value in node.values]
            if isinstance(node.op, ast.And):
                return lambda env: all(part(env) for part in parts)
            return lambda env: any(part(env) for part in parts)
        if isinstance(node, ast.UnaryOp):
            operand = self.node(node.operand)
            if isinstance(node.op, ast.Not):
                return lambda env: not operand(env)
            if isinstance(node.op, ast.USub):
                return lambda env: -operand(env)
            raise self.fail("only 'not' and '-' can stand before a value", node)
        if isinstance(node, ast.Compare):
            return self.compare(node)
        if isinstance(node, ast.BinOp):
            op = _ARITH.get(type(node.op))
            if isinstance(node.op, ast.Pow):  # 10**400 would be a number beyond any sensor
                raise self.fail(
                    "a condition cannot raise to a power ('**'); only + - * / are allowed",
                    node,
                    f"write the number itself, at most {GUARD_NUMBER_LIMIT:g}",
                )
            word = {ast.BitAnd: ("&", "and"), ast.BitOr: ("|", "or")}.get(type(node.op))
            if word is not None and word[0] in self.source:  # one '&' of '&&', as elsewhere
                fixed = " ".join(self.source.replace(word[0], f" {word[1]} ").split())
                raise GuardError(
                    f"cannot read the condition '{self.source}': '{word[0]}' is not a condition"
                    " word",
                    self.source.index(word[0]),
                    f"write '{word[1]}': {fixed}",
                )
            if op is None:
                raise self.fail("only + - * / are allowed in a condition", node)
            left, right = self.node(node.left), self.node(node.right)
            return lambda env: op(left(env), right(env))
        if isinstance(node, ast.Constant):
            value = node.value
            if isinstance(value, bool | int | float):
                if not isinstance(value, bool):
                    self.check_number(value, node)
                return lambda env: value
            end = node.end_col_offset or node.col_offset
            quoted = self.source[node.col_offset : end]  # as written: "20 cm" was rewritten
            number = quoted.strip("'\"").strip()
            unquoted = self.source[: node.col_offset] + number + self.source[end:]
            raise self.fail(
                "a condition compares numbers, not text",
                node,
                f"write the number without quotes: {unquoted.strip()}"
                if _NUMBER_WITH_UNIT.fullmatch(number) or re.fullmatch(r"-?\d+(\.\d*)?", number)
                else None,
            )
        if isinstance(node, ast.Name | ast.Attribute):
            reader, _ = self.name(node)
            return reader
        if isinstance(node, ast.Call):
            raise self.fail("a condition cannot call functions", node, _call_meant(node))
        if isinstance(node, ast.Tuple):  # 'range.distance_cm < 0,5' reads as a pair
            raise _syntax_mistake(self.source) or self.fail("a condition has no ','", node)
        raise self.fail("this is not allowed in a condition", node)

    def _refuse_bare_numbers(self, node: ast.expr) -> None:
        """Refuse a value that is a number where true or false is asked (``if: visits.turn``,
        ``range.distance_cm and bumper.any``): it would hold whenever it is not 0."""
        if isinstance(node, ast.BoolOp):
            for value in node.values:
                self._refuse_bare_numbers(value)
            return
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            self._refuse_bare_numbers(node.operand)
            return
        numeric = False
        if isinstance(node, ast.Name):
            numeric = bool(_PLAIN.get(node.id, (None, None))[0])
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            root, attr = node.value.id, node.attr
            unit = _ATTRS.get(root, {}).get(attr, (None, ""))[0]
            numeric = root == "visits" or bool(unit) or (root, attr) == ("color", "reflection")
        if numeric:
            text = ast.unparse(node)
            limit = ">= 2" if text.startswith("visits.") else "< 20"
            raise GuardError(
                f"'{text}' is a number, not true or false, so it would count as true"
                " whenever it is not 0",
                self._source_offset(node.col_offset),
                f"compare it, e.g. {text} {limit}",
            )

    def check_number(self, value: float, node: ast.AST | None) -> None:
        """Refuse a number no sensor, time or count comes near (``1e400`` is infinity)."""
        if not (math.isfinite(value) and abs(value) <= GUARD_NUMBER_LIMIT):
            raise self.fail(
                f"the number {shown(value)} is too large for a condition "
                f"(at most {GUARD_NUMBER_LIMIT:g})",
                node,
                "compare with a number a sensor can read, e.g. range.distance_cm < 20",
            )

    def unit_of(self, node: ast.expr) -> str | None:
        if isinstance(node, ast.Name | ast.Attribute) and not self.is_quantity(node):
            return self.name(node)[1]
        return None

    def is_quantity(self, node: ast.expr) -> bool:
        return isinstance(node, ast.Name) and node.id in self.quantities

    def operand(self, node: ast.expr, unit: str | None) -> _Eval:
        if (
            isinstance(node, ast.UnaryOp)
            and isinstance(node.op, ast.USub)
            and self.is_quantity(node.operand)
        ):  # 'pose.x_mm < -10 cm': the minus belongs to the number with its unit
            magnitude = self.operand(node.operand, unit)
            return lambda env: -magnitude(env)
        if self.is_quantity(node):
            assert isinstance(node, ast.Name)
            value = self._in_unit(node, unit)
            self.check_number(self.quantities[node.id].value, node)
            return lambda env: value
        return self.node(node)

    def compare(self, node: ast.Compare) -> _Eval:
        items = [node.left, *node.comparators]
        known = {*_PLAIN, *_ATTRS, "visits", "in_region", "True", "False", *self.quantities}
        for item in items:
            others = [other for other in items if other is not item]
            if (
                isinstance(item, ast.Name)
                and item.id not in known
                and any(isinstance(other, ast.Attribute) for other in others)
            ):  # bumper.any == yes, line.left == black: a word where a value goes
                raise self.fail(
                    f"'{item.id}' is not a value a condition knows",
                    item,
                    "a sensor's value is a number or true/false: compare it with a number in"
                    " the unit its name ends in, or with true or false",
                )
        if any(self.is_quantity(item) for item in items):
            # 'range.distance < 20 cm': the unit written on the number says which is meant
            items = [_with_unit_suffix(item) for item in items]
        units = [self.unit_of(item) for item in items]
        unit = next((u for u in units if u), None)
        numbers = [item for item in items if self.is_quantity(_unsigned(item))]
        if numbers:
            for item, item_unit in zip(items, units, strict=True):
                # 'bumper.any < 2 cm' would otherwise read as 'bumper.any < 20'
                named = isinstance(item, ast.Name | ast.Attribute) and not self.is_quantity(item)
                if not item_unit and named:
                    raise self.fail(
                        f"'{ast.unparse(item)}' has no unit, so it cannot be compared with a"
                        " number that has one",
                        numbers[0],
                        "write the number without a unit",
                    )
        parts = [self.operand(item, unit) for item in items]
        ops = []
        for op in node.ops:
            func = _COMPARE.get(type(op))
            if func is None and isinstance(op, ast.Is | ast.IsNot):
                raise self.fail(
                    f"'{'is not' if isinstance(op, ast.IsNot) else 'is'}' is not a comparison"
                    " in a condition",
                    node,
                    self._is_meant(node),
                )
            if func is None:
                raise self.fail("use < <= > >= == or != to compare", node)
            ops.append(func)

        def evaluate(env: GuardEnv) -> bool:
            left = parts[0](env)
            for func, part in zip(ops, parts[1:], strict=True):
                right = part(env)
                if not func(left, right):
                    return False
                left = right
            return True

        return evaluate

    def name(self, node: ast.Name | ast.Attribute) -> tuple[_Eval, str | None]:
        if isinstance(node, ast.Name):
            if node.id in self.quantities:
                raise self.fail("a number with a unit must be compared with a sensor value", node)
            if node.id in _PLAIN:
                unit, needs = _PLAIN[node.id]
                if needs:
                    self.capabilities.add(needs)
                ident = node.id
                return (lambda env: env.sensor(ident, None)), unit
            if node.id in _ATTRS or node.id in ("visits", "in_region"):
                raise self.fail(
                    f"'{node.id}' needs a '.' and a name after it", node, _dotted_example(node.id)
                )
            raise self.unknown(node.id, node)
        value = node.value
        if isinstance(value, ast.Name) and value.id == "self":  # "self.close": a method's name
            raise self.fail(
                "a condition written as text names things without 'self.'",
                value,
                f"a condition method is named alone, in quotes: write '{node.attr}'"
                if node.attr not in _PLAIN
                else f"write {node.attr}",
            )
        if (
            isinstance(value, ast.Attribute)
            and isinstance(value.value, ast.Name)
            and value.value.id == "self"
        ):
            raise self.fail(
                "a condition written as text names the sensors without 'self.'",
                value.value,
                f"write {value.attr}.{node.attr}",
            )
        if not isinstance(value, ast.Name):
            raise self.fail("a name has at most one '.'", node)
        root, attr = value.id, node.attr
        if root == "visits":
            if self.state_names is not None and attr not in self.state_names:
                close = difflib.get_close_matches(attr, sorted(self.state_names), n=1)
                raise self.fail(
                    f"'visits.{attr}': there is no state '{attr}'",
                    node,
                    f"did you mean 'visits.{close[0]}'?" if close else None,
                )
            self.states.add(attr)
            return (lambda env: env.visits(attr)), None
        if root == "in_region":
            region = self.region_names.get(attr, attr)
            self.regions.add(region)
            self.capabilities.add(cap.DRIVE_BASE)  # odometry tells where in the world it is
            return (lambda env: env.in_region(region)), None
        if root not in _ATTRS:
            raise self.unknown(root, value)
        attrs = _ATTRS[root]
        if attr not in attrs and f"{attr}_mm" in attrs:
            named = [a for a in sorted(attrs) if a.startswith(f"{attr}_")]
            raise self.fail(
                f"'{root}.{attr}' needs its unit in the name: "
                + " or ".join(f"'{root}.{a}'" for a in named),
                node,
                f"e.g. {root}.{named[0]} < 20, or give the number a unit: {root}.{attr} < 2 cm",
            )
        if attr not in attrs:
            close = difflib.get_close_matches(attr, sorted(attrs), n=1)
            raise self.fail(
                f"'{root}' has no '{attr}' (it has {', '.join(sorted(attrs))})",
                node,
                _UNREADABLE.get(f"{root}.{attr}")
                or (f"did you mean '{root}.{close[0]}'?" if close else None),
            )
        unit, needs = attrs[attr]
        self.capabilities.add(needs)
        return (lambda env: env.sensor(root, attr)), unit or None

    def unknown(self, name: str, node: ast.AST) -> GuardError:
        known = [*_PLAIN, *(f"{r}.{a}" for r, attrs in _ATTRS.items() for a in attrs), "visits"]
        roots = [*_PLAIN, *_ATTRS, "visits", "in_region"]
        close = difflib.get_close_matches(name, roots, n=1)
        # a sensor's value without its sensor (distance_cm for range.distance_cm), or without
        # its sensor and unit (distance): the sensors that have it, in cm where there is a choice
        owners = [f"{r}.{a}" for r, attrs in _ATTRS.items() for a in attrs if a == name]
        if not owners:
            owners = [
                f"{r}.{a}" for r, attrs in _ATTRS.items() for a in attrs if a.startswith(f"{name}_")
            ]
            owners = [o for o in owners if o.endswith("_cm")] or owners
        if name.lower() in TIME_WORDS:  # time > 5: which clock was meant
            return self.fail(
                f"unknown name '{name}' in a condition: a condition reads two clocks",
                node,
                "write elapsed, the seconds since the mission started, or state_time, the"
                " seconds since this state began: e.g. state_time > 5",
            )
        if owners and not close:
            return self.fail(
                f"unknown name '{name}' in a condition: a sensor's value is named with its"
                " sensor" + ("" if owners[0].endswith(f".{name}") else " and its unit"),
                node,
                "write " + " or ".join(f"'{o}'" for o in owners[:3]),
            )
        return self.fail(
            f"unknown name '{name}' in a condition",
            node,
            f"did you mean '{close[0]}'?" if close else f"names: {', '.join(known[:8])}, ...",
        )


TIME_WORDS = frozenset({"time", "timer", "time_s", "seconds", "secs", "clock", "t", "duration"})
"""Words a student reads the time with, where a condition has elapsed and state_time (a YAML
condition, and ``self.`` in a Python one)."""


def _call_meant(node: ast.Call) -> str | None:
    """What a call in a condition written as text meant: ``visits('turn')`` (or
    ``self.visits('turn')``) is ``visits.turn``; ``None`` for another call."""
    func = node.func
    name = (
        func.id
        if isinstance(func, ast.Name)
        else func.attr
        if isinstance(func, ast.Attribute)
        else ""
    )
    given = node.args[0] if len(node.args) == 1 else None
    if name == "visits" and isinstance(given, ast.Constant) and isinstance(given.value, str):
        return f"a state's visits are read with a '.': write visits.{given.value}"
    if name == "visits" and isinstance(given, ast.Name):  # visits(turn)
        return f"a state's visits are read with a '.': write visits.{given.id}"
    if not node.args and not node.keywords:  # elapsed(), bumper.any()
        return f"a value is read without brackets: write {ast.unparse(func)}"
    return None


def _unclosed(source: str) -> GuardError | None:
    """A condition with a ``(`` it never closes, or a ``)`` it never opened."""
    open_at: list[int] = []
    for at, char in enumerate(source):
        if char == "(":
            open_at.append(at)
        elif char == ")":
            if not open_at:
                return GuardError(
                    f"cannot read the condition '{source}': this ')' closes no '('",
                    at,
                    "take it away, or add the '(' it closes",
                )
            open_at.pop()
    if open_at:
        return GuardError(
            f"cannot read the condition '{source}': this '(' is never closed",
            open_at[-1],
            "add ')' where what it groups ends",
        )
    return None


def _with_unit_suffix(node: ast.expr) -> ast.expr:
    """``range.distance`` -> ``range.distance_mm``, when a number with a unit sits beside it."""
    if (
        isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.attr not in _ATTRS.get(node.value.id, {})
        and f"{node.attr}_mm" in _ATTRS.get(node.value.id, {})
    ):
        return ast.copy_location(ast.Attribute(node.value, f"{node.attr}_mm", node.ctx), node)
    return node


_MISTAKES: tuple[tuple[re.Pattern[str], str, str], ...] = (
    (
        re.compile(f"[{CURLY_QUOTES}]"),
        "'{found}' is a curly quote, as a word processor writes it",
        'type straight quotes around the condition, or none: "{fixed}"',
    ),
    (
        re.compile(f"[{DASHES}]"),
        "'{found}' is a dash, as a word processor writes a minus",
        "type the minus key: {fixed}",
    ),
    (re.compile(r"&&"), "'&&' is not a condition word", "write 'and': {fixed}"),
    (re.compile(r"\|\|"), "'||' is not a condition word", "write 'or': {fixed}"),
    (re.compile(r"!(?!=)"), "'!' is not a condition word", "write 'not': {fixed}"),
    (
        re.compile(r"\b(?!(?:and|or|not)\b)(?i:and|or|not)\b"),
        "'{found}' is written in lower case",
        "write {fixed}",
    ),
    (
        re.compile(r"=<|=>"),
        "'{found}' is not a comparison",
        "write it the other way round: {fixed}",
    ),
    (
        re.compile(r"(?<![<>=!])=(?!=)"),
        "'=' sets a value; a condition compares",
        "write '==' to compare: {fixed}",
    ),
    (
        re.compile(r"\b(?:is\s+)?(?:less|smaller|lower|fewer)\s+than\b"),
        "'{found}' is written '<' in a condition",
        "write {fixed}",
    ),
    (
        re.compile(r"\b(?:is\s+)?(?:greater|more|bigger|higher|larger)\s+than\b"),
        "'{found}' is written '>' in a condition",
        "write {fixed}",
    ),
    (
        re.compile(r"\b(?:is\s+equal\s+to|equals)\b"),
        "'{found}' is written '==' in a condition",
        "write {fixed}",
    ),
    (
        re.compile(r"\b(?:and|or|not)\s*$"),
        "'{found}' at its end needs a condition after it",
        "finish it, or take away the last word",
    ),
    (
        re.compile(r":\s*$"),
        "a condition has no ':' at its end",
        "take it away: {fixed}",
    ),
    (
        re.compile(r"(?<=\d)\s*%"),
        "'%' is not a unit a condition knows",
        "a value is in the unit its name ends in, a reflection in percent: {fixed}",
    ),
    (
        re.compile(r"\d,\d"),
        "a decimal comma in a condition",
        "write decimals with a point: {fixed}",
    ),
    (
        re.compile(
            r"(?<=\d)\s*(?!(?:and|or|not|true|false|if|else|is|in"
            r"|mm|cm|m|ms|s|sec|min|deg|rad)\b)([A-Za-z]+)\b"
        ),
        "'{found}' is not a unit a condition knows",
        "use mm, cm, m, s, ms, min, deg or rad, e.g. range.distance < 20 cm",
    ),
)
_FIXES = {
    "&&": " and ",
    "||": " or ",
    "!": "not ",
    "=<": "<=",
    "=>": ">=",
    "=": "==",
    "%": "",
    ":": "",
}
_COMPARISON_WORDS = {"less": "<", "smaller": "<", "lower": "<", "fewer": "<", "greater": ">"}
_COMPARISON_WORDS.update(dict.fromkeys(("more", "bigger", "higher", "larger"), ">"))
_COMPARISON_WORDS.update(dict.fromkeys(("equal", "equals"), "=="))
_FIXES.update(dict.fromkeys(CURLY_QUOTES, ""))
_FIXES.update(dict.fromkeys(DASHES, "-"))


_HALF_COMPARISON = re.compile(
    r"(?P<value>[\w.]+)\s*(?P<first>[<>]=?|==|!=)\s*(?P<limit>[^\s]+(?:\s+[a-z]+)?)\s+"
    r"(?P<word>and|or)\s*(?P<second>[<>]=?|==|!=)"
)
_BETWEEN = re.compile(r"(?P<value>[\w.]+)\s+(?:is\s+)?between\s+(?P<low>\S+)\s+and\s+(?P<high>\S+)")


def _half_comparison(source: str) -> GuardError | None:
    """``range.distance_cm < 20 and > 5`` (the value left out of the second comparison) and
    ``range.distance_cm between 5 and 20``, said with the condition written in full."""
    half = _HALF_COMPARISON.search(source)
    if half is not None:
        at = half.start("second")
        fixed = " ".join(f"{source[:at]}{half['value']} {source[at:]}".split())
        return GuardError(
            f"cannot read the condition '{source}': '{half['word']}' joins two whole comparisons",
            at,
            f"name the value again: {fixed}",
        )
    between = _BETWEEN.search(source)
    if between is not None:
        fixed = f"{between['low']} < {between['value']} < {between['high']}"
        return GuardError(
            f"cannot read the condition '{source}': 'between' is written with two '<'",
            between.start() + source[between.start() :].index("between"),
            f"write {source[: between.start()]}{fixed}{source[between.end() :]}".strip(),
        )
    return None


def _syntax_mistake(source: str) -> GuardError | None:
    """A located message with a hint for a common mistake in a condition that did not parse."""
    half = _half_comparison(source)
    if half is not None:
        return half
    for pattern, message, hint in _MISTAKES:
        match = pattern.search(source)
        if match is None:
            continue
        found = match.group(match.lastindex or 0).strip()
        words = [_COMPARISON_WORDS[w] for w in found.split() if w in _COMPARISON_WORDS]
        if found.lower() in ("and", "or", "not"):  # AND, Or: the words in lower case
            fixed = pattern.sub(lambda word: word.group(0).lower(), source)
        elif found in _FIXES:
            fixed = re.sub(r"\s+", " ", pattern.sub(_FIXES[found], source)).strip()
        elif words:
            fixed = re.sub(r"\s+", " ", pattern.sub(words[0], source)).strip()
        else:
            fixed = source.replace(match.group(0), match.group(0).replace(",", "."))
        offset = match.start(match.lastindex or 0)
        return GuardError(
            f"cannot read the condition '{source}': {message.format(found=found)}",
            offset,
            hint.format(fixed=fixed),
        )
    return None


def _unsigned(node: ast.expr) -> ast.expr:
    """The number under a leading minus (``-10 cm``), else the node itself."""
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        return node.operand
    return node


def _default_unit(unit: str) -> str | None:
    for dimension_key, base in (("distance", "mm"), ("time", "s"), ("angle", "deg")):
        if (
            unit in DIMENSIONS[dimension_key].units
            or unit.lower() in DIMENSIONS[dimension_key].units
        ):
            return base
    return None


def compile_guard(
    source: str, state_names: frozenset[str] | None = None, *, truth: bool = False
) -> Guard:
    """Compile a guard expression.

    Args:
        source: The expression, e.g. ``"range.distance_cm < 20 and not bumper.any"``.
        state_names: The mission's states, to check ``visits.STATE`` (``None`` skips it).
        truth: True for a condition, which must be true or false: a number alone (``20``,
            ``range.distance_cm``, ``visits.turn and bumper.any``) is refused, as it would
            hold whenever it is not 0. False for a value (a ``plot:`` channel).

    Raises:
        GuardError: With the offset of the problem and a hint where one fits.
    """
    if not isinstance(source, str) or not source.strip():
        raise GuardError("a condition cannot be empty")
    return _Compiler(source, state_names, truth=truth).compile()


def guard_names() -> Mapping[str, str | None]:
    """Every name a guard can read, with the capability it needs (for docs and errors)."""
    names: dict[str, str | None] = {name: needs for name, (_, needs) in _PLAIN.items()}
    for root, attrs in _ATTRS.items():
        for attr, (_, needs) in attrs.items():
            names[f"{root}.{attr}"] = needs
    names["visits.STATE"] = None
    names["in_region.NAME"] = cap.DRIVE_BASE
    return names
