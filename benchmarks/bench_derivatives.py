"""Analytical derivatives against Pinocchio: ``python benchmarks/bench_derivatives.py``.

Interleaved medians in one process (``bench_core.median_pair``), ratio featherdyn / Pinocchio (below 1:
featherdyn is faster), on panda (fixed base), solo12 and talos_full_v2 (floating base):

* one state: ``fd.rnea_derivatives(model, q, v, a)`` (∂τ/∂q, ∂τ/∂q̇ and M, returned as new arrays) against
  ``pin.computeRNEADerivatives(model, data, q, v, a)`` (which fills ``data``); ``fd.aba_derivatives`` against
  ``pin.computeABADerivatives``;
* batched: ``fd.rnea_derivatives`` on N states in one call against a Python loop of
  ``pin.computeRNEADerivatives`` (the issue's target: ≥ 8×).
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

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
        n = 2000
        Q, V, A, QP, VP, AP = p.states(n)
        fd.rnea_derivatives(p.model, Q[:8], V[:8], A[:8])
        best_fd = best_pin = float("inf")
        for _ in range(3):
            t0 = time.perf_counter()
            fd.rnea_derivatives(p.model, Q, V, A)
            best_fd = min(best_fd, time.perf_counter() - t0)
            t0 = time.perf_counter()
            for k in range(n):
                pin.computeRNEADerivatives(p.pm, p.pd, QP[k], VP[k], AP[k])
            best_pin = min(best_pin, time.perf_counter() - t0)
        rows.append((f"{name}: rnea_derivatives batch of {n} / loop of computeRNEADerivatives", best_fd / n,
                     best_pin / n))
    print(f"featherdyn {fd.__version__}, pinocchio {pin.__version__}, core threads {fd.get_num_threads()}")
    print_ratios(rows)
    return 0


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sys.exit(main())
