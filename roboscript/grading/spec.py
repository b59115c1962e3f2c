"""Teacher test specs: which world and robot, which run variants, and what must happen.

A test spec (YAML; quantities take units, bare numbers the documented unit)::

    test: square-50cm
    description: Drive a 50 cm square, beep at each corner, and come home.
    world: empty            # built-in name, or a world file relative to this spec
    robot: mirto
    runs:                   # each run is one seeded variant; the mission must pass all
      - {seed: 1}
      - {seed: 2, start: {x: 100 mm, y: 0 mm, heading: 10 deg}}
      - {seed: 3, start: {heading: 30 deg}, hidden: true}   # students see "hidden run 3"
      - {seed: 4, start: {x: 0 mm, y: 300 mm}, expect: {final_pose_within: {y: 300 mm}}}
    points: 12              # what the test is worth (default: one point per run)
    max_time: 60 s          # simulated time
    wall_time_limit: 60 s   # real time, per run, before the grader gives up on it
    expect:
      - outcome: success
      - final_pose_within: {x: 0 mm, y: 0 mm, radius: 80 mm}
      - {tones: {count: 4}, weight: 2}
      - {no_collisions: true, required: true}   # a run that fails it scores 0

Every mistake is a :class:`~roboscript.errors.SpecError` at ``file:line:col``, with a "did you
mean" where one fits. The expectations are documented in :mod:`roboscript.grading.expectations`
and in the teachers' guide.
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from roboscript.errors import InputError, ProfileError, SpecError, did_you_mean, grouped
from roboscript.grading.expectations import (
    Expectation,
    MaxDuration,
    RunOverride,
    SpecContext,
    apply_run_targets,
    parse_expectation,
)
from roboscript.grading.expectations.contradictions import RunSetup, find_contradiction
from roboscript.grading.record import RunResult, RunStatus
from roboscript.grading.regions import enclosing_walls
from roboscript.grading.text import clean_name
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.kinds import (
    OWN_KEYS,
    FileKind,
    file_kind,
    not_the_kind_expected,
    refuse_another_kind,
)
from roboscript.inputs.limits import name_too_long
from roboscript.inputs.quantities import bare_number_warning
from roboscript.inputs.source import (
    Location,
    Mark,
    YamlList,
    YamlMap,
    load_yaml,
    read_source,
)
from roboscript.mission.limits import MAX_TIME_S
from roboscript.profiles import BUILTIN_PROFILES, get_profile
from roboscript.sim.geometry import segment_distance
from roboscript.sim.world import WORLD_REACH_MM, World, builtin_worlds, load_world

__all__ = [
    "DEFAULT_MAX_TIME_S",
    "DEFAULT_WALL_TIME_LIMIT_S",
    "GRADER_BACKSTOP_S",
    "WALL_TIME_STRETCH",
    "TestSpec",
    "Variant",
    "is_test_spec",
    "load_test_spec",
]

DEFAULT_MAX_TIME_S = 60.0
"""Simulated time a mission gets when the spec gives no ``max_time``."""
DEFAULT_WALL_TIME_LIMIT_S = 60.0
"""Real time one run may take before the grader stops it. The simulator runs a 60 s mission
in well under a second, so only a mission stuck in a loop of its own code comes near this."""
GRADER_BACKSTOP_S = 15.0
"""Real time past a test's ``wall_time_limit`` after which the grader ends a run's worker
itself: the worker stops its run at the limit, and this is for a worker that could not."""
WALL_TIME_STRETCH = 1000.0
"""How many times its :attr:`TestSpec.longest_wall_time_s` a run's measured wall time may be.
The grader does not hold against a run the time a busy machine kept it waiting for a CPU, nor
a pause of the grader itself (Ctrl-Z, a suspended laptop): its wall time may pass its
allowance by that much, and a results file's time beyond this many times it is no grading's."""

_LONGEST_RUN = (MAX_TIME_S, f"1 hour ({MAX_TIME_S:g} s)")
"""Most seconds a run's ``max_time`` and ``wall_time_limit`` may give it, as a mission's own
waits and timeouts: far past any class's test, and within what the system's timers take
(``1e9 s`` overflowed them and stopped the class)."""

_TOP_KEYS = (
    "test",
    "description",
    "world",
    "robot",
    "runs",
    "max_time",
    "wall_time_limit",
    "points",
    "expect",
)
_RUN_KEYS = ("seed", "start", "world", "name", "hidden", "expect")
_MISPLACED_KEYS = {
    "seed": "a seed belongs to a run: runs: [{seed: 1}]",
    "seeds": "each seed is a run: runs: [{seed: 1}, {seed: 2}]",
    "start": "a start belongs to a run: runs: [{seed: 1, start: {x: 10 cm}}]",
    "hidden": "a run is hidden, not the test: runs: [{seed: 1}, {seed: 2, hidden: true}]",
    "expectations": "the expectations are listed under 'expect'",
    "expects": "the expectations are listed under 'expect'",
}
"""Keys a quick spec puts at its top that belong elsewhere, and where."""

MAX_RUNS = 200
"""The most runs a test may list: every student's mission runs once per run, so a class of
30 with this many is already 6,000 runs."""


@dataclass(frozen=True)
class Variant:
    """One run of a test: a seed, and optionally another start pose or world.

    Attributes:
        index: Position in the spec's ``runs`` (0-based).
        seed: Simulator seed.
        world: World name or absolute path.
        start: ``(x_mm, y_mm, heading_deg)``, or ``None`` for the world's start.
        name: The teacher's name for it, or empty.
        hidden: Students never see its seed, start or world: their feedback names it
            "hidden run N" (see :attr:`public_label`), with pass or fail and the reason.
    """

    index: int
    seed: int
    world: str
    start: tuple[float, float, float] | None = None
    name: str = ""
    hidden: bool = False

    @property
    def label(self) -> str:
        """How reports name the variant: its name, else ``seed 2, start (100, 0) mm 10°``."""
        if self.name:
            return self.name
        text = f"seed {self.seed}"
        if self.start is not None:
            x, y, h = self.start
            text += f", start ({x:g}, {y:g}) mm {h:g}°"
        return text

    @property
    def public_label(self) -> str:
        """How student-facing reports name it: :attr:`label`, or ``hidden run N`` if hidden."""
        return f"hidden run {self.index + 1}" if self.hidden else self.label


@dataclass(frozen=True)
class TestSpec:
    """A whole test spec.

    Attributes:
        name: The ``test`` name (a column of the class table).
        path: The spec file.
        description: Free text for the report.
        world: The default world, as written (name or path).
        robot: The robot profile the missions run on.
        variants: The runs.
        max_time_s: Simulated time limit per run.
        wall_time_limit_s: Real time limit per run.
        expectations: What must hold on every run.
        location: Where the spec starts.
        worlds: The worlds the runs use, loaded once, by the name or path the runs give.
        points: What the test is worth (``points:``), or ``None`` for the default, one point
            per run; see :attr:`max_points`.
        warnings: What is legal but likely a mistake, one printed line each
            (``spec.yaml:7:40: warning: max: 5 taken as 5 mm; ...``).
    """

    __test__ = False  # not a pytest test class, despite the name

    name: str
    path: str
    description: str
    world: str
    robot: str
    variants: tuple[Variant, ...]
    max_time_s: float
    wall_time_limit_s: float
    expectations: tuple[Expectation, ...]
    location: Location | None = None
    worlds: dict[str, World] = field(default_factory=dict, compare=False, repr=False)
    points: float | None = None
    warnings: tuple[str, ...] = field(default=(), compare=False)

    @property
    def longest_wall_time_s(self) -> float:
        """Real seconds the grader gives one run of this test before it ends the run's worker:
        the ``wall_time_limit`` plus :data:`GRADER_BACKSTOP_S`, not counting the time a busy
        machine kept the run waiting for a CPU."""
        return self.wall_time_limit_s + GRADER_BACKSTOP_S

    @property
    def longest_wall_time_shown_s(self) -> float:
        """The most real seconds a run of this test may show in a results file:
        :attr:`longest_wall_time_s` stretched by a busy or paused machine
        (:data:`WALL_TIME_STRETCH`)."""
        return self.longest_wall_time_s * WALL_TIME_STRETCH

    @property
    def max_points(self) -> float:
        """Points the test is worth: ``points:``, else one per run. Each run earns an equal
        share of it times its score (0 to 1)."""
        return self.points if self.points is not None else float(len(self.variants))

    def result(
        self, variant: Variant, *, student: str, mission: str, status: RunStatus, **fields: Any
    ) -> RunResult:
        """A result of one of this test's runs, named after the run; ``fields`` fill the rest.

        Every result the grader reports starts here: graded, missing, timed out or crashed.
        """
        return RunResult(
            student=student,
            test=self.name,
            variant=variant.index,
            label=variant.label,
            seed=variant.seed,
            mission=mission,
            status=status,
            **fields,
        )

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready summary for reports (the expectations by name and weight, and
        ``required`` for those that are)."""
        return {
            "test": self.name,
            "path": self.path,
            "description": self.description,
            "world": self.world,
            "robot": self.robot,
            "max_time_s": self.max_time_s,
            "wall_time_limit_s": self.wall_time_limit_s,
            "points": self.max_points,
            "runs": [
                {
                    "index": v.index,
                    "label": v.label,
                    "seed": v.seed,
                    "world": v.world,
                    "start": list(v.start) if v.start is not None else None,
                    "hidden": v.hidden,
                }
                for v in self.variants
            ],
            "expect": [
                {"name": e.name, "weight": e.weight} | ({"required": True} if e.required else {})
                for e in self.expectations
            ],
        }


