"""Constrained dynamics and operational space against Pinocchio: ``python benchmarks/bench_constraints.py``.

Interleaved medians in one process (``bench_core.median_pair``), ratio featherdyn / Pinocchio (below 1:
featherdyn is faster):

* solo12 standing on four 3D point contacts: ``fd.constrained_dynamics`` against
  ``pin.constraintDynamics`` (constraint datas initialised once, outside the timing, as a
  control loop would);
* talos_full_v2 in double support (two 6D soles): the same;
* on both, an impact: ``fd.impulse_dynamics`` against ``pin.impulseDynamics`` (restitution 0), one state and a
  batch of 2000 (the core's thread pool) against a Python loop of Pinocchio's one-state calls;
* Λ at one frame (panda's hand) and at two frames (talos's grippers): ``fd.operational_space_inertia``
  against Pinocchio's best route from Python, ``computeDelassusMatrix`` then ``np.linalg.inv``; and on batches
  of 200 and 2000 states against a Python loop of one-state calls;
* batched: ``fd.constrained_dynamics`` on N = 200 and 2000 states in one call (the core's thread pool, ``fd.get_num_threads()``
  threads; also on one thread, to show what the pool adds) against a Python loop of one-state calls, both
  warmed up and timed as interleaved medians like the rest.

The load average is printed with the table: the 2-core sandbox is shared, and a batch on two threads is only
as parallel as the cores left free.

featherdyn's call includes building the constraint rows (frame Jacobians and drifts) from the
constraint objects; Pinocchio's includes the same work inside ``constraintDynamics``.
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import Pair, median_pair, print_ratios

import featherdyn as fd


def _pin_constraints(pin, p: Pair, frames: list[str], kind):  # type: ignore[no-untyped-def]
    pm = p.pm
    cms, cds = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for f in frames:
        fr = pm.frames[pm.getFrameId(f)]
        cms.append(pin.RigidConstraintModel(kind, pm, fr.parentJoint, fr.placement, pin.LOCAL))
    for c in cms:
        cds.append(c.createData())
    pin.initConstraintDynamics(pm, p.pd, cms, cds)
    return cms, cds


BATCHES = (200, 2000)  # a short batch (the pool's start-up shows) and a longer one


def main() -> int:
    import pinocchio as pin

    repeats, budget = 7, 0.2
    rows: list[tuple[str, float, float]] = []
    settings = pin.ProximalSettings(1e-12, 0.0, 1)
    scenes = [("solo12", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"], True),
              ("talos_full_v2", ["left_sole_link", "right_sole_link"], False)]
    for name, frames, three_d in scenes:
        p = Pair(name, True)
        q, v, tau, qp, vp, taup = (x[0] for x in p.states(1))
        cons = [fd.PointContact(f) if three_d else fd.FrameContact(f) for f in frames]
        kind = pin.ContactType.CONTACT_3D if three_d else pin.ContactType.CONTACT_6D
        cms, cds = _pin_constraints(pin, p, frames, kind)
        t_fd, t_pin = median_pair(lambda: fd.constrained_dynamics(p.model, q, v, tau, cons),  # noqa: B023
                                  lambda: pin.constraintDynamics(p.pm, p.pd, qp, vp, taup, cms, cds, settings),  # noqa: B023
                                  repeats, budget)
        rows.append((f"{name}: constrained_dynamics, {len(frames)} {'3D' if three_d else '6D'} contacts", t_fd, t_pin))
        t_fd, t_pin = median_pair(lambda: fd.impulse_dynamics(p.model, q, v, cons),  # noqa: B023
                                  lambda: pin.impulseDynamics(p.pm, p.pd, qp, vp, cms, cds, 0.0, settings),  # noqa: B023
                                  repeats, budget)
        rows.append((f"{name}: impulse_dynamics / impulseDynamics", t_fd, t_pin))
        n = BATCHES[-1]  # impacts of a batch (SIMD lanes on the pool) against a Python loop over Pinocchio's
        Q, V, _, QP, VP = p.states(n)[:5]
        t_fd, t_pin = median_pair(lambda: fd.impulse_dynamics(p.model, Q, V, cons),  # noqa: B023
                                  lambda: [pin.impulseDynamics(p.pm, p.pd, QP[k], VP[k], cms, cds, 0.0,  # noqa: B023
                                                               settings) for k in range(n)],  # noqa: B023
                                  repeats, budget)
        rows.append((f"{name}: impulse_dynamics batch of {n} ({fd.get_num_threads()} threads) / Python loop of "
                     "impulseDynamics", t_fd / n, t_pin / n))
        # batched against a Python loop of one-state calls
        for n in BATCHES:
            Q, V, T = p.states(n)[:3]

            def batch() -> None:
                fd.constrained_dynamics(p.model, Q, V, T, cons)  # noqa: B023

            def loop() -> None:
                for k in range(n):  # noqa: B023
                    fd.constrained_dynamics(p.model, Q[k], V[k], T[k], cons)  # noqa: B023

            threads = fd.get_num_threads()
            t_batch, t_loop = median_pair(batch, loop, repeats, budget)
            rows.append((f"{name}: batch of {n} ({threads} threads) / Python loop of one-state calls", t_batch / n,
                         t_loop / n))
            fd.set_num_threads(1)
            try:
                t_batch1, t_loop = median_pair(batch, loop, repeats, budget)
            finally:
                fd.set_num_threads(threads)
            rows.append((f"{name}: batch of {n} (1 thread) / Python loop of one-state calls", t_batch1 / n,
                         t_loop / n))

    for name, floating, frames in (("panda", False, ["panda_hand"]),
                                   ("talos_full_v2", True, ["gripper_left_base_link", "gripper_right_base_link"])):
        p = Pair(name, floating)
        q, qp = (x[0] for x in p.states(1)[::3][:2])
        cms, cds = _pin_constraints(pin, p, frames, pin.ContactType.CONTACT_6D)

        def pin_lambda() -> np.ndarray:
            return np.linalg.inv(pin.computeDelassusMatrix(p.pm, p.pd, qp, cms, cds, 0.0))  # noqa: B023

        t_fd, t_pin = median_pair(lambda: fd.operational_space_inertia(p.model, q, frames, fd.LOCAL),  # noqa: B023
                                  pin_lambda, repeats, budget)
        rows.append((f"{name}: Λ at {len(frames)} frame{'s' if len(frames) > 1 else ''} / Delassus + inv", t_fd, t_pin))
        for n in BATCHES:
            Q = p.states(n)[0]

            def lam_batch() -> None:
                fd.operational_space_inertia(p.model, Q, frames, fd.LOCAL)  # noqa: B023

            def lam_loop() -> None:
                for k in range(n):  # noqa: B023
                    fd.operational_space_inertia(p.model, Q[k], frames, fd.LOCAL)  # noqa: B023

            t_batch, t_loop = median_pair(lam_batch, lam_loop, repeats, budget)
            rows.append((f"{name}: Λ batch of {n} ({fd.get_num_threads()} threads) / Python loop of one-state calls",
                         t_batch / n, t_loop / n))

    print(f"featherdyn {fd.__version__}, pinocchio {pin.__version__}, load average {os.getloadavg()[0]:.2f} "
          f"(1 min) on {os.cpu_count()} cores")
    print_ratios(rows)
    return 0


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sys.exit(main())
