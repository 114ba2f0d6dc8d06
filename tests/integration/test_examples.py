"""Every script in ``examples/`` runs top to bottom, after the install its first line names.

The examples are the chapter made executable (worked examples, code blocks,
exercises, errata); each stops with ``SystemExit(1)`` on a failed comparison,
so a wrong number anywhere fails its test here. Each script's first line is
``# needs: featherdyn[EXTRA] …`` (or ``featherdyn (no extra …``): the test runs
it with the distributions of the other extras made to look absent (modules
unimportable, metadata not found), as on a machine where only that extra was
installed, so a declaration short of what the script uses fails here. A
missing one is one line naming the install command, never a traceback. CI
installs the ``test`` extra, which holds every extra the examples name (checked
below), so every example runs in CI: about 60 s in all on two cores, 3 s at
most for one (the SymPy proofs of 10 and 11, the Dask dataset of 29).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
SCRIPTS = sorted(p for p in EXAMPLES.glob("[0-9]*.py"))
TIMEOUT_S = 120  # each runs in about a second; the budget is generous for slow CI machines
NEEDS = re.compile(r"# needs: featherdyn(?:\[([\w,]+)\]| \(no extra)")

#: the modules each optional distribution of pyproject.toml's extras provides (the ones an example may import;
#: example-robot-data is robot files, found through its distribution's metadata)
DIST_MODULES = {"pin": ("pinocchio",), "example-robot-data": (), "mujoco": ("mujoco",),
                "sympy": ("sympy", "mpmath"), "gymnasium": ("gymnasium",), "dask": ("dask", "distributed"),
                "zarr": ("zarr",), "drake": ("pydrake",), "jax": ("jax", "jaxlib"), "torch": ("torch",)}


def _extras() -> dict[str, list[str]]:
    """pyproject.toml's extras: name -> distribution names (no versions, markers or extras)."""
    try:
        import tomllib
    except ImportError:  # Python 3.10
        tomllib = pytest.importorskip("tomli")
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    return {name: [re.match(r"[A-Za-z0-9_.-]+", req)[0] for req in reqs]  # type: ignore[index]
            for name, reqs in project["optional-dependencies"].items()}


def declared_extras(script: Path) -> list[str]:
    """The extras named on the script's first line (``[]``: none)."""
    first = script.read_text(encoding="utf-8").split("\n", 1)[0]
    found = NEEDS.match(first)
    assert found, f"{script.name}: the first line should say what it needs (# needs: featherdyn[EXTRA] …)"
    return found[1].split(",") if found[1] else []


def blocked(extras: list[str]) -> set[str]:
    """The optional distributions an install of featherdyn with ``extras`` would not have."""
    table = _extras()
    optional = {d for name, dists in table.items() if name not in ("test", "dev") for d in dists}
    unknown = optional - set(DIST_MODULES)
    assert not unknown, f"DIST_MODULES does not know the modules of {unknown}"
    return optional - {d for name in extras for d in table[name]}


#: a sitecustomize that makes the distributions DISTS and their modules MODULES look not installed
_SITECUSTOMIZE = """
import importlib.metadata as _md
import sys

for _m in MODULES:
    sys.modules[_m] = None
_distribution = _md.distribution


def _without(name, _distribution=_distribution):
    if name.lower().replace("_", "-") in DISTS:
        raise _md.PackageNotFoundError(name)
    return _distribution(name)


_md.distribution = _without
"""


def run(script: Path, tmp_path: Path, dists: set[str]) -> subprocess.CompletedProcess[str]:
    """Run ``script`` in a fresh interpreter where the distributions ``dists`` look not installed."""
    site = tmp_path / "site"
    site.mkdir(exist_ok=True)
    modules = sorted(m for d in dists for m in DIST_MODULES[d])
    (site / "sitecustomize.py").write_text(f"DISTS = {sorted(dists)!r}\nMODULES = {modules!r}\n{_SITECUSTOMIZE}",
                                           encoding="utf-8")
    path = os.pathsep.join(p for p in (str(site), os.environ.get("PYTHONPATH", "")) if p)
    env = dict(os.environ, PYTHONIOENCODING="utf-8", MPLBACKEND="Agg", PYTHONPATH=path)
    return subprocess.run([sys.executable, str(script)], cwd=EXAMPLES, capture_output=True, text=True,
                          timeout=TIMEOUT_S, env=env, check=False)