def is_test_spec(path: str | Path) -> bool:
    """Whether a YAML file is a test spec (its first key is ``test:``), judged from its text."""
    try:
        text = read_source(path)  # not a device or a pipe: load_mission says what is wrong
    except InputError:
        return False
    for line in text.splitlines():
        stripped = line.strip()
        if not stripped or stripped.startswith(("#", "---")):
            continue
        return line.startswith("test:")
    return False


def load_test_spec(path: str | Path) -> TestSpec:
    """Read and check a test spec, its worlds and its region names.

    Raises:
        SpecError: The spec is invalid (at ``file:line:col``).
        WorldError: A world it names is invalid.
    """
    shown = str(path)
    reader = _SpecReader(shown, SpecError)
    data = load_yaml(path, error=SpecError)
    if data is None:
        raise reader.fail(
            "this test spec is empty (or holds only comments): is it saved? A test spec"
            " starts with test: NAME, then the world, the runs and what to expect",
            (1, 1),
        )
    top = reader.mapping(data, "a test spec", (1, 1))
    refuse_another_kind(top, path, "test spec", SpecError)  # grade square.yaml --mission ...
    for problem in reader.unknown_keys(top, _TOP_KEYS, "a test spec", _misplaced):
        raise problem
    reader.allowed(top, _TOP_KEYS, "a test spec", required=("test", "expect"))
    folder = Path(path).resolve().parent
    name = _shown_name(reader, top, "test")
    world = reader.text(top, "world") if "world" in top else "empty"
    worlds: dict[str, World] = {}
    default_world = _resolve_world(reader, world, folder, top.value_mark("world"), worlds)
    robot = _robot(reader, top)
    max_time = (
        reader.positive(top, "max_time", "time", "s", _LONGEST_RUN)
        if "max_time" in top
        else DEFAULT_MAX_TIME_S
    )
    wall_limit = (
        reader.positive(top, "wall_time_limit", "time", "s", _LONGEST_RUN)
        if "wall_time_limit" in top
        else DEFAULT_WALL_TIME_LIMIT_S
    )
    variants = _variants(reader, top, folder, default_world, worlds)
    _refuse_starts_in_walls(reader, top, variants, worlds, get_profile(robot).body_radius_mm)
    points = _points(reader, top)
    _refuse_unlisted(reader, top, "expect", "expectation", "- outcome: success")
    items = reader.items(top["expect"], "expect", top.value_mark("expect"))
    if not items:
        raise reader.fail(
            "expect lists at least one expectation, such as - outcome: success: a test that"
            " expects nothing would pass every mission",
            top.value_mark("expect"),
        )
    context = SpecContext(folder, tuple(worlds[v.world] for v in variants))
    expectations = tuple(parse_expectation(reader, item, mark, context) for item, mark in items)
    runs = _run_overrides(top, variants, worlds)
    expectations = apply_run_targets(reader, expectations, items, runs, folder)
    _refuse_contradictions(reader, expectations, variants, worlds, max_time)
    _warn_of_free_limits(reader, expectations, max_time)
    return TestSpec(
        name=name,
        path=shown,
        description=_description(reader, top),
        world=world,
        robot=robot,
        variants=variants,
        max_time_s=max_time,
        wall_time_limit_s=wall_limit,
        expectations=expectations,
        location=Location(shown, 1, 1),
        worlds=worlds,
        points=points,
        warnings=tuple(grouped(reader.warnings)),
    )


