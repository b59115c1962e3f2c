"""Grading a class: pairing the students' missions with tests, running them all.

The students are found by :func:`~roboscript.grading.submissions.find_submissions` (see
:mod:`roboscript.grading.submissions` for who is who, what is refused and what a run may read).

With several tests, a student with one mission runs it in every test; a student with several
runs, in each test, the mission named after the test (``square-50cm.yaml``) or after the spec
file; a student without one is marked ``missing`` for that test. A submission that cannot be
graded (:attr:`~roboscript.grading.submissions.Submission.problem`) is ``invalid`` in every
run, none of which is started.
"""

from __future__ import annotations

import contextlib
import os
import re
import unicodedata
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Protocol

from roboscript.errors import InputError
from roboscript.grading.cell import Cell
from roboscript.grading.pool import RunTask, run_tasks
from roboscript.grading.record import RunResult
from roboscript.grading.sandbox import check_visible, detect_isolation, private_class
from roboscript.grading.spec import TestSpec, Variant, is_test_spec, load_test_spec
from roboscript.grading.submissions import (
    FoundSubmissions,
    Submission,
    changed_file,
    files_now,
    find_submissions,
    teachers_file_held,
    visible_files,
)
from roboscript.grading.text import cap_result, student_text
from roboscript.grading.world_host import DEFAULT_HANG_AFTER_S
from roboscript.inputs.kinds import file_kind
from roboscript.sim.world import World

__all__ = [
    "Cell",
    "ClassReport",
    "FoundSubmissions",
    "RunStore",
    "Submission",
    "SummariesOnly",
    "find_specs",
    "find_submissions",
    "grade_class",
    "mission_for_test",
    "run_summary",
    "visible_files",
]


def find_specs(paths: Sequence[str]) -> list[TestSpec]:
    """Load the test specs named (folders: every test spec in them).

    Raises:
        SpecError: A spec is invalid.
        InputError: A folder holds no test spec.
    """
    files: list[Path] = []
    for raw in paths:
        path = Path(raw)
        if path.is_dir():
            found = sorted(p for p in path.rglob("*.y*ml") if is_test_spec(p))
            if not found:
                raise InputError(f"no test specs (YAML files starting 'test:') in {raw}")
            files += found
        else:
            kind = file_kind(path)
            if kind in ("world", "profile"):  # a mission may still be a misnamed test spec
                raise InputError(
                    f"this is a {kind} file, not a test spec",
                    path=str(path),
                    line=1,
                    col=1,
                    hint="a test spec starts with 'test:' (see roboscript grade --help)",
                )
            files.append(path)
    specs = [load_test_spec(p) for p in dict.fromkeys(files)]
    seen: dict[str, str] = {}
    for spec in specs:
        # names that look the same (José composed and decomposed) would make two columns
        # no report tells apart
        key = unicodedata.normalize("NFC", spec.name)
        if key in seen:
            raise InputError(
                f"two specs are both called '{spec.name}' ({seen[key]} and {spec.path})"
            )
        seen[key] = spec.path
    return specs


def _key(text: str) -> str:
    return re.sub(r"[-_\s]+", "-", text.strip().lower())


def mission_for_test(submission: Submission, spec: TestSpec) -> str | None:
    """The mission a student runs in ``spec`` (see the module docstring), or ``None``."""
    if len(submission.missions) == 1:
        return submission.missions[0]
    wanted = {_key(spec.name), _key(Path(spec.path).stem)}
    for mission in submission.missions:
        if _key(Path(mission).stem) in wanted:
            return mission
    return None


