"""Finding the students' work in what the teacher hands the grader, without trusting it.

Submissions (``--mission``) are files, globs or folders:

* a file is one student, named after the file (``alice.yaml`` -> ``alice``);
* a folder is a class: each mission file directly in it is one student (named after the file),
  and each sub-folder is one student (named after the folder) holding their mission(s);
* a glob's files are students named after the files, its folders students named after the
  folders (``subs/*`` -> one student per folder of ``subs``).

Students with the same file name (``subs/*/square.yaml``) are told apart by their folder, and
two mission files with one name in one folder (``ana.py`` beside ``ana.yaml``) are two
students named by their whole file names: neither takes the other's place. Python files count
only if they define a ``Mission`` class (behaviours and helpers do not); YAML files that are
test specs, worlds or robot profiles do not count.

The grader's own process never runs, imports or parses a student's code: it looks at each
``.py``, ``.yaml`` and ``.yml`` file it meets through
:func:`~roboscript.inputs.source.read_source` (at most 1 MiB, ordinary UTF-8 files only) and
reads a Python file's ``class ...(Mission)`` lines and a YAML file's top-level keys as text.
Whatever a file does to that (too big, not UTF-8, a pipe that never ends, anything raised),
it is its student's result: the submission is ``invalid``, with one sentence naming the file
by its path inside the submission. So are symbolic links (which could show a classmate's or
the teacher's files), devices, pipes and sockets, names that are not UTF-8, and a folder
holding more than :data:`MAX_ENTRIES` files and folders or :data:`MAX_SOURCE_BYTES` of them
to look into. Every student's name is cleaned once, here
(:func:`~roboscript.grading.text.clean_name`), and names are unique once cleaned.

What a graded run may read (:func:`visible_files`) follows the same lines: a student who is a
folder sees that folder; a student who is a file in a folder shared with classmates sees their
mission and the files of their own that it names: files named after the mission
(``alice.yaml`` -> ``alice.py``, ``alice_helpers.py``, ``behaviours/alice-turns.py``; only
``.py``, ``.yaml`` and ``.yml`` files), never a classmate's file, a shared file or an earlier
report, even to a student named ``grades`` beside ``grades.csv``.
"""

from __future__ import annotations

import contextlib
import glob
import os
import re
import stat
import unicodedata
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from roboscript.errors import InputError
from roboscript.grading.text import clean_name, one_line
from roboscript.inputs.kinds import file_kind, kind_of_keys, not_a_mission
from roboscript.inputs.limits import MAX_FILE_BYTES
from roboscript.inputs.source import read_source

__all__ = [
    "MAX_DEPTH",
    "MAX_ENTRIES",
    "MAX_SOURCE_BYTES",
    "MISSION_SUFFIXES",
    "FoundSubmissions",
    "Submission",
    "changed_file",
    "files_now",
    "find_submissions",
    "named_files",
    "teachers_file_held",
    "visible_files",
]

MISSION_SUFFIXES = (".yaml", ".yml", ".py")
"""The files that may be missions (and so are looked into)."""

MAX_ENTRIES = 10_000
"""The most files and folders one student's folder may hold (counted before any is read)."""

MAX_DEPTH = 32
"""The deepest one student's folders may nest (folders inside folders): deeper, paths grow
past what the system can open (4096 bytes), and no mission needs it."""

SHOWN_PATH_CHARS = 160
"""The longest path inside a submission a sentence shows whole; a longer one keeps its start
and its end, so the sentence still says what is wrong."""

MAX_SOURCE_BYTES = 16 * 1024 * 1024
"""The most ``.py``, ``.yaml`` and ``.yml`` bytes one student's folder may hold in all (16 MiB,
measured before any is read): each is read to tell whether it is a mission."""

_SPECIAL = {
    stat.S_IFCHR: "a device",
    stat.S_IFBLK: "a device",
    stat.S_IFIFO: "a named pipe",
    stat.S_IFSOCK: "a socket",
}


