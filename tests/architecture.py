"""Every import the package makes, resolved: the facts ``tests/test_architecture.py`` judges.

A :class:`Tree` is the package's source, module by module (read from disk, or a copy with a
line planted for the architecture test's test of itself). :func:`imports_of` finds every way
one module reaches another:

* ``import roboscript.x.y`` and ``from roboscript.x import name``;
* relative imports (``from ..drivers import base``);
* ``from pkg import module``: the module, not the package;
* names the root package loads lazily (``from roboscript import run`` is ``roboscript.api``);
* attributes of an imported package (``import roboscript`` then ``roboscript.api.main()``);
* ``importlib.import_module("...")`` and ``__import__("...")`` with a constant name (a name
  computed at run time cannot be resolved: each such call is on an allow-list, with why).

Each import says whether it happens at run time (not under ``if TYPE_CHECKING:``) and whether
it sits inside a function.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "roboscript"
ROOT = "roboscript"


@dataclass(frozen=True)
class Import:
    """One import of one module.

    Attributes:
        source: The importing module (``roboscript.actions.motion``).
        target: The module imported (``roboscript.drivers.base``), resolved to a module of
            the package; for anything else, its dotted name (``time``); ``?`` for a
            dynamic import whose name is computed at run time.
        line: Where, in the importing module.
        form: ``import``, ``from``, ``relative``, ``lazy`` (a root package attribute),
            ``attribute`` (``roboscript.api.main``), ``import_module`` or ``__import__``.
        runtime: False under ``if TYPE_CHECKING:`` (annotations only).
        in_function: True inside a function body.
    """

    source: str
    target: str
    line: int
    form: str
    runtime: bool
    in_function: bool

    @property
    def own(self) -> bool:
        """True for a module of the package."""
        return self.target == ROOT or self.target.startswith(ROOT + ".")

    @property
    def top(self) -> str:
        """The target's top-level name (``time``, ``serial``, ``roboscript``)."""
        return self.target.split(".")[0]

    def __str__(self) -> str:
        where = " in a function" if self.in_function else ""
        return f"{self.source}:{self.line} imports {self.target} ({self.form}{where})"


@dataclass
class Tree:
    """The package's modules: dotted name -> (path, source text).

    Attributes:
        sources: Source text by module name.
        paths: The file of each module (``__init__.py`` for a package).
    """

    sources: dict[str, str]
    paths: dict[str, Path]
    _imports: dict[str, list[Import]] = field(default_factory=dict, repr=False)
    _trees: dict[str, ast.Module] = field(default_factory=dict, repr=False)

    @classmethod
    def read(cls, package: Path = PACKAGE) -> Tree:
        """The package on disk, leaving out the MicroPython that runs on a SPIKE hub."""
        sources: dict[str, str] = {}
        paths: dict[str, Path] = {}
        for path in sorted(package.rglob("*.py")):
            parts = path.relative_to(package.parent).with_suffix("").parts
            if "agent" in parts:
                continue
            name = ".".join(parts).removesuffix(".__init__")
            sources[name] = path.read_text(encoding="utf-8")
            paths[name] = path
        return cls(sources, paths)

    def planted(self, module: str, code: str) -> Tree:
        """A copy in which ``module`` ends with ``code`` (a new module if it has none)."""
        sources = dict(self.sources)
        paths = dict(self.paths)
        if module not in paths:
            paths[module] = PACKAGE.parent.joinpath(*module.split(".")).with_suffix(".py")
        sources[module] = sources.get(module, '"""A planted module."""\n') + "\n" + code
        copy = Tree(sources, paths)
        if module != ROOT:  # what the other modules import is as before
            copy._trees = {name: t for name, t in self._trees.items() if name != module}
            copy._imports = {name: i for name, i in self._imports.items() if name != module}
        return copy

    def is_package(self, module: str) -> bool:
        """True for a package's ``__init__.py``."""
        return self.paths[module].name == "__init__.py"

    def tree(self, module: str) -> ast.Module:
        """The module's syntax tree (parsed once)."""
        if module not in self._trees:
            self._trees[module] = ast.parse(self.sources[module], filename=str(self.paths[module]))
        return self._trees[module]

    def resolve(self, dotted: str) -> str:
        """The package's module ``dotted`` names, or the longest that contains it."""
        name = dotted
        while name and name not in self.sources:
            name = name.rpartition(".")[0]
        return name or dotted

    def lazy_attributes(self) -> Mapping[str, str]:
        """The root package's lazy attributes: name -> the module that holds it."""
        table: dict[str, str] = {}
        for node in ast.walk(self.tree(ROOT)):
            if (
                isinstance(node, ast.Assign)
                and isinstance(node.targets[0], ast.Name)
                and node.targets[0].id == "_LAZY"
                and isinstance(node.value, ast.Dict)
            ):
                for key, value in zip(node.value.keys, node.value.values, strict=True):
                    if isinstance(key, ast.Constant) and isinstance(value, ast.Constant):
                        table[str(key.value)] = str(value.value)
        return table

    def imports(self, module: str) -> list[Import]:
        """Every import ``module`` makes (cached)."""
        if module not in self._imports:
            self._imports[module] = list(_Finder(self, module).run())
        return self._imports[module]

    def all_imports(self) -> Iterator[Import]:
        """Every import of every module."""
        for module in self.sources:
            yield from self.imports(module)


