"""Read a YAML mission into a :class:`~roboscript.mission.spec.MissionSpec`.

Every problem is reported in the student's terms, ``file:line:col: error: ...`` with a "did
you mean" where one fits. All problems in a file are collected, so one run of
``roboscript check`` lists them all; the first is raised, carrying the rest.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from roboscript.actions import ACTIONS, Action, Param
from roboscript.errors import InputError, MissionError, did_you_mean
from roboscript.mission.guards import GuardError, compile_guard
from roboscript.mission.quantities import DIMENSIONS, QuantityError, parse_quantity
from roboscript.mission.source import Mark, YamlList, YamlMap, load_yaml, load_yaml_text
from roboscript.mission.spec import (
    OUTCOMES,
    ActionSpec,
    Location,
    MissionSpec,
    StateSpec,
    TransitionSpec,
)

__all__ = ["MissionProblemsError", "build_action", "load_yaml_mission", "parse_yaml_mission"]

_TOP_KEYS = ("mission", "description", "robot", "world", "behaviours", "initial", "states")
_STATE_KEYS = ("do", "during", "on", "when", "timeout", "final", "description")
_COMPOSITES = ("parallel", "repeat", "states", "mission")


_LOADING: set[str] = set()  # mission files being loaded, to refuse a file that includes itself


class MissionProblemsError(MissionError):
    """The first error in a mission, carrying every problem found (errors and warnings).

    Attributes:
        problems: All problems, in file order.
    """

    def __init__(self, problems: list[InputError]) -> None:
        self.problems = problems
        first = next(p for p in problems if p.severity == "error")
        super().__init__(
            first.message,
            path=first.path,
            line=first.line,
            col=first.col,
            hint=first.hint,
        )


def build_action(
    cls: type[Action],
    values: Mapping[str, Any],
    state_names: frozenset[str] | None = None,
) -> tuple[dict[str, Any], list[tuple[str, str, str | None, int | None]]]:
    """Convert mission parameters to an action's keyword arguments.

    Args:
        cls: The action class.
        values: Parameter values by YAML name (quantities may carry units).
        state_names: The mission's states, for conditions that read ``visits.STATE``.

    Returns:
        The keyword arguments, and the problems as ``(param name, message, hint, offset)``;
        ``offset`` is the character in a condition where the problem is, else ``None``.
    """
    kwargs: dict[str, Any] = {}
    problems: list[tuple[str, str, str | None, int | None]] = []
    params = {p.name: p for p in cls.params}
    for name, value in values.items():
        param = params.get(name)
        if param is None:
            hint = did_you_mean(name, params) or (
                f"'{cls.name}' takes {', '.join(params)}" if params else None
            )
            problems.append((name, f"'{cls.name}' has no parameter '{name}'", hint, None))
            continue
        try:
            kwargs[param.kwarg] = _convert(param, value, state_names)
        except GuardError as exc:
            problems.append((name, f"{cls.name} {name}: {exc}", exc.hint, exc.offset))
        except ValueError as exc:
            problems.append((name, f"{cls.name} {name}: {exc}", None, None))
    for param in cls.params:
        if param.required and param.kwarg not in kwargs and param.name not in values:
            problems.append(("", f"'{cls.name}' needs '{param.name}' ({param.doc})", None, None))
    return kwargs, problems


def _convert(param: Param, value: Any, state_names: frozenset[str] | None = None) -> Any:
    if value is None and not param.required:
        return param.default
    if param.kind == "count":
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"expected a whole number, got {value!r}")
        return value
    if param.kind in DIMENSIONS:
        try:
            return parse_quantity(value, param.kind)
        except QuantityError as exc:
            raise ValueError(str(exc)) from None
    if param.kind == "choice":
        if value not in param.choices:
            raise ValueError(f"expected one of {', '.join(param.choices)}, got {value!r}")
        return value
    if param.kind == "guard":
        if isinstance(value, bool):
            value = "true" if value else "false"
        if not isinstance(value, str):
            raise ValueError(
                f'expected a condition such as "range.distance_cm < 20", got {value!r}'
            )
        return compile_guard(value, state_names)
    if param.kind == "color":
        from roboscript.actions.output import parse_color

        return parse_color(value)
    if param.kind == "text":
        if not isinstance(value, str | int | float):
            raise ValueError(f"expected text, got {value!r}")
        return str(value)
    return value


class _Reader:
    def __init__(self, path: str) -> None:
        self.path = path
        self.problems: list[InputError] = []
        self.actions: Mapping[str, type[Action]] = ACTIONS  # plus the mission's behaviours
        self.broken: frozenset[str] = frozenset()  # behaviours whose file has errors
        # Mission files used as states, by resolved path (None: it had errors), so a file
        # used by several states is read, checked and warned about once.
        self.included: dict[str, MissionSpec | None] = {}

    def problem(
        self, message: str, mark: Mark | None, hint: str | None = None, severity: str = "error"
    ) -> None:
        line, col = mark if mark else (None, None)
        self.problems.append(
            MissionError(message, path=self.path, line=line, col=col, hint=hint, severity=severity)
        )

    def loc(self, mark: Mark | None) -> Location:
        return Location(self.path, *(mark or (None, None)))

    # ------------------------------------------------------------------------------ top

    def read(self, data: Any, inner_of: str | None = None) -> MissionSpec | None:
        if not isinstance(data, YamlMap):
            self.problem(
                "a mission file is a mapping with 'mission:', 'initial:' and 'states:'", (1, 1)
            )
            return None
        if inner_of is None:
            for key in data:
                if key not in _TOP_KEYS:
                    self.problem(
                        f"unknown key '{key}'", data.key_mark(key), did_you_mean(key, _TOP_KEYS)
                    )
        if inner_of is None and "behaviours" in data:
            from roboscript.mission.behaviours import behaviours_from_yaml

            extra, problems, self.broken = behaviours_from_yaml(
                data["behaviours"], data.value_mark("behaviours"), self.path
            )
            self.problems.extend(problems)
            self.actions = {**ACTIONS, **extra}
        states_raw = data.get("states")
        if not isinstance(states_raw, YamlMap) or not states_raw:
            self.problem(
                "a mission needs 'states:', a mapping of state names to states",
                data.key_mark("states") if "states" in data else data.mark,
            )
            return None
        names = frozenset(str(name) for name in states_raw)
        states: dict[str, StateSpec] = {}
        for name, raw in states_raw.items():
            state = self.state(
                str(name), raw, states_raw.value_mark(name), states_raw.key_mark(name), names
            )
            if state is not None:
                states[state.name] = state
        initial = data.get("initial", next(iter(states_raw)))
        if not isinstance(initial, str) or initial not in names:
            self.problem(
                f"the initial state '{initial}' is not one of the states",
                data.value_mark("initial"),
                did_you_mean(str(initial), names),
            )
        mission = inner_of or data.get("mission", Path(self.path).stem)
        hints: dict[str, str | None] = {}
        for key in ("robot", "world"):
            value = data.get(key)
            if value is not None and not isinstance(value, str):
                self.problem(f"'{key}' names a {key}, e.g. {key}: mirto", data.value_mark(key))
            hints[key] = value if isinstance(value, str) else None
        return MissionSpec(
            name=str(mission),
            initial=str(initial),
            states=states,
            description=str(data.get("description", "")),
            path=self.path,
            location=self.loc(data.mark),
            robot=hints["robot"],
            world=hints["world"],
        )

    # ---------------------------------------------------------------------------- states

    def state(
        self, name: str, raw: Any, mark: Mark, key_mark: Mark, names: frozenset[str]
    ) -> StateSpec | None:
        if raw is None:
            raw = YamlMap.at(mark)
        if not isinstance(raw, YamlMap):
            self.problem(f"state '{name}' must be a mapping (do:, on:, when:, final:)", mark)
            return None
        for key in raw:
            if key not in _STATE_KEYS:
                self.problem(
                    f"unknown key '{key}' in state '{name}'",
                    raw.key_mark(key),
                    did_you_mean(key, _STATE_KEYS),
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
            try:
                timeout_s = parse_quantity(raw["timeout"], "time")
                if timeout_s <= 0:
                    self.problem("a timeout must be positive", raw.value_mark("timeout"))
            except QuantityError as exc:
                self.problem(f"timeout: {exc}", raw.value_mark("timeout"))
        final = None
        if "final" in raw:
            value = raw["final"]
            if value is True or value == "success":
                final = "success"
            elif value == "failure":
                final = "failure"
            elif value is not False:
                self.problem(
                    f"final must be 'success' or 'failure', got {value!r}", raw.value_mark("final")
                )
        return StateSpec(
            name=name,
            action=action,
            during=tuple(during),
            on=on,
            when=when,
            timeout_s=timeout_s,
            final=final,
            description=str(raw.get("description", "")),
            location=self.loc(key_mark),
        )

    def action(
        self, raw: Any, mark: Mark, names: frozenset[str], label: str = ""
    ) -> ActionSpec | None:
        if isinstance(raw, YamlMap) and "states" in raw:
            return self.inline_machine(raw, mark, label)
        if isinstance(raw, YamlMap) and len(raw) == 1 and next(iter(raw)) in _COMPOSITES:
            return self.composite(raw, names, label)
        if isinstance(raw, str):
            name, params, name_mark, params_mark = raw, YamlMap.at(mark), mark, mark
        elif isinstance(raw, YamlMap) and len(raw) == 1:
            name = next(iter(raw))
            name_mark = raw.key_mark(name)
            params_mark = raw.value_mark(name)
            params = raw[name]
            if params is None:
                params = YamlMap.at(params_mark)
            if not isinstance(params, YamlMap):
                self.problem(
                    f"the parameters of '{name}' must be a mapping, e.g. {{{name}: {{...}}}}",
                    params_mark,
                )
                return None
        else:
            self.problem("'do' names one action, e.g. do: {drive: {distance: 50 cm}}", mark)
            return None
        cls = self.actions.get(name)
        if cls is None:
            if name not in self.broken:  # else its behaviour file's errors say why
                self.problem(
                    f"unknown action '{name}'", name_mark, did_you_mean(name, self.actions)
                )
            return None
        kwargs, problems = build_action(cls, params, names)
        for param_name, message, hint, offset in problems:
            where = params.value_mark(param_name) if param_name in params else name_mark
            if param_name in params and "has no parameter" in message:
                where = params.key_mark(param_name)
            elif offset is not None:
                where = params.text_mark(param_name, offset)
            self.problem(message, where, hint)
        if problems:
            return None
        try:
            cls(**kwargs)
        except ValueError as exc:
            self.problem(f"{name}: {exc}", name_mark)
            return None
        except Exception as exc:  # noqa: BLE001 - a student's behaviour may raise anything
            from roboscript.mission.student_code import StudentCodeError

            self.problem(StudentCodeError(f"behaviour '{name}'", exc).reason(None), name_mark)
            return None
        guard_caps: set[str] = set()
        for value in kwargs.values():
            guard_caps |= set(getattr(value, "capabilities", ()))
        return ActionSpec(
            name=name,
            kwargs=kwargs,
            factory=lambda: cls(**kwargs),
            requires=cls.requires | guard_caps,
            location=self.loc(name_mark),
            bounded=not cls.bounded_by
            or any(kwargs.get(p.kwarg) is not None for p in cls.params if p.name in cls.bounded_by),
        )

    # ------------------------------------------------------------------------ composites

    def composite(self, raw: YamlMap, names: frozenset[str], label: str) -> ActionSpec | None:
        from roboscript.actions.composite import Parallel, Repeat

        kind = next(iter(raw))
        mark = raw.key_mark(kind)
        body = raw[kind]
        if kind == "mission":
            return self.mission_file(body, raw.value_mark(kind), label)
        if kind == "parallel":
            if (
                not isinstance(body, YamlMap)
                or len(body) != 1
                or next(iter(body)) not in ("all", "any")
            ):
                self.problem("write parallel: {all: [ACTIONS]} or parallel: {any: [ACTIONS]}", mark)
                return None
            mode = next(iter(body))
            items = body[mode]
            if not isinstance(items, YamlList) or not items:
                self.problem(f"parallel {mode}: needs a list of actions", body.value_mark(mode))
                return None
            children = [
                self.action(item, item_mark, names, label)
                for item, item_mark in zip(items, items.item_marks, strict=True)
            ]
            if any(child is None for child in children):
                return None
            specs = [child for child in children if child is not None]
            factories = [child.factory for child in specs]
            return ActionSpec(
                name="parallel",
                kwargs={"mode": mode, "actions": tuple(c.name for c in specs)},
                factory=lambda: Parallel(factories, mode),
                requires=frozenset().union(*(c.requires for c in specs)),
                location=self.loc(mark),
                bounded=all(c.bounded for c in specs)
                if mode == "all"
                else any(c.bounded for c in specs),
            )
        # repeat
        if not isinstance(body, YamlMap) or set(body) != {"times", "do"}:
            self.problem("write repeat: {times: N, do: ACTION}", mark)
            return None
        times = body["times"]
        if isinstance(times, bool) or not isinstance(times, int) or times < 1:
            self.problem(
                "repeat times must be a whole number of at least 1", body.value_mark("times")
            )
            return None
        child = self.action(body["do"], body.value_mark("do"), names, label)
        if child is None:
            return None
        make = child.factory
        return ActionSpec(
            name="repeat",
            kwargs={"times": times, "action": child.name},
            factory=lambda: Repeat(make, times),
            requires=child.requires,
            location=self.loc(mark),
            bounded=child.bounded,
        )

    def inline_machine(self, raw: YamlMap, mark: Mark, label: str) -> ActionSpec | None:
        for key in raw:
            if key not in ("states", "initial", "description"):
                self.problem(
                    f"unknown key '{key}' in the inner states of '{label}'",
                    raw.key_mark(key),
                    did_you_mean(key, ("states", "initial", "description")),
                )
        inner = _Reader(self.path)
        inner.actions, inner.broken, inner.included = self.actions, self.broken, self.included
        spec = inner.read(raw, inner_of=label)
        if spec is not None and not any(p.severity == "error" for p in inner.problems):
            from roboscript.mission.checks import check_mission

            inner.problems.extend(check_mission(spec))
        self.problems.extend(inner.problems)
        if spec is None or any(p.severity == "error" for p in inner.problems):
            return None
        return self._machine_action(spec, label, mark)

    def mission_file(self, value: Any, mark: Mark, label: str) -> ActionSpec | None:
        if not isinstance(value, str):
            self.problem("mission: names a mission file, e.g. mission: patrol.yaml", mark)
            return None
        path = (Path(self.path).parent / value).resolve()
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
        return None if spec is None else self._machine_action(spec, label, mark)

    def _machine_action(self, spec: MissionSpec, label: str, mark: Mark) -> ActionSpec:
        from roboscript.mission.nested import SubMission

        return ActionSpec(
            name="states",
            kwargs={"mission": spec.name, "states": tuple(spec.states)},
            factory=lambda: SubMission(spec, label),
            requires=spec.requires(),
            location=self.loc(mark),
            inner=spec,
        )

    # ------------------------------------------------------------------------ transitions

    def target(self, value: Any, mark: Mark, names: frozenset[str]) -> str | None:
        if not isinstance(value, str):
            self.problem(f"expected a state name, got {value!r}", mark)
            return None
        if value not in names:
            self.problem(f"there is no state '{value}'", mark, did_you_mean(value, names))
            return None
        return value

    def guarded(
        self, item: Any, mark: Mark, names: frozenset[str], need_if: bool
    ) -> TransitionSpec | None:
        if isinstance(item, str) and not need_if:
            target = self.target(item, mark, names)
            return TransitionSpec(target, location=self.loc(mark)) if target else None
        if not isinstance(item, YamlMap):
            self.problem("expected {if: CONDITION, goto: STATE}", mark)
            return None
        for key in item:
            if key not in ("if", "goto"):
                self.problem(
                    f"unknown key '{key}'", item.key_mark(key), did_you_mean(key, ("if", "goto"))
                )
        if "goto" not in item:
            self.problem("this choice needs 'goto: STATE'", item.mark)
            return None
        target = self.target(item["goto"], item.value_mark("goto"), names)
        guard = None
        text = None
        if "if" in item:
            text = item["if"]
            if isinstance(text, bool):
                text = "true" if text else "false"
            if not isinstance(text, str):
                self.problem(
                    'a condition is text, e.g. if: "range.distance_cm < 20"', item.value_mark("if")
                )
                return None
            try:
                guard = compile_guard(text, names)
            except GuardError as exc:
                self.problem(str(exc), item.text_mark("if", exc.offset), exc.hint)
                return None
        elif need_if:
            self.problem("each 'when' entry needs 'if: CONDITION'", item.mark)
            return None
        if target is None:
            return None
        return TransitionSpec(target, guard, text, self.loc(item.mark))

    def on(
        self, raw: Any, mark: Mark, names: frozenset[str]
    ) -> dict[str, tuple[TransitionSpec, ...]]:
        if not isinstance(raw, YamlMap):
            self.problem(
                "'on' maps outcomes to states, e.g. on: {done: next, timeout: stuck}", mark
            )
            return {}
        result: dict[str, tuple[TransitionSpec, ...]] = {}
        for outcome, value in raw.items():
            if outcome not in OUTCOMES:
                self.problem(
                    f"unknown outcome '{outcome}' (outcomes: {', '.join(OUTCOMES)})",
                    raw.key_mark(outcome),
                    did_you_mean(outcome, OUTCOMES),
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
            self.problem("'when' is a list of {if: CONDITION, goto: STATE}", mark)
            return ()
        found = []
        for item, item_mark in zip(raw, raw.item_marks, strict=True):
            transition = self.guarded(item, item_mark, names, need_if=True)
            if transition is not None:
                found.append(transition)
        return tuple(found)


def _finish(reader: _Reader, data: Any, profile: Any) -> tuple[MissionSpec, list[InputError]]:
    from roboscript.mission.checks import check_mission

    spec = reader.read(data)
    if spec is not None and not any(p.severity == "error" for p in reader.problems):
        reader.problems.extend(check_mission(spec, profile))
    errors = [p for p in reader.problems if p.severity == "error"]
    if errors or spec is None:
        reader.problems.sort(key=lambda p: (p.line or 0, p.col or 0))
        raise MissionProblemsError(reader.problems)
    return spec, [p for p in reader.problems if p.severity != "error"]


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
        return _finish(reader, load_yaml(path, error=MissionError), profile)
    finally:
        _LOADING.discard(key)


def parse_yaml_mission(
    text: str, path: str = "<mission>", profile: Any = None
) -> tuple[MissionSpec, list[InputError]]:
    """Like :func:`load_yaml_mission`, from text."""
    reader = _Reader(path)
    return _finish(reader, load_yaml_text(text, path, error=MissionError), profile)