@dataclass
class ClassReport:
    """A class graded against a set of tests.

    Attributes:
        specs: The tests, in the order given.
        submissions: The students.
        results: Every run, by test, then student, then variant.
        worlds: The worlds the runs used, by the name or path the variants give.
        isolation: How the runs were isolated, one sentence
            (:attr:`~roboscript.grading.sandbox.Isolation.statement`), for every report.
        full_run: Gives a run of :attr:`results` in full (record, replay, traceback) when
            the report holds only its summary (``grade`` and the gradebook read a run's
            line of the results file again when a page draws it); ``None`` when the
            results are whole.
    """

    specs: list[TestSpec]
    submissions: list[Submission]
    results: list[RunResult]
    worlds: dict[str, World] = field(default_factory=dict)
    isolation: str = ""
    full_run: Callable[[RunResult], RunResult] | None = field(
        default=None, compare=False, repr=False
    )

    def in_full(self, result: RunResult) -> RunResult:
        """``result`` with its record, replay and traceback, capped: what a report that draws
        a run (a page, ``--json``) reads, one run at a time."""
        return result if self.full_run is None else self.full_run(result)

    @property
    def passed(self) -> bool:
        """True if every run of every student passed."""
        return all(r.passed for r in self.results)

    @property
    def teachers_faults(self) -> str | None:
        """One sentence for the teacher when a check of theirs failed to judge some runs (see
        :attr:`~roboscript.grading.record.Verdict.teachers_fault`), or None.

        Those runs fail the check whatever the robot did: the grades are wrong until the check
        is fixed, which a teacher reading only scores would never see.
        """
        faults = [
            (result, verdict)
            for result in self.results
            for verdict in result.verdicts
            if verdict.teachers_fault
        ]
        if not faults:
            return None
        first, verdict = faults[0]
        names = sorted({v.name for _, v in faults})
        runs = len({id(result) for result, _ in faults})
        return (
            f"{' and '.join(names)} failed to judge {runs} of {len(self.results)} runs"
            f" (first: {first.student}, {first.test}: {verdict.detail}); those runs fail it"
            " whatever the robot did, so their grades are not to be trusted: fix the check"
            " and grade again"
        )

    _index: _Index | None = field(default=None, init=False, compare=False, repr=False)

    def _indexed(self) -> _Index:
        """Runs by student and test, specs by name, students by name: built once, when a
        report first asks, so a class of thousands is reported in time that grows with its
        runs, not with their square. Built again if :attr:`results` is replaced."""
        index = self._index
        if index is None or index.results is not self.results or index.count != len(self.results):
            index = _Index.of(self)
            self._index = index
        return index

    def cell(self, student: str, test: str) -> Cell:
        """One student in one test."""
        index = self._indexed()
        found = index.cells.get((student, test), ())
        spec = index.specs.get(test)
        if spec is None:
            return Cell(student, test, found, float(len(found)))
        return Cell(student, test, found, spec.max_points, index.hidden[test])

    def student_score(self, student: str) -> float:
        """A student's mean score over the tests, 0 to 1."""
        cells = [self.cell(student, spec.name) for spec in self.specs]
        return round(sum(c.score for c in cells) / len(cells), 4) if cells else 0.0

    def student_points(self, student: str) -> float:
        """The points a student earned over every test."""
        return round(sum(self.cell(student, spec.name).points for spec in self.specs), 4)

    @property
    def max_points(self) -> float:
        """The points every test together is worth."""
        return round(sum(spec.max_points for spec in self.specs), 4)

    def variant_of(self, result: RunResult) -> Variant | None:
        """The spec's variant a run was made on."""
        spec = self._indexed().specs.get(result.test)
        if spec is None or result.variant >= len(spec.variants):
            return None
        return spec.variants[result.variant]

    def is_hidden(self, result: RunResult) -> bool:
        """Whether students must not see the run's variant (``hidden: true`` in the spec)."""
        variant = self.variant_of(result)
        return variant is not None and variant.hidden

    def public_label(self, result: RunResult) -> str:
        """How student-facing reports name the run: its label, or ``hidden run N``."""
        variant = self.variant_of(result)
        return variant.public_label if variant is not None else result.label

    def capped(self) -> ClassReport:
        """This report with every run's text capped (:func:`~roboscript.grading.text.cap`).

        Every report writer starts here, so no student-controlled text reaches a file
        uncapped, whoever built the report.
        """
        return replace(self, results=[cap_result(r) for r in self.results])

    def shown_mission(self, result: RunResult) -> str:
        """The run's mission file as its student knows it (no folder of the teacher's)."""
        submission = self._indexed().submissions.get(result.student)
        if submission is None:
            return Path(result.mission).name
        return submission.shown(result.mission)

    def world_for(self, result: RunResult) -> World | None:
        """The world a run happened in."""
        variant = self.variant_of(result)
        return None if variant is None else self.worlds.get(variant.world)

    def spec_for(self, test: str) -> TestSpec:
        """The spec of a test by name.

        Raises:
            KeyError: No spec of the report has that name.
        """
        return self._indexed().specs[test]


@dataclass(frozen=True)
class _Index:
    """What :class:`ClassReport` looks up by name, gathered in one pass over its runs."""

    results: list[RunResult]
    count: int
    cells: dict[tuple[str, str], tuple[RunResult, ...]]
    specs: dict[str, TestSpec]
    hidden: dict[str, frozenset[int]]
    submissions: dict[str, Submission]

    @classmethod
    def of(cls, report: ClassReport) -> _Index:
        cells: dict[tuple[str, str], list[RunResult]] = {}
        for result in report.results:
            cells.setdefault((result.student, result.test), []).append(result)
        specs: dict[str, TestSpec] = {}
        for spec in report.specs:
            specs.setdefault(spec.name, spec)  # the first of a name, as a search finds
        submissions: dict[str, Submission] = {}
        for submission in report.submissions:
            submissions.setdefault(submission.student, submission)
        return cls(
            report.results,
            len(report.results),
            {key: tuple(runs) for key, runs in cells.items()},
            specs,
            {name: frozenset(v.index for v in s.variants if v.hidden) for name, s in specs.items()},
            submissions,
        )


