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
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from roboscript import __version__
from roboscript.errors import InputError
from roboscript.grading.batch import ClassReport, find_specs
from roboscript.grading.record import RunResult
from roboscript.grading.spec import TestSpec
from roboscript.grading.submissions import Submission
from roboscript.grading.text import clean_name

__all__ = [
    "RESULTS_FORMAT",
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
    runs: list[RunResult]


def _read_part(path: str) -> _Part:
    try:
        lines = Path(path).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read {path}: {getattr(exc, 'strerror', None) or exc}") from None
    try:
        header = json.loads(lines[0]) if lines else None
        if (
            not isinstance(header, dict)
            or header.get("roboscript_results") not in READABLE_RESULTS_FORMATS
        ):
            raise InputError(
                f"{path} is not a results file of this roboscript"
                " (written by `roboscript grade --results FILE`)"
            )
        _check_header(header)
        # A grader killed mid-line leaves a partial last line: the missing-run check names it.
        whole = [line for line in lines[1:] if line.endswith("}")]
        runs = [RunResult.from_dict(json.loads(line)) for line in whole]
    except (ValueError, KeyError, TypeError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"{path} is damaged: {exc}") from None
    return _Part(path, header, runs)


def _check_header(header: dict[str, Any]) -> None:
    """The header holds what the gradebook reads from it (else ``TypeError``: damaged)."""
    specs, students = header.get("specs"), header.get("students")
    if not isinstance(specs, list) or not isinstance(students, list):
        raise TypeError("its first line lacks the test specs or the students")
    for entry in specs:
        if not isinstance(entry, dict) or not all(
            isinstance(entry.get(key), str) for key in ("path", "sha256")
        ):
            raise TypeError(f"a test spec on its first line is not a path and a hash: {entry!r}")
    for entry in students:
        if not (
            isinstance(entry, dict)
            and isinstance(entry.get("name"), str)
            and isinstance(entry.get("missions"), list)
        ):
            raise TypeError(f"a student on its first line has no name or missions: {entry!r}")


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


def read_results(paths: Sequence[str]) -> ClassReport:
    """The class report the results files make together, as one ``grade`` would have made it.

    Raises:
        InputError: A file cannot be read or is damaged, the files are not the parts of one
            class, a spec is missing or changed, or a part lacks runs.
    """
    parts = [_read_part(path) for path in dict.fromkeys(paths)]
    _check_parts(parts)
    specs = _load_specs(parts[0].header, parts[0].path)
    submissions: list[Submission] = []
    results: dict[tuple[str, str, int], RunResult] = {}
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
        for run in part.runs:
            # Cleaned as the header's names are by Submission: a part graded by an older
            # roboscript, which cleaned names less, still finds its students' runs.
            run = replace(run, student=clean_name(run.student))
            results[(run.test, run.student, run.variant)] = run
    names = [s.student for s in submissions]
    if len(set(names)) < len(names):
        twice = sorted(n for n in set(names) if names.count(n) > 1)
        raise InputError(f"the student {twice[0]} is in two parts: were they split differently?")
    # The order of `find_submissions` and `grade_class`: students by name, runs by test,
    # student and variant.
    submissions.sort(key=lambda s: s.student.lower())
    ordered: list[RunResult] = []
    for spec in specs:
        for submission in submissions:
            for variant in spec.variants:
                found = results.get((spec.name, submission.student, variant.index))
                if found is None:
                    where = next(p.path for p in parts if submission.student in _students(p.header))
                    raise InputError(
                        f"{where} lacks the run of {submission.student} in {spec.name}"
                        f" ({variant.label}): the grader stopped early; grade that part again"
                    )
                ordered.append(found)
    worlds = {name: world for spec in specs for name, world in spec.worlds.items()}
    # parts graded on different machines may have been isolated differently: say each way
    isolation = "; ".join(dict.fromkeys(str(p.header.get("isolation") or "") for p in parts))
    return ClassReport(specs, submissions, ordered, worlds, isolation.strip("; "))


def _students(header: dict[str, Any]) -> set[str]:
    return {clean_name(entry["name"]) for entry in header["students"]}
