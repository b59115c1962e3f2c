"""Grading a class in parts on several machines, and putting the parts back together.

``roboscript grade … --shard I/N --results PART.jsonl`` grades part ``I`` of ``N`` of the
class: the students whose name falls in that part (:func:`shard_number`, a hash of the name,
so the same student is in the same part on every machine, whatever else the class holds).
``roboscript gradebook PART.jsonl…`` reads the parts back into one
:class:`~roboscript.grading.batch.ClassReport`, from which every report is written as one
run would have written it.

A results file (``--results``) is JSON Lines:

* line 1, the header: ``{"roboscript_results": 2, "roboscript": VERSION, "shard": [I, N] or
  null, "isolation": how the runs were isolated, "specs": [{"path", "sha256"}], "students":
  [{"name", "missions", "folder", "problem", "root", "own"}]}``: the
  specs by the path they were given (relative to the folder ``grade`` ran in) and a hash of
  their files (the spec, and the world files it names), and the students of this part;
* one line per finished run, written the moment it ends: the run as in ``--json``'s ``runs``
  (without ``hidden`` and the points, which the specs give), with its replay for the HTML
  report.

The gradebook reads the specs again from their paths (so it runs in the same folder as
``grade``, e.g. the same checkout of the course repository) and refuses to merge when a spec
changed since, when the parts are not one whole class (one missing, one twice, different
``N``), or when a part lacks runs (a grader stopped early).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from roboscript import __version__
from roboscript.errors import InputError
from roboscript.grading.batch import ClassReport, find_specs, run_summary
from roboscript.grading.record import MAX_GRADED_STATES, GradedRecord, RunResult
from roboscript.grading.spec import TestSpec
from roboscript.grading.submissions import Submission
from roboscript.grading.text import cap_result, clean_name
from roboscript.interrupts import deferred
from roboscript.replay.recording import replay_misfit
from roboscript.run_record import misfit
from roboscript.sim.body import MAX_CONTACTS, MAX_TONES
from roboscript.sim.simulation import MAX_PATH_SAMPLES
from roboscript.sim.world import WORLD_REACH_MM

__all__ = [
    "RESULTS_FORMAT",
    "ResultsFile",
    "Shard",
    "read_results",
    "results_header",
    "shard_number",
    "spec_hash",
]

RESULTS_FORMAT = 2
"""The version of the results file's layout (the header's ``roboscript_results``): 2 since a
run's ``record`` is ``run --json``'s object (format 1's is still read, so parts graded by
the roboscript before merge)."""

READABLE_RESULTS_FORMATS = (1, RESULTS_FORMAT)
"""The results files' layouts the gradebook reads."""


def shard_number(student: str, count: int) -> int:
    """The part (1 to ``count``) a student is graded in: a hash of the name, the same on every
    machine and Python (never Python's own ``hash()``, which changes with each process)."""
    digest = hashlib.sha256(student.encode("utf-8")).digest()
    return int.from_bytes(digest[:8], "big") % count + 1


@dataclass(frozen=True)
class Shard:
    """Part ``index`` (1-based) of ``count``."""

    index: int
    count: int

    @classmethod
    def parse(cls, text: str) -> Shard:
        """``"2/3"`` as ``Shard(2, 3)``.

        Raises:
            ValueError: One sentence saying what is wrong.
        """
        head, sep, tail = text.partition("/")
        if not sep or not head.strip().isdigit() or not tail.strip().isdigit():
            raise ValueError(f"--shard is I/N, such as 2/3 (got '{text}')")
        index, count = int(head), int(tail)
        if count < 1 or not 1 <= index <= count:
            raise ValueError(f"--shard I/N needs 1 <= I <= N (got '{text}')")
        return cls(index, count)

    def holds(self, student: str) -> bool:
        """Whether the student is graded in this part."""
        return shard_number(student, self.count) == self.index

    def __str__(self) -> str:
        return f"{self.index}/{self.count}"


def spec_hash(spec: TestSpec) -> str:
    """SHA-256 of the spec's file and the world files it names, in a fixed order."""
    digest = hashlib.sha256()
    files = [Path(spec.path), *sorted(Path(w) for w in spec.worlds if Path(w).is_file())]
    for file in files:
        digest.update(file.name.encode("utf-8") + b"\0")
        digest.update(file.read_bytes())
    return digest.hexdigest()


