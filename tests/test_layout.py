"""The tree's rules: modules under 400 lines (the compiled core's C++ files too), functions under
80, no numba (the compiled core is the one fast path), no private name used outside its module,
no public core function returning a tuple of 4 or more.

Today's offenders are allow-listed with the step of issue 25 that takes each under; the lists
only shrink (a listed entry that complies fails the test, so that it is taken off).
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "virtual_actuators"
MAX_MODULE_LINES = 400  # a module has fewer lines
MAX_FUNCTION_LINES = 80  # a function (def line to its last line) has fewer lines

#: Modules of 400 lines or more, path under virtual_actuators/ -> why it is still that long
LONG_MODULES: dict[str, str] = {}

#: Functions of 80 lines or more, "path::qualified name" -> why
LONG_FUNCTIONS: dict[str, str] = {}


def _functions(tree: ast.AST, prefix: str = ""):
    """``(qualified name, node)`` of every function, methods and nested ones included."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield prefix + node.name, node
            yield from _functions(node, f"{prefix}{node.name}.")
        elif isinstance(node, ast.ClassDef):
            yield from _functions(node, f"{prefix}{node.name}.")


def _modules() -> dict[str, str]:
    return {
        path.relative_to(PACKAGE).as_posix(): path.read_text(encoding="utf-8")
        for path in sorted(PACKAGE.rglob("*.py"))
    }


def test_modules_are_short():
    long = {
        path: len(text.splitlines())
        for path, text in _modules().items()
        if len(text.splitlines()) >= MAX_MODULE_LINES
    }
    assert sorted(set(long) - set(LONG_MODULES)) == [], f"modules of 400+ lines: {long}"
    fixed = sorted(set(LONG_MODULES) - set(long))
    assert fixed == [], f"take these off LONG_MODULES, they are short now: {fixed}"


#: The compiled core's sources; its vendored code (third_party) is not held to the rule
CPP_SOURCES = PACKAGE.parent / "src" / "core"
CPP_SUFFIXES = {".hpp", ".cpp", ".h", ".c"}


def _cpp_files() -> dict[str, int]:
    """Line counts of the core's C++ files, path under src/core/, outside third_party."""
    return {
        path.relative_to(CPP_SOURCES).as_posix(): len(path.read_text(encoding="utf-8").splitlines())
        for path in sorted(CPP_SOURCES.rglob("*"))
        if path.suffix in CPP_SUFFIXES and "third_party" not in path.relative_to(CPP_SOURCES).parts
    }


def test_cpp_files_are_short():
    """A C++ file follows the modules' rule: fewer than 400 lines, split where a concept ends."""
    files = _cpp_files()
    assert "module.cpp" in files and "kinematics.hpp" in files, f"no core sources: {files}"
    long = {path: lines for path, lines in files.items() if lines >= MAX_MODULE_LINES}
    assert long == {}, f"C++ files of 400+ lines: {long}"


def test_functions_are_short():
    long = {}
    for path, text in _modules().items():
        for name, node in _functions(ast.parse(text)):
            lines = node.end_lineno - node.lineno + 1
            if lines >= MAX_FUNCTION_LINES:
                long[f"{path}::{name}"] = lines
    assert sorted(set(long) - set(LONG_FUNCTIONS)) == [], f"functions of 80+ lines: {long}"
    fixed = sorted(set(LONG_FUNCTIONS) - set(long))
    assert fixed == [], f"take these off LONG_FUNCTIONS, they are short now: {fixed}"


def test_no_module_uses_numba():
    """One implementation per kernel: the compiled core's C++; numpy where no core runs."""
    users = [
        path for path, text in _modules().items()
        if any(
            isinstance(node, (ast.Import, ast.ImportFrom)) and "numba" in ast.dump(node)
            for node in ast.walk(ast.parse(text))
        ) or "@njit" in text
    ]  # fmt: skip
    assert users == [], f"modules that use numba: {users}"


