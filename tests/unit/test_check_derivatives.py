"""``featherdyn check`` on derivative matrices: the user's dtau_dq & co. and the convention that explains a mismatch."""

from __future__ import annotations

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import conventions as C
from featherdyn.verify.check import ValuesError, check_values


@pytest.fixture(scope="module")
def state() -> dict[str, np.ndarray]:
    model = fd.load_robot("solo12", floating_base=True)
    rng = np.random.default_rng(7)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    tau = fd.rnea(model, q, v, a)
    dq, dv, _ = fd.rnea_derivatives(model, q, v, a)
    ddq_dq, ddq_dv, _ = fd.aba_derivatives(model, q, v, tau)
    return {"q": q, "v": v, "a": a, "tau": tau, "dq": dq, "dv": dv, "ddq_dq": ddq_dq, "ddq_dv": ddq_dv,
            "model": model}  # type: ignore[dict-item]


def _check(state: dict, **derivs: np.ndarray):  # type: ignore[no-untyped-def]
    values = {k: state[k] for k in ("q", "v", "a", "tau")}
    return check_values({**values, **derivs}, "solo12", floating_base=True)


def test_featherdyns_own_derivatives_pass(state: dict) -> None:  # type: ignore[type-arg]
    rep = _check(state, dtau_dq=state["dq"], dtau_dv=state["dv"], dddq_dq=state["ddq_dq"], dddq_dv=state["ddq_dv"])
    assert rep.passed and len(rep.results) == 5  # tau and the four matrices


@pytest.mark.parametrize(("suspect", "key", "make"), [
    ("transposed", "dtau_dv", lambda s: s["dv"].T),
    ("world_tangent", "dtau_dq", lambda s: C.derivatives_to_parent_tangent(s["model"], s["q"], s["dq"])),
    ("linear_first_6d", "dtau_dq", lambda s: C.derivatives_to_pinocchio(s["model"], s["dq"])),
    ("quaternion_coordinates", "dtau_dq", lambda s: C.derivatives_to_coordinates(s["model"], s["q"], s["dq"])),
    ("missing_minv", "dddq_dq", lambda s: -fd.rnea_derivatives(s["model"], s["q"], s["v"],
                                                               fd.aba(s["model"], s["q"], s["v"], s["tau"]))[0]),
])
def test_each_convention_mix_up_is_named(state: dict, suspect: str, key: str, make) -> None:  # type: ignore[no-untyped-def,type-arg]
    rep = _check(state, **{key: make(state)})
    assert not rep.passed
    assert [f.suspect for f in rep.diagnosis] == [suspect], rep.summary
    assert all(r.passed for f in rep.diagnosis for r in f.results)


def test_an_unexplained_mismatch_says_so_and_bad_input_is_refused(state: dict) -> None:  # type: ignore[type-arg]
    rep = _check(state, dtau_dq=state["dq"] * 1.01)
    assert not rep.passed and not rep.diagnosis and "no usual suspect" in rep.summary
    with pytest.raises(ValuesError, match="missing key 'tau'"):
        check_values({"q": state["q"], "v": state["v"], "dddq_dq": state["ddq_dq"]}, "solo12", floating_base=True)
    with pytest.raises(fd.ShapeError, match="dtau_dv"):
        _check(state, dtau_dv=state["dv"][:, :5])


def test_a_layout_mistake_recompares_the_derivative_matrices_too(state: dict) -> None:  # type: ignore[type-arg]
    # issue 32 item 9: everything in Pinocchio's free-flyer order [v; ω] (v, a, tau and the derivative matrices'
    # rows and columns) declared as featherdyn's: the diagnosis is swapped_6d_halves, and its corrected table
    # re-compares every quantity given, the matrices at the corrected state, not tau alone
    model = state["model"]
    swap = np.arange(model.nv)
    swap[:6] = [3, 4, 5, 0, 1, 2]
    values = {"q": state["q"], "v": state["v"][swap], "a": state["a"][swap], "tau": state["tau"][swap],
              "dtau_dq": state["dq"][swap][:, swap], "dtau_dv": state["dv"][swap][:, swap]}
    rep = check_values(values, "solo12", floating_base=True)
    assert not rep.passed
    assert [f.suspect for f in rep.diagnosis] == ["swapped_6d_halves"], rep.summary
    corrected = rep.diagnosis[0].results
    assert [r.quantity.split()[0] for r in corrected] == ["tau", "dtau_dq", "dtau_dv"], rep.to_text()
    assert all(r.passed and r.group == "corrected" for r in corrected), rep.to_text()


def test_a_derivative_matrix_still_wrong_after_the_correction_shows_as_failed(state: dict) -> None:  # type: ignore[type-arg]
    # the corrected table is honest: a matrix that the reading does not fix stays a failed row
    model = state["model"]
    swap = np.arange(model.nv)
    swap[:6] = [3, 4, 5, 0, 1, 2]
    values = {"q": state["q"], "v": state["v"][swap], "a": state["a"][swap], "tau": state["tau"][swap],
              "dtau_dv": 1.01 * state["dv"][swap][:, swap]}
    rep = check_values(values, "solo12", floating_base=True)
    rows = {r.quantity.split()[0]: r for f in rep.diagnosis for r in f.results}
    assert "dtau_dv" in rows and not rows["dtau_dv"].passed, rep.to_text()