@dataclass(frozen=True)
class Submission:
    """One student's work: their name and mission files (paths as given).

    Attributes:
        student: The student's name, cleaned on creation
            (:func:`~roboscript.grading.text.clean_name`): every report shows this.
        missions: Their mission files.
        folder: Their own folder, when the student is a folder; their graded runs may read
            everything in it. A student who is a file may read only that file and the files of
            their own beside it that it names (see :func:`visible_files`).
        problem: Why the submission cannot be graded (one sentence naming the file by its path
            inside the submission), or empty. Every run of a submission with a problem is
            ``invalid``, and none is started.
        root: The folder paths are shown from: the student's folder, or the folder their file
            is in. No student-facing text holds a path above it.
        own: For a student who is a file: the files beside it that are theirs (named after
            their mission); what a run may read is the part of these the mission names.
    """

    student: str
    missions: tuple[str, ...]
    folder: str | None = None
    problem: str = ""
    root: str | None = None
    own: tuple[str, ...] = field(default=(), compare=False, repr=False)

    def __post_init__(self) -> None:
        # The one place a student's name is made safe: every report is written from this.
        object.__setattr__(self, "student", clean_name(self.student))

    def shown(self, path: str | Path) -> str:
        """``path`` as the student knows it: relative to :attr:`root` (else its file name)."""
        if self.root is None:
            return Path(path).name
        try:
            return Path(path).resolve().relative_to(Path(self.root).resolve()).as_posix()
        except (ValueError, OSError):
            return Path(path).name


@dataclass(frozen=True)
class FoundSubmissions:
    """What :func:`find_submissions` found in what the teacher handed the grader.

    Attributes:
        submissions: The students and their missions, in name order. A student whose files
            cannot be graded is still listed, with the reason in :attr:`Submission.problem`.
        unclaimed: What a class folder holds that is no student's work, by name
            (``bo.zip``, ``notes/``): hidden entries and the files a student who is a file
            owns by name (``alice_helpers.py``) left out, names cleaned for a terminal.
        lookalikes: One sentence per group of students whose names look the same in every
            report (``José`` written composed and decomposed, ``ana`` and ``ana ``): each is
            graded on its own, the one whose name is written as reports show it keeps it and
            the others are numbered (``José-2``); the sentence names their files by their
            codes, so the teacher can tell which is whose.
    """

    submissions: list[Submission]
    unclaimed: tuple[str, ...] = ()
    lookalikes: tuple[str, ...] = ()


# ------------------------------------------------------------------------- looking at files

_CLASS = re.compile(r"^[ \t]*class[ \t]+\w+[ \t]*\(([^)]{0,2000})\)", re.MULTILINE)
_BASE = re.compile(r"(?:\w+\s*\.\s*)*Mission")
_ALIAS = re.compile(r"\bMission[ \t]+as[ \t]+(\w{1,100})")
_TOP_KEY = re.compile(r"^([A-Za-z_][\w-]{0,100})[ \t]*:(?=[ \t\r]|$)", re.MULTILINE)
_TRIPLE_QUOTED = re.compile(r"(\"\"\"|\'\'\').*?(?:\1|\Z)", re.DOTALL)
"""A triple-quoted string (a docstring, or old code kept in one): no class is defined in it."""


def _defines_mission(text: str) -> bool:
    """Whether Python text defines a class with a base named ``Mission`` (or a name it is
    imported as: ``from roboscript import Mission as M``), read as text (outside
    triple-quoted strings, where old code is often kept)."""
    text = _TRIPLE_QUOTED.sub("", text)  # a mission kept in a docstring is no mission
    aliases = set(_ALIAS.findall(text))
    for match in _CLASS.finditer(text):
        bases = (part.strip() for part in match.group(1).split(","))
        if any(_BASE.fullmatch(base) or base in aliases for base in bases):
            return True
    return False


def _is_mission_text(path: Path, text: str) -> bool:
    if path.suffix.lower() == ".py":
        return _defines_mission(text)
    return kind_of_keys(set(_TOP_KEY.findall(text))) == "mission"


def _examine(path: Path, shown: str) -> tuple[bool, str]:
    """``(is a mission, problem)`` for a file that may be a mission; never raises."""
    try:
        return _is_mission_text(path, read_source(path)), ""
    except InputError as exc:
        where = f"{shown}:{exc.line}" if exc.line is not None else shown
        return False, f"{where} cannot be graded: {exc.message}"
    except Exception as exc:  # noqa: BLE001 - whatever a file does is its student's result
        return False, f"{shown} cannot be graded: reading it failed ({type(exc).__name__})"


