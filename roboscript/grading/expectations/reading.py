"""Reading a spec's ``expect`` list: each item's kind, weight and ``required``, and the targets
runs give of their own (``runs: [{seed: 2, expect: {KIND: {key: value}}}]``)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from roboscript.errors import did_you_mean
from roboscript.grading.expectations.base import (
    KINDS,
    Expectation,
    Rule,
    RunKey,
    RunTargets,
    SpecContext,
    start_mismatch,
)
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Location, Mark, YamlList, YamlMap
from roboscript.sim.world import World

__all__ = ["RunOverride", "apply_run_targets", "parse_expectation"]

_SCORING_KEYS = ("weight", "required")
"""Keys of an ``expect`` item that say how it counts, beside its one kind."""


def parse_expectation(
    reader: FieldReader, item: object, mark: Mark, ctx: SpecContext
) -> Expectation:
    """Read one item of ``expect`` (``{KIND: VALUE}``, optionally with ``weight`` and
    ``required``).

    Raises:
        SpecError: At the mistake, with a "did you mean" for a misspelt kind.
    """
    if not isinstance(item, YamlMap):
        raise reader.fail(_not_an_expectation(item), mark)
    data = reader.mapping(item, "an expectation", mark)
    kinds = [key for key in data if key not in _SCORING_KEYS]
    for key in kinds if len(kinds) > 1 else ():
        near = did_you_mean(key, _SCORING_KEYS) if key not in KINDS else None
        if near:
            raise reader.fail(f"unknown key '{key}' in an expectation", data.key_mark(key), near)
    if len(kinds) != 1:
        listed = ", ".join(KINDS)
        raise reader.fail(f"an expectation has exactly one of: {listed}", data.mark)
    kind = kinds[0]
    if kind not in KINDS:
        raise reader.fail(
            f"unknown expectation '{kind}'",
            data.key_mark(kind),
            did_you_mean(kind, KINDS) or f"expected one of: {', '.join(KINDS)}",
        )
    weight = 1.0
    if "weight" in data:
        value = data["weight"]
        if isinstance(value, bool) or not isinstance(value, int | float) or value <= 0:
            raise reader.fail("weight must be a number above 0", data.value_mark("weight"))
        if not value < 1e9:  # infinity or NaN (YAML's .inf, .nan) would make every score NaN
            raise reader.fail(
                "weight must be a finite number below a billion", data.value_mark("weight")
            )
        weight = float(value)
    required = False
    if "required" in data:
        required = data["required"]
        if not isinstance(required, bool):
            raise reader.fail(
                f"'required' must be true or false (got {required!r}); a run that fails a"
                " required expectation scores 0",
                data.value_mark("required"),
                did_you_mean(str(required), ("true", "false")),
            )
    rule = KINDS[kind].parse(reader, data[kind], data.value_mark(kind), ctx)
    line, col = data.key_mark(kind)
    return Expectation(rule, weight, Location(reader.path, line, col), required)


def _not_an_expectation(item: object) -> str:
    """Why an ``expect`` item that is not a mapping is none, in one sentence."""
    sentence = "an expectation is KIND: VALUE, such as - outcome: success"
    if item is None:
        return f"{sentence} (this '- ' line has nothing after it)"
    if isinstance(item, str):
        first = item.split()[0] if item.split() else ""
        kind = first if first in KINDS else did_you_mean(first, KINDS) and first
        if kind:
            return f"{sentence} (got {item!r}: is the ':' after '{kind}' missing?)"
    return f"{sentence} (got {item!r})"


@dataclass(frozen=True)
class RunOverride:
    """One run of a spec, for :func:`apply_run_targets`.

    Attributes:
        key: How its record is recognised (world name, seed, start pose).
        world: Its world (region names are checked in it).
        expect: Its own ``expect:`` as written (``{KIND: targets}``), or ``None``.
        mark: Where that ``expect:`` was written.
    """

    key: RunKey
    world: World
    expect: object = None
    mark: Mark = (1, 1)


def apply_run_targets(
    reader: FieldReader,
    expectations: tuple[Expectation, ...],
    written: Sequence[tuple[object, Mark]],
    runs: Sequence[RunOverride],
    folder: Path,
) -> tuple[Expectation, ...]:
    """The spec's expectations with each run's own targets (a run's ``expect:``).

    A run's ``expect: {KIND: {key: value}}`` changes those keys of the spec's one ``KIND``
    expectation for that run (the rest as the spec writes them); a value that is not a mapping
    (``max_duration: 50 s``) replaces the spec's. The expectations it changes get
    :class:`RunTargets`, chosen per run when judged.

    Args:
        reader: The spec's reader.
        expectations: As read from the spec's ``expect``.
        written: The ``expect`` items as written, with their marks, in the same order.
        runs: Every run, in order.
        folder: The spec's folder.

    Raises:
        SpecError: At a run's target that names no expectation of the spec, names one the
            spec has twice, changes a weight or a check, or is not a valid target.
    """
    kinds = [e.kind for e in expectations]
    own: dict[int, dict[int, Rule]] = {}  # expectation index -> run index -> its parameters
    for r, run in enumerate(runs):
        if run.expect is None:
            continue
        example = "such as expect: {final_pose_within: {x: 30 cm}}"
        if not isinstance(run.expect, YamlMap) or not run.expect:
            raise reader.fail(
                f"a run's expect changes the targets of the spec's expectations, {example}",
                run.mark,
            )
        for kind in run.expect:
            at = run.expect.key_mark(kind)
            if kind == "weight":
                raise reader.fail("a run cannot change weights, only targets", at)
            if kind == "required":
                raise reader.fail("a run cannot change what is required, only targets", at)
            if kind == "check":
                raise reader.fail(
                    "a run cannot change a check; your function gets the run's record"
                    " (its seed, start and world) to judge by",
                    at,
                )
            found = [i for i, k in enumerate(kinds) if k == kind]
            if not found:
                known = KINDS if kind not in KINDS else kinds
                listed = ", ".join(dict.fromkeys(kinds))
                raise reader.fail(
                    f"the spec expects no '{kind}' for this run to change (a run changes the"
                    f" targets of the spec's own expectations: {listed})",
                    at,
                    did_you_mean(kind, known),
                )
            if len(found) > 1:
                raise reader.fail(
                    f"the spec expects '{kind}' {len(found)} times, so a run cannot say which"
                    " to change",
                    at,
                )
            i = found[0]
            item = written[i][0]
            assert isinstance(item, YamlMap)  # parse_expectation read it as one
            base = item[kind]
            if kind == "path_visits" and isinstance(base, YamlList):  # the short form
                base = YamlMap.at(item.value_mark(kind), {"waypoints": base})
            merged = _merged(base, run.expect[kind], at)
            ctx = SpecContext(folder, (run.world,))
            value_at = run.expect.value_mark(kind)
            own.setdefault(i, {})[r] = KINDS[kind].parse(reader, merged, value_at, ctx)
    if not own:
        return expectations
    changed = list(expectations)
    for i, by_run in own.items():
        base = expectations[i].rule
        targets = tuple((run.key, by_run.get(r, base)) for r, run in enumerate(runs))
        _refuse_lookalike_runs(reader, targets, runs, expectations[i].kind)
        changed[i] = replace(expectations[i], targets=RunTargets(base, targets))
    return tuple(changed)


def _merged(base: object, change: object, change_mark: Mark) -> object:
    """``base`` with the keys of ``change`` (when both are mappings), else ``change``."""
    if not (isinstance(base, YamlMap) and isinstance(change, YamlMap)):
        return change
    merged = YamlMap.at(change_mark, {**base, **change})
    merged.key_marks = {**base.key_marks, **change.key_marks}
    merged.value_marks = {**base.value_marks, **change.value_marks}
    merged.quoted = (base.quoted - set(change)) | change.quoted
    return merged


def _refuse_lookalike_runs(
    reader: FieldReader,
    targets: tuple[tuple[RunKey, Rule], ...],
    runs: Sequence[RunOverride],
    kind: str,
) -> None:
    """Two runs told apart only by their targets would be judged by the same ones."""
    for b, (key_b, params_b) in enumerate(targets):
        for a, (key_a, params_a) in enumerate(targets[:b]):
            same_run = key_a[:2] == key_b[:2] and start_mismatch(key_a[2], *key_b[2]) < 50.0
            if same_run and params_a != params_b:
                raise reader.fail(
                    f"runs {a + 1} and {b + 1} have the same world, seed and start, but"
                    f" different '{kind}' targets; give them different seeds",
                    runs[b].mark if runs[b].expect is not None else runs[a].mark,
                )


# ------------------------------------------------------------------------------- evaluate
