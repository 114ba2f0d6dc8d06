"""``featherdyn verify``'s rows of the issue-30 derivatives (``featherdyn.verify.derivatives``).

They pass on featherdyn against Pinocchio (fixed and floating bases, a robot whose hands have no mass), and a
planted convention mistake fails its row with the cause named: rows ``[v; ω]`` or ``[p; k]``, another reference
frame, Pinocchio's LOCAL_WORLD_ALIGNED convention, spatial for classical, a transposed matrix, the external
forces' sign; the second order's rows fail on a tensor with two indices exchanged.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import featherdyn as fd

pin = pytest.importorskip("pinocchio")

from _models import pinocchio_pair  # noqa: E402

from featherdyn.verify import derivatives as vder  # noqa: E402
from featherdyn.verify.bridge import SWAP6  # noqa: E402


def _states(name: str, floating: bool, n: int = 3, seed: int = 4) -> vder.States:
    model, pm, pd, jm = pinocchio_pair(name, floating)
    rng = np.random.default_rng(seed)
    q = fd.random_configuration(model, rng, n)
    v, a, tau = rng.normal(size=(3, n, model.nv))
    fext = rng.normal(size=(n, model.nbodies, 6))
    cond = float(np.max(np.linalg.cond(fd.crba(model, q))))
    return vder.States(model, pm, pd, jm, q, v, a, tau, fext, cond)


def _frame_rows(st: vder.States, frame: str) -> list[vder.Row]:
    fid = st.pin_model.getFrameId(frame)
    return vder.frame_rows(st.model, st.model.resolve_frame(frame), fid)


def _row(rows: list[vder.Row], *words: str) -> vder.Row:
    found = [r for r in rows if all(w in r.quantity for w in words)]
    assert len(found) == 1, [r.quantity for r in found]
    return found[0]


@pytest.mark.parametrize(("name", "floating", "frame"), [("panda", False, "panda_hand"), ("solo12", True, "FL_FOOT")])
def test_rows_pass_against_pinocchio(name: str, floating: bool, frame: str) -> None:
    st = _states(name, floating)
    rows = [*vder.DERIVATIVE_ROWS, *_frame_rows(st, frame)]
    results = vder.derivative_checks(st, rows, 1e-9)
    assert len(results) == len(vder.DERIVATIVE_ROWS) + 11  # 3 references × 3 kinds + 2 points
    failed = [(r.quantity, r.max_rel, r.note) for r in results if not r.passed]
    assert not failed
    assert all(r.max_rel < 1e-12 and r.max_abs > 0 for r in results)  # compared, not skipped or trivially zero


def test_run_carries_the_rows_and_passes() -> None:
    report = fd.verify.run("panda", samples=3, algebra=False)
    assert report.passed, report.to_table()
    names = [r.quantity for r in report.results]
    for needle in ("generalized_gravity_derivatives", "static_torque_derivatives", "centroidal_dynamics_derivatives",
                   "center_of_mass_derivatives dcdot_dq", "LOCAL_WORLD_ALIGNED at a point",
                   "rnea_second_derivatives d2tau_dq2", "aba_second_derivatives d2ddq_dqdtau"):
        assert any(needle in n for n in names), needle
    assert len(names) == len(set(names))


def test_massless_subtrees_are_zero_columns_not_pinocchios_nan() -> None:
    """Pinocchio's getCenterOfMassVelocityDerivatives divides by each subtree's mass: 0/0 on romeo's hands."""
    st = _states("romeo", False, n=2)
    pm, pd, jm = st.pin_model, st.pin_data, st.jmap
    pin.centerOfMass(pm, pd, st.qp[0], st.vp[0])
    raw = np.asarray(pin.getCenterOfMassVelocityDerivatives(pm, pd))
    assert not np.isfinite(raw).all()  # Pinocchio's own values are NaN there
    row = _row(list(vder.DERIVATIVE_ROWS), "dcdot_dq")
    (r,) = vder.derivative_checks(st, [row], 1e-9)
    assert r.passed, r.note
    # and the columns are zero by central differences of ċ along those joints (an independent check)
    k = next(i for i in range(st.model.nv) if not np.isfinite(raw[:, jm.v_perm[i]]).all())
    step = np.zeros(st.model.nv)
    step[k] = 1e-6
    cdot = [fd.center_of_mass(st.model, fd.integrate(st.model, st.q[0], s * step), st.v[0]).velocity for s in (1, -1)]
    assert np.abs((cdot[0] - cdot[1]) / 2e-6).max() < 1e-8


def _planted(row: vder.Row, mistake: Callable[[vder.States, np.ndarray], np.ndarray]) -> vder.Row:
    return dataclasses.replace(row, ours=lambda st: mistake(st, np.asarray(row.ours(st))))


def _swap_rows(st: vder.States, x: np.ndarray) -> np.ndarray:
    return x[..., SWAP6, :]


