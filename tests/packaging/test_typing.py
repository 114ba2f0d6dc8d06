"""What a user's type checker sees (issue 31): ``mypy --strict`` on a user's script (user_script.py here) that calls
``fd.rnea``, ``fd.compile(model).aba`` and ``fd.constrained_dynamics``, and on every public function of ``fd``.

featherdyn ships ``py.typed`` and the compiled module's stub (test_stubs.py); the types of the public calls come
from their Python annotations. The declared algorithms (``fd.rnea`` & co., api/declarations.py) are made by
``public_function`` and typed ``Callable[..., Any]``, and a compiled model's methods come through
``CompiledModel.__getattr__`` (``Any``): the names below, which the annotations of api/ and core/ (issue 29) are to
fix. The test holds the list exact: a fixed name must leave it, a new Any-typed public function fails it.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import featherdyn as fd

HERE = Path(__file__).resolve().parent

#: public functions of fd whose result a type checker sees as Any: none (the declared algorithms are typed by their
#: results in api/declarations.py, a compiled model's methods in core/compiled.py)
RETURNS_ANY: set[str] = set()


def _mypy(files: list[Path], cache: Path) -> str:
    """mypy --strict on ``files`` (errors reported for them alone), reading the featherdyn this test imports: an
    installed one from site-packages, a source tree's (an editable install's import hook, which mypy cannot follow,
    or a path) through MYPYPATH."""
    env = dict(os.environ)
    where = Path(fd.__file__).resolve().parents[1]
    if where.name not in ("site-packages", "dist-packages"):
        env["MYPYPATH"] = str(where)
    res = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--follow-imports=silent", "--cache-dir",
                          str(cache), *map(str, files)], capture_output=True, text=True, timeout=900, cwd=cache, env=env)
    return res.stdout + res.stderr


@pytest.fixture(scope="module")
def revealed(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[str, str]]:
    """``{expression: (revealed type, file)}`` of the user's script and of every public name of fd; mypy run once."""
    tmp = tmp_path_factory.mktemp("mypy")
    names = sorted(n for n in fd.__all__ if callable(getattr(fd, n)) and not isinstance(getattr(fd, n), type))
    every = tmp / "every_public_function.py"
    every.write_text("import featherdyn as fd\n" + "".join(f"reveal_type(fd.{n})\n" for n in names), encoding="utf-8")
    script = HERE / "user_script.py"
    out = _mypy([script, every], tmp)
    errors = [line for line in out.splitlines() if ": error:" in line]
    assert not errors, out
    lines = {script.name: script.read_text(encoding="utf-8").splitlines(), every.name: every.read_text().splitlines()}
    found: dict[str, tuple[str, str]] = {}
    for m in re.finditer(r"([\w.]+):(\d+): note: Revealed type is \"(.*)\"", out):
        file = Path(m.group(1)).name
        expr = re.fullmatch(r"reveal_type\((.*?)\)(\s*#.*)?", lines[file][int(m.group(2)) - 1].strip())
        assert expr, m.group(0)
        found[expr.group(1)] = (m.group(3), file)
    assert len(found) == 4 + len(names), out
    return found


def _is_any(t: str) -> bool:
    return t == "Any" or t.endswith("-> Any")


def test_the_script_passes_mypy_strict(revealed: dict[str, tuple[str, str]]) -> None:
    # (the fixture asserts that mypy --strict reports no error in the script)
    assert revealed["held"][0] == "featherdyn.api.constraints.ConstrainedDynamics"
    assert revealed["held.ddq"][0].startswith("numpy.ndarray[")


def test_the_public_functions_returning_any_are_the_known_ones(revealed: dict[str, tuple[str, str]]) -> None:
    returns_any = {e.removeprefix("fd.") for e, (t, f) in revealed.items() if f != "user_script.py" and _is_any(t)}
    assert returns_any == RETURNS_ANY, (sorted(returns_any - RETURNS_ANY), sorted(RETURNS_ANY - returns_any))


def test_no_result_of_the_script_is_any(revealed: dict[str, tuple[str, str]]) -> None:
    assert not [v for v in ("tau", "ddq", "held", "held.ddq") if _is_any(revealed[v][0])]
    assert revealed["tau"][0].startswith("numpy.ndarray[") and revealed["ddq"][0].startswith("numpy.ndarray[")