# ---------------------------------------------------------------------------------------------------------
# the issue-30 first-order quantities: gravity, centre of mass, centroidal momentum, a frame's motion.
# The planted values are Pinocchio's own (pinocchio_pair: the same URDF), raw or partly converted.
# ---------------------------------------------------------------------------------------------------------

FRAME = "FL_FOOT"


@pytest.fixture(scope="module")
def pin_state() -> dict[str, object]:
    pin = pytest.importorskip("pinocchio")
    from _models import pinocchio_pair

    model, pm, pd, jm = pinocchio_pair("solo12", True)
    rng = np.random.default_rng(11)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    qp, vp, ap = jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a)
    raw: dict[str, np.ndarray] = {}
    raw["dh_dq"], raw["dhdot_dq"], raw["dhdot_dv"], raw["dhdot_da"] = (
        np.asarray(x).copy() for x in pin.computeCentroidalDynamicsDerivatives(pm, pd, qp, vp, ap))
    raw["dc_dq"] = pin.jacobianCenterOfMass(pm, pd, qp).copy()
    pin.centerOfMass(pm, pd, qp, vp)
    raw["dcdot_dq"] = pin.getCenterOfMassVelocityDerivatives(pm, pd).copy()
    raw["dg_dq"] = pin.computeGeneralizedGravityDerivatives(pm, pd, qp).copy()
    pin.computeForwardKinematicsDerivatives(pm, pd, qp, vp, ap)
    fid = pm.getFrameId(FRAME)
    for name in ("LOCAL", "WORLD", "LOCAL_WORLD_ALIGNED"):
        ref = getattr(pin, name)
        dv = pin.getFrameVelocityDerivatives(pm, pd, fid, ref)
        da = pin.getFrameAccelerationDerivatives(pm, pd, fid, ref)
        raw[f"dv_dq {name}"], raw[f"dv_dv {name}"] = (np.asarray(x).copy() for x in dv)
        raw[f"da_dq {name}"], raw[f"da_dv {name}"], raw[f"da_da {name}"] = (np.asarray(x).copy() for x in da[1:])
    return {"model": model, "jm": jm, "q": q, "v": v, "a": a, "qp": qp, "vp": vp, "ap": ap, "raw": raw}


def _featherdyn_layout(s: dict, key: str, rows: bool = True, columns: bool = True) -> np.ndarray:  # type: ignore[type-arg]
    """Pinocchio's matrix with its 6 rows (``rows``) and its columns (``columns``) in featherdyn's layout."""
    m = s["raw"][key].copy()
    if rows and m.shape[0] == 6:
        m = m[[3, 4, 5, 0, 1, 2]]
    if columns:
        m = s["jm"].columns_from_pin(m) if m.shape[0] != s["model"].nv else s["jm"].matrix_from_pin(m)
    return m


def _check_ours(s: dict, reference: str = "LOCAL", **mats: np.ndarray):  # type: ignore[no-untyped-def,type-arg]
    return check_values({"q": s["q"], "v": s["v"], "a": s["a"], **mats}, "solo12", floating_base=True,
                        frame=FRAME, reference=reference)


def test_pinocchios_raw_matrices_pass_in_the_pinocchio_convention(pin_state: dict) -> None:  # type: ignore[type-arg]
    s = pin_state
    raw = s["raw"]
    for reference in ("LOCAL", "WORLD"):
        mats = {k: raw[k] for k in ("dh_dq", "dhdot_dq", "dhdot_dv", "dhdot_da", "dc_dq", "dcdot_dq", "dg_dq")}
        mats.update({k: raw[f"{k} {reference}"] for k in ("dv_dq", "dv_dv", "da_dq", "da_dv", "da_da")})
        rep = check_values({"q": s["qp"], "v": s["vp"], "a": s["ap"], **mats}, "solo12", floating_base=True,
                           convention="pinocchio", frame=FRAME, reference=reference)
        assert rep.passed and len(rep.results) == 12, rep.to_text()
        assert rep.meta["frame"] == FRAME and rep.meta["reference"] == reference


def test_featherdyn_layout_passes(pin_state: dict) -> None:  # type: ignore[type-arg]
    s = pin_state
    keys = ("dh_dq", "dhdot_dq", "dhdot_dv", "dhdot_da", "dc_dq", "dcdot_dq", "dg_dq")
    rep = _check_ours(s, "WORLD", **{k: _featherdyn_layout(s, k) for k in keys},
                      dv_dq=_featherdyn_layout(s, "dv_dq WORLD"), da_da=_featherdyn_layout(s, "da_da WORLD"))
    assert rep.passed, rep.to_text()