def results_header(
    specs: Sequence[TestSpec],
    submissions: Sequence[Submission],
    shard: Shard | None,
    isolation: str = "",
) -> dict[str, Any]:
    """The first line of a results file (see the module docstring); ``isolation`` says how
    this part's runs were isolated, as every report does."""
    return {
        "roboscript_results": RESULTS_FORMAT,
        "roboscript": __version__,
        "shard": [shard.index, shard.count] if shard is not None else None,
        "isolation": isolation,
        "specs": [{"path": spec.path, "sha256": spec_hash(spec)} for spec in specs],
        "students": [
            {
                "name": s.student,
                "missions": list(s.missions),
                "folder": s.folder,
                "problem": s.problem,
                "root": s.root,
                "own": list(s.own),
            }
            for s in submissions
        ],
    }


@dataclass
class _Part:
    path: str
    header: dict[str, Any]


MAX_RUN_LINE_BYTES = 64 * 1024**2
"""The longest run line a results file may hold (bytes): a run's line is its record and its
replay, a few hundred kilobytes for the longest graded run."""


def _lines(path: str) -> Iterator[tuple[int, int, str]]:
    """Each line of a results file as it is read: (line number, byte offset, text).

    One line at a time, so a class's file is never held whole (the gradebook keeps only what
    the reports sum up, and reads a run's record and replay again when a page draws it).

    Raises:
        InputError: The file cannot be read, is not UTF-8, or holds a line longer than any
            run writes.
    """
    try:
        with Path(path).open("rb") as stream:
            number = 0
            while True:
                offset = stream.tell()
                raw = stream.readline(MAX_RUN_LINE_BYTES + 1)
                if not raw:
                    return
                number += 1
                if len(raw) > MAX_RUN_LINE_BYTES:
                    raise InputError(
                        f"{path} is damaged: line {number} is longer than"
                        f" {MAX_RUN_LINE_BYTES:,} bytes, more than any run writes"
                    )
                yield number, offset, raw.decode("utf-8").rstrip("\n")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read {path}: {getattr(exc, 'strerror', None) or exc}") from None


def _read_part(path: str) -> _Part:
    """A results file's header (its first line), checked; its runs are read later, one by
    one."""
    first = next(_lines(path), None)
    try:
        try:
            header = _json_object(first[2]) if first is not None else None
        except (ValueError, RecursionError):
            header = None  # a first line that is no JSON object: another kind of file
        if (
            not isinstance(header, dict)
            or header.get("roboscript_results") not in READABLE_RESULTS_FORMATS
        ):
            raise InputError(
                f"{path} is not a results file of this roboscript"
                " (written by `roboscript grade --results FILE`)"
            )
        _check_header(header)
    except (ValueError, KeyError, TypeError, RecursionError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"{path} is damaged: {_reason(exc)}") from None
    return _Part(path, header)


def _run_lines(part: _Part) -> Iterator[tuple[int, int, str]]:
    """The run lines of a part, one at a time (line 1 is the header). A grader killed
    mid-line leaves a partial last line: skipped here, the missing-run check names it."""
    for number, offset, line in _lines(part.path):
        if number > 1 and line.strip() and line.rstrip().endswith("}"):
            yield number, offset, line


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a number JSON allows")


def _json_object(text: str) -> Any:
    """The JSON value of ``text``, refusing NaN and Infinity (which no report can draw)."""
    return json.loads(text, parse_constant=_no_constant)


def _reason(exc: BaseException) -> str:
    if isinstance(exc, RecursionError):
        return "it is nested too deeply"
    if isinstance(exc, KeyError):
        return f"the field {exc} is missing"
    return str(exc.args[0] if exc.args else exc).split("\n")[0]


