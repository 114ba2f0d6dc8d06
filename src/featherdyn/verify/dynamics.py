"""Verification of a robot model: featherdyn against Pinocchio, and identities that need no oracle.

Both libraries read the same URDF; joints are mapped by name and layouts
converted by :class:`~featherdyn.verify.bridge.JointMap`. featherdyn computes
each quantity for all sampled states in one batched call; Pinocchio state by
state.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike

import featherdyn as fd

from ..configuration import integrate, integrate_derivatives, random_configuration
from ..errors import SingularMassMatrixError
from ..model import Model, massless_subtrees
from .bridge import SWAP6, JointMap, from_pin6, from_pin6_rows
from .pinocchio import PinModel, PinValue, require_pinocchio
from .report import (
    ROUNDOFF,
    Cause,
    CheckResult,
    Diagnostics,
    InvalidInertia,
    LinkInfo,
    compare,
    likely_cause,
    roundoff_note,
)

__all__ = ["RobotPair", "dynamics_checks", "model_diagnostics", "ModelDiagnostics", "forward_dynamics_result"]

_REFS = (("LOCAL", fd.LOCAL), ("WORLD", fd.WORLD), ("LOCAL_WORLD_ALIGNED", fd.LOCAL_WORLD_ALIGNED))

#: how forward dynamics is judged (:func:`forward_dynamics_result`), as the reports state it.
FORWARD_DYNAMICS_RULE = ("forward dynamics is judged by its backward error max_i |M q̈ + h − τ|_i / (|M||q̈| + |h| + "
                         "|τ|)_i <= tol and its forward error |q̈ − q̈_ref| / max(|q̈_ref|, 1) <= tol·cond(M) "
                         "(solving for q̈ amplifies round-off by cond(M))")


def _second(fn: Callable[[int, PinValue], np.ndarray], second: PinValue, s: int) -> np.ndarray:
    return fn(s, second)


def forward_dynamics_result(group: str, quantity: str, model: Model, q: np.ndarray, v: np.ndarray, tau: np.ndarray,
                            ddq: np.ndarray, ddq_ref: np.ndarray, M: np.ndarray, tol: float,
                            f_ext: np.ndarray | None = None) -> CheckResult:
    """Judge forward dynamics ``ddq`` `(N, nv)` by its backward error, and its distance to ``ddq_ref`` by cond(M).

    Solving ``M q̈ = τ − h`` amplifies round-off by the condition number of ``M``
    (1e7 to 1e13 on arms with light fingers, e.g. the iCub models), so two
    correct solvers can differ far above ``tol``. What a correct solver
    guarantees is a small backward error: ``q̈`` solves the equations of motion
    of a nearby problem. Per state, joint by joint (``|·|`` elementwise)::

        r        = M q̈ + h − τ  =  rnea(q, v, q̈, f_ext) − τ
        backward = max_i |r_i| / (|M| |q̈| + |h| + |τ|)_i
        forward  = max|q̈ − q̈_ref| / max(max|q̈_ref|, 1)
        error    = max(backward, forward / cond₂(M))  <=  tol

    that is, ``backward <= tol`` and ``forward <= tol · cond(M)``. The
    joint-by-joint backward error implies the norm-wise one
    (``‖r‖ <= tol (‖M‖‖q̈‖ + ‖h‖ + ‖τ‖)``) and is stronger: a joint with huge
    accelerations (a light finger) does not hide a wrong torque at another
    joint. Correct solvers give ~1e-16 on every robot of the library; a wrong
    gravity, a missing body or an offset of 1e-3 give 1e-5 to 1. The row's
    ``max_rel`` is the worst ``error``; ``max_abs`` the worst ``|q̈ − q̈_ref|``.
    """
    ddq = np.asarray(ddq, dtype=np.float64)
    ref = np.asarray(ddq_ref, dtype=np.float64)
    if model.nv == 0 or ddq.shape != ref.shape or not (np.all(np.isfinite(ddq)) and np.all(np.isfinite(ref))):
        return compare(group, quantity, ddq, ref, tol)
    n = ddq.shape[0]
    residual = fd.rnea(model, q, v, ddq, f_ext) - tau
    h = fd.rnea(model, q, v, np.zeros_like(ddq), f_ext)
    scale = np.einsum("nij,nj->ni", np.abs(M), np.abs(ddq)) + np.abs(h) + np.abs(tau)
    ratio = np.divide(np.abs(residual), scale, out=np.where(residual == 0, 0.0, np.inf), where=scale > 0)
    backward = ratio.max(axis=1)
    err = np.abs(ddq - ref).reshape(n, -1).max(axis=1)
    forward = err / np.maximum(np.abs(ref).reshape(n, -1).max(axis=1), 1.0)
    cond = np.linalg.cond(M)
    per_state = np.maximum(backward, forward / cond)
    worst = int(np.argmax(per_state))
    max_rel = float(per_state[worst])
    k = int(np.argmax(forward))
    criterion = (f"{FORWARD_DYNAMICS_RULE}; worst backward error {backward.max():.1e}, worst forward error "
                 f"{forward[k]:.1e} at cond(M) {cond[k]:.1e}")
    note = ""
    if max_rel > tol:
        if max_rel <= ROUNDOFF:
            note = roundoff_note(max_rel, tol)
        elif backward[worst] >= forward[worst] / cond[worst]:
            note = (f"q̈ does not solve M q̈ = τ − h: backward error {backward[worst]:.1e} at state {worst} "
                    f"(round-off would be ~1e-15)")
        else:
            note = (f"q̈ differs from the oracle's by {forward[worst]:.1e} at state {worst}, more than "
                    f"tol·cond(M) = {tol * cond[worst]:.1e} explains")
    return CheckResult(group, quantity, float(err.max(initial=0.0)), max_rel, worst, tol, max_rel <= tol, note,
                       tuple(float(e) for e in per_state), criterion)


@dataclass
class RobotPair:
    """The same robot in featherdyn and in Pinocchio, with the joint map between them."""

    model: Model
    pin_model: PinModel
    jmap: JointMap

    @classmethod
    def from_urdf(cls, model: Model, path: str, floating_base: bool) -> RobotPair:
        pin = require_pinocchio()
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            pm = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating_base else \
                pin.buildModelFromUrdf(str(path))
        return cls(model, pm, JointMap(model, pm))


_PIN_TYPE = {"body": "BODY", "link": "BODY", "joint": "JOINT", "fixed_joint": "FIXED_JOINT"}


def _pin_frame_ids(model: Model, pin_model: PinModel) -> dict[int, int]:
    """featherdyn frame index → Pinocchio frame id, matched by name and type (links and joints may share names)."""
    pin_ids = {(f.name, str(f.type).rsplit(".", 1)[-1]): k for k, f in enumerate(pin_model.frames)}
    out = {}
    for k, f in enumerate(model.frames):
        key = (f.name, _PIN_TYPE.get(f.kind, ""))
        if key in pin_ids:
            out[k] = pin_ids[key]
    return out


def _pick_frames(model: Model, matched: dict[int, int], k: int = 3) -> list[int]:
    """A few frames to check velocities and Jacobians on: a link frame on each of the deepest bodies."""
    chosen: list[int] = []
    depth = [0] * model.nbodies
    for i, p in enumerate(model.parents):
        depth[i] = 0 if p == -1 else depth[p] + 1
    for i in sorted(range(model.nbodies), key=lambda i: -depth[i]):
        leaves = [n for n, f in enumerate(model.frames) if f.body == i and n in matched and f.kind in ("link", "body")]
        if leaves:
            chosen.append(leaves[-1])
        if len(chosen) >= k:
            break
    return chosen


def dynamics_checks(pair: RobotPair, samples: int = 10, seed: int = 0, tol: float = 1e-9,
                    progress: Callable[[str], None] | None = None) -> list[CheckResult]:
    """Compare every dynamics quantity with Pinocchio over ``samples`` random states, then check identities.

    Relative errors are ``|a − b| / max(|b|, 1)`` per state, held to ``tol``.
    """
    pin = require_pinocchio()
    model, pm, jm = pair.model, pair.pin_model, pair.jmap
    pd = pm.createData()
    rng = np.random.default_rng(seed)
    n = samples
    q = random_configuration(model, rng, size=n)
    v = rng.normal(size=(n, model.nv))
    a = rng.normal(size=(n, model.nv))
    tau = rng.normal(size=(n, model.nv))
    qp, vp, ap, taup = jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a), jm.v_to_pin(tau)
    results: list[CheckResult] = []

    def note(msg: str) -> None:
        if progress is not None:
            progress(msg)

    def stack(theirs: Callable[[int], ArrayLike]) -> np.ndarray:
        return np.stack([np.asarray(theirs(s), dtype=np.float64) for s in range(n)])

    def check(quantity: str, ours: ArrayLike, theirs: Callable[[int], ArrayLike],
              causes: Sequence[Cause] = (), group: str = "pinocchio", tolerance: float | None = None) -> None:
        t = tol if tolerance is None else tolerance
        ref = stack(theirs)
        r = compare(group, quantity, ours, ref, t)
        if not r.passed and not r.note:
            r = replace(r, note=likely_cause(np.asarray(ours, dtype=np.float64), ref, causes, t))
        results.append(r)

    def swapped_halves(ref: np.ndarray) -> np.ndarray:
        return ref[..., SWAP6] if ref.shape[-1] == 6 else ref[..., SWAP6, :]

    def oracle(theirs: Callable[[int], ArrayLike]) -> Callable[[np.ndarray], np.ndarray]:
        """The oracle's values of another call: what featherdyn's would equal under a mix-up."""
        return lambda ref: stack(theirs)

    swap6: Cause = ("the linear and angular halves of the 6D vectors are swapped", swapped_halves)
    gravity_terms: list[np.ndarray] = []

    def gravity(ref: np.ndarray) -> np.ndarray:  # Pinocchio's g(q), the term a gravity mistake changes
        if not gravity_terms:
            gravity_terms.append(stack(lambda s: jm.v_from_pin(pin.computeGeneralizedGravity(pm, pd, qp[s]))))
        return gravity_terms[0]

    gravity_causes: list[Cause] = [
        ("the gravity is reversed (featherdyn's value is Pinocchio's with −g)", lambda ref: ref - 2 * gravity(ref)),
        ("the gravity term is missing (featherdyn's value is Pinocchio's with g = 0)", lambda ref: ref - gravity(ref)),
    ]

    body_jid = jm.joint_ids
    matched = _pin_frame_ids(model, pm)
    frames = _pick_frames(model, matched)

    note("kinematics")
    kin = fd.forward_kinematics(model, q, v, a)
    assert kin.velocities is not None and kin.accelerations is not None

    def fk(s: int) -> None:
        pin.forwardKinematics(pm, pd, qp[s], vp[s], ap[s])
        pin.updateFramePlacements(pm, pd)

    def per_body(getter: Callable[[int], np.ndarray]) -> Callable[[int], np.ndarray]:
        def f(s: int) -> np.ndarray:
            fk(s)
            return np.stack([getter(j) for j in body_jid]) if body_jid else np.zeros((0,))
        return f

    if model.nbodies:
        check("body placements ⁰M_i vs data.oMi", kin.placements.homogeneous(),
              per_body(lambda j: pd.oMi[j].homogeneous))
        check("body velocities v_i vs data.v", kin.velocities.vector, per_body(lambda j: from_pin6(pd.v[j].vector)),
              [swap6])
        check("body spatial accelerations a_i vs data.a", kin.accelerations.vector,
              per_body(lambda j: from_pin6(pd.a[j].vector)), [swap6])
    common = sorted(matched)
    if common:
        ours = np.stack([fd.frame_placement(model, q, k).homogeneous() for k in common], axis=1)

        def frame_poses(s: int) -> np.ndarray:
            fk(s)
            return np.stack([pd.oMf[matched[k]].homogeneous for k in common])

        check(f"frame placements ({len(common)} frames) vs data.oMf", ours, frame_poses)

    note("frame velocities and Jacobians")
    pin_refs = {"LOCAL": pin.LOCAL, "WORLD": pin.WORLD, "LOCAL_WORLD_ALIGNED": pin.LOCAL_WORLD_ALIGNED}
    for frame in frames:
        fid, name = matched[frame], model.frames[frame].name
        for rname, ref in _REFS:
            pref = pin_refs[rname]

            def fv(s: int, pref: PinValue = pref, fid: int = fid) -> np.ndarray:
                fk(s)
                return from_pin6(pin.getFrameVelocity(pm, pd, fid, pref).vector)

            def fa(s: int, pref: PinValue = pref, fid: int = fid) -> np.ndarray:
                fk(s)
                return from_pin6(pin.getFrameAcceleration(pm, pd, fid, pref).vector)

            def fc(s: int, pref: PinValue = pref, fid: int = fid) -> np.ndarray:
                fk(s)
                return from_pin6(pin.getFrameClassicalAcceleration(pm, pd, fid, pref).vector)

            def fj(s: int, pref: PinValue = pref, fid: int = fid) -> np.ndarray:
                pin.computeJointJacobians(pm, pd, qp[s])
                pin.updateFramePlacements(pm, pd)
                return jm.columns_from_pin(from_pin6_rows(pin.getFrameJacobian(pm, pd, fid, pref)))

            def fdj(s: int, pref: PinValue = pref, fid: int = fid) -> np.ndarray:
                pin.computeJointJacobiansTimeVariation(pm, pd, qp[s], vp[s])
                pin.updateFramePlacements(pm, pd)
                return jm.columns_from_pin(from_pin6_rows(pin.getFrameJacobianTimeVariation(pm, pd, fid, pref)))

            def in_frames(fn: Callable[[int, PinValue], np.ndarray], what: str, rname: str = rname) -> list[Cause]:
                """Causes: the value is Pinocchio's in another reference frame."""
                return [(f"featherdyn's {what} is Pinocchio's in the {other} frame, not in {rname}",
                         oracle(functools.partial(_second, fn, other_ref)))
                        for other, other_ref in pin_refs.items() if other != rname]

            check(f"frame_velocity {name} {rname}", fd.frame_velocity(model, q, v, frame, ref).vector, fv,
                  [swap6, *in_frames(fv, "velocity")])
            check(f"frame_acceleration {name} {rname}", fd.frame_acceleration(model, q, v, a, frame, ref).vector,
                  fa, [swap6, ("featherdyn's spatial acceleration is Pinocchio's classical one (ω × v added)",
                               oracle(fc)), *in_frames(fa, "acceleration")])
            check(f"frame_classical_acceleration {name} {rname}",
                  fd.frame_classical_acceleration(model, q, v, a, frame, ref).vector, fc,
                  [swap6, ("featherdyn's classical acceleration is Pinocchio's spatial one (ω × v missing)",
                           oracle(fa)), *in_frames(fc, "classical acceleration")])
            check(f"frame_jacobian {name} {rname}", fd.frame_jacobian(model, q, frame, ref), fj,
                  [swap6, *in_frames(fj, "Jacobian")])
            check(f"frame_jacobian_time_variation {name} {rname}",
                  fd.frame_jacobian_time_variation(model, q, v, frame, ref), fdj, [swap6])

    def jj(s: int) -> np.ndarray:
        pin.computeJointJacobians(pm, pd, qp[s])
        return jm.columns_from_pin(from_pin6_rows(pd.J))

    check("joint_jacobians vs data.J", fd.joint_jacobians(model, q), jj, [swap6])

    note("dynamics")
    check("rnea vs pin.rnea", fd.rnea(model, q, v, a), lambda s: jm.v_from_pin(pin.rnea(pm, pd, qp[s], vp[s], ap[s])),
          gravity_causes)
    fext = rng.normal(size=(n, model.nbodies, 6))

    def pin_fext(s: int) -> list[PinValue]:
        out = [pin.Force.Zero() for _ in range(pm.njoints)]
        for i, j in enumerate(body_jid):
            out[j] = pin.Force(fext[s, i, 3:], fext[s, i, :3])
        return out

    check("rnea with f_ext vs pin.rnea(fext)", fd.rnea(model, q, v, a, fext),
          lambda s: jm.v_from_pin(pin.rnea(pm, pd, qp[s], vp[s], ap[s], pin_fext(s))), gravity_causes)
    M = fd.crba(model, q)
    check("crba vs pin.crba", M, lambda s: jm.matrix_from_pin(pin.crba(pm, pd, qp[s])),
          [("featherdyn's M holds only the upper triangle of Pinocchio's", np.triu),
           ("featherdyn's M holds only the lower triangle of Pinocchio's", np.tril)])
    note("derivatives")
    dtau = fd.rnea_derivatives(model, q, v, a)

    def pin_rnea_derivatives(s: int, which: str) -> np.ndarray:
        pin.computeRNEADerivatives(pm, pd, qp[s], vp[s], ap[s])
        return jm.matrix_from_pin(getattr(pd, which).copy())

    transposed: Cause = ("featherdyn's matrix is Pinocchio's transposed", lambda ref: np.swapaxes(ref, -1, -2))
    check("rnea_derivatives dtau_dq vs computeRNEADerivatives", dtau[0],
          lambda s: pin_rnea_derivatives(s, "dtau_dq"), [transposed])
    check("rnea_derivatives dtau_dv vs computeRNEADerivatives", dtau[1],
          lambda s: pin_rnea_derivatives(s, "dtau_dv"), [transposed])

    def pin_minverse(s: int) -> np.ndarray:
        Mi = pin.computeMinverse(pm, pd, qp[s]).copy()
        return jm.matrix_from_pin(np.triu(Mi) + np.triu(Mi, 1).T)

    # M⁻¹ and ABA's derivatives carry M⁻¹: two correct solvers differ by up to cond(M) × round-off
    # (the forward-error rule of ABA below), so their tolerance is scaled by the worst cond(M)
    cond = float(np.max(np.linalg.cond(M))) if model.nv else 1.0
    tol_minv = tol * max(1.0, cond)
    try:
        Minv = fd.mass_matrix_inverse(model, q)
        dddq = fd.aba_derivatives(model, q, v, tau)
    except SingularMassMatrixError as exc:  # as for ABA below: nothing to compare when M is singular
        for what in ("mass_matrix_inverse vs computeMinverse", "aba_derivatives vs computeABADerivatives"):
            results.append(CheckResult("pinocchio", what, float("nan"), 0.0, 0, tol, True, f"skipped: {exc}"))
    else:
        check(f"mass_matrix_inverse vs computeMinverse (tol × cond(M) = {tol_minv:.1e})", Minv, pin_minverse,
              tolerance=tol_minv)

        def pin_aba_derivatives(s: int, which: str) -> np.ndarray:
            pin.computeABADerivatives(pm, pd, qp[s], vp[s], taup[s])
            return jm.matrix_from_pin(getattr(pd, which).copy())

        aba_dtau: list[np.ndarray] = []

        def dtau_at_aba(ref: np.ndarray) -> np.ndarray:
            if not aba_dtau:
                aba_dtau.append(-fd.rnea_derivatives(model, q, v, fd.aba(model, q, v, tau))[0])
            return aba_dtau[0]

        missing_minv: Cause = ("featherdyn's value lacks the factor M⁻¹ (it is −∂τ/∂q, not ∂q̈/∂q)", dtau_at_aba)

        check("aba_derivatives ddq_dq vs computeABADerivatives (tol × cond(M))", dddq[0],
              lambda s: pin_aba_derivatives(s, "ddq_dq"), [missing_minv, transposed], tolerance=tol_minv)
        check("aba_derivatives ddq_dv vs computeABADerivatives (tol × cond(M))", dddq[1],
              lambda s: pin_aba_derivatives(s, "ddq_dv"), [transposed], tolerance=tol_minv)
    Jq, Jv = integrate_derivatives(model, q, v)
    check("integrate_derivatives vs dIntegrate (ARG0, ARG1)", np.concatenate([Jq, Jv], axis=-1),
          lambda s: np.concatenate([jm.matrix_from_pin(pin.dIntegrate(pm, qp[s], vp[s], pin.ARG0).copy()),
                                    jm.matrix_from_pin(pin.dIntegrate(pm, qp[s], vp[s], pin.ARG1).copy())], axis=-1))
    check("nonlinear_effects vs nonLinearEffects", fd.nonlinear_effects(model, q, v),
          lambda s: jm.v_from_pin(pin.nonLinearEffects(pm, pd, qp[s], vp[s])), gravity_causes)
    check("generalized_gravity vs computeGeneralizedGravity", fd.generalized_gravity(model, q),
          lambda s: jm.v_from_pin(pin.computeGeneralizedGravity(pm, pd, qp[s])),
          [("the gravity is reversed (featherdyn's g(q) is −Pinocchio's)", lambda ref: -ref)])
    C = fd.coriolis_matrix(model, q, v)
    check("coriolis_matrix vs computeCoriolisMatrix", C,
          lambda s: jm.matrix_from_pin(pin.computeCoriolisMatrix(pm, pd, qp[s], vp[s])))
    singular = False
    try:
        ddq = fd.aba(model, q, v, tau)
        results.append(forward_dynamics_result(
            "pinocchio", "aba vs pin.aba", model, q, v, tau, ddq,
            stack(lambda s: jm.v_from_pin(pin.aba(pm, pd, qp[s], vp[s], taup[s]))), M, tol))
        results.append(forward_dynamics_result(
            "pinocchio", "aba with f_ext vs pin.aba(fext)", model, q, v, tau, fd.aba(model, q, v, tau, fext),
            stack(lambda s: jm.v_from_pin(pin.aba(pm, pd, qp[s], vp[s], taup[s], pin_fext(s)))), M, tol, fext))
    except SingularMassMatrixError as exc:
        singular = True
        results.append(CheckResult("pinocchio", "aba vs pin.aba", float("nan"), 0.0, 0, tol, True,
                                   f"skipped: {exc}"))

    note("energy and momentum")
    check("kinetic_energy vs computeKineticEnergy", fd.kinetic_energy(model, q, v),
          lambda s: pin.computeKineticEnergy(pm, pd, qp[s], vp[s]))
    check("potential_energy vs computePotentialEnergy", fd.potential_energy(model, q),
          lambda s: pin.computePotentialEnergy(pm, pd, qp[s]),
          [("the gravity is reversed (featherdyn's potential energy is −Pinocchio's)", lambda ref: -ref)])
    if model.total_mass > 0:
        com = fd.center_of_mass(model, q, v)

        def pin_com(s: int) -> np.ndarray:
            pin.centerOfMass(pm, pd, qp[s], vp[s])
            return np.concatenate([pd.com[0], pd.vcom[0]])

        check("center_of_mass (c, ċ) vs centerOfMass", np.concatenate([com.position, com.velocity], axis=-1), pin_com)

        def pin_ccrba(s: int) -> np.ndarray:
            pin.ccrba(pm, pd, qp[s], vp[s])
            return jm.columns_from_pin(from_pin6_rows(pd.Ag))

        check("centroidal_momentum_matrix vs ccrba", fd.centroidal_momentum_matrix(model, q), pin_ccrba, [swap6])

        def pin_hg(s: int) -> np.ndarray:
            pin.computeCentroidalMomentum(pm, pd, qp[s], vp[s])
            return from_pin6(pd.hg.vector)

        check("centroidal_momentum vs computeCentroidalMomentum", fd.centroidal_momentum(model, q, v).vector, pin_hg,
              [swap6])

    else:  # a fixed-base robot whose mass is all in the fixed root link: no centre of mass
        for quantity in ("center_of_mass (c, ċ) vs centerOfMass", "centroidal_momentum_matrix vs ccrba",
                         "centroidal_momentum vs computeCentroidalMomentum"):
            results.append(CheckResult("pinocchio", quantity, 0.0, 0.0, 0, tol, True,
                                       "skipped: the moving bodies have no mass"))

    note("derivatives of gravity, frames, centre of mass and centroidal momentum")
    from .derivatives import DERIVATIVE_ROWS, States, derivative_checks, frame_rows, second_order_checks

    states = States(model, pm, pd, jm, q, v, a, tau, fext, cond)
    rows = [*DERIVATIVE_ROWS, *(r for frame in frames for r in frame_rows(model, frame, matched[frame]))]
    results += derivative_checks(states, rows, tol)
    note("identities")
    results += identity_checks(model, q, v, a, tau, M, C, tol, singular)
    note("second-order derivatives (central differences of the first order)")
    results += second_order_checks(model, q, v, a, tau, cond)
    return results