def is_type_checking(test: ast.expr) -> bool:
    """True for ``if TYPE_CHECKING:`` and ``if typing.TYPE_CHECKING:``."""
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


_FUNCTIONS = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)


class _Finder:
    """Walks one module, keeping track of ``TYPE_CHECKING`` blocks and function bodies."""

    def __init__(self, tree: Tree, module: str) -> None:
        self.tree = tree
        self.module = module
        self.package = module if tree.is_package(module) else module.rpartition(".")[0]
        self.found: list[Import] = []
        self.bound: dict[str, str] = {}  # a local name -> the package module it is

    def run(self) -> Iterator[Import]:
        self.visit(self.tree.tree(self.module), runtime=True, in_function=False)
        return iter(self.found)

    def add(self, target: str, node: ast.AST, form: str, runtime: bool, in_function: bool) -> None:
        own = target == ROOT or target.startswith(ROOT + ".")
        resolved = self.tree.resolve(target) if own else target
        if resolved == self.module:
            return
        line = getattr(node, "lineno", 0)
        self.found.append(Import(self.module, resolved, line, form, runtime, in_function))

    def absolute(self, level: int, module: str | None) -> str:
        parts = self.package.split(".")
        base = parts[: len(parts) - level + 1]
        return ".".join([*base, *([module] if module else [])])

    def from_import(self, node: ast.ImportFrom, runtime: bool, in_function: bool) -> None:
        base = self.absolute(node.level, node.module) if node.level else (node.module or "")
        form = "relative" if node.level else "from"
        if not (base == ROOT or base.startswith(ROOT + ".")):
            self.add(base, node, form, runtime, in_function)
            return
        lazy = self.tree.lazy_attributes() if base == ROOT else {}
        for alias in node.names:
            sub = f"{base}.{alias.name}"
            if sub in self.tree.sources:  # `from pkg import module` imports the module
                self.add(sub, node, form, runtime, in_function)
                self.bound[alias.asname or alias.name] = sub
            elif base == ROOT and alias.name != "__version__":
                # the root package's attributes load lazily: missions' names from
                # roboscript.actions unless the table names another module
                self.add(
                    lazy.get(alias.name, "roboscript.actions"), node, "lazy", runtime, in_function
                )
            else:
                self.add(base, node, form, runtime, in_function)

    def plain_import(self, node: ast.Import, runtime: bool, in_function: bool) -> None:
        for alias in node.names:
            self.add(alias.name, node, "import", runtime, in_function)
            if alias.name.split(".")[0] == ROOT:
                if alias.asname:
                    self.bound[alias.asname] = alias.name
                else:
                    self.bound[ROOT] = ROOT

    def dynamic(self, node: ast.Call, runtime: bool, in_function: bool) -> None:
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
        if name not in ("import_module", "__import__"):
            return
        if isinstance(func, ast.Attribute) and not (
            isinstance(func.value, ast.Name) and func.value.id == "importlib"
        ):
            return
        first = node.args[0] if node.args else None
        if isinstance(first, ast.Constant) and isinstance(first.value, str):
            target = first.value
            if target.startswith("."):
                level = len(target) - len(target.lstrip("."))
                target = self.absolute(level, target.lstrip(".") or None)
            self.add(target, node, name, runtime, in_function)
        else:
            self.add("?", node, name, runtime, in_function)

    def attribute(self, node: ast.Attribute, runtime: bool, in_function: bool) -> None:
        chain: list[str] = []
        current: ast.expr = node
        while isinstance(current, ast.Attribute):
            chain.append(current.attr)
            current = current.value
        if not isinstance(current, ast.Name) or current.id not in self.bound:
            return
        dotted = ".".join([self.bound[current.id], *reversed(chain)])
        target = self.tree.resolve(dotted)
        if target == ROOT:
            first = dotted.split(".")[1]
            if first in self.tree.lazy_attributes():
                target = self.tree.lazy_attributes()[first]
            elif first[:1].isupper() or first == "REQUIRED":
                target = "roboscript.actions"
            else:
                return
        if target != self.bound[current.id]:
            self.add(target, node, "attribute", runtime, in_function)

    def visit(self, node: ast.AST, runtime: bool, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and is_type_checking(child.test):
                for inner in child.body:
                    self.visit_one(inner, False, in_function)
                for inner in child.orelse:
                    self.visit_one(inner, runtime, in_function)
                continue
            self.visit_one(child, runtime, in_function)

    def visit_one(self, node: ast.AST, runtime: bool, in_function: bool) -> None:
        if isinstance(node, ast.Import):
            self.plain_import(node, runtime, in_function)
        elif isinstance(node, ast.ImportFrom):
            self.from_import(node, runtime, in_function)
        elif isinstance(node, ast.Call):
            self.dynamic(node, runtime, in_function)
        elif isinstance(node, ast.Attribute):
            self.attribute(node, runtime, in_function)
            base: ast.expr = node
            while isinstance(base, ast.Attribute):  # the inner attributes are the same chain
                base = base.value
            self.visit_one(base, runtime, in_function)
            return
        self.visit(node, runtime, in_function or isinstance(node, _FUNCTIONS))