def _entry_problem(mode: int, shown: str) -> str:
    """Why an entry that is not a folder or an ordinary file is refused."""
    if stat.S_ISLNK(mode):
        return (
            f"{shown} is a symbolic link: a submission holds its own files, not links to"
            " others (hand in the file itself)"
        )
    kind = _SPECIAL.get(stat.S_IFMT(mode), "not an ordinary file")
    return f"{shown} is {kind}, not an ordinary file: a submission holds ordinary files only"


def _name_problem(name: str, shown: str) -> str:
    """Why a file or folder name is refused (it is not UTF-8 text), or empty."""
    try:
        name.encode("utf-8")
    except UnicodeEncodeError:  # undecodable bytes, kept by Python as lone surrogates
        return f"{shown} has a name that is not UTF-8 text: rename it"
    return ""


def _shown_path(relative: str) -> str:
    """``relative`` as a sentence shows it: one line of visible text (a newline in a file's
    name would print a line of its own), whole or its start and end around ``…``."""
    relative = one_line(relative)
    if len(relative) <= SHOWN_PATH_CHARS:
        return relative
    half = SHOWN_PATH_CHARS // 2
    return f"{relative[: half - 10]}…{relative[-half:]}"


def _hidden(relative: str) -> bool:
    return any(part.startswith((".", "__")) for part in relative.split("/"))


def _walk(
    folder: Path,
    skip: frozenset[Path] = frozenset(),
    shared: bool = False,
    linked: dict[str, _Inode] | None = None,
) -> tuple[list[tuple[str, Path]], list[str]]:
    """Every ordinary file under ``folder`` (path relative to it, path), and what is refused.

    Nothing is followed: a symbolic link, a device, a pipe or a socket is a problem, named by
    its path relative to ``folder``. Folders in ``skip`` are not entered, nor hidden ones
    (``.git``) in a folder ``shared`` by students. At most :data:`MAX_ENTRIES` entries are
    looked at; a student's folder nesting deeper than :data:`MAX_DEPTH` is refused (a shared
    one is not looked into below that). Each file with more than one name (a hard link) is
    put in ``linked``, by its relative path, with its identity on the disk.
    """
    files: list[tuple[str, Path]] = []
    problems: list[str] = []
    stack = [(folder, "", 0)]
    count = 0
    while stack:
        current, shown, depth = stack.pop()
        try:
            entries = os.scandir(current)
        except OSError as exc:
            problems.append(f"{_shown_path(shown or '.')} cannot be read: {exc.strerror or exc}")
            continue
        with entries:
            for entry in entries:
                count += 1
                if count > MAX_ENTRIES:
                    too_many = (
                        f"the folder holds more than {MAX_ENTRIES} files and folders:"
                        " hand in the mission and its own files only"
                    )
                    return sorted(files), [too_many]
                name = f"{shown}/{entry.name}" if shown else entry.name
                if _name_problem(entry.name, name):
                    problems.append(_name_problem(entry.name, _shown_path(name)))
                    continue
                try:
                    mode = entry.stat(follow_symlinks=False).st_mode
                except OSError as exc:
                    problems.append(f"{_shown_path(name)} cannot be read: {exc.strerror or exc}")
                    continue
                if stat.S_ISDIR(mode):
                    if Path(entry.path) in skip or (shared and _hidden(entry.name)):
                        continue
                    if depth + 1 > MAX_DEPTH and shared:
                        continue  # no student's own file is that deep: a mission names none
                    if depth + 1 > MAX_DEPTH:
                        too_deep = (
                            f"the folder nests folders more than {MAX_DEPTH} deep"
                            f" ({_shown_path(name)}): hand in the mission and its own files only"
                        )
                        return sorted(files), [too_deep]
                    stack.append((Path(entry.path), name, depth + 1))
                elif stat.S_ISREG(mode):
                    files.append((name, Path(entry.path)))
                    if linked is not None:
                        _note_links(entry.stat(follow_symlinks=False), name, linked)
                else:
                    problems.append(_entry_problem(mode, _shown_path(name)))
    return sorted(files), sorted(problems)