def identity_checks(model: Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, tau: np.ndarray, M: np.ndarray,
                    C: np.ndarray, tol: float, singular: bool) -> list[CheckResult]:
    """Laws that need no oracle: symmetry and definiteness of M, RNEA = M a + h, ABA∘RNEA = id, Ṁ − 2C skew."""
    out: list[CheckResult] = []

    def _identity(quantity: str, lhs: ArrayLike, rhs: ArrayLike, tol: float) -> CheckResult:
        r = compare("identity", quantity, lhs, rhs, tol)
        if r.passed or r.note:
            return r
        return replace(r, note=likely_cause(np.asarray(lhs, dtype=np.float64), np.asarray(rhs, dtype=np.float64),
                                            (), tol))

    h = fd.nonlinear_effects(model, q, v)
    g = fd.generalized_gravity(model, q)
    out.append(_identity("M = Mᵀ", M, np.swapaxes(M, -1, -2), tol))
    if not singular and model.nv:
        eig = np.linalg.eigvalsh(M)[..., 0]
        out.append(CheckResult("identity", "M positive definite (min eigenvalue > 0)", 0.0, 0.0,
                               int(np.argmin(eig)), tol, bool(np.all(eig > 0)),
                               "" if np.all(eig > 0) else f"min eigenvalue {float(eig.min()):.3g}"))
    out.append(_identity("RNEA(q, v, a) = M a + h", fd.rnea(model, q, v, a),
                       (M @ a[..., None])[..., 0] + h, tol))
    out.append(_identity("h − g = C v", h - g, (C @ v[..., None])[..., 0], tol))
    out.append(_identity("T = ½ vᵀ M v", fd.kinetic_energy(model, q, v),
                       0.5 * np.einsum("...i,...ij,...j->...", v, M, v), tol))
    if not singular:
        tau_a = fd.rnea(model, q, v, a)
        out.append(forward_dynamics_result("identity", "ABA(RNEA(a)) = a", model, q, v, tau_a,
                                           fd.aba(model, q, v, tau_a), a, M, tol))
    # Ṁ − 2C skew-symmetric, with Ṁ by a central difference along q(t) = q ⊕ t v
    eps = 1e-6
    Mdot = (fd.crba(model, integrate(model, q, eps * v)) - fd.crba(model, integrate(model, q, -eps * v))) / (2 * eps)
    N = Mdot - 2 * C
    out.append(_identity("Ṁ − 2C skew-symmetric (finite difference)", N + np.swapaxes(N, -1, -2),
                       np.zeros_like(N), 1e-5))
    return out