class _SpecReader(FieldReader):
    """A spec's reader, which keeps a warning for each bare number that was likely meant in
    another unit (``max: 5`` for a distance is 5 mm: did you mean 5 cm?)."""

    def __init__(self, path: str, error: type[InputError]) -> None:
        super().__init__(path, error)
        self.warnings: list[InputError] = []

    def quantity(
        self, data: YamlMap, key: str, dimension: str, default_unit: str | None = None
    ) -> float:
        found = super().quantity(data, key, dimension, default_unit)
        if key not in data.quoted:
            bare = bare_number_warning(data[key], dimension, default_unit)
            if bare is not None and bare[1] is not None:  # only where another unit is likely
                self.warnings.append(
                    self.fail(f"{key}: {bare[0]}", data.value_mark(key), bare[1], "warning")
                )
        return found


def _misplaced(key: str, value: object) -> str | None:
    """Where a key a quick spec put at its top belongs (``seed`` goes in a run)."""
    return _MISPLACED_KEYS.get(key)


def _refuse_unlisted(reader: FieldReader, top: YamlMap, key: str, what: str, example: str) -> None:
    """``key`` written as a mapping, a text or nothing where a list belongs (the ``- `` lines
    forgotten, or ``runs: 3``): said in the spec's own terms, with the line to write."""
    value = top[key]
    mark = top.value_mark(key)
    if isinstance(value, YamlMap) and value:
        first = next(iter(value))
        raise reader.fail(
            f"{key} is a list: put '- ' before each {what}"
            f" (here, '- {first}: ...' on line {value.key_mark(first)[0]})",
            value.key_mark(first),
        )
    if value is None:
        raise reader.fail(f"{key} is empty: list each {what} under it, such as {example}", mark)
    if not isinstance(value, YamlList):
        raise reader.fail(
            f"{key} is a list of {what}s, one '- ' line each, such as {example} (got {value!r})",
            mark,
        )


