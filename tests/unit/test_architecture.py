"""The import direction of docs/architecture.md, enforced on the source tree.

The import graph of ``src/featherdyn`` is built from the source (every
``import`` statement, lazy imports inside functions included) and checked:

* every module belongs to a layer, and imports only modules of its own layer
  or of layers below it: values → model → {algorithms, core} → api → tools;
* the reference algorithms and the compiled core never import each other;
* there is no cycle between packages (and none between top-level modules);
* the rooms hold: at most 20 modules at the package root, and no private name used across rooms.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "featherdyn"

#: the layers, lowest first; a module may import its own layer and every layer before it
LAYERS: dict[str, int] = {"values": 0, "model": 1, "algorithms": 2, "core": 2, "api": 3, "tools": 4}

#: the layer of each top-level module or package of featherdyn (private pieces go with their public module)
LAYER_OF: dict[str, str] = {
    "errors": "values",
    "tolerances": "values",
    "frames": "values",
    "spatial": "values",
    "spatial_algebra": "values",
    "rotation": "values",
    "conventions": "values",
    "testing": "values",
    "joints": "model",
    "model": "model",
    "results": "model",
    "constraints": "model",
    "_state_checks": "model",
    "readers": "model",
    "urdf": "model",
    "mjcf": "model",
    "configuration": "model",
    "_dask": "model",
    "robots": "model",
    "algorithms": "algorithms",
    "core": "core",
    "api": "api",
    "symbolic": "tools",
    "verify": "tools",
    "tools": "tools",
    "__main__": "tools",
    "torch": "tools",
    "jax": "tools",
}


def _module_name(path: Path) -> str:
    rel = path.relative_to(SRC.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path) -> set[str]:
    """Every featherdyn module ``path`` imports, anywhere in the file, as dotted names."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.split(".")[0] == "featherdyn")
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "featherdyn":
                continue
            # `from . import x` / `from .pkg import mod` may name submodules; a name that is not one
            # comes from the package (or module) ``target`` itself
            for alias in node.names:
                candidate = f"{target}.{alias.name}"
                rel = Path(*candidate.split(".")[1:])
                # (a compiled module is known by its type stub, ``.pyi``)
                if any((SRC / rel).with_suffix(ext).exists() for ext in (".py", ".pyi")) or (
                        SRC / rel / "__init__.py").exists():
                    out.add(candidate)
                else:
                    out.add(target)
    return out


def _graph() -> dict[str, set[str]]:
    return {_module_name(p): _imports(p) for p in SRC.rglob("*.py")}


