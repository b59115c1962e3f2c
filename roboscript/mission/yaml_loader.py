"""Read a YAML mission into a :class:`~roboscript.mission.spec.MissionSpec`.

Every problem is reported in the student's terms, ``file:line:col: error: ...`` with a "did
you mean" where one fits. All problems in a file are collected, so one run of
``roboscript check`` lists them all; the first is raised, carrying the rest.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from roboscript.actions import ACTION_WORDS, ACTIONS, Action, Parallel, Repeat
from roboscript.actions.base import PARAM_EXAMPLES, params_of
from roboscript.errors import InputError, MissionError, did_you_mean
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.quantities import (
    DIMENSIONS,
    QuantityError,
    bare_number_warning,
    parse_quantity,
)
from roboscript.inputs.source import (
    YAML_1_1_WORDS,
    Location,
    Mark,
    YamlList,
    YamlMap,
    load_yaml,
    load_yaml_text,
)
from roboscript.mission.behaviours import behaviours_from_yaml
from roboscript.mission.builder import MissionBuilder
from roboscript.mission.channels import MAX_CHANNELS
from roboscript.mission.files import FileReferenceError, beside_mission
from roboscript.mission.key_mistakes import is_a_state, meant_at_top, meant_in_state, meant_outcome
from roboscript.mission.spec import (
    OUTCOMES,
    ActionSpec,
    MissionSpec,
    StateSpec,
    TransitionSpec,
)

__all__ = ["load_yaml_mission", "parse_yaml_mission"]


def _at(where: Location) -> Callable[[int], Location]:
    """A locator for a mistake anywhere in one list item: the item itself."""
    return lambda _offset: where


_TOP_KEYS = ("mission", "description", "robot", "world", "behaviours", "initial", "states", "plot")
_STATE_KEYS = ("do", "during", "on", "when", "timeout", "final", "description")
_INNER_KEYS = ("states", "initial", "description")
_CHOICE_KEYS = ("if", "goto")
_COMPOSITES = ("parallel", "repeat", "states", "mission")

_STATE_EXAMPLES = {
    "do": "write the action it runs, e.g. do: {drive: {distance: 50 cm}}",
    "during": "write a list of actions, or leave 'during' out",
    "on": "write where each outcome goes, e.g. on: {done: NEXT}",
    "when": "write a list of choices, e.g. when: [{if: bumper.any, goto: NEXT}]",
    "timeout": "write how long it may last, e.g. timeout: 10 s, or leave 'timeout' out",
    "final": "write final: success or final: failure, or leave 'final' out",
}
"""What each of a state's keys written with no value is given, as the fix says."""

_NO_LIMIT = frozenset(
    {"none", "never", "false", "unlimited", "infinite"}
    | {word for word, true in YAML_1_1_WORDS.items() if not true}
)
"""What a timeout is written as when no time limit is meant: YAML 1.1's words for false
(``off``, ``no``) among them."""

_REPEAT = {"times": "how many times", "do": "the action to repeat"}
"""What a ``repeat:`` holds, and what each is."""


def _first_key(items: YamlList) -> str:
    """The name of a list's first mapping's first key (a state written as ``- go:``)."""
    first = items[0] if items else None
    if isinstance(first, YamlMap) and isinstance(first.get("name"), str):
        return str(first["name"])  # - name: go
    return str(next(iter(first))) if isinstance(first, YamlMap) and first else "go"


def _first_written(items: YamlList) -> str:
    """How the first state of a list starts: ``go:``, or ``name: go`` when it is named so."""
    first = items[0] if items else None
    if isinstance(first, YamlMap) and isinstance(first.get("name"), str):
        return f"name: {first['name']}"
    return f"{_first_key(items)}:"


_LOADING: set[str] = set()  # mission files being loaded, to refuse a file that includes itself


_STATES_MISSPELT = frozenset({"state", "states"})
"""``States:`` and ``state:``, whose own "did you mean 'states'?" is the whole story."""