@dataclass
class ModelDiagnostics:
    """Per-link inertia validity, mass-matrix conditioning and singular subtrees."""

    invalid_inertias: list[tuple[str, str]] = field(default_factory=list)
    singular_subtrees: list[str] = field(default_factory=list)
    mass_matrix_condition: float = float("nan")
    total_mass: float = 0.0
    links: list[LinkInfo] = field(default_factory=list)

    def to_dict(self) -> Diagnostics:
        """The diagnostics as :attr:`VerifyReport.diagnostics <featherdyn.verify.VerifyReport>` holds them."""
        return Diagnostics(links=self.links,
                           invalid_inertias=[InvalidInertia(body=b, reason=r) for b, r in self.invalid_inertias],
                           singular_subtrees=self.singular_subtrees, mass_matrix_condition=self.mass_matrix_condition,
                           total_mass=self.total_mass)


def equivalent_ellipsoid(mass: float, moments: np.ndarray) -> list[float] | None:
    """Semi-axes of the uniform solid ellipsoid with this mass and these principal moments (``None`` if none exists).

    ::

        I₁ = m (b² + c²)/5, …   ⇒   a² = 5 (I₂ + I₃ − I₁) / (2m), …

    The square roots exist exactly when the triangle inequality holds.
    """
    if not mass > 0:
        return None
    i1, i2, i3 = (float(x) for x in moments)
    sq = [5 * (i2 + i3 - i1) / (2 * mass), 5 * (i1 + i3 - i2) / (2 * mass), 5 * (i1 + i2 - i3) / (2 * mass)]
    if min(sq) < 0:
        return None
    return [float(np.sqrt(x)) for x in sq]