def test_examples_found() -> None:
    assert len(SCRIPTS) >= 20, f"expected the chapter's example scripts in {EXAMPLES}"


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_example_runs_with_only_the_extras_it_names(script: Path, tmp_path: Path) -> None:
    extras = declared_extras(script)
    assert set(extras) <= set(_extras()), f"{script.name} names an extra pyproject.toml does not have: {extras}"
    if "zarr" in script.read_text(encoding="utf-8") and sys.version_info < (3, 11):
        pytest.skip("zarr 3 (featherdyn dataset's format) needs Python 3.11")
    proc = run(script, tmp_path, blocked(extras))
    assert proc.returncode == 0, (
        f"{script.name} exited with {proc.returncode}\n--- stdout (tail) ---\n{proc.stdout[-3000:]}"
        f"\n--- stderr (tail) ---\n{proc.stderr[-3000:]}"
    )


@pytest.mark.parametrize("name", ["06_rnea_verification_panda", "08_2r_rnea_appendix_d", "09_sympy_verification",
                                  "26_derivatives_for_mpc", "28_mjcf_against_mujoco", "29_dask_and_datasets"])
def test_a_missing_module_is_one_line_naming_the_install(name: str, tmp_path: Path) -> None:
    script = EXAMPLES / f"{name}.py"
    extras = declared_extras(script)
    proc = run(script, tmp_path, blocked([]))  # featherdyn alone, no extra
    assert proc.returncode == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert proc.stdout == "" and proc.stderr.strip().count("\n") == 0, proc.stdout + proc.stderr
    assert f'pip install "featherdyn[{",".join(extras)}]"' in proc.stderr, proc.stderr
    assert f'pip install ".[{",".join(extras)}]"' in proc.stderr, proc.stderr


def test_the_examples_extra_holds_every_extra_the_examples_name_and_ci_installs_it() -> None:
    table = _extras()
    named = {e for script in SCRIPTS for e in declared_extras(script)}
    for extra in named:
        assert set(table[extra]) <= set(table["examples"]), f"`examples` lacks what `{extra}` installs"
    assert set(table["examples"]) <= set(table["test"]), "CI installs `test`: it must hold every example's needs"


def test_readme_names_an_install_that_runs_the_example_it_names() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## The textbook, executable", 1)[1].split("\n## ", 1)[0]
    installs = re.findall(r'pip install "\.\[([\w,]+)\]"', section)
    scripts = re.findall(r"python3? (examples/\w+\.py)", section)
    assert installs and scripts, section
    table = _extras()

    def dists(extras: list[str]) -> set[str]:
        return {d for e in extras for d in table[e]}

    for script in scripts:  # each runs after the quick start's `.[verify]` and one install the section names
        assert (ROOT / script).is_file(), script
        need = dists(declared_extras(ROOT / script))
        assert any(need <= dists(["verify", *i.split(",")]) for i in installs), (script, installs)


def test_speed_claims_label_the_backend_they_measure() -> None:
    # the reference (NumPy) recursion is hundreds of times slower than the compiled core: a line labelled
    # NumPy that shows the compiled core's time (as it did) is caught by the ratio
    pytest.importorskip("pinocchio")
    env = dict(os.environ, PYTHONIOENCODING="utf-8")
    proc = subprocess.run([sys.executable, str(EXAMPLES / "23_speed_claims.py")], cwd=EXAMPLES, capture_output=True,
                          text=True, timeout=TIMEOUT_S, env=env, check=False)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]

    def micros(label: str) -> float:
        line = next((ln for ln in proc.stdout.splitlines() if label in ln), None)
        assert line is not None, f"no line with {label!r} in\n{proc.stdout}"
        return float(line.split(":", 1)[1].split("µs")[0])

    t_numpy = micros("backend='reference', NumPy")
    t_compiled = micros("compiled core, C++")
    assert t_numpy > 20 * t_compiled, (t_numpy, t_compiled)
