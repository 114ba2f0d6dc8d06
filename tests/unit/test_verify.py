"""The verification tool's Python API: it passes on correct code and catches injected bugs."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import verify
from featherdyn.verify import dynamics as vdyn
from featherdyn.verify.report import compare


def test_run_on_the_bundled_arm_passes() -> None:
    report = verify.run("two_link_arm", samples=3, seed=1)
    assert report.passed, report.to_table()
    assert report.meta["robot"] == "two_link_arm" and report.meta["nv"] == 2
    d = json.loads(report.to_json())
    assert d["passed"] and d["diagnostics"]["invalid_inertias"] == []
    names = {r.quantity for r in report.results}
    assert {"rnea vs pin.rnea", "crba vs pin.crba", "aba vs pin.aba", "M = Mᵀ"} <= names


def _wrong(fn: Any, factor: float) -> Any:
    def wrapped(*args: Any, **kwargs: Any) -> Any:
        return np.asarray(fn(*args, **kwargs)) * factor
    return wrapped


@pytest.mark.parametrize("name, quantity", [("rnea", "rnea vs pin.rnea"), ("crba", "crba vs pin.crba"),
                                            ("aba", "aba vs pin.aba")])
def test_an_injected_bug_is_reported(monkeypatch: pytest.MonkeyPatch, name: str, quantity: str) -> None:
    monkeypatch.setattr(vdyn.fd, name, _wrong(getattr(fd, name), 1.0 + 1e-6))
    report = verify.run("two_link_arm", samples=2, algebra=False)
    failed = {r.quantity for r in report.failures}
    assert quantity in failed


def test_compare_names_the_worst_sample() -> None:
    expected = np.zeros((4, 3))
    actual = expected.copy()
    actual[2, 1] = 1e-3
    r = compare("g", "q", actual, expected, 1e-9, "hint")
    assert not r.passed and r.worst_sample == 2 and r.note == "hint"
    assert r.max_abs == pytest.approx(1e-3)
    r = compare("g", "q", actual, expected[:, :2], 1e-9)
    assert not r.passed and "shape" in r.note


def test_diagnostics_flag_bad_inertias_and_singular_subtrees() -> None:
    b = fd.ModelBuilder("bad")
    good = fd.SpatialInertia.box(1.0, [0.1, 0.2, 0.3])
    # principal moments (1, 1, 3) break the triangle inequality
    bad = fd.SpatialInertia(1.0, [0, 0, 0], np.diag([1.0, 1.0, 3.0]))
    i0 = b.add_body("a", -1, fd.RevoluteJoint([0, 0, 1]), inertia=good)
    b.add_body("b", i0, fd.RevoluteJoint([0, 1, 0]), inertia=bad)
    b.add_body("c", i0, fd.RevoluteJoint([1, 0, 0]))  # massless leaf: singular mass matrix
    with pytest.warns(fd.PhysicalityWarning):
        model = b.build()
    diag = vdyn.model_diagnostics(model)
    assert [name for name, _ in diag.invalid_inertias] == ["b", "c"]
    assert "triangle" in diag.invalid_inertias[0][1]
    assert len(diag.singular_subtrees) == 1 and "'c_joint'" in diag.singular_subtrees[0]


def test_equivalent_ellipsoid_recovers_the_semi_axes() -> None:
    a, b, c, m = 0.3, 0.2, 0.1, 2.0
    moments = np.array([m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5])
    assert vdyn.equivalent_ellipsoid(m, moments) == pytest.approx([a, b, c])
    assert vdyn.equivalent_ellipsoid(m, np.array([1.0, 1.0, 3.0])) is None  # triangle inequality fails
    assert vdyn.equivalent_ellipsoid(0.0, moments) is None


def test_html_report_shows_every_link(tmp_path: Any) -> None:
    from featherdyn.verify.html import reports_to_html

    report = verify.run("two_link_arm", samples=2, algebra=False)
    page = reports_to_html([report])
    assert page.count("<ellipse") == 2 and "link1" in page and "link2" in page
    assert page.count("<circle") == sum(len(r.sample_errors) for r in report.results)
