"""Issue 30's derivatives against Pinocchio 4.1: ``python benchmarks/bench_derivatives_everywhere.py [N]``.

Interleaved medians in one process (``bench_core.median_pair``, many short samples: ``ONE_STATE``), ratio featherdyn / Pinocchio (below 1:
featherdyn is faster; the issue's target ≤ 0.8 one state, ≥ 8× for batches), on panda (fixed base), solo12
(floating, four point contacts on its feet, LOCAL) and talos_full_v2 (floating, two 6D sole contacts, LOCAL).
Each featherdyn call returns new arrays; each Pinocchio call fills its ``data``:

* ``fd.kinematics_derivatives`` (a frame's eight derivatives) / ``computeForwardKinematicsDerivatives`` +
  ``getFrameVelocityDerivatives`` + ``getFrameAccelerationDerivatives``; at a point (its argument ``point``) /
  ``computeForwardKinematicsDerivatives`` + ``getPointVelocityDerivatives`` + ``getPointClassicAccelerationDerivatives``;
* ``fd.center_of_mass_derivatives`` / ``jacobianCenterOfMass`` + ``getCenterOfMassVelocityDerivatives``
  (after ``computeForwardKinematicsDerivatives``, which the latter needs);
* ``fd.centroidal_dynamics_derivatives`` / ``computeCentroidalDynamicsDerivatives``;
* ``fd.constrained_dynamics_derivatives`` / ``constraintDynamics`` + ``computeConstraintDynamicsDerivatives``
  and ``fd.impulse_dynamics_derivatives`` / ``impulseDynamics`` + ``computeImpulseDynamicsDerivatives``
  (solo12 and talos: the forward solve is part of both);
* batches of N states (default 256) on the thread pool (``fd.set_num_threads(2)``) against a Python loop of
  the Pinocchio calls: the kinematics, centre-of-mass, centroidal, constrained and impulse derivatives (interleaved, the
  best of 9 runs each; 3 for the constrained and impulse ones).
"""

from __future__ import annotations

import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_constraints import _pin_constraints
from bench_core import Pair, median_pair, print_ratios

import featherdyn as fd

#: median_pair's samples for one state: 101 of about 4 ms each side, interleaved. The machine's speed drifts by up to
#: 1.5× over seconds (a shared VM); with 7 samples of 0.2 s, a ratio of two medians taken from different windows
#: moved from 0.75 to 0.97 between consecutive runs (results-contact-derivatives-2026-11-30.md, fifth session).
#: Many short alternating samples put both medians over the same windows.
ONE_STATE = (101, 0.004)

CONTACTS = {"solo12": (["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"], True),
            "talos_full_v2": (["left_sole_link", "right_sole_link"], False)}


def _batch_pair(f: Callable[[], Any], g: Callable[[], Any], repeats: int = 9) -> tuple[float, float]:
    """The best of ``repeats`` runs of each, interleaved (f, g, f, g, ...; a shared machine's slow spells then fall
    on both)."""
    best = [float("inf"), float("inf")]
    for _ in range(repeats):
        for k, h in enumerate((f, g)):
            t0 = time.perf_counter()
            h()
            best[k] = min(best[k], time.perf_counter() - t0)
    return best[0], best[1]


