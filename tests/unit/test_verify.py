"""The verification tool's Python API: it passes on correct code and catches injected bugs."""

from __future__ import annotations

import dataclasses
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


ONE_DOF = """<?xml version="1.0"?>
<robot name="one_dof">
  <link name="base"/>
  <link name="arm"><inertial><origin xyz="0.1 0 0"/><mass value="1.0"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""


def test_a_one_dof_fixed_base_robot_verifies(tmp_path: Any) -> None:
    # Pinocchio returns the 6×1 Jacobians of a one-joint model flattened to (6,)
    path = tmp_path / "one_dof.urdf"
    path.write_text(ONE_DOF, encoding="utf-8")
    report = verify.run(str(path), samples=2, algebra=False)
    assert report.passed, report.to_table()
    assert report.meta["nv"] == 1 and any(r.quantity.startswith("frame_jacobian") for r in report.results)


ROOT_JOINT = """<robot name="rj">
  <link name="base_link"/>
  <link name="torso"><inertial><mass value="2"/><origin xyz="0 0 0.1"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="root_joint" type="fixed"><parent link="base_link"/><child link="torso"/><origin xyz="0 0 0.5"/></joint>
  <link name="arm"><inertial><mass value="1"/><origin xyz="0.2 0 0"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="torso"/><child link="arm"/><origin xyz="0 0.1 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>
"""


def test_a_urdf_joint_named_root_joint_verifies_with_a_floating_base(tmp_path: Any) -> None:
    # issue 32 item 8 (armar4): featherdyn's free flyer is 'root_joint_1' (the URDF took 'root_joint'),
    # Pinocchio's is 'root_joint': the two free-flyer roots map to each other whatever their names
    path = tmp_path / "rj.urdf"
    path.write_text(ROOT_JOINT, encoding="utf-8")
    model = fd.load_urdf(path, floating_base=True)
    assert model.joint_names[0] == "root_joint_1"
    report = verify.run(str(path), floating_base=True, samples=2, algebra=False)
    assert report.passed, report.to_table()
    assert report.meta["nv"] == 7
    assert any(r.quantity.startswith("body placements") for r in report.results)


ICUB = [name for name in fd.list_robots() if "icub" in name.lower()]


def test_the_icub_models_are_in_the_library() -> None:
    assert ICUB, "the public iCub models (example-robot-data) should be in fd.list_robots()"


@pytest.mark.parametrize("name", ICUB)
def test_forward_dynamics_is_judged_by_its_backward_error(name: str) -> None:
    # cond(M) of the iCub models reaches 1e7–1e13 (light fingers): q̈ from featherdyn and Pinocchio then differ
    # far above 1e-9 although both solve M q̈ = τ − h to round-off
    report = verify.run(name, samples=10, algebra=False)
    assert report.passed, report.to_table()
    aba = next(r for r in report.results if r.quantity == "aba vs pin.aba")
    assert "backward error" in aba.criterion and "cond(M)" in aba.criterion
    assert "backward error" in report.to_table()
    from featherdyn.verify.html import reports_to_html

    assert "backward error" in reports_to_html([report])
    assert "backward error" in json.loads(report.to_json())["results"][[r.quantity for r in report.results]
                                                                      .index("aba vs pin.aba")]["criterion"]


def test_a_wrong_forward_dynamics_still_fails_on_an_ill_conditioned_robot(monkeypatch: pytest.MonkeyPatch) -> None:
    orig = fd.aba

    def aba_plus(model: fd.Model, q: np.ndarray, v: np.ndarray, tau: np.ndarray, *args: Any, **kw: Any) -> np.ndarray:
        return orig(model, q, v, tau, *args, **kw) + 1e-3  # a constant offset: M q̈ + h − τ no longer vanishes

    monkeypatch.setattr(vdyn.fd, "aba", aba_plus)
    report = verify.run(ICUB[0], samples=3, algebra=False)
    assert "aba vs pin.aba" in {r.quantity for r in report.failures}


def test_a_tolerance_below_round_off_is_named_as_such() -> None:
    report = verify.run("two_link_arm", samples=2, tol=1e-18, algebra=False)
    assert report.failures
    for r in report.failures:
        assert "round-off" in r.note, (r.quantity, r.note)
        assert "gravity" not in r.note and "triangle" not in r.note, (r.quantity, r.note)


def test_the_likely_cause_is_the_one_that_explains_the_numbers(monkeypatch: pytest.MonkeyPatch) -> None:
    rnea, crba = fd.rnea, fd.crba

    def rnea_flipped(model: fd.Model, *args: Any, **kw: Any) -> np.ndarray:
        return rnea(dataclasses.replace(model, gravity=-np.asarray(model.gravity)), *args, **kw)

    def crba_upper(model: fd.Model, q: np.ndarray, *args: Any, **kw: Any) -> np.ndarray:
        return np.triu(crba(model, q, *args, **kw))

    monkeypatch.setattr(vdyn.fd, "rnea", rnea_flipped)
    monkeypatch.setattr(vdyn.fd, "crba", crba_upper)
    report = verify.run("panda", samples=2, algebra=False)
    notes = {r.quantity: r.note for r in report.failures}
    assert "gravity" in notes["rnea vs pin.rnea"] and "reversed" in notes["rnea vs pin.rnea"]
    assert "upper triangle" in notes["crba vs pin.crba"]

    monkeypatch.setattr(vdyn.fd, "rnea", _wrong(rnea, 1.0 + 1e-6))
    monkeypatch.setattr(vdyn.fd, "crba", _wrong(crba, 1.0 + 1e-6))
    report = verify.run("panda", samples=2, algebra=False)
    notes = {r.quantity: r.note for r in report.failures}
    for quantity in ("rnea vs pin.rnea", "crba vs pin.crba"):
        assert "gravity" not in notes[quantity] and "triangle" not in notes[quantity], notes[quantity]
        assert "largest difference" in notes[quantity]


def test_the_algebra_checks_name_a_cause_only_when_it_reproduces_the_numbers(monkeypatch: pytest.MonkeyPatch) -> None:
    from featherdyn.verify import algebra

    orig = algebra.rot.quat_to_matrix
    monkeypatch.setattr(algebra.rot, "quat_to_matrix", lambda q, *a, **k: orig(np.asarray(q)[..., [1, 2, 3, 0]], *a, **k))
    failed = {r.quantity: r.note for r in algebra.algebra_checks(samples=4) if not r.passed}
    assert "(w, x, y, z)" in failed["quat_to_matrix vs Quaternion.toRotationMatrix"]
    monkeypatch.setattr(algebra.rot, "quat_to_matrix", orig)
    failed = {r.quantity: r.note for r in algebra.algebra_checks(samples=4, tol=1e-18) if not r.passed}
    assert failed and all("round-off" in note for note in failed.values()), failed


def test_the_table_repeats_what_the_loader_said(tmp_path: Any) -> None:
    # issue 32 item 6: a misspelt attribute verified 119/119 without a word; the table now says what the loader said
    path = tmp_path / "rpyy.urdf"
    path.write_text(ROOT_JOINT.replace('<origin xyz="0 0 0.1"/>', '<origin xyz="0 0 0.1" rpyy="0 0 1"/>', 1),
                    encoding="utf-8")
    report = verify.run(str(path), samples=2, algebra=False)
    assert report.passed, report.to_table()
    table = report.to_table()
    assert "loader warning:\n" in table
    assert "line 3: <origin> attribute 'rpyy' (did you mean 'rpy'?)" in table.split("loader warning:", 1)[1]
