"""``featherdyn verify``'s rows of the derivatives added in issue 30, against Pinocchio, and the second order.

One table, :data:`DERIVATIVE_ROWS` (and :func:`frame_rows` for each frame checked): each row names featherdyn's
batched call, Pinocchio's call at one state converted to featherdyn's layout, the causes a mismatch is tried
against, and its tolerance (``tol``, or ``tol × cond(M)`` where the quantity carries ``M⁻¹``). Adding a
derivative is one :class:`Row`. Conventions converted at the boundary (``docs/derivatives.md``):

* joints by name, the free-flyer's ``[v; ω]`` columns: :class:`~featherdyn.verify.bridge.JointMap`; both
  libraries differentiate along the same tangent (``q ⊕ δ``, δ in the body frame);
* motion rows ``[v; ω]`` → ``[ω; v]``, centroidal rows ``[p; k]`` → ``[k; p]`` (:func:`from_pin6_rows`);
* LOCAL_WORLD_ALIGNED frame derivatives: Pinocchio's ``getFrame*Derivatives`` hold the frame's origin fixed;
  featherdyn differentiates the function itself, whose linear part refers to the moving origin: Pinocchio's
  linear rows gain ``ω × J_v`` (``∂v/∂q``) and ``ω̇ × J_v`` (``∂a/∂q``), all three from Pinocchio;
* the classical acceleration of a frame: in LOCAL and LOCAL_WORLD_ALIGNED its linear rows are Pinocchio's
  ``getPointClassicAccelerationDerivatives`` at the frame's origin (its angular rows the spatial
  acceleration's); in WORLD, ``∂a^c = ∂a + [0; ∂ω × v + ω × ∂v]`` from Pinocchio's WORLD derivatives.

The second order (``fd.rnea_second_derivatives``, ``fd.aba_second_derivatives``) has no Pinocchio Python
counterpart: :func:`second_order_checks` compares it with central differences of the analytical first order
along ``fd.integrate``'s tangent, ``q̇`` and ``τ`` (identities that need no oracle, as ``Ṁ − 2C``).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

import featherdyn as fd

from ..configuration import integrate
from ..errors import SingularMassMatrixError
from ..model import Model
from ..tolerances import VERIFY_ABA_DIFFERENCE_ROUNDING, VERIFY_SECOND_ORDER
from .bridge import SWAP6, JointMap, from_pin6_rows
from .pinocchio import PinModel, PinValue, require_pinocchio
from .report import COND_SCALED, Cause, CheckResult, compare, likely_cause

__all__ = ["States", "Row", "DERIVATIVE_ROWS", "frame_rows", "derivative_checks", "second_order_checks", "POINT",
           "SECOND_ORDER_TOL", "SECOND_ORDER_STATES", "SECOND_ORDER_DIRECTIONS",
           "ABA_DIFFERENCE_ROUNDING"]

#: the point of each checked frame (its own coordinates, metres) whose velocity and classical acceleration
#: derivatives are compared with Pinocchio's ``getPoint*Derivatives``
POINT = np.array([0.05, -0.04, 0.1])

#: relative tolerance of the central differences against the second order (:mod:`featherdyn.tolerances`)
SECOND_ORDER_TOL = VERIFY_SECOND_ORDER

_REFS = (("LOCAL", fd.LOCAL), ("WORLD", fd.WORLD), ("LOCAL_WORLD_ALIGNED", fd.LOCAL_WORLD_ALIGNED))


@dataclass
class States:
    """The sampled states on both sides: featherdyn's `(N, ·)` arrays and Pinocchio's model, data and arrays."""

    model: Model
    pin_model: PinModel
    pin_data: PinValue
    jmap: JointMap
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray
    fext: np.ndarray  # (N, nbodies, 6), [n; f] in each body's frame
    cond: float       # the worst cond(M) over the states

    def __post_init__(self) -> None:
        jm = self.jmap
        self.qp, self.vp, self.ap = jm.q_to_pin(self.q), jm.v_to_pin(self.v), jm.v_to_pin(self.a)
        self.n = self.q.shape[0]

    def pin_fext(self, s: int) -> list[PinValue]:
        """State ``s``'s external forces as Pinocchio's per-joint list (``[f; n]``, joint frames)."""
        pin = require_pinocchio()
        out = [pin.Force.Zero() for _ in range(self.pin_model.njoints)]
        for i, j in enumerate(self.jmap.joint_ids):
            out[j] = pin.Force(self.fext[s, i, 3:], self.fext[s, i, :3])
        return out


@dataclass(frozen=True)
class Row:
    """One comparison: featherdyn's values over all states against Pinocchio's, state by state.

    ``ours(st)`` is `(N, ...)`; ``theirs(st, s)`` Pinocchio's value at state ``s`` in featherdyn's layout;
    ``causes(st)`` the mistakes a mismatch is tried against; ``scaled``: the tolerance is ``tol × cond(M)``
    (the quantity carries M⁻¹); ``needs_mass``: skipped when the moving bodies have no mass.

    A row of the constrained or impulse dynamics' derivatives captures its constraints in its two functions
    (``verify/contacts.py`` builds them, as it builds Pinocchio's constraint models) and sets ``scaled``.
    """

    quantity: str
    ours: Callable[[States], np.ndarray]
    theirs: Callable[[States, int], np.ndarray]
    causes: Callable[[States], Sequence[Cause]] = lambda st: ()
    scaled: bool = False
    needs_mass: bool = False


def _transposed(ref: np.ndarray) -> np.ndarray:
    return np.swapaxes(ref, -1, -2)


def _rows_swapped(ref: np.ndarray) -> np.ndarray:
    return ref[..., SWAP6, :]


TRANSPOSED: Cause = ("featherdyn's matrix is Pinocchio's transposed", _transposed)
LINEAR_FIRST_ROWS: Cause = ("featherdyn's rows are [v; ω] (Pinocchio's order), not [ω; v]", _rows_swapped)
PK_ROWS: Cause = ("featherdyn's rows are [p; k] (Pinocchio's order), not [k; p]", _rows_swapped)


def _columns(st: States, m: PinValue, rows: int) -> np.ndarray:
    """Pinocchio's `(rows, nv)` matrix with featherdyn's columns (a one-DoF model's comes flattened to `(rows,)`)."""
    return st.jmap.columns_from_pin(np.asarray(m).copy().reshape(rows, st.model.nv))


def _stack(st: States, fn: Callable[[int], np.ndarray]) -> np.ndarray:
    return np.stack([np.asarray(fn(s), dtype=np.float64) for s in range(st.n)])


def _pin_gravity_derivatives(st: States, s: int) -> np.ndarray:
    pin = require_pinocchio()
    return st.jmap.matrix_from_pin(
        pin.computeGeneralizedGravityDerivatives(st.pin_model, st.pin_data, st.qp[s]).copy())


def _pin_static_torque_derivatives(st: States, s: int) -> np.ndarray:
    pin = require_pinocchio()
    return st.jmap.matrix_from_pin(
        pin.computeStaticTorqueDerivatives(st.pin_model, st.pin_data, st.qp[s], st.pin_fext(s)).copy())


def _pin_centroidal(field: int) -> Callable[[States, int], np.ndarray]:
    def theirs(st: States, s: int) -> np.ndarray:
        pin = require_pinocchio()
        out = pin.computeCentroidalDynamicsDerivatives(st.pin_model, st.pin_data, st.qp[s], st.vp[s], st.ap[s])
        return st.jmap.columns_from_pin(from_pin6_rows(np.asarray(out[field]).copy()))
    return theirs


def _pin_com_jacobian(st: States, s: int) -> np.ndarray:
    pin = require_pinocchio()
    return _columns(st, pin.jacobianCenterOfMass(st.pin_model, st.pin_data, st.qp[s]), 3)


def _pin_com_velocity_derivatives(st: States, s: int) -> np.ndarray:
    pin = require_pinocchio()
    pm, pd = st.pin_model, st.pin_data
    pin.centerOfMass(pm, pd, st.qp[s], st.vp[s])
    out = np.asarray(pin.getCenterOfMassVelocityDerivatives(pm, pd)).copy().reshape(3, pm.nv)
    # Pinocchio divides by each subtree's mass: the columns of a massless subtree (romeo's hands) are 0/0 there;
    # moving a massless subtree moves no mass, so those columns are zero
    for jid in range(1, pm.njoints):
        if pd.mass[jid] == 0:
            out[:, pm.idx_vs[jid] : pm.idx_vs[jid] + pm.nvs[jid]] = 0.0
    return st.jmap.columns_from_pin(out)


def _external_forces_reversed(st: States) -> Sequence[Cause]:
    # ∂(g + Σ Jᵀf)/∂q = 2 ∂g/∂q − ∂(g − Σ Jᵀf)/∂q, with Pinocchio's ∂g/∂q
    return [("featherdyn's external forces enter with the wrong sign (∂(g + Σ Jᵀf)/∂q)",
             lambda ref: 2 * _stack(st, lambda s: _pin_gravity_derivatives(st, s)) - ref)]


_CENTROIDAL = ("dh_dq", "dhdot_dq", "dhdot_dv", "dhdot_da")


def _centroidal(st: States, *, field: int) -> np.ndarray:
    return fd.centroidal_dynamics_derivatives(st.model, st.q, st.v, st.a)[field]


#: the rows that need no frame, in the order they are reported
DERIVATIVE_ROWS: tuple[Row, ...] = (
    Row("generalized_gravity_derivatives vs computeGeneralizedGravityDerivatives",
        lambda st: fd.generalized_gravity_derivatives(st.model, st.q), _pin_gravity_derivatives,
        lambda st: [TRANSPOSED, ("the gravity is reversed (featherdyn's ∂g/∂q is −Pinocchio's)", lambda ref: -ref)]),
    Row("static_torque_derivatives vs computeStaticTorqueDerivatives (f_ext)",
        lambda st: fd.static_torque_derivatives(st.model, st.q, st.fext), _pin_static_torque_derivatives,
        lambda st: [TRANSPOSED, *_external_forces_reversed(st)]),
    Row("center_of_mass_derivatives dc_dq vs jacobianCenterOfMass",
        lambda st: fd.center_of_mass_derivatives(st.model, st.q, st.v).dc_dq, _pin_com_jacobian, needs_mass=True),
    Row("center_of_mass_derivatives dcdot_dq vs getCenterOfMassVelocityDerivatives",
        lambda st: fd.center_of_mass_derivatives(st.model, st.q, st.v).dcdot_dq, _pin_com_velocity_derivatives,
        needs_mass=True),
    *(Row(f"centroidal_dynamics_derivatives {name} vs computeCentroidalDynamicsDerivatives",
          functools.partial(_centroidal, field=k), _pin_centroidal(k), lambda st: [PK_ROWS], needs_mass=True)
      for k, name in enumerate(_CENTROIDAL)),
)


# ---------------------------------------------------------------------------------------------------------
# a frame, in three references, and a point of it
# ---------------------------------------------------------------------------------------------------------

def _frame_derivatives(st: States, s: int, fid: int, rname: str) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Pinocchio's ``(∂v/∂q, ∂v/∂q̇)`` and ``(∂a/∂q, ∂a/∂q̇, ∂a/∂q̈)`` of frame ``fid`` at state ``s`` in
    featherdyn's layout, LOCAL_WORLD_ALIGNED as the derivative of the function (the moving origin's terms added)."""
    pin = require_pinocchio()
    pm, pd = st.pin_model, st.pin_data
    ref = getattr(pin, rname)
    pin.computeForwardKinematicsDerivatives(pm, pd, st.qp[s], st.vp[s], st.ap[s])
    pin.updateFramePlacements(pm, pd)

    def ours(m: np.ndarray) -> np.ndarray:
        return st.jmap.columns_from_pin(from_pin6_rows(np.asarray(m).copy()))

    vel = [ours(x) for x in pin.getFrameVelocityDerivatives(pm, pd, fid, ref)]
    acc = [ours(x) for x in pin.getFrameAccelerationDerivatives(pm, pd, fid, ref)]
    acc = acc[1:]  # (Pinocchio returns ∂v/∂q first)
    if rname == "LOCAL_WORLD_ALIGNED":
        omega = pin.getFrameVelocity(pm, pd, fid, ref).angular
        omega_dot = pin.getFrameAcceleration(pm, pd, fid, ref).angular
        jv = vel[1][3:]  # the Jacobian's linear rows (∂v/∂q̇)
        vel[0][3:] += np.cross(omega, jv.T).T
        acc[0][3:] += np.cross(omega_dot, jv.T).T
    return vel, acc


def _classical(st: States, s: int, fid: int, rname: str) -> np.ndarray:
    """Pinocchio's ``(∂a^c/∂q, ∂a^c/∂q̇, ∂a^c/∂q̈)`` of the frame's classical acceleration, `(6, 3 nv)`."""
    pin = require_pinocchio()
    pm, pd = st.pin_model, st.pin_data
    vel, acc = _frame_derivatives(st, s, fid, rname)
    ref = getattr(pin, rname)
    out = [x.copy() for x in acc]
    if rname == "WORLD":  # a^c = [ω̇; a_lin + ω × v_lin]: the product rule on Pinocchio's WORLD values
        motion = pin.getFrameVelocity(pm, pd, fid, ref)
        omega, lin = motion.angular, motion.linear
        for k, d_v in ((0, vel[0]), (1, vel[1])):
            out[k][3:] += np.cross(d_v[:3].T, lin).T + np.cross(omega, d_v[3:].T).T
    else:  # the linear rows: the classical acceleration of the point at the frame's origin
        frame = pm.frames[fid]
        point = pin.getPointClassicAccelerationDerivatives(pm, pd, frame.parentJoint, frame.placement, ref)
        for k in range(3):
            out[k][3:] = _columns(st, point[k + 1], 3)
    return np.concatenate(out, axis=-1)


def _point_rows(st: States, s: int, fid: int, rname: str) -> np.ndarray:
    """Pinocchio's point velocity and classical acceleration derivatives at :data:`POINT`, `(3, 5 nv)`."""
    pin = require_pinocchio()
    pm, pd = st.pin_model, st.pin_data
    ref = getattr(pin, rname)
    pin.computeForwardKinematicsDerivatives(pm, pd, st.qp[s], st.vp[s], st.ap[s])
    frame = pm.frames[fid]
    place = frame.placement * pin.SE3(np.eye(3), POINT)
    pv = pin.getPointVelocityDerivatives(pm, pd, frame.parentJoint, place, ref)
    pc = pin.getPointClassicAccelerationDerivatives(pm, pd, frame.parentJoint, place, ref)
    return np.concatenate([_columns(st, x, 3) for x in (pv[0], pv[1], pc[1], pc[2], pc[3])], axis=-1)


def _linear_rows(k: fd.KinematicsDerivatives) -> np.ndarray:
    """The linear rows of a point's ``(dv_dq, dv_dv, dac_dq, dac_dv, dac_da)``, side by side, `(..., 3, 5 nv)`."""
    return np.concatenate([x[..., 3:, :] for x in (k.dv_dq, k.dv_dv, k.dac_dq, k.dac_dv, k.dac_da)], axis=-1)


def _pinocchio_lwa(st: States, fid: int, which: int) -> Cause:
    """The cause "featherdyn's LOCAL_WORLD_ALIGNED derivatives hold the origin fixed, as Pinocchio's do"."""
    pin = require_pinocchio()

    def as_pinocchio(ref: np.ndarray) -> np.ndarray:
        def one(s: int) -> np.ndarray:
            pin.computeForwardKinematicsDerivatives(st.pin_model, st.pin_data, st.qp[s], st.vp[s], st.ap[s])
            get = pin.getFrameVelocityDerivatives if which == 0 else pin.getFrameAccelerationDerivatives
            got = get(st.pin_model, st.pin_data, fid, pin.LOCAL_WORLD_ALIGNED)[which:]
            return np.concatenate([st.jmap.columns_from_pin(from_pin6_rows(np.asarray(x).copy())) for x in got],
                                  axis=-1)
        return _stack(st, one)

    return ("featherdyn's LOCAL_WORLD_ALIGNED derivative holds the frame's origin fixed (Pinocchio's "
            "getFrame*Derivatives); the function's own derivative has ω × J_v (ω̇ × J_v) in its linear rows",
            as_pinocchio)


#: the fields of fd.kinematics_derivatives compared side by side, by what Pinocchio calls gives them
_KINDS = {"velocity": ("dv_dq", "dv_dv"), "acceleration": ("da_dq", "da_dv", "da_da"),
          "classical": ("dac_dq", "dac_dv", "dac_da")}


def _ours(st: States, *, frame: int, ref: fd.ReferenceFrame, kind: str) -> np.ndarray:
    k = fd.kinematics_derivatives(st.model, st.q, st.v, st.a, frame, ref)
    return np.concatenate([getattr(k, f) for f in _KINDS[kind]], axis=-1)


def _ours_at_point(st: States, *, frame: int, ref: fd.ReferenceFrame) -> np.ndarray:
    return _linear_rows(fd.kinematics_derivatives(st.model, st.q, st.v, st.a, frame, ref, POINT))


def _theirs(st: States, s: int, *, fid: int, rname: str, kind: str) -> np.ndarray:
    if kind == "classical":
        return _classical(st, s, fid, rname)
    return np.concatenate(_frame_derivatives(st, s, fid, rname)[0 if kind == "velocity" else 1], axis=-1)


def _theirs_at_point(st: States, s: int, *, fid: int, rname: str) -> np.ndarray:
    return _point_rows(st, s, fid, rname)


def _theirs_stacked(st: States, fid: int, rname: str, kind: str) -> Callable[[np.ndarray], np.ndarray]:
    """A cause's values: Pinocchio's ``kind`` in reference ``rname``, over the states (the argument ignored)."""
    return lambda ref: _stack(st, functools.partial(_theirs, st, fid=fid, rname=rname, kind=kind))


def _causes(st: States, *, fid: int, rname: str, kind: str) -> list[Cause]:
    out: list[Cause] = []
    if rname == "LOCAL_WORLD_ALIGNED" and kind != "classical":
        out.append(_pinocchio_lwa(st, fid, 0 if kind == "velocity" else 1))
    out.append(LINEAR_FIRST_ROWS)
    if kind == "acceleration":
        out.append(("featherdyn's spatial acceleration derivatives are Pinocchio's of the classical acceleration",
                    _theirs_stacked(st, fid, rname, "classical")))
    if kind == "classical":
        out.append(("featherdyn's classical acceleration derivatives are Pinocchio's of the spatial one (the ω × v "
                    "terms missing)", _theirs_stacked(st, fid, rname, "acceleration")))
    out += [(f"featherdyn's derivative is Pinocchio's in the {other} frame, not in {rname}",
             _theirs_stacked(st, fid, other, kind)) for other, _ in _REFS if other != rname]
    return out


def frame_rows(model: Model, frame: int, fid: int) -> list[Row]:
    """The rows of featherdyn frame ``frame`` (Pinocchio's frame ``fid``): its velocity, spatial and classical
    acceleration derivatives in the three references, and a point's (:data:`POINT`) in LOCAL and
    LOCAL_WORLD_ALIGNED."""
    name = model.frames[frame].name
    rows: list[Row] = []
    for rname, ref in _REFS:
        for kind, fields in _KINDS.items():
            rows.append(Row(f"kinematics_derivatives {name} {rname} {', '.join(fields)}",
                            functools.partial(_ours, frame=frame, ref=ref, kind=kind),
                            functools.partial(_theirs, fid=fid, rname=rname, kind=kind),
                            functools.partial(_causes, fid=fid, rname=rname, kind=kind)))
        if rname != "WORLD":  # (in WORLD a point's spatial motion is the frame's)
            rows.append(Row(f"kinematics_derivatives {name} {rname} at a point, linear rows",
                            functools.partial(_ours_at_point, frame=frame, ref=ref),
                            functools.partial(_theirs_at_point, fid=fid, rname=rname)))
    return rows


def derivative_checks(st: States, rows: Sequence[Row], tol: float) -> list[CheckResult]:
    """Each row compared over the states: ``max|a − b| / max(|b|, 1)`` per state held to ``tol`` (or
    ``tol × cond(M)``, marked so); on a mismatch the row's causes are tried (:func:`likely_cause`)."""
    out: list[CheckResult] = []
    massless = not st.model.total_mass > 0
    tol_cond = tol * max(1.0, st.cond)
    for row in rows:
        t = tol_cond if row.scaled else tol
        quantity = f"{row.quantity} ({COND_SCALED} = {t:.1e})" if row.scaled else row.quantity
        if row.needs_mass and massless:
            out.append(CheckResult("pinocchio", quantity, 0.0, 0.0, 0, t, True,
                                   "skipped: the moving bodies have no mass"))
            continue
        ours = np.asarray(row.ours(st), dtype=np.float64)
        ref = _stack(st, functools.partial(row.theirs, st))
        r = compare("pinocchio", quantity, ours, ref, t)
        if not r.passed and not r.note:
            r = replace(r, note=likely_cause(ours, ref, row.causes(st), t))
        out.append(r)
    return out


# ---------------------------------------------------------------------------------------------------------
# the second order: central differences of the analytical first order
# ---------------------------------------------------------------------------------------------------------

def _differences(f: Callable[..., tuple[np.ndarray, ...]], model: Model, x: np.ndarray, ks: list[int], eps: float,
                 on_q: bool, fixed: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Central differences of each array of ``f(x, *fixed)`` `(n, ...)` along every direction in ``ks``, stacked
    on a new last axis: along ``x ⊕ ε e_k`` (:func:`integrate`) when ``on_q``, else ``x + ε e_k``. One batched call
    over the ``2 len(ks) n`` displaced states."""
    n, nv = x.shape[0], model.nv
    steps = np.zeros((2, len(ks), n, nv))
    for c, k in enumerate(ks):
        steps[0, c, :, k], steps[1, c, :, k] = eps, -eps
    moved = integrate(model, np.broadcast_to(x, steps.shape[:-1] + x.shape[-1:]), steps) if on_q else x + steps
    outs = f(moved, *(np.broadcast_to(y, steps.shape[:-1] + y.shape[-1:]) for y in fixed))
    return [np.moveaxis((o[0] - o[1]) / (2 * eps), 0, -1) for o in outs]


def _extrapolated(f: Callable[..., tuple[np.ndarray, ...]], model: Model, x: np.ndarray, ks: list[int], eps: float,
                  on_q: bool, fixed: Sequence[np.ndarray]) -> list[np.ndarray]:
    """:func:`_differences` at ε and ε/2 combined as ``(4 D(ε/2) − D(ε)) / 3`` (Richardson): the central
    differences' ε² term cancels. ABA's derivatives vary fast on light limbs: on icub_reduced (cond(M) 3e4) the
    plain difference at ε = 1e-4 is off by 8e-5 relative, the combination by 1e-9."""
    coarse = _differences(f, model, x, ks, eps, on_q, fixed)
    fine = _differences(f, model, x, ks, eps / 2, on_q, fixed)
    return [(4 * b - a) / 3 for a, b in zip(coarse, fine, strict=True)]


#: states and (at most) directions the second order is checked on: its cost grows as nv⁴ (ABA's) and its
#: differences take 10 first-order calls per direction (tiago_dual, nv = 101: 1.5 s on 2 states, 24 directions)
SECOND_ORDER_STATES = 2
SECOND_ORDER_DIRECTIONS = 24

#: the rounding of the central differences of fd.aba_derivatives per unit of cond(M) (:mod:`featherdyn.tolerances`):
#: ABA's second-order rows are held to max(SECOND_ORDER_TOL, cond(M) × this)
ABA_DIFFERENCE_ROUNDING = VERIFY_ABA_DIFFERENCE_ROUNDING


def second_order_checks(model: Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, tau: np.ndarray,
                        cond: float, tol: float = SECOND_ORDER_TOL) -> list[CheckResult]:
    """``fd.rnea_second_derivatives`` and ``fd.aba_second_derivatives`` at the first :data:`SECOND_ORDER_STATES`
    states against central differences of ``fd.rnea_derivatives``, ``fd.crba`` and ``fd.aba_derivatives``
    (``docs/derivatives.md``), along every direction k (at most :data:`SECOND_ORDER_DIRECTIONS`, spread over the
    tree, the root's first):

    ``d2tau_dq2[:, :, k] ≈ Δ_k ∂τ/∂q`` along ``q ⊕ ε e_k``, ``d2tau_dqdv[:, :, k] ≈ Δ_k ∂τ/∂q`` along ``q̇ + ε e_k``,
    ``d2tau_dv2[:, :, k] ≈ Δ_k ∂τ/∂q̇`` along ``q̇``, ``dM_dq[:, :, k] ≈ Δ_k M`` along ``q``; ABA's alike, with
    ``d2ddq_dqdtau[:, :, k] ≈ Δ_k ∂q̈/∂q`` along ``τ + ε e_k``. Along ``q̇`` and ``τ`` the first order is quadratic
    (affine) in them and a unit step is exact; along ``q`` ε = 1e-6, ABA's ε = 1e-4 and 5e-5 extrapolated
    (:func:`_extrapolated`). Held to ``tol``, ABA's to
    ``max(tol, cond(M) × ABA_DIFFERENCE_ROUNDING)``: its first order carries M⁻¹, and the differences lose
    ``cond(M) · 2e-16 / ε`` to rounding (marked ``tol × cond(M)`` where that term decides).
    """
    nv = model.nv
    out: list[CheckResult] = []
    if nv == 0:
        return out
    n = min(SECOND_ORDER_STATES, q.shape[0])
    q, v, a, tau = q[:n], v[:n], a[:n], tau[:n]
    ks = list(range(nv)) if nv <= SECOND_ORDER_DIRECTIONS else \
        sorted({*range(min(6, nv)), *np.linspace(0, nv - 1, SECOND_ORDER_DIRECTIONS - 6).round().astype(int).tolist()})
    where = f"{n} state{'s' if n > 1 else ''}" + ("" if len(ks) == nv else f", {len(ks)} of {nv} directions")

    def row(quantity: str, ours: np.ndarray, differences: np.ndarray, t: float) -> None:
        out.append(compare("identity", f"{quantity} ({where})", ours[..., ks], differences, t))

    s = fd.rnea_second_derivatives(model, q, v, a)

    def first(qq: np.ndarray, vv: np.ndarray, aa: np.ndarray) -> tuple[np.ndarray, ...]:
        dq, dv, _ = fd.rnea_derivatives(model, qq, vv, aa)
        return dq, dv, fd.crba(model, qq)

    dq_q, _, dm_q = _differences(lambda qq, vv, aa: first(qq, vv, aa), model, q, ks, 1e-6, True, (v, a))
    # along q̇ (and τ below) the first order is a quadratic (affine) function: a central difference is exact for
    # any step, and a unit step loses the least to rounding
    dq_v, dv_v, _ = _differences(lambda vv, qq, aa: first(qq, vv, aa), model, v, ks, 1.0, False, (q, a))
    what = "central differences of"
    row(f"rnea_second_derivatives d2tau_dq2 vs {what} dtau_dq along q", s.d2tau_dq2, dq_q, tol)
    row(f"rnea_second_derivatives d2tau_dv2 vs {what} dtau_dv along q̇", s.d2tau_dv2, dv_v, tol)
    row(f"rnea_second_derivatives d2tau_dqdv vs {what} dtau_dq along q̇", s.d2tau_dqdv, dq_v, tol)
    row(f"rnea_second_derivatives dM_dq vs {what} M along q", s.dM_dq, dm_q, tol)
    # ABA's first order carries M⁻¹: its differences (ε = 1e-4) lose up to cond(M) · 2e-16 / ε to rounding,
    # held to 50 times that where it exceeds tol (measured on the robot library: ≤ 6e-7 at cond(M) ≤ 6e3)
    t = max(tol, cond * ABA_DIFFERENCE_ROUNDING)
    scaled = f", {COND_SCALED}" if t > tol else ""
    try:
        sa = fd.aba_second_derivatives(model, q, v, tau)
    except SingularMassMatrixError as exc:
        out.append(CheckResult("identity", "aba_second_derivatives vs central differences of aba_derivatives",
                               float("nan"), 0.0, 0, tol, True, f"skipped: {exc}"))
        return out

    def aba_first(qq: np.ndarray, vv: np.ndarray, tt: np.ndarray) -> tuple[np.ndarray, ...]:
        return fd.aba_derivatives(model, qq, vv, tt)[:2]

    eps = 1e-4  # (ABA's first order carries M⁻¹: a smaller step loses more to rounding)
    aq = _extrapolated(lambda qq, vv, tt: aba_first(qq, vv, tt), model, q, ks, eps, True, (v, tau))[0]
    av_q, av_v = _differences(lambda vv, qq, tt: aba_first(qq, vv, tt), model, v, ks, 1.0, False, (q, tau))
    at = _differences(lambda tt, qq, vv: aba_first(qq, vv, tt), model, tau, ks, 1.0, False, (q, v))[0]
    row(f"aba_second_derivatives d2ddq_dq2 vs {what} ddq_dq along q{scaled}", sa.d2ddq_dq2, aq, t)
    row(f"aba_second_derivatives d2ddq_dv2 vs {what} ddq_dv along q̇{scaled}", sa.d2ddq_dv2, av_v, t)
    row(f"aba_second_derivatives d2ddq_dqdv vs {what} ddq_dq along q̇{scaled}", sa.d2ddq_dqdv, av_q, t)
    row(f"aba_second_derivatives d2ddq_dqdtau vs {what} ddq_dq along τ{scaled}", sa.d2ddq_dqdtau, at, t)
    return out