def main() -> int:
    import pinocchio as pin

    N = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    fd.set_num_threads(2)
    rows: list[tuple[str, float, float]] = []
    batch_rows: list[tuple[str, float, float]] = []
    for name, floating, frame in (("panda", False, "panda_hand"), ("solo12", True, "FL_FOOT"),
                                  ("talos_full_v2", True, "left_sole_link")):
        p = Pair(name, floating)
        m, pm, pd = p.model, p.pm, p.pd
        Q, V, A, Qp, Vp, Ap = p.states(N)
        q, v, a, qp, vp, ap = Q[0], V[0], A[0], Qp[0].copy(), Vp[0].copy(), Ap[0].copy()
        fid = pm.getFrameId(frame)

        def pin_kin(qp: np.ndarray = qp, vp: np.ndarray = vp, ap: np.ndarray = ap) -> None:
            pin.computeForwardKinematicsDerivatives(pm, pd, qp, vp, ap)  # noqa: B023
            pin.getFrameVelocityDerivatives(pm, pd, fid, pin.LOCAL)  # noqa: B023
            pin.getFrameAccelerationDerivatives(pm, pd, fid, pin.LOCAL)  # noqa: B023

        t = median_pair(lambda: fd.kinematics_derivatives(m, q, v, a, frame), pin_kin, *ONE_STATE)  # noqa: B023
        rows.append((f"{name}: kinematics_derivatives / FK derivatives + two getters", *t))
        point = np.array([0.02, -0.03, 0.05])  # (in the frame; for Pinocchio, its placement on the joint)
        jid, on_joint = pm.frames[fid].parentJoint, pm.frames[fid].placement * pin.SE3(np.eye(3), point)

        def pin_point(qp: np.ndarray = qp, vp: np.ndarray = vp, ap: np.ndarray = ap) -> None:
            pin.computeForwardKinematicsDerivatives(pm, pd, qp, vp, ap)  # noqa: B023
            pin.getPointVelocityDerivatives(pm, pd, jid, on_joint, pin.LOCAL)  # noqa: B023
            pin.getPointClassicAccelerationDerivatives(pm, pd, jid, on_joint, pin.LOCAL)  # noqa: B023

        t = median_pair(lambda: fd.kinematics_derivatives(m, q, v, a, frame, fd.LOCAL, point),  # noqa: B023
                        pin_point, *ONE_STATE)
        rows.append((f"{name}: kinematics_derivatives at a point / FK derivatives + two point getters", *t))

        def pin_com() -> None:
            pin.computeForwardKinematicsDerivatives(pm, pd, qp, vp, ap)  # noqa: B023
            pin.jacobianCenterOfMass(pm, pd, qp)  # noqa: B023
            pin.getCenterOfMassVelocityDerivatives(pm, pd)  # noqa: B023

        t = median_pair(lambda: fd.center_of_mass_derivatives(m, q, v), pin_com, *ONE_STATE)  # noqa: B023
        rows.append((f"{name}: center_of_mass_derivatives / jacobianCenterOfMass + com velocity derivatives", *t))
        t = median_pair(lambda: fd.centroidal_dynamics_derivatives(m, q, v, a),  # noqa: B023
                        lambda: pin.computeCentroidalDynamicsDerivatives(pm, pd, qp, vp, ap), *ONE_STATE)  # noqa: B023
        rows.append((f"{name}: centroidal_dynamics_derivatives / computeCentroidalDynamicsDerivatives", *t))
        t = _batch_pair(lambda: fd.kinematics_derivatives(m, Q, V, A, frame),  # noqa: B023
                        lambda: [pin_kin(Qp[k], Vp[k], Ap[k]) for k in range(N)])  # noqa: B023
        batch_rows.append((f"{name}: kinematics_derivatives, {N} states", *t))

        def pin_com_loop() -> None:
            for k in range(N):
                pin.computeForwardKinematicsDerivatives(pm, pd, Qp[k], Vp[k], Ap[k])  # noqa: B023
                pin.jacobianCenterOfMass(pm, pd, Qp[k])  # noqa: B023
                pin.getCenterOfMassVelocityDerivatives(pm, pd)  # noqa: B023

        t = _batch_pair(lambda: fd.center_of_mass_derivatives(m, Q, V), pin_com_loop)  # noqa: B023
        batch_rows.append((f"{name}: center_of_mass_derivatives, {N} states", *t))
        t = _batch_pair(lambda: fd.centroidal_dynamics_derivatives(m, Q, V, A),  # noqa: B023
                        lambda: [pin.computeCentroidalDynamicsDerivatives(pm, pd, Qp[k], Vp[k], Ap[k])  # noqa: B023
                                 for k in range(N)])
        batch_rows.append((f"{name}: centroidal_dynamics_derivatives, {N} states", *t))
        if name not in CONTACTS:
            continue
        frames, three_d = CONTACTS[name]
        cons = [fd.PointContact(f) if three_d else fd.FrameContact(f) for f in frames]
        cms, cds = _pin_constraints(pin, p, frames, pin.ContactType.CONTACT_3D if three_d else pin.ContactType.CONTACT_6D)
        settings = pin.ProximalSettings(1e-12, 0.0, 1)
        tau = fd.rnea(m, q, v, a) * 0.5
        Tau = fd.rnea(m, Q, V, A) * 0.5
        taup, Taup = p.jm.v_to_pin(tau), p.jm.v_to_pin(Tau)

        def pin_cd(qp: np.ndarray = qp, vp: np.ndarray = vp, taup: np.ndarray = taup) -> None:
            pin.constraintDynamics(pm, pd, qp, vp, taup, cms, cds, settings)  # noqa: B023
            pin.computeConstraintDynamicsDerivatives(pm, pd, cms, cds, settings)  # noqa: B023

        def pin_imp(qp: np.ndarray = qp, vp: np.ndarray = vp) -> None:
            pin.impulseDynamics(pm, pd, qp, vp, cms, cds, 0.0, settings)  # noqa: B023
            pin.computeImpulseDynamicsDerivatives(pm, pd, cms, cds, 0.0, settings)  # noqa: B023

        t = median_pair(lambda: fd.constrained_dynamics_derivatives(m, q, v, tau, cons), pin_cd, *ONE_STATE)  # noqa: B023
        rows.append((f"{name}: constrained_dynamics_derivatives / constraintDynamics + derivatives", *t))
        t = median_pair(lambda: fd.impulse_dynamics_derivatives(m, q, v, cons), pin_imp, *ONE_STATE)  # noqa: B023
        rows.append((f"{name}: impulse_dynamics_derivatives / impulseDynamics + derivatives", *t))
        t = _batch_pair(lambda: fd.constrained_dynamics_derivatives(m, Q, V, Tau, cons),  # noqa: B023
                        lambda: [pin_cd(Qp[k], Vp[k], Taup[k]) for k in range(N)], 3)  # noqa: B023
        batch_rows.append((f"{name}: constrained_dynamics_derivatives, {N} states", *t))
        t = _batch_pair(lambda: fd.impulse_dynamics_derivatives(m, Q, V, cons),  # noqa: B023
                        lambda: [pin_imp(Qp[k], Vp[k]) for k in range(N)], 3)  # noqa: B023
        batch_rows.append((f"{name}: impulse_dynamics_derivatives, {N} states", *t))
    print("one state (µs, ratio featherdyn / Pinocchio; target ≤ 0.8)")
    print_ratios(rows)
    print(f"\nbatches of {N} (featherdyn on 2 threads; Pinocchio a Python loop; target ratio ≤ 0.125)")
    print_ratios(batch_rows)
    return 0


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        raise SystemExit(main())