#: Private names reached from another module, "path::name" -> why it is still there
PRIVATE_USES: dict[str, str] = {}


def _private_uses(text: str) -> set[str]:
    """Private names one module takes from another.

    ``from x import _name`` (any level, ``from . import _name`` too), and ``Name._attr`` where
    ``Name`` is bound by an import of this module (another module's private function, or a
    class's private attribute reached from outside the class's module).
    """
    tree = ast.parse(text)
    imported: set[str] = set()
    uses: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            for alias in node.names:
                imported.add(alias.asname or alias.name)
                if alias.name.startswith("_") and not alias.name.startswith("__"):
                    uses.add(alias.name)
        elif isinstance(node, ast.Import):
            imported.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in imported
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
            and node.value.id not in EXTERNAL_MODULES
        ):
            uses.add(f"{node.value.id}.{node.attr}")
    return uses


#: Third-party modules whose private names are theirs to expose (none is used today)
EXTERNAL_MODULES: set[str] = set()


def test_private_uses_detected():
    """The check finds both forms (it can fail), and not a module's own private names."""
    source = (
        "from .springs import SpringDamper, _helper\n"
        "from . import _kernels\n"
        "import numpy as np\n"
        "def _own():\n"
        "    return SpringDamper._wrench_floats, np._core, _own\n"
    )
    found = {"_helper", "_kernels", "SpringDamper._wrench_floats", "np._core"}
    assert _private_uses(source) == found
    assert _private_uses("def _own():\n    return _own\nclass A:\n    _x = 1\n") == set()


def test_no_private_name_crosses_modules():
    uses = {f"{path}::{name}" for path, text in _modules().items() for name in _private_uses(text)}
    assert sorted(uses - set(PRIVATE_USES)) == [], f"private names used across modules: {uses}"
    fixed = sorted(set(PRIVATE_USES) - uses)
    assert fixed == [], f"take these off PRIVATE_USES, they are gone now: {fixed}"


#: Private attributes read on a function's parameter that its module never defines,
#: "path::parameter.attribute" -> why it is still there
PARAMETER_PRIVATES: dict[str, str] = {
    "simulation/contact_queries.py::data._address": "MuJoCo's MjData address (no public one)",
    "simulation/contact_queries.py::model._address": "MuJoCo's MjModel address (no public one)",
}


def _own_privates(tree: ast.AST) -> set[str]:
    """Private names a module defines: attributes it assigns, its private functions and
    classes, class attributes and ``__slots__`` entries."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            names.add(node.attr)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            names.add(node.value)  # a __slots__ entry, a getattr name
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
    return {name for name in names if name.startswith("_")}


#: A NamedTuple's public methods (their underscore only keeps them apart from the fields)
NAMED_TUPLE_API = {"_replace", "_asdict", "_fields", "_make", "_field_defaults"}


def _parameter_privates(text: str) -> set[str]:
    """``parameter._attr`` reads (``self`` and ``cls`` aside) of an attribute the module never
    defines: another module's object's private state, reached through an argument."""
    tree = ast.parse(text)
    own, found = _own_privates(tree), set()
    for function in ast.walk(tree):
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            continue
        arguments = function.args
        names = {a.arg for a in [*arguments.posonlyargs, *arguments.args, *arguments.kwonlyargs]}
        names -= {"self", "cls"}
        for node in ast.walk(function):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id in names
                and node.attr.startswith("_")
                and not node.attr.startswith("__")
                and node.attr not in own | NAMED_TUPLE_API
            ):
                found.add(f"{node.value.id}.{node.attr}")
    return found


def test_parameter_privates_detected():
    """The check finds a private read through an argument (it can fail), not a module's own."""
    source = (
        "def tick(gait, self):\n"
        "    return gait._swing, self._mine\n"
        "class A:\n"
        "    def f(self, other):\n"
        "        self._x = 1\n"
        "        return other._x\n"
    )
    assert _parameter_privates(source) == {"gait._swing"}