_Inode = tuple[int, int]
"""A file's identity on the disk, ``(device, inode)``: every hard link to it shares it."""


def _note_links(info: os.stat_result, shown: str, linked: dict[str, _Inode]) -> None:
    """Put a file in ``linked`` when it has more than one name (a hard link)."""
    if info.st_nlink > 1:
        linked[shown] = (info.st_dev, info.st_ino)


@dataclass
class _Found:
    """One student as found, before naming: where their work came from."""

    source: Path  # the file or folder that is this student
    missions: list[Path]
    folder: Path | None = None
    problem: str = ""
    by_parent: bool = False  # named after its folder (a glob of same-named files)
    name: str = ""
    linked: dict[str, _Inode] = field(default_factory=dict)  # its files with several names


def _folder_student(folder: Path) -> _Found | None:
    """A student who is a folder, or ``None`` when it holds no mission and nothing refused
    (a class's shared ``behaviours/`` folder is no student)."""
    linked: dict[str, _Inode] = {}
    files, problems = _walk(folder, linked=linked)
    sources = [
        (relative, path)
        for relative, path in files
        if not _hidden(relative) and path.suffix.lower() in MISSION_SUFFIXES
    ]
    if _total_bytes(path for _, path in sources) > MAX_SOURCE_BYTES:
        too_much = (
            f"the folder holds more than {MAX_SOURCE_BYTES // 1024 // 1024} MiB of .py and"
            " .yaml files: hand in the mission and its own files only"
        )
        return _Found(folder, [], folder, too_much)
    missions: list[Path] = []
    for relative, path in sources:
        is_mission, problem = _examine(path, _shown_path(relative))
        if problem:
            problems.append(problem)
        elif is_mission:
            missions.append(path)
    if not missions and not problems:
        return None
    return _Found(folder, missions, folder, problems[0] if problems else "", linked=linked)


def _total_bytes(paths: Iterable[Path]) -> int:
    """The bytes reading ``paths`` would cost: a file over the 1 MiB a file may have is
    refused by its size, unread, so it counts for nothing."""
    total = 0
    for path in paths:
        try:
            size = path.lstat().st_size
        except OSError:
            continue  # gone meanwhile: reading it will say so
        total += size if size <= MAX_FILE_BYTES else 0
    return total


def _student_at(path: Path, named: bool = False) -> _Found | None:
    """The student a file or folder is, or ``None`` when it is none (a helper, a picture).

    A link is never followed: one named like a mission, or leading to a folder, is a student
    refused with the reason. A Python file the teacher ``named`` is a mission however it
    makes its ``Mission`` class.
    """
    try:
        mode = path.lstat().st_mode
    except OSError as exc:
        problem = f"{_shown_path(path.name)} cannot be read: {exc.strerror or exc}"
        return _Found(path, [], problem=problem)
    is_mission_name = path.suffix.lower() in MISSION_SUFFIXES
    if (is_mission_name or stat.S_ISDIR(mode)) and _name_problem(path.name, path.name):
        return _Found(path, [], problem=_name_problem(path.name, _shown_path(path.name)))
    if stat.S_ISDIR(mode):
        return _folder_student(path)
    if stat.S_ISLNK(mode) and not is_mission_name:
        if not path.is_dir():
            return None  # a link to something that is not a student: never shown to one
        return _Found(path, [], path, _entry_problem(mode, path.name))
    if not is_mission_name:
        return None
    if not stat.S_ISREG(mode):
        return _Found(path, [], problem=_entry_problem(mode, _shown_path(path.name)))
    is_mission, problem = _examine(path, path.name)
    if problem:
        return _Found(path, [], problem=problem)
    if is_mission or (named and path.suffix.lower() == ".py"):
        return _Found(path, [path])
    return None