def _read_run(part: _Part, number: int, text: str, specs: dict[str, TestSpec]) -> RunResult:
    """The run on line ``number`` of ``part``, checked to be one its spec could give.

    Raises:
        InputError: One sentence naming the file, the line and what is wrong with it.
    """
    try:
        data = _json_object(text)
        if not isinstance(data, dict):
            raise TypeError("it is not a JSON object")
        run = RunResult.from_dict(data)
        problem = misfit(RunResult, run) or _out_of_range(run, specs)
    except (ValueError, KeyError, TypeError, RecursionError) as exc:
        problem = _reason(exc)
    if problem:
        raise InputError(f"{part.path} line {number} is damaged: {problem}")
    # Cleaned as the header's names are by Submission: a part graded by an older roboscript,
    # which cleaned names less, still finds its students' runs.
    return replace(run, student=clean_name(run.student))


TIME_SLACK_S = 5.0
"""How far past its test's ``max_time`` a run's times may go (the world's own slack and the
tick the run ended in)."""
FASTEST_MM_S = 10_000.0
"""Faster than any simulated robot moves (the fastest built-in robot drives at 350 mm/s):
with the farthest a world (and so a start) reaches, it bounds where a run's robot can be."""


def _out_of_range(run: RunResult, specs: dict[str, TestSpec]) -> str | None:
    """What in a run (whose types fit) no grading of its spec could have given, or None."""
    spec = specs.get(run.test)
    if spec is None:
        return f"its test {run.test!r} is not one of the specs graded"
    if not 0 <= run.variant < len(spec.variants):
        count = len(spec.variants)
        return f"its 'variant' {run.variant} is not one of the {count} runs of {spec.name}"
    if not 0 <= run.score <= 1:
        return f"its 'score' {run.score!r} is not between 0 and 1"
    if not 0 <= run.wall_time_s <= spec.longest_wall_time_shown_s:
        longest = spec.longest_wall_time_shown_s
        return (
            f"its 'wall_time_s' {run.wall_time_s!r} is not a time a run of {spec.name} takes"
            f" (at most {longest:g} s)"
        )
    if len(run.verdicts) > len(spec.expectations):
        return f"it has {len(run.verdicts)} verdicts, more than {spec.name}'s expectations"
    limit_s = spec.max_time_s + TIME_SLACK_S
    for verdict in run.verdicts:
        if not 0 <= verdict.weight <= 1e6:
            return f"the verdict {verdict.name!r} has the weight {verdict.weight!r}"
        if (
            verdict.first_violation_s is not None
            and not -limit_s <= verdict.first_violation_s <= limit_s
        ):
            at = verdict.first_violation_s
            return f"the verdict {verdict.name!r} failed at {at!r} s, outside the run"
    record = run.record
    if record is not None:
        problem = _record_out_of_range(record, limit_s)
        if problem:
            return problem
    if run.replay is not None:
        return replay_misfit(run.replay, limit_s)
    return None


def _record_out_of_range(record: GradedRecord, limit_s: float) -> str | None:
    if not 0 <= record.duration_s <= limit_s:
        return (
            f"its 'duration_s' {record.duration_s!r} is not between 0 and its test's max_time"
            f" ({limit_s - TIME_SLACK_S:g} s)"
        )
    sim = record.simulation
    sizes = (
        ("states", len(record.states), MAX_GRADED_STATES),
        ("transitions", len(record.transitions), MAX_GRADED_STATES),  # one per state
        ("path samples", len(sim.path), MAX_PATH_SAMPLES + 16),
        ("tones", len(sim.tones), MAX_TONES),
        ("collisions", len(record.collisions), MAX_CONTACTS),
    )
    for name, size, most in sizes:
        if size > most:
            return f"its record lists {size:,} {name}, more than the {most:,} any run keeps"
    counts = (record.states_dropped, sim.collisions, sim.tones_not_listed)
    if any(not 0 <= count <= 10**9 for count in counts):
        return "a count in its record is negative or beyond any run"
    times = [t for t, _ in record.states]
    times += [sample[0] for sample in sim.path]
    times += [tone.t_s for tone in sim.tones] + [c.t_s for c in record.collisions]
    if any(not -limit_s <= t <= limit_s for t in times):
        return "a time in its record is outside the run"
    farthest_mm = WORLD_REACH_MM + FASTEST_MM_S * limit_s
    places = [value for sample in sim.path for value in sample[1:3]]
    places += [sim.final_pose.x_mm, sim.final_pose.y_mm]
    places += [value for c in record.collisions for value in (c.x_mm, c.y_mm)]
    places += [record.body_radius_mm, record.side_sensor_offset_mm]
    if any(abs(value) > farthest_mm for value in places):
        return f"a position in its record is more than {farthest_mm / 1e6:g} km away"
    if not 0 <= sim.distance_travelled_mm <= FASTEST_MM_S * limit_s:
        return f"its 'distance_travelled_mm' {sim.distance_travelled_mm!r} is not a distance"
    if any(not 0 <= tone.duration_s <= limit_s or tone.frequency_hz < 0 for tone in sim.tones):
        return "a tone in its record has a negative frequency or a duration outside the run"
    return None


