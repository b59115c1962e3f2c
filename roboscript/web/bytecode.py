"""Python source compiled to bytecode ahead of time, for the browser app.

Python in WebAssembly is slow to compile source: a page that imported the standard library and
roboscript from ``.py`` files spent most of its start compiling them, every time it opened.
``roboscript web build`` therefore compiles them once, with the very interpreter the page runs
(bytecode belongs to one Python version: node runs Pyodide's CPython on ``compile.mjs``, which
calls :func:`compile_zip`), into hash-based ``.pyc`` files that are never checked against their
source, since nothing in the page can change the source.

Standard library only: this module also runs inside Pyodide.
"""

from __future__ import annotations

import importlib.util
import io
import sys
import zipfile
from importlib._bootstrap_external import _code_to_hash_pyc  # type: ignore[attr-defined]

__all__ = ["compile_zip"]


def _put(archive: zipfile.ZipFile, name: str, data: bytes) -> None:
    info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))  # the same bytes every build
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = 0o644 << 16
    archive.writestr(info, data)


def _cached_name(source: str) -> str:
    """Where the import system looks for a source file's bytecode (``__pycache__``)."""
    folder, _, name = source.rpartition("/")
    tag = sys.implementation.cache_tag
    return f"{folder + '/' if folder else ''}__pycache__/{name[:-3]}.{tag}.pyc"


def compile_zip(data: bytes, *, beside_source: bool) -> bytes:
    """A zip of Python files with each ``.py`` compiled by this interpreter.

    Args:
        data: The zip.
        beside_source: True for packages unpacked onto a disk (the source stays, its bytecode
            goes in ``__pycache__``); False for a zip imported as it is (zipimport): each
            ``.py`` becomes a ``.pyc`` in its place, and the source is left out.

    Returns:
        The new zip; a file that does not compile here keeps its source, so the page reports
        it exactly as it would have.
    """
    buffer = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as source, zipfile.ZipFile(buffer, "w") as out:
        for info in source.infolist():
            if info.is_dir():
                continue
            text = source.read(info)
            if not info.filename.endswith(".py"):
                _put(out, info.filename, text)
                continue
            try:
                code = compile(text, info.filename, "exec", dont_inherit=True)
            except (SyntaxError, ValueError):
                _put(out, info.filename, text)
                continue
            pyc = bytes(_code_to_hash_pyc(code, importlib.util.source_hash(text), checked=False))
            if beside_source:
                _put(out, info.filename, text)
                _put(out, _cached_name(info.filename), pyc)
            else:
                _put(out, info.filename + "c", pyc)
    return buffer.getvalue()