def _top(module: str) -> str:
    """``featherdyn.core._errors`` → ``core``; ``featherdyn`` → ``""`` (the flat facade)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def test_every_module_has_a_layer() -> None:
    unknown = sorted({_top(m) for m in _graph()} - set(LAYER_OF) - {""})
    assert not unknown, f"modules without a layer in docs/architecture.md (add them to LAYER_OF): {unknown}"


def test_imports_go_down_the_layers() -> None:
    bad = []
    for module, imported in _graph().items():
        if _top(module) == "":  # featherdyn/__init__.py re-exports the public names of every layer
            continue
        layer = LAYER_OF[_top(module)]
        for target in imported:
            top = _top(target)
            if top == "":
                if LAYERS[layer] < LAYERS["tools"]:
                    bad.append(f"{module} imports the featherdyn facade (all layers)")
                continue
            tlayer = LAYER_OF.get(top)
            if tlayer is None:
                continue
            if LAYERS[tlayer] > LAYERS[layer]:
                bad.append(f"{module} ({layer}) imports {target} ({tlayer})")
            elif LAYERS[tlayer] == LAYERS[layer] and tlayer != layer:
                bad.append(f"{module} ({layer}) imports {target} ({tlayer}): the two implementations are separate")
    assert not bad, "imports against the direction of docs/architecture.md:\n" + "\n".join(sorted(bad))


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one node (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def _package_of(module: str) -> str:
    """The package a module belongs to: ``featherdyn.verify.check.values`` → ``featherdyn.verify``."""
    path = SRC.parent / Path(*module.split("."))
    if (path / "__init__.py").exists():
        return module
    return module.rpartition(".")[0]


def test_no_cycle_between_packages() -> None:
    graph: dict[str, set[str]] = {}
    for module, imported in _graph().items():
        node = _top(module) or "featherdyn"
        graph.setdefault(node, set()).update(_top(t) or "featherdyn" for t in imported if (_top(t) or "featherdyn") != node)
    # the facade imports everything by design; nothing imports the facade but tools
    graph.pop("featherdyn", None)
    cycles = _cycles(graph)
    assert not cycles, f"import cycles between top-level modules/packages: {cycles}"


def _nested(a: str, b: str) -> bool:
    """One package contains the other (a package and its subpackage import each other's modules by design)."""
    return a == b or a.startswith(b + ".") or b.startswith(a + ".")


def test_no_cycle_between_subpackages() -> None:
    """Sibling packages (``featherdyn.api`` and ``featherdyn.core``, ...) never import each other both ways."""
    graph: dict[str, set[str]] = {}
    for module, imported in _graph().items():
        pkg = _package_of(module)
        graph.setdefault(pkg, set()).update(_package_of(t) for t in imported if not _nested(_package_of(t), pkg))
    graph.pop("featherdyn", None)
    cycles = _cycles(graph)
    assert not cycles, f"import cycles between packages: {cycles}"


def test_no_cycle_between_modules() -> None:
    """No module imports, directly or through others, a module that imports it (``__init__`` files count)."""
    graph = {m: {t for t in imported if t != m} for m, imported in _graph().items()}
    graph.pop("featherdyn", None)  # the facade imports everything; only tools import it back
    cycles = _cycles(graph)
    assert not cycles, f"import cycles between modules: {cycles}"


@pytest.mark.parametrize(("module", "forbidden"), [("algorithms", "core"), ("core", "algorithms")])
def test_reference_and_core_are_separate(module: str, forbidden: str) -> None:
    offenders = sorted(m for m, imported in _graph().items() if _top(m) == module
                       and any(_top(t) == forbidden for t in imported))
    assert not offenders, f"{module} must not import {forbidden}: {offenders}"


def test_the_checker_sees_lazy_imports(tmp_path: Path) -> None:
    """The graph includes imports inside functions (the test would be blind to lazy cycles otherwise)."""
    graph = _graph()
    # the public fd.compile imports the core's CompiledModel lazily inside the function body
    assert "featherdyn.core.compiled" in graph["featherdyn.api"]


def test_no_source_cites_documents_outside_the_repository() -> None:
    offenders = [str(p.relative_to(SRC)) for p in SRC.rglob("*.py")
                 if "DESIGN.md" in (text := p.read_text(encoding="utf-8")) or "../shared" in text
                 or "shared/DESIGN" in text]
    assert not offenders, f"cite docs/architecture.md instead of the design document outside the repo: {offenders}"


# --------------------------------------------------------------------------
# the rooms (docs/architecture.md, "Rooms"): a short package root, no private name shared across rooms
# --------------------------------------------------------------------------

#: the package root holds the facade, the chapter's public modules and a few others; concepts live in folders
MAX_ROOT_MODULES = 20


def _root_modules() -> list[str]:
    """The modules at the package root (``.py`` files and the type stubs of compiled modules)."""
    names = {p.name for p in SRC.iterdir() if p.is_file() and p.suffix in (".py", ".pyi")}
    # a compiled module with a stub is one module, not two
    return sorted(n for n in names if not (n.endswith(".pyi") and n[:-1] in names))


def test_the_package_root_holds_at_most_twenty_modules() -> None:
    modules = _root_modules()
    assert len(modules) <= MAX_ROOT_MODULES, (
        f"{len(modules)} modules at the package root (at most {MAX_ROOT_MODULES}): {modules}; "
        "put a module with the concept it belongs to (a room of docs/architecture.md)")


# --------------------------------------------------------------------------
# the glue's budget (docs/architecture.md, "One declaration per algorithm"): the generic machinery of the binding
# stays small next to the algorithms it serves
# --------------------------------------------------------------------------

CPP = SRC / "core" / "cpp"
#: the binding's generic machinery: the module, its families, the declaration templates, the boundary
GLUE = ("bindings.cpp", "bind_dynamics.cpp", "bind_options.cpp", "bind_public_calls.cpp", "bind_jax.cpp", "declare.hpp",
        "public_calls.hpp", "boundary.hpp", "buffer.hpp", "numpy_api.hpp", "entry_points.hpp", "build_info.cpp",
        "build_info.hpp")
#: what the algorithms state (name, operands, kernel call): one struct each, neither glue nor kernel
DECLARATIONS = "declarations*.hpp"
#: the kernels: the algorithms, their SIMD group kernels and the arithmetic they share
KERNELS = ("aba.hpp", "centroidal.hpp", "contacts.hpp", "crba.hpp", "derivatives.hpp", "energy.hpp",
           "frame_derivatives.hpp", "frames.hpp", "jacobians.hpp", "joints.hpp", "kinematics.hpp", "ltl.hpp",
           "pack.hpp", "regressor.hpp", "rnea.hpp", "simd_groups.hpp", "spatial.hpp", "trig.hpp", "second_order.hpp",
           "rnea_second_order.hpp", "kinematics_derivatives.hpp", "contact_derivatives.hpp", "configuration.hpp",
           "vjp.hpp")
#: counted as neither: the thread pool, the CPU's features, the model's layout, the checks, scratch memory
INFRASTRUCTURE = ("thread_pool.hpp", "cpu_features.hpp", "model_view.hpp", "checks.hpp", "scratch.hpp", "groups.hpp")


def _lines(path: Path) -> int:
    return len(path.read_text(encoding="utf-8").splitlines())


def test_no_cpp_file_is_over_700_lines() -> None:
    long = {p.name: n for p in CPP.iterdir() if p.suffix in (".hpp", ".cpp", ".inc") and (n := _lines(p)) > 700}
    assert not long, f"C++ files over 700 lines: {long}; split them by family"


def test_the_glue_stays_under_six_tenths_of_the_kernels() -> None:
    missing = [n for n in GLUE + KERNELS if not (CPP / n).exists()]
    assert not missing, f"files named in GLUE or KERNELS that do not exist: {missing}"
    glue, kernels = sum(_lines(CPP / n) for n in GLUE), sum(_lines(CPP / n) for n in KERNELS)
    assert glue < 0.6 * kernels, f"the binding's machinery is {glue} lines for {kernels} lines of kernels"
    new_kernel_headers = sorted(p.name for p in CPP.glob("*.hpp") if p.name not in GLUE + KERNELS + INFRASTRUCTURE
                                and not p.match(DECLARATIONS) and _lines(p) > 150)
    assert not new_kernel_headers, f"classify these headers in GLUE or KERNELS: {new_kernel_headers}"


def test_the_core_python_side_stays_under_900_lines() -> None:
    n = sum(_lines(p) for p in (SRC / "core").glob("*.py"))
    assert n < 900, f"core/*.py holds {n} lines: the glue belongs to the declarations' generic code"


def test_the_binding_reaches_numpy_only_through_its_documented_interfaces() -> None:
    import re

    patterns = [r"\bapi\s*\[\s*\d+\s*\]", r"PyArray_API\s*\[", r"PyArrayObject_fields", r"_ARRAY_API\s*\["]
    found = [(p.name, pat) for p in CPP.iterdir() if p.suffix in (".hpp", ".cpp", ".inc")
             for pat in patterns if re.search(pat, p.read_text(encoding="utf-8"))]
    assert not found, f"undocumented NumPy ABI in the binding: {found}"


def _room(module: str) -> str:
    """The top-level module or package a module belongs to: ``featherdyn.spatial.ops`` → ``featherdyn.spatial``."""
    return ".".join(module.split(".")[:2])


def _is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _is_module(dotted: str) -> bool:
    """``featherdyn.a.b`` is a module or package of the source tree (a compiled one known by its ``.pyi``)."""
    rel = SRC / Path(*dotted.split(".")[1:])
    return rel.with_suffix(".py").exists() or rel.with_suffix(".pyi").exists() or (rel / "__init__.py").exists()


def _private_uses() -> set[tuple[str, str]]:
    """``(importer, what)`` for each private module or name one room takes from another.

    ``what`` is ``featherdyn.x._y`` for ``from featherdyn.x import _y``, ``x._y`` (``x`` an imported
    featherdyn module) or an import of a module with a private segment in its path.
    """
    out = set()
    for path in SRC.rglob("*.py"):
        importer = _module_name(path)
        package = importer if path.name == "__init__.py" else importer.rpartition(".")[0]
        modules: dict[str, str] = {}  # local name -> featherdyn module
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for a in node.names:
                    if a.name.split(".")[0] == "featherdyn":
                        modules[a.asname or a.name] = a.name
                        if any(_is_private(p) for p in a.name.split(".")):
                            out.add((importer, a.name))
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")
                    target = ".".join(base[: len(base) - (node.level - 1)] + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if target.split(".")[0] != "featherdyn":
                    continue
                for a in node.names:
                    full = f"{target}.{a.name}"
                    if _is_module(full):
                        modules[a.asname or a.name] = full
                    if any(_is_private(p) for p in full.split(".")[1:]):
                        out.add((importer, full))
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and _is_private(node.attr) and isinstance(node.value, ast.Name)
                    and node.value.id in modules):
                out.add((importer, f"{modules[node.value.id]}.{node.attr}"))
    return {(i, w) for i, w in out if _room(i) != _room(w)}


#: private names still shared across rooms, each with its reason: ``(importer glob, imported glob, reason)``
_PRIVATE_ACROSS_ROOMS_ALLOWED = [
    ("featherdyn.api*", "featherdyn.core.*", "api/ and core/ are rewritten by the glue work of issue 29 "
     "(the core's public face is decided there)"),
    ("featherdyn.api*", "featherdyn._dask*", "_dask is placed by the glue work of issue 29"),
    ("featherdyn.configuration", "featherdyn._dask*", "_dask is placed by the glue work of issue 29"),
    ("featherdyn.api*", "featherdyn._state_checks*", "_state_checks is placed by the glue work of issue 29"),
    ("featherdyn.core*", "featherdyn._state_checks*", "_state_checks is placed by the glue work of issue 29"),
    ("featherdyn.configuration", "featherdyn._state_checks*",
     "the configuration functions (fd.integrate's reference) check a state as the declared functions do"),
    ("featherdyn.tools.bench", "featherdyn.core._core*", "the kernels' SIMD width, _core.simd(), which core/ "
     "(rewritten in issue 29) does not wrap"),
    ("featherdyn.tools.cli", "featherdyn.core._core*", "the binary's build_info() for `featherdyn info --build` "
     "(issue 31), which core/ (rewritten in issue 29) does not wrap"),
    ("featherdyn.readers*", "featherdyn.joints._with_unit_axis", "an unchecked constructor of a public joint class "
     "(the loader has normalised the axis): not for the public API"),
]


def test_no_private_name_is_shared_across_rooms() -> None:
    """A helper another room uses is public in its module (docs/architecture.md, "Rooms")."""
    from fnmatch import fnmatchcase

    bad = sorted(f"{i} uses {w}" for i, w in _private_uses()
                 if not any(fnmatchcase(i, a) and fnmatchcase(w, b) for a, b, _ in _PRIVATE_ACROSS_ROOMS_ALLOWED))
    assert not bad, "private names used across rooms (make them public in their module):\n" + "\n".join(bad)


def test_the_private_use_checker_sees_each_form() -> None:
    """The checker finds ``from m import _x``, ``m._x`` and private modules (it would pass vacuously otherwise)."""
    uses = _private_uses()
    # api/ takes the core's model view by private name, in both forms; configuration imports the private _dask
    assert ("featherdyn.api._backend", "featherdyn.core._view") in uses
    assert ("featherdyn.api.constraints", "featherdyn.core._view") in uses
    assert any(i == "featherdyn.configuration" and w.startswith("featherdyn._dask") for i, w in uses)


#: module-level state the public layer may rebind with ``global``: settings, not caches
_API_SETTINGS = {("_backend.py", "_DEFAULT")}


def _module_caches(name: str, source: str) -> list[str]:
    """A module's module-level caches: ``global`` rebinding a name (beyond :data:`_API_SETTINGS`) and functions
    decorated with ``functools.lru_cache`` / ``cache`` / ``cached_property``."""
    bad = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Global):
            bad += [f"{name}: global {n}" for n in node.names if (name, n) not in _API_SETTINGS]
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for d in node.decorator_list:
                what = ast.unparse(d.func if isinstance(d, ast.Call) else d)
                if what.split(".")[-1] in ("lru_cache", "cache", "cached_property"):
                    bad.append(f"{name}: {node.name} decorated with {what}")
    return bad


def test_the_public_layer_keeps_no_module_level_caches() -> None:
    """Caches of per-model work live on the model (``model._core``, ``model._plans``), not in ``api/``."""
    bad = [b for path in sorted((SRC / "api").glob("*.py")) for b in _module_caches(path.name, path.read_text("utf-8"))]
    assert not bad, "module-level caches in api/ (keep them on the model):\n" + "\n".join(bad)


def test_the_cache_check_sees_a_global_and_an_lru_cache() -> None:
    """The scan above, on planted modules: it finds both kinds, and lets the default-backend setting pass."""
    source = ("import functools\n_LAST = None\n\n@functools.lru_cache(maxsize=8)\ndef f(x):\n"
              "    global _LAST, _DEFAULT\n    _LAST = x\n    return x\n\n@functools.cache\ndef g():\n    return 1\n")
    assert sorted(_module_caches("constraints.py", source)) == [
        "constraints.py: f decorated with functools.lru_cache", "constraints.py: g decorated with functools.cache",
        "constraints.py: global _DEFAULT", "constraints.py: global _LAST"]
    assert _module_caches("_backend.py", "def f():\n    global _DEFAULT\n") == []
