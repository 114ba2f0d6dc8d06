"""``fd.verify.check_values``: the user's numbers against featherdyn, and the diagnosis of a mismatch.

Correct values come from featherdyn (featherdyn convention) or from Pinocchio
itself (Pinocchio convention, and every injected suspect that Pinocchio can
produce on its own: world-aligned base velocity, classical acceleration,
another gravity, (cos, sin) continuous joints, its joint order). Each suspect
injected on purpose must be named alone by the diagnosis, and the corrected
comparison must pass; noise above the tolerance must fail with no diagnosis.
"""

from __future__ import annotations

import io
import json
import os
import warnings
import zipfile
from collections.abc import Callable
from functools import cache
from typing import Any

import numpy as np
import pytest
from _models import random_q, tree

import featherdyn as fd
from featherdyn.verify import check_values, resolve_robot
from featherdyn.verify.bridge import JointMap
from featherdyn.verify.check import SUSPECTS, CheckReport, ValuesError

pin = pytest.importorskip("pinocchio")

Values = dict[str, np.ndarray]


# --------------------------------------------------------------------------
# robots and correct values
# --------------------------------------------------------------------------


@cache
def robot(name: str, floating_base: bool) -> tuple[fd.Model, Any, JointMap]:
    """The featherdyn model, the Pinocchio model (from the same URDF) and the joint map."""
    path = str(resolve_robot(name)[1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_urdf(path, floating_base=floating_base)
        pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating_base else pin.buildModelFromUrdf(path)
    return model, pm, JointMap(model, pm)


def fd_values(model: fd.Model, n: int | None = 4, seed: int = 0) -> Values:
    """Correct values in the featherdyn convention, computed by featherdyn (``n=None``: one state)."""
    rng = np.random.default_rng(seed)
    size = () if n is None else (n,)
    q = fd.random_configuration(model, rng, size=size)
    v = rng.normal(size=size + (model.nv,))
    a = rng.normal(size=size + (model.nv,))
    tau = fd.rnea(model, q, v, a)
    return {"q": q, "v": v, "a": a, "tau": tau, "M": fd.crba(model, q), "ddq": fd.aba(model, q, v, tau)}


def pin_values(pm: Any, n: int = 4, seed: int = 0, gravity: Any = None) -> Values:
    """Correct values in the Pinocchio convention, computed by Pinocchio state by state."""
    np.random.seed(seed)  # pin.randomConfiguration draws from NumPy's global generator
    rng = np.random.default_rng(seed)
    pm = pm.copy()
    if gravity is not None:
        pm.gravity = pin.Motion(np.asarray(gravity, dtype=float), np.zeros(3))
    lo, hi = pm.lowerPositionLimit.copy(), pm.upperPositionLimit.copy()
    lo[~np.isfinite(lo) | (np.abs(lo) > 1e10)] = -1.0  # the free-flyer position is unbounded
    hi[~np.isfinite(hi) | (np.abs(hi) > 1e10)] = 1.0
    pd = pm.createData()
    out: dict[str, list[np.ndarray]] = {k: [] for k in ("q", "v", "a", "tau", "M", "ddq")}
    for _ in range(n):
        q = pin.randomConfiguration(pm, lo, hi)
        v, a = rng.normal(size=pm.nv), rng.normal(size=pm.nv)
        tau = pin.rnea(pm, pd, q, v, a).copy()
        out["q"].append(q)
        out["v"].append(v)
        out["a"].append(a)
        out["tau"].append(tau)
        out["M"].append(pin.crba(pm, pd, q).copy())
        out["ddq"].append(pin.aba(pm, pd, q, v, tau).copy())
    return {k: np.array(x) for k, x in out.items()}


def to_fd(jm: JointMap, vals: Values) -> Values:
    """Pinocchio-convention values in the featherdyn convention (through the bridge)."""
    out = {"q": jm.q_from_pin(vals["q"]), "M": jm.matrix_from_pin(vals["M"])}
    out.update({k: jm.v_from_pin(vals[k]) for k in ("v", "a", "tau", "ddq")})
    return out


def base_rotation(pm: Any, q_pin: np.ndarray) -> np.ndarray:
    """`(N, 3, 3)` orientation of the free-flyer (joint 1) in the world, from Pinocchio."""
    pd = pm.createData()
    out = []
    for q in q_pin:
        pin.forwardKinematics(pm, pd, q)
        out.append(pd.oMi[1].rotation.copy())
    return np.array(out)


def assert_passed(report: CheckReport) -> None:
    assert report.passed, report.to_text()
    assert report.diagnosis == []
    assert report.results and all(r.passed for r in report.results)


def assert_diagnosis(report: CheckReport, *suspects: str) -> None:
    """The values failed; exactly one reading explains them, made of exactly ``suspects``; it passes."""
    assert not report.passed, report.to_text()
    assert [f.suspects for f in report.diagnosis] == [tuple(suspects)], report.to_text()
    finding = report.diagnosis[0]
    assert finding.results and all(r.passed for r in finding.results), report.to_text()
    assert {r.quantity for r in finding.results} >= {r.quantity for r in report.results if r.quantity != "q layout"}
    text = report.to_text()
    for s in suspects:
        assert f"suspect: {' + '.join(suspects)}" in text
        assert s in SUSPECTS


# --------------------------------------------------------------------------
# correct values pass
# --------------------------------------------------------------------------


@pytest.mark.parametrize("name, floating_base", [("panda", False), ("solo12", True), ("double_pendulum_continuous", False),
                                                 ("double_pendulum_continuous", True)])
@pytest.mark.parametrize("n", [None, 3], ids=["one_state", "batch"])
def test_featherdyn_values_pass(name: str, floating_base: bool, n: int | None) -> None:
    model, _, _ = robot(name, floating_base)
    report = check_values(fd_values(model, n), name, floating_base=floating_base)
    assert_passed(report)
    assert [r.quantity for r in report.results] == ["M vs fd.crba(q)", "tau vs fd.rnea(q, v, a)",
                                                    "ddq: tau vs fd.rnea(q, v, ddq)"]
    assert report.meta["states"] == (1 if n is None else n) and report.meta["batched"] == (n is not None)


@pytest.mark.parametrize("name, floating_base", [("solo12", True), ("double_pendulum_continuous", True),
                                                 ("talos_reduced", True)])
def test_pinocchio_values_pass_in_pinocchio_convention(name: str, floating_base: bool) -> None:
    _model, pm, _ = robot(name, floating_base)
    vals = pin_values(pm, n=3)
    assert_passed(check_values(vals, name, floating_base=floating_base, convention="pinocchio"))
    one = {k: x[0] for k, x in vals.items()}
    assert_passed(check_values(one, name, floating_base=floating_base, convention="pinocchio"))


def test_npz_path_and_model_object(tmp_path: Any) -> None:
    model, _, _ = robot("solo12", True)
    vals = fd_values(model)
    np.savez(tmp_path / "v.npz", **vals)
    report = check_values(tmp_path / "v.npz", "solo12", floating_base=True)
    assert_passed(report)
    assert report.meta["source"] == str(tmp_path / "v.npz")
    assert_passed(check_values(vals, model))  # a Model instead of a name


def test_subsets_of_keys() -> None:
    model, _, _ = robot("panda", False)
    vals = fd_values(model)
    only_m = check_values({"q": vals["q"], "M": vals["M"]}, "panda")
    assert_passed(only_m)
    assert [r.quantity for r in only_m.results] == ["M vs fd.crba(q)"]
    fwd = check_values({k: vals[k] for k in ("q", "v", "tau", "ddq")}, "panda")
    assert_passed(fwd)
    assert [r.quantity for r in fwd.results] == ["ddq: tau vs fd.rnea(q, v, ddq)"]


# --------------------------------------------------------------------------
# noise: below the tolerance passes, above fails without a false diagnosis
# --------------------------------------------------------------------------


@pytest.mark.parametrize("name, floating_base", [("panda", False), ("solo12", True)])
def test_noise_below_tol_and_float32_pass(name: str, floating_base: bool) -> None:
    model, _, _ = robot(name, floating_base)
    vals = fd_values(model)
    rng = np.random.default_rng(1)
    noisy = {k: x * (1 + 1e-8 * rng.standard_normal(x.shape)) if k != "q" else x for k, x in vals.items()}
    assert_passed(check_values(noisy, name, floating_base=floating_base))
    f32 = {k: x.astype(np.float32) for k, x in vals.items()}
    assert_passed(check_values(f32, name, floating_base=floating_base))
    # the same float32 values held to float64's standard fail, and the report says round-off may be why
    strict = check_values(f32, name, floating_base=floating_base, tol=1e-12)
    assert not strict.passed and strict.diagnosis == []
    assert "the values are float32" in strict.summary and strict.meta["dtypes"]["tau"] == "float32"


@pytest.mark.parametrize("name, floating_base", [("panda", False), ("solo12", True)])
def test_noise_above_tol_fails_without_diagnosis(name: str, floating_base: bool) -> None:
    model, _, _ = robot(name, floating_base)
    vals = fd_values(model)
    rng = np.random.default_rng(2)
    noisy = {k: x + 1e-3 * rng.standard_normal(x.shape) if k in ("tau", "M", "ddq") else x for k, x in vals.items()}
    report = check_values(noisy, name, floating_base=floating_base)
    assert not report.passed
    assert report.diagnosis == [], report.to_text()
    assert report.summary.startswith("no usual suspect explains it; the largest discrepancy is in ")
    assert "no usual suspect explains it" in report.to_text()


def test_largest_discrepancy_names_joint_and_state() -> None:
    model, _, _ = robot("panda", False)
    vals = {k: fd_values(model, n=5)[k] for k in ("q", "v", "a", "tau")}
    vals["tau"][3, model.joint_id("panda_joint4")] += 0.5
    report = check_values(vals, "panda")
    assert report.diagnosis == []
    assert "joint 'panda_joint4' at state 3" in report.summary
    assert report.largest_discrepancy is not None
    assert report.largest_discrepancy["joint"] == "panda_joint4"
    assert report.largest_discrepancy["state"] == 3
    assert report.largest_discrepancy["quantity"] == "tau"


# --------------------------------------------------------------------------
# each suspect injected on purpose is named, alone, and the corrected comparison passes
# --------------------------------------------------------------------------


def _swap_ff_block(x: np.ndarray, axes: tuple[int, ...] = (-1,)) -> np.ndarray:
    idx = np.r_[3:6, 0:3, 6 : x.shape[-1]]
    for ax in axes:
        x = np.take(x, idx, axis=ax)
    return x


@pytest.mark.parametrize("convention", ["featherdyn", "pinocchio"])
def test_swapped_6d_halves(convention: str) -> None:
    model, pm, _jm = robot("solo12", True)
    vals = fd_values(model) if convention == "featherdyn" else pin_values(pm)
    bad = {k: _swap_ff_block(x) if k in ("v", "a", "tau", "ddq") else x for k, x in vals.items()}
    bad["M"] = _swap_ff_block(vals["M"], axes=(-1, -2))
    report = check_values(bad, "solo12", floating_base=True, convention=convention)
    assert_diagnosis(report, "swapped_6d_halves")
    expected_order = "linear first" if convention == "featherdyn" else "angular first"
    assert expected_order in report.diagnosis[0].explanation


def _world_aligned(pm: Any, vals: Values) -> Values:
    """Pinocchio-convention values with the free-flyer block LOCAL_WORLD_ALIGNED, from Pinocchio's own frame algebra."""
    pd = pm.createData()
    out = {k: x.copy() for k, x in vals.items()}
    R = base_rotation(pm, vals["q"])
    lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for s in range(len(vals["q"])):
        for vkey, akey in (("v", "a"), ("v", "ddq")):
            pin.forwardKinematics(pm, pd, vals["q"][s], vals[vkey][s], vals[akey][s])
            vel = pin.getVelocity(pm, pd, 1, lwa)
            acc = pin.getAcceleration(pm, pd, 1, lwa)
            classical = pin.getClassicalAcceleration(pm, pd, 1, lwa)
            out[vkey][s, :6] = np.r_[vel.linear, vel.angular]  # [ṗ; ω_w]
            out[akey][s, :6] = np.r_[classical.linear, acc.angular]  # [p̈; ω̇_w]
        out["tau"][s, :3] = R[s] @ vals["tau"][s, :3]
        out["tau"][s, 3:6] = R[s] @ vals["tau"][s, 3:6]
        T = np.eye(pm.nv)
        T[:3, :3] = T[3:6, 3:6] = R[s].T
        out["M"][s] = T.T @ vals["M"][s] @ T
    return out


@pytest.mark.parametrize("convention", ["featherdyn", "pinocchio"])
def test_world_frame_base_velocity(convention: str) -> None:
    _model, pm, jm = robot("solo12", True)
    world = _world_aligned(pm, pin_values(pm))
    if convention == "featherdyn":
        world = to_fd(jm, world)
    report = check_values(world, "solo12", floating_base=True, convention=convention)
    assert_diagnosis(report, "world_frame_base_velocity")
    assert "LOCAL_WORLD_ALIGNED" in report.diagnosis[0].explanation


def test_world_frame_in_pinocchio_order_is_two_suspects() -> None:
    """Pinocchio's LOCAL_WORLD_ALIGNED [ṗ; ω] given as featherdyn values: halves swapped and world frame."""
    _model, pm, jm = robot("solo12", True)
    world = _world_aligned(pm, pin_values(pm, n=3))
    bad = to_fd(jm, world)
    for k in ("v", "a", "tau", "ddq"):
        bad[k] = _swap_ff_block(bad[k])
    bad["M"] = _swap_ff_block(bad["M"], axes=(-1, -2))
    assert_diagnosis(check_values(bad, "solo12", floating_base=True), "swapped_6d_halves",
                     "world_frame_base_velocity")


def test_quaternion_wxyz_free_flyer() -> None:
    model, _, _ = robot("solo12", True)
    vals = fd_values(model)
    bad = dict(vals, q=vals["q"][:, [0, 1, 2, 6, 3, 4, 5, *range(7, model.nq)]])
    report = check_values(bad, "solo12", floating_base=True)
    assert_diagnosis(report, "quaternion_wxyz")
    assert "root_joint" in report.diagnosis[0].explanation


def test_quaternion_wxyz_spherical_joint() -> None:
    model = tree("fixed_branch_mixed")  # spherical root, more spherical and planar joints below
    rng = np.random.default_rng(3)
    q = random_q(model, rng, (3,))
    v, a = rng.normal(size=(3, model.nv)), rng.normal(size=(3, model.nv))
    vals = {"q": q, "v": v, "a": a, "tau": fd.rnea(model, q, v, a)}
    assert_passed(check_values(vals, model))
    sph = [model.idx_q[i] for i, j in enumerate(model.joints) if j.kind == "spherical"]
    assert sph
    bad_q = q.copy()
    for s in sph:
        bad_q[:, s : s + 4] = q[:, [s + 3, s, s + 1, s + 2]]
    report = check_values(dict(vals, q=bad_q), model)
    assert_diagnosis(report, "quaternion_wxyz")
    assert report.diagnosis[0].details["quaternion_joints"] == [model.joint_names[i] for i, j in
                                                                 enumerate(model.joints) if j.kind == "spherical"]


def test_quaternion_wxyz_only_the_free_flyer() -> None:
    """A free-flyer and spherical joints: only the base quaternion in (w, x, y, z) order is told apart."""
    model = tree("free_branch")
    assert {"free_flyer", "spherical"} <= {j.kind for j in model.joints}
    vals = fd_values(model, n=3)
    bad = dict(vals, q=vals["q"][:, [0, 1, 2, 6, 3, 4, 5, *range(7, model.nq)]])
    report = check_values(bad, model)
    assert_diagnosis(report, "quaternion_wxyz")
    assert report.diagnosis[0].details["quaternion_joints"] == [model.joint_names[0]]


@pytest.mark.parametrize("convention", ["featherdyn", "pinocchio"])
def test_classical_base_acceleration(convention: str) -> None:
    _model, pm, jm = robot("solo12", True)
    vals = pin_values(pm)
    pd = pm.createData()
    bad = {k: x.copy() for k, x in vals.items()}
    for s in range(len(vals["q"])):
        for akey in ("a", "ddq"):
            pin.forwardKinematics(pm, pd, vals["q"][s], vals["v"][s], vals[akey][s])
            bad[akey][s, :3] = pin.getClassicalAcceleration(pm, pd, 1, pin.ReferenceFrame.LOCAL).linear
    if convention == "featherdyn":
        bad = to_fd(jm, bad)
    assert_diagnosis(check_values(bad, "solo12", floating_base=True, convention=convention),
                     "classical_base_acceleration")


@pytest.mark.parametrize("gravity, words", [((0, 0, 9.81), "sign flipped"), ((0, 0, 0), "without gravity"),
                                            ((0, 0, -9.8), "|g| = 9.8")])
def test_gravity(gravity: tuple[float, ...], words: str) -> None:
    _, pm, _ = robot("panda", False)  # panda: featherdyn's layout is Pinocchio's
    vals = pin_values(pm, gravity=gravity)
    report = check_values(vals, "panda")
    assert_diagnosis(report, "gravity")
    assert np.allclose(report.diagnosis[0].details["gravity"], gravity)
    assert words in report.diagnosis[0].explanation


def test_gravity_on_floating_base_in_pinocchio_convention() -> None:
    _, pm, _ = robot("solo12", True)
    report = check_values(pin_values(pm, gravity=(0, 0, -9.80665)), "solo12", floating_base=True,
                          convention="pinocchio")
    assert_diagnosis(report, "gravity")
    assert np.allclose(report.diagnosis[0].details["gravity"], (0, 0, -9.80665))


def test_continuous_as_cos_sin_under_featherdyn_convention() -> None:
    model, pm, _jm = robot("double_pendulum_continuous", False)
    vals = pin_values(pm)  # q: (cos, sin) per joint, nq = 4 where featherdyn's is 2
    assert vals["q"].shape[1] == 4 and model.nq == 2
    report = check_values(vals, "double_pendulum_continuous")
    assert_diagnosis(report, "continuous_layout")
    assert report.results[0].quantity == "q layout" and not report.results[0].passed
    assert "(cos θ, sin θ)" in report.diagnosis[0].explanation
    assert report.diagnosis[0].details["continuous_joints"] == ["joint1", "joint2"]


def test_continuous_as_angle_under_pinocchio_convention() -> None:
    model, _, _ = robot("double_pendulum_continuous", True)
    report = check_values(fd_values(model), "double_pendulum_continuous", floating_base=True, convention="pinocchio")
    # featherdyn's values in Pinocchio's convention: angles, and the free-flyer halves the other way round
    assert_diagnosis(report, "continuous_layout", "swapped_6d_halves")


def test_continuous_plus_gravity() -> None:
    _, pm, _ = robot("double_pendulum_continuous", False)
    report = check_values(pin_values(pm, gravity=(0, 0, 0)), "double_pendulum_continuous")
    assert_diagnosis(report, "continuous_layout", "gravity")


def _permute(model: fd.Model, vals: Values, order: list[int]) -> Values:
    """featherdyn-convention values with the joints in ``order`` (one-dof joints only)."""
    qi = np.array([model.idx_q[i] for i in order])
    vi = np.array([model.idx_v[i] for i in order])
    out = {"q": vals["q"][:, qi], "M": vals["M"][:, vi][:, :, vi]}
    out.update({k: vals[k][:, vi] for k in ("v", "a", "tau", "ddq")})
    return out


@pytest.mark.parametrize("which", ["reverse", "alphabetical"])
def test_joint_order(which: str) -> None:
    model, _, _ = robot("panda", False)
    order = list(range(model.nbodies))[::-1] if which == "reverse" else \
        sorted(range(model.nbodies), key=lambda i: model.joint_names[i])
    report = check_values(_permute(model, fd_values(model), order), "panda")
    assert_diagnosis(report, "joint_order")
    assert report.diagnosis[0].details["joint_order"] == which
    assert report.diagnosis[0].details["joints"] == [model.joint_names[i] for i in order]


def test_joint_order_keeps_the_free_flyer_first() -> None:
    model, _, _ = robot("solo12", True)
    vals = fd_values(model)
    legs_q, legs_v = np.arange(7, model.nq)[::-1], np.arange(6, model.nv)[::-1]
    qi, vi = np.r_[0:7, legs_q], np.r_[0:6, legs_v]
    bad = {"q": vals["q"][:, qi], "M": vals["M"][:, vi][:, :, vi]}
    bad.update({k: vals[k][:, vi] for k in ("v", "a", "tau", "ddq")})
    report = check_values(bad, "solo12", floating_base=True)
    assert_diagnosis(report, "joint_order")
    assert report.diagnosis[0].details["joints"][0] == "root_joint"
    assert report.diagnosis[0].details["joint_order"] == "reverse"


def test_pinocchio_joint_order_under_featherdyn_convention() -> None:
    model, pm, _ = robot("talos_reduced", False)
    assert list(pm.names)[1:] != list(model.joint_names)  # the two orders differ on this robot
    report = check_values(pin_values(pm, n=2), "talos_reduced")
    assert_diagnosis(report, "joint_order")
    assert report.diagnosis[0].details["joint_order"] == "pinocchio"


def test_featherdyn_joint_order_under_pinocchio_convention() -> None:
    model, _, _ = robot("talos_reduced", False)
    report = check_values(fd_values(model, n=2), "talos_reduced", convention="pinocchio")
    assert_diagnosis(report, "joint_order")
    assert report.diagnosis[0].details["joint_order"] == "featherdyn"


@pytest.mark.parametrize("triangle", ["upper", "lower"])
def test_mass_matrix_triangle(triangle: str) -> None:
    model, _, _ = robot("panda", False)
    vals = fd_values(model)
    vals["M"] = np.triu(vals["M"]) if triangle == "upper" else np.tril(vals["M"])
    report = check_values(vals, "panda")
    assert_diagnosis(report, "mass_matrix_triangle")
    assert report.diagnosis[0].details["triangle"] == triangle
    assert [r.passed for r in report.results] == [False, True, True]  # only M was wrong


def test_upper_triangle_in_pinocchio_order() -> None:
    """The triangle is the user's, in the user's joint order (talos: Pinocchio's order differs)."""
    _, pm, _ = robot("talos_reduced", False)
    vals = pin_values(pm, n=2)
    vals["M"] = np.triu(vals["M"])
    assert_diagnosis(check_values(vals, "talos_reduced", convention="pinocchio"), "mass_matrix_triangle")


# --------------------------------------------------------------------------
# the report
# --------------------------------------------------------------------------


def test_report_dict_and_json() -> None:
    model, _, _ = robot("panda", False)
    vals = fd_values(model)
    vals["M"] = np.triu(vals["M"])
    report = check_values(vals, "panda", tol=1e-7)
    d = json.loads(report.to_json())
    assert d["passed"] is False
    assert d["meta"]["tol"] == 1e-7 and d["meta"]["robot"] == "panda"
    assert d["diagnosis"][0]["suspect"] == "mass_matrix_triangle"
    assert all(r["passed"] for r in d["diagnosis"][0]["results"])
    assert [r["passed"] for r in d["results"]] == [False, True, True]
    assert report.to_dict()["summary"] == "explained by mass_matrix_triangle"


def test_report_json_with_infinite_errors() -> None:
    _, pm, _ = robot("double_pendulum_continuous", False)
    d = json.loads(check_values(pin_values(pm), "double_pendulum_continuous").to_json())
    assert d["results"][0]["max_rel"] == "inf"


# --------------------------------------------------------------------------
# usage errors: one line naming the key and the expected shape
# --------------------------------------------------------------------------


def _vals() -> Values:
    return fd_values(robot("panda", False)[0], n=3)


Mutation = Callable[[Values], Values]


@pytest.mark.parametrize("mutate, error, words", [
    (lambda d: {k: x for k, x in d.items() if k != "q"}, ValuesError, "missing key 'q'"),
    (lambda d: {k: x for k, x in d.items() if k != "v"}, ValuesError, "missing key 'v'"),
    (lambda d: {k: d[k] for k in ("q", "v", "tau")}, ValuesError, "missing key 'a'"),
    (lambda d: {k: d[k] for k in ("q", "v", "a", "ddq")}, ValuesError, "missing key 'tau'"),
    (lambda d: {k: d[k] for k in ("q", "v", "a")}, ValuesError, "nothing to check"),
    (lambda d: dict(d, tau=d["tau"][:, :8]), fd.ShapeError, "tau: expected shape (9,) for one state or (N, 9)"),
    (lambda d: dict(d, M=d["M"][:, :, :8]), fd.ShapeError, "M: expected shape (9, 9) for one state or (N, 9, 9)"),
    (lambda d: dict(d, q=d["q"][:, :5]), fd.ShapeError, "q: expected shape (9,)"),
    (lambda d: dict(d, q=np.zeros((3, 16))), fd.ShapeError, "16 is nq with --floating-base"),
    (lambda d: dict(d, tau=d["tau"][:2]), fd.ShapeError, "batch sizes differ"),
    (lambda d: dict(d, tau=d["tau"][0]), fd.ShapeError, "tau is one state"),
    (lambda d: dict(d, v=np.where(np.arange(9) == 4, np.nan, d["v"])), fd.NonFiniteError,
     "v: non-finite value nan at state 0, index 4"),
    (lambda d: dict(d, a=d["a"].astype(complex)), fd.DTypeError, "a: expected real numbers"),
])
def test_usage_errors(mutate: Mutation, error: type[Exception], words: str) -> None:
    with pytest.raises(error) as info:
        check_values(mutate(_vals()), "panda")
    assert words in str(info.value)
    assert "\n" not in str(info.value)


def test_bad_arguments(tmp_path: Any) -> None:
    with pytest.raises(ValuesError, match="file not found"):
        check_values(tmp_path / "nope.npz", "panda")
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(ValuesError, match=r"not an \.npz archive"):
        check_values(tmp_path / "bad.npz", "panda")
    np.save(tmp_path / "one.npy", np.zeros(3))
    with pytest.raises(ValuesError, match=r"single \.npy array"):
        check_values(tmp_path / "one.npy", "panda")
    with pytest.raises(ValueError, match="convention"):
        check_values(_vals(), "panda", convention="drake")
    with pytest.raises(ValueError, match="tol"):
        check_values(_vals(), "panda", tol=0.0)
    with pytest.raises(fd.ModelError):
        check_values(_vals(), "no_such_robot_anywhere")


def _npz_declaring(path: Any, shape: tuple[int, ...], data: bytes) -> Any:
    """An .npz whose member q.npy declares ``shape`` (float64) and holds ``data`` after its header."""
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": shape})
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("q.npy", header.getvalue() + data)
    return path


@pytest.mark.parametrize("shape", [(10**12,), (1000,), (10**5, 10**5)])
def test_values_declaring_more_than_they_hold_are_refused_before_allocation(tmp_path: Any, shape: Any) -> None:
    path = _npz_declaring(tmp_path / "v.npz", shape, b"\0" * 80)
    with pytest.raises(ValuesError, match=r"array 'q' declares shape .* bytes\), more than its"):
        check_values(path, "panda")
    # the same header over enough data is read (and then checked as values: q alone is nothing to check)
    path = _npz_declaring(tmp_path / "w.npz", (10,), b"\0" * 80)
    with pytest.raises(ValuesError, match=r"nothing to check: .*\(given: q\)"):
        check_values(path, "panda")


@pytest.mark.skipif(not hasattr(os, "mkfifo") or not os.path.exists("/dev/zero"), reason="POSIX special files")
def test_values_from_a_pipe_or_a_device_are_refused_not_read_forever(tmp_path: Any) -> None:
    os.mkfifo(tmp_path / "pipe.npz")
    for path in (tmp_path / "pipe.npz", "/dev/zero"):
        with pytest.raises(ValuesError, match="not a regular file"):
            check_values(path, "panda")


def test_a_tolerance_below_round_off_is_named_as_such() -> None:
    _, pm, _ = robot("panda", False)
    report = check_values(pin_values(pm), "panda", convention="pinocchio", tol=1e-18)
    assert not report.passed and report.diagnosis == []
    assert "round-off" in report.summary and "suspect" not in report.summary, report.summary
    assert all("round-off" in r.note for r in report.results if not r.passed)
    assert "gravity" not in report.to_text() and "triangle" not in report.to_text()