def _changed_while_graded(shown: str) -> str:
    """Why a run is ``invalid`` whose student's files changed while the class was graded."""
    return (
        f"{shown} changed while the class was being graded (added, removed or rewritten after"
        " grading began): this run may have read another version of the mission than the"
        " others, so it is not counted; grade the student again"
    )


def run_summary(result: RunResult) -> RunResult:
    """What a class's report holds of a run while something else holds it in full: all that
    its summaries read (status, score, verdicts, message), without the record, replay and
    traceback, which a report reads again one run at a time to draw it
    (:meth:`ClassReport.in_full`)."""
    return replace(result, record=None, replay=None, debug="")


class RunStore(Protocol):
    """Where :func:`grade_class` puts each run in full the moment it ends, so the report holds
    only summaries (a results file: :class:`~roboscript.grading.shards.ResultsFile`)."""

    def keep(self, result: RunResult) -> RunResult:
        """Keep ``result`` in full; return what the report holds of it
        (:func:`run_summary`)."""
        ...

    def full_run(self, result: RunResult) -> RunResult:
        """The run :meth:`keep` returned ``result`` for, in full and capped."""
        ...


class SummariesOnly:
    """A :class:`RunStore` that keeps no run in full: for reports that draw no run (the
    table, ``--csv``, ``--junit``, a platform's ``results.json``)."""

    def keep(self, result: RunResult) -> RunResult:
        """``result``'s :func:`run_summary`; the rest is let go."""
        return run_summary(result)

    def full_run(self, result: RunResult) -> RunResult:
        """``result`` itself: nothing more of it was kept."""
        return result


def grade_class(
    specs: Sequence[TestSpec],
    submissions: Sequence[Submission],
    jobs: int | None = None,
    on_result: Callable[[RunResult], None] | None = None,
    *,
    hang_after_s: float = DEFAULT_HANG_AFTER_S,
    store: RunStore | None = None,
) -> ClassReport:
    """Run every student's mission on every variant of every test, each in its own worker.

    Args:
        specs: The tests.
        submissions: The students.
        jobs: Runs at once (default: one per CPU core).
        on_result: Called with each result the moment it is known: first those of runs that
            are not started (``missing``, and ``invalid`` for a submission with a problem),
            then the others in the order they end.
        hang_after_s: Own seconds one tick's code may run before the run is ``hung``.
        store: Given each result in full the moment it is known (before ``on_result``);
            the report then holds only what it returns (a summary), and reads a run in full
            from it again to draw it, so a class of any size is graded in the same memory.
            Without it, the report holds every run whole.

    Returns:
        The report; its results are in a fixed order (test, student, variant) whatever
        ``jobs`` is.
    """
    worlds = {name: world for spec in specs for name, world in spec.worlds.items()}
    # No student may read another's missions, nor the tests.
    private = frozenset(
        [Path(m).resolve() for s in submissions for m in s.missions]
        + [Path(s.folder).resolve() for s in submissions if s.folder is not None]
        + [Path(spec.path).resolve() for spec in specs]
    )
    # A run reads the student's files as they are when it starts: one changed meanwhile (a
    # late push, a sync) makes runs of one student grade two versions, so it is said
    started = {s.student: files_now(s) for s in submissions if not s.problem}
    teachers: dict[tuple[int, int], str] = {}
    for spec in specs:
        with contextlib.suppress(OSError):
            info = os.stat(spec.path)
            teachers[info.st_dev, info.st_ino] = Path(spec.path).name
    submissions = list(submissions)  # the caller's list stays as it was
    for i, s in enumerate(submissions):
        if s.student in started and (held := teachers_file_held(started[s.student], teachers)):
            submissions[i] = replace(s, problem=held)
    tasks: list[RunTask] = []
    slots: list[RunResult | int] = []  # a missing submission's result, or its task's index
    for spec in specs:
        for submission in submissions:
            mission = mission_for_test(submission, spec)
            for variant in spec.variants:
                if submission.problem:
                    slots.append(_refused(spec, submission, variant))
                    continue
                if mission is None:
                    slots.append(_missing(spec, submission, variant))
                    continue
                slots.append(len(tasks))
                own = frozenset(Path(m).resolve() for m in submission.missions)
                visible = visible_files(submission, mission, private - own)
                tasks.append(
                    RunTask(spec, mission, variant, submission.student, visible, hang_after_s)
                )
    roots = {s.student: s.root for s in submissions}
    by_student = {s.student: s for s in submissions}

    changed: dict[str, str] = {}  # a student whose file changed: the first file found

    def arrived(result: RunResult) -> RunResult:
        # Capped as they arrive, so a 20 MB exception message is not kept (or copied) any
        # further; and no report, the results file included, holds a folder of the teacher's.
        student = result.student
        if student in started and result.status not in ("invalid", "missing"):
            # once changed, every run after it may have read another version, even if the
            # file is put back: the student's files are not looked at again
            if student not in changed and (
                found := changed_file(by_student[student], started[student])
            ):
                changed[student] = found
            if student in changed:
                result = replace(
                    result,
                    status="invalid",
                    message=_changed_while_graded(changed[student]),
                    score=0.0,
                    verdicts=(),
                )
        return _for_students(cap_result(result), roots)

    def delivered(result: RunResult) -> RunResult:
        """What the report holds of a result, once it is kept and told."""
        result = arrived(result)
        kept = result if store is None else store.keep(result)
        if on_result is not None:
            on_result(result)
        return kept

    # Without bubblewrap, a run reads what file modes allow: only its own student's files.
    readable: dict[str, set[Path]] = {}
    for task in tasks:
        readable.setdefault(task.student, set()).update(task.visible or (Path(task.mission),))
    with private_class([sorted(p) for p in readable.values()], [Path(s.path) for s in specs]):
        tasks, slots = _check_setup(tasks, slots)
        # known before any run starts: reported first
        slots = [delivered(s) if isinstance(s, RunResult) else s for s in slots]
        done = run_tasks(tasks, jobs, keep=delivered)
    results = [slot if isinstance(slot, RunResult) else done[slot] for slot in slots]
    # Records come back through a pipe without their worlds; reports find them in `worlds`.
    return ClassReport(
        list(specs),
        list(submissions),
        results,
        worlds,
        detect_isolation().statement,
        None if store is None else store.full_run,
    )