class _Reader:
    """The YAML front end: reads values and where they were written; the builder does the rest."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.build = MissionBuilder(path)
        self.fields = FieldReader(path, MissionError)
        self.actions: Mapping[str, type[Action]] = ACTIONS  # plus the mission's behaviours
        self.broken: frozenset[str] = frozenset()  # behaviours whose file has errors
        # Mission files used as states, by resolved path (None: it had errors), so a file
        # used by several states is read, checked and warned about once.
        self.included: dict[str, MissionSpec | None] = {}

    @property
    def problems(self) -> list[InputError]:
        return self.build.problems

    def problem(self, message: str, mark: Mark | None, hint: str | None = None) -> None:
        self.build.problem(message, self.loc(mark), hint)

    def loc(self, mark: Mark | None) -> Location:
        return Location.at(self.path, mark)

    def unknown_keys(
        self,
        data: YamlMap,
        keys: tuple[str, ...],
        what: str,
        meant: Callable[[str, Any], str | None] | None = None,
    ) -> None:
        self.problems.extend(self.fields.unknown_keys(data, keys, what, meant))

    def without_value(self, data: YamlMap, what: str, examples: Mapping[str, str]) -> list[str]:
        """The keys of ``examples`` written in ``data`` with no value (``speed: ~``, ``done:``
        with nothing after it), each told once with its example."""
        empty = [key for key in examples if key in data and data[key] is None]
        for key in empty:
            self.problem(
                f"'{key}' {what}has no value: YAML reads `~`, `null` and nothing after the"
                " ':' as no value",
                data.value_mark(key),
                examples[key],
            )
        return empty

    def valued(self, data: YamlMap, what: str, examples: Mapping[str, str]) -> YamlMap:
        """``data`` without the keys of ``examples`` written with no value, each told once
        (:meth:`without_value`), so no second message says the key is missing or holds
        'None'."""
        empty = self.without_value(data, what, examples)
        if not empty:
            return data
        kept = YamlMap.at(data.mark, {k: v for k, v in data.items() if k not in empty})
        kept.key_marks, kept.value_marks = data.key_marks, data.value_marks
        kept.quoted = data.quoted
        return kept

    # ------------------------------------------------------------------------------ top

    def read(self, data: Any, inner_of: str | None = None) -> MissionSpec | None:
        if not isinstance(data, YamlMap):
            self.problem(
                "a mission file is a mapping with 'mission:', 'initial:' and 'states:'",
                (1, 1),
                "this file is empty, or holds only comments: is it saved?"
                if data is None
                else _not_a_mapping(data),
            )
            return None
        if inner_of is None:
            self.unknown_keys(data, _TOP_KEYS, "a mission", meant_at_top)
        states_written = data.get("states")
        first = next(iter(states_written), "go") if isinstance(states_written, YamlMap) else "go"
        data = self.valued(
            data, "", {"initial": f"write the state to start in, e.g. initial: {first}"}
        )
        if inner_of is None and "behaviours" in data:
            extra, problems, self.broken = behaviours_from_yaml(
                data["behaviours"], data.value_mark("behaviours"), self.path
            )
            self.problems.extend(problems)
            self.actions = {**ACTIONS, **extra}
        states_raw = data.get("states")
        if isinstance(states_raw, YamlList) and states_raw:
            self.problem(
                "'states:' is written as a list (its lines start with '- '), but it maps"
                " each state's name to the state",
                data.value_mark("states"),
                "take away the '- ' and line the names up: write"
                f" {_first_key(states_raw)}: rather than - {_first_written(states_raw)}",
            )
            return None
        if "states" not in data and any(str(k).lower() in _STATES_MISSPELT for k in data):
            return None  # the key's own "did you mean 'states'?" says it
        if not states_raw and any(is_a_state(v) for k, v in data.items() if k not in _TOP_KEYS):
            return None  # each state at the left edge was told to go under states:
        if not isinstance(states_raw, YamlMap) or not states_raw:
            self.problem(
                "a mission needs 'states:', a mapping of state names to states",
                data.key_mark("states") if "states" in data else data.mark,
                "under states:, indented, write each state by its name, e.g. go: {final: success}"
                if "states" in data
                else "write states: and under it, indented, each state, e.g. go: {final: success}",
            )
            return None
        no_colon = {
            str(name): self.colon_missing(name, raw, states_raw) for name, raw in states_raw.items()
        }
        names = frozenset(no_colon[str(name)] or str(name) for name in states_raw)
        states: dict[str, StateSpec] = {}
        previous: str | None = None
        for name, raw in states_raw.items():
            if no_colon[str(name)]:
                continue
            if previous is not None and self.dedented_state_key(
                str(name), raw, previous, states_raw.key_mark(name)
            ):
                continue
            previous = str(name)
            state = self.state(
                str(name), raw, states_raw.value_mark(name), states_raw.key_mark(name), names
            )
            if state is not None:
                states[state.name] = state
        initial = data.get("initial", next(iter(states_raw)))
        self.build.initial(initial, names, self.loc(data.value_mark("initial")))
        hints = {
            key: self.build.names_a(
                key, data.get(key), self.loc(data.value_mark(key)), f"{key}: {example}"
            )
            for key, example in (("robot", "mirto"), ("world", "square-room"))
        }
        return self.build.mission(
            name=inner_of or data.get("mission", Path(self.path).stem),
            initial=str(initial),
            states=states,
            description=data.get("description"),
            where=self.loc(data.mark),
            robot=hints["robot"],
            world=hints["world"],
            robot_where=self.loc(data.value_mark("robot")),
            world_where=self.loc(data.value_mark("world")),
            plots=self.plots(data["plot"], data.value_mark("plot"), names)
            if inner_of is None and "plot" in data
            else (),
        )

    def plots(self, raw: Any, mark: Mark, names: frozenset[str]) -> tuple[tuple[str, Any], ...]:
        """``plot:``, condition values recorded each tick: a list of expressions."""
        if not isinstance(raw, YamlList):
            self.problem(
                "'plot' is a list of values to record, e.g. plot: [range.distance_cm]", mark
            )
            return ()
        found: list[tuple[str, Any]] = []
        for item, item_mark in zip(raw, raw.item_marks, strict=True):
            guard = self.build.expression(item, names, _at(self.loc(item_mark)), truth=False)
            if guard is not None:
                found.append((str(guard.source), guard))
        if len(found) > MAX_CHANNELS:
            self.problem(
                f"'plot' records at most {MAX_CHANNELS} values (it lists {len(found)})", mark
            )
            return ()
        return tuple(found)

    # ---------------------------------------------------------------------------- states

    def colon_missing(self, name: str, raw: Any, states_raw: YamlMap) -> str | None:
        """``end {final: success}``, read by YAML as a state called ``end {final``: the name
        the student meant (``end``), once told, or ``None``."""
        text = str(name)
        meant = text.split("{", 1)[0].strip()
        if "{" not in text or not meant or not meant.replace("_", "").isalnum():
            return None
        rest = text[len(meant) :].strip()
        self.problem(
            f"a ':' is missing after the state name '{meant}'",
            states_raw.key_mark(name),
            f"write {meant}: {rest}" + (f": {raw}" if raw is not None else ""),
        )
        return meant

    def dedented_state_key(self, name: str, raw: Any, previous: str, mark: Mark) -> bool:
        """True (and a problem said) when a state's own key, such as ``on:``, was indented
        as far as the state names, so YAML made it a state of its own.

        A state may be called ``on`` or ``final``: it is taken as one while all its keys are
        a state's keys."""
        if name not in _STATE_KEYS or raw is None:
            return False
        if isinstance(raw, YamlMap) and all(key in _STATE_KEYS for key in raw):
            return False
        self.problem(
            f"'{name}:' is indented as far as the state names, so it makes a state called '{name}'",
            mark,
            f"indent it two more spaces, under '{previous}:', to make it part of state "
            f"'{previous}'",
        )
        return True

    def state(
        self, name: str, raw: Any, mark: Mark, key_mark: Mark, names: frozenset[str]
    ) -> StateSpec | None:
        if raw is None:
            raw = YamlMap.at(mark)
        if not isinstance(raw, YamlMap):
            items = raw if isinstance(raw, list) else []
            keys = [next(iter(item)) for item in items if isinstance(item, dict) and len(item) == 1]
            listed = bool(keys) and len(keys) == len(items) and all(k in _STATE_KEYS for k in keys)
            self.problem(
                f"state '{name}' must be a mapping (do:, on:, when:, final:)",
                mark,
                # "- do: ...", "- on: ...": a list of one-key items where its keys were meant
                f"write {' and '.join(f'{k}:' for k in keys)} without the '- ' before them: a"
                " state's keys are one under the other, not a list"
                if listed
                else None,
            )
            return None
        misplaced = [key for key in raw if key not in _STATE_KEYS and key in self.actions]
        for key in misplaced:
            self.problem(
                f"'{key}' is an action, and a state runs its action under 'do:'",
                raw.key_mark(key),
                f"write do: {{{key}: {{...}}}}",
            )
        mission_keys = [key for key in raw if key not in _STATE_KEYS and key in _TOP_KEYS]
        for key in mission_keys:
            self.problem(
                f"'{key}' is written once for the whole mission, not in a state",
                raw.key_mark(key),
                "move it to the top, beside 'states:'"
                + (f": initial: {name}" if key == "initial" else ""),
            )
        self.unknown_keys(
            raw, (*_STATE_KEYS, *misplaced, *mission_keys), f"state '{name}'", meant_in_state
        )
        # on: with its outcomes under it not indented: the outcomes' own message says it
        dedented = any(key in OUTCOMES for key in raw)
        raw = self.valued(
            raw,
            f"in state '{name}' ",
            {k: v for k, v in _STATE_EXAMPLES.items() if k != "on" or not dedented},
        )
        action = None
        if "do" in raw:
            action = self.action(raw["do"], raw.value_mark("do"), names, label=name)
        during: list[ActionSpec] = []
        if "during" in raw:
            items = raw["during"]
            if not isinstance(items, YamlList):
                self.problem(
                    "'during' is a list of actions run alongside 'do'", raw.value_mark("during")
                )
            else:
                for item, item_mark in zip(items, items.item_marks, strict=True):
                    extra = self.action(item, item_mark, names, label=name)
                    if extra is not None:
                        during.append(extra)
        on: dict[str, tuple[TransitionSpec, ...]] = {}
        if "on" in raw:
            on = self.on(raw["on"], raw.value_mark("on"), names)
        when: tuple[TransitionSpec, ...] = ()
        if "when" in raw:
            when = self.when(raw["when"], raw.value_mark("when"), names)
        timeout_s = None
        if "timeout" in raw:
            where = self.loc(raw.value_mark("timeout"))
            try:
                seconds = parse_quantity(raw["timeout"], "time")
            except QuantityError as exc:
                written = str(raw["timeout"]).strip().lower()
                self.build.problem(
                    f"state '{name}': timeout: {exc}",
                    where,
                    "a state with no time limit has no 'timeout', so take it away"
                    if isinstance(raw["timeout"], bool)
                    else f"'{raw['timeout']}' is a word here: a state with no time limit has no"
                    " 'timeout', so take it away"
                    if written in _NO_LIMIT
                    else None,
                )
            else:
                timeout_s = self.build.timeout(name, "timeout", seconds, where, raw["timeout"])
                note = bare_number_warning(raw["timeout"], "time")
                if note is not None:
                    message, hint = note
                    self.build.problem(
                        f"state '{name}': timeout: {message}", where, hint, "warning"
                    )
        return self.build.state(
            name,
            action=action,
            during=tuple(during),
            on=on,
            when=when,
            timeout_s=timeout_s,
            final=self.build.final(name, raw.get("final"), self.loc(raw.value_mark("final"))),
            description=raw.get("description"),
            where=self.loc(key_mark),
        )

    def action(
        self, raw: Any, mark: Mark, names: frozenset[str], label: str = ""
    ) -> ActionSpec | None:
        if isinstance(raw, YamlMap) and "states" in raw:
            return self.inline_machine(raw, mark, label)
        if isinstance(raw, YamlMap) and len(raw) == 1 and next(iter(raw)) in _COMPOSITES:
            return self.composite(raw, names, label)
        words = raw.split() if isinstance(raw, str) else []
        if len(words) > 1 and words[0] in self.actions:
            first = words[0]
            self.problem(
                f"'do: {raw}' gives '{first}' its settings as plain text",
                mark,
                "write them as a mapping: do: "
                + _as_mapping(first, self.actions[first], raw.split(None, 1)[1]),
            )
            return None
        if isinstance(raw, str):
            name, params, name_mark = raw, YamlMap.at(mark), mark
        elif isinstance(raw, YamlMap) and len(raw) == 1:
            name = next(iter(raw))
            name_mark = raw.key_mark(name)
            params_mark = raw.value_mark(name)
            params = raw[name]
            if params is None:
                params = YamlMap.at(params_mark)
            if name not in self.actions and name not in self.broken:
                self.problem(f"unknown action '{name}'", name_mark, self.action_meant(name))
                return None
            if not isinstance(params, YamlMap):
                known = self.actions.get(name)
                self.problem(
                    f"the parameters of '{name}' must be a mapping, e.g. {{{name}: {{...}}}}"
                    if known is None
                    else f"the parameters of '{name}' must be a mapping, each with its name",
                    params_mark,
                    None if known is None else f"write `{_as_mapping(name, known, params)}`",
                )
                return None
        else:
            self.problem(
                "'do' names one action, e.g. do: {drive: {distance: 50 cm}}",
                mark,
                "to do one thing after another, give each its own state and go on with"
                " on: {done: NEXT}"
                + ("" if isinstance(raw, YamlList) else "; to do them at once, use parallel:")
                if isinstance(raw, YamlList)
                or (isinstance(raw, YamlMap) and sum(k in self.actions for k in raw) > 1)
                else None,
            )
            return None
        cls = self.actions.get(name)
        if cls is not None and "..." in params:  # {drive: {...}}, copied from an example
            self.problem(
                "'...' stands for the parameters an example leaves to you",
                params.key_mark("..."),
                f"write them: {_as_mapping(name, cls, None)}",
            )
            return None
        if cls is not None and self.without_value(
            params,
            f"of '{name}' ",
            {
                p.name: f"write {p.name}: {p.example_value}"
                + (f", or leave {p.name} out for its default" if p.default is not None else "")
                for p in params_of(cls)
            },
        ):
            return None
        if cls is None:
            if name not in self.broken:  # else its behaviour file's errors say why
                self.problem(f"unknown action '{name}'", name_mark, self.action_meant(name))
            return None

        def param_where(param: str, message: str, offset: int | None) -> Location:
            if param not in params:
                return self.loc(name_mark)
            if "has no parameter" in message:
                return self.loc(params.key_mark(param))
            if offset is not None:
                return self.loc(params.text_mark(param, offset))
            return self.loc(params.value_mark(param))

        return self.build.action(
            cls, params, self.loc(name_mark), names, param_where=param_where, name=name
        )

    # ------------------------------------------------------------------------ composites

    def action_meant(self, name: str) -> str:
        """The hint for an unknown action: a look-alike, the action that does what its word
        says (``forward``: ``drive``), or the actions there are."""
        meant = ACTION_WORDS.get(name.lower())
        if meant is not None and (meant in self.actions or meant in _COMPOSITES):
            return f"the action for that is '{meant}'"
        return did_you_mean(name, self.actions) or f"actions: {', '.join(sorted(self.actions))}"

    def composite(self, raw: YamlMap, names: frozenset[str], label: str) -> ActionSpec | None:
        kind = next(iter(raw))
        mark = raw.key_mark(kind)
        body = raw[kind]
        if kind == "mission":
            return self.mission_file(body, raw.value_mark(kind), label)
        if kind == "parallel":
            together = f"write {Parallel.example()[0]}; with any: it ends when the first one does"
            if (
                not isinstance(body, YamlMap)
                or len(body) != 1
                or next(iter(body)) not in ("all", "any")
            ):
                both = isinstance(body, YamlMap) and {"all", "any"} <= set(body)
                self.problem(
                    "parallel takes 'all' or 'any', not both"
                    if both
                    else "parallel needs 'all' or 'any', with the list of actions to run together",
                    mark,
                    together,
                )
                return None
            mode = next(iter(body))
            items = body[mode]
            if not isinstance(items, YamlList) or not items:
                self.problem(
                    f"parallel {mode}: needs a list of actions", body.value_mark(mode), together
                )
                return None
            children = [
                self.action(item, item_mark, names, label)
                for item, item_mark in zip(items, items.item_marks, strict=True)
            ]
            specs = [child for child in children if child is not None]
            if len(specs) != len(children):
                return None
            return self.build.parallel(mode, specs, self.loc(mark))
        # repeat
        again = f"write {Repeat.example()[0]}"
        if not isinstance(body, YamlMap) or set(body) != {"times", "do"}:
            given = body if isinstance(body, YamlMap) else {}
            missing = [key for key in _REPEAT if key not in given]
            if not any(key not in _REPEAT for key in given):
                needs = ", and ".join(f"'{key}', {_REPEAT[key]}" for key in missing)
                self.problem(f"repeat needs {needs}", mark, again)
            else:
                self.problem("repeat takes 'times' and 'do', and nothing else", mark, again)
            return None
        times = body["times"]
        wrong = Repeat.times_problem(times)
        if wrong is not None:
            self.problem(wrong.message, body.value_mark("times"), f"write {wrong.yaml}")
            return None
        child = self.action(body["do"], body.value_mark("do"), names, label)
        if child is None:
            return None
        return self.build.repeat(times, child, self.loc(mark))

    def inline_machine(self, raw: YamlMap, mark: Mark, label: str) -> ActionSpec | None:
        self.unknown_keys(raw, _INNER_KEYS, f"the inner states of '{label}'")
        inner = _Reader(self.path)
        inner.actions, inner.broken, inner.included = self.actions, self.broken, self.included
        spec = self.build.check_inner(inner.read(raw, inner_of=label), inner.build)
        return None if spec is None else self.build.machine(spec, label, self.loc(mark))

    def mission_file(self, value: Any, mark: Mark, label: str) -> ActionSpec | None:
        if not isinstance(value, str):
            self.problem("mission: names a mission file, e.g. mission: patrol.yaml", mark)
            return None
        try:
            path = beside_mission(self.path, value, "mission file", (".yaml", ".yml"))
        except FileReferenceError as exc:
            self.problem(str(exc), mark, exc.hint)
            return None
        if str(path) in _LOADING:
            self.problem(f"'{value}' includes itself (directly or through another file)", mark)
            return None
        if str(path) in self.included:
            spec = self.included[str(path)]
        else:
            try:
                spec, warnings = load_yaml_mission(path)
            except MissionError as exc:
                self.problems.extend(getattr(exc, "problems", [exc]))
                spec = None
            else:
                self.problems.extend(warnings)
            self.included[str(path)] = spec
        return None if spec is None else self.build.machine(spec, label, self.loc(mark))

    # ------------------------------------------------------------------------ transitions

    def guarded(
        self, item: Any, mark: Mark, names: frozenset[str], need_if: bool
    ) -> TransitionSpec | None:
        if isinstance(item, int) and not isinstance(item, bool) and str(item) in names:
            item = str(item)  # a state named by a number (`2:`), gone to as `done: 2`
        if isinstance(item, str) and not need_if:
            target = self.build.target(item, names, self.loc(mark))
            return self.build.transition(target, where=self.loc(mark)) if target else None
        if not isinstance(item, YamlMap):
            self.problem(
                "a choice is a condition and the state it goes to",
                mark,
                f"write {_choice(item, names)}",
            )
            return None
        self.unknown_keys(item, _CHOICE_KEYS, "a choice")
        if self.without_value(
            item,
            "in this choice ",
            {
                "if": f"write the condition, e.g. if: {PARAM_EXAMPLES['guard']}",
                "goto": f"write the state it goes to, e.g. goto: {_a_state(names)}",
            },
        ):
            return None
        if "goto" not in item:
            # `then: stuck`, `next: stuck`: the state written under another key
            written = [
                v
                for k, v in item.items()
                if k not in _CHOICE_KEYS and isinstance(v, str) and v in names
            ]
            self.problem(
                "this choice needs 'goto', the state it goes to",
                item.mark,
                f"write `goto: {written[0] if written else _a_state(names)}`",
            )
            return None
        goto = item["goto"]
        if isinstance(goto, int) and not isinstance(goto, bool) and str(goto) in names:
            goto = str(goto)
        target = self.build.target(goto, names, self.loc(item.value_mark("goto")))
        guard = None
        text = None
        if "if" in item:
            text = item["if"]
            guard = self.build.expression(
                text, names, lambda offset: self.loc(item.text_mark("if", offset))
            )
            if guard is None:
                return None
            text = guard.source if hasattr(guard, "source") else str(text)
        elif need_if:
            self.problem(
                "each 'when' entry needs 'if', the condition that moves on",
                item.mark,
                f"write `if: {PARAM_EXAMPLES['guard']}`",
            )
            return None
        if target is None:
            return None
        return self.build.transition(target, guard, text, self.loc(item.mark))

    def on(
        self, raw: Any, mark: Mark, names: frozenset[str]
    ) -> dict[str, tuple[TransitionSpec, ...]]:
        if not isinstance(raw, YamlMap):
            self.problem(
                "'on' maps outcomes to states, e.g. on: {done: next, timeout: stuck}",
                mark,
                f"write on: {{done: {raw}}}" if isinstance(raw, str) and raw in names else None,
            )
            return {}
        raw = self.valued(
            raw,
            "",
            {o: f"write the state it goes to, e.g. {o}: {_a_state(names)}" for o in OUTCOMES},
        )
        result: dict[str, tuple[TransitionSpec, ...]] = {}
        for outcome, value in raw.items():
            if outcome not in OUTCOMES and outcome.partition(":")[0] in OUTCOMES:
                self.problem(
                    f"'{outcome}' needs a space after its ':' (else YAML reads it as one word)",
                    raw.key_mark(outcome),
                    f"write {outcome.replace(':', ': ', 1)}",
                )
                continue
            if outcome not in OUTCOMES:
                meant = meant_outcome(str(outcome))
                self.problem(
                    f"unknown outcome '{outcome}' (outcomes: {', '.join(OUTCOMES)})",
                    raw.key_mark(outcome),
                    f"write {meant}: {value}"
                    if meant is not None and isinstance(value, str)
                    else did_you_mean(outcome, OUTCOMES),
                )
                continue
            vmark = raw.value_mark(outcome)
            items = value if isinstance(value, YamlList) else [value]
            marks = value.item_marks if isinstance(value, YamlList) else [vmark]
            found = []
            for item, item_mark in zip(items, marks, strict=True):
                transition = self.guarded(item, item_mark, names, need_if=False)
                if transition is not None:
                    found.append(transition)
            result[outcome] = tuple(found)
        return result

    def when(self, raw: Any, mark: Mark, names: frozenset[str]) -> tuple[TransitionSpec, ...]:
        if not isinstance(raw, YamlList):
            entry = (
                _choice(raw.get("if"), names, raw.get("goto"))
                if isinstance(raw, YamlMap)
                else _choice(raw, names)
            )
            self.problem(
                "'when' is a list of choices, each a condition and the state it goes to",
                mark,
                f"write `when: [{entry.strip('`')}]`, one {{...}} per choice",
            )
            return ()
        found = []
        for item, item_mark in zip(raw, raw.item_marks, strict=True):
            transition = self.guarded(item, item_mark, names, need_if=True)
            if transition is not None:
                found.append(transition)
        return tuple(found)


def _as_mapping(name: str, cls: type[Action], value: Any) -> str:
    """``{name: {...}}`` for an action whose settings were written as one value (``drive 50
    cm``, ``{rotate: 90 deg}``): that value given to its main parameter (its first required
    one, else its first), with the example of each other parameter it needs."""
    params = params_of(cls)
    main = next((p for p in params if p.required), params[0] if params else None)
    given = value if isinstance(value, str | int | float) else None
    if isinstance(given, int | float) and not isinstance(given, bool) and main is not None:
        # {wait: 2}, {drive: 50}: the number with a unit, the one most likely meant (cm for
        # 50) where a bare number's warning names one, else the unit it would be read in
        note = bare_number_warning(given, main.kind)
        if note is not None:
            likely = note[1].removeprefix("or did you mean ").rstrip("?") if note[1] else None
            given = likely or f"{given:g} {DIMENSIONS[main.kind].base_unit}"
    shown = [
        f"{p.name}: {given if p is main and given is not None else p.example_value}"
        for p in params
        if p.required or p is main
    ]
    return f"{{{name}: {{{', '.join(shown)}}}}}"


def _not_a_mapping(data: Any) -> str:
    """What a mission file that is not a mapping holds instead, and how a mission starts."""
    what = "a list" if isinstance(data, list) else "plain text"
    return (
        f"this file holds {what}; a mission starts `mission: NAME`, then `states:` with each"
        " state indented under it"
    )


@functools.lru_cache(maxsize=8)
def _a_state(names: frozenset[str]) -> str:
    """A state of the mission to show in an example (``end`` if it has one); found once for
    a mission's states, not once for each state's examples (a search of them all)."""
    return "end" if "end" in names or not names else min(names)


def _choice(condition: Any, names: frozenset[str], goto: Any = None) -> str:
    """A ``when`` choice to copy, with the condition written if it is one (``bumper.any``), or
    going to the state written if it is one (``goto``, or ``condition`` if it names one)."""
    target = goto if isinstance(goto, str) and goto in names else _a_state(names)
    if isinstance(condition, str) and condition.strip() in names:
        condition, target = None, condition.strip()
    if not isinstance(condition, str) or not condition.strip():
        condition = PARAM_EXAMPLES["guard"]
    return f"`{{if: {condition.strip()}, goto: {target}}}`"


def load_yaml_mission(
    path: str | Path, profile: Any = None
) -> tuple[MissionSpec, list[InputError]]:
    """Load and check a YAML mission file.

    Args:
        path: The mission file.
        profile: A :class:`~roboscript.profiles.RobotProfile` to check capabilities against,
            or ``None``.

    Returns:
        The mission and its warnings.

    Raises:
        MissionProblemsError: The first error, with every problem in ``problems``.
    """
    key = str(Path(path).resolve())
    _LOADING.add(key)
    try:
        reader = _Reader(str(path))
        spec = reader.read(load_yaml(path, error=MissionError))
        return reader.build.finish(spec, profile)
    finally:
        _LOADING.discard(key)


def parse_yaml_mission(
    text: str, path: str = "<mission>", profile: Any = None
) -> tuple[MissionSpec, list[InputError]]:
    """Like :func:`load_yaml_mission`, from text."""
    reader = _Reader(path)
    spec = reader.read(load_yaml_text(text, path, error=MissionError))
    return reader.build.finish(spec, profile)