def _refuse_contradictions(
    reader: FieldReader,
    expectations: tuple[Expectation, ...],
    variants: tuple[Variant, ...],
    worlds: dict[str, World],
    max_time_s: float,
) -> None:
    """Expectations no run could meet together are an error at the later one
    (:mod:`~roboscript.grading.expectations.contradictions`)."""
    runs = []
    for variant in variants:
        world = worlds[variant.world]
        start = variant.start or (world.start.x_mm, world.start.y_mm, world.start.heading_deg)
        runs.append(RunSetup(variant.index + 1, world, start))
    found = find_contradiction(expectations, runs, max_time_s)
    if found is not None:
        expectation, sentence = found
        where = expectation.location or Location(reader.path, 1, 1)
        raise reader.fail_at(sentence, where)


def _warn_of_free_limits(
    reader: _SpecReader, expectations: tuple[Expectation, ...], max_time_s: float
) -> None:
    """A ``max_duration`` of at least ``max_time`` is met by every run that ends by itself (a
    run its max_time stops scores 0 anyway): a free share of the score, likely not meant."""
    for expectation in expectations:
        rule = expectation.rule
        if isinstance(rule, MaxDuration) and rule.limit_s >= max_time_s:
            where = expectation.location or Location(reader.path, 1, 1)
            reader.warnings.append(
                reader.fail_at(
                    f"max_duration of {rule.limit_s:g} s is not under the spec's max_time of"
                    f" {max_time_s:g} s: every run that ends by itself meets it",
                    where,
                    "give it less than max_time, or leave it out",
                    "warning",
                )
            )


