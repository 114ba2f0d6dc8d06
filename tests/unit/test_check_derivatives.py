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