def _check_header(header: dict[str, Any]) -> None:
    """The header holds what the gradebook reads from it (else ``TypeError``: damaged)."""
    specs, students = header.get("specs"), header.get("students")
    if not isinstance(specs, list) or not isinstance(students, list):
        raise TypeError("its first line lacks the test specs or the students")
    for entry in specs:
        if not isinstance(entry, dict) or not all(
            isinstance(entry.get(key), str) for key in ("path", "sha256")
        ):
            raise TypeError(
                _capped(f"a test spec on its first line is not a path and a hash: {entry!r}")
            )
    for entry in students:
        if not (
            isinstance(entry, dict)
            and isinstance(entry.get("name"), str)
            and _texts(entry.get("missions"))
        ):
            raise TypeError(
                _capped(f"a student on its first line has no name or missions: {entry!r}")
            )
        for key, kind in _STUDENT_FIELDS.items():
            value = entry.get(key)
            if key in entry and not (isinstance(value, kind) and (key != "own" or _texts(value))):
                name = entry["name"]
                raise TypeError(
                    _capped(f"the student {name!r}'s {key!r} on its first line is {value!r}")
                )
    shard = header.get("shard")
    if shard is not None and not (
        isinstance(shard, list)
        and len(shard) == 2
        and all(isinstance(n, int) and not isinstance(n, bool) for n in shard)
        and 1 <= shard[0] <= shard[1]
    ):
        raise TypeError(_capped(f"its first line's 'shard' is {shard!r}, not a part I of N"))


def _texts(value: Any) -> bool:
    """Whether ``value`` is a list of texts."""
    return isinstance(value, list) and all(isinstance(item, str) for item in value)


def _capped(sentence: str) -> str:
    """``sentence`` cut to 300 characters: a damaged file's value may be megabytes long."""
    return sentence if len(sentence) <= 300 else sentence[:299] + "…"


_STUDENT_FIELDS: dict[str, Any] = {
    "folder": str | None,
    "problem": str,
    "root": str | None,
    "own": list,
}


def _check_parts(parts: Sequence[_Part]) -> None:
    """The parts are one whole class, graded against the same specs.

    Raises:
        InputError: One sentence naming the file and what is wrong.
    """
    first = parts[0]
    for part in parts[1:]:
        if part.header["specs"] != first.header["specs"]:
            raise InputError(
                f"{part.path} and {first.path} were graded against different test specs"
            )
    shards = [part.header.get("shard") for part in parts]
    if any(shard is None for shard in shards):
        if len(parts) > 1:
            unsharded = next(p.path for p in parts if p.header.get("shard") is None)
            raise InputError(
                f"{unsharded} holds a whole class (graded without --shard): merge it alone"
            )
        return
    splits = [(int(shard[0]), int(shard[1])) for shard in shards if shard is not None]
    counts = {count for _, count in splits}
    if len(counts) > 1:
        raise InputError(f"the parts come from different splits (--shard I/N with N = {counts})")
    count = counts.pop()
    seen: dict[int, str] = {}
    for part, (index, _) in zip(parts, splits, strict=True):
        if index in seen:
            raise InputError(f"{part.path} and {seen[index]} are both part {index}/{count}")
        seen[index] = part.path
    missing = [str(i) for i in range(1, count + 1) if i not in seen]
    if missing:
        raise InputError(
            f"part{'s' if len(missing) > 1 else ''} {', '.join(missing)} of {count}"
            " missing: give every part's results file"
        )