def _start_mm(reader: FieldReader, pose: YamlMap, key: str) -> float:
    """A start's ``x`` or ``y``, mm, as far from the world's origin as a world reaches
    (:data:`~roboscript.sim.world.WORLD_REACH_MM`)."""
    value = reader.quantity(pose, key, "distance", "mm")
    if not -WORLD_REACH_MM <= value <= WORLD_REACH_MM:
        raise reader.fail(
            f"'{key}' puts the start more than {WORLD_REACH_MM / 1e6:g} km from the world's"
            " origin: outside any world",
            pose.value_mark(key),
        )
    return value


def _shown_name(reader: FieldReader, data: YamlMap, key: str) -> str:
    """``data[key]``, a name every report shows as it is: one line of at most
    :data:`~roboscript.inputs.limits.MAX_NAME_CHARS` characters, none a terminal obeys or
    shows as nothing (a newline in a test's name would print a forged row of the table)."""
    name = reader.text(data, key)
    too_long = name_too_long(name, f"'{key}'")
    if too_long:
        raise reader.fail(too_long, data.value_mark(key))
    if clean_name(name) != unicodedata.normalize("NFC", name):
        raise reader.fail(
            f"'{key}' must be one line of visible text: reports would show it as"
            f" {clean_name(name)!r} (a newline, a tab or an invisible character shows as \ufffd,"
            " spaces at either end are dropped)",
            data.value_mark(key),
        )
    return name


def _description(reader: FieldReader, top: YamlMap) -> str:
    """``description:``, free text (a list or mapping would show in reports as Python's)."""
    value = top.get("description")
    if isinstance(value, YamlMap | YamlList):
        raise reader.fail(
            "description is text, such as description: Drive a 50 cm square (for several"
            " lines, description: > and the text indented below it)",
            top.value_mark("description"),
        )
    return str(value or "")


def _points(reader: FieldReader, top: YamlMap) -> float | None:
    """``points:``, a number of at least 0 (0: the test counts for nothing), or ``None``."""
    if "points" not in top:
        return None
    value = top["points"]
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value < 1e9:
        raise reader.fail(
            "'points' must be a number of at least 0, such as points: 10",
            top.value_mark("points"),
        )
    return float(value)


def _robot(reader: FieldReader, top: YamlMap) -> str:
    if "robot" not in top:
        return "mirto"
    robot = reader.text(top, "robot")
    try:
        get_profile(robot)
    except ProfileError:
        raise reader.fail(
            f"no robot called '{robot}' (built-in robots: {', '.join(BUILTIN_PROFILES)})",
            top.value_mark("robot"),
            did_you_mean(robot, BUILTIN_PROFILES),
        ) from None
    return robot


def _resolve_world(
    reader: FieldReader, written: str, folder: Path, mark: Mark, worlds: dict[str, World]
) -> str:
    """The world's name (built-in) or absolute path, loaded once into ``worlds``."""
    key = written
    if written not in builtin_worlds():
        candidate = folder / written
        if not candidate.is_file():
            raise reader.fail(
                f"no world called '{written}' (built-in worlds: {', '.join(builtin_worlds())};"
                " or a world file next to the spec)",
                mark,
                did_you_mean(written, builtin_worlds()),
            )
        kind = _kind_of_world_file(candidate)
        if kind is not None:
            raise reader.fail(
                f"world names '{written}': {not_the_kind_expected(kind, 'a simulator world')}",
                mark,
                "a world file has start:, walls:, lines: or regions:; or name a built-in"
                f" world: {', '.join(builtin_worlds())}",
            )
        key = str(candidate.resolve())
    if key not in worlds:
        worlds[key] = load_world(key)  # a WorldError names the world file's own line
    return key