def _matched(path: Path, pattern: str) -> _Found | None:
    """The student a glob matched: :func:`_student_at`, unless the glob went through a link.

    ``subs/*/square.yaml`` also matches ``subs/dave/square.yaml`` when ``dave`` is a link to
    a classmate's folder; that student is refused, as in a class folder.
    """
    fixed = next(
        (i for i, part in enumerate(Path(pattern).parts) if glob.has_magic(part)),
        len(path.parts),
    )
    for end in range(max(fixed, 1), len(path.parts)):
        below = Path(*path.parts[: end + 1])
        if below.is_symlink():
            problem = _entry_problem(below.lstat().st_mode, _shown_path(below.name))
            return _Found(path, [], problem=problem)
    return _student_at(path)


def _class_folder(folder: Path) -> tuple[list[_Found], list[Path]]:
    """The students in a class folder (its mission files and its sub-folders), and its
    entries that are no student (hidden ones left out)."""
    try:
        children = sorted(folder.iterdir())
    except OSError as exc:
        raise InputError(f"cannot read the folder {folder}: {exc.strerror or exc}") from None
    found = []
    nobodys = []
    for child in children:
        if not child.name.startswith((".", "__")):
            student = _student_at(child)
            if student is None:
                nobodys.append(child)
            else:
                found.append(student)
    return found, nobodys


_ARCHIVES = (".zip", ".tar", ".gz", ".tgz", ".bz2", ".xz", ".7z", ".rar")


def _holds(entries: list[Path]) -> str:
    """What a folder with no mission holds instead, for the sentence that says so (a student
    who handed in a zip learns why it was not graded), or ``""``."""
    names = _unclaimed(entries, [])
    if not names:
        return ""
    shown = ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")
    archive = any(name.lower().endswith(_ARCHIVES) for name in names)
    return (
        f" (it holds {shown}: a mission is a .yaml file with 'mission:', 'initial:' and"
        " 'states:', or a .py file defining a class based on Mission"
        + (", handed in as it is, not in an archive)" if archive else ")")
    )


def _unclaimed(nobodys: list[Path], found: list[_Found]) -> list[str]:
    """Entries that are no student, less the files a student who is a file owns by name
    (``alice_helpers.py``): by name, cleaned for a terminal, a folder ending in ``/``."""
    stems: dict[Path, set[str]] = {}
    for f in found:
        if f.folder is None:
            stems.setdefault(f.source.parent, set()).add(f.source.stem)
    return [
        clean_name(entry.name) + ("/" if entry.is_dir() and not entry.is_symlink() else "")
        for entry in nobodys
        if _owner(entry.name, stems.get(entry.parent, set())) is None
    ]


def _name(found: list[_Found]) -> list[str]:
    """Give every student a name: unique once cleaned, so no one takes another's place.

    Returns:
        One sentence per group of students whose names look the same once cleaned (``José``
        written composed and decomposed), naming each and how their files are written.
    """
    singles = [f for f in found if f.folder is None]
    stems = Counter(f.source.stem for f in singles)
    in_folder = Counter((f.source.parent, f.source.stem) for f in singles)
    folders_named = Counter(parent.name for parent in {f.source.parent for f in singles})
    for f in found:
        f.name = f.source.name if f.folder is not None else f.source.stem
        if f.folder is not None or stems[f.source.stem] == 1:
            continue
        if in_folder[f.source.parent, f.source.stem] > 1:
            f.name = f.source.name  # ana.py beside ana.yaml: two students, by their whole names
        elif folders_named[f.source.parent.name] == 1:
            f.name, f.by_parent = f.source.parent.name, True  # subs/*/square.yaml
        else:
            f.name = f"{f.source.parent.name}/{f.source.stem}"
    # A name two sources claim (a folder ana/ beside a file ana.yaml) is told apart by the
    # whole file or folder name, then by a number: never merged into one student.
    claims: dict[str, list[_Found]] = {}
    for f in found:
        claims.setdefault(clean_name(f.name), []).append(f)
    for group in claims.values():
        sources = {_identity(f): _whole_name(f) for f in group}
        if len(sources) > 1 and len(set(sources.values())) == len(sources):
            for f in group:
                f.name = sources[_identity(f)]
    # A name already as reports show it keeps it; one that only looks the same (José written
    # decomposed, a trailing space, a ligature or a full-width letter: "ﬁona" beside
    # "fiona") is the one numbered, and named in a warning.
    taken: dict[str, Path] = {}
    alike: dict[str, dict[Path, _Found]] = {}
    for f in sorted(found, key=lambda f: (clean_name(f.name) != f.name, _looks(f.name) != f.name)):
        base = name = clean_name(f.name)
        n = 1
        while taken.get(_looks(name), _identity(f)) != _identity(f):
            n += 1
            name = clean_name(f"{base}-{n}")
        taken[_looks(name)] = _identity(f)
        alike.setdefault(_looks(base), {}).setdefault(_identity(f), f)
        f.name = name
    return [_lookalike(list(group.values())) for group in alike.values() if len(group) > 1]


