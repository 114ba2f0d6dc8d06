"""featherdyn.torch against the NumPy functions: ``python benchmarks/bench_torch.py [N] [NGRAD]``.

Interleaved medians in one process (``bench_core.median_pair``), ratio torch / NumPy (targets: ≤ 1.3 for the
operator on a batch, ≤ 1.5 for a gradient), on panda (fixed base), solo12 and talos_full_v2 (floating):

* ``ft.rnea(model, Q, V, A)`` / ``fd.rnea(model, Q, V, A)`` on N states (default 10 000), float64 tensors and
  the same arrays (the operator's cost above the call: the tensors' NumPy views, the dispatcher, the
  result's tensor, without a copy);
* ``ft.rnea`` / ``fd.rnea`` on one state (the dispatcher's fixed cost);
* a gradient through ``ft.aba`` on NGRAD states (default 1 000): ``torch.autograd.grad(ft.aba(q, v, τ),
  (q, v, τ), ȳ)`` (the forward, ``fd.aba_derivatives`` inside the backward — api/jacobians.py, through the
  operator's ``autograd.Function`` —, the products with ``ȳ`` and the tangent's map ``T(q)ᵀ`` to ``q``'s
  coordinates) / ``fd.aba_derivatives(model, q, v, τ)`` (the Jacobians alone); the same for ``ft.rnea`` /
  ``fd.rnea_derivatives``, on NGRAD states and on one;
* ``torch.func.grad`` of ``w · ft.rnea`` in ``v`` on one state / ``fd.rnea_derivatives`` on one state.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import median_pair

import featherdyn as fd
import featherdyn.torch as ft

ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]


def robot_rows(name: str, floating: bool, n: int, n_grad: int) -> list[tuple[str, float, float]]:
    """``(label, torch seconds, numpy seconds)`` of the three calls on one robot."""
    model = fd.load_robot(name, floating_base=floating)
    rng = np.random.default_rng(0)
    q = fd.random_configuration(model, rng, size=n)
    v, a = rng.normal(size=(n, model.nv)), rng.normal(size=(n, model.nv))
    tq, tv, ta = (torch.from_numpy(x) for x in (q, v, a))
    rows = []
    t, f = median_pair(lambda: ft.rnea(model, tq, tv, ta), lambda: fd.rnea(model, q, v, a), 5, 0.5)
    rows.append((f"rnea, {n} states", t, f))
    t, f = median_pair(lambda: ft.rnea(model, tq[0], tv[0], ta[0]), lambda: fd.rnea(model, q[0], v[0], a[0]), 5, 0.3)
    rows.append(("rnea, one state", t, f))
    qg, vg, tg = (torch.from_numpy(x[:n_grad].copy()).requires_grad_() for x in (q, v, a))
    ybar = torch.ones(n_grad, model.nv, dtype=torch.float64)
    qn, vn, taun = (x[:n_grad] for x in (q, v, a))
    t, f = median_pair(lambda: torch.autograd.grad(ft.aba(model, qg, vg, tg), (qg, vg, tg), ybar),
                       lambda: fd.aba_derivatives(model, qn, vn, taun), 5, 0.5)
    rows.append((f"grad aba / aba_derivatives, {n_grad}", t, f))
    t, f = median_pair(lambda: torch.autograd.grad(ft.rnea(model, qg, vg, tg), (qg, vg, tg), ybar),
                       lambda: fd.rnea_derivatives(model, qn, vn, taun), 5, 0.5)
    rows.append((f"grad rnea / rnea_derivatives, {n_grad}", t, f))
    q1, v1, a1 = (x[0].detach().clone().requires_grad_() for x in (qg, vg, tg))
    t, f = median_pair(lambda: torch.autograd.grad(ft.rnea(model, q1, v1, a1), (q1, v1, a1), ybar[0]),
                       lambda: fd.rnea_derivatives(model, qn[0], vn[0], taun[0]), 5, 0.3)
    rows.append(("grad rnea / rnea_derivatives, one", t, f))
    w = ybar[0]
    grad_v = torch.func.grad(lambda v: ft.rnea(model, q1.detach(), v, a1.detach()) @ w)
    t, f = median_pair(lambda: grad_v(v1.detach()), lambda: fd.rnea_derivatives(model, qn[0], vn[0], taun[0]), 5, 0.3)
    rows.append(("torch.func.grad rnea (v), one", t, f))
    return rows


def main(argv: list[str]) -> int:
    n = int(argv[1]) if len(argv) > 1 else 10_000
    n_grad = int(argv[2]) if len(argv) > 2 else 1_000
    torch.set_num_threads(1)
    print(f"torch {torch.__version__}, featherdyn threads {fd.get_num_threads()}, N = {n}, NGRAD = {n_grad}")
    print(f"{'robot':<15}{'call':<38}{'torch':>12}{'numpy':>12}{'ratio':>8}")
    for name, floating in ROBOTS:
        for label, t, f in robot_rows(name, floating, n, n_grad):
            scale, unit = (1e3, "ms") if t > 1e-3 else (1e6, "µs")
            print(f"{name:<15}{label:<38}{t * scale:>9.3f} {unit}{f * scale:>9.3f} {unit}{t / f:>8.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv))