def _kind_of_world_file(path: Path) -> FileKind | None:
    """What another kind of file named as a spec's world is (``mission``, ``profile``, ``test
    spec``), or ``None`` for a world, or a file the world reader says more about."""
    kind = file_kind(path)
    if kind == "world":
        return None
    if kind == "mission":  # also what a file that tells nothing is: only one with a mission's keys
        try:
            keys = set(load_yaml(path, error=SpecError) or {})
        except InputError:
            return None
        return kind if keys & OWN_KEYS["mission"] else None
    return kind


def _variants(
    reader: FieldReader,
    top: YamlMap,
    folder: Path,
    default_world: str,
    worlds: dict[str, World],
) -> tuple[Variant, ...]:
    if "runs" not in top:
        return (Variant(0, 1, default_world),)
    _refuse_unlisted(reader, top, "runs", "run", "- {seed: 1}")
    items = reader.items(top["runs"], "runs", top.value_mark("runs"))
    if not items:
        raise reader.fail(
            "runs lists at least one run, such as - {seed: 1}", top.value_mark("runs")
        )
    if len(items) > MAX_RUNS:
        raise reader.fail(
            f"a test lists at most {MAX_RUNS} runs, and this one lists {len(items):,}: every"
            f" student's mission runs once per run (a class of 30 would need"
            f" {30 * len(items):,} runs)",
            top.value_mark("runs"),
        )
    variants: list[Variant] = []
    targeted: set[int] = set()  # the runs with targets of their own
    for index, (item, mark) in enumerate(items):
        if item is None or not isinstance(item, YamlMap):
            got = "nothing" if item is None else repr(item)
            raise reader.fail(
                f"a run is a mapping such as - {{seed: {index + 1}}} (got {got})", mark
            )
        data = reader.mapping(item, "a run", mark)
        reader.allowed(data, _RUN_KEYS, "a run")
        seed = reader.integer(data, "seed") if "seed" in data else index + 1
        world = default_world
        if "world" in data:
            world = _resolve_world(
                reader, reader.text(data, "world"), folder, data.value_mark("world"), worlds
            )
        start = None
        if "start" in data:
            pose = reader.mapping(data["start"], "start", data.value_mark("start"))
            reader.allowed(pose, ("x", "y", "heading"), "start")
            base = worlds[world].start
            start = (
                _start_mm(reader, pose, "x") if "x" in pose else base.x_mm,
                _start_mm(reader, pose, "y") if "y" in pose else base.y_mm,
                reader.quantity(pose, "heading", "angle", "deg")
                if "heading" in pose
                else base.heading_deg,
            )
        name = _shown_name(reader, data, "name") if "name" in data else ""
        hidden = _flag(reader, data, "hidden")
        variants.append(Variant(index, seed, world, start, name, hidden))
        if "expect" in data:
            targeted.add(index)
    _check_runs_differ(reader, variants, targeted, worlds, [mark for _, mark in items])
    return tuple(variants)


