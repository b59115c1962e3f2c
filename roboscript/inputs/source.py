"""Safe YAML with positions: every mapping and list remembers where each item was written.

Missions, robot profiles, worlds and test specs are all read through :func:`load_yaml`, so
every error about them can name ``file:line:col``. Only the YAML safe subset is accepted:
tags such as ``!!python/object`` are refused, as are duplicate keys. Dates, times and the
other YAML 1.1 implicit types stay text. A hostile file (an alias bomb, deep nesting, a device
or a pipe, a huge file or number) is refused before any expensive work, at the limits of
:mod:`roboscript.inputs.limits`; a YAML syntax mistake is explained in a beginner's terms (a
tab, a bracket or quote never closed, a line indented wrongly). This module is the package's
only user of ``yaml``.

A :data:`Mark` is a place in the file being read; a :class:`Location` is a place in any file
(a mark with its file), the one location type missions, worlds, profiles and test specs use.
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Hashable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from roboscript.errors import InputError, nearby_file, pasted_with_it
from roboscript.inputs.limits import (
    MAX_DEPTH,
    MAX_FILE_BYTES,
    MAX_INTEGER_DIGITS,
    MAX_VALUES,
    name_too_long,
)
from roboscript.inputs.quantities import clock_time, without_leading_zeros

__all__ = [
    "YAML_1_1_WORDS",
    "Location",
    "Mark",
    "YamlList",
    "YamlMap",
    "load_yaml",
    "load_yaml_text",
    "read_source",
]

Mark = tuple[int, int]
"""A 1-based (line, column)."""


@dataclass(frozen=True)
class Location:
    """Where something was written: file, 1-based line and column."""

    path: str
    line: int | None = None
    col: int | None = None

    @classmethod
    def at(cls, path: str, mark: Mark | None) -> Location:
        """The place ``mark`` in ``path`` (the whole file when ``mark`` is ``None``)."""
        return cls(path, *(mark or (None, None)))

    def __str__(self) -> str:
        text = self.path
        if self.line is not None:
            text += f":{self.line}"
            if self.col is not None:
                text += f":{self.col}"
        return text


class YamlMap(dict[str, Any]):
    """A mapping from YAML that knows where its keys and values were written.

    Attributes:
        mark: Where the mapping starts.
        key_marks: Where each key was written.
        value_marks: Where each value starts.
        quoted: Keys whose value was written in quotes.
    """

    mark: Mark
    key_marks: dict[str, Mark]
    value_marks: dict[str, Mark]
    quoted: set[str]

    @classmethod
    def at(cls, mark: Mark, values: dict[str, Any] | None = None) -> YamlMap:
        """A mapping that was not written as one (an absent value, a value given alone),
        with every key and value placed at ``mark``."""
        made = cls(values or {})
        made.mark, made.key_marks, made.value_marks, made.quoted = mark, {}, {}, set()
        return made

    def key_mark(self, key: str) -> Mark:
        """Where ``key`` was written (the mapping's start if it was not)."""
        return self.key_marks.get(key, self.mark)

    def value_mark(self, key: str) -> Mark:
        """Where the value of ``key`` starts (the mapping's start if absent)."""
        return self.value_marks.get(key, self.mark)

    def text_mark(self, key: str, offset: int = 0) -> Mark:
        """Where character ``offset`` of the value of ``key`` was written (inside its quotes)."""
        line, col = self.value_mark(key)
        return line, col + (1 if key in self.quoted else 0) + offset


class YamlList(list[Any]):
    """A list from YAML that knows where each item was written."""

    mark: Mark
    item_marks: list[Mark]


def _mark(node: yaml.Node) -> Mark:
    return node.start_mark.line + 1, node.start_mark.column + 1


def _at(mark: Any) -> Mark:
    return mark.line + 1, mark.column + 1


_NAME_LIKE = re.compile(r"[^\W\d][\w.\-]*")
"""One word, as state, action, robot and world names are written."""

_WHOLE_NUMBER = re.compile(r"[-+]?\d+")

_SHORT_TAG = "tag:yaml.org,2002:"


_OCTAL = re.compile(r"[-+]?0[0-7_]+")
"""``010``, which YAML 1.1 reads as an octal number: 8."""


def _refuse_yaml_1_1_number(node: yaml.ScalarNode) -> None:
    """Refuse the numbers YAML 1.1 reads as other than what is written, with no word:
    ``1:30`` (90, counted in sixties as a clock counts) and ``010`` (8, in octal).

    In quotes they are text, which a quantity's reader explains in its own terms."""
    if node.style is not None:  # !!int "010": the writer's own choice
        return
    text = str(node.value)
    clock = clock_time(text)
    if clock is not None:
        raise _RefusedError(
            f"YAML reads {text} as the number {clock[0]:g}, counting in sixties as a clock"
            " does, and roboscript reads a number with its unit",
            _mark(node),
            clock[1],
        )
    if _OCTAL.fullmatch(text):
        raise _RefusedError(
            f"{text} starts with a 0, so YAML reads it as an octal number:"
            f" {int(text.replace('_', ''), 8)}",
            _mark(node),
            f"write {without_leading_zeros(text)}, without the leading 0",
        )


class _RefusedError(Exception):
    """A limit or rule of this module broken while PyYAML is mid-parse: a message and a mark.

    Raised instead of the file's :class:`InputError`, which is a ``ValueError``: the loader
    turns PyYAML's own ``ValueError`` into a located error, and must not catch this one.
    """

    def __init__(self, message: str, mark: Mark | None, hint: str | None = None) -> None:
        super().__init__(message)
        self.message, self.mark, self.hint = message, mark, hint


class _Loader(yaml.SafeLoader):
    """SafeLoader that keeps positions, refuses duplicate keys and keeps to the limits."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.text = text
        self.depth = 0  # mappings and lists open, the one being composed included
        self.values = 0  # values composed so far, each alias counted as what it names
        self.aliases = 0
        # Values under each finished node, aliases expanded, by id(node): the tree keeps every
        # node alive while loading, so an id is not reused.
        self.sizes: dict[int, int] = {}

    # --------------------------------------------------------------------------- composing

    def compose_node(self, parent: yaml.Node | None, index: Any) -> Any:
        event: Any = self.peek_event()  # type: ignore[no-untyped-call]
        node: Any
        if isinstance(event, yaml.AliasEvent):
            node = super().compose_node(parent, index)
            size = self.sizes.get(id(node))
            if size is None:  # the anchor is still open: the value would contain itself
                raise _RefusedError(
                    f"the alias *{event.anchor} is used inside the value it names,"
                    " so that value would never end",
                    _at(event.start_mark),
                )
            self.aliases += 1
            self._count(size, event.start_mark)
            return node
        opens = isinstance(event, yaml.CollectionStartEvent)
        self.depth += opens
        if self.depth > MAX_DEPTH:
            raise _RefusedError(
                f"the values here are nested more than {MAX_DEPTH} deep",
                _at(event.start_mark),
                f"a roboscript file nests at most {MAX_DEPTH} levels",
            )
        self._count(1, event.start_mark)
        try:
            node = super().compose_node(parent, index)
        finally:
            self.depth -= opens
        children: list[yaml.Node] = []
        if isinstance(node, yaml.SequenceNode):
            children = node.value
        elif isinstance(node, yaml.MappingNode):
            children = [part for pair in node.value for part in pair]
        self.sizes[id(node)] = 1 + sum(self.sizes[id(child)] for child in children)
        return node

    def _count(self, values: int, where: Any) -> None:
        self.values += values
        if self.values <= MAX_VALUES:
            return
        if self.aliases:
            raise _RefusedError(
                f"the aliases (*name) here expand to more than {MAX_VALUES} values",
                _at(where),
                f"a roboscript file holds at most {MAX_VALUES} values, aliases expanded",
            )
        raise _RefusedError(
            f"the file holds more than {MAX_VALUES} values",
            _at(where),
            f"a roboscript file holds at most {MAX_VALUES} values",
        )

    # ------------------------------------------------------------------------ constructing

    def construct_object(self, node: yaml.Node, deep: bool = False) -> Any:
        try:
            return super().construct_object(node, deep=deep)
        except (_RefusedError, yaml.YAMLError):
            raise
        except (ValueError, OverflowError, TypeError) as exc:
            # A scalar with an explicit tag it does not fit (``!!float abc``): PyYAML's
            # constructors raise plain ValueErrors, which carry no position.
            tag = str(node.tag).replace(_SHORT_TAG, "!!")
            shown = node.value if isinstance(node, yaml.ScalarNode) else "this value"
            raise _RefusedError(f"cannot read {shown!r} as {tag} ({exc})", _mark(node)) from None

    def construct_yaml_int(self, node: yaml.ScalarNode) -> int:
        _refuse_yaml_1_1_number(node)
        digits = len(str(node.value).replace("_", "").lstrip("+-"))
        if digits > MAX_INTEGER_DIGITS:
            raise _RefusedError(
                f"this number has {digits} digits; roboscript reads at most {MAX_INTEGER_DIGITS}",
                _mark(node),
            )
        value: int = super().construct_yaml_int(node)
        return value

    def construct_yaml_float(self, node: yaml.ScalarNode) -> float:
        _refuse_yaml_1_1_number(node)
        value: float = super().construct_yaml_float(node)
        return value

    def construct_yaml_str(self, node: yaml.ScalarNode) -> str:
        value: str = super().construct_yaml_str(node)
        too_long = name_too_long(value)
        if too_long and _NAME_LIKE.fullmatch(value):
            raise _RefusedError(too_long, _mark(node))
        return value

    def construct_yaml_map_with_marks(self, node: yaml.MappingNode) -> Iterator[YamlMap]:
        result = YamlMap()
        result.mark = _mark(node)
        result.key_marks = {}
        result.value_marks = {}
        result.quoted = set()
        yield result
        written = sum(1 for key_node, _ in node.value if key_node.tag != f"{_SHORT_TAG}merge")
        self.flatten_mapping(node)
        # A merge key's pairs come first: the mapping's own keys override them, as YAML says
        # ({<<: *defaults, seed: 2}), and of two merged mappings the first wins.
        merged = len(node.value) - written
        from_merge: set[str] = set()
        before: yaml.Node | None = None
        for index, (key_node, value_node) in enumerate(node.value):
            if node.flow_style:
                self._refuse_decimal_comma(before, key_node, value_node)
            before = value_node
            key = self.construct_object(key_node, deep=True)
            if not isinstance(key, Hashable):
                raise _RefusedError("a key must be a plain word", _mark(key_node))
            key = str(key)
            too_long = name_too_long(key)
            if too_long:
                raise _RefusedError(too_long, _mark(key_node))
            if key in from_merge and index >= merged:
                from_merge.discard(key)
                del result[key]
            elif key in result and index < merged:
                # PyYAML lists the merged mappings last first: a later pair is from a mapping
                # named earlier in '<<: [*a, *b]', which wins, as YAML says
                del result[key]
            if key in result:
                first = result.key_marks[key][0]
                raise _RefusedError(
                    f"'{key}' is given twice (first on line {first})",
                    _mark(key_node),
                    "keep one of the two, or give one of them another name",
                )
            if index < merged:
                from_merge.add(key)
            result[key] = self.construct_object(value_node, deep=True)
            result.key_marks[key] = _mark(key_node)
            result.value_marks[key] = _mark(value_node)
            if isinstance(value_node, yaml.ScalarNode) and value_node.style in ("'", '"'):
                result.quoted.add(key)

    def _refuse_decimal_comma(
        self, before: yaml.Node | None, key_node: yaml.Node, value_node: yaml.Node
    ) -> None:
        """``{speed: 0,2 m/s}``: YAML reads ``speed: 0`` and a key ``2 m/s`` with no value."""
        if (
            isinstance(before, yaml.ScalarNode)
            and before.style is None
            and _WHOLE_NUMBER.fullmatch(before.value)
            and isinstance(key_node, yaml.ScalarNode)
            and key_node.style is None
            and key_node.value[:1].isdigit()
            and isinstance(value_node, yaml.ScalarNode)
            and value_node.tag == f"{_SHORT_TAG}null"
            and self.text[before.end_mark.index : key_node.start_mark.index] == ","
        ):
            written = f"{before.value},{key_node.value}"
            raise _RefusedError(
                f"'{written}' has a decimal comma, which YAML reads as two items",
                _mark(before),
                f"use a decimal point: {before.value}.{key_node.value}",
            )

    def construct_yaml_seq_with_marks(self, node: yaml.SequenceNode) -> Iterator[YamlList]:
        result = YamlList()
        result.mark = _mark(node)
        result.item_marks = [_mark(item) for item in node.value]
        yield result
        result.extend(self.construct_object(item, deep=True) for item in node.value)


YAML_1_1_WORDS: dict[str, bool] = {
    "yes": True,
    "y": True,
    "on": True,
    "no": False,
    "n": False,
    "off": False,
}
"""YAML 1.1's words for true and false (in lower case), which roboscript's YAML reads as the
words they are: a field that is no word says what each was likely meant as (``final: yes``,
``timeout: off``)."""

# YAML 1.1 reads on/off/yes/no as booleans, which would turn a state's "on:" into True.
# Booleans are only true/false, as in YAML 1.2. Dates and times (2024-13-45 would fail to
# construct, 2024-01-05 would become a date no field expects), "=" and the other YAML 1.1
# implicit types stay text: only null, true/false, numbers and the merge key "<<" are read.
_IMPLICIT = {f"{_SHORT_TAG}{name}" for name in ("null", "int", "float", "merge")}
_Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag in _IMPLICIT]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:bool",
    re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"),
    list("tTfF"),
)
_Loader.add_constructor("tag:yaml.org,2002:map", _Loader.construct_yaml_map_with_marks)
_Loader.add_constructor("tag:yaml.org,2002:seq", _Loader.construct_yaml_seq_with_marks)
_Loader.add_constructor("tag:yaml.org,2002:int", _Loader.construct_yaml_int)
_Loader.add_constructor("tag:yaml.org,2002:float", _Loader.construct_yaml_float)
_Loader.add_constructor("tag:yaml.org,2002:str", _Loader.construct_yaml_str)
# Explicit tags for values no reader expects (!!set, !!timestamp...) are refused like
# !!python/object: no roboscript file needs them.
for _tag in ("binary", "timestamp", "omap", "pairs", "set"):
    del _Loader.yaml_constructors[f"{_SHORT_TAG}{_tag}"]


# ------------------------------------------------------------------------- syntax mistakes

_INDENT_HINT = (
    "YAML nests by indentation: line it up, with spaces, with the key or '- ' item it belongs with"
)
_COLON_HINT = (
    "is this line indented further than the one above it? Text holding ': ' goes in quotes"
)


_PYTHON_LINE = re.compile(
    r"^(?:from [\w.]+ import |import [\w.]+$|class \w+\(|def \w+\()", re.MULTILINE
)
"""A line only Python starts so (YAML would read it as text, or refuse it)."""


_SIGN_CONTEXTS = (
    "while scanning a directive",
    "while scanning an anchor",
    "while scanning an alias",
    "while scanning a block scalar",
)
"""What PyYAML was reading when a value starts with %, &, *, | or >, signs of its own."""


def _explain(exc: yaml.MarkedYAMLError, text: str) -> tuple[str, Mark | None, str | None]:
    """A PyYAML syntax error in a beginner's terms: ``(message, where, hint)``."""
    pasted = pasted_with_it(text, python=False)
    if pasted is not None:  # a Markdown fence or a terminal's command copied with the mission
        return pasted[2], (pasted[0], pasted[1]), pasted[3]
    for number, text_line in enumerate(text.splitlines(), 1):
        indent = text_line[: len(text_line) - len(text_line.lstrip())]
        if "\u00a0" in indent:  # copied from a web page: it shows as a space
            message = (
                "this line is indented with non-breaking spaces, copied from a web page or a"
                " document, and YAML indents with plain spaces"
            )
            return (
                message,
                (number, indent.index("\u00a0") + 1),
                "indent it again with the space bar",
            )
    wide = text.find("\uff1a")
    if wide >= 0:  # a keyboard set to Chinese or Japanese
        return (
            "'\uff1a' is a full-width colon, and YAML reads only ':'",
            _offset_mark(text, wide),
            "type ':' with the keyboard set to English",
        )
    python = _PYTHON_LINE.search(text)
    if python is not None:  # a Python mission saved with a .yaml ending
        return (
            "this file holds Python, not YAML",
            _offset_mark(text, python.start()),
            "a Python mission's file name ends in .py",
        )
    problem = str(exc.problem or "invalid YAML")
    context = str(exc.context or "")
    found = problem.rpartition("but found ")[2].strip("'")
    at = _at(exc.problem_mark) if exc.problem_mark else None
    opened = exc.context_mark
    opener = text[opened.index] if opened and opened.index < len(text) else ""
    if "'\\t'" in problem or "tab character" in problem:
        if at is None:
            return "a tab: YAML indents with spaces", None, None
        line, col = at
        index = exc.problem_mark.index if exc.problem_mark else 0
        before = text[text.rfind("\n", 0, index) + 1 : index]
        if before.strip(" \t") == "":
            return f"a tab at {line}:{col}: YAML indents with spaces", at, None
        return f"a tab at {line}:{col}: YAML needs spaces here, not tabs", at, None
    if opened and context.startswith("while parsing a flow") and opener in ("{", "["):
        closer = "}" if opener == "{" else "]"
        got = problem.rpartition("but got ")[2].strip("'")
        if got in ("<stream end>", "}", "]") or (at and at[0] != opened.line + 1):
            hint = f"close it with `{closer}`"
            if got != "<stream end>" and at:
                hint += f" before {at[0]}:{at[1]}"
            end = text.find("\n", opened.index)
            line_text = text[opened.index : end if end >= 0 else len(text)]
            if " #" in line_text and closer in line_text.partition(" #")[2]:
                hint = (  # {drive: {speed: 20 cm/s # fast}}: the comment took the `}}`
                    f"a ' #' starts a comment, which hides the rest of the line, its `{closer}`"
                    f" too: put the comment after the `{closer}`, or take it away"
                )
            return f"this `{opener}` is never closed", _at(opened), hint
        return (
            f"expected `,` or `{closer}` here",
            at,
            f"inside the `{opener}` at {opened.line + 1}:{opened.column + 1}",
        )
    if opened and context == "while scanning a quoted scalar" and "end of stream" in problem:
        return f"this `{opener}` is never closed", _at(opened), f"close the text with `{opener}`"
    if problem.startswith("expected <block end>") and found in ("}", "]"):
        opening = "{" if found == "}" else "["
        return f"this `{found}` closes a `{opening}` that was never opened", at, "remove it"
    if problem.startswith("expected <block end>"):
        return (
            "this line is indented differently from the lines above it",
            at,
            _INDENT_HINT,
        )
    long_key = _long_key(text, exc, problem)
    if long_key is not None:
        return long_key[0], long_key[1], None
    if problem == "mapping values are not allowed here":
        index = exc.problem_mark.index if exc.problem_mark else 0
        line_text = text[text.rfind("\n", 0, index) + 1 :].split("\n", 1)[0]
        two = re.match(r"^(\s*(?:- )?[\w-]+):\s+([\w-]+):\s+(\S.*?)\s*$", line_text)
        if two is not None:  # do: drive: {distance: 50 cm}
            return (
                "a ':' is not allowed here: this line holds two keys",
                at,
                (
                    "a value that is itself a 'key: value' goes in braces:"
                    f" {two.group(1).strip()}: {{{two.group(2)}: {two.group(3)}}}; text holding"
                    " ': ' goes in quotes"
                ),
            )
        glued = _glued_above(text, index)
        if glued is not None:
            return glued
        return (
            "a ':' is not allowed here",
            at,
            _COLON_HINT,
        )
    if opened and problem == "could not find expected ':'":
        return (
            "this line needs a ':' after its key",
            _at(opened),
            "write 'key: value', or indent it as part of the line above",
        )
    if problem == "sequence entries are not allowed here" or (
        problem.startswith("expected the node content") and found == "-"
    ):
        return (
            "'- ' starts a list item, and a list cannot go here",
            at,
            "a negative number has no space after its minus: write -90 deg, not - 90 deg",
        )
    if found == "<stream end>":
        return "the file ends where a value was expected", at, "close each `[` and `{` it opens"
    if problem.startswith("expected the node content") and found == ",":
        return "a value is missing before this `,`", at, "write a value, or remove the comma"
    if problem.startswith("expected the node content"):
        return f"a value is missing before this `{found}`", at, None
    if problem == "but found another document":
        return (
            "this file holds a second document after `---`, and a roboscript file holds one",
            at,
            "remove the `---` line and what follows it, or move that to a file of its own",
        )
    if problem.startswith("found character") and problem.endswith("cannot start any token"):
        char = problem.split("'")[1] if problem.count("'") >= 2 else "?"
        return f"'{char}' cannot start a value in YAML", at, f'put the text in quotes: "{char}..."'
    if context in _SIGN_CONTEXTS and opener:
        return (
            f"'{opener}' at the start of a value is a sign YAML reads, not text",
            _at(opened),
            f'put the text in quotes: "{opener}..."',
        )
    if problem.startswith("found unknown escape character"):
        return (
            'inside "..." a backslash starts an escape such as \\n',
            (at[0], at[1] - 1) if at else None,  # at the backslash, not the letter after it
            "write the text in single quotes, 'like\\this', or use / instead of \\",
        )
    if problem.startswith("found undefined alias"):
        name = problem.rpartition(" ")[2].strip("'")
        return f"the alias *{name} names no anchor &{name} written before it", at, None
    if "could not determine a constructor" in str(exc):
        tag = problem.split()[-1].strip("'").replace(_SHORT_TAG, "!!")
        return f"tag {tag} is not allowed in roboscript files", at, None
    return problem, at or (_at(opened) if opened else None), None


_GLUED_DASH = re.compile(r"^(\s*)-([\[{A-Za-z_\"'].*)$")
_GLUED_COLON = re.compile(r"^(\s*)([A-Za-z_][\w-]*):([A-Za-z_\"'\[{].*)$")


def _glued_above(text: str, index: int) -> tuple[str, Mark | None, str | None] | None:
    """The line at ``index``, or one of the two above it, whose '-' or ':' lacks the space
    after it, which made YAML read it as one word (``-{if: ...}``, ``mission:m``) and fail
    a little further on."""
    end = text.find("\n", index)
    lines = text[: end if end >= 0 else len(text)].split("\n")
    for number in range(len(lines), max(0, len(lines) - 3), -1):  # YAML fails within two lines
        line = lines[number - 1].rstrip("\r")
        dash = _GLUED_DASH.match(line)
        if dash is not None:
            return (
                "'-' starts a list item only with a space after it",
                (number, len(dash.group(1)) + 1),
                f"write - {dash.group(2)}",
            )
        colon = _GLUED_COLON.match(line)
        if colon is not None and "://" not in line:
            key, value = colon.group(2), colon.group(3)
            word = f"{key}:{value.split()[0] if value.split() else value}"
            return (
                f"'{word}' has no space after its ':', so YAML reads it as one word",
                (number, len(colon.group(1)) + len(key) + 1),
                f"write {key}: {value}",
            )
    return None


def _long_key(
    text: str, exc: yaml.MarkedYAMLError, problem: str
) -> tuple[str, tuple[int, int]] | None:
    """A key longer than YAML reads as one (1024 characters), which it reports as a ':' out
    of place or a missing one: named as the too-long name it is, where it starts."""
    if problem == "mapping values are not allowed here" and exc.problem_mark:
        mark = exc.problem_mark  # at the ':' after the key
        start = text.rfind("\n", 0, mark.index) + 1
        key = text[start : mark.index]
    elif problem == "could not find expected ':'" and exc.context_mark:
        mark = exc.context_mark  # at the start of the key
        start = text.rfind("\n", 0, mark.index) + 1
        end = text.find("\n", mark.index)
        key = text[start : end if end >= 0 else len(text)].rstrip().removesuffix(":")
    else:
        return None
    name = key.strip(" -")
    too_long = name_too_long(name, "key")
    if too_long is None or ":" in name:
        return None
    return too_long, (mark.line + 1, len(key) - len(key.lstrip(" -")) + 1)


# -------------------------------------------------------------------------------- loading


def load_yaml_text(
    text: str, path: str = "<input>", *, error: type[InputError] = InputError
) -> Any:
    """Parse YAML text safely, keeping positions, within :mod:`~roboscript.inputs.limits`.

    Args:
        text: The YAML document.
        path: The file name to put in error messages.
        error: The :class:`InputError` subclass to raise (``MissionError``, ``WorldError``...).

    Raises:
        InputError: The text is not valid YAML, uses a tag outside the safe subset, repeats a
            key, or breaks a limit (nesting, values with aliases expanded, a name's length,
            a number's digits). Always located at ``path:line:col`` when the place is known.
    """

    def located(message: str, mark: Mark | None, hint: str | None = None) -> InputError:
        line, col = mark or (None, None)
        return error(message, path=path, line=line, col=col, hint=hint)

    if len(text) > MAX_FILE_BYTES:  # text handed in directly, not read by load_yaml
        raise located(_too_big(len(text), "characters"), None)
    try:
        loader = _Loader(text)
    except yaml.reader.ReaderError as exc:
        # PyYAML checks for unprintable characters before it parses anything.
        offset = max(0, exc.position)
        code = f"U+{exc.character:04X}" if isinstance(exc.character, int) else repr(exc.character)
        raise located(
            f"the file contains a character YAML does not allow ({code})",
            _offset_mark(text, offset),
        ) from None
    try:
        return loader.get_single_data()
    except _RefusedError as exc:
        raise located(exc.message, exc.mark, exc.hint) from None
    except yaml.MarkedYAMLError as exc:
        raise located(*_explain(exc, text)) from None
    except yaml.YAMLError as exc:
        raise located(f"invalid YAML: {exc}", None) from None
    finally:
        loader.dispose()


def _offset_mark(text: str, offset: int) -> Mark:
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _too_big(size: int, unit: str) -> str:
    return (
        f"the file is {size} {unit}; roboscript reads files of at most"
        f" {MAX_FILE_BYTES // 1024 // 1024} MiB ({MAX_FILE_BYTES} bytes)"
    )


_NOT_A_FILE = {
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFIFO: "a named pipe",
    stat.S_IFSOCK: "a socket",
}


def _refuse_unless_regular(mode: int, shown: str, error: type[InputError]) -> None:
    if stat.S_ISDIR(mode):
        raise error("this is a folder, not a file", path=shown, hint="give the path of a file")
    if not stat.S_ISREG(mode):
        kind = _NOT_A_FILE.get(stat.S_IFMT(mode), "not an ordinary file")
        raise error(
            f"this is {kind}, not an ordinary file", path=shown, hint="give the path of a file"
        )


def read_source(path: str | Path, *, error: type[InputError] = InputError) -> str:
    """The text of a file a user wrote, at most :data:`~.limits.MAX_FILE_BYTES` long.

    The path is checked with :func:`os.stat` before it is opened: a folder, a device
    (``/dev/zero``), a named pipe or a socket is refused unread, as is a file over the size
    limit; the open file is checked again, in case the path changed in between.

    Raises:
        InputError: The file cannot be read, is not an ordinary file, is too large, or is not
            UTF-8 (located at the first bad byte).
    """
    shown = str(path)
    try:
        found = os.stat(path)
        _refuse_unless_regular(found.st_mode, shown, error)
        if found.st_size > MAX_FILE_BYTES:
            raise error(_too_big(found.st_size, "bytes"), path=shown)
        # Non-blocking, so a path swapped for a pipe since the stat cannot hang the open.
        flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
        fd = os.open(path, flags | getattr(os, "O_CLOEXEC", 0))
        with os.fdopen(fd, "rb") as file:
            _refuse_unless_regular(os.fstat(fd).st_mode, shown, error)
            data = file.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise error(
            f"cannot read the file: {exc.strerror or exc}", path=shown, hint=nearby_file(path)
        ) from None
    if len(data) > MAX_FILE_BYTES:
        raise error(_too_big(len(data), "bytes or more"), path=shown)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        start = data.rfind(b"\n", 0, exc.start) + 1
        col = len(data[start : exc.start].decode("utf-8", errors="replace")) + 1
        raise error(
            f"byte 0x{data[exc.start]:02X} is not UTF-8 text",
            path=shown,
            line=line,
            col=col,
            hint="save the file as UTF-8",
        ) from None


def load_yaml(path: str | Path, *, error: type[InputError] = InputError) -> Any:
    """Read and parse a YAML file safely (see :func:`read_source` and
    :func:`load_yaml_text`).

    Raises:
        InputError: The file cannot be read, breaks a limit, or is not valid YAML.
    """
    return load_yaml_text(read_source(path, error=error), str(path), error=error)