def test_no_private_attribute_is_read_through_an_argument():
    uses = {
        f"{path}::{name}" for path, text in _modules().items() for name in _parameter_privates(text)
    }
    assert sorted(uses - set(PARAMETER_PRIVATES)) == [], f"private reads through arguments: {uses}"
    fixed = sorted(set(PARAMETER_PRIVATES) - uses)
    assert fixed == [], f"take these off PARAMETER_PRIVATES, they are gone now: {fixed}"


#: The core: below simulation, experiments, visualization, gaits, demos and the CLI
CORE = (
    "exceptions.py",
    "vocabulary/",
    "models/",
    "kinematics/",
    "contacts/",
    "distribution/",
    "actuators/",
    "components/",
    "control/",
)
MAX_TUPLE = 3  # a longer result is a NamedTuple or a slotted dataclass


def _returns(node: ast.AST):
    """The return statements of a function, not those of functions defined inside it."""
    for child in ast.iter_child_nodes(node):
        if isinstance(child, ast.Return):
            yield child
        if not isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            yield from _returns(child)


def _long_tuples(tree: ast.AST, prefix: str = "") -> set[str]:
    """Public functions and methods returning a tuple literal of more than :data:`MAX_TUPLE`.

    Private functions (``_name``) and functions nested in another stay in their module (see
    :func:`test_no_private_name_crosses_modules`), so their tuples cross no boundary.
    """
    found = set()
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
            found |= _long_tuples(node, f"{prefix}{node.name}.")
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            if not node.name.startswith("_") and any(
                isinstance(r.value, ast.Tuple) and len(r.value.elts) > MAX_TUPLE
                for r in _returns(node)
            ):
                found.add(prefix + node.name)
    return found


def test_long_tuples_detected():
    source = (
        "def public():\n    return 1, 2, 3, 4\n"
        "def _private():\n    return 1, 2, 3, 4\n"
        "def short():\n    return 1, 2, 3\n"
        "def outer():\n    def inner():\n        return 1, 2, 3, 4\n    return inner\n"
        "class A:\n    def method(self):\n        return (1, 2, 3, 4, 5)\n"
    )
    assert _long_tuples(ast.parse(source)) == {"public", "A.method"}


def test_no_long_tuple_crosses_modules():
    """Layers hand each other typed results: no public core function returns a long tuple."""
    long = {
        f"{path}::{name}"
        for path, text in _modules().items()
        if path.startswith(CORE)
        for name in _long_tuples(ast.parse(text))
    }
    assert sorted(long) == [], f"return a NamedTuple or a dataclass instead: {long}"


def _imports(path: str, source: str, modules: set[str]) -> set[str]:
    """The package's modules that ``path`` imports (``TYPE_CHECKING`` imports included)."""
    name = "virtual_actuators." + path.removesuffix(".py").replace("/", ".")
    package = name.removesuffix(".__init__") if path.endswith("__init__.py") else name
    package = package if path.endswith("__init__.py") else package.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1]
            target = ".".join(base + [node.module]) if node.level and node.module else None
            target = target or (".".join(base) if node.level else node.module)
            names = [target, *(f"{target}.{alias.name}" for alias in node.names)]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        else:
            continue
        found.update(n for n in names if n in modules)
    return found


def test_no_import_circle():
    """No two modules import each other, even indirectly (packages' ``__init__`` aside)."""
    sources = _modules()
    module_of = {
        "virtual_actuators." + path.removesuffix(".py").replace("/", "."): path for path in sources
    }
    modules = {name for name, path in module_of.items() if not path.endswith("__init__.py")}
    graph = {name: _imports(module_of[name], sources[module_of[name]], modules) for name in modules}
    circles = []
    for start in sorted(modules):  # a module that reaches itself again is on a circle
        seen, frontier = set(), set(graph[start])
        while frontier:
            seen |= frontier
            frontier = {n for m in frontier for n in graph[m]} - seen
        if start in seen:
            circles.append(start)
    assert not circles, f"modules on an import circle: {circles}"