def _load_specs(header: dict[str, Any], path: str) -> list[TestSpec]:
    written = header["specs"]
    paths = [entry["path"] for entry in written]
    for spec_path in paths:
        if not Path(spec_path).is_file():
            raise InputError(
                f"the test spec {spec_path} that {path} was graded against is not here:"
                " run the gradebook in the folder where `roboscript grade` ran"
            )
    specs = find_specs(paths)
    for spec, entry in zip(specs, written, strict=True):
        if spec_hash(spec) != entry["sha256"]:
            raise InputError(
                f"the test spec {spec.path} (or a world it names) changed since {path} was"
                " graded: grade again, or merge with the specs it was graded against"
            )
    return specs


def read_results(paths: Sequence[str], refused: Callable[[str], None] | None = None) -> ClassReport:
    """The class report the results files make together, as one ``grade`` would have made it.

    Every run line is checked field by field (types, finite numbers, times within its test's
    ``max_time``, sizes no run reaches) before any report reads it. The files are read line
    by line, and the report keeps of each run only what its summaries need (status, score,
    verdicts, message): a report that draws a run (its record, replay and traceback) reads
    that line again (:meth:`~roboscript.grading.batch.ClassReport.in_full`), so the memory
    the gradebook needs does not grow with the runs' records and replays, however large the
    class.

    Args:
        paths: The results files.
        refused: Told one sentence per damaged run line (naming the file and the line) and
            per student left out for it; the other students' report is still made. Without
            it, a damaged run line raises.

    Raises:
        InputError: A file cannot be read or its header is damaged, the files are not the
            parts of one class, a spec is missing or changed, or a part lacks runs (the
            grader stopped early); a run line is damaged and ``refused`` is not given.
    """
    parts = [_read_part(path) for path in dict.fromkeys(paths)]
    _check_parts(parts)
    specs = _load_specs(parts[0].header, parts[0].path)
    by_name = {spec.name: spec for spec in specs}
    submissions: list[Submission] = []
    results: dict[tuple[str, str, int], tuple[RunResult, _Line]] = {}
    damaged: set[str] = set()  # the parts with a damaged run line
    for part in parts:
        for entry in part.header["students"]:
            submissions.append(
                Submission(
                    entry["name"],
                    tuple(entry["missions"]),
                    entry.get("folder"),
                    entry.get("problem", ""),
                    entry.get("root"),
                    tuple(entry.get("own", ())),
                )
            )
        for number, offset, text in _run_lines(part):
            try:
                run = _read_run(part, number, text, by_name)
                key = (run.test, run.student, run.variant)
                if key in results:
                    raise InputError(
                        f"{part.path} line {number} is damaged: it repeats the run of"
                        f" {run.student} in {run.test} on line {results[key][1].number}"
                    )
            except InputError as exc:
                if refused is None:
                    raise
                refused(exc.message)
                damaged.add(part.path)
                continue
            results[key] = (run_summary(run), _Line(part, number, offset))
    names = [s.student for s in submissions]
    if len(set(names)) < len(names):
        twice = sorted(n for n in set(names) if names.count(n) > 1)
        raise InputError(f"the student {twice[0]} is in two parts: were they split differently?")
    # The order of `find_submissions` and `grade_class`: students by name, runs by test,
    # student and variant.
    submissions.sort(key=lambda s: s.student.lower())
    ordered: list[RunResult] = []
    left_out: set[str] = set()
    for spec in specs:
        for submission in submissions:
            for variant in spec.variants:
                found = results.get((spec.name, submission.student, variant.index))
                if found is not None:
                    ordered.append(found[0])
                    continue
                where = next(p.path for p in parts if submission.student in _students(p.header))
                if where not in damaged or refused is None:
                    raise InputError(
                        f"{where} lacks the run of {submission.student} in {spec.name}"
                        f" ({variant.label}): the grader stopped early; grade that part again"
                    )
                if submission.student not in left_out:
                    refused(
                        f"{submission.student} is left out of every report: {where} has no"
                        f" sound line for their run in {spec.name} ({variant.label}), which a"
                        " damaged line may have held; grade them again"
                    )
                    left_out.add(submission.student)
    if left_out:
        submissions = [s for s in submissions if s.student not in left_out]
        ordered = [r for r in ordered if r.student not in left_out]
    lines = {key: line for key, (_, line) in results.items()}

    def in_full(run: RunResult) -> RunResult:
        line = lines[run.test, run.student, run.variant]
        return cap_result(line.read(by_name))

    worlds = {name: world for spec in specs for name, world in spec.worlds.items()}
    # parts graded on different machines may have been isolated differently: say each way
    isolation = "; ".join(dict.fromkeys(str(p.header.get("isolation") or "") for p in parts))
    return ClassReport(specs, submissions, ordered, worlds, isolation.strip("; "), in_full)