def _lwa_origin_fixed(st: vder.States, x: np.ndarray) -> np.ndarray:
    """featherdyn's LWA dv_dq, dv_dv with Pinocchio's convention: the linear rows lose ω × J_v."""
    nv = st.model.nv
    w = fd.frame_velocity(st.model, st.q, st.v, "FL_FOOT", fd.LOCAL_WORLD_ALIGNED).vector[..., :3]
    out = x.copy()
    jv = x[..., 3:, nv:]
    out[..., 3:, :nv] -= np.cross(w[:, None, :], np.swapaxes(jv, -1, -2)).swapaxes(-1, -2)
    return out


def _in_world(st: vder.States, x: np.ndarray) -> np.ndarray:
    k = fd.kinematics_derivatives(st.model, st.q, st.v, st.a, "FL_FOOT", fd.WORLD)
    return np.concatenate([k.dv_dq, k.dv_dv], axis=-1)


def _spatial(st: vder.States, x: np.ndarray) -> np.ndarray:
    k = fd.kinematics_derivatives(st.model, st.q, st.v, st.a, "FL_FOOT", fd.LOCAL)
    return np.concatenate([k.da_dq, k.da_dv, k.da_da], axis=-1)


def _reversed_forces(st: vder.States, x: np.ndarray) -> np.ndarray:
    return np.asarray(fd.static_torque_derivatives(st.model, st.q, -st.fext))


PLANTED: list[tuple[str, tuple[str, ...], Callable[[vder.States, np.ndarray], np.ndarray], str]] = [
    ("centroidal [p; k]", ("dhdot_dq",), _swap_rows, "[p; k]"),
    ("frame velocity [v; ω]", ("LOCAL dv_dq",), _swap_rows, "[v; ω]"),
    ("frame velocity in WORLD for LOCAL", ("LOCAL dv_dq",), _in_world, "in the WORLD frame"),
    ("Pinocchio's LWA", ("LOCAL_WORLD_ALIGNED dv_dq",), _lwa_origin_fixed, "origin fixed"),
    ("spatial for classical", ("LOCAL dac_dq",), _spatial, "of the spatial one"),
    ("gravity derivatives transposed", ("generalized_gravity",), lambda st, x: np.swapaxes(x, -1, -2), "transposed"),
    ("external forces reversed", ("static_torque",), _reversed_forces, "wrong sign"),
]


@pytest.mark.parametrize(("label", "words", "mistake", "named"), PLANTED, ids=[p[0] for p in PLANTED])
def test_a_planted_mistake_fails_with_its_cause_named(label: str, words: tuple[str, ...],
                                                       mistake: Callable[[vder.States, np.ndarray], np.ndarray],
                                                       named: str) -> None:
    st = _states("solo12", True)
    rows = [*vder.DERIVATIVE_ROWS, *_frame_rows(st, "FL_FOOT")]
    if "LOCAL dv_dq" in words or "LOCAL dac_dq" in words:
        row = next(r for r in rows if f" {words[0]}" in r.quantity and "at a point" not in r.quantity)
    else:
        row = _row(rows, *words)
    (good,) = vder.derivative_checks(st, [row], 1e-9)
    assert good.passed
    (bad,) = vder.derivative_checks(st, [_planted(row, mistake)], 1e-9)
    assert not bad.passed and named in bad.note, (label, bad.note)


def _exchange(fn: Any, field: str) -> Any:
    def wrapped(*args: Any, **kwargs: Any) -> Any:
        r = fn(*args, **kwargs)
        return r._replace(**{field: np.swapaxes(getattr(r, field), -1, -2)})
    return wrapped


@pytest.mark.parametrize(("function", "field"), [("rnea_second_derivatives", "d2tau_dq2"),
                                                 ("rnea_second_derivatives", "d2tau_dqdv"),
                                                 ("aba_second_derivatives", "d2ddq_dq2")])
def test_second_order_rows(monkeypatch: pytest.MonkeyPatch, function: str, field: str) -> None:
    """They pass as they are; with j and k exchanged (the free-flyer's columns do not commute) the row fails."""
    st = _states("solo12", True, n=2)
    good = vder.second_order_checks(st.model, st.q, st.v, st.a, st.tau, st.cond)
    assert len(good) == 8 and all(r.passed for r in good), [(r.quantity, r.max_rel) for r in good]
    assert all(r.max_rel < 1e-6 for r in good)
    monkeypatch.setattr(fd, function, _exchange(getattr(fd, function), field))
    bad = {r.quantity.split(" vs ")[0]: r for r in vder.second_order_checks(st.model, st.q, st.v, st.a, st.tau,
                                                                           st.cond)}
    r = bad[f"{function} {field}"]
    assert not r.passed, (r.quantity, r.max_rel)


def test_second_order_checks_a_spread_of_directions_on_large_trees() -> None:
    st = _states("talos_full_v2", True, n=1)
    assert st.model.nv > vder.SECOND_ORDER_DIRECTIONS
    rows = vder.second_order_checks(st.model, st.q, st.v, st.a, st.tau, st.cond)
    assert all(r.passed for r in rows) and all(f"of {st.model.nv} directions" in r.quantity for r in rows)