def _check_setup(
    tasks: list[RunTask], slots: list[RunResult | int]
) -> tuple[list[RunTask], list[RunResult | int]]:
    """Every submission's files can be shown to its sandbox, checked before any run.

    When no submission's can (a class folder root's jails cannot read), that is one error for
    the teacher. When only some cannot (a student's file that others may not read), those
    students' runs are ``invalid``, saying why, and the others are graded.

    Returns:
        The tasks to run and the slots, those of refused runs now their results.

    Raises:
        InputError: Naming a student and what to fix, when no submission can be shown.
    """
    blocked: dict[str, str] = {}
    checked: set[tuple[Path, ...]] = set()
    for task in tasks:
        visible = task.visible or (Path(task.mission).resolve(),)
        if visible in checked or task.student in blocked:
            continue
        checked.add(visible)
        try:
            check_visible(visible)
        except (OSError, ValueError) as exc:
            blocked[task.student] = str(exc)
    if not blocked:
        return tasks, slots
    if blocked.keys() >= {task.student for task in tasks}:
        student, reason = next(iter(blocked.items()))
        raise InputError(f"cannot grade {student or tasks[0].mission}: {reason}")
    kept: list[RunTask] = []
    new_slots: list[RunResult | int] = []
    for slot in slots:
        if isinstance(slot, RunResult):
            new_slots.append(slot)
        elif tasks[slot].student in blocked:
            task = tasks[slot]
            reason = blocked[task.student]
            new_slots.append(
                task.spec.result(
                    task.variant,
                    student=task.student,
                    mission=task.mission,
                    status="invalid",
                    message=f"the grader's sandbox cannot show this submission's files: {reason}",
                    during_load=True,
                )
            )
        else:
            new_slots.append(len(kept))
            kept.append(tasks[slot])
    return kept, new_slots


def _for_students(result: RunResult, roots: dict[str, str | None]) -> RunResult:
    """``result`` with no folder of the teacher's computer in what students read of it."""
    root = roots.get(result.student)
    record = result.record
    if record is not None and record.reason:
        record = replace(record, reason=student_text(record.reason, root))
    return replace(result, message=student_text(result.message, root), record=record)


def _refused(spec: TestSpec, submission: Submission, variant: Variant) -> RunResult:
    """The result of a run of a submission that cannot be graded: never started."""
    return spec.result(
        variant,
        student=submission.student,
        mission=submission.missions[0] if submission.missions else "",
        status="invalid",
        message=submission.problem,
        during_load=True,
    )


def _missing(spec: TestSpec, submission: Submission, variant: Variant) -> RunResult:
    names = ", ".join(Path(m).name for m in submission.missions)
    return spec.result(
        variant,
        student=submission.student,
        mission="",
        status="missing",
        message=(
            f"no mission for the test '{spec.name}': name it {spec.name}.yaml or"
            f" {spec.name}.py (found {names})"
        ),
    )
