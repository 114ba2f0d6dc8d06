"""The compiled module's type stub (issue 31): ``featherdyn/core/_core.pyi``, made by nanobind's stubgen when the wheel
is built (CMakeLists.txt, ``nanobind_add_stub``) and installed beside the module.

Here the stub is made again from the module this test imports, and checked: it names every public function, class
and attribute of the module and nothing else, each function with the module's parameters; mypy reads it without an
error; and where featherdyn is installed from a wheel, the installed stub is that same text (the stub matches the
binary it ships with). ``py.typed`` is kept.
"""

from __future__ import annotations

import ast
import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest

import featherdyn
from featherdyn.core import _core


@pytest.fixture(scope="module")
def stub_text(tmp_path_factory: pytest.TempPathFactory) -> str:
    out = tmp_path_factory.mktemp("stub") / "_core.pyi"
    res = subprocess.run([sys.executable, "-m", "nanobind.stubgen", "-q", "-m", "featherdyn.core._core", "-o", str(out)],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    return out.read_text(encoding="utf-8")


def _public(names: list[str]) -> set[str]:
    return {n for n in names if not n.startswith("_")}


def _stub_tree(text: str) -> dict[str, ast.AST]:
    """The stub's top-level definitions by name (functions, classes, annotated attributes)."""
    out: dict[str, ast.AST] = {}
    for node in ast.parse(text).body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef):
            out[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out[node.target.id] = node
    return out


def test_the_stub_names_every_public_name_of_the_module(stub_text: str) -> None:
    defined = _stub_tree(stub_text)
    module_names = {n for n in _public(dir(_core)) if not inspect.ismodule(getattr(_core, n))}
    assert module_names == set(defined), (sorted(module_names - set(defined)), sorted(set(defined) - module_names))
    assert {"build_info", "simd", "Kernel", "Model", "kernels"} <= set(defined)


def _parameters(obj: object) -> list[str]:
    """The parameters of a nanobind function or method, from its signature ("def simd() -> tuple[str, int]")."""
    signature = obj.__nb_signature__[0][0]  # type: ignore[attr-defined]
    return re.findall(r"[(,]\s*(\w+)\s*:", signature)


def test_each_function_and_method_has_the_module_parameters(stub_text: str) -> None:
    checked = 0
    for name, node in _stub_tree(stub_text).items():
        if isinstance(node, ast.FunctionDef):
            assert [a.arg for a in node.args.args + node.args.kwonlyargs] == _parameters(getattr(_core, name)), name
            checked += 1
        elif isinstance(node, ast.ClassDef):
            for member in node.body:
                if isinstance(member, ast.FunctionDef) and not member.decorator_list:  # (properties: no parameters)
                    args = [a.arg for a in member.args.args + member.args.kwonlyargs]  # (keyword-only: Options)
                    assert args[0] == "self" and args[1:] == _parameters(getattr(getattr(_core, name), member.name)), (
                        name, member.name)
                    checked += 1
    # every function of the module and every method of its classes (the declared algorithms' Kernel among them)
    assert checked >= 15 and {"declared_call", "set_num_threads"} <= set(_stub_tree(stub_text))


def test_build_info_is_typed_in_the_stub(stub_text: str) -> None:
    assert "def build_info() -> dict[str, str | int | bool | tuple[str, ...]]" in stub_text


def test_mypy_reads_the_stub(stub_text: str, tmp_path: Path) -> None:
    (tmp_path / "_core.pyi").write_text(stub_text, encoding="utf-8")
    res = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "_core.pyi"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr


def test_an_installed_wheel_ships_the_stub_of_its_module(stub_text: str) -> None:
    """Installed from a wheel (site-packages): the stub beside the module is the one its binary gives. In a source
    checkout the stub is not there (the build directory has it): then the package is the source tree's."""
    package = Path(featherdyn.__file__).resolve().parent
    installed = Path(_core.__file__).with_name("_core.pyi")
    assert (package / "py.typed").is_file()
    if "site-packages" in package.parts or "dist-packages" in package.parts:
        assert installed.read_text(encoding="utf-8") == stub_text
    else:
        assert (package.parent.parent / "CMakeLists.txt").is_file(), package