#: What :func:`inertia_problem` says of a body the loader inserted (:attr:`Model.inserted_bodies`).
INSERTED = "inserted by the loader: a massless body carrying one of several joints of one MJCF body"


def inertia_problem(model: Model, i: int) -> str:
    """Why body ``i``'s inertia is not physical (:meth:`SpatialInertia.check`'s message), or ``""``.

    A body the loader inserted (:attr:`Model.inserted_bodies`, a massless carrier of one of several joints on
    one MJCF body) is massless by construction, not by the user's mistake: ``""`` (:data:`INSERTED` says what
    it is). Every other body is checked.
    """
    from ..errors import InertiaError

    name = model.body_names[i]
    if name in model.inserted_bodies:
        return ""
    try:
        model.inertias[i].check(name=f"body {name!r}")
    except InertiaError as exc:
        return str(exc)
    return ""


def model_diagnostics(model: Model, q: np.ndarray | None = None) -> ModelDiagnostics:
    """Inertia validity per body (with the reason; the bodies the loader inserted pass, :func:`inertia_problem`),
    conditioning of ``M(q)`` and massless subtrees."""
    diag = ModelDiagnostics(total_mass=model.total_mass)
    for i, name in enumerate(model.body_names):
        inertia = model.inertias[i]
        reason = inertia_problem(model, i)
        if reason:
            diag.invalid_inertias.append((name, reason))
        diag.links.append({"body": name, "mass": float(inertia.mass), "principal_moments":
                           [float(x) for x in inertia.principal_moments()],
                           "ellipsoid_semi_axes": equivalent_ellipsoid(float(inertia.mass), inertia.principal_moments()),
                           "valid": not reason,
                           "reason": INSERTED if name in model.inserted_bodies else reason})
    diag.singular_subtrees = massless_subtrees(model)
    if model.nv:
        qq = q if q is not None else random_configuration(model, np.random.default_rng(0), size=4)
        M = fd.crba(model, qq)
        diag.mass_matrix_condition = float(np.max(np.linalg.cond(M)))
    return diag
