"""Wheels of roboscript and every dependency, made offline from what is installed here.

An autograder image installs roboscript with ``pip install --no-index --find-links wheels/``:
nothing comes from a package index (roboscript is not on one, and grading containers often
have no network). The wheels are made from the installed distributions themselves:

* each file the distribution installed (its ``RECORD``), without byte-code and scripts (pip
  makes both again), or, for an editable install (a source checkout), the files of its
  package folder;
* its metadata (``METADATA``, entry points, licences), with a new ``WHEEL`` (tag
  ``py3-none-any``) and ``RECORD``.

So every wheel is pure Python and installs on any Python 3 the distribution supports, such
as Gradescope's Ubuntu image with another Python than the teacher's. A distribution with
compiled code is refused, except where the compiled part only speeds up a pure-Python one
(:data:`OPTIONAL_COMPILED`: PyYAML's libyaml binding), which is left out; a directory of
ready wheels (``--wheels DIR``) is used instead where it has one.

The wheels are reproducible: the same installed files make the same bytes (entries sorted,
every time stamp 1980-01-01, fixed permissions).
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
import re
import zipfile
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from importlib import metadata
from importlib.util import find_spec
from pathlib import Path

from roboscript.errors import RoboscriptError

__all__ = [
    "OPTIONAL_COMPILED",
    "Wheel",
    "canonical_name",
    "dependency_wheels",
    "reproducible_zip",
]

OPTIONAL_COMPILED = frozenset({"pyyaml"})
"""Distributions whose compiled modules only speed up pure-Python code (left out of the wheel):
PyYAML falls back to its pure-Python parser when its libyaml binding is missing."""

_COMPILED_SUFFIXES = (".so", ".pyd", ".dylib", ".dll")
_FIXED_TIME = (1980, 1, 1, 0, 0, 0)  # the earliest time a zip can hold
_REGENERATED = {"RECORD", "WHEEL", "INSTALLER", "REQUESTED", "direct_url.json"}


def canonical_name(name: str) -> str:
    """A distribution's name as package indexes compare it (``PyYAML`` -> ``pyyaml``)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def reproducible_zip(files: Mapping[str, tuple[bytes, bool]]) -> bytes:
    """A zip of ``{name: (content, executable)}``: entries sorted, fixed time and modes."""
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as archive:
        for name in sorted(files):
            content, executable = files[name]
            info = zipfile.ZipInfo(name, date_time=_FIXED_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.create_system = 3  # Unix: the modes below are read
            info.external_attr = (0o100755 if executable else 0o100644) << 16
            archive.writestr(info, content)
    return out.getvalue()


@dataclass(frozen=True)
class Wheel:
    """A wheel file: its name and bytes, and what was left out of it (for the teacher)."""

    filename: str
    content: bytes
    note: str = ""


def _record_hash(content: bytes) -> str:
    digest = base64.urlsafe_b64encode(hashlib.sha256(content).digest()).rstrip(b"=")
    return f"sha256={digest.decode('ascii')}"


def _is_editable(dist: metadata.Distribution) -> bool:
    """Installed from a source folder (``pip install -e``, or a bare ``.egg-info``): the
    installed files are not listed, the package folder is the source."""
    if dist.read_text("RECORD") is None:
        return True
    text = dist.read_text("direct_url.json")
    if not text:
        return False
    try:
        return bool(json.loads(text).get("dir_info", {}).get("editable"))
    except ValueError:
        return False


def _package_files(dist: metadata.Distribution) -> dict[str, Path]:
    """An editable install's files: everything in its package folders but byte-code."""
    tops = (dist.read_text("top_level.txt") or "").split() or [
        canonical_name(dist.metadata["Name"]).replace("-", "_")
    ]
    found: dict[str, Path] = {}
    for top in tops:
        spec = find_spec(top)
        if spec is None or not spec.submodule_search_locations:
            continue
        folder = Path(next(iter(spec.submodule_search_locations)))
        for path in sorted(folder.rglob("*")):
            relative = path.relative_to(folder.parent)
            if path.is_file() and "__pycache__" not in relative.parts and path.suffix != ".pyc":
                found[relative.as_posix()] = path
    return found


def _installed_files(dist: metadata.Distribution, name: str) -> tuple[dict[str, Path], str]:
    """The files to pack, by their name in the wheel, and a note on what was left out."""
    if _is_editable(dist):
        return _package_files(dist), ""
    files: dict[str, Path] = {}
    dropped = []
    for entry in dist.files or ():
        relative = entry.as_posix()
        if relative.startswith("..") or "__pycache__" in entry.parts or relative.endswith(".pyc"):
            continue  # scripts (pip makes them again from the entry points) and byte-code
        if entry.parts[0].endswith(".dist-info"):
            continue  # the metadata is written below
        if relative.endswith(_COMPILED_SUFFIXES) or ".cpython-" in relative:
            if canonical_name(name) not in OPTIONAL_COMPILED:
                raise RoboscriptError(
                    f"{name} has compiled code ({relative}), which a wheel made here would not"
                    f" run elsewhere: give --wheels DIR with a {name} wheel for the platform"
                )
            dropped.append(entry.name)
            continue
        path = Path(str(dist.locate_file(entry)))
        if path.is_file():
            files[relative] = path
    note = f"left out its compiled speed-up ({', '.join(dropped)})" if dropped else ""
    return files, note


def _wheel_from_installed(dist: metadata.Distribution) -> Wheel:
    name = dist.metadata["Name"]
    version = dist.version
    escaped = re.sub(r"[-_.]+", "_", name)
    info_dir = f"{escaped}-{version}.dist-info"
    sources, note = _installed_files(dist, name)
    contents = {relative: path.read_bytes() for relative, path in sources.items()}
    for entry in dist.files or ():
        if entry.parts[0].endswith(".dist-info") and entry.name not in _REGENERATED:
            text = Path(str(dist.locate_file(entry)))
            if text.is_file():
                contents[f"{info_dir}/{'/'.join(entry.parts[1:])}"] = text.read_bytes()
    for required in ("METADATA", "entry_points.txt", "top_level.txt"):
        key = f"{info_dir}/{required}"
        written = dist.read_text(required)
        if required == "METADATA" and written is None:
            written = dist.read_text("PKG-INFO")  # an .egg-info's name for the same fields
        if key not in contents and written is not None:
            contents[key] = written.encode("utf-8")
    contents[f"{info_dir}/WHEEL"] = (
        b"Wheel-Version: 1.0\nGenerator: roboscript autograder (from the installed files)\n"
        b"Root-Is-Purelib: true\nTag: py3-none-any\n"
    )
    record = [f"{n},{_record_hash(c)},{len(c)}" for n, c in sorted(contents.items())]
    record.append(f"{info_dir}/RECORD,,")
    contents[f"{info_dir}/RECORD"] = ("\n".join(record) + "\n").encode()
    packed = reproducible_zip({n: (c, False) for n, c in contents.items()})
    return Wheel(f"{escaped}-{version}-py3-none-any.whl", packed, note)


def _requirement_names(dist: metadata.Distribution) -> Iterable[str]:
    """The distributions ``dist`` needs, extras left out (``PyYAML>=6,<7`` -> ``PyYAML``)."""
    for requirement in dist.requires or ():
        head, _, marker = requirement.partition(";")
        if "extra" in marker:
            continue
        match = re.match(r"\s*([A-Za-z0-9][A-Za-z0-9._-]*)", head)
        if match:
            yield match.group(1)


def _installed(name: str) -> metadata.Distribution | None:
    """The installed distribution ``name``: the one pip installed (with a ``RECORD``) where a
    source folder's ``.egg-info`` on the path shows the same name first."""
    found = list(metadata.distributions(name=name))
    recorded = [dist for dist in found if dist.read_text("RECORD") is not None]
    return (recorded or found)[0] if found else None


def _ready_wheel(folder: Path, name: str) -> Wheel | None:
    """A wheel of ``name`` in ``folder`` (``--wheels DIR``), if there is one."""
    for path in sorted(folder.glob("*.whl")):
        if canonical_name(path.name.split("-")[0]) == canonical_name(name):
            return Wheel(path.name, path.read_bytes(), "taken from --wheels")
    return None


def dependency_wheels(root: str = "roboscript", ready: Path | None = None) -> list[Wheel]:
    """Wheels of ``root`` and everything it needs (not its extras), in name order.

    Raises:
        RoboscriptError: A distribution needed is not installed here, or has compiled code
            and no wheel in ``ready``.
    """
    wheels: dict[str, Wheel] = {}
    todo = [root]
    while todo:
        name = todo.pop()
        key = canonical_name(name)
        if key in wheels:
            continue
        dist = _installed(name)
        if dist is None:
            raise RoboscriptError(
                f"{root} needs {name}, which is not installed here: install it, or give"
                " --wheels DIR with its wheel"
            )
        found = _ready_wheel(ready, name) if ready is not None else None
        wheels[key] = found or _wheel_from_installed(dist)
        todo.extend(_requirement_names(dist))
    return [wheels[key] for key in sorted(wheels)]