def _looks(name: str) -> str:
    """What a name looks like in a report: its compatibility form (NFKC), in which a ligature
    (``ﬁ``), a full-width letter (``ａ``) or a superscript reads as the plain letters it is
    drawn as."""
    return unicodedata.normalize("NFKC", name)


def _lookalike(group: list[_Found]) -> str:
    """One sentence naming students whose names look the same, and how their files differ."""
    names = " and ".join(f"'{f.name}'" for f in group)
    sources = " and ".join(_spelled(_identity(f)) for f in group)
    return (
        f"the students {names} have names that look the same: they are {sources}, which"
        " differ only in how their names are written (each character that is not plain"
        " ASCII is shown as its code); each is graded on its own: check which is whose"
    )


def _spelled(path: Path) -> str:
    """``path`` with every character that is not printable ASCII as its code (``\\u00e9``),
    so two names that look the same are told apart on any terminal."""
    text = "".join(c if " " <= c <= "~" else f"\\u{ord(c):04x}" for c in str(path))
    return text if len(text) <= 300 else text[:299] + "…"


def _whole_name(found: _Found) -> str:
    """A student's name told apart from a same-named one: ``ana/`` (folder), ``ana.yaml``."""
    return clean_name(f"{found.source.name}/" if found.folder is not None else found.source.name)


def _identity(found: _Found) -> Path:
    """What makes two found files one student: their folder, when named after it."""
    return found.source.parent if found.by_parent else found.source


def find_submissions(patterns: Sequence[str]) -> FoundSubmissions:
    """The students and their missions, in name order, and what is no student's work.

    Args:
        patterns: Files, globs and class folders.

    Returns:
        The students (a student whose files cannot be graded is still listed, with the
        reason in :attr:`Submission.problem`) and what a class folder holds besides them.

    Raises:
        InputError: A pattern matches no mission (nor any student to refuse).
    """
    found: list[_Found] = []
    nobodys: list[Path] = []
    for pattern in patterns:
        path = Path(pattern)
        if path.is_dir():  # the teacher's class folder: followed if it is a link
            students, left = _class_folder(path)
            nobodys += left
            if not students:
                raise InputError(f"no mission files in the folder {pattern}" + _holds(left))
        elif path.is_file() or path.is_symlink():
            if path.suffix.lower() not in MISSION_SUFFIXES:
                raise InputError(f"{pattern} is not a mission file (.yaml or .py)")
            student = _student_at(path, named=True)
            if student is None:
                raise not_a_mission(path, file_kind(path))
            students = [student]
        else:
            matches = sorted(Path(m) for m in glob.glob(pattern, recursive=True))
            found_here = (_matched(match, pattern) for match in matches[:MAX_ENTRIES])
            students = [s for s in found_here if s is not None]
            if not students:
                raise InputError(f"no mission matches '{pattern}'")
        found += students
    unique: dict[Path, _Found] = {}
    for f in found:
        unique.setdefault(f.source.absolute(), f)
    found = list(unique.values())
    unclaimed = tuple(_unclaimed(nobodys, found))
    lookalikes = tuple(_name(found))
    return FoundSubmissions(_submissions(found), unclaimed, lookalikes)