def _lwa_shifted(s: dict, key: str) -> np.ndarray:  # type: ignore[type-arg]
    """Pinocchio's LOCAL_WORLD_ALIGNED ∂v/∂q (∂a/∂q) made the function's own: ω × J_v (ω̇ × J_v) added."""
    import pinocchio as pin
    from _models import pinocchio_pair

    _, pm, pd, _ = pinocchio_pair("solo12", True)
    pin.forwardKinematics(pm, pd, s["qp"], s["vp"], s["ap"])
    fid = pm.getFrameId(FRAME)
    w = (pin.getFrameVelocity if key == "dv_dq" else pin.getFrameAcceleration)(
        pm, pd, fid, pin.LOCAL_WORLD_ALIGNED).angular
    m = _featherdyn_layout(s, f"{key} LOCAL_WORLD_ALIGNED")
    jv = _featherdyn_layout(s, "dv_dv LOCAL_WORLD_ALIGNED")[3:]
    m[3:] += np.cross(w, jv.T).T
    return m


PLANTED = [
    ("pk_rows", "dhdot_dq", "LOCAL", lambda s: _featherdyn_layout(s, "dhdot_dq", rows=False)),
    ("pinocchio_layout", "dh_dq", "LOCAL", lambda s: s["raw"]["dh_dq"]),
    ("linear_first_rows", "dv_dq", "LOCAL", lambda s: _featherdyn_layout(s, "dv_dq LOCAL", rows=False)),
    ("pinocchio_layout", "da_dv", "WORLD", lambda s: s["raw"]["da_dv WORLD"]),
    ("linear_first_6d", "dc_dq", "LOCAL", lambda s: s["raw"]["dc_dq"]),
    ("other_reference", "dv_dq", "LOCAL", lambda s: _featherdyn_layout(s, "dv_dq WORLD")),
    ("pinocchio_lwa", "dv_dq", "LOCAL_WORLD_ALIGNED", lambda s: _featherdyn_layout(s, "dv_dq LOCAL_WORLD_ALIGNED")),
    ("pinocchio_lwa", "da_dq", "LOCAL_WORLD_ALIGNED", lambda s: _featherdyn_layout(s, "da_dq LOCAL_WORLD_ALIGNED")),
    ("spatial_classical", "dac_dq", "LOCAL", lambda s: _featherdyn_layout(s, "da_dq LOCAL")),
    ("negated", "dg_dq", "LOCAL", lambda s: -_featherdyn_layout(s, "dg_dq")),
    ("transposed", "dg_dq", "LOCAL", lambda s: _featherdyn_layout(s, "dg_dq").T),
    ("quaternion_coordinates", "dcdot_dq", "LOCAL",
     lambda s: C.derivatives_to_coordinates(s["model"], s["q"], _featherdyn_layout(s, "dcdot_dq"))),
]


@pytest.mark.parametrize(("suspect", "key", "reference", "make"), PLANTED,
                         ids=[f"{p[0]}-{p[1]}" for p in PLANTED])
def test_each_new_convention_mix_up_is_named(pin_state: dict, suspect: str, key: str, reference: str,  # type: ignore[type-arg]
                                             make) -> None:  # type: ignore[no-untyped-def]
    rep = _check_ours(pin_state, reference, **{key: make(pin_state)})
    assert not rep.passed
    assert [f.suspect for f in rep.diagnosis] == [suspect], rep.to_text()
    assert all(r.passed for f in rep.diagnosis for r in f.results)


def test_lwa_made_the_functions_own_passes(pin_state: dict) -> None:  # type: ignore[type-arg]
    """With ω × J_v (ω̇ × J_v) added, Pinocchio's LOCAL_WORLD_ALIGNED matrices are featherdyn's (docs/derivatives.md)."""
    rep = _check_ours(pin_state, "LOCAL_WORLD_ALIGNED", dv_dq=_lwa_shifted(pin_state, "dv_dq"),
                      da_dq=_lwa_shifted(pin_state, "da_dq"))
    assert rep.passed, rep.to_text()


def test_new_keys_bad_input(pin_state: dict) -> None:  # type: ignore[type-arg]
    s = pin_state
    dh = _featherdyn_layout(s, "dh_dq")
    with pytest.raises(fd.ShapeError, match="transposed shape"):
        _check_ours(s, dh_dq=dh.T)
    with pytest.raises(fd.ShapeError, match=r"dc_dq: expected shape \(3, 18\)"):
        _check_ours(s, dc_dq=dh)
    with pytest.raises(ValuesError, match="name the frame"):
        check_values({"q": s["q"], "v": s["v"], "dv_dq": dh}, "solo12", floating_base=True)
    with pytest.raises(fd.ModelError, match="no_such_frame"):
        check_values({"q": s["q"], "v": s["v"], "dv_dq": dh}, "solo12", floating_base=True, frame="no_such_frame")
    with pytest.raises(fd.ShapeError, match="reference"):
        _check_ours(s, "SIDEWAYS", dv_dq=dh)
    with pytest.raises(ValuesError, match="missing key 'a'"):
        check_values({"q": s["q"], "v": s["v"], "dhdot_dq": dh}, "solo12", floating_base=True)
    with pytest.raises(fd.NonFiniteError, match="dh_dq"):
        _check_ours(s, dh_dq=np.where(dh == dh.max(), np.nan, dh))
