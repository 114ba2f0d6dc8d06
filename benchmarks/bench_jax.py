"""featherdyn.jax against the NumPy functions: ``python benchmarks/bench_jax.py [N] [NGRAD]``.

Interleaved medians in one process (``bench_core.median_pair``), ratio JAX / NumPy (targets: ≤ 1.3 for the
operation on a batch, ≤ 1.5 for a gradient), on panda (fixed base), solo12 and talos_full_v2 (floating):

* ``jax.jit(jax.vmap(fj.rnea))`` on N states (default 10 000) / ``fd.rnea`` on the same batch (the handler runs
  the core's batch; the rest is XLA's dispatch and the results' buffers);
* ``jax.jit(jax.grad)`` of ``Σ ȳ · fj.aba(q, v, τ)`` with respect to (q, v, τ) on NGRAD states (default 1 000)
  / ``fd.aba_derivatives`` on them (the issue's comparison), and / ``fd.aba`` + ``fd.aba_vjp`` (what the reverse
  mode runs: the forward, then the vector–Jacobian product; the rest is XLA's and q's tangent map).
"""

from __future__ import annotations

import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import median_pair

import featherdyn as fd
import featherdyn.jax as fj

ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]


def robot_rows(name: str, floating: bool, n: int, n_grad: int) -> list[tuple[str, float, float]]:
    model = fd.load_robot(name, floating_base=floating)
    rng = np.random.default_rng(0)
    q = fd.random_configuration(model, rng, size=n)
    v, a = rng.normal(size=(n, model.nv)), rng.normal(size=(n, model.nv))
    rnea = jax.jit(jax.vmap(lambda q, v, a: fj.rnea(model, q, v, a)))
    jq, jv, ja = (jnp.asarray(x) for x in (q, v, a))
    rows = []
    t, f = median_pair(lambda: rnea(jq, jv, ja).block_until_ready(), lambda: fd.rnea(model, q, v, a), 5, 0.5)
    rows.append((f"{name}: jit(vmap(rnea)), {n} states / fd.rnea", t, f))
    qg, vg, tg = q[:n_grad], v[:n_grad], a[:n_grad]
    ybar = jnp.asarray(rng.normal(size=(n_grad, model.nv)))
    grad = jax.jit(jax.grad(lambda q, v, tau: jnp.sum(ybar * fj.aba(model, q, v, tau)), argnums=(0, 1, 2)))
    gq, gv, gt = (jnp.asarray(x) for x in (qg, vg, tg))
    t, f = median_pair(lambda: jax.block_until_ready(grad(gq, gv, gt)),
                       lambda: fd.aba_derivatives(model, qg, vg, tg), 5, 0.5)
    rows.append((f"{name}: jit(grad) through aba, {n_grad} states / fd.aba_derivatives", t, f))
    yb = np.asarray(ybar)
    t, f = median_pair(lambda: jax.block_until_ready(grad(gq, gv, gt)),
                       lambda: (fd.aba(model, qg, vg, tg), fd.aba_vjp(model, qg, vg, tg, yb)), 5, 0.5)
    rows.append((f"{name}: jit(grad) through aba, {n_grad} states / fd.aba + fd.aba_vjp", t, f))
    return rows


def main() -> int:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    n_grad = int(sys.argv[2]) if len(sys.argv) > 2 else 1_000
    rows = [r for name, floating in ROBOTS for r in robot_rows(name, floating, n, n_grad)]
    width = max(len(label) for label, _, _ in rows)
    print(f"{'call':{width}} {'jax ms':>9} {'numpy ms':>9} {'ratio':>7}")
    for label, t, f in rows:
        print(f"{label:{width}} {t * 1e3:9.3f} {f * 1e3:9.3f} {t / f:7.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