def _submissions(found: list[_Found]) -> list[Submission]:
    by_name: dict[str, list[_Found]] = {}
    for f in found:
        by_name.setdefault(f.name, []).append(f)
    owners = _Owners(found)
    result = []
    for name, parts in sorted(by_name.items(), key=lambda item: item[0].lower()):
        missions = tuple(dict.fromkeys(str(m) for part in parts for m in part.missions))
        problem = next((p.problem for p in parts if p.problem), "")
        first = parts[0]
        if first.folder is not None:
            folder = str(first.folder)
            result.append(Submission(name, missions, folder, problem, folder))
            continue
        root = first.source.parent
        own = owners.files_of(root, {Path(m).stem for m in missions})
        for path in (*missions, *own):
            with contextlib.suppress(OSError):  # gone meanwhile: reading it will say so
                _note_links(os.stat(path, follow_symlinks=False), Path(path).name, first.linked)
        result.append(Submission(name, missions, None, problem, str(root), own))
    return _refuse_shared_files(result, {name: parts[0].linked for name, parts in by_name.items()})


def _refuse_shared_files(
    submissions: list[Submission], linked: dict[str, dict[str, _Inode]]
) -> list[Submission]:
    """Refuse every student who shares a file (one file on the disk, two names: a hard link)
    with another student, naming the other.

    A hard link is not a copy: the two names are one file, so the student who made it reads,
    in their graded run, whatever the other student hands in, and the file is no more one's
    than the other's. Nothing on the disk says which name came first, so both students are
    refused with the same sentence, and the teacher, who can ask, decides. Two files that only
    hold the same text are two files, and stay allowed: two students may write the same
    thing. A student's own file under two names of their own is theirs.
    """
    holders: dict[_Inode, dict[str, str]] = {}
    for name, files in linked.items():
        for shown, inode in sorted(files.items()):
            holders.setdefault(inode, {}).setdefault(name, shown)
    shared: dict[str, str] = {}
    for names in holders.values():
        if len(names) < 2:
            continue
        for name, shown in names.items():
            other, other_shown = next((n, f) for n, f in names.items() if n != name)
            shared.setdefault(
                name,
                f"{_shown_path(shown)} is the same file as {other}'s {_shown_path(other_shown)}"
                " (a hard link, not a copy: each sees what the other hands in): one file"
                " cannot be the work of two students, so neither is graded; hand in a copy of"
                " your own",
            )
    return [
        replace(s, problem=shared[s.student]) if s.student in shared and not s.problem else s
        for s in submissions
    ]


# ------------------------------------------------------------------- what a run may read


class _Owners:
    """Who owns each file in a folder shared by students who are files.

    A file is a student's when its name is their mission's name, or starts with it followed
    by ``_``, ``-`` or ``.`` (``alice_helpers.py``); when several students' names fit, the
    longest wins. Only mission and behaviour files (:data:`MISSION_SUFFIXES`) are shown to a
    run: a student named ``grades``, ``results`` or ``index`` must not see an earlier
    ``grades.csv``, ``results.jsonl`` or class page by their name. Students' folders, hidden
    folders, links and anything not an ordinary file are no one's. Each shared folder is
    walked once.
    """

    def __init__(self, found: list[_Found]) -> None:
        self._stems: dict[Path, set[str]] = {}
        for f in found:
            if f.folder is None:
                self._stems.setdefault(f.source.parent, set()).add(f.source.stem)
        self._skip = frozenset(f.source for f in found if f.folder is not None)
        self._missions = {m.resolve() for f in found for m in f.missions}
        self._files: dict[Path, list[tuple[str, Path]]] = {}

    def files_of(self, root: Path, stems: set[str]) -> tuple[str, ...]:
        """The files in ``root`` (and its sub-folders) owned by the student with ``stems``."""
        if root not in self._files:
            self._files[root] = _walk(root, self._skip, shared=True)[0]
        return tuple(
            str(path)
            for relative, path in self._files[root]
            if not _hidden(relative)
            and path.suffix.lower() in MISSION_SUFFIXES
            and path.resolve() not in self._missions
            and _owner(path.name, self._stems.get(root, set())) in stems
        )


def _owner(file_name: str, stems: Iterable[str]) -> str | None:
    best: str | None = None
    for stem in stems:
        fits = file_name == stem or (
            file_name.startswith(stem) and file_name[len(stem) : len(stem) + 1] in ("_", "-", ".")
        )
        if fits and (best is None or len(stem) > len(best)):
            best = stem
    return best


