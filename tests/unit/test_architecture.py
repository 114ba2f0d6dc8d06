"""The import direction of docs/architecture.md, enforced on the source tree.

The import graph of ``src/featherdyn`` is built from the source (every
``import`` statement, lazy imports inside functions included) and checked:

* every module belongs to a layer, and imports only modules of its own layer
  or of layers below it: values → model → {algorithms, core} → api → tools;
* the reference algorithms and the compiled core never import each other;
* there is no cycle between packages (and none between top-level modules).
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
    "_validation": "values",
    "spatial_algebra": "values",
    "_spatial_ops": "values",
    "_spatial_vectors": "values",
    "_spatial_inertia": "values",
    "_spatial_transform": "values",
    "rotation": "values",
    "_lie_jacobians": "values",
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
    "_symbolic_reduce": "tools",
    "_symbolic_dynamics": "tools",
    "verify": "tools",
    "cli": "tools",
    "bench": "tools",
    "dataset": "tools",
    "_distributed": "tools",
    "_cli_args": "tools",
    "__main__": "tools",
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
