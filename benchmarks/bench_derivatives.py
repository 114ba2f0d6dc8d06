"""Analytical derivatives against Pinocchio: ``python benchmarks/bench_derivatives.py``.

Interleaved medians in one process (``bench_core.median_pair``), ratio featherdyn / Pinocchio (below 1:
featherdyn is faster), on panda (fixed base), solo12 and talos_full_v2 (floating base):

* one state: ``fd.rnea_derivatives(model, q, v, a)`` (∂τ/∂q, ∂τ/∂q̇ and M, returned as new arrays) against
  ``pin.computeRNEADerivatives(model, data, q, v, a)`` (which fills ``data``); ``fd.aba_derivatives`` against
  ``pin.computeABADerivatives``;
* one state: the declared ``fd.generalized_gravity_derivatives`` / ``fd.static_torque_derivatives`` against
  ``pin.computeGeneralizedGravityDerivatives`` / ``computeStaticTorqueDerivatives``;
* batched: ``fd.compile(model).rnea_derivatives_batch`` / ``aba_derivatives_batch`` on N states in one call
  (the same kernels as ``fd.rnea_derivatives`` on a batch), returning new results (whose memory is that of the
  results dropped before: ``fd.set_result_cache_size``), the same with that cache off (fresh pages), and into
  reused ``out=`` arrays,
  against a Python loop of ``pin.computeRNEADerivatives`` / ``computeABADerivatives`` (which fill ``data``:
  nothing allocated); the issue's target: ≥ 8×.
* one state: ``fd.rnea_second_derivatives`` / ``fd.aba_second_derivatives`` (Pinocchio's Python has no second
  order) against the central differences of ``computeRNEADerivatives`` one would write instead (4 nv calls);
* for comparison, ∂τ/∂q and ∂τ/∂q̇ by central finite differences (4 nv perturbed states in one batched
  ``fd.rnea`` call) against the analytical ``computeRNEADerivatives``. Fresh arrays of N·nv² doubles cost their page faults
  (the kernel zeroes every page the first time it is touched).
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import Pair, median_pair, print_ratios

import featherdyn as fd


def main() -> int:
    import pinocchio as pin

    rows: list[tuple[str, float, float]] = []
    for name, floating in (("panda", False), ("solo12", True), ("talos_full_v2", True)):
        p = Pair(name, floating)
        q, v, a, qp, vp, ap = (x[0] for x in p.states(1))
        tau = fd.rnea(p.model, q, v, a)
        taup = p.jm.v_to_pin(tau)
        t_fd, t_pin = median_pair(lambda: fd.rnea_derivatives(p.model, q, v, a),  # noqa: B023
                                  lambda: pin.computeRNEADerivatives(p.pm, p.pd, qp, vp, ap), 7, 0.2)  # noqa: B023
        rows.append((f"{name}: rnea_derivatives / computeRNEADerivatives", t_fd, t_pin))
        t_fd, t_pin = median_pair(lambda: fd.aba_derivatives(p.model, q, v, tau),  # noqa: B023
                                  lambda: pin.computeABADerivatives(p.pm, p.pd, qp, vp, taup), 7, 0.2)  # noqa: B023
        rows.append((f"{name}: aba_derivatives / computeABADerivatives", t_fd, t_pin))
        # second order (Pinocchio's Python has none): against the central differences of computeRNEADerivatives
        # along integrate and q̇ that one would write instead (4 nv calls; inexact)
        steps = [pin.integrate(p.pm, qp, e) for k in range(p.pm.nv) for e in (1e-6 * np.eye(p.pm.nv)[k],
                                                                              -1e-6 * np.eye(p.pm.nv)[k])]
        vsteps = [vp + e for k in range(p.pm.nv) for e in (1e-6 * np.eye(p.pm.nv)[k], -1e-6 * np.eye(p.pm.nv)[k])]

        def pin_differences() -> None:
            for qs in steps:  # noqa: B023
                pin.computeRNEADerivatives(p.pm, p.pd, qs, vp, ap)  # noqa: B023
            for vs in vsteps:  # noqa: B023
                pin.computeRNEADerivatives(p.pm, p.pd, qp, vs, ap)  # noqa: B023

        t_fd, t_pin = median_pair(lambda: fd.rnea_second_derivatives(p.model, q, v, a), pin_differences, 5, 0.2)  # noqa: B023
        rows.append((f"{name}: rnea_second_derivatives / differences of computeRNEADerivatives (4 nv)", t_fd, t_pin))
        t_fd, _ = median_pair(lambda: fd.aba_second_derivatives(p.model, q, v, tau), pin_differences, 5, 0.2)  # noqa: B023
        rows.append((f"{name}: aba_second_derivatives / the same differences", t_fd, t_pin))
        # the declared algorithms (api/declarations.py): their one-state calls through the generic path
        f_ext = np.random.default_rng(1).normal(size=(p.model.nbodies, 6))
        fext_pin = [pin.Force.Zero() for _ in range(p.pm.njoints)]
        for i, jn in enumerate(p.model.joint_names):
            fext_pin[p.pm.getJointId(jn)] = pin.Force(np.concatenate([f_ext[i, 3:], f_ext[i, :3]]))
        t_fd, t_pin = median_pair(lambda: fd.generalized_gravity_derivatives(p.model, q),  # noqa: B023
                                  lambda: pin.computeGeneralizedGravityDerivatives(p.pm, p.pd, qp), 7, 0.2)  # noqa: B023
        rows.append((f"{name}: generalized_gravity_derivatives / computeGeneralizedGravityDerivatives", t_fd, t_pin))
        t_fd, t_pin = median_pair(lambda: fd.static_torque_derivatives(p.model, q, f_ext),  # noqa: B023
                                  lambda: pin.computeStaticTorqueDerivatives(p.pm, p.pd, qp, fext_pin), 7, 0.2)  # noqa: B023
        rows.append((f"{name}: static_torque_derivatives / computeStaticTorqueDerivatives", t_fd, t_pin))
        # for comparison: ∂τ/∂q and ∂τ/∂q̇ by central differences, the 4 nv perturbed states in one batched
        # fd.rnea call (q ⊕ ±h e_j through fd.integrate)
        nv, step = p.model.nv, 1e-6
        E = np.eye(nv) * step
        qs = fd.integrate(p.model, np.broadcast_to(q, (2 * nv, q.size)), np.concatenate([E, -E]))
        Qs = np.concatenate([qs, np.broadcast_to(q, (2 * nv, q.size))])
        Vs = np.concatenate([np.broadcast_to(v, (2 * nv, nv)), v + np.concatenate([E, -E])])

        def central() -> tuple[np.ndarray, np.ndarray]:
            t = fd.rnea(p.model, Qs, Vs, a)  # noqa: B023
            return ((t[:nv] - t[nv:2 * nv]).T / (2 * step), (t[2 * nv:3 * nv] - t[3 * nv:]).T / (2 * step))  # noqa: B023

        t_fd, t_pin = median_pair(central, lambda: pin.computeRNEADerivatives(p.pm, p.pd, qp, vp, ap), 7, 0.2)  # noqa: B023
        rows.append((f"{name}: central differences (4 nv RNEAs, batched) / computeRNEADerivatives", t_fd, t_pin))
        n = 2000
        Q, V, A, QP, VP, AP = p.states(n)
        T = fd.rnea(p.model, Q, V, A)
        TP = p.jm.v_to_pin(T)
        cm = fd.compile(p.model)
        outs = tuple(np.empty((n, p.model.nv, p.model.nv)) for _ in range(3))
        for what, fd_call, pin_call, X, XP in (
                ("rnea_derivatives", cm.rnea_derivatives_batch, pin.computeRNEADerivatives, A, AP),
                ("aba_derivatives", cm.aba_derivatives_batch, pin.computeABADerivatives, T, TP)):
            fd_call(Q[:8], V[:8], X[:8])
            best_fresh = best_nocache = best_out = best_pin = float("inf")
            for _ in range(3):  # rounds: the batch call 3 times back to back (best), then the loop once
                for _ in range(3):
                    t0 = time.perf_counter()
                    fd_call(Q, V, X)
                    best_fresh = min(best_fresh, time.perf_counter() - t0)
                limit = fd.result_cache_info()["limit"]
                fd.set_result_cache_size(0)
                for _ in range(3):
                    t0 = time.perf_counter()
                    fd_call(Q, V, X)
                    best_nocache = min(best_nocache, time.perf_counter() - t0)
                fd.set_result_cache_size(limit)
                for _ in range(3):
                    t0 = time.perf_counter()
                    fd_call(Q, V, X, out=outs)
                    best_out = min(best_out, time.perf_counter() - t0)
                t0 = time.perf_counter()
                for k in range(n):
                    pin_call(p.pm, p.pd, QP[k], VP[k], XP[k])
                best_pin = min(best_pin, time.perf_counter() - t0)
            rows.append((f"{name}: {what} batch of {n}, new results / loop", best_fresh / n, best_pin / n))
            rows.append((f"{name}: {what} batch of {n}, new results, no result cache / loop", best_nocache / n,
                         best_pin / n))
            rows.append((f"{name}: {what} batch of {n}, out= / loop", best_out / n, best_pin / n))
    print(f"featherdyn {fd.__version__}, pinocchio {pin.__version__}, core threads {fd.get_num_threads()}")
    print_ratios(rows)
    return 0


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sys.exit(main())