def named_files(start: Path, candidates: Sequence[tuple[str, Path]]) -> tuple[Path, ...]:
    """``start`` and the ``candidates`` its text names, and those theirs, in turn.

    A candidate is ``(path relative to the start's folder, path)``; it is named by its
    relative path, its file name, its module name (``behaviours.zigzag``) or, for a ``.py``
    file, its stem (``import helpers``). Each file's first
    :data:`~roboscript.inputs.limits.MAX_FILE_BYTES` are read, never more.
    """
    seen = [start.resolve()]
    queue = [start.resolve()]
    resolved_candidates = [(relative, path.resolve()) for relative, path in candidates]
    while queue:
        words = _words(queue.pop())
        for relative, resolved in resolved_candidates:
            if resolved in seen:
                continue
            names = {relative, resolved.name, relative.rsplit(".", 1)[0].replace("/", ".")}
            if relative.endswith(".py"):
                names.add(Path(relative).stem)
            if names & words:
                seen.append(resolved)
                queue.append(resolved)
    return tuple(seen)


def _words(path: Path) -> set[str]:
    try:
        flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
        fd = os.open(path, flags)
        with os.fdopen(fd, "rb") as file:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                return set()
            text = file.read(MAX_FILE_BYTES).decode("utf-8", errors="replace")
    except OSError:
        return set()
    words = set(re.findall(r"[\w.\-/]+", text))
    return words | {part for word in words for part in word.split("/")}


def visible_files(
    submission: Submission, mission: str, others: frozenset[Path] = frozenset()
) -> tuple[Path, ...]:
    """What ``submission``'s graded run of ``mission`` may read (see :class:`Submission`).

    ``others`` (other students' files and folders, the test specs) are never among them.
    """
    if submission.folder is not None:
        return (Path(submission.folder).resolve(),)
    folder = Path(mission).resolve().parent
    candidates = []
    for own in submission.own:
        path = Path(own).resolve()
        if path in others or any(parent in others for parent in path.parents):
            continue
        try:
            candidates.append((path.relative_to(folder).as_posix(), path))
        except ValueError:
            continue
    return named_files(Path(mission), candidates)


# ------------------------------------------------------------- files changed while graded

FilesNow = dict[str, tuple[int, int, _Inode]]
"""A student's files as they are on the disk: by path inside the submission, each file's size,
modification time (ns) and identity on the disk (device, inode)."""


def files_now(submission: Submission) -> FilesNow:
    """What :func:`changed_file` compares: every file a run of the student may read, as it is
    on the disk now (their folder's files, or their mission and own files beside it).
    Only stats are read, never a file's bytes; a file that cannot be read is left out."""
    if submission.folder is not None:
        paths = [path for _, path in _walk(Path(submission.folder))[0]]
    else:
        paths = [Path(p) for p in (*submission.missions, *submission.own)]
    now: FilesNow = {}
    for path in paths:
        try:
            info = path.stat(follow_symlinks=False)
        except OSError:
            continue
        now[submission.shown(path)] = (info.st_size, info.st_mtime_ns, (info.st_dev, info.st_ino))
    return now


def changed_file(submission: Submission, before: FilesNow) -> str:
    """The first of the student's files (by its path inside the submission) that was added,
    removed, rewritten or replaced since ``before`` (:func:`files_now`), or ``""``."""
    now = files_now(submission)
    changed = sorted(
        name for name in before.keys() | now.keys() if before.get(name) != now.get(name)
    )
    return _shown_path(changed[0]) if changed else ""


def teachers_file_held(before: FilesNow, teachers: dict[_Inode, str]) -> str:
    """Why a submission that holds one of the teacher's files (``teachers``: by identity on
    the disk, the name to show) under another name, a hard link, is refused; or ``""``.

    A test spec linked into a student's folder would let their run read the hidden runs'
    seeds and starts; a copy would have to be made by someone who can read the spec already.
    """
    for name, (_size, _time, inode) in sorted(before.items()):
        if inode in teachers:
            return (
                f"{_shown_path(name)} is the same file as the test {teachers[inode]} (a hard link,"
                " not a copy): a submission holds its own files, never the teacher's"
            )
    return ""