def _check_runs_differ(
    reader: FieldReader,
    variants: list[Variant],
    targeted: set[int],
    worlds: dict[str, World],
    marks: list[Mark | None],
) -> None:
    """A run copied without changing it (a spec written in a hurry) is an error: a simulated
    run gives the same result every time, so it would only count one result twice, and
    reports (JUnit, Gradescope) would list two runs no one can tell apart. Runs with targets
    of their own (``targeted``, by index) are told apart by those (:func:`_run_overrides`)."""

    def setup(run: Variant) -> tuple[str, int, tuple[float, float, float]]:
        start = worlds[run.world].start
        return run.world, run.seed, run.start or (start.x_mm, start.y_mm, start.heading_deg)

    # Looked up by setup and by label, not compared pair by pair: a test of many runs is
    # read in time that grows with its runs.
    untargeted: dict[tuple[str, int, tuple[float, float, float]], Variant] = {}
    labels: dict[str, list[Variant]] = {}
    for later in variants:
        other = untargeted.get(setup(later))
        if other is not None and later.index not in targeted:
            raise reader.fail(
                f"this run is run {other.index + 1} again (seed {later.seed}, the same"
                " world and start): a simulated run gives the same result every time, so"
                " give it another seed or start",
                marks[later.index],
            )
        for named in labels.get(later.label, []):
            told_apart = setup(named) == setup(later) and {named.index, later.index} & targeted
            if not told_apart:
                raise reader.fail(
                    f"runs {named.index + 1} and {later.index + 1} are both named"
                    f" '{later.label}': reports could not tell them apart; give each its own"
                    " name",
                    marks[later.index],
                )
        if later.index not in targeted:
            untargeted.setdefault(setup(later), later)
        labels.setdefault(later.label, []).append(later)


def _refuse_starts_in_walls(
    reader: FieldReader,
    top: YamlMap,
    variants: tuple[Variant, ...],
    worlds: dict[str, World],
    body_radius_mm: float,
) -> None:
    """A run whose robot would start with its body in a wall is an error at that run (its
    ``start``): the simulator would report a collision before the mission did anything, and
    every student would be graded on a robot stuck in a wall."""
    written = top.get("runs")
    for variant in variants:
        world = worlds[variant.world]
        x, y, _ = variant.start or (world.start.x_mm, world.start.y_mm, world.start.heading_deg)
        if not world.walls:
            continue
        data = written[variant.index] if isinstance(written, YamlList) else None
        if isinstance(data, YamlMap) and "start" in data:
            mark = data.value_mark("start")
        elif isinstance(written, YamlList):
            mark = written.item_marks[variant.index]
        else:
            mark = top.value_mark("world") if "world" in top else (1, 1)
        room = enclosing_walls(world.walls, world.start.x_mm, world.start.y_mm)
        if room is not None and enclosing_walls(world.walls, x, y) != room:
            raise reader.fail(
                f"run {variant.index + 1} starts the robot at ({x:g}, {y:g}) mm, outside the"
                f" walls that shut in the start of '{world.name}': it could never reach"
                " anything inside them",
                mark,
            )
        gap_mm = min(segment_distance(x, y, wall) for wall in world.walls)
        if gap_mm >= body_radius_mm:
            continue
        raise reader.fail(
            f"run {variant.index + 1} starts the robot at ({x:g}, {y:g}) mm, {gap_mm:g} mm"
            f" from a wall of '{world.name}', but its body reaches {body_radius_mm:g} mm from"
            " its centre: it would start inside the wall; move the start at least"
            f" {body_radius_mm - gap_mm:.0f} mm away from it",
            mark,
        )


def _flag(reader: FieldReader, data: YamlMap, key: str) -> bool:
    """``data[key]`` as ``true``/``false`` (``False`` when absent)."""
    if key not in data:
        return False
    value = data[key]
    if not isinstance(value, bool):
        raise reader.fail(f"'{key}' must be true or false", data.value_mark(key))
    return value


def _run_overrides(
    top: YamlMap, variants: tuple[Variant, ...], worlds: dict[str, World]
) -> list[RunOverride]:
    """Each run's own targets (its ``expect:``), with what tells its record from the others'."""
    written = top.get("runs")
    runs = []
    for variant in variants:
        world = worlds[variant.world]
        start = variant.start or (world.start.x_mm, world.start.y_mm, world.start.heading_deg)
        key = (world.name, variant.seed, start)
        data = written[variant.index] if isinstance(written, YamlList) else None
        if isinstance(data, YamlMap) and "expect" in data:
            runs.append(RunOverride(key, world, data["expect"], data.value_mark("expect")))
        else:
            runs.append(RunOverride(key, world))
    return runs