class ResultsFile:
    """A results file (``grade --results FILE``) as ``grade`` writes it: the header, then
    each run's line the moment the run ends.

    It is where the class's runs are kept in full while they are graded
    (a :class:`~roboscript.grading.batch.RunStore`): the report holds each run's
    :func:`~roboscript.grading.batch.run_summary` and reads the run's line again when a
    page draws it, so grading a class needs no more memory for a thousand students than for
    ten.
    """

    def __init__(
        self,
        path: str | Path,
        specs: Sequence[TestSpec],
        submissions: Sequence[Submission],
        shard: Shard | None = None,
        isolation: str = "",
    ) -> None:
        """Create (or empty) ``path`` and write its header.

        Raises:
            OSError: The file cannot be written.
        """
        header = results_header(specs, submissions, shard, isolation)
        self.path = str(path)
        self.written = 0
        """Run lines written so far (whole: a signal waits until a line is)."""
        self._part = _Part(self.path, header)
        self._specs = {spec.name: spec for spec in specs}
        self._lines: dict[tuple[str, str, int], _Line] = {}
        # bytes, so each line's offset is known; open until close(), as the class is graded
        self._stream = Path(path).open("wb")  # noqa: SIM115
        self._write(json.dumps(header) + "\n")

    def _write(self, line: str) -> None:
        self._stream.write(line.encode("utf-8"))
        self._stream.flush()  # a grader killed now keeps every finished run

    def keep(self, result: RunResult) -> RunResult:
        """Write ``result`` in full (with its replay: a gradebook's --html shows it) as the
        next line; return its :func:`~roboscript.grading.batch.run_summary`."""
        line = json.dumps(result.to_dict(replay=True), ensure_ascii=False) + "\n"
        with deferred():  # a Ctrl-C waits until the line is whole
            offset = self._stream.tell()
            self._write(line)
            self.written += 1
            number = self.written + 1  # the header is line 1
        self._lines[result.test, result.student, result.variant] = _Line(self._part, number, offset)
        return run_summary(result)

    def full_run(self, result: RunResult) -> RunResult:
        """The run of ``result`` (a summary :meth:`keep` gave) in full, capped, read again
        from its line.

        Raises:
            InputError: The line is no longer the run written there (the file changed).
        """
        line = self._lines.get((result.test, result.student, result.variant))
        if line is None:
            return result
        return cap_result(line.read(self._specs))

    def close(self) -> None:
        """Close the file (its runs can still be read again)."""
        self._stream.close()


@dataclass(frozen=True)
class _Line:
    """Where a run's line is in its results file, to read it again when a report draws it."""

    part: _Part
    number: int
    offset: int

    def read(self, specs: dict[str, TestSpec]) -> RunResult:
        """The run on this line, checked again (the file is read, not trusted, each time).

        Raises:
            InputError: The line is no longer the run it was (the file changed meanwhile).
        """
        with Path(self.part.path).open("rb") as stream:
            stream.seek(self.offset)
            raw = stream.readline(MAX_RUN_LINE_BYTES + 1)
        try:
            text = raw.decode("utf-8").rstrip("\n")
        except UnicodeDecodeError:
            text = ""
        return _read_run(self.part, self.number, text, specs)


def _students(header: dict[str, Any]) -> set[str]:
    return {clean_name(entry["name"]) for entry in header["students"]}
