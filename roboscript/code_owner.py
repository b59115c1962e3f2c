"""Whose code is this: roboscript's, a library's, or a student's.

Every question roboscript asks about a piece of running code is answered here, once:

* the watchdog watches a student's code line by line, and only theirs;
* an error is told in the student's terms at the student's innermost line, and a built-in
  action's own check (raised in roboscript) is told differently from a student's own
  ``__init__`` raising;
* a student's action class has its ``update`` checked for what it returns, roboscript's do not;
* a crashed graded run names the student's line of its traceback.

The rule, by the file the code was read from (a code object's ``co_filename``), resolved
(symbolic links followed, so a symlinked or editable install is judged where its files really
are):

* **roboscript's**: a file inside roboscript's own folder, whoever put it there;
* **a library's**: Python's and installed packages' folders (standard library, site-packages,
  the scripts folder of ``pip``'s console commands), the folder each of roboscript's runtime
  packages was imported from (the browser page unpacks them outside Python's paths), and code read
  from no file of this computer: a name in brackets (``<frozen importlib._bootstrap>``,
  ``<string>`` from ``exec``, ``<stdin>``), or a relative name that names no file in the working
  folder (bytecode compiled with its name in a zip, as the browser page's standard library);
* **a student's**: anything else (a student's, a teacher's: "not ours"), a folder named like
  roboscript's plus a suffix, or named ``roboscript`` somewhere else, included.

A class is roboscript's when its module is, by the same rule on the module's file; a module
with no file (``__main__`` in a notebook, a class made by ``exec``) is roboscript's only by its
name (``roboscript`` or ``roboscript.*``).

Standard library only, and importing nothing of roboscript: :mod:`roboscript.actions.base`
and :mod:`roboscript.mission.student_code` both use it, and the second imports the first. In a
graded run's jail the package and Python's folders are seen at the same paths as outside
(:mod:`roboscript.grading.sandbox` binds them where they are), so the answer is the same there.
"""

from __future__ import annotations

import functools
import os
import sys
import sysconfig
from typing import Final, Literal

__all__ = [
    "LIBRARY",
    "PACKAGE_DIR",
    "ROBOSCRIPT",
    "RUNTIME_PACKAGES",
    "STUDENT",
    "Owner",
    "is_roboscript_module",
    "is_student_class",
    "is_student_file",
    "owner_of_file",
    "raised_by_roboscript",
]

Owner = Literal["roboscript", "library", "student"]
"""Whose code: roboscript's, Python's or an installed package's, or a student's (anyone
else's, a teacher's included)."""

ROBOSCRIPT: Final = "roboscript"
LIBRARY: Final = "library"
STUDENT: Final = "student"

PACKAGE_DIR: Final = os.path.join(os.path.dirname(os.path.realpath(__file__)), "")
"""roboscript's own folder, symbolic links followed, ending in a separator (so that a folder
named like it plus a suffix, ``roboscript_missions``, is not inside it)."""

RUNTIME_PACKAGES: Final = ("yaml", "transitions", "simple_pid", "serial")
"""The installed packages roboscript runs on (a student's code calls into them, never the
reverse)."""

_SYSCONFIG_KEYS = ("stdlib", "platstdlib", "purelib", "platlib", "scripts")


def _library_dirs() -> tuple[str, ...]:
    """The folders whose code is Python's or an installed package's, each ending in a
    separator: Python's install paths, and the folder each of :data:`RUNTIME_PACKAGES` was
    imported from.

    Only an imported package counts, and only a package (a folder), never a module found on
    the path: a student's own ``serial.py`` beside their mission, first on the path, must not
    make their folder a library's.
    """
    files = []
    for name in RUNTIME_PACKAGES:
        module = sys.modules.get(name)
        file = getattr(module, "__file__", None)
        if isinstance(file, str) and hasattr(module, "__path__"):
            files.append(file)
    return _folders_with(tuple(files))


@functools.cache
def _folders_with(package_files: tuple[str, ...]) -> tuple[str, ...]:
    paths = sysconfig.get_paths()
    folders = {os.path.realpath(path) for key in _SYSCONFIG_KEYS if (path := paths.get(key))}
    for file in package_files:  # .../site-packages/yaml/__init__.py -> .../site-packages
        folders.add(os.path.dirname(os.path.dirname(os.path.realpath(file))))
    return tuple(sorted(os.path.join(folder, "") for folder in folders))


@functools.lru_cache(maxsize=4096)
def _owner_of_path(path: str, library_dirs: tuple[str, ...]) -> Owner:
    """The owner of an absolute ``path`` (cached: the watchdog asks for each function called)."""
    real = os.path.realpath(path)
    if real.startswith(PACKAGE_DIR):
        return ROBOSCRIPT
    if real.startswith(library_dirs):
        return LIBRARY
    return STUDENT


def owner_of_file(filename: str) -> Owner:
    """Whose code was read from ``filename`` (a code object's ``co_filename``, a traceback's
    or a module's file), by the rule of this module's docstring."""
    if filename.startswith("<"):
        return LIBRARY  # <frozen importlib._bootstrap>, <string>, <stdin>
    if os.path.isabs(filename):
        return _owner_of_path(filename, _library_dirs())
    try:
        here = os.path.join(os.getcwd(), filename)
    except OSError:  # the working folder was removed: no relative name names a file
        return LIBRARY
    if not os.path.isfile(here):
        # bytecode compiled under a name in its zip (the page's standard library: "json/
        # decoder.py"), a frozen application's module: nothing a student could open
        return LIBRARY
    return _owner_of_path(here, _library_dirs())


def is_student_file(filename: str) -> bool:
    """True if code from ``filename`` (a code object's ``co_filename``) is a student's or a
    teacher's: neither roboscript's, nor Python's, nor an installed package's."""
    return owner_of_file(filename) == STUDENT


def is_roboscript_module(name: str) -> bool:
    """True if a module named ``name`` is named as one of roboscript's (``roboscript``,
    ``roboscript.actions``; not ``roboscript_helpers``)."""
    return name == "roboscript" or name.startswith("roboscript.")


def is_student_class(cls: type) -> bool:
    """True if ``cls`` was written outside roboscript (by a student or a teacher): its module's
    file is not roboscript's or, for a module with no file, its module is not named as one of
    roboscript's."""
    module = getattr(cls, "__module__", None)
    name = module if isinstance(module, str) else ""
    file = getattr(sys.modules.get(name), "__file__", None)
    if isinstance(file, str) and file:
        return owner_of_file(file) != ROBOSCRIPT
    return not is_roboscript_module(name)


def raised_by_roboscript(exc: BaseException) -> bool:
    """True if ``exc`` was raised by roboscript's own code: the innermost frame of its
    traceback is roboscript's (a built-in action's checks), not a student's nor a library's."""
    tb = exc.__traceback__
    if tb is None:
        return False
    while tb.tb_next is not None:
        tb = tb.tb_next
    return owner_of_file(tb.tb_frame.f_code.co_filename) == ROBOSCRIPT
