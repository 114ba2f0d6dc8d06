"""Second-order derivatives against differencing the first order: ``python benchmarks/bench_second_order.py``.

Interleaved medians in one process (``bench_core.median_pair``), one state, on panda, solo12 (floating base),
talos_reduced and talos_full_v2 (floating base):

* ``fd.rnea_second_derivatives`` against ``nv + 1`` calls of ``fd.rnea_derivatives`` — what differencing the
  analytical first order costs (one call at the state, one per direction);
* ``fd.aba_second_derivatives`` against ``nv + 1`` calls of ``fd.aba_derivatives``, likewise.

Ratio = second order / differencing (below 1: the second order is faster; the issue's target is ≤ 1/3). The
second order returns four (nv, nv, nv) arrays, 4 MB on talos_full_v2: a fresh result's pages are faulted in on
the first write, which on this machine costs more than the kernel: since 2026-11-29 (evening) such a result
reuses the memory of one the caller dropped (the batches' result pool), as the loop here does. The ``out=`` rows
call the public function on arrays allocated once (``fd.rnea_second_derivatives(..., out=outs)``: since 2026-11-30
in C, the record of the given arrays).
The load average is printed: the 2-core sandbox is shared. The samples are 101 of about 4 ms a side, alternating
(as ``bench_derivatives_everywhere.ONE_STATE``, since 2026-12-01): with 5 samples of 50 ms, the two medians could
come from different windows of a machine whose speed drifts over seconds.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import median_pair

import featherdyn as fd

ROBOTS = [("panda", False), ("solo12", True), ("talos_reduced", True), ("talos_full_v2", True)]


def rows(name: str, floating: bool, repeats: int, budget: float) -> list[tuple[str, float, float]]:
    """``(label, second-order s, differencing s)`` for one robot at a random state."""
    model = fd.load_robot(name, floating_base=True) if floating else fd.load_robot(name)
    rng = np.random.default_rng(0)
    n = model.nv
    q = fd.random_configuration(model, rng)
    v, a, tau = rng.normal(size=n), rng.normal(size=n), rng.normal(size=n)
    outs = tuple(np.empty((n, n, n)) for _ in range(4))

    def diff_rnea() -> None:
        for _ in range(n + 1):
            fd.rnea_derivatives(model, q, v, a)

    def diff_aba() -> None:
        for _ in range(n + 1):
            fd.aba_derivatives(model, q, v, tau)

    out: list[tuple[str, float, float]] = []
    for label, second, diff in (
            ("rnea", lambda: fd.rnea_second_derivatives(model, q, v, a), diff_rnea),
            ("rnea out=", lambda: fd.rnea_second_derivatives(model, q, v, a, out=outs), diff_rnea),
            ("aba", lambda: fd.aba_second_derivatives(model, q, v, tau), diff_aba),
            ("aba out=", lambda: fd.aba_second_derivatives(model, q, v, tau, out=outs), diff_aba)):
        s, d = median_pair(second, diff, repeats, budget)
        out.append((f"{name} (nv {n}) {label}", s, d))
    return out


def main() -> int:
    repeats, budget = 101, 0.004
    print(f"load average {os.getloadavg()[0]:.2f}; one state; µs per call\n")
    print(f"{'call':34s} {'second order':>13s} {'nv+1 first':>11s} {'ratio':>6s}")
    for name, floating in ROBOTS:
        for label, s, d in rows(name, floating, repeats, budget):
            print(f"{label:34s} {s * 1e6:13.1f} {d * 1e6:11.1f} {s / d:6.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
