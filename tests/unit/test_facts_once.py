"""Facts stated once (docs/architecture.md, "Facts once").

Tolerances per dtype, the ABA singularity rule and its message, the
reference-frame codes and the default backend each have one definition that
everything reads. These tests scan the source for a second one, and check that
the one definition is what every implementation uses.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import tolerances
from featherdyn.errors import SingularMassMatrixError

SRC = Path(__file__).resolve().parents[2] / "src" / "featherdyn"
SOURCES = sorted(SRC.rglob("*.py"))


def _rel(p: Path) -> str:
    return str(p.relative_to(SRC))


def _module_assignments(path: Path) -> list[tuple[str, ast.expr]]:
    """``(name, value)`` of every module-level assignment (tuple targets unpacked)."""
    out = []
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        targets: list[ast.expr] = []
        if isinstance(node, ast.Assign):
            targets, value = node.targets, node.value
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            targets, value = [node.target], node.value
        else:
            continue
        for t in targets:
            if isinstance(t, ast.Name):
                out.append((t.id, value))
            elif isinstance(t, ast.Tuple) and isinstance(value, ast.Tuple):
                out += [(e.id, v) for e, v in zip(t.elts, value.elts, strict=False) if isinstance(e, ast.Name)]
    return out


def _has_float_literal(node: ast.expr) -> bool:
    return any(isinstance(n, ast.Constant) and isinstance(n.value, float) for n in ast.walk(node))


def test_tolerances_are_defined_only_in_tolerances_py() -> None:
    """No module but tolerances.py binds a ``*TOL*`` name to a number it writes itself."""
    offenders = [
        f"{_rel(p)}: {name}"
        for p in SOURCES
        if p.name != "tolerances.py"
        for name, value in _module_assignments(p)
        if "TOL" in name.upper() and _has_float_literal(value)
    ]
    assert not offenders, f"tolerances defined outside featherdyn/tolerances.py: {offenders}"


def test_no_literal_dtype_tolerance_pairs_outside_tolerances_py() -> None:
    """``default_tol(dtype, 1e-6, 1e-4)``-style calls with literal numbers belong in tolerances.py."""
    pattern = re.compile(r"default_tol\([^)]*\d")
    offenders = [_rel(p) for p in SOURCES if p.name != "tolerances.py" and pattern.search(p.read_text("utf-8"))]
    assert not offenders, offenders


def test_singular_message_is_written_once() -> None:
    phrase = "the subtree has no mass or inertia"
    holders = sorted(_rel(p) for p in SOURCES if phrase in p.read_text(encoding="utf-8"))
    assert holders == ["errors.py"], holders


def test_singular_rule_is_the_one_in_tolerances() -> None:
    """The reference and the core's model view both read the rule from tolerances.py."""
    for path in (SRC / "algorithms" / "aba.py", SRC / "core" / "_model_view.py"):
        assert "SINGULAR_PIVOT_RTOL" in path.read_text(encoding="utf-8"), path


def test_reference_frame_codes_are_defined_once() -> None:
    holders = sorted(_rel(p) for p in SOURCES if "class ReferenceFrame" in p.read_text(encoding="utf-8"))
    assert holders == ["frames.py"], holders
    offenders = [
        f"{_rel(p)}: {name}"
        for p in SOURCES
        if p.name != "frames.py"
        for name, value in _module_assignments(p)
        if name.endswith("_CODE") and name.startswith(("LOCAL", "WORLD", "LWA"))
        and any(isinstance(n, ast.Constant) and isinstance(n.value, int) for n in ast.walk(value))
    ]
    assert not offenders, f"reference-frame codes written outside frames.py: {offenders}"
    assert [r.code for r in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)] == [0, 1, 2]


def test_default_backend_is_decided_in_one_place() -> None:
    holders = sorted(_rel(p) for p in SOURCES if "FEATHERDYN_BACKEND" in p.read_text(encoding="utf-8")
                     and "os.environ" in p.read_text(encoding="utf-8"))
    assert holders == ["api/_backend.py"], holders


def test_quaternion_tolerance_is_the_same_everywhere() -> None:
    """One quaternion off unit norm by 5e-4 in float32 is refused by q checks, integrate and converters alike."""
    model = fd.load_robot("two_link_arm", floating_base=True)
    q = fd.neutral(model).astype(np.float32)
    q[3:7] = np.array([0, 0, 0, 1 + 5e-4], dtype=np.float32)  # off by 5e-4 > float32's 1e-4
    assert abs(float(np.linalg.norm(q[3:7])) - 1) > tolerances.QUATERNION_NORM.float32
    with pytest.raises(fd.QuaternionNormError):
        fd.rnea(model, q, np.zeros(model.nv, np.float32), np.zeros(model.nv, np.float32))
    with pytest.raises(fd.QuaternionNormError):
        fd.integrate(model, q, np.zeros(model.nv, np.float32))
    with pytest.raises(fd.QuaternionNormError):
        fd.rotation.quat_to_matrix(q[3:7])


def test_singular_error_is_the_same_from_every_backend() -> None:
    """A massless moving subtree: the reference and the compiled core raise the same words."""
    b = fd.ModelBuilder("massless")
    b.add_body("link", parent=-1, joint=fd.RevoluteJoint([0, 0, 1]), joint_name="j",
               inertia=fd.SpatialInertia(0.0, [0, 0, 0], np.zeros((3, 3))))
    with pytest.warns(fd.PhysicalityWarning):
        model = b.build()
    messages = set()
    for backend in ("reference", "compiled"):
        with pytest.raises(SingularMassMatrixError) as info:
            fd.aba(model, np.zeros(1), np.zeros(1), np.zeros(1), backend=backend)
        messages.add(re.sub(r"is \S+ —", "is … —", str(info.value)))
    assert len(messages) == 1, messages
